//! Study errors: where (file, line, column), what (field), why, and what to do about it.

use std::fmt;

#[derive(Clone, Debug, PartialEq)]
pub struct StudyError {
    pub origin: String,
    pub line: Option<usize>,
    pub column: Option<usize>,
    pub field: Option<String>,
    pub message: String,
    pub hint: Option<String>,
}

impl std::error::Error for StudyError {}

impl fmt::Display for StudyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.origin)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(col) = self.column {
                write!(f, ":{col}")?;
            }
        }
        write!(f, ": ")?;
        if let Some(field) = &self.field {
            write!(f, "{field}: ")?;
        }
        write!(f, "{}", self.message)?;
        if let Some(hint) = &self.hint {
            write!(f, " (hint: {hint})")?;
        }
        Ok(())
    }
}

impl StudyError {
    /// An error about a field, without a file position yet.
    pub fn field(field: impl Into<String>, message: impl Into<String>, hint: &str) -> Self {
        StudyError {
            origin: "study".into(),
            line: None,
            column: None,
            field: Some(field.into()),
            message: message.into(),
            hint: (!hint.is_empty()).then(|| hint.to_string()),
        }
    }

    /// A RON error of study `text` (as RON read it), with the field it falls in.
    pub fn from_ron(e: ron::error::SpannedError, text: &str, origin: &str) -> Self {
        use ron::error::Error as E;
        let (field, hint) = match &e.code {
            E::NoSuchStructField { found, .. } => (
                Some(found.clone()),
                Some("check the spelling: fields are snake_case as in studies/*.ron".into()),
            ),
            E::MissingStructField { field, outer } => (
                Some(field.to_string()),
                Some(match outer {
                    Some(o) => format!("add `{field}: …` to {o}"),
                    None => format!("add `{field}: …`"),
                }),
            ),
            E::NoSuchEnumVariant { found, .. } => (
                Some(found.clone()),
                Some("variant names are snake_case, e.g. `none`, `alpha_ratio(1.5)`".into()),
            ),
            E::DuplicateStructField { field, .. } => {
                (Some(field.to_string()), Some("give each field once".into()))
            }
            _ => (
                None,
                Some("see studies/default.ron for a complete example".into()),
            ),
        };
        let mut error = StudyError {
            origin: origin.to_string(),
            line: Some(e.span.start.line),
            column: Some(e.span.start.col),
            field,
            message: e.code.to_string(),
            hint,
        };
        // RON's own words name no field (`seed: 1.5` is "Expected comma"): the field whose
        // value holds the position, and what the error means there.
        if error.field.is_none()
            && let Some(place) = super::strict::place_of(text, e.span.start.line, e.span.start.col)
        {
            let (message, hint) = super::strict::explain_ron_error(&e.code, &place);
            (error.field, error.message, error.hint) = (Some(place.field), message, Some(hint));
        }
        error
    }

    /// Fill in the file and the position of the field's key in `text`: the first occurrence of
    /// the last path component as a key, searched after the path's earlier components.
    pub fn located(mut self, text: &str, origin: &str) -> Self {
        self.origin = origin.to_string();
        if self.line.is_some() {
            return self;
        }
        let Some(path) = &self.field else {
            return self;
        };
        let mut from = 0;
        let mut found = None;
        for part in path.split('.') {
            let name = part.split('[').next().unwrap_or(part);
            if let Some(at) = find_key(&text[from..], name) {
                from += at;
                found = Some(from);
            }
            if let Some(idx) = part
                .split('[')
                .nth(1)
                .and_then(|s| s.trim_end_matches(']').parse::<usize>().ok())
            {
                // Skip to the idx-th item of the list: count top-level item starts crudely by
                // the variant names that open each device.
                if let Some(at) = nth_item(&text[from..], idx) {
                    from += at;
                    found = Some(from);
                }
            }
        }
        if found.is_none() && !path.contains('.') {
            // A top-level field that is not in the file (missing): where it would go, the
            // study's closing parenthesis.
            found = last_close(text);
        }
        if let Some(at) = found {
            let before = &text[..at];
            self.line = Some(before.matches('\n').count() + 1);
            self.column = Some(before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1);
        }
        self
    }
}

/// Offset of the last `)` outside comments.
fn last_close(text: &str) -> Option<usize> {
    let mut offset = 0;
    let mut last = None;
    for line in text.split_inclusive('\n') {
        let code = line.split("//").next().unwrap_or(line);
        if let Some(i) = code.rfind(')') {
            last = Some(offset + i);
        }
        offset += line.len();
    }
    last
}

/// Offset of `name` used as a key (`name:` or `name(`) outside comments.
fn find_key(text: &str, name: &str) -> Option<usize> {
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let code = line.split("//").next().unwrap_or(line);
        let mut start = 0;
        while let Some(i) = code[start..].find(name) {
            let at = start + i;
            let before_ok = at == 0
                || !code[..at]
                    .chars()
                    .next_back()
                    .is_some_and(|c| c.is_alphanumeric() || c == '_');
            let rest = code[at + name.len()..].trim_start();
            if before_ok && (rest.starts_with(':') || rest.starts_with('(')) {
                return Some(offset + at);
            }
            start = at + name.len();
        }
        offset += line.len();
    }
    None
}

/// Offset of the idx-th element of the list that starts at the first '[' in `text`.
fn nth_item(text: &str, idx: usize) -> Option<usize> {
    let open = text.find('[')?;
    let mut depth = 0;
    let mut item = 0;
    let mut item_start = None;
    let mut in_comment = false;
    let bytes = text.as_bytes();
    let mut i = open + 1;
    while i < bytes.len() {
        let c = bytes[i] as char;
        if in_comment {
            if c == '\n' {
                in_comment = false;
            }
        } else if c == '/' && bytes.get(i + 1) == Some(&b'/') {
            in_comment = true;
        } else if depth == 0 && item_start.is_none() && !c.is_whitespace() && c != ',' {
            if c == ']' {
                return None;
            }
            item_start = Some(i);
            if item == idx {
                return Some(i);
            }
        }
        if !in_comment {
            match c {
                '(' | '[' => depth += 1,
                ')' | ']' if depth == 0 => return None,
                ')' | ']' => depth -= 1,
                ',' if depth == 0 => {
                    item += 1;
                    item_start = None;
                }
                _ => {}
            }
        }
        i += 1;
    }
    None
}
