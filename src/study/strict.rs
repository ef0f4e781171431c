//! Strict parsing: every `name(` in a study file must be a variant of the schema. RON hands a
//! parameter's value (a number, list or range, read with `deserialize_any`) to us without the
//! name in front of it, so `ratio(linspace(1, 12, 24))` read as the list [1, 12, 24] and
//! `alpha_ratio(foo(1.5))` as 1.5: a silently different study. Names outside values are
//! checked by serde already; this scan catches the rest, before serde runs.
//!
//! The valid names come from the schema types themselves (serde's derived variant lists), so
//! they cannot drift from it.

use super::error::StudyError;
use super::{AmplitudeAxis, Axis, CouplingFamily, DeviceVariant, ExcitationFamily, FrequencyAxis};
use super::{RecordScaling, StructureFamily};
use crate::excitation::{KinkPolicy, PulseShape};
use crate::ron_syntax::{self as syntax, Kind, SyntaxError, Token};
use crate::scene::{Form, Impact, ResetRule};
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

/// The names of the pulse shapes (the schema's own).
pub fn pulse_shape_names() -> &'static [&'static str] {
    variants::<PulseShape>()
}

/// Every `shape:` value names a pulse shape: an unknown one (alone or in a list) is a located
/// error with the nearest name, before RON would say "data did not match any variant".
pub fn check_shapes(text: &str, origin: &str) -> Result<(), StudyError> {
    let Ok(doc) = syntax::parse(text, false) else {
        return Ok(());
    };
    shapes_in(&doc.root, origin)
}

fn shapes_in(value: &syntax::Value, origin: &str) -> Result<(), StudyError> {
    let syntax::Value::Group { items, .. } = value else {
        return Ok(());
    };
    for item in items {
        if item.key.as_ref().is_some_and(|(k, _)| k == "shape") {
            let words: Vec<&syntax::Value> = match &item.value {
                syntax::Value::Group {
                    name,
                    open: '[',
                    items,
                    ..
                } if name.is_empty() => items.iter().map(|i| &i.value).collect(),
                other => vec![other],
            };
            for word in words {
                let syntax::Value::Atom(name, at) = word else {
                    continue;
                };
                let known = pulse_shape_names();
                if !known.contains(&name.as_str()) {
                    return Err(StudyError {
                        origin: origin.to_string(),
                        line: Some(at.line),
                        column: Some(at.column),
                        field: Some("excitation.shape".into()),
                        message: format!("unknown pulse shape `{name}`"),
                        hint: Some(match super::error::closest(name, known) {
                            Some(near) => format!("did you mean `{near}`?"),
                            None => format!(
                                "the shapes are: {}; several as a list, e.g. [sine, ricker]",
                                known.join(", ")
                            ),
                        }),
                    });
                }
            }
        }
        shapes_in(&item.value, origin)?;
    }
    Ok(())
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
        variants::<CouplingFamily>(),
        variants::<Impact>(),
        variants::<ResetRule>(),
        variants::<Form>(),
        variants::<super::design::DesignTarget>(),
        variants::<super::fragility::DamageStates>(),
        variants::<super::fragility::Method>(),
        variants::<super::uncertain::Distribution>(),
        variants::<super::uncertain::Sampling>(),
        variants::<super::uncertain::Draws>(),
    ]
    .concat();
    names.push("Some");
    names.sort_unstable();
    names.dedup();
    names
}

/// `(line, column, name)` of every identifier directly followed by `(`, outside strings and
/// comments (1-based positions).
fn calls(text: &str, tokens: &[Token]) -> Vec<(usize, usize, String)> {
    tokens
        .windows(2)
        .filter(|w| w[0].is_name(text) && w[1].kind == Kind::Punct('('))
        .map(|w| {
            (
                w[0].span.line,
                w[0].span.column,
                w[0].text(text).to_string(),
            )
        })
        .collect()
}

