//! The study as the Study screen shows and edits it: the [`ron_syntax`](crate::ron_syntax)
//! tree of its text, as its user wrote it (spelling such as `deg(10)`, field order,
//! comments), beside the tree of its full serialisation, which supplies the fields the text
//! leaves to their defaults. An edit replaces one item's text; the whole document is printed
//! and parsed by the study's own parser, which owns every rule and every error message.

use crate::ron_syntax::{self as syntax, Document, Item, Span, Value, flat, render};
use crate::study::Study;
use crate::study::fields::{EXCLUSIVE_FIELDS, optional_fields};

/// One row of the Study screen: an item of the study's text, or a field it does not write.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub depth: usize,
    pub label: String,
    /// Item indices from the root (for a field not written: its group's path).
    pub path: Vec<usize>,
    /// Inline value (leaf rows), a short tag (rows whose children follow), the default
    /// value of a field not written, or `unset`.
    pub text: String,
    pub leaf: bool,
    /// The row is an element of a list: it can be duplicated or deleted.
    pub in_list: bool,
    /// A field the text does not write: editing it adds the field to the group at `path`.
    pub absent: Option<String>,
}

pub struct StudyTree {
    doc: Document,
    /// The study serialised whole (every default spelled out), for the fields `doc` omits.
    full: Value,
}

/// A document with an empty root, for a study that cannot be printed (not reached).
fn empty() -> Document {
    Document {
        header: String::new(),
        root: Value::Group {
            name: String::new(),
            at: Span::default(),
            open: '(',
            items: Vec::new(),
            tail: Vec::new(),
            broken: None,
        },
        footer: Vec::new(),
    }
}

impl StudyTree {
    /// The tree of `study` as `text` (the file it was read from, or the text of its last
    /// edit) writes it; without a text, as a save would write it afresh.
    pub fn new(study: &Study, text: Option<&str>) -> StudyTree {
        let written = study.to_ron_keeping(text).text;
        StudyTree {
            doc: syntax::parse(&written, true).unwrap_or_else(|_| empty()),
            full: syntax::parse(&crate::study::writer::compact(study), false)
                .map_or_else(|_| empty().root, |d| d.root),
        }
    }

    /// The document as text.
    pub fn text(&self) -> String {
        render(&self.doc.header, &self.doc.root, &self.doc.footer)
    }

    /// The item at `path`.
    pub fn item(&self, path: &[usize]) -> Option<&Item> {
        let (last, parent) = path.split_last()?;
        group(&self.doc.root, parent)?.items().get(*last)
    }

    /// The text to start editing the item at `path` from.
    pub fn item_text(&self, path: &[usize]) -> String {
        self.item(path).map_or(String::new(), |i| flat(&i.value))
    }

    /// The document with the item at `path` replaced by `text`.
    pub fn replaced(&self, path: &[usize], text: &str) -> String {
        self.edited(path, |items, i| items[i].value = atom(text))
    }

    /// The document with a new list element `text` after the one at `path`.
    pub fn inserted_after(&self, path: &[usize], text: &str) -> String {
        self.edited(path, |items, i| {
            items.insert(i + 1, keyed(None, text));
        })
    }

    /// The document without the item at `path`.
    pub fn removed(&self, path: &[usize]) -> String {
        self.edited(path, |items, i| {
            items.remove(i);
        })
    }

    /// The document with `field: text` added to the group at `path`, and the path of the new
    /// item. A field that excludes another one set in the group (`size` and `p`) takes its
    /// place, in one edit: the name of the field replaced comes back too.
    pub fn added(
        &self,
        path: &[usize],
        field: &str,
        text: &str,
    ) -> (String, Vec<usize>, Option<String>) {
        let mut doc = self.doc.root.clone();
        let mut at = path.to_vec();
        let mut replaced = None;
        if let Some(items) = group_mut(&mut doc, path) {
            let other = exclusive_partner(field)
                .and_then(|other| items.iter().position(|i| i.key() == Some(other)));
            match other {
                Some(i) => {
                    replaced = items[i].key().map(str::to_string);
                    let old = std::mem::replace(&mut items[i], keyed(Some(field), text));
                    items[i].before = old.before;
                    items[i].after = old.after;
                    at.push(i);
                }
                None => {
                    at.push(items.len());
                    items.push(keyed(Some(field), text));
                }
            }
        }
        (
            render(&self.doc.header, &doc, &self.doc.footer),
            at,
            replaced,
        )
    }

