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

/// The first `name(` in `text` that is not a variant of the schema, as a located error.
pub fn check_names(text: &str, origin: &str) -> Result<(), StudyError> {
    let valid = wrapper_names();
    for (line, column, name) in calls(text) {
        if !valid.contains(&name.as_str()) {
            return Err(StudyError {
                origin: origin.to_string(),
                line: Some(line),
                column: Some(column),
                field: None,
                message: format!("unknown name `{name}(`"),
                hint: Some(format!(
                    "a parameter is a number, a list [a, b, …] or a range (from: a, to: b, \
                     steps: n); the names a study may use before `(` are: {}",
                    valid.join(", ")
                )),
            });
        }
    }
    Ok(())
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
