//! The `fragility` section of a study: multiple-stripe analysis over a record suite. The
//! record excitation's `scale` values are the stripes (intensity-measure values) and its
//! `scale_to` is the intensity measure (PGA, PGV, PGA* or PGV*), so every record × stripe ×
//! variant is an ordinary scene of the study and runs through the same parallel, journalled,
//! resumable (and shardable) sweep as spectra. After the sweep, `report::stripes` turns the
//! scenes into observations, fits them (report::fragility) and writes stripes.csv,
//! fragility.csv and fragility.json.
//!
//! With `method: ida(resolution: r)` the `scale` values are instead the hunt's ladder of an
//! incremental dynamic analysis (sweep/ida.rs): per record and variant, climb the ladder
//! until the highest damage state is reached, then bisect every state's first exceedance to
//! r (IM units); report::ida writes ida.csv and fits the capacities (censored at the top).

use super::{Axis, ExcitationFamily, Quantity, RecordScaling, StructureFamily, Study, StudyError};
use crate::numfmt::fmt_exact;
use serde::{Deserialize, Serialize};

/// Fragility analysis of a study's scenes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Fragility {
    /// Multiple-stripe analysis (default) or incremental dynamic analysis.
    #[serde(default, skip_serializing_if = "Method::is_stripes")]
    pub method: Method,
    /// Thresholds of the damage measure (default 0.2, 0.5, 1 = overturning for θmax/α).
    #[serde(default)]
    pub damage_states: DamageStates,
    /// The damage measure: one of the study's quantities; `peak_rotation_ratio` (θmax/α,
    /// default; for a flexible structure the uplift θmax/α), or for a flexible structure
    /// `peak_drift` or `peak_deformation`. A scene that overturns exceeds every state.
    #[serde(default = "default_measure")]
    pub measure: Quantity,
    /// Bootstrap resamples over records for the confidence intervals (0: none).
    #[serde(default = "default_bootstrap")]
    pub bootstrap: usize,
    /// Bootstrap seed: reruns agree bit for bit.
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// Two-sided confidence level of the intervals (0.9: 5th and 95th percentiles).
    #[serde(default = "default_confidence")]
    pub confidence: f64,
}

/// How a fragility analysis uses the record excitation's `scale` values.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Method {
    /// Multiple-stripe analysis: every record at every `scale` value (the stripes).
    #[default]
    Stripes,
    /// Incremental dynamic analysis: per record and variant, hunt up the `scale` values (the
    /// ladder, lowest first) until the highest damage state is reached, then bisect each
    /// state's first exceedance until its bracket is no wider than `resolution` (IM units).
    Ida { resolution: f64 },
}

impl Method {
    pub fn is_stripes(&self) -> bool {
        *self == Method::Stripes
    }

    /// The IDA's resolution, if the method is IDA.
    pub fn ida_resolution(&self) -> Option<f64> {
        match self {
            Method::Ida { resolution } => Some(*resolution),
            Method::Stripes => None,
        }
    }
}

/// Most bisection steps an IDA bracket may need (the ladder's top over the resolution is at
/// most 2^this).
pub const MAX_BISECTIONS: u32 = 16;

/// The damage states of a fragility analysis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DamageStates {
    /// These thresholds, increasing.
    Levels(Vec<f64>),
    /// The 12-level set of [`TWELVE_LEVELS`].
    Twelve,
}

impl Default for DamageStates {
    fn default() -> Self {
        DamageStates::Levels(DEFAULT_LEVELS.to_vec())
    }
}

/// 0.2, 0.5 and 1 (= overturning for θmax/α).
pub const DEFAULT_LEVELS: [f64; 3] = [0.2, 0.5, 1.0];

/// Twelve θmax/α levels from the onset of rocking to overturning. D'Angela et al. (2026) use
/// 12 levels from 0.01 to 1 "through small increments" without listing them: these values
/// are rocklab's choice within that range.
pub const TWELVE_LEVELS: [f64; 12] = [0.01, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0];

