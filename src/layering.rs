//! The architecture's rules, checked mechanically (docs/ARCHITECTURE.md): no cycle among the
//! top-level modules, the TUI and CLI never reach into the model or the solver, and nothing
//! outside `sweep` reaches its journal or output directory layout. The check reads the
//! sources: every `crate::<module>[::<item>]` path (grouped `use crate::{a, b::{c, d}}` too)
//! outside comments and outside `#[cfg(test)]` items is an edge from the file's top-level
//! module to `<module>` (and to `<module>::<item>` for the nested rules).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// (importer, imported) pairs that must not appear; `a::b` forbids that nested module.
const FORBIDDEN: [(&str, &str); 8] = [
    ("tui", "model"),
    ("tui", "solver"),
    ("cli", "model"),
    ("cli", "solver"),
    ("tui", "sweep::journal"),
    ("tui", "sweep::output"),
    ("cli", "sweep::journal"),
    ("cli", "sweep::output"),
];

type Graph = BTreeMap<String, BTreeSet<String>>;

/// `source` without its `#[cfg(test)]` items (a test may import what the code must not).
fn without_tests(source: &str) -> String {
    let mut out = String::new();
    let mut rest = source;
    while let Some(i) = rest.find("#[cfg(test)]") {
        out.push_str(&rest[..i]);
        rest = &rest[i..];
        // Skip to the end of the item: its braced body, or the `;` of a `mod x;`.
        let Some(open) = rest.find(['{', ';']) else {
            return out;
        };
        if rest.as_bytes()[open] == b';' {
            rest = &rest[open + 1..];
            continue;
        }
        let mut depth = 0;
        let mut end = rest.len();
        for (j, c) in rest.char_indices().skip_while(|(j, _)| *j < open) {
            match c {
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        end = j + 1;
                        break;
                    }
                }
                _ => {}
            }
        }
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

/// The items of a `{a, b::c, d as e}` group (the text after its `{`), split at top-level
/// commas.
fn group_items(group: &str) -> Vec<String> {
    let mut depth = 0;
    let mut items = vec![String::new()];
    for c in group.chars() {
        match c {
            '{' => depth += 1,
            '}' if depth == 0 => break,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                items.push(String::new());
                continue;
            }
            _ => {}
        }
        items.last_mut().expect("one item").push(c);
    }
    items.into_iter().map(|i| i.trim().to_string()).collect()
}

/// The paths a `crate::` path names, to two segments: `sweep::journal::X` → `sweep::journal`,
/// `model::{rigid, flexible}` → `model::rigid`, `model::flexible`, `study` → `study`.
fn paths(rest: &str) -> Vec<String> {
    let first = first_ident(rest);
    let Some(after) = rest[first.len()..].trim_start().strip_prefix("::") else {
        return vec![first.to_string()];
    };
    let after = after.trim_start();
    match after.strip_prefix('{') {
        Some(group) => group_items(group)
            .iter()
            .map(|item| format!("{first}::{}", first_ident(item)))
            .collect(),
        None => vec![format!("{first}::{}", first_ident(after))],
    }
}

/// The crate paths (to two segments) a source text names through `crate::`, of the
/// top-level `modules`; test-only items and comments aside.
fn imports(source: &str, modules: &BTreeSet<String>) -> BTreeSet<String> {
    let code: String = source
        .lines()
        .map(|line| match line.find("//") {
            Some(i) => &line[..i],
            None => line,
        })
        .collect::<Vec<_>>()
        .join("\n");
    let code = without_tests(&code);
    let mut found = BTreeSet::new();
    let mut rest = code.as_str();
    while let Some(i) = rest.find("crate::") {
        // `crate` must start a path, not end an identifier such as `my_crate::`.
        let preceded_by_ident = rest[..i]
            .chars()
            .next_back()
            .is_some_and(|c| c.is_alphanumeric() || c == '_');
        rest = &rest[i + "crate::".len()..];
        if preceded_by_ident {
            continue;
        }
        let names: Vec<String> = if let Some(group) = rest.strip_prefix('{') {
            group_items(group)
                .iter()
                .flat_map(|item| paths(item))
                .collect()
        } else {
            paths(rest)
        };
        found.extend(names.into_iter().filter(|n| modules.contains(top(n))));
    }
    found
}

/// The top-level module of a path: `sweep::journal` → `sweep`.
fn top(path: &str) -> &str {
    path.split("::").next().unwrap_or(path)
}

fn first_ident(s: &str) -> &str {
    let end = s
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    &s[..end]
}

