//! Strict parsing: every `name(` in a study file must be a variant of the schema. RON hands a
//! parameter's value (a number, list or range, read with `deserialize_any`) to us without the
//! name in front of it, so `ratio(linspace(1, 12, 24))` read as the list [1, 12, 24] and
//! `alpha_ratio(foo(1.5))` as 1.5: a silently different study. Names outside values are
//! checked by serde already; this scan catches the rest, before serde runs.
//!
//! The valid names come from the schema types themselves (serde's derived variant lists), so
//! they cannot drift from it.

use super::error::StudyError;
use super::{AmplitudeAxis, Axis, DeviceVariant, ExcitationFamily, FrequencyAxis};
use super::{RecordScaling, StructureFamily};
use crate::excitation::{KinkPolicy, PulseShape};
use crate::scene::{Coupling, Form, Impact, ResetRule};
use serde::Deserialize;
use serde::de::{self, Visitor};

/// A deserializer that only records the variant names an enum asks for.
struct VariantNames(Option<&'static [&'static str]>);

impl<'de> de::Deserializer<'de> for &mut VariantNames {
    type Error = de::value::Error;

    fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Self::Error> {
        Err(de::Error::custom("not an enum"))
    }

    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _name: &'static str,
        variants: &'static [&'static str],
        _: V,
    ) -> Result<V::Value, Self::Error> {
        self.0 = Some(variants);
        Err(de::Error::custom("recorded"))
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
        option unit unit_struct newtype_struct seq tuple tuple_struct map struct identifier
        ignored_any
    }
}

fn variants<T: for<'de> Deserialize<'de>>() -> &'static [&'static str] {
    let mut names = VariantNames(None);
    let _ = T::deserialize(&mut names);
    names.0.unwrap_or_default()
}

/// Every name a study file may put before `(`.
pub fn wrapper_names() -> Vec<&'static str> {
    let mut names: Vec<&'static str> = [
        variants::<StructureFamily>(),
        variants::<DeviceVariant>(),
        variants::<ExcitationFamily>(),
        variants::<AmplitudeAxis>(),
        variants::<FrequencyAxis>(),
        variants::<RecordScaling>(),
        variants::<Axis>(),
        variants::<PulseShape>(),
        variants::<KinkPolicy>(),
        variants::<Coupling>(),
        variants::<Impact>(),
        variants::<ResetRule>(),
        variants::<Form>(),
        variants::<super::fragility::DamageStates>(),
    ]
    .concat();
    names.push("Some");
    names.sort_unstable();
    names.dedup();
    names
}

/// `(line, column, name)` of every identifier directly followed by `(`, outside strings and
/// comments (1-based positions).
fn calls(text: &str) -> Vec<(usize, usize, String)> {
    let chars: Vec<char> = text.chars().collect();
    let (mut line, mut col) = (1, 1);
    let mut out = Vec::new();
    let mut i = 0;
    let advance = |c: char, line: &mut usize, col: &mut usize| {
        if c == '\n' {
            *line += 1;
            *col = 1;
        } else {
            *col += 1;
        }
    };
    while i < chars.len() {
        let c = chars[i];
        if c == '/' && chars.get(i + 1) == Some(&'/') {
            while i < chars.len() && chars[i] != '\n' {
                advance(chars[i], &mut line, &mut col);
                i += 1;
            }
        } else if c == '/' && chars.get(i + 1) == Some(&'*') {
            let mut depth = 0;
            while i < chars.len() {
                if chars[i] == '/' && chars.get(i + 1) == Some(&'*') {
                    depth += 1;
                } else if chars[i] == '*' && chars.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    if depth == 0 {
                        advance('*', &mut line, &mut col);
                        advance('/', &mut line, &mut col);
                        i += 2;
                        break;
                    }
                }
                advance(chars[i], &mut line, &mut col);
                i += 1;
            }
        } else if c == '"' {
            advance(c, &mut line, &mut col);
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                if chars[i] == '\\' {
                    advance(chars[i], &mut line, &mut col);
                    i += 1;
                }
                if i < chars.len() {
                    advance(chars[i], &mut line, &mut col);
                    i += 1;
                }
            }
            if i < chars.len() {
                advance(chars[i], &mut line, &mut col);
                i += 1;
            }
        } else if c.is_alphabetic() || c == '_' {
            let (start_line, start_col) = (line, col);
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                advance(chars[i], &mut line, &mut col);
                i += 1;
            }
            let name: String = chars[start..i].iter().collect();
            let mut j = i;
            while j < chars.len() && chars[j].is_whitespace() {
                j += 1;
            }
            // A raw string r"…" / r#"…"# is not a call; neither is a number's exponent.
            if chars.get(j) == Some(&'(') {
                out.push((start_line, start_col, name));
            }
        } else if c.is_ascii_digit() {
            // Skip a number whole (1e5, 0x1F) so its letters are not read as a name.
            while i < chars.len()
                && (chars[i].is_alphanumeric() || chars[i] == '.' || chars[i] == '_')
            {
                advance(chars[i], &mut line, &mut col);
                i += 1;
            }
        } else {
            advance(c, &mut line, &mut col);
            i += 1;
        }
    }
    out
}