impl Fragility {
    /// The options of this section's fits (the fragility report's and a design target's).
    pub fn fit_options(&self) -> crate::stats::FragilityOptions {
        crate::stats::FragilityOptions {
            damage_states: self.damage_states.levels(),
            bootstrap: self.bootstrap,
            seed: self.seed,
            confidence: self.confidence,
        }
    }
}

impl DamageStates {
    pub fn levels(&self) -> Vec<f64> {
        match self {
            DamageStates::Levels(v) => v.clone(),
            DamageStates::Twelve => TWELVE_LEVELS.to_vec(),
        }
    }
}

impl Default for Fragility {
    fn default() -> Self {
        Fragility {
            method: Method::default(),
            damage_states: DamageStates::default(),
            measure: default_measure(),
            bootstrap: default_bootstrap(),
            seed: default_seed(),
            confidence: default_confidence(),
        }
    }
}

pub(crate) fn default_measure() -> Quantity {
    Quantity::PeakRotationRatio
}

pub(crate) fn default_bootstrap() -> usize {
    1000
}

pub(crate) fn default_seed() -> u64 {
    1
}

pub(crate) fn default_confidence() -> f64 {
    0.9
}

/// Most bootstrap resamples a study may ask for (each refits every curve).
const MAX_BOOTSTRAP: usize = 100_000;

/// Fewest bootstrap resamples a study may ask for (0 asks for none). A 90 % interval is read
/// off the 5th and 95th percentiles of the resamples: with a handful of them those are
/// single draws, and the "interval" need not even contain the median it is about (2 gave
/// one that did not); 200 puts ten resamples beyond each end.
pub const MIN_BOOTSTRAP: usize = 200;

/// The intensity measure of a fragility study's stripes, as `stripes.csv` and the fit name it.
/// Sa is named `sa(T)` (`sa(1.0)`), the spelling hazard curves in Sa use too.
pub fn im_name(scale_to: RecordScaling) -> Option<String> {
    Some(match scale_to {
        RecordScaling::Pga => "pga_g".into(),
        RecordScaling::Pgv => "pgv_m_s".into(),
        RecordScaling::PgaStar => "pga_star".into(),
        RecordScaling::PgvStar => "pgv_star".into(),
        RecordScaling::Sa { period, .. } => format!("sa({period:?})"),
        RecordScaling::SaAvg { from, to } => format!("sa_avg({from:?},{to:?})"),
        RecordScaling::Arias => "arias_m_s".into(),
        RecordScaling::Factor | RecordScaling::Fema => return None,
    })
}

