//! Picking groups of a results file by device and parameter values, written in the study's own
//! RON syntax: `mechanistic`, `bare`, `mechanistic(k_theta: 3.0, play: [0.0, 0.005])`,
//! `sequential(record: landers)`. Matching works on the groups' structured settings, never on
//! label text.

use super::aggregate::Group;
use crate::numfmt::fmt_digits;
use crate::ron_syntax::{self as syntax, Value, flat};
use crate::study::{DeviceKind, Values};
use std::fmt::Write as _;

/// A selector that is malformed or matches nothing; the message says what there is instead.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct SelectError(pub String);

#[derive(Clone, Debug, PartialEq)]
pub struct Selector {
    /// As the user wrote it, for messages.
    pub text: String,
    /// A device kind (`none`/`bare`, `inerter`, `sequential`, `mechanistic`) or a variant's
    /// `label`.
    pub device: String,
    pub filters: Vec<Filter>,
}

/// One `field: value` of a selector: the group's setting `id` must be one of the values.
#[derive(Clone, Debug, PartialEq)]
pub struct Filter {
    pub id: String,
    pub wanted: Wanted,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Wanted {
    /// A number, list or range, as in a study.
    Numbers(Vec<f64>),
    /// Record names.
    Names(Vec<String>),
}

const EXAMPLE: &str = "e.g. `mechanistic`, `bare`, `mechanistic(k_theta: 3.0, play: [0.0, 0.005])`";

impl Selector {
    /// Read a selector with the study's RON reading: a value takes no name in front of it
    /// (`friction: foo(0.0)` is refused, not read as 0.0), and no key is given twice.
    pub fn parse(text: &str) -> Result<Selector, SelectError> {
        let trimmed = text.trim();
        let bad = |why: &str| SelectError(format!("invalid selector `{text}`: {why}; {EXAMPLE}"));
        if !trimmed.contains(['(', ')', '[', ']', ',', ':']) {
            // A device kind or a variant's label, which may hold spaces.
            if trimmed.is_empty() {
                return Err(bad("name a device first"));
            }
            return Ok(Selector {
                text: trimmed.to_string(),
                device: trimmed.trim_matches('"').to_string(),
                filters: Vec::new(),
            });
        }
        let doc = syntax::parse(trimmed, false)
            .map_err(|e| bad(&format!("{} (at column {})", e.message, e.span.column)))?;
        let (device, items) = match &doc.root {
            Value::Atom(name, _) => (name.as_str(), &[][..]),
            Value::Group {
                name, open, items, ..
            } if *open == '(' => (name.as_str(), &items[..]),
            _ => return Err(bad("name a device first")),
        };
        if device.is_empty() || !doc.header.is_empty() || !doc.footer.is_empty() {
            return Err(bad("name a device first"));
        }
        let mut filters: Vec<Filter> = Vec::new();
        for item in items {
            let value = &item.value;
            let Some(id) = item.key() else {
                return Err(bad(&format!("`{}` is not `field: value`", flat(value))));
            };
            let id = if id == "names" { "record" } else { id };
            if filters.iter().any(|f| f.id == id) {
                return Err(bad(&format!("`{id}` is given twice")));
            }
            if let Some((key, _)) = value.duplicate_key() {
                return Err(bad(&format!("`{key}` is given twice in `{id}`")));
            }
            let wanted = if id == "record" || id == "shape" {
                Wanted::Names(record_names(value))
            } else {
                if let Some((name, _)) = value.first_name() {
                    return Err(bad(&format!(
                        "`{name}(…)` in `{id}` means nothing: give a number, a list [a, b] or \
                         a range (from: a, to: b, steps: n) with no name in front"
                    )));
                }
                let value = flat(value);
                let values: Values = ron::from_str(&value).map_err(|e| {
                    bad(&format!(
                        "`{id}: {value}` is not a number, list or range ({e})"
                    ))
                })?;
                if let Some((why, hint)) = values.shape_error() {
                    return Err(bad(&format!("`{id}`: {why} ({hint})")));
                }
                Wanted::Numbers(values.expand())
            };
            filters.push(Filter {
                id: id.to_string(),
                wanted,
            });
        }
        Ok(Selector {
            text: trimmed.to_string(),
            device: device.trim_matches('"').to_string(),
            filters,
        })
    }

    /// Whether a group is of the selector's device (kind or variant label).
    pub fn device_matches(&self, group: &Group) -> bool {
        group.device_label == self.device
            || DeviceKind::from_name(&self.device) == Some(group.device)
    }