/// The tokens of `text` without its comments; none if the text cannot be read (an unclosed
/// string): then RON reports it, in its own words, and nothing else is checked.
fn tokens(text: &str) -> Vec<Token> {
    let mut tokens = syntax::lex(text).unwrap_or_default();
    tokens.retain(|t| t.kind != Kind::Comment);
    tokens
}

fn syntax_error(e: SyntaxError, origin: &str) -> StudyError {
    StudyError {
        origin: origin.to_string(),
        line: Some(e.span.line),
        column: Some(e.span.column),
        field: None,
        message: e.message,
        hint: Some("close every string with `\"` and every `/*` comment with `*/`".into()),
    }
}

/// Brackets nested past [`syntax::MAX_DEPTH`], as a located error: checked before anything
/// recurses over the text.
pub fn check_nesting(text: &str, origin: &str) -> Result<(), StudyError> {
    match syntax::too_deep(&tokens(text)) {
        Some(e) => Err(StudyError {
            hint: Some(format!(
                "a study nests a few levels (a list in a range in a device); remove the \
                 extra brackets (at most {} levels)",
                syntax::MAX_DEPTH
            )),
            ..syntax_error(e, origin)
        }),
        None => Ok(()),
    }
}

/// The first `name(` in `text` that is not a variant of the schema (or `deg`, see
/// [`resolve_degrees`]), as a located error.
pub fn check_names(text: &str, origin: &str) -> Result<(), StudyError> {
    let valid = wrapper_names();
    for (line, column, name) in calls(text, &tokens(text)) {
        if name != DEGREES && !valid.contains(&name.as_str()) {
            return Err(StudyError {
                origin: origin.to_string(),
                line: Some(line),
                column: Some(column),
                field: None,
                message: format!("unknown name `{name}(`"),
                hint: Some(match super::error::closest(&name, &valid) {
                    Some(near) => format!("did you mean `{near}(`?"),
                    None => format!(
                        "a parameter is a number, a list [a, b, …] or a range (from: a, to: b, \
                         steps: n); an angle may be given in degrees as deg(10); the names a \
                         study may use before `(` are: {}",
                        // `Some` is RON's, not a name to offer.
                        (valid.iter().filter(|n| **n != "Some"))
                            .copied()
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                }),
            });
        }
    }
    Ok(())
}

/// Where a RON error of the study's text falls: the field being given there (a dotted path,
/// `devices[1].sigma`) and the value written at that place, if one is.
pub struct ErrorPlace {
    pub field: String,
    pub value: Option<String>,
}

/// The field whose value holds 1-based (`line`, `column`) of `text`: the keys given at each
/// enclosing level, in a walk over the tokens before the position (a list's items by index).
pub fn place_of(text: &str, line: usize, column: usize) -> Option<ErrorPlace> {
    // At each nesting level: the key being given, and for a list the item's index.
    let mut levels: Vec<(Option<&str>, Option<usize>)> = vec![(None, None)];
    let mut value = None;
    let tokens = tokens(text);
    for (i, t) in tokens.iter().enumerate() {
        if (t.span.line, t.span.column) > (line, column) {
            break;
        }
        let next = tokens.get(i + 1).map(|n| &n.kind);
        match t.kind {
            Kind::Atom if next == Some(&Kind::Punct(':')) => {
                if let Some(top) = levels.last_mut() {
                    top.0 = Some(t.text(text));
                }
                value = None;
            }
            Kind::Punct('[') => levels.push((None, Some(0))),
            Kind::Punct('(' | '{') => levels.push((None, None)),
            Kind::Punct(')' | ']' | '}') if levels.len() > 1 => {
                levels.pop();
            }
            Kind::Punct(',') => {
                if let Some((key, index)) = levels.last_mut() {
                    match index {
                        Some(n) => *n += 1,
                        None => *key = None,
                    }
                }
                value = None;
            }
            Kind::Atom | Kind::Text => value = Some(t.text(text)),
            _ => {}
        }
    }
    let mut path = String::new();
    for (key, index) in &levels {
        if let Some(key) = key {
            if !path.is_empty() {
                path.push('.');
            }
            path.push_str(key);
        }
        if let (Some(n), false) = (index, path.is_empty()) {
            path.push_str(&format!("[{n}]"));
        }
    }
    // An error inside a list names the list's field (`records`, not `records[0]`).
    let field = match path.rsplit_once('[') {
        Some((list, rest)) if rest.ends_with(']') && !rest.contains('.') => list,
        _ => path.as_str(),
    };
    (!field.is_empty()).then(|| ErrorPlace {
        field: field.to_string(),
        value: value.map(crate::excitation::reader::excerpt),
    })
}

/// What a RON error means at `place`: the message and a hint, the field's own help when the
/// schema has one. `seed: 1.5` is "not a whole number", not RON's "Expected comma".
pub fn explain_ron_error(code: &ron::error::Error, place: &ErrorPlace) -> (String, String) {
    use ron::error::Error as E;
    let found = place.value.as_deref();
    let number = found.and_then(|v| v.parse::<f64>().ok());
    let message = match (code, found, number) {
        (E::IntegerOutOfBounds, Some(v), _) => {
            format!("`{v}` is out of range: this field takes a whole number ≥ 0")
        }
        (E::ExpectedComma, Some(v), Some(n)) if n.fract() != 0.0 || v.contains(['e', 'E']) => {
            format!("`{v}` is not a whole number, which this field takes")
        }
        (E::ExpectedComma, Some(v), None) if v.starts_with(|c: char| c.is_ascii_digit()) => {
            format!("`{v}` is not a number")
        }
        (_, Some(v), _) => format!("{code} (at `{v}`)"),
        (_, None, _) => code.to_string(),
    };
    let last = place.field.rsplit('.').next().unwrap_or(&place.field);
    let last = last.split('[').next().unwrap_or(last);
    let hint = match super::fields::field_help(last) {
        Some(help) => format!("`{last}`: {help}"),
        None => "see studies/default.ron for a complete example".to_string(),
    };
    (message, hint)
}

/// Words RON reads as a unit value, or as a float no study field takes, where a number is
/// expected: `alpha: nan` would otherwise be reported as "found a unit value".
const NOT_NUMBERS: [&str; 5] = ["nan", "inf", "infinity", "+inf", "-inf"];

/// NaN and infinities, in any spelling, where a study has a value: refused with the field
/// named, before serde would report `nan` as "a unit value". (A text our syntax reader
/// cannot read is left to RON, whose message says what is wrong with it.)
pub fn check_not_numbers(text: &str, origin: &str) -> Result<(), StudyError> {
    let Ok(doc) = syntax::parse(text, false) else {
        return Ok(());
    };
    not_numbers(&doc.root, "", origin)
}

fn not_numbers(value: &syntax::Value, field: &str, origin: &str) -> Result<(), StudyError> {
    match value {
        syntax::Value::Atom(word, at) => {
            let lower = word.to_ascii_lowercase();
            let lower = lower.trim_start_matches(['+', '-']);
            if NOT_NUMBERS.contains(&lower) {
                return Err(StudyError {
                    origin: origin.to_string(),
                    line: Some(at.line),
                    column: Some(at.column),
                    field: (!field.is_empty()).then(|| field.to_string()),
                    message: format!(
                        "`{word}` is not a number a study accepts (NaN and infinities are not \
                         values of any parameter)"
                    ),
                    hint: Some("give a finite number, e.g. 0.5".into()),
                });
            }
            Ok(())
        }
        syntax::Value::Group { name, items, .. } => {
            for (i, item) in items.iter().enumerate() {
                let label = match (&item.key, field.is_empty()) {
                    (Some((key, _)), true) => key.clone(),
                    (Some((key, _)), false) => format!("{field}.{key}"),
                    // A wrapper's single argument stands for the field itself.
                    (None, _) if !name.is_empty() && items.len() == 1 => field.to_string(),
                    (None, _) => format!("{field}[{i}]"),
                };
                not_numbers(&item.value, &label, origin)?;
            }
            Ok(())
        }
    }
}

/// The strict reading of a parsed study, on the text it was read from: every key appears once
/// in its group (a range's `from`, `to`, `steps` included), and every `name(` stands where the
/// study, written back, has the same name. RON reads a parameter's value with
/// `deserialize_any`, which drops the name in front of it, so `sigma: xi(0.5)` or
/// `ratio(ratio(4.0))` would read as the plain number: the closed set of names a field takes
/// is what serde writes there, so it follows the schema (new fields included) by itself.
pub fn check_meaning(text: &str, study: &super::Study, origin: &str) -> Result<(), StudyError> {
    let doc = syntax::parse(text, false).map_err(|e| syntax_error(e, origin))?;
    let written = super::ron_options()
        .to_string(study)
        .expect("studies serialise");
    let fresh = syntax::parse(&written, false).expect("ron writes RON");
    Meaning { origin }.walk(&doc.root, Some(&fresh.root), "")
}

struct Meaning<'a> {
    origin: &'a str,
}

