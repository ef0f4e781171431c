//! RON syntax, once: a lexer that keeps comments and positions, a small tree of the text
//! (named groups, keys, atoms, comments where they were written) and a printer. The strict
//! reading of a study (`study::strict`) and the writer that saves a study as its user wrote
//! it (`study::writer`) both read RON through this module, so a raw string, a nested
//! comment or a byte string is read the same way everywhere (the records index too).
//!
//! Why not the `ron` crate's own parser: it reads straight into serde types and drops what the
//! strict reading needs (the name written before a parameter's value, duplicate keys of a
//! `deserialize_any` map, the position of each) and what the writer needs (comments, layout).
//! Serde still owns the meaning of a study; this module only sees its shape.

/// Where a token sits: byte range, 1-based line and column (in characters).
///
/// Positions never make two values different: two trees that spell the same values at
/// different places compare equal (the writer compares a file's tree with a fresh one).
#[derive(Clone, Copy, Debug, Default)]
pub struct Span {
    pub start: usize,
    pub end: usize,
    pub line: usize,
    pub column: usize,
}

impl PartialEq for Span {
    fn eq(&self, _: &Span) -> bool {
        true
    }
}

#[derive(Clone, Debug, PartialEq)]
pub enum Kind {
    /// `// …` or `/* … */` (nested), as written.
    Comment,
    /// A string: `"…"`, raw `r#"…"#`, byte `b"…"`, or a character `'…'`.
    Text,
    /// A name, number or other bare word (`rigid`, `1e-5`, `true`, `-inf`).
    Atom,
    /// One of `( ) [ ] { } , :`.
    Punct(char),
}

#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    pub kind: Kind,
    pub span: Span,
    /// Whether the token is the first thing on its line.
    pub starts_line: bool,
}

impl Token {
    /// The token's text in `source`.
    pub fn text<'a>(&self, source: &'a str) -> &'a str {
        &source[self.span.start..self.span.end]
    }

    /// Whether the token is an identifier (not a number): `rigid`, `from`, `Some`.
    pub fn is_name(&self, source: &str) -> bool {
        self.kind == Kind::Atom
            && self
                .text(source)
                .starts_with(|c: char| c.is_alphabetic() || c == '_')
    }
}

/// A text RON cannot read: an unclosed comment or string.
#[derive(Clone, Debug, PartialEq)]
pub struct SyntaxError {
    pub span: Span,
    pub message: String,
}

const PUNCT: &str = "()[]{},:";

/// The deepest nesting of brackets a text may have. A study needs about six (a list in a
/// range in a device in the study); the parser and every walk over its tree recurse once per
/// level, so a bound far above any study's keeps a hostile text (10 000 brackets) from
/// overflowing the stack.
pub const MAX_DEPTH: usize = 64;

/// The first bracket of `tokens` that opens a level past [`MAX_DEPTH`], as an error.
pub fn too_deep(tokens: &[Token]) -> Option<SyntaxError> {
    let mut depth = 0usize;
    for t in tokens {
        match t.kind {
            Kind::Punct('(' | '[' | '{') => depth += 1,
            Kind::Punct(')' | ']' | '}') => depth = depth.saturating_sub(1),
            _ => {}
        }
        if depth > MAX_DEPTH {
            return Some(SyntaxError {
                span: t.span,
                message: format!("brackets nested more than {MAX_DEPTH} deep"),
            });
        }
    }
    None
}