    fn edited(&self, path: &[usize], change: impl FnOnce(&mut Vec<Item>, usize)) -> String {
        let mut root = self.doc.root.clone();
        if let Some((last, parent)) = path.split_last()
            && let Some(items) = group_mut(&mut root, parent)
            && *last < items.len()
        {
            change(items, *last);
        }
        render(&self.doc.header, &root, &self.doc.footer)
    }

    /// The rows of the Study screen, in the order of the text; after each group's items, the
    /// fields it leaves to their defaults (with the default) and the optional ones it leaves
    /// unset.
    pub fn rows(&self) -> Vec<Row> {
        let mut rows = Vec::new();
        let root = &self.doc.root;
        let mut path = Vec::new();
        for (i, item) in root.items().iter().enumerate() {
            path.push(i);
            self.flatten(item, 0, &mut path, label_of(i, item), false, &mut rows);
            path.pop();
        }
        self.defaults("study", root, 0, &[], &mut rows);
        rows
    }

    fn flatten(
        &self,
        item: &Item,
        depth: usize,
        path: &mut Vec<usize>,
        label: String,
        in_list: bool,
        out: &mut Vec<Row>,
    ) {
        let value = &item.value;
        let text = flat(value);
        let (name, open) = match value {
            Value::Group { name, open, .. } => (name.as_str(), *open),
            Value::Atom(..) => ("", ' '),
        };
        let children = value.items();
        let scalar_list = open == '['
            && children
                .iter()
                .all(|c| c.key.is_none() && matches!(c.value, Value::Atom(..)));
        let mut defaults = Vec::new();
        self.defaults(name, value, depth + 1, path, &mut defaults);
        // Groups with fields not written expand so that those show; an optional label alone
        // does not justify a row per field.
        let hidden = defaults.iter().any(|r| r.label != "label");
        let inline = children.is_empty() || scalar_list || (text.chars().count() <= 40 && !hidden);
        if inline {
            out.push(Row {
                depth,
                label,
                path: path.clone(),
                text,
                leaf: true,
                in_list,
                absent: None,
            });
            return;
        }
        out.push(Row {
            depth,
            label,
            path: path.clone(),
            text: match open {
                '[' => format!("[{} items]", children.len()),
                _ => name.to_string(),
            },
            leaf: false,
            in_list,
            absent: None,
        });
        for (i, child) in children.iter().enumerate() {
            path.push(i);
            self.flatten(child, depth + 1, path, label_of(i, child), open == '[', out);
            path.pop();
        }
        out.extend(defaults);
    }

    /// Rows for the fields of the group at `path` (named `owner`) that its text does not
    /// write: those with a default (from the full serialisation), then the optional ones.
    fn defaults(
        &self,
        owner: &str,
        value: &Value,
        depth: usize,
        path: &[usize],
        out: &mut Vec<Row>,
    ) {
        let written: Vec<&str> = value.items().iter().filter_map(Item::key).collect();
        // The same group in the full serialisation (not a value spelled otherwise, such as
        // `deg(10)` for a number).
        if let Some(full) =
            counterpart(&self.full, &self.doc.root, path).filter(|f| name_of(f) == name_of(value))
        {
            for item in full.items() {
                let Some(key) = item.key() else { continue };
                if !written.contains(&key) && !is_none(&item.value) {
                    out.push(absent_row(depth, path, key, shown(&item.value)));
                }
            }
        }
        let listed: Vec<String> = out.iter().map(|r| r.label.clone()).collect();
        for f in optional_fields(owner) {
            if !written.contains(&f.field) && !listed.iter().any(|l| l == f.field) {
                out.push(absent_row(depth, path, f.field, "unset".into()));
            }
        }
    }
}