/// The first `name(` in `text` that is not a variant of the schema (or `deg`, see
/// [`resolve_degrees`]), as a located error.
pub fn check_names(text: &str, origin: &str) -> Result<(), StudyError> {
    let valid = wrapper_names();
    for (line, column, name) in calls(text) {
        if name != DEGREES && !valid.contains(&name.as_str()) {
            return Err(StudyError {
                origin: origin.to_string(),
                line: Some(line),
                column: Some(column),
                field: None,
                message: format!("unknown name `{name}(`"),
                hint: Some(format!(
                    "a parameter is a number, a list [a, b, …] or a range (from: a, to: b, \
                     steps: n); an angle may be given in degrees as deg(10); the names a study \
                     may use before `(` are: {}",
                    valid.join(", ")
                )),
            });
        }
    }
    Ok(())
}

/// The wrapper that gives an angle in degrees: `alpha: deg(10)`.
const DEGREES: &str = "deg";

/// The study fields that hold an angle (in radians), and so take `deg(…)`.
pub const ANGLE_FIELDS: &[&str] = &["alpha"];

/// The keys of a range (`(from: a, to: b, steps: n, log: true)`), which belong to the field
/// the range is the value of.
const RANGE_KEYS: &[&str] = &["from", "to", "steps", "log"];

/// A token of a study file: its byte span, 1-based line and column, and kind.
#[derive(Clone, Debug)]
struct Token {
    start: usize,
    end: usize,
    line: usize,
    column: usize,
    kind: Kind,
}

#[derive(Clone, Debug, PartialEq)]
enum Kind {
    Name,
    Number,
    Text,
    Punct(char),
}