/// The tokens of `text`, whitespace left out, comments kept.
pub fn lex(text: &str) -> Result<Vec<Token>, SyntaxError> {
    let chars: Vec<(usize, char)> = text.char_indices().collect();
    let at = |i: usize| chars.get(i).map(|c| c.1);
    let offset = |i: usize| chars.get(i).map_or(text.len(), |c| c.0);
    let mut out = Vec::new();
    let (mut line, mut column) = (1, 1);
    let mut line_start = true;
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i].1;
        let (start_line, start_column) = (line, column);
        let span_to = |end: usize| Span {
            start: offset(i),
            end: offset(end),
            line: start_line,
            column: start_column,
        };
        let unclosed = |what: &str| SyntaxError {
            span: span_to(i + 1),
            message: format!("{what} is never closed"),
        };
        let (kind, end) = if c.is_whitespace() {
            (None, i + 1)
        } else if c == '/' && at(i + 1) == Some('/') {
            let mut end = i;
            while end < chars.len() && chars[end].1 != '\n' {
                end += 1;
            }
            (Some(Kind::Comment), end)
        } else if c == '/' && at(i + 1) == Some('*') {
            let (mut depth, mut end) = (1, i + 2);
            while depth > 0 {
                match (at(end), at(end + 1)) {
                    (None, _) => return Err(unclosed("the comment `/*`")),
                    (Some('/'), Some('*')) => (depth, end) = (depth + 1, end + 2),
                    (Some('*'), Some('/')) => (depth, end) = (depth - 1, end + 2),
                    _ => end += 1,
                }
            }
            (Some(Kind::Comment), end)
        } else if let Some(end) = raw_string(&chars, i) {
            (
                Some(Kind::Text),
                end.ok_or_else(|| unclosed("the raw string"))?,
            )
        } else if c == '"' || c == '\'' || (c == 'b' && at(i + 1) == Some('"')) {
            let quote = if c == 'b' { '"' } else { c };
            let mut end = if c == 'b' { i + 2 } else { i + 1 };
            loop {
                match at(end) {
                    None => return Err(unclosed("the string")),
                    Some('\\') => end += 2,
                    Some(q) if q == quote => break,
                    Some(_) => end += 1,
                }
            }
            (Some(Kind::Text), end + 1)
        } else if PUNCT.contains(c) {
            (Some(Kind::Punct(c)), i + 1)
        } else {
            let mut end = i + 1;
            while let Some(d) = at(end) {
                let comment = d == '/' && matches!(at(end + 1), Some('/' | '*'));
                if d.is_whitespace() || PUNCT.contains(d) || d == '"' || comment {
                    break;
                }
                end += 1;
            }
            (Some(Kind::Atom), end)
        };
        let end = end.min(chars.len());
        if let Some(kind) = kind {
            out.push(Token {
                kind,
                span: span_to(end),
                starts_line: line_start,
            });
            line_start = false;
        }
        while i < end {
            if chars[i].1 == '\n' {
                (line, column) = (line + 1, 1);
                line_start = true;
            } else {
                column += 1;
            }
            i += 1;
        }
    }
    Ok(out)
}

/// If a raw string (`r"…"`, `r#"…"#`, `br#"…"#`) starts at `i`: the index after it, or None
/// inside if it is never closed.
fn raw_string(chars: &[(usize, char)], i: usize) -> Option<Option<usize>> {
    let at = |i: usize| chars.get(i).map(|c| c.1);
    let mut j = i;
    if at(j) == Some('b') {
        j += 1;
    }
    if at(j) != Some('r') {
        return None;
    }
    // A raw string starts a token: `bar"` is not one.
    if i > 0 && at(i - 1).is_some_and(|p| p.is_alphanumeric() || p == '_') {
        return None;
    }
    j += 1;
    let mut hashes = 0;
    while at(j) == Some('#') {
        hashes += 1;
        j += 1;
    }
    if at(j) != Some('"') {
        return None;
    }
    j += 1;
    while j < chars.len() {
        if chars[j].1 == '"' && (1..=hashes).all(|k| at(j + k) == Some('#')) {
            return Some(Some(j + 1 + hashes));
        }
        j += 1;
    }
    Some(None)
}

/// The closing bracket of `open`.
pub fn close_of(open: char) -> char {
    match open {
        '(' => ')',
        '[' => ']',
        _ => '}',
    }
}

/// A value of the tree: a bare atom or string, or a bracketed group with an optional name
/// in front (`rigid(…)`, `[…]`, `(from: …)`).
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Atom(String, Span),
    Group {
        /// The name before the bracket (`rigid`, `ratio`), or empty.
        name: String,
        /// The name's position (the bracket's for an unnamed group).
        at: Span,
        open: char,
        items: Vec<Item>,
        /// Comments after the last item, before the closing bracket.
        tail: Vec<String>,
        /// Whether the file had the group over several lines (None: not from a file).
        broken: Option<bool>,
    },
}

impl Value {
    pub fn span(&self) -> Span {
        match self {
            Value::Atom(_, at) | Value::Group { at, .. } => *at,
        }
    }

    pub fn items(&self) -> &[Item] {
        match self {
            Value::Group { items, .. } => items,
            Value::Atom(..) => &[],
        }
    }
}

impl Value {
    /// The first `name(` in the value (itself or nested), with where it is written.
    pub fn first_name(&self) -> Option<(&str, Span)> {
        match self {
            Value::Atom(..) => None,
            Value::Group {
                name, at, items, ..
            } => {
                if !name.is_empty() {
                    return Some((name, *at));
                }
                items.iter().find_map(|i| i.value.first_name())
            }
        }
    }