    /// The setting ids the selector constrains.
    pub fn ids(&self) -> impl Iterator<Item = &str> {
        self.filters.iter().map(|f| f.id.as_str())
    }
}

/// `landers`, `"landers"` or `["landers", northridge]`.
fn record_names(value: &Value) -> Vec<String> {
    let names: Vec<&Value> = match value {
        Value::Group {
            open: '[', items, ..
        } => items.iter().map(|i| &i.value).collect(),
        _ => vec![value],
    };
    names
        .into_iter()
        .map(|n| flat(n).trim_matches('"').to_string())
        .filter(|n| !n.is_empty())
        .collect()
}

fn written_digits(v: f64) -> usize {
    let sci = format!("{v:e}");
    let mantissa = sci.split('e').next().unwrap_or("");
    mantissa.chars().filter(char::is_ascii_digit).count().max(1)
}

/// Of the `present` values, those a typed value names: the exact ones if any, else those that
/// round to it at the precision it was typed with (so a label's `5.623e-5` finds
/// 5.62341325e-5, while `1.0` picks 1.0 and not 1.00000001 when both are present).
fn resolve(typed: f64, present: &[f64]) -> Vec<f64> {
    if present.contains(&typed) {
        return vec![typed];
    }
    let d = written_digits(typed);
    present
        .iter()
        .copied()
        .filter(|v| fmt_digits(*v, d) == fmt_digits(typed, d))
        .collect()
}

/// Indices of the `groups` a selector picks. If it picks none: an error naming the devices,
/// or the parameters, or the values per parameter that there are (a few lines, never every
/// group).
pub fn select(groups: &[&Group], sel: &Selector) -> Result<Vec<usize>, SelectError> {
    let of_device: Vec<usize> = (0..groups.len())
        .filter(|&i| sel.device_matches(groups[i]))
        .collect();
    if of_device.is_empty() {
        let mut devices: Vec<String> = Vec::new();
        for g in groups {
            let name = match g.device {
                DeviceKind::None => "bare".to_string(),
                k => k.name().to_string(),
            };
            for n in [name, g.device_label.clone()] {
                if !devices.contains(&n) {
                    devices.push(n);
                }
            }
        }
        return Err(SelectError(format!(
            "no device `{}` in these results; devices here: {}",
            sel.device,
            devices.join(", ")
        )));
    }
    let mut chosen = of_device.clone();
    for filter in &sel.filters {
        let known = of_device
            .iter()
            .any(|&i| groups[i].setting(&filter.id).is_some());
        if !known {
            let mut ids: Vec<&str> = Vec::new();
            for &i in &of_device {
                for s in &groups[i].settings {
                    if !ids.contains(&s.id.as_str()) {
                        ids.push(&s.id);
                    }
                }
            }
            return Err(SelectError(format!(
                "`{}` is not a parameter of `{}` here; its parameters: {}",
                filter.id,
                sel.device,
                ids.join(", ")
            )));
        }
        chosen.retain(|&i| {
            let Some(s) = groups[i].setting(&filter.id) else {
                return false;
            };
            match &filter.wanted {
                Wanted::Names(names) => s.name.as_ref().is_some_and(|n| names.contains(n)),
                Wanted::Numbers(typed) => {
                    let present = values_of(groups, &of_device, &filter.id);
                    typed
                        .iter()
                        .any(|t| resolve(*t, &present).contains(&s.value))
                }
            }
        });
    }
    if chosen.is_empty() {
        return Err(SelectError(format!(
            "`{}` matches nothing; the values of `{}` here are:\n{}",
            sel.text,
            sel.device,
            available(groups, &of_device, sel)
        )));
    }
    Ok(chosen)
}

/// Distinct values of a setting among some groups, in order of appearance.
fn values_of(groups: &[&Group], among: &[usize], id: &str) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for &i in among {
        if let Some(s) = groups[i].setting(id)
            && !out.contains(&s.value)
        {
            out.push(s.value);
        }
    }
    out
}

/// One line per parameter that takes more than one value among the device's groups (or that
/// the selector names): `  k_theta (kθ): 0.3, 3, 30`.
pub fn available(groups: &[&Group], among: &[usize], sel: &Selector) -> String {
    let mut ids: Vec<(&str, &str)> = Vec::new();
    for &i in among {
        for s in &groups[i].settings {
            if !ids.iter().any(|(id, _)| *id == s.id) {
                ids.push((&s.id, &s.label));
            }
        }
    }
    let mut text = String::new();
    for (id, label) in ids {
        let mut names: Vec<String> = Vec::new();
        let values = values_of(groups, among, id);
        for &i in among {
            if let Some(n) = groups[i].setting(id).and_then(|s| s.name.clone())
                && !names.contains(&n)
            {
                names.push(n);
            }
        }
        let named = sel.ids().any(|s| s == id);
        if values.len() < 2 && !named {
            continue;
        }
        let shown: Vec<String> = if names.is_empty() {
            let mut sorted = values.clone();
            sorted.sort_by(f64::total_cmp);
            let d = (4..=17)
                .find(|&d| {
                    let mut t: Vec<String> = sorted.iter().map(|v| fmt_digits(*v, d)).collect();
                    t.dedup();
                    t.len() == sorted.len()
                })
                .unwrap_or(17);
            sorted.iter().map(|v| fmt_digits(*v, d)).collect()
        } else {
            names
        };
        const MAX: usize = 10;
        let list = if shown.len() > MAX {
            format!(
                "{}, … {} (of {})",
                shown[..MAX - 1].join(", "),
                shown[shown.len() - 1],
                shown.len()
            )
        } else {
            shown.join(", ")
        };
        let _ = writeln!(text, "  {id} ({label}): {list}");
    }
    if text.is_empty() {
        text = "  (no parameter varies)\n".into();
    }
    text.trim_end().to_string()
}