/// The tokens of `text`, comments and whitespace left out.
fn tokens(text: &str) -> Vec<Token> {
    let bytes: Vec<(usize, char)> = text.char_indices().collect();
    let at = |i: usize| bytes.get(i).map(|b| b.1);
    let offset = |i: usize| bytes.get(i).map_or(text.len(), |b| b.0);
    let (mut line, mut column) = (1, 1);
    let mut out = Vec::new();
    let mut i = 0;
    // Move `i` to `to`, keeping line and column.
    let skip_to = |i: &mut usize, to: usize, line: &mut usize, column: &mut usize| {
        while *i < to {
            if bytes[*i].1 == '\n' {
                *line += 1;
                *column = 1;
            } else {
                *column += 1;
            }
            *i += 1;
        }
    };
    while i < bytes.len() {
        let c = bytes[i].1;
        let start = i;
        let (start_line, start_column) = (line, column);
        let mut end = i + 1;
        let kind = if c.is_whitespace() {
            None
        } else if c == '/' && at(i + 1) == Some('/') {
            while end < bytes.len() && bytes[end].1 != '\n' {
                end += 1;
            }
            None
        } else if c == '/' && at(i + 1) == Some('*') {
            let mut depth = 1;
            end = i + 2;
            while end < bytes.len() && depth > 0 {
                if bytes[end].1 == '/' && at(end + 1) == Some('*') {
                    depth += 1;
                    end += 1;
                } else if bytes[end].1 == '*' && at(end + 1) == Some('/') {
                    depth -= 1;
                    end += 1;
                }
                end += 1;
            }
            None
        } else if c == '"' {
            while end < bytes.len() && bytes[end].1 != '"' {
                end += if bytes[end].1 == '\\' { 2 } else { 1 };
            }
            end = (end + 1).min(bytes.len());
            Some(Kind::Text)
        } else if c.is_alphabetic() || c == '_' {
            while end < bytes.len() && (bytes[end].1.is_alphanumeric() || bytes[end].1 == '_') {
                end += 1;
            }
            Some(Kind::Name)
        } else if c.is_ascii_digit()
            || ((c == '-' || c == '+' || c == '.')
                && at(i + 1).is_some_and(|d| d.is_ascii_digit() || d == '.'))
        {
            while end < bytes.len() {
                let d = bytes[end].1;
                let sign_of_exponent =
                    (d == '-' || d == '+') && matches!(bytes[end - 1].1, 'e' | 'E');
                if d.is_alphanumeric() || d == '.' || d == '_' || sign_of_exponent {
                    end += 1;
                } else {
                    break;
                }
            }
            Some(Kind::Number)
        } else {
            Some(Kind::Punct(c))
        };
        skip_to(&mut i, end, &mut line, &mut column);
        if let Some(kind) = kind {
            out.push(Token {
                start: offset(start),
                end: offset(end),
                line: start_line,
                column: start_column,
                kind,
            });
        }
    }
    out
}

