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

/// Lines are kept within this many columns where they can be.
pub const WIDTH: usize = 100;
const INDENT: usize = 4;

/// A study as text, and the comments of the opened file it could not keep.
#[derive(Clone, Debug, PartialEq)]
pub struct Written {
    pub text: String,
    /// Comments (as written, `//` included) whose field is no longer in the study.
    pub lost: Vec<String>,
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    /// A comment, and whether it starts its line.
    Comment(String, bool),
    Atom(String),
    Punct(char),
}

/// Tokens of RON text: comments kept, whitespace dropped. None if the text holds something
/// this writer does not read (a raw string, an unclosed comment or string).
fn lex(text: &str) -> Option<Vec<(Tok, bool)>> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    let mut line_start = true;
    while i < chars.len() {
        let c = chars[i];
        if c == '\n' {
            line_start = true;
            i += 1;
            continue;
        }
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        let start = i;
        if c == '/' && chars.get(i + 1) == Some(&'/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
            let comment: String = chars[start..i].iter().collect();
            out.push((
                Tok::Comment(comment.trim_end().to_string(), line_start),
                line_start,
            ));
        } else if c == '/' && chars.get(i + 1) == Some(&'*') {
            let mut depth = 0;
            loop {
                if i + 1 >= chars.len() {
                    return None;
                }
                if chars[i] == '/' && chars[i + 1] == '*' {
                    depth += 1;
                    i += 2;
                } else if chars[i] == '*' && chars[i + 1] == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
            let comment: String = chars[start..i].iter().collect();
            out.push((Tok::Comment(comment, line_start), line_start));
        } else if c == '"' {
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                i += if chars[i] == '\\' { 2 } else { 1 };
            }
            if i >= chars.len() {
                return None;
            }
            i += 1;
            out.push((Tok::Atom(chars[start..i].iter().collect()), line_start));
        } else if "()[]{},:".contains(c) {
            i += 1;
            out.push((Tok::Punct(c), line_start));
        } else {
            let ends_atom = |i: usize| {
                let c = chars[i];
                c.is_whitespace()
                    || "()[]{},:\"".contains(c)
                    || (c == '/' && matches!(chars.get(i + 1), Some('/' | '*')))
            };
            while i < chars.len() && !ends_atom(i) {
                i += 1;
            }
            let atom: String = chars[start..i].iter().collect();
            // A raw string (r"…", r#"…"#) would need its own rules: not read here.
            if atom.starts_with("r#") || (atom == "r" && chars.get(i) == Some(&'"')) {
                return None;
            }
            out.push((Tok::Atom(atom), line_start));
        }
        line_start = false;
    }
    Some(out)
}

#[derive(Clone, Debug, PartialEq)]
enum Value {
    Atom(String),
    Group {
        /// The name before the bracket (`rigid`, `ratio`), or empty.
        name: String,
        open: char,
        items: Vec<Item>,
        /// Comments after the last item, before the closing bracket.
        tail: Vec<String>,
        /// Whether the file had the group over several lines (None: not from a file).
        broken: Option<bool>,
    },
}

#[derive(Clone, Debug, PartialEq)]
struct Item {
    key: Option<String>,
    value: Value,
    /// Comments on the lines above the item.
    before: Vec<String>,
    /// A comment after the item on its line.
    after: Option<String>,
}

struct Parser {
    toks: Vec<Tok>,
    /// Whether each token starts its line.
    starts_line: Vec<bool>,
    /// Record how groups were broken over lines (for a file, not for generated text).
    keep_layout: bool,
    at: usize,
}

