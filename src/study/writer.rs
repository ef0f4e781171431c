//! Writing a study the way its user wrote it. ron's pretty printer puts every list element on
//! its own line, spells out every default and knows nothing of comments; a saved study should
//! read like the file that was opened. So the study is serialised compactly, read back into a
//! small syntax tree, and laid out here:
//! - where the file that was opened spells a value differently but to the same effect
//!   (`deg(10)`, `1e-5`, a range), its spelling is kept;
//! - fields the opened file left to their defaults stay left out;
//! - the opened file's comments are kept: the header block verbatim, the others above (or
//!   after, on the same line) the field they were written at; a comment whose field is gone
//!   is reported as lost, so that the caller can ask before dropping it;
//! - a group from the file keeps its line breaks; a new or edited one stays on one line when
//!   it fits in [`WIDTH`] columns and holds at most one nested group; a long list of numbers
//!   fills its lines.
//!
//! Every choice above is checked by reading the text back: the result always parses to the
//! same study ([`Study::parse_ron`]), whatever the opened file held.

use super::Study;
pub use crate::ron_syntax::WIDTH;
use crate::ron_syntax::{self as syntax, Document, Item, Value, render};

/// A study as text, and the comments of the opened file it could not keep.
#[derive(Clone, Debug, PartialEq)]
pub struct Written {
    pub text: String,
    /// Comments (as written, `//` included) whose field is no longer in the study.
    pub lost: Vec<String>,
}

/// The tree of a RON text (see [`syntax`]), None if it cannot be read.
fn parse(text: &str, keep_layout: bool) -> Option<Document> {
    syntax::parse(text, keep_layout).ok()
}

/// Where an item sits: its key, or its position and variant name in a list.
fn step(index: usize, item: &Item) -> String {
    match (item.key(), &item.value) {
        (Some(k), _) => k.to_string(),
        (None, Value::Group { name, .. }) | (None, Value::Atom(name, _)) => {
            format!("[{index}]{name}")
        }
    }
}

fn children(value: &Value) -> &[Item] {
    value.items()
}

/// The item at `path` under `value`.
fn find<'a>(value: &'a Value, path: &[String]) -> Option<&'a Item> {
    let (first, rest) = path.split_first()?;
    let (_, item) = children(value)
        .iter()
        .enumerate()
        .find(|(i, item)| step(*i, item) == *first)?;
    if rest.is_empty() {
        Some(item)
    } else {
        find(&item.value, rest)
    }
}

/// The items of the group at `path` (the root for an empty path).
fn group_items<'a>(root: &'a mut Value, path: &[String]) -> Option<&'a mut Vec<Item>> {
    let value = if path.is_empty() {
        root
    } else {
        &mut find_mut(root, path)?.value
    };
    match value {
        Value::Group { items, .. } => Some(items),
        Value::Atom(..) => None,
    }
}

fn find_mut<'a>(value: &'a mut Value, path: &[String]) -> Option<&'a mut Item> {
    let (first, rest) = path.split_first()?;
    let Value::Group { items, .. } = value else {
        return None;
    };
    let position = items
        .iter()
        .enumerate()
        .position(|(i, item)| step(i, item) == *first)?;
    let item = &mut items[position];
    if rest.is_empty() {
        Some(item)
    } else {
        find_mut(&mut item.value, rest)
    }
}

/// Every item's path, parents before children.
fn paths(value: &Value, prefix: &[String], out: &mut Vec<Vec<String>>) {
    for (i, item) in children(value).iter().enumerate() {
        let mut path = prefix.to_vec();
        path.push(step(i, item));
        out.push(path.clone());
        paths(&item.value, &path, out);
    }
}

/// A value without its comments.
fn bare(value: &Value) -> Value {
    match value {
        Value::Atom(..) => value.clone(),
        Value::Group {
            name,
            at,
            open,
            items,
            broken,
            ..
        } => Value::Group {
            broken: *broken,
            at: *at,
            name: name.clone(),
            open: *open,
            items: items
                .iter()
                .map(|i| Item {
                    key: i.key.clone(),
                    value: bare(&i.value),
                    before: Vec::new(),
                    after: None,
                })
                .collect(),
            tail: Vec::new(),
        },
    }
}

/// Whether `text` reads back as `study`.
fn same(text: &str, study: &Study) -> bool {
    Study::parse_ron(text, "save").is_ok_and(|back| back == *study)
}

