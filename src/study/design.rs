//! The design section of a study: the inverse question "what is the least device parameter
//! (σ, c̄ or ξθ, fμ, the clutch stiffness) for which a target holds at every point of the
//! excitation axes?". This file holds the schema and its validation; the search runs in
//! `sweep::design`, and the answer is written by `report::design`.
//!
//! ```ron
//! design: (
//!     parameter: sigma,
//!     bracket: (0.0, 3.0),
//!     resolution: 0.01,
//!     target: limit(quantity: peak_rotation_ratio, max: 0.5),
//! ),
//! ```

use super::{DeviceVariant, ExcitationFamily, Layout, Quantity, Study, StudyError};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Design {
    /// The device parameter to size.
    pub parameter: DesignParameter,
    /// The search bracket [low, high] of the parameter.
    pub bracket: (f64, f64),
    /// Relative resolution of the answer: the search stops once its bracket is narrower than
    /// `resolution` × the least passing value (0.01 = 1 %).
    #[serde(default = "default_resolution")]
    pub resolution: f64,
    pub target: DesignTarget,
    /// The excitation axes the target must hold over (every point of them); the study's other
    /// varying parameters are the axes of the answer. Default: the pulse frequency, or the
    /// record list.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub over: Vec<ExcitationAxis>,
    /// Values checked above the answer (denser near it; the bracket's top is always probed)
    /// for a failure again: a non-monotone response.
    #[serde(default = "default_verify")]
    pub verify: usize,
}

pub(crate) fn default_resolution() -> f64 {
    0.01
}

pub(crate) fn default_verify() -> usize {
    4
}

/// A sizable device parameter, named as the study's device fields.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DesignParameter {
    /// Inertance ratio σ (every device but the bare structure). σ = 0 is the bare structure.
    Sigma,
    /// Clutch damping c̄ (1/s), mechanistic clutch.
    Cbar,
    /// Clutch damping ratio ξθ, mechanistic clutch.
    XiTheta,
    /// Dry friction fμ/(mr·g), mechanistic clutch.
    Friction,
    /// Clutch stiffness kθ (N·m/rad), mechanistic clutch.
    KTheta,
    /// Clutch frequency ratio √(kθ/J)/p, mechanistic clutch.
    ClutchFrequencyRatio,
}

impl DesignParameter {
    pub const ALL: [DesignParameter; 6] = [
        DesignParameter::Sigma,
        DesignParameter::Cbar,
        DesignParameter::XiTheta,
        DesignParameter::Friction,
        DesignParameter::KTheta,
        DesignParameter::ClutchFrequencyRatio,
    ];

    /// The study field (and expansion parameter id) it sizes.
    pub fn id(self) -> &'static str {
        match self {
            DesignParameter::Sigma => "sigma",
            DesignParameter::Cbar => "cbar",
            DesignParameter::XiTheta => "xi_theta",
            DesignParameter::Friction => "friction",
            DesignParameter::KTheta => "k_theta",
            DesignParameter::ClutchFrequencyRatio => "clutch_frequency_ratio",
        }
    }

    /// Paper notation (as coordinates label it).
    pub fn label(self) -> &'static str {
        match self {
            DesignParameter::Sigma => "σ",
            DesignParameter::Cbar => "c̄",
            DesignParameter::XiTheta => "ξθ",
            DesignParameter::Friction => "fμ",
            DesignParameter::KTheta => "kθ",
            DesignParameter::ClutchFrequencyRatio => "ωc/p",
        }
    }

    /// Whether a device variant has this parameter (the others are evaluated once, as a
    /// reference: the bare structure, a sequential clutch when sizing a clutch parameter).
    pub fn sizes(self, device: &DeviceVariant) -> bool {
        match device {
            DeviceVariant::None => false,
            DeviceVariant::Inerter { .. } | DeviceVariant::Sequential { .. } => {
                self == DesignParameter::Sigma
            }
            DeviceVariant::Mechanistic { .. } => true,
        }
    }

    /// The smallest value a device accepts (σ = 0 is probed as the bare structure).
    fn least(self) -> f64 {
        0.0
    }
}

/// What must hold at every excitation point.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum DesignTarget {
    /// `quantity <= max` and no overturning.
    Limit { quantity: Quantity, max: f64 },
    /// The structure does not overturn.
    NoOverturning,
}

impl DesignTarget {
    /// The quantity the target limits (no overturning: the rotation ratio, 1 at overturning).
    pub fn quantity(self) -> Quantity {
        match self {
            DesignTarget::Limit { quantity, .. } => quantity,
            DesignTarget::NoOverturning => Quantity::PeakRotationRatio,
        }
    }