impl Parser {
    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.at)
    }

    fn peek_at(&self, ahead: usize) -> Option<&Tok> {
        self.toks.get(self.at + ahead)
    }

    /// Comments that start their lines (`own_line`), or the one comment after a token on
    /// its line.
    fn comments(&mut self, own_line: bool) -> Vec<String> {
        let mut out = Vec::new();
        while let Some(Tok::Comment(text, starts_line)) = self.peek() {
            if *starts_line != own_line {
                break;
            }
            out.push(text.clone());
            self.at += 1;
            if !own_line {
                break;
            }
        }
        out
    }

    fn value(&mut self) -> Option<Value> {
        match self.peek()?.clone() {
            Tok::Atom(a) => {
                self.at += 1;
                if let Some(Tok::Punct(open @ ('(' | '[' | '{'))) = self.peek().cloned() {
                    self.at += 1;
                    return self.group(a, open);
                }
                Some(Value::Atom(a))
            }
            Tok::Punct(open @ ('(' | '[' | '{')) => {
                self.at += 1;
                self.group(String::new(), open)
            }
            _ => None,
        }
    }

    fn group(&mut self, name: String, open: char) -> Option<Value> {
        let close = match open {
            '(' => ')',
            '[' => ']',
            _ => '}',
        };
        let mut items = Vec::new();
        // Whether an item or the closing bracket starts a line.
        let mut broken = false;
        loop {
            // Comments before an item (or after the bracket, on its line) go above it.
            let mut before = Vec::new();
            while let Some(Tok::Comment(text, _)) = self.peek() {
                before.push(text.clone());
                self.at += 1;
            }
            broken |= self.starts_line.get(self.at) == Some(&true);
            if self.peek() == Some(&Tok::Punct(close)) {
                let broken = self.keep_layout.then_some(broken);
                self.at += 1;
                return Some(Value::Group {
                    name,
                    open,
                    items,
                    tail: before,
                    broken,
                });
            }
            let key = match (self.peek(), self.peek_at(1)) {
                (Some(Tok::Atom(k)), Some(Tok::Punct(':'))) => {
                    let k = k.clone();
                    self.at += 2;
                    Some(k)
                }
                _ => None,
            };
            let value = self.value()?;
            let mut after = self.comments(false).pop();
            match self.peek() {
                Some(Tok::Punct(',')) => self.at += 1,
                Some(Tok::Punct(c)) if *c == close => {}
                _ => return None,
            }
            if after.is_none() {
                after = self.comments(false).pop();
            }
            items.push(Item {
                key,
                value,
                before,
                after,
            });
        }
    }
}

/// A RON document: the text before the root value (comments, blank lines), the root, and
/// what follows it.
struct Document {
    header: String,
    root: Value,
    footer: Vec<String>,
}

fn parse(text: &str, keep_layout: bool) -> Option<Document> {
    let (toks, starts_line): (Vec<Tok>, Vec<bool>) = lex(text)?.into_iter().unzip();
    let first = toks.iter().position(|t| !matches!(t, Tok::Comment(..)))?;
    // The header is kept as written: everything up to the root's first character.
    let root_start = root_offset(text)?;
    let mut parser = Parser {
        toks,
        starts_line,
        keep_layout,
        at: first,
    };
    let root = parser.value()?;
    let footer = parser.comments(true);
    if parser.at != parser.toks.len() {
        return None;
    }
    Some(Document {
        header: text[..root_start].to_string(),
        root,
        footer,
    })
}

/// Byte offset of the first character that is neither whitespace nor in a comment.
fn root_offset(text: &str) -> Option<usize> {
    let mut rest = text;
    loop {
        let trimmed = rest.trim_start();
        if let Some(after) = trimmed.strip_prefix("//") {
            rest = after.find('\n').map_or("", |n| &after[n..]);
        } else if let Some(after) = trimmed.strip_prefix("/*") {
            rest = &after[after.find("*/")? + 2..];
        } else {
            return (!trimmed.is_empty()).then(|| text.len() - trimmed.len());
        }
    }
}

/// Where an item sits: its key, or its position and variant name in a list.
fn step(index: usize, item: &Item) -> String {
    match (&item.key, &item.value) {
        (Some(k), _) => k.clone(),
        (None, Value::Group { name, .. }) | (None, Value::Atom(name)) => {
            format!("[{index}]{name}")
        }
    }
}