fn absent_row(depth: usize, path: &[usize], field: &str, text: String) -> Row {
    Row {
        depth,
        label: field.to_string(),
        path: path.to_vec(),
        text,
        leaf: true,
        in_list: false,
        absent: Some(field.to_string()),
    }
}

/// The field that cannot be set together with `field` (`p` for `size`), if any.
fn exclusive_partner(field: &str) -> Option<&'static str> {
    EXCLUSIVE_FIELDS.iter().find_map(|(a, b)| {
        if *a == field {
            Some(*b)
        } else if *b == field {
            Some(*a)
        } else {
            None
        }
    })
}

/// A row's label: the item's key, or its index in a list.
fn label_of(i: usize, item: &Item) -> String {
    item.key().map_or_else(|| format!("[{i}]"), str::to_string)
}

fn atom(text: &str) -> Value {
    Value::Atom(text.trim().to_string(), Span::default())
}

fn keyed(key: Option<&str>, text: &str) -> Item {
    Item {
        key: key.map(|k| (k.to_string(), Span::default())),
        value: atom(text),
        before: Vec::new(),
        after: None,
    }
}

fn name_of(value: &Value) -> Option<&str> {
    match value {
        Value::Group { name, .. } => Some(name),
        Value::Atom(..) => None,
    }
}

fn is_none(value: &Value) -> bool {
    matches!(value, Value::Atom(a, _) if a == "None")
}

/// A default value as the user may type it: unset options (`None`) left out.
fn shown(value: &Value) -> String {
    match value {
        Value::Atom(..) => flat(value),
        Value::Group {
            name,
            at,
            open,
            items,
            ..
        } => flat(&Value::Group {
            name: name.clone(),
            at: *at,
            open: *open,
            items: items
                .iter()
                .filter(|i| !is_none(&i.value))
                .map(|i| Item {
                    key: i.key.clone(),
                    value: Value::Atom(shown(&i.value), Span::default()),
                    before: Vec::new(),
                    after: None,
                })
                .collect(),
            tail: Vec::new(),
            broken: None,
        }),
    }
}

/// The group at `path` under `root` (the root itself for an empty path).
fn group<'a>(root: &'a Value, path: &[usize]) -> Option<&'a Value> {
    let mut value = root;
    for &i in path {
        value = &value.items().get(i)?.value;
    }
    Some(value)
}

fn group_mut<'a>(root: &'a mut Value, path: &[usize]) -> Option<&'a mut Vec<Item>> {
    let mut value = root;
    for &i in path {
        let Value::Group { items, .. } = value else {
            return None;
        };
        value = &mut items.get_mut(i)?.value;
    }
    match value {
        Value::Group { items, .. } => Some(items),
        Value::Atom(..) => None,
    }
}

