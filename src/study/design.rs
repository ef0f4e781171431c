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
//!
//! A fragility study (record suite, `scale` stripes, a `fragility` section) may instead size
//! the device for its fragility curve of one damage state, named by its threshold as
//! `fragility.damage_states` and fragility.csv name it, in the study's intensity measure
//! (`scale_to`): each probe runs every record at every stripe and fits the curve as the
//! fragility report does (`crate::stats`).
//!
//! ```ron
//! target: fragility(state: 1.0, median_at_least: 4.0),
//! target: fragility(state: 0.5, at: 3.0, exceedance_at_most: 0.1),
//! ```
//!
//! With a `risk` section too (the site's hazard curve), it may size the device for the risk
//! at the site: the mean annual frequency of reaching the state over the section's hazard
//! (`crate::risk`, the fitted curve converted to the hazard's measure), or the probability in
//! the section's `years`, p = 1 − exp(−MAF · years):
//!
//! ```ron
//! target: risk(state: 1.0, maf_at_most: 5e-4),
//! target: risk(state: 1.0, p_years_at_most: 0.02),
//! ```

use super::fragility::Method;
use super::{DeviceVariant, ExcitationFamily, Layout, Param, Quantity, Study, StudyError};
use crate::numfmt::fmt_exact;
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

/// The finest `resolution` a search can reach: four spacings of f64 at the answer (its
/// relative spacing is at most `f64::EPSILON` anywhere in a bracket). Below it the bracket
/// stops narrowing before it is narrow enough, so the search could never stop.
pub const MIN_RESOLUTION: f64 = 4.0 * f64::EPSILON;

pub(crate) fn default_resolution() -> f64 {
    0.01
}

pub(crate) fn default_verify() -> usize {
    4
}

all_variants! {
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
}

impl DesignParameter {
    /// The grid parameter it sizes.
    pub fn param(self) -> Param {
        match self {
            DesignParameter::Sigma => Param::Sigma,
            DesignParameter::Cbar => Param::Cbar,
            DesignParameter::XiTheta => Param::XiTheta,
            DesignParameter::Friction => Param::Friction,
            DesignParameter::KTheta => Param::KTheta,
            DesignParameter::ClutchFrequencyRatio => Param::ClutchFrequencyRatio,
        }
    }

    /// The study field (and expansion parameter id) it sizes.
    pub fn id(self) -> &'static str {
        self.param().field()
    }

    /// Paper notation (as coordinates label it).
    pub fn label(self) -> &'static str {
        self.param().label()
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
    /// A fragility study's curve of damage state `state` (a threshold of its
    /// `damage_states`), fitted over every record and stripe: either its median intensity is
    /// at least `median_at_least`, or its probability of reaching the state at intensity `at`
    /// is at most `exceedance_at_most` (one form or the other: [`validate`]).
    Fragility {
        state: f64,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        median_at_least: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        at: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        exceedance_at_most: Option<f64>,
    },
    /// A fragility study's risk at the site of its `risk` section: the mean annual frequency
    /// of reaching damage state `state` (the fitted curve over that hazard) is at most
    /// `maf_at_most`, or its probability in the section's `years` at most `p_years_at_most`
    /// (one or the other: [`validate`]).
    Risk {
        state: f64,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        maf_at_most: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        p_years_at_most: Option<f64>,
    },
}

/// A fragility target's requirement on the fitted curve (the target after validation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FragilityGoal {
    /// Median intensity ≥ this.
    MedianAtLeast(f64),
    /// P(reach the state | IM = at) ≤ most.
    ExceedanceAtMost { at: f64, most: f64 },
    /// The mean annual frequency of reaching the state at the site ≤ this (1/yr).
    MafAtMost(f64),
    /// The probability of reaching the state in the risk section's years ≤ this.
    PYearsAtMost(f64),
}

impl FragilityGoal {
    /// The intensity the goal is read at (a median of at least x: P(x) ≤ 1/2); None for a
    /// risk goal (read off the whole curve).
    pub fn im(self) -> Option<f64> {
        match self {
            FragilityGoal::MedianAtLeast(x) => Some(x),
            FragilityGoal::ExceedanceAtMost { at, .. } => Some(at),
            FragilityGoal::MafAtMost(_) | FragilityGoal::PYearsAtMost(_) => None,
        }
    }

    /// The most probability of reaching the state at [`FragilityGoal::im`] (a median of at
    /// least x: 1/2); for a risk goal its bound.
    pub fn most(self) -> f64 {
        match self {
            FragilityGoal::MedianAtLeast(_) => 0.5,
            FragilityGoal::ExceedanceAtMost { most, .. } => most,
            FragilityGoal::MafAtMost(most) | FragilityGoal::PYearsAtMost(most) => most,
        }
    }
}

impl DesignTarget {
    /// The response quantity a limit target limits (no overturning: the rotation ratio, 1 at
    /// overturning); None for a fragility target (its damage measure is the study's).
    pub fn quantity(self) -> Option<Quantity> {
        match self {
            DesignTarget::Limit { quantity, .. } => Some(quantity),
            DesignTarget::NoOverturning => Some(Quantity::PeakRotationRatio),
            DesignTarget::Fragility { .. } | DesignTarget::Risk { .. } => None,
        }
    }