/// `text` with every `deg(…)` replaced by the same angles in radians: `alpha: deg(10)`,
/// `alpha: deg([5, 10])`, `alpha: deg((from: 5, to: 15, steps: 3))` (a range's `steps` and
/// `log` are kept). RON would read `deg(10)` as the bare 10 (its `deserialize_any` drops the
/// name), so degrees are turned into radians here, before serde runs; a study records angles
/// in radians only. `deg` on a field that is not an angle, or around anything but numbers,
/// is a located error. Lines keep their numbers (only numbers and the wrapper change).
pub fn resolve_degrees<'a>(
    text: &'a str,
    origin: &str,
) -> Result<std::borrow::Cow<'a, str>, StudyError> {
    let tokens = tokens(text);
    if !tokens
        .iter()
        .any(|t| t.kind == Kind::Name && &text[t.start..t.end] == DEGREES)
    {
        return Ok(std::borrow::Cow::Borrowed(text));
    }
    let error = |t: &Token, field: Option<&str>, message: String, hint: &str| StudyError {
        origin: origin.to_string(),
        line: Some(t.line),
        column: Some(t.column),
        field: field.map(str::to_string),
        message,
        hint: Some(hint.to_string()),
    };
    let word = |t: &Token| &text[t.start..t.end];
    let mut out = String::with_capacity(text.len());
    let mut copied = 0;
    // The key being given at each nesting level.
    let mut keys: Vec<Option<&str>> = vec![None];
    let mut i = 0;
    while i < tokens.len() {
        let t = &tokens[i];
        let next = tokens.get(i + 1).map(|n| &n.kind);
        match &t.kind {
            Kind::Name if next == Some(&Kind::Punct(':')) => {
                if let Some(top) = keys.last_mut() {
                    *top = Some(word(t));
                }
            }
            Kind::Punct('(' | '[' | '{') => keys.push(None),
            Kind::Punct(')' | ']' | '}') => {
                keys.pop();
                if keys.is_empty() {
                    keys.push(None);
                }
            }
            Kind::Name if word(t) == DEGREES && next == Some(&Kind::Punct('(')) => {
                let field = keys
                    .iter()
                    .rev()
                    .flatten()
                    .find(|k| !RANGE_KEYS.contains(k))
                    .copied();
                if !field.is_some_and(|f| ANGLE_FIELDS.contains(&f)) {
                    return Err(error(
                        t,
                        field,
                        format!(
                            "`deg(…)` on {}, which is not an angle",
                            field.map_or("a value".to_string(), |f| format!("`{f}`"))
                        ),
                        &format!(
                            "degrees are for the angle fields ({}); give this field as a plain \
                             number in its own unit",
                            ANGLE_FIELDS.join(", ")
                        ),
                    ));
                }
                // The argument: numbers in a list or range, up to the matching `)`.
                let mut depth = 0;
                let mut j = i + 1;
                let mut converted = String::new();
                let mut from = tokens[i + 1].end;
                let mut key: Option<&str> = None;
                let mut numbers = 0;
                loop {
                    let Some(a) = tokens.get(j) else {
                        return Err(error(
                            t,
                            field,
                            "`deg(` is never closed".into(),
                            "write the angle in degrees as deg(10)",
                        ));
                    };
                    match &a.kind {
                        Kind::Punct('(' | '[') => depth += 1,
                        Kind::Punct(')' | ']') => depth -= 1,
                        Kind::Punct(',' | ':') => {}
                        Kind::Name if RANGE_KEYS.contains(&word(a)) => key = Some(word(a)),
                        Kind::Name if matches!(word(a), "true" | "false") => {}
                        Kind::Number if key == Some("steps") => numbers += 1,
                        Kind::Number => {
                            let radians = parse_angle(&format!("{}deg", word(a))).map_err(|e| {
                                error(a, field, e, "write the angle in degrees as deg(10)")
                            })?;
                            converted.push_str(&text[from..a.start]);
                            converted.push_str(&format!("{radians:?}"));
                            from = a.end;
                            numbers += 1;
                        }
                        _ => {
                            return Err(error(
                                a,
                                field,
                                format!("`{}` in deg(…) is not a number", word(a)),
                                "deg takes a number, a list or a range of degrees: deg(10), \
                                 deg([5, 10]), deg((from: 5, to: 15, steps: 3))",
                            ));
                        }
                    }
                    if depth == 0 {
                        break;
                    }
                    j += 1;
                }
                if numbers == 0 {
                    return Err(error(
                        t,
                        field,
                        "`deg()` holds no angle".into(),
                        "write the angle in degrees as deg(10)",
                    ));
                }
                // `deg(` … `)` becomes the converted argument alone.
                let close = &tokens[j];
                converted.push_str(&text[from..close.start]);
                out.push_str(&text[copied..t.start]);
                out.push_str(&converted);
                copied = close.end;
                i = j + 1;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    out.push_str(&text[copied..]);
    Ok(std::borrow::Cow::Owned(out))
}

/// An angle in radians: a bare number or `…rad`, or degrees as `…deg` / `…°` (the study's
/// `deg(…)` and `simulate --alpha` share it).
pub fn parse_angle(text: &str) -> Result<f64, String> {
    let t = text.trim();
    let (number, to_rad) = if let Some(n) = t.strip_suffix("deg").or_else(|| t.strip_suffix('°')) {
        (n, std::f64::consts::PI / 180.0)
    } else {
        (t.strip_suffix("rad").unwrap_or(t), 1.0)
    };
    number
        .trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .map(|v| v * to_rad)
        .ok_or_else(|| {
            format!("`{text}` is not an angle: give radians (0.1745) or degrees (10deg)")
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_come_from_the_schema() {
        let names = wrapper_names();
        for n in [
            "rigid",
            "flexible",
            "mechanistic",
            "pulse",
            "record",
            "ratio",
            "alpha_ratio",
        ] {
            assert!(names.contains(&n), "{n} missing from {names:?}");
        }
        assert!(!names.contains(&"linspace"));
    }

    #[test]
    fn calls_skip_strings_comments_and_numbers() {
        let text = "a(b: \"x(\", // y(\n /* z( */ c (1e5))";
        let found: Vec<String> = calls(text).into_iter().map(|c| c.2).collect();
        assert_eq!(found, ["a", "c"]);
        assert_eq!(calls("\n  foo(1)")[0], (2, 3, "foo".to_string()));
    }
}