/// The value of the full serialisation at the place of `path` in the text: keyed items by
/// key, list elements by index.
fn counterpart<'a>(full: &'a Value, text: &Value, path: &[usize]) -> Option<&'a Value> {
    let (mut full, mut text) = (full, text);
    for &i in path {
        let item = text.items().get(i)?;
        let theirs = match item.key() {
            Some(k) => full.items().iter().find(|f| f.key() == Some(k))?,
            None => full.items().get(i)?,
        };
        full = &theirs.value;
        text = &item.value;
    }
    Some(full)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tree(text: &str) -> (Study, StudyTree) {
        let study = Study::from_ron_str(text, "t").unwrap();
        let tree = StudyTree::new(&study, Some(text));
        (study, tree)
    }

    const TEXT: &str = "// head\n(\n    version: 1,\n    name: \"x\",\n    \
        structure: rigid(p: 2.0, alpha: deg(10)), // the block\n    \
        devices: [none, sequential(sigma: 0.5)],\n    \
        excitation: pulse(shape: sine, amplitude: alpha_ratio(1.5), frequency: ratio(4.0)),\n    \
        duration: 2.0,\n    rtol: 1e-6,\n)\n";

    fn row<'a>(rows: &'a [Row], label: &str) -> &'a Row {
        rows.iter().find(|r| r.label == label).unwrap()
    }

    #[test]
    fn rows_show_the_text_as_written_and_the_defaults_it_leaves_out() {
        let (_, tree) = tree(TEXT);
        assert_eq!(tree.text(), TEXT);
        let rows = tree.rows();
        assert_eq!(row(&rows, "alpha").text, "deg(10)");
        let mass = row(&rows, "mass");
        assert_eq!(
            (mass.text.as_str(), mass.absent.as_deref()),
            ("1.0", Some("mass"))
        );
        assert_eq!(row(&rows, "size").text, "unset");
        // rtol before duration as written; the defaults after them.
        let at = |l: &str| rows.iter().position(|r| r.label == l).unwrap();
        assert!(at("duration") < at("rtol") && at("rtol") < at("stop_when_settled"));
        let impact = row(&rows, "impact");
        assert!(!impact.text.contains("None"), "{}", impact.text);
    }

    #[test]
    fn an_edit_keeps_spelling_order_and_comments() {
        let (study, tree) = tree(TEXT);
        let alpha = row(&tree.rows(), "alpha").path.clone();
        let text = tree.replaced(&alpha, "deg([8, 12])");
        let edited = Study::parse_ron(&text, "t").unwrap();
        assert_ne!(edited, study);
        let again = StudyTree::new(&edited, Some(&text));
        assert_eq!(row(&again.rows(), "alpha").text, "deg([8, 12])");
        let saved = edited.to_ron_keeping(Some(&again.text())).text;
        assert!(
            saved.contains("alpha: deg([8, 12])), // the block"),
            "{saved}"
        );
        assert!(saved.find("duration").unwrap() < saved.find("rtol").unwrap());
        assert!(saved.starts_with("// head\n"));
        assert_eq!(Study::parse_ron(&saved, "t").unwrap(), edited);
    }

    #[test]
    fn size_replaces_p_in_one_edit() {
        let (_, tree) = tree(TEXT);
        let size = row(&tree.rows(), "size").path.clone();
        let (text, at, replaced) = tree.added(&size, "size", "1.5");
        assert_eq!(replaced.as_deref(), Some("p"));
        let study = Study::parse_ron(&text, "t").unwrap();
        let tree = StudyTree::new(&study, Some(&text));
        assert_eq!(tree.item(&at).and_then(Item::key), Some("size"));
        assert!(text.contains("rigid(size: 1.5, alpha: deg(10))"), "{text}");
    }

    /// A field left to its default shows that default, in a spelling the study reads back
    /// (no `None`): written in, it changes nothing. For every shipped study.
    #[test]
    fn every_default_shown_is_the_default() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/studies");
        let mut seen = 0;
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            let Ok(study) = Study::load(&path) else {
                continue;
            };
            let text = std::fs::read_to_string(&path).unwrap();
            let tree = StudyTree::new(&study, Some(&text));
            assert_eq!(tree.text(), study.to_ron_keeping(Some(&text)).text);
            for row in tree.rows() {
                let Some(field) = &row.absent else { continue };
                if row.text == "unset" {
                    continue;
                }
                assert!(!row.text.contains("None"), "{}: {field}", path.display());
                let (doc, _, replaced) = tree.added(&row.path, field, &row.text);
                assert_eq!(replaced, None);
                let back = Study::parse_ron(&doc, "t")
                    .unwrap_or_else(|e| panic!("{}: {field}: {e}", path.display()));
                assert_eq!(back, study, "{}: {field} = {}", path.display(), row.text);
                seen += 1;
            }
        }
        assert!(seen > 20, "{seen}");
    }
}