    /// A fragility target's damage state and goal (None: another target, or the fields do
    /// not make one goal: [`validate`] refuses those).
    pub fn fragility(self) -> Option<(f64, FragilityGoal)> {
        if let DesignTarget::Risk {
            state,
            maf_at_most,
            p_years_at_most,
        } = self
        {
            let goal = match (maf_at_most, p_years_at_most) {
                (Some(x), None) => FragilityGoal::MafAtMost(x),
                (None, Some(p)) => FragilityGoal::PYearsAtMost(p),
                _ => return None,
            };
            return Some((state, goal));
        }
        let DesignTarget::Fragility {
            state,
            median_at_least,
            at,
            exceedance_at_most,
        } = self
        else {
            return None;
        };
        let goal = match (median_at_least, at, exceedance_at_most) {
            (Some(x), None, None) => FragilityGoal::MedianAtLeast(x),
            (None, Some(at), Some(most)) => FragilityGoal::ExceedanceAtMost { at, most },
            _ => return None,
        };
        Some((state, goal))
    }

    pub fn describe(self) -> String {
        match self {
            DesignTarget::Limit { quantity, max } => format!("{} <= {max}", quantity.name()),
            DesignTarget::NoOverturning => "no overturning".into(),
            DesignTarget::Fragility { state, .. } => match self.fragility() {
                Some((_, FragilityGoal::MedianAtLeast(x))) => {
                    format!("median IM of damage state {state} >= {x}")
                }
                Some((_, FragilityGoal::ExceedanceAtMost { at, most })) => {
                    format!("P(damage state {state} | IM = {at}) <= {most}")
                }
                _ => format!("fragility of damage state {state}"),
            },
            DesignTarget::Risk { state, .. } => match self.fragility() {
                Some((_, FragilityGoal::MafAtMost(x))) => {
                    format!("MAF of damage state {state} <= {x} /yr")
                }
                Some((_, FragilityGoal::PYearsAtMost(p))) => {
                    format!("P(damage state {state} in the risk's years) <= {p}")
                }
                _ => format!("risk of damage state {state}"),
            },
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
    /// The excitation axes of `study` the target holds over (`over`, or its default; a
    /// fragility target's curve is fitted over every record and stripe).
    pub fn over_ids(&self, study: &Study) -> Vec<&'static str> {
        if !self.over.is_empty() {
            return self.over.iter().map(|a| a.id()).collect();
        }
        match study.excitation {
            ExcitationFamily::Pulse { .. } => vec!["frequency"],
            ExcitationFamily::Record { .. } if self.target.fragility().is_some() => {
                vec!["record", "scale"]
            }
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
            format!("{} is out of range", fmt_exact(design.resolution)),
            "a relative resolution in (0, 0.5), e.g. 0.01 for 1 % of the answer",
        ));
    }
    if design.resolution < MIN_RESOLUTION {
        return Err(StudyError::field(
            "design.resolution",
            format!(
                "{} is finer than f64 can resolve: neighbouring numbers are up to {} apart \
                 (relative), so the bracket would stop narrowing before it got there",
                fmt_exact(design.resolution),
                fmt_exact(f64::EPSILON)
            ),
            &format!(
                "at least {} (4 spacings of f64); 0.01 finds the answer to 1 %",
                fmt_exact(MIN_RESOLUTION)
            ),
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
                format!("{} is not a response limit", fmt_exact(max)),
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
    if let DesignTarget::Risk { .. } = design.target {
        validate_risk_target(study, design)?;
    } else if let DesignTarget::Fragility { .. } = design.target {
        validate_fragility_target(study, design)?;
    } else if study
        .fragility
        .as_ref()
        .is_some_and(|f| f.method.ida_resolution().is_some())
    {
        return Err(StudyError::field(
            "fragility.method",
            "a design search cannot run an incremental dynamic analysis",
            "a design study's scenes are its probes: size the device on stripes (remove \
             `method: ida(…)`) with target: fragility(state: 1.0, median_at_least: 4.0)",
        ));
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

/// A risk target against the study: a `risk` section (its hazard), a fragility study on
/// stripes with the state among its damage states, and one bound in range.
fn validate_risk_target(study: &Study, design: &Design) -> Result<(), StudyError> {
    const FORMS: &str = "risk(state: 1.0, maf_at_most: 5e-4) or \
                         risk(state: 1.0, p_years_at_most: 0.02)";
    let DesignTarget::Risk {
        state,
        maf_at_most,
        p_years_at_most,
    } = design.target
    else {
        return Ok(());
    };
    if study.risk.is_none() {
        return Err(StudyError::field(
            "design.target",
            "a risk target needs the site's hazard curve",
            "add a risk section: risk: (hazard: \"hazards/illustrative_pga.csv\", years: 50.0), \
             the path relative to the study file",
        ));
    }
    // The fragility checks, on the same state (median 1 stands for any fragility goal).
    let as_fragility = Design {
        target: DesignTarget::Fragility {
            state,
            median_at_least: Some(1.0),
            at: None,
            exceedance_at_most: None,
        },
        ..design.clone()
    };
    validate_fragility_target(study, &as_fragility)?;
    match (maf_at_most, p_years_at_most) {
        (Some(x), None) if !(x.is_finite() && x > 0.0) => Err(StudyError::field(
            "design.target.maf_at_most",
            format!("{} is not a mean annual frequency", fmt_exact(x)),
            "a finite rate > 0 per year, e.g. maf_at_most: 5e-4 (once in 2000 years)",
        )),
        (None, Some(p)) if !(p > 0.0 && p < 1.0) => Err(StudyError::field(
            "design.target.p_years_at_most",
            format!(
                "{} is not a probability strictly between 0 and 1",
                fmt_exact(p)
            ),
            "e.g. p_years_at_most: 0.02 (2 % in the risk section's years)",
        )),
        (Some(_), Some(_)) => Err(StudyError::field(
            "design.target.p_years_at_most",
            "a risk target is either a MAF or a probability in years, not both",
            FORMS,
        )),
        (None, None) => Err(StudyError::field(
            "design.target",
            "a risk target needs maf_at_most or p_years_at_most",
            FORMS,
        )),
        _ => Ok(()),
    }
}

/// A fragility target against the study: a fragility study on stripes, a damage state of its
/// section, one goal with its values in range, and the default excitation axes.
fn validate_fragility_target(study: &Study, design: &Design) -> Result<(), StudyError> {
    const FORMS: &str = "fragility(state: 1.0, median_at_least: 4.0) or \
                         fragility(state: 1.0, at: 3.0, exceedance_at_most: 0.1)";
    let DesignTarget::Fragility {
        state,
        median_at_least,
        at,
        exceedance_at_most,
    } = design.target
    else {
        return Ok(());
    };
    let Some(f) = &study.fragility else {
        return Err(StudyError::field(
            "design.target",
            "a fragility target needs a fragility study",
            "add fragility: (damage_states: levels([0.2, 0.5, 1.0])) over a record suite with \
             scale_to: pga_star and stripes in `scale`, or use limit(quantity: q, max: v)",
        ));
    };
    if f.method != Method::Stripes {
        return Err(StudyError::field(
            "fragility.method",
            "a fragility target is fitted over stripes, not an incremental dynamic analysis",
            "remove `method: ida(…)`: each probe runs every record at every `scale` stripe",
        ));
    }
    let levels = f.damage_states.levels();
    if !levels.contains(&state) {
        let list: Vec<String> = levels.iter().map(|l| format!("{l:?}")).collect();
        return Err(StudyError::field(
            "design.target.state",
            format!(
                "{} is not one of the study's damage states",
                fmt_exact(state)
            ),
            &format!(
                "a threshold of fragility.damage_states: one of {} (1.0 = overturning for θmax/α)",
                list.join(", ")
            ),
        ));
    }
    match (median_at_least, at, exceedance_at_most) {
        (Some(_), Some(_), _) => {
            return Err(StudyError::field(
                "design.target.at",
                "`at` belongs to an exceedance target, not to median_at_least",
                FORMS,
            ));
        }
        (Some(_), None, Some(_)) => {
            return Err(StudyError::field(
                "design.target.exceedance_at_most",
                "a target is either a median or an exceedance probability, not both",
                FORMS,
            ));
        }
        (None, None, None) => {
            return Err(StudyError::field(
                "design.target",
                "a fragility target needs median_at_least, or at and exceedance_at_most",
                FORMS,
            ));
        }
        (None, None, Some(_)) => {
            return Err(StudyError::field(
                "design.target.at",
                "missing: the intensity the exceedance probability is read at",
                FORMS,
            ));
        }
        (None, Some(_), None) => {
            return Err(StudyError::field(
                "design.target.exceedance_at_most",
                "missing: the most probability of reaching the state at `at`",
                FORMS,
            ));
        }
        (Some(_), None, None) | (None, Some(_), Some(_)) => {}
    }
    let im = |name: &str, v: Option<f64>| match v {
        Some(v) if !(v.is_finite() && v > 0.0) => Err(StudyError::field(
            format!("design.target.{name}"),
            format!("{} is not an intensity", fmt_exact(v)),
            "a finite intensity > 0 in the study's measure (scale_to), e.g. 4.0 for PGA* = 4",
        )),
        _ => Ok(()),
    };
    im("median_at_least", median_at_least)?;
    im("at", at)?;
    if let Some(p) = exceedance_at_most
        && !(p > 0.0 && p < 1.0)
    {
        return Err(StudyError::field(
            "design.target.exceedance_at_most",
            format!(
                "{} is not a probability strictly between 0 and 1",
                fmt_exact(p)
            ),
            "e.g. exceedance_at_most: 0.1 (at most a 10 % chance of reaching the state at `at`)",
        ));
    }
    let mut over = design.over_ids(study);
    over.sort_unstable();
    if over != ["record", "scale"] {
        return Err(StudyError::field(
            "design.over",
            "a fragility target's curve is fitted over every record and stripe",
            "leave `over` out (it is [record, scale] for a fragility target)",
        ));
    }
    Ok(())
}