/// `Some(x)` as `x`: implicit or not, the same value.
fn unwrap_some(value: &syntax::Value) -> &syntax::Value {
    match value {
        syntax::Value::Group { name, items, .. }
            if name == "Some" && items.len() == 1 && items[0].key.is_none() =>
        {
            unwrap_some(&items[0].value)
        }
        _ => value,
    }
}

impl Meaning<'_> {
    fn error(&self, at: syntax::Span, field: &str, message: String, hint: String) -> StudyError {
        StudyError {
            origin: self.origin.to_string(),
            line: Some(at.line),
            column: Some(at.column),
            field: (!field.is_empty()).then(|| field.to_string()),
            message,
            hint: Some(hint),
        }
    }

    /// Check `ours` (as written) against `theirs` (the study written back; None where the
    /// study keeps nothing of the value).
    fn walk(
        &self,
        ours: &syntax::Value,
        theirs: Option<&syntax::Value>,
        field: &str,
    ) -> Result<(), StudyError> {
        use syntax::Value;
        let mut ours = unwrap_some(ours);
        let theirs = theirs.map(unwrap_some);
        if let Value::Group { name, items, .. } = ours
            && name == DEGREES
            && items.len() == 1
        {
            // Resolved into radians before serde: `deg(…)` stands for its argument.
            ours = &items[0].value;
        }
        let Value::Group {
            name, at, items, ..
        } = ours
        else {
            return Ok(());
        };
        if !name.is_empty() && !matches!(theirs, Some(Value::Group { name: n, .. }) if n == name) {
            let expected = match theirs {
                Some(Value::Group { name: n, .. }) if !n.is_empty() => {
                    format!("here the study takes `{n}(…)`")
                }
                Some(_) => "give the value alone here: a number, a list [a, b, …] or a range \
                            (from: a, to: b, steps: n), with no name in front"
                    .to_string(),
                None => "remove it: nothing of this value is used".to_string(),
            };
            return Err(self.error(
                *at,
                field,
                format!("`{name}(…)` means nothing here, and would be read as its content alone"),
                expected,
            ));
        }
        let mut seen: Vec<(&str, syntax::Span)> = Vec::new();
        let theirs_items = theirs.map_or(&[][..], Value::items);
        for (i, item) in items.iter().enumerate() {
            let (label, counterpart) = match &item.key {
                Some((key, at)) => {
                    if let Some((_, first)) = seen.iter().find(|(k, _)| k == key) {
                        return Err(self.error(
                            *at,
                            field,
                            format!("`{key}` is given twice (first on line {})", first.line),
                            format!("give `{key}` once; a later value would not add to the first"),
                        ));
                    }
                    seen.push((key, *at));
                    let counterpart = theirs_items.iter().find(|t| t.key() == Some(key));
                    let label = if field.is_empty() {
                        key.clone()
                    } else {
                        format!("{field}.{key}")
                    };
                    (label, counterpart)
                }
                None => (
                    format!("{field}[{i}]"),
                    theirs_items.get(i).filter(|t| t.key.is_none()),
                ),
            };
            let label = if item.key.is_none() && !name.is_empty() && items.len() == 1 {
                field.to_string()
            } else {
                label
            };
            self.walk(&item.value, counterpart.map(|t| &t.value), &label)?;
        }
        Ok(())
    }
}