/// The top-level modules declared in lib.rs.
fn top_level_modules(lib: &str) -> BTreeSet<String> {
    lib.lines()
        .filter_map(|l| {
            let l = l.trim();
            let l = l.strip_prefix("pub ").unwrap_or(l);
            let name = l.strip_prefix("mod ")?.trim_end_matches(';').trim();
            Some(name.to_string())
        })
        .collect()
}

fn rust_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir)
        .expect("readable source dir")
        .flatten()
    {
        let path = entry.path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The module graph of the crate at `src`.
fn graph(src: &Path) -> Graph {
    let lib = std::fs::read_to_string(src.join("lib.rs")).expect("lib.rs");
    let modules = top_level_modules(&lib);
    let mut graph = Graph::new();
    for module in &modules {
        let mut files = Vec::new();
        let dir = src.join(module);
        if dir.is_dir() {
            rust_files(&dir, &mut files);
        }
        let file = src.join(format!("{module}.rs"));
        if file.is_file() {
            files.push(file);
        }
        let edges = graph.entry(module.clone()).or_default();
        for f in files {
            let text = std::fs::read_to_string(&f).expect("readable source");
            edges.extend(
                imports(&text, &modules)
                    .into_iter()
                    .filter(|m| top(m) != module),
            );
        }
    }
    graph
}

/// A cycle in the graph as a path `a → b → … → a`, if there is one.
fn find_cycle(graph: &Graph) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        graph: &Graph,
        done: &mut BTreeSet<String>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        if let Some(at) = stack.iter().position(|n| n == node) {
            let mut cycle = stack[at..].to_vec();
            cycle.push(node.to_string());
            return Some(cycle);
        }
        if done.contains(node) {
            return None;
        }
        stack.push(node.to_string());
        for next in graph.get(node).into_iter().flatten() {
            if let Some(c) = visit(top(next), graph, done, stack) {
                return Some(c);
            }
        }
        stack.pop();
        done.insert(node.to_string());
        None
    }
    let mut done = BTreeSet::new();
    graph
        .keys()
        .find_map(|n| visit(n, graph, &mut done, &mut Vec::new()))
}

/// Every broken rule, in words.
fn violations(graph: &Graph) -> Vec<String> {
    let mut out: Vec<String> = FORBIDDEN
        .iter()
        .filter(|(from, to)| {
            graph.get(*from).is_some_and(|edges| {
                edges
                    .iter()
                    .any(|e| e == to || e.starts_with(&format!("{to}::")))
            })
        })
        .map(|(from, to)| format!("`{from}` imports `{to}` (docs/ARCHITECTURE.md: never)"))
        .collect();
    if let Some(cycle) = find_cycle(graph) {
        out.push(format!("module cycle: {}", cycle.join(" → ")));
    }
    out
}

#[test]
fn the_module_graph_is_one_way() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let graph = graph(&src);
    assert!(graph.len() >= 8, "modules found: {:?}", graph.keys());
    let broken = violations(&graph);
    assert!(broken.is_empty(), "layering broken:\n{}", broken.join("\n"));
}

#[test]
fn the_check_sees_forbidden_imports_and_cycles() {
    let modules: BTreeSet<String> = ["model", "solver", "study", "report", "sweep", "tui"]
        .map(String::from)
        .into();
    let source = "use crate::{study::Study, model::{rigid, flexible}};\n\
                  // crate::report in a comment is no import\n\
                  fn f() { my_crate::solver::x(); crate::sweep::run(); }\n\
                  #[cfg(test)]\n\
                  mod tests { use crate::tui::App; fn g() { if true { crate::solver::y(); } } }\n\
                  use crate::sweep::{journal::Journal, store};";
    assert_eq!(
        imports(source, &modules),
        [
            "model::flexible",
            "model::rigid",
            "study::Study",
            "sweep::journal",
            "sweep::run",
            "sweep::store"
        ]
        .map(String::from)
        .into()
    );
    let mut g = Graph::new();
    g.entry("tui".into())
        .or_default()
        .insert("model::rigid".into());
    g.entry("tui".into())
        .or_default()
        .insert("sweep::run".into());
    g.entry("study".into()).or_default().insert("report".into());
    g.entry("report".into()).or_default().insert("sweep".into());
    g.entry("sweep".into()).or_default().insert("study".into());
    let broken = violations(&g);
    assert_eq!(broken.len(), 2, "{broken:?}");
    assert!(broken[0].contains("`tui` imports `model`"));
    assert!(
        broken[1].contains("report → sweep → study → report"),
        "{}",
        broken[1]
    );
    // A nested rule: the TUI may use the sweep, not its journal.
    g.entry("tui".into())
        .or_default()
        .insert("sweep::journal".into());
    let broken = violations(&g);
    assert!(
        broken
            .iter()
            .any(|b| b.contains("`tui` imports `sweep::journal`")),
        "{broken:?}"
    );
}