    /// The first key given twice in one group of the value, with where it is repeated.
    pub fn duplicate_key(&self) -> Option<(&str, Span)> {
        let items = self.items();
        for (i, item) in items.iter().enumerate() {
            if let Some((key, at)) = &item.key
                && items[..i].iter().any(|o| o.key() == Some(key))
            {
                return Some((key, *at));
            }
        }
        items.iter().find_map(|i| i.value.duplicate_key())
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Item {
    /// The key (`sigma` in `sigma: 0.5`), and where it is written.
    pub key: Option<(String, Span)>,
    pub value: Value,
    /// Comments on the lines above the item.
    pub before: Vec<String>,
    /// A comment after the item on its line.
    pub after: Option<String>,
}

impl Item {
    pub fn key(&self) -> Option<&str> {
        self.key.as_ref().map(|(k, _)| k.as_str())
    }
}

/// A RON document: the text before the root value (comments, blank lines), the root, and
/// the comments after it.
pub struct Document {
    pub header: String,
    pub root: Value,
    pub footer: Vec<String>,
}

struct Parser<'a> {
    source: &'a str,
    toks: Vec<Token>,
    /// Record how groups were broken over lines (for a file, not for generated text).
    keep_layout: bool,
    at: usize,
}

impl Parser<'_> {
    fn peek(&self) -> Option<&Token> {
        self.toks.get(self.at)
    }

    fn peek_kind(&self, ahead: usize) -> Option<&Kind> {
        self.toks.get(self.at + ahead).map(|t| &t.kind)
    }

    fn text(&self, t: &Token) -> String {
        let text = t.text(self.source);
        match t.kind {
            Kind::Comment => text.trim_end().to_string(),
            _ => text.to_string(),
        }
    }

    fn error<T>(&self, message: &str) -> Result<T, SyntaxError> {
        let span = self.peek().map_or_else(
            || {
                let mut s = self.toks.last().map(|t| t.span).unwrap_or_default();
                s.start = s.end;
                s
            },
            |t| t.span,
        );
        Err(SyntaxError {
            span,
            message: message.to_string(),
        })
    }

    /// Comments that start their lines (`own_line`), or the one comment after a token on
    /// its line.
    fn comments(&mut self, own_line: bool) -> Vec<String> {
        let mut out = Vec::new();
        while let Some(t) = self.peek() {
            if t.kind != Kind::Comment || t.starts_line != own_line {
                break;
            }
            out.push(self.text(t));
            self.at += 1;
            if !own_line {
                break;
            }
        }
        out
    }

    fn value(&mut self) -> Result<Value, SyntaxError> {
        let Some(t) = self.peek().cloned() else {
            return self.error("a value is missing");
        };
        match t.kind {
            Kind::Atom | Kind::Text => {
                self.at += 1;
                if let Some(Kind::Punct(open @ ('(' | '[' | '{'))) = self.peek_kind(0).cloned() {
                    self.at += 1;
                    return self.group(self.text(&t), t.span, open);
                }
                Ok(Value::Atom(self.text(&t), t.span))
            }
            Kind::Punct(open @ ('(' | '[' | '{')) => {
                self.at += 1;
                self.group(String::new(), t.span, open)
            }
            _ => self.error("expected a value"),
        }
    }

