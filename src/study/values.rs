//! A study parameter: one value, a list, or a range. In RON: `0.5`, `[0, 0.1, 0.2]`, or
//! `(from: 0.5, to: 10, steps: 40)` (add `log: true` for geometric spacing).

use serde::de::{self, MapAccess, SeqAccess, Visitor};
use serde::ser::SerializeStruct;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// Most steps a range may have (larger is surely a typo, and would not fit in memory).
pub const MAX_STEPS: usize = 1_000_000;

#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    One(f64),
    List(Vec<f64>),
    Range {
        from: f64,
        to: f64,
        steps: usize,
        log: bool,
    },
}

impl Values {
    /// The values in order. A range includes both ends.
    pub fn expand(&self) -> Vec<f64> {
        match self {
            Values::One(v) => vec![*v],
            Values::List(l) => l.clone(),
            Values::Range {
                from,
                to,
                steps,
                log,
            } => {
                if *steps <= 1 {
                    return vec![*from];
                }
                let n = (*steps - 1) as f64;
                (0..*steps)
                    .map(|i| {
                        let f = i as f64 / n;
                        if *log {
                            from * (to / from).powf(f)
                        } else {
                            from + (to - from) * f
                        }
                    })
                    .collect()
            }
        }
    }

    pub fn len(&self) -> usize {
        match self {
            Values::One(_) => 1,
            Values::List(l) => l.len(),
            Values::Range { steps, .. } => *steps,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether this parameter varies (and so names an axis or a group).
    pub fn varies(&self) -> bool {
        self.len() > 1
    }

    /// A reason the values are malformed (not physics: empty lists, bad ranges).
    pub fn shape_error(&self) -> Option<(String, &'static str)> {
        match self {
            Values::List(l) if l.is_empty() => Some((
                "empty list".into(),
                "give at least one value, e.g. [0.5] or 0.5",
            )),
            Values::Range {
                from, to, steps, ..
            } if *steps < 2 || !from.is_finite() || !to.is_finite() => Some((
                format!("range from {from} to {to} in {steps} steps"),
                "a range needs finite ends and steps ≥ 2, e.g. (from: 0.5, to: 10, steps: 40)",
            )),
            Values::Range { steps, .. } if *steps > MAX_STEPS => Some((
                format!("range of {steps} steps"),
                "a range has at most 1 000 000 steps",
            )),
            Values::Range {
                from,
                to,
                log: true,
                ..
            } if *from <= 0.0 || *to <= 0.0 => Some((
                format!("log range from {from} to {to}"),
                "a log range needs both ends > 0",
            )),
            _ => None,
        }
    }
}

impl From<f64> for Values {
    fn from(v: f64) -> Self {
        Values::One(v)
    }
}

impl Serialize for Values {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Values::One(v) => s.serialize_f64(*v),
            Values::List(l) => l.serialize(s),
            Values::Range {
                from,
                to,
                steps,
                log,
            } => {
                let mut st = s.serialize_struct("Range", if *log { 4 } else { 3 })?;
                st.serialize_field("from", from)?;
                st.serialize_field("to", to)?;
                st.serialize_field("steps", steps)?;
                if *log {
                    st.serialize_field("log", log)?;
                } else {
                    st.skip_field("log")?;
                }
                st.end()
            }
        }
    }
}

struct ValuesVisitor;

const RANGE_FIELDS: &[&str] = &["from", "to", "steps", "log"];

impl<'de> Visitor<'de> for ValuesVisitor {
    type Value = Values;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a number, a list [a, b, …], or a range (from: a, to: b, steps: n)")
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Values, E> {
        Ok(Values::One(v))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Values, E> {
        Ok(Values::One(v as f64))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Values, E> {
        Ok(Values::One(v as f64))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Values, A::Error> {
        let mut out = Vec::new();
        while let Some(v) = seq.next_element::<f64>()? {
            out.push(v);
        }
        Ok(Values::List(out))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Values, A::Error> {
        let (mut from, mut to, mut steps, mut log) = (None, None, None, false);
        while let Some(key) = map.next_key::<String>()? {
            match key.as_str() {
                "from" => from = Some(map.next_value::<f64>()?),
                "to" => to = Some(map.next_value::<f64>()?),
                "steps" => steps = Some(map.next_value::<usize>()?),
                "log" => log = map.next_value::<bool>()?,
                other => return Err(de::Error::unknown_field(other, RANGE_FIELDS)),
            }
        }
        Ok(Values::Range {
            from: from.ok_or_else(|| de::Error::missing_field("from"))?,
            to: to.ok_or_else(|| de::Error::missing_field("to"))?,
            steps: steps.ok_or_else(|| de::Error::missing_field("steps"))?,
            log,
        })
    }
}

impl<'de> Deserialize<'de> for Values {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Values, D::Error> {
        d.deserialize_any(ValuesVisitor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn range_includes_both_ends_and_is_evenly_spaced() {
        let v = Values::Range {
            from: 1.0,
            to: 3.0,
            steps: 5,
            log: false,
        }
        .expand();
        assert_eq!(v, vec![1.0, 1.5, 2.0, 2.5, 3.0]);
        let g = Values::Range {
            from: 1.0,
            to: 100.0,
            steps: 3,
            log: true,
        }
        .expand();
        assert!((g[1] - 10.0).abs() < 1e-12 && (g[2] - 100.0).abs() < 1e-12);
    }

    #[test]
    fn ron_forms_parse_and_round_trip() {
        for text in ["0.5", "[0.0, 0.1, 0.2]", "(from: 0.5, to: 10.0, steps: 40)"] {
            let v: Values = ron::from_str(text).unwrap();
            let back = ron::to_string(&v).unwrap();
            assert_eq!(
                ron::from_str::<Values>(&back).unwrap(),
                v,
                "{text} → {back}"
            );
        }
        assert_eq!(ron::from_str::<Values>("2").unwrap(), Values::One(2.0));
        let e = ron::from_str::<Values>("(from: 1, to: 2, stpes: 3)").unwrap_err();
        assert!(e.to_string().contains("stpes"), "{e}");
    }
}