/// `study` on one line, every field spelled out (defaults included), as serde writes it.
pub fn compact(study: &Study) -> String {
    ron::Options::default()
        .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
        .to_string(study)
        .expect("studies serialise")
}

/// The comments of `original` that `text` no longer holds (a comment written twice counts
/// twice): what a save of `text` over `original` would lose.
pub fn lost_comments(original: &str, text: &str) -> Vec<String> {
    let comments = |t: &str| -> Vec<String> {
        syntax::lex(t)
            .map(|toks| {
                toks.iter()
                    .filter(|k| k.kind == syntax::Kind::Comment)
                    .map(|k| k.text(t).trim_end().to_string())
                    .collect()
            })
            .unwrap_or_default()
    };
    let mut kept = comments(text);
    comments(original)
        .into_iter()
        .filter(|c| match kept.iter().position(|k| k == c) {
            Some(i) => {
                kept.remove(i);
                false
            }
            None => true,
        })
        .collect()
}

/// `study` as text, laid out as the module says, keeping what it can of `original` (the
/// text of the file the study was opened from, if any).
pub fn write(study: &Study, original: Option<&str>) -> Written {
    let original = original.map(|t| t.strip_prefix('\u{feff}').unwrap_or(t));
    let compact = compact(study);
    let Some(fresh) = parse(&compact, false) else {
        // Not reached (the compact writer's output is plain RON); never fail a save for it.
        return Written {
            text: study.to_ron_string(),
            lost: original.map(comment_lines).unwrap_or_default(),
        };
    };
    let Some(old) = original.and_then(|t| parse(t, true)) else {
        return Written {
            text: render("", &fresh.root, &[]),
            lost: original.map(comment_lines).unwrap_or_default(),
        };
    };
    let mut root = fresh.root;
    let footer = old.footer.clone();
    let check = |root: &Value| same(&render("", root, &[]), study);

    // The opened file's spelling wherever it means the same (parents first: an unedited
    // group comes back whole).
    let mut all = Vec::new();
    paths(&root, &[], &mut all);
    if check(&bare(&old.root)) {
        root = bare(&old.root);
    } else {
        for path in &all {
            let Some(theirs) = find(&old.root, path).map(|i| bare(&i.value)) else {
                continue;
            };
            let Some(ours) = find_mut(&mut root, path) else {
                continue;
            };
            if ours.value == theirs {
                continue;
            }
            let mine = std::mem::replace(&mut ours.value, theirs);
            if !check(&root) {
                find_mut(&mut root, path).expect("still there").value = mine;
            }
        }
    }

    // Fields the opened file did not write stay unwritten where that changes nothing.
    let mut all = Vec::new();
    paths(&root, &[], &mut all);
    for path in all.iter().rev() {
        if find(&old.root, path).is_some() {
            continue;
        }
        let (last, parent) = path.split_last().expect("paths are not empty");
        let Some(items) = group_items(&mut root, parent) else {
            continue;
        };
        let Some(at) = items
            .iter()
            .enumerate()
            .position(|(i, item)| item.key.is_some() && step(i, item) == *last)
        else {
            continue;
        };
        let removed = items.remove(at);
        if !check(&root) {
            group_items(&mut root, parent)
                .expect("the parent was a group a moment ago")
                .insert(at, removed);
        }
    }

    // The comments, at the fields they were written at.
    let mut lost = Vec::new();
    let mut old_paths = Vec::new();
    paths(&old.root, &[], &mut old_paths);
    if let Value::Group { tail, .. } = &old.root {
        set_tail(&mut root, tail.clone());
    }
    for path in &old_paths {
        let theirs = find(&old.root, path).expect("listed");
        let tail = match &theirs.value {
            Value::Group { tail, .. } => tail.clone(),
            Value::Atom(..) => Vec::new(),
        };
        if theirs.before.is_empty() && theirs.after.is_none() && tail.is_empty() {
            continue;
        }
        match find_mut(&mut root, path) {
            Some(ours) => {
                ours.before = theirs.before.clone();
                ours.after = theirs.after.clone();
                if !tail.is_empty() {
                    if matches!(ours.value, Value::Group { .. }) {
                        set_tail(&mut ours.value, tail);
                    } else {
                        lost.extend(tail);
                    }
                }
            }
            None => {
                lost.extend(theirs.before.iter().cloned());
                lost.extend(theirs.after.iter().cloned());
                lost.extend(tail);
            }
        }
    }
    let text = render(&old.header, &root, &footer);
    if same(&text, study) {
        return Written { text, lost };
    }
    // Not reached with a well-formed original; never save a different study if it is.
    Written {
        text: render(&old.header, &bare(&root), &[]),
        lost: all_comments(&old),
    }
}