    pub fn describe(self) -> String {
        match self {
            DesignTarget::Limit { quantity, max } => format!("{} <= {max}", quantity.name()),
            DesignTarget::NoOverturning => "no overturning".into(),
        }
    }
}

/// An excitation parameter the target must hold over.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ExcitationAxis {
    Frequency,
    Amplitude,
    Record,
    Scale,
}

impl ExcitationAxis {
    /// The expansion parameter id.
    pub fn id(self) -> &'static str {
        match self {
            ExcitationAxis::Frequency => "frequency",
            ExcitationAxis::Amplitude => "amplitude",
            ExcitationAxis::Record => "record",
            ExcitationAxis::Scale => "scale",
        }
    }
}

impl Design {
    /// The excitation axes of `study` the target holds over (`over`, or its default).
    pub fn over_ids(&self, study: &Study) -> Vec<&'static str> {
        if !self.over.is_empty() {
            return self.over.iter().map(|a| a.id()).collect();
        }
        match study.excitation {
            ExcitationFamily::Pulse { .. } => vec!["frequency"],
            ExcitationFamily::Record { .. } => vec!["record"],
        }
    }
}

/// Checks of a study's design section against the rest of the study (after the expansion's
/// own checks). Errors name the field with a hint.
pub fn validate(study: &Study) -> Result<(), StudyError> {
    let Some(design) = &study.design else {
        return Ok(());
    };
    let (lo, hi) = design.bracket;
    let param = design.parameter;
    if !(lo.is_finite() && hi.is_finite() && lo >= param.least() && lo < hi) {
        return Err(StudyError::field(
            "design.bracket",
            format!("({lo}, {hi}) is not a search bracket"),
            "two finite values, low < high, low ≥ 0, e.g. bracket: (0.0, 3.0)",
        ));
    }
    if !(design.resolution.is_finite() && design.resolution > 0.0 && design.resolution < 0.5) {
        return Err(StudyError::field(
            "design.resolution",
            format!("{} is out of range", design.resolution),
            "a relative resolution in (0, 0.5), e.g. 0.01 for 1 % of the answer",
        ));
    }
    if design.verify > 20 {
        return Err(StudyError::field(
            "design.verify",
            format!("{} verification probes is too many", design.verify),
            "0 to 20 values above the answer are checked (the bracket's top always is)",
        ));
    }
    if let DesignTarget::Limit { quantity, max } = design.target {
        if !(max.is_finite() && max > 0.0) {
            return Err(StudyError::field(
                "design.target.max",
                format!("{max} is not a response limit"),
                "a finite limit > 0, e.g. limit(quantity: peak_rotation_ratio, max: 0.5)",
            ));
        }
        if !study.quantities.contains(&quantity) {
            return Err(StudyError::field(
                "design.target.quantity",
                format!(
                    "the target's quantity `{}` is not among the study's quantities",
                    quantity.name()
                ),
                &format!("add it: quantities: [{}]", quantity.name()),
            ));
        }
    }
    if !study.devices.iter().any(|d| param.sizes(d)) {
        return Err(StudyError::field(
            "design.parameter",
            format!("no device variant of the study has `{}`", param.id()),
            "sigma sizes every device but `none`; clutch parameters size `mechanistic` ones",
        ));
    }
    let layout = Layout::of(study)?;
    let over = design.over_ids(study);
    for (d, variant) in layout.variants.iter().enumerate() {
        for id in &over {
            if !variant.params.iter().any(|p| p.id == *id) {
                return Err(StudyError::field(
                    "design.over",
                    format!("`{id}` is not an axis of this study's excitation"),
                    "pulses: frequency, amplitude; records: record, scale",
                ));
            }
        }
        if !param.sizes(&study.devices[d]) {
            continue;
        }
        if let Some(p) = variant.params.iter().find(|p| p.id == param.id())
            && p.varies()
        {
            return Err(StudyError::field(
                p.path.clone(),
                format!(
                    "`{}` varies, but the design searches it (design.parameter: {})",
                    param.id(),
                    param.id()
                ),
                "give it one value (the probes replace it), or remove the design section",
            ));
        }
    }
    if study.map.is_some() {
        return Err(StudyError::field(
            "design",
            "a design study has no overturning map",
            "remove `map`: the design chart is drawn over the study's other axes",
        ));
    }
    Ok(())
}