/// The wrapper that gives an angle in degrees: `alpha: deg(10)`.
const DEGREES: &str = "deg";

/// The study fields that hold an angle (in radians), and so take `deg(…)`.
pub const ANGLE_FIELDS: &[&str] = &["alpha"];

/// The keys of a range (`(from: a, to: b, steps: n, log: true)`), which belong to the field
/// the range is the value of.
const RANGE_KEYS: &[&str] = &["from", "to", "steps", "log"];

/// The keys of an uncertain parameter's distribution that are in the parameter's unit, and
/// so belong to it: `alpha: normal(mean: deg(14), sd: deg(1))` is in degrees (a lognormal's
/// `beta` is a ratio, and takes no `deg`).
const DISTRIBUTION_KEYS: &[&str] = &["mean", "sd", "median", "lo", "hi"];

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
        .any(|t| t.is_name(text) && t.text(text) == DEGREES)
    {
        return Ok(std::borrow::Cow::Borrowed(text));
    }
    let error = |t: &Token, field: Option<&str>, message: String, hint: &str| StudyError {
        origin: origin.to_string(),
        line: Some(t.span.line),
        column: Some(t.span.column),
        field: field.map(str::to_string),
        message,
        hint: Some(hint.to_string()),
    };
    let word = |t: &Token| t.text(text);
    let mut out = String::with_capacity(text.len());
    let mut copied = 0;
    // The key being given at each nesting level.
    let mut keys: Vec<Option<&str>> = vec![None];
    let mut i = 0;
    while i < tokens.len() {
        let t = &tokens[i];
        let next = tokens.get(i + 1).map(|n| &n.kind);
        match &t.kind {
            Kind::Atom if t.is_name(text) && next == Some(&Kind::Punct(':')) => {
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
            Kind::Atom if word(t) == DEGREES && next == Some(&Kind::Punct('(')) => {
                let field = keys
                    .iter()
                    .rev()
                    .flatten()
                    .find(|k| !RANGE_KEYS.contains(k) && !DISTRIBUTION_KEYS.contains(k))
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
                let mut from = tokens[i + 1].span.end;
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
                        Kind::Atom if RANGE_KEYS.contains(&word(a)) => key = Some(word(a)),
                        Kind::Atom if matches!(word(a), "true" | "false") => {}
                        Kind::Atom if !a.is_name(text) && key == Some("steps") => numbers += 1,
                        Kind::Atom if !a.is_name(text) => {
                            let radians = parse_angle(&format!("{}deg", word(a))).map_err(|e| {
                                error(a, field, e, "write the angle in degrees as deg(10)")
                            })?;
                            converted.push_str(&text[from..a.span.start]);
                            converted.push_str(&format!("{radians:?}"));
                            from = a.span.end;
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
                converted.push_str(&text[from..close.span.start]);
                out.push_str(&text[copied..t.span.start]);
                out.push_str(&converted);
                copied = close.span.end;
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
        let found: Vec<String> = calls(text, &tokens(text))
            .into_iter()
            .map(|c| c.2)
            .collect();
        assert_eq!(found, ["a", "c"]);
        let text = "\n  foo(1)";
        assert_eq!(calls(text, &tokens(text))[0], (2, 3, "foo".to_string()));
    }
}