fn children(value: &Value) -> &[Item] {
    match value {
        Value::Group { items, .. } => items,
        Value::Atom(_) => &[],
    }
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
        Value::Atom(_) => None,
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
        Value::Atom(a) => Value::Atom(a.clone()),
        Value::Group {
            name,
            open,
            items,
            broken,
            ..
        } => Value::Group {
            broken: *broken,
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

fn close_of(open: char) -> char {
    match open {
        '(' => ')',
        '[' => ']',
        _ => '}',
    }
}

/// One line, comments ignored.
fn flat(value: &Value) -> String {
    match value {
        Value::Atom(a) => a.clone(),
        Value::Group {
            name, open, items, ..
        } => {
            let inner: Vec<String> = items.iter().map(flat_item).collect();
            format!("{name}{open}{}{}", inner.join(", "), close_of(*open))
        }
    }
}

fn flat_item(item: &Item) -> String {
    match &item.key {
        Some(k) => format!("{k}: {}", flat(&item.value)),
        None => flat(&item.value),
    }
}

fn has_comments(value: &Value) -> bool {
    match value {
        Value::Atom(_) => false,
        Value::Group { items, tail, .. } => {
            !tail.is_empty()
                || items
                    .iter()
                    .any(|i| !i.before.is_empty() || i.after.is_some() || has_comments(&i.value))
        }
    }
}

/// Lay `value` out starting at column `column` (after a key), its lines indented by
/// `indent`, with `suffix` (a comma) after it.
fn layout(value: &Value, indent: usize, column: usize, suffix: &str, out: &mut String) {
    let flat_text = flat(value);
    let Value::Group {
        name,
        open,
        items,
        tail,
        broken,
    } = value
    else {
        out.push_str(&flat_text);
        out.push_str(suffix);
        return;
    };
    let nested = items
        .iter()
        .filter(|i| matches!(i.value, Value::Group { .. }))
        .count();
    let fits = column + flat_text.chars().count() + suffix.len() <= WIDTH;
    // As the file had it, if it comes from the file; else on one line when it fits and holds
    // at most one nested group.
    let one_line = match broken {
        Some(broken) => !broken,
        None => fits && nested <= 1,
    };
    if indent > 0 && one_line && !has_comments(value) {
        out.push_str(&flat_text);
        out.push_str(suffix);
        return;
    }
    let inner = indent + INDENT;
    let pad = " ".repeat(inner);
    out.push_str(name);
    out.push(*open);
    out.push('\n');
    let plain_list = items.iter().all(|i| {
        i.key.is_none()
            && matches!(i.value, Value::Atom(_))
            && i.before.is_empty()
            && i.after.is_none()
    });
    if plain_list && !items.is_empty() {
        // Numbers (or names) fill their lines.
        let mut line = String::new();
        for item in items {
            let word = format!("{},", flat(&item.value));
            if !line.is_empty() && inner + line.len() + 1 + word.len() > WIDTH {
                out.push_str(&pad);
                out.push_str(&line);
                out.push('\n');
                line.clear();
            }
            if !line.is_empty() {
                line.push(' ');
            }
            line.push_str(&word);
        }
        out.push_str(&pad);
        out.push_str(&line);
        out.push('\n');
    } else {
        for item in items {
            for comment in &item.before {
                push_comment(comment, &pad, out);
            }
            out.push_str(&pad);
            let mut column = inner;
            if let Some(k) = &item.key {
                out.push_str(k);
                out.push_str(": ");
                column += k.chars().count() + 2;
            }
            layout(&item.value, inner, column, ",", out);
            if let Some(after) = &item.after {
                out.push(' ');
                out.push_str(after);
            }
            out.push('\n');
        }
    }
    for comment in tail {
        push_comment(comment, &pad, out);
    }
    out.push_str(&" ".repeat(indent));
    out.push(close_of(*open));
    out.push_str(suffix);
}

/// A comment on its own lines at `pad`; a block comment's later lines as written.
fn push_comment(comment: &str, pad: &str, out: &mut String) {
    out.push_str(pad);
    out.push_str(comment);
    out.push('\n');
}

fn render(header: &str, root: &Value, footer: &[String]) -> String {
    let mut out = header.to_string();
    layout(
        root,
        0,
        header.lines().last().map_or(0, str::len),
        "",
        &mut out,
    );
    out.push('\n');
    for comment in footer {
        out.push_str(comment);
        out.push('\n');
    }
    out
}

/// Whether `text` reads back as `study`.
fn same(text: &str, study: &Study) -> bool {
    Study::parse_ron(text, "save").is_ok_and(|back| back == *study)
}

/// `study` as text, laid out as the module says, keeping what it can of `original` (the
/// text of the file the study was opened from, if any).
pub fn write(study: &Study, original: Option<&str>) -> Written {
    let original = original.map(|t| t.strip_prefix('\u{feff}').unwrap_or(t));
    let compact = ron::Options::default()
        .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
        .to_string(study)
        .expect("studies serialise");
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
            Value::Atom(_) => Vec::new(),
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