/// The study field of an axis a spectrum or map shows by its label (`A/g` → `amplitude`).
pub fn axis_id(label: &str) -> Option<&'static str> {
    crate::study::Param::from_label(label).map(|p| p.info().field)
}

/// The selector without its filters on `axes` (the study fields of a spectrum's x axis or a
/// map's axes: values within one group, never settings that tell groups apart), and those
/// filters.
pub fn split_axes(sel: &Selector, axes: &[&str]) -> (Selector, Vec<Filter>) {
    let (on_axes, rest): (Vec<Filter>, Vec<Filter>) = sel
        .filters
        .iter()
        .cloned()
        .partition(|f| axes.contains(&f.id.as_str()));
    let reduced = Selector {
        filters: rest,
        ..sel.clone()
    };
    (reduced, on_axes)
}

/// Which of `values` (one axis of a spectrum or map, study field `id`) every filter on `id`
/// keeps: all when none names it. A filter that keeps none is an error naming the axis's
/// values (`text` is the selector, for the message).
pub fn keep_on_axis(
    text: &str,
    id: &str,
    values: &[f64],
    filters: &[Filter],
) -> Result<Vec<bool>, SelectError> {
    let mut keep = vec![true; values.len()];
    for f in filters.iter().filter(|f| f.id == id) {
        let Wanted::Numbers(typed) = &f.wanted else {
            return Err(SelectError(format!("`{text}`: `{id}` takes numbers")));
        };
        let picked: Vec<f64> = typed.iter().flat_map(|t| resolve(*t, values)).collect();
        for (k, v) in keep.iter_mut().zip(values) {
            *k &= picked.contains(v);
        }
    }
    if !keep.contains(&true) {
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        sorted.dedup();
        let shown: Vec<String> = sorted.iter().map(|v| fmt_digits(*v, 4)).collect();
        let list = match shown.len() {
            n if n > 10 => format!("{}, … {} (of {n})", shown[..9].join(", "), shown[n - 1]),
            _ => shown.join(", "),
        };
        return Err(SelectError(format!(
            "`{text}` picks no `{id}` here; its values: {list}"
        )));
    }
    Ok(keep)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn selectors_parse_in_study_syntax() {
        let s = Selector::parse("mechanistic(k_theta: 3.0, play: [0.0, 0.005], record: landers)")
            .unwrap();
        assert_eq!(s.device, "mechanistic");
        assert_eq!(
            s.filters,
            vec![
                Filter {
                    id: "k_theta".into(),
                    wanted: Wanted::Numbers(vec![3.0])
                },
                Filter {
                    id: "play".into(),
                    wanted: Wanted::Numbers(vec![0.0, 0.005])
                },
                Filter {
                    id: "record".into(),
                    wanted: Wanted::Names(vec!["landers".into()])
                },
            ]
        );
        let r = Selector::parse("mechanistic(xi_theta: (from: 0.0, to: 0.2, steps: 3))").unwrap();
        assert_eq!(r.filters[0].wanted, Wanted::Numbers(vec![0.0, 0.1, 0.2]));
        for bad in [
            "mechanistic(k_theta: 3.0",
            "(k_theta: 3)",
            "mechanistic(k_theta 3)",
            "mechanistic(k_theta: abc)",
            "mechanistic(play: 1, play: 2)",
            // The study's strict reading: no name before a value, no key twice in a range.
            "mechanistic(friction: foo(0.0))",
            "mechanistic(friction: [xi(0.0)])",
            "mechanistic(xi_theta: (from: 0.0, to: 0.2, steps: 3, from: 0.1))",
            "",
        ] {
            assert!(Selector::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn typed_values_resolve_exactly_first_then_at_their_precision() {
        assert_eq!(resolve(1.0, &[1.0, 1.00000001]), vec![1.0]);
        assert_eq!(resolve(1.00000001, &[1.0, 1.00000001]), vec![1.00000001]);
        let log = [1e-5, 1.778279410038923e-5, 3.1622776601683795e-5];
        assert_eq!(resolve(1.778e-5, &log), vec![log[1]]);
        assert!(resolve(1.7e-5, &log).is_empty());
    }
}