    fn group(&mut self, name: String, at: Span, open: char) -> Result<Value, SyntaxError> {
        let close = close_of(open);
        let mut items = Vec::new();
        // Whether an item or the closing bracket starts a line.
        let mut broken = false;
        loop {
            // Comments before an item (or after the bracket, on its line) go above it.
            let mut before = Vec::new();
            while let Some(t) = self.peek().filter(|t| t.kind == Kind::Comment) {
                before.push(self.text(t));
                self.at += 1;
            }
            broken |= self.peek().is_some_and(|t| t.starts_line);
            if self.peek_kind(0) == Some(&Kind::Punct(close)) {
                self.at += 1;
                return Ok(Value::Group {
                    name,
                    at,
                    open,
                    items,
                    tail: before,
                    broken: self.keep_layout.then_some(broken),
                });
            }
            let key = match (self.peek().cloned(), self.peek_kind(1)) {
                (Some(k), Some(Kind::Punct(':'))) if k.kind != Kind::Punct(':') => {
                    self.at += 2;
                    Some((self.text(&k), k.span))
                }
                _ => None,
            };
            let value = self.value()?;
            let mut after = self.comments(false).pop();
            match self.peek_kind(0) {
                Some(Kind::Punct(',')) => self.at += 1,
                Some(Kind::Punct(c)) if *c == close => {}
                _ => return self.error(&format!("expected `,` or `{close}`")),
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

/// The tree of `text`; `keep_layout` records which groups the text broke over lines.
pub fn parse(text: &str, keep_layout: bool) -> Result<Document, SyntaxError> {
    let toks = lex(text)?;
    if let Some(e) = too_deep(&toks) {
        return Err(e);
    }
    let first = toks
        .iter()
        .position(|t| t.kind != Kind::Comment)
        .ok_or_else(|| SyntaxError {
            span: Span::default(),
            message: "the file holds no value".into(),
        })?;
    let root_start = toks[first].span.start;
    let mut parser = Parser {
        source: text,
        toks,
        keep_layout,
        at: first,
    };
    let root = parser.value()?;
    let footer = parser.comments(true);
    if parser.at != parser.toks.len() {
        return parser.error("more text after the value");
    }
    Ok(Document {
        header: text[..root_start].to_string(),
        root,
        footer,
    })
}

/// Lines are kept within this many columns where they can be.
pub const WIDTH: usize = 100;
const INDENT: usize = 4;

/// One line, comments left out.
pub fn flat(value: &Value) -> String {
    match value {
        Value::Atom(a, _) => a.clone(),
        Value::Group {
            name, open, items, ..
        } => {
            let inner: Vec<String> = items.iter().map(flat_item).collect();
            format!("{name}{open}{}{}", inner.join(", "), close_of(*open))
        }
    }
}

fn flat_item(item: &Item) -> String {
    match item.key() {
        Some(k) => format!("{k}: {}", flat(&item.value)),
        None => flat(&item.value),
    }
}

fn has_comments(value: &Value) -> bool {
    match value {
        Value::Atom(..) => false,
        Value::Group { items, tail, .. } => {
            !tail.is_empty()
                || items
                    .iter()
                    .any(|i| !i.before.is_empty() || i.after.is_some() || has_comments(&i.value))
        }
    }
}

/// Lay `value` out starting at column `column` (after a key), its lines indented by
/// `indent`, with `suffix` (a comma) after it: a group from a file keeps its line breaks; a
/// new one stays on one line when it fits in [`WIDTH`] columns and holds at most one nested
/// group; a long list of atoms fills its lines; comments above or after their items.
pub fn layout(value: &Value, indent: usize, column: usize, suffix: &str, out: &mut String) {
    let flat_text = flat(value);
    let Value::Group {
        name,
        open,
        items,
        tail,
        broken,
        ..
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
            && matches!(i.value, Value::Atom(..))
            && i.before.is_empty()
            && i.after.is_none()
    });
    if plain_list && !items.is_empty() {
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
            if let Some(k) = item.key() {
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

/// A document as text: the header as written, the root laid out, the footer's comments.
pub fn render(header: &str, root: &Value, footer: &[String]) -> String {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(text: &str) -> Vec<(Kind, String)> {
        lex(text)
            .unwrap()
            .into_iter()
            .map(|t| (t.kind.clone(), t.text(text).to_string()))
            .collect()
    }

    #[test]
    fn raw_strings_with_quotes_are_one_token() {
        let text = "(d: r#\"tricky \" quote\"#, e: r\"a(\", f: br##\"x\"#y\"##, g: bar(1))";
        let texts: Vec<String> = kinds(text)
            .into_iter()
            .filter(|(k, _)| *k == Kind::Text)
            .map(|(_, t)| t)
            .collect();
        assert_eq!(
            texts,
            ["r#\"tricky \" quote\"#", "r\"a(\"", "br##\"x\"#y\"##"]
        );
        assert!(kinds(text).contains(&(Kind::Atom, "bar".into())));
    }

    #[test]
    fn nested_comments_strings_and_positions() {
        let text = "/* a /* b */ c( */ x(\"y(\\\"\", 'z') // w(\n  1e-5";
        let k = kinds(text);
        assert_eq!(k[0].0, Kind::Comment);
        assert_eq!(k[0].1, "/* a /* b */ c( */");
        assert_eq!(k[1], (Kind::Atom, "x".into()));
        assert_eq!(k[3], (Kind::Text, "\"y(\\\"\"".into()));
        assert_eq!(k[5], (Kind::Text, "'z'".into()));
        assert_eq!(k[7], (Kind::Comment, "// w(".into()));
        let last = lex(text).unwrap().pop().unwrap();
        assert_eq!((last.span.line, last.span.column), (2, 3));
        assert!(last.starts_line);
        assert_eq!(last.text(text), "1e-5");
    }

    #[test]
    fn unclosed_strings_and_comments_are_errors() {
        for bad in ["(a: \"x)", "/* /* */ (a: 1)", "(a: r#\"x\")"] {
            assert!(lex(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn the_tree_prints_back_what_it_read() {
        let text = "// head\n(\n    a: rigid(p: 2.0, alpha: 0.1), // tail\n    b: [1, 2, 3],\n)\n";
        let doc = parse(text, true).unwrap();
        assert_eq!(render(&doc.header, &doc.root, &doc.footer), text);
        let Value::Group { items, .. } = &doc.root else {
            panic!("a group");
        };
        assert_eq!(items[0].key(), Some("a"));
        assert_eq!(items[0].value.span().line, 3);
        assert_eq!(items[0].value.span().column, 8);
        assert_eq!(items[0].after.as_deref(), Some("// tail"));
        assert!(parse("(a: 1 b: 2)", false).is_err());
        assert!(parse("(a: 1) x", false).is_err());
    }
}
