//! The README's command examples, run against the binary: every indented example block that
//! shows output (`rocklab compare …`, `simulate … --check`) is run as written (`cargo run
//! --release --` is the binary; `out/` a scratch directory; results a block reads are made
//! first by running the study of that name, from studies/ or from a `// NAME.ron` block) and
//! its output must match what the README shows, a `…` line standing for any lines. So a number
//! in the README is one the program prints.

use std::path::{Path, PathBuf};

/// One example block: its command lines (joined where a line ends in `\`) and the output
/// shown after them.
struct Example {
    line: usize,
    commands: Vec<String>,
    output: Vec<String>,
}

/// The README's indented blocks: runs of lines indented by 4 (a blank line ends one).
fn blocks(readme: &str) -> Vec<(usize, Vec<String>)> {
    let mut out: Vec<(usize, Vec<String>)> = Vec::new();
    let mut current: Option<(usize, Vec<String>)> = None;
    for (i, line) in readme.lines().enumerate() {
        match line.strip_prefix("    ") {
            Some(code) if !code.trim().is_empty() => current
                .get_or_insert_with(|| (i + 1, Vec::new()))
                .1
                .push(code.to_string()),
            _ => out.extend(current.take()),
        }
    }
    out.extend(current);
    out
}

fn examples(readme: &str) -> Vec<Example> {
    let mut out = Vec::new();
    for (line, block) in blocks(readme) {
        let mut commands: Vec<String> = Vec::new();
        let mut output = Vec::new();
        let mut continued = false;
        for l in &block {
            let command = l.starts_with("rocklab ") || l.starts_with("cargo run --release -- ");
            if continued {
                let last = commands.last_mut().expect("a command continues");
                last.pop();
                last.push_str(l.trim());
            } else if command && output.is_empty() {
                commands.push(l.trim().to_string());
            } else if !commands.is_empty() {
                output.push(l.trim_end().to_string());
            }
            continued = l.ends_with('\\');
        }
        if !commands.is_empty() {
            out.push(Example {
                line,
                commands,
                output,
            });
        }
    }
    out
}

/// A `// NAME.ron` block of the README (a study shown in full), by name.
fn readme_study(readme: &str, name: &str) -> Option<String> {
    let header = format!("// {name}");
    blocks(readme)
        .into_iter()
        .find(|(_, b)| b.first().is_some_and(|l| l.trim() == header))
        .map(|(_, b)| b.join("\n"))
}

/// Words of a command line (no quoting is needed by the README's examples but `'…'`).
fn words(command: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut word = String::new();
    let mut quoted = false;
    for c in command.chars() {
        match c {
            '\'' => quoted = !quoted,
            ' ' if !quoted => {
                if !word.is_empty() {
                    out.push(std::mem::take(&mut word));
                }
            }
            c => word.push(c),
        }
    }
    out.extend((!word.is_empty()).then_some(word));
    out
}

/// Run one README command in `dir` (`out/…` and study files resolved there), making the
/// results it reads first; its stdout.
fn run(command: &str, dir: &Path, readme: &str) -> String {
    let mut args = words(command);
    let binary_at = usize::from(args[0] == "cargo") * 3;
    args.drain(..=binary_at);
    for a in &args {
        if let Some(name) = a.strip_prefix("out/")
            && args[0] != "run"
            && !dir.join(a).exists()
        {
            make_results(name, dir, readme);
        }
        if a.ends_with(".ron") && !a.contains('/') {
            let text = readme_study(readme, a).unwrap_or_else(|| panic!("no `// {a}` block"));
            std::fs::write(dir.join(a), text).unwrap();
        }
    }
    let crate_dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let args: Vec<String> = args
        .into_iter()
        .map(|a| match a.strip_prefix("studies/") {
            Some(_) => crate_dir.join(&a).display().to_string(),
            None => a,
        })
        .collect();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rocklab"))
        .args(&args)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{command}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// The results of the shipped study `name` (or the first whose name starts with it) in
/// `dir/out/name`.
fn make_results(name: &str, dir: &Path, readme: &str) {
    let studies = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("studies");
    let mut found: Vec<PathBuf> = std::fs::read_dir(&studies)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_stem().is_some_and(|s| {
                let s = s.to_string_lossy();
                s == name || s.starts_with(&format!("{name}_"))
            })
        })
        .collect();
    found.sort();
    let study = found
        .first()
        .unwrap_or_else(|| panic!("no study for out/{name}"));
    run(
        &format!("rocklab run {} --out out/{name} --quiet", study.display()),
        dir,
        readme,
    );
}

#[test]
fn the_readme_examples_print_what_the_readme_shows() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/README.md");
    let readme = std::fs::read_to_string(path).unwrap();
    let examples: Vec<Example> = (examples(&readme).into_iter())
        .filter(|ex| !ex.output.is_empty())
        .collect();
    assert!(
        examples.len() >= 4,
        "README examples with output: {}",
        examples.len()
    );
    let dir = tempfile::tempdir().unwrap();
    for ex in &examples {
        let mut printed = String::new();
        for c in &ex.commands {
            printed = run(c, dir.path(), &readme);
        }
        let printed: Vec<&str> = printed.lines().map(str::trim_end).collect();
        // The README's `…` is snapbox's `...` (any lines).
        let expected: Vec<String> = ex
            .output
            .iter()
            .map(|l| {
                if l.trim() == "…" {
                    "...".into()
                } else {
                    l.clone()
                }
            })
            .collect();
        snapbox::assert_data_eq!(printed.join("\n"), snapbox::Data::text(expected.join("\n")),);
        let _ = ex.line;
    }
}

/// The README's command examples that show no output run as written and succeed (files they
/// write land in a scratch directory), all but the workbench (`tui`, interactive) and `slurm
/// … --submit` (needs a cluster; its scripts are tests/slurm.rs's). A `# comment` after a
/// command is the README's, not the command's.
#[test]
fn the_readme_commands_without_output_run() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/README.md");
    let readme = std::fs::read_to_string(path).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut ran = Vec::new();
    for ex in examples(&readme).iter().filter(|ex| ex.output.is_empty()) {
        for c in &ex.commands {
            let c = c.split(" #").next().unwrap().trim();
            let sub = words(c)[if c.starts_with("cargo") { 4 } else { 1 }].clone();
            if sub == "tui" || sub.starts_with("--") || c.contains("--submit") {
                continue;
            }
            let stdout = run(c, dir.path(), &readme);
            if c.contains("--json") {
                let json: serde_json::Value = serde_json::from_str(&stdout)
                    .unwrap_or_else(|e| panic!("README line {}: {c}: {e}", ex.line));
                assert!(json["peak_rotation"].as_f64().is_some(), "{c}: {stdout}");
            }
            ran.push(sub);
        }
    }
    // The --history example wrote its CSV; the plot examples their figures.
    assert!(dir.path().join("fig14.csv").exists());
    assert!(dir.path().join("figs").read_dir().unwrap().count() > 0);
    for sub in ["simulate", "run", "compare", "plot", "design"] {
        assert!(
            ran.iter().any(|s| s == sub),
            "no README `{sub}` example ran: {ran:?}"
        );
    }
}