/// The lines of a file this writer cannot read that hold comments (all are lost).
fn comment_lines(text: &str) -> Vec<String> {
    text.lines()
        .filter(|l| l.contains("//") || l.contains("/*"))
        .map(|l| l.trim().to_string())
        .collect()
}

fn set_tail(value: &mut Value, comments: Vec<String>) {
    if let Value::Group { tail, .. } = value {
        *tail = comments;
    }
}

fn all_comments(doc: &Document) -> Vec<String> {
    let mut out = Vec::new();
    let mut all = Vec::new();
    paths(&doc.root, &[], &mut all);
    if let Value::Group { tail, .. } = &doc.root {
        out.extend(tail.iter().cloned());
    }
    for path in &all {
        let item = find(&doc.root, path).expect("listed");
        out.extend(item.before.iter().cloned());
        out.extend(item.after.iter().cloned());
        if let Value::Group { tail, .. } = &item.value {
            out.extend(tail.iter().cloned());
        }
    }
    out.extend(doc.footer.iter().cloned());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_fit_on_one_line_and_long_ones_fill_lines() {
        let mut study = Study::builtin_default();
        let text = write(&study, None).text;
        assert!(
            text.contains("quantities: [peak_rotation_ratio],"),
            "{text}"
        );
        assert!(
            text.contains("structure: rigid(p: 2.0, alpha: 0.17453292519943295"),
            "{text}"
        );
        if let super::super::ExcitationFamily::Pulse { frequency, .. } = &mut study.excitation {
            *frequency = super::super::FrequencyAxis::Ratio(super::super::Values::List(
                (1..=40).map(|i| f64::from(i) * 0.25).collect(),
            ));
        }
        let text = write(&study, None).text;
        assert!(text.lines().all(|l| l.chars().count() <= WIDTH), "{text}");
        let list_lines = text.lines().filter(|l| l.contains("1.25,")).count();
        assert_eq!(list_lines, 1, "{text}");
        assert_eq!(Study::parse_ron(&text, "t").unwrap(), study);
    }

    #[test]
    fn an_unedited_study_saves_as_it_was_written() {
        let original = include_str!("../../studies/default.ron");
        let study = Study::from_ron_str(original, "default.ron").unwrap();
        let written = write(&study, Some(original));
        assert!(written.lost.is_empty());
        assert_eq!(written.text, original);
    }

    #[test]
    fn comments_follow_their_fields_and_lost_ones_are_reported() {
        let original = "// header\n(\n    version: 1,\n    name: \"x\", // the name\n    \
            structure: rigid(p: 2.0, alpha: deg(10)),\n    devices: [\n        none,\n        \
            // the clutch\n        sequential(sigma: 0.5),\n    ],\n    excitation: pulse(shape: \
            sine, amplitude: alpha_ratio(1.5), frequency: ratio([2.0, 4.0])),\n    \
            duration: 1e1,\n)\n";
        let mut study = Study::from_ron_str(original, "t").unwrap();
        study.name = "y".into();
        let written = write(&study, Some(original));
        assert!(written.lost.is_empty(), "{written:?}");
        let text = &written.text;
        assert!(text.starts_with("// header\n("), "{text}");
        assert!(text.contains("name: \"y\", // the name"), "{text}");
        assert!(text.contains("alpha: deg(10)"), "{text}");
        assert!(text.contains("duration: 1e1"), "{text}");
        assert!(
            text.contains("// the clutch\n        sequential(sigma: 0.5),"),
            "{text}"
        );
        assert!(!text.contains("mass"), "defaults stay unwritten: {text}");
        assert_eq!(Study::parse_ron(text, "t").unwrap(), study);
        // The commented device goes: its comment cannot be kept.
        study.devices.pop();
        let written = write(&study, Some(original));
        assert_eq!(written.lost, ["// the clutch"]);
        assert_eq!(Study::parse_ron(&written.text, "t").unwrap(), study);
    }
}
