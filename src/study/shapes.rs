//! A pulse study's shapes: one (`shape: sine`) or several (`shape: [sine, ricker]`). Several
//! shapes are an axis of the study like any list-valued field: its scenes expand over them
//! (a categorical parameter, as records are), and groups, selectors (`shape: ricker`) and
//! figures name each by its study spelling. A single shape is written back as a single value,
//! so existing studies round-trip unchanged.

use crate::excitation::PulseShape;
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum PulseShapes {
    One(PulseShape),
    Many(Vec<PulseShape>),
}

impl PulseShapes {
    /// The shapes in the study's order.
    pub fn list(&self) -> Vec<PulseShape> {
        match self {
            PulseShapes::One(s) => vec![*s],
            PulseShapes::Many(l) => l.clone(),
        }
    }

    /// The first shape (a study's only one, usually).
    pub fn first(&self) -> Option<PulseShape> {
        self.list().first().copied()
    }
}

impl From<PulseShape> for PulseShapes {
    fn from(shape: PulseShape) -> Self {
        PulseShapes::One(shape)
    }
}

/// A shape as a study spells it: `sine`, `mavroeidis_papageorgiou(gamma:2.0,nu:0.0)`.
pub fn shape_name(shape: &PulseShape) -> String {
    ron::to_string(shape).unwrap_or_else(|_| format!("{shape:?}"))
}

/// The names a study may give a shape (the schema's own variant names).
pub fn shape_names() -> &'static [&'static str] {
    super::strict::pulse_shape_names()
}