/// Check a study's fragility section against the rest of the study.
pub fn validate(study: &Study) -> Result<(), StudyError> {
    let Some(f) = &study.fragility else {
        return Ok(());
    };
    let ExcitationFamily::Record { scale_to, .. } = &study.excitation else {
        return Err(StudyError::field(
            "fragility",
            "a fragility analysis needs recorded ground motions",
            "excitation: record(suite: (name: \"far_field\"), scale: [1.5, 2.0, 3.0], scale_to: pga_star)",
        ));
    };
    if im_name(*scale_to).is_none() {
        return Err(StudyError::field(
            "excitation.scale_to",
            "the stripes of a fragility analysis are intensity-measure values",
            "scale_to: pga (g), pgv (m/s), pga_star (PGA/(g·tanα)), pgv_star (PGV·p/(g·tanα)), \
             sa(period: T), sa_avg(from: T1, to: T2) or arias; \
             `scale` then lists the stripes",
        ));
    }
    if study.spectrum != Axis::Scale {
        return Err(StudyError::field(
            "spectrum",
            "a fragility study's x axis is its intensity measure",
            "spectrum: scale (the stripes)",
        ));
    }
    let levels = f.damage_states.levels();
    if levels.is_empty() {
        return Err(StudyError::field(
            "fragility.damage_states",
            "no damage states",
            "e.g. damage_states: levels([0.2, 0.5, 1.0]), or twelve",
        ));
    }
    if let Some(bad) = levels.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
        return Err(StudyError::field(
            "fragility.damage_states",
            format!("{} is not a damage-state threshold", fmt_exact(*bad)),
            "thresholds of the damage measure are finite and > 0 (1 = overturning for θmax/α)",
        ));
    }
    if levels.windows(2).any(|w| w[1] <= w[0]) {
        return Err(StudyError::field(
            "fragility.damage_states",
            "damage states must increase",
            "list each threshold once, smallest first: levels([0.2, 0.5, 1.0])",
        ));
    }
    if !study.quantities.contains(&f.measure) {
        return Err(StudyError::field(
            "fragility.measure",
            format!(
                "the damage measure `{}` is not among the study's quantities",
                f.measure.name()
            ),
            "add it to `quantities`, e.g. quantities: [peak_rotation_ratio]",
        ));
    }
    let flexible_only = matches!(f.measure, Quantity::PeakDrift | Quantity::PeakDeformation);
    if flexible_only && matches!(study.structure, StructureFamily::Rigid { .. }) {
        return Err(StudyError::field(
            "fragility.measure",
            format!("a rigid block has no `{}`", f.measure.name()),
            "rigid blocks: peak_rotation_ratio (θmax/α)",
        ));
    }
    if !matches!(
        f.measure,
        Quantity::PeakRotationRatio | Quantity::PeakDrift | Quantity::PeakDeformation
    ) {
        return Err(StudyError::field(
            "fragility.measure",
            format!("`{}` is not a damage measure", f.measure.name()),
            "peak_rotation_ratio (θmax/α; for a flexible structure its uplift), or for a \
             flexible structure peak_drift or peak_deformation",
        ));
    }
    if let Some(resolution) = f.method.ida_resolution() {
        validate_ida(study, resolution)?;
    }
    if (1..MIN_BOOTSTRAP).contains(&f.bootstrap) {
        return Err(StudyError::field(
            "fragility.bootstrap",
            format!(
                "{} resamples are too few for a confidence interval",
                f.bootstrap
            ),
            &format!("at least {MIN_BOOTSTRAP} (1000 is the default), or 0 for no intervals"),
        ));
    }
    if f.bootstrap > MAX_BOOTSTRAP {
        return Err(StudyError::field(
            "fragility.bootstrap",
            format!("{} resamples are too many", f.bootstrap),
            &format!("at most {MAX_BOOTSTRAP}; 1000 is the default"),
        ));
    }
    if !(f.confidence > 0.0 && f.confidence < 1.0) {
        return Err(StudyError::field(
            "fragility.confidence",
            format!("{} is not a confidence level", fmt_exact(f.confidence)),
            "between 0 and 1, e.g. 0.9 for 5th–95th percentile intervals",
        ));
    }
    Ok(())
}

/// An IDA's ladder (the `scale` values) and resolution.
fn validate_ida(study: &Study, resolution: f64) -> Result<(), StudyError> {
    let ExcitationFamily::Record { scale, .. } = &study.excitation else {
        return Ok(());
    };
    let ladder = scale.expand();
    if ladder.iter().any(|v| !(v.is_finite() && *v > 0.0))
        || ladder.windows(2).any(|w| w[1] <= w[0])
    {
        return Err(StudyError::field(
            "excitation.scale",
            "an IDA's ladder must be positive intensities, increasing",
            "e.g. scale: (from: 1.0, to: 16.0, steps: 9, log: true): the hunt climbs them in order",
        ));
    }
    let top = ladder.last().copied().unwrap_or(1.0);
    let finest = top / f64::from(1u32 << MAX_BISECTIONS);
    if !(resolution.is_finite() && resolution >= finest) {
        return Err(StudyError::field(
            "fragility.method",
            format!(
                "resolution {} is not an IM interval of at least {finest:.3e}",
                fmt_exact(resolution)
            ),
            &format!(
                "ida(resolution: r): the widest final bracket in IM units, ≥ the ladder's top \
                 ({}) / 2^{MAX_BISECTIONS}, e.g. ida(resolution: {})",
                fmt_exact(top),
                crate::numfmt::fmt_sig(top / 100.0)
            ),
        ));
    }
    Ok(())
}
