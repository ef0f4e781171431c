//! The `uncertain` section of a fragility study: parameters that are never known exactly
//! (slenderness, size, restitution, the clutch's spring and damping) drawn from stated
//! distributions, one draw per record × stripe (an IDA: per record, since its hunt climbs
//! one structure), seeded, by Monte Carlo or Latin hypercube sampling:
//!
//! ```ron
//! uncertain: (
//!     seed: 7,
//!     sampling: latin_hypercube,
//!     alpha: normal(mean: deg(14), sd: deg(1)),
//!     restitution: uniform(lo: 0.8, hi: 0.95),
//!     size: lognormal(median: 2.0, beta: 0.1),
//! ),
//! ```
//!
//! Each parameter is named as the study names it elsewhere (the parameter table,
//! `study::Param`), so a misspelt one is an unknown field with "did you mean". The drawn
//! value replaces the study's value of that parameter in the scene; the expansion
//! (`draw.rs`) makes the draws from the seed and each scene's place on the record × stripe
//! grid, never from the order scenes run in, so a killed and resumed sweep draws the same
//! numbers. A stripes study also runs each scene's deterministic companion (every drawn
//! parameter at its distribution's centre): the fit over the companions is the dispersion
//! from records alone, reported beside the total (report/stripes.rs, docs/MODEL.md).
//!
//! Physically impossible values (α ≤ 0, restitution outside (0, 1], …) are never drawn: a
//! distribution is truncated to its parameter's range ([`Range`]) by drawing from the
//! truncated distribution (inversion restricted to the range, so a Latin hypercube stays
//! stratified), and refused when more than [`MAX_MASS_OUTSIDE`] of it lies outside (a
//! truncation that large would change the distribution the study states).

mod draw;

pub use draw::{Sample, apply, uniforms};

use super::{DeviceVariant, Param, StructureFamily, Study, StudyError};
use crate::numfmt::fmt_exact;
use crate::scene::Impact;
use crate::stats::normal;
use serde::{Deserialize, Serialize};

/// The uncertain parameters of a study, with how they are drawn.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Uncertain {
    /// Seed of the draws: the same seed draws the same values for the same study.
    #[serde(default = "default_seed")]
    pub seed: u64,
    #[serde(default)]
    pub sampling: Sampling,
    #[serde(default)]
    pub draws: Draws,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha: Option<Distribution>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<Distribution>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub p: Option<Distribution>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<Distribution>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_theta: Option<Distribution>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clutch_frequency_ratio: Option<Distribution>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cbar: Option<Distribution>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub xi_theta: Option<Distribution>,
}

pub(crate) fn default_seed() -> u64 {
    1
}

/// How the uniforms behind the draws are laid out.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Sampling {
    /// Independent draws.
    MonteCarlo,
    /// Latin hypercube: with N draws, each parameter has exactly one draw in each of its N
    /// equal-probability strata (McKay, Beckman & Conover 1979).
    #[default]
    LatinHypercube,
}

/// Which scenes share a draw.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Draws {
    /// One draw per record × stripe, shared by the study's device variants (they meet the
    /// same structure, so their difference is the device's); an IDA draws once per record.
    #[default]
    PerRecordStripe,
}

/// A parameter's distribution.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Distribution {
    /// Normal with mean and standard deviation (in the parameter's unit; an angle may be
    /// given in degrees, deg(…)).
    Normal { mean: f64, sd: f64 },
    /// Lognormal with median and logarithmic standard deviation β.
    Lognormal { median: f64, beta: f64 },
    /// Uniform between lo and hi.
    Uniform { lo: f64, hi: f64 },
}

/// Largest probability a distribution may put outside its parameter's range; the rest is
/// drawn from the distribution truncated to the range.
pub const MAX_MASS_OUTSIDE: f64 = 0.01;

/// The values a parameter may physically take: `lo < x ≤ hi` (the scene's own checks, e.g.
/// 0 < α < π/2, a block at least 1 mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    pub lo: f64,
    pub hi: f64,
}

impl Range {
    /// The range of a parameter that can be uncertain.
    pub fn of(param: Param) -> Range {
        let positive = Range {
            lo: 0.0,
            hi: f64::INFINITY,
        };
        match param {
            Param::Alpha => Range {
                lo: 0.0,
                hi: std::f64::consts::FRAC_PI_2,
            },
            Param::Size => Range {
                lo: crate::scene::MIN_SIZE,
                hi: f64::INFINITY,
            },
            // p = √(3g/4R) with R ≥ 1 mm.
            Param::P => Range {
                lo: 0.0,
                hi: (3.0 * crate::excitation::G / (4.0 * crate::scene::MIN_SIZE)).sqrt(),
            },
            Param::Restitution => Range { lo: 0.0, hi: 1.0 },
            _ => positive,
        }
    }

    fn text(&self) -> String {
        format!("({}, {}]", fmt_exact(self.lo), fmt_exact(self.hi))
    }
}

impl Distribution {
    /// The value a deterministic companion scene takes: the mean, median or midpoint.
    pub fn centre(&self) -> f64 {
        match *self {
            Distribution::Normal { mean, .. } => mean,
            Distribution::Lognormal { median, .. } => median,
            Distribution::Uniform { lo, hi } => 0.5 * (lo + hi),
        }
    }

    /// Whether it has no spread (sd 0, β 0, lo = hi): every draw is its centre, exactly.
    pub fn is_degenerate(&self) -> bool {
        match *self {
            Distribution::Normal { sd, .. } => sd == 0.0,
            Distribution::Lognormal { beta, .. } => beta == 0.0,
            Distribution::Uniform { lo, hi } => lo == hi,
        }
    }

    /// The standard-normal location and scale of the underlying normal (of ln x for a
    /// lognormal) and the range in that variable; None for a uniform.
    fn normal_form(&self, range: Range) -> Option<(f64, f64, f64, f64)> {
        match *self {
            Distribution::Normal { mean, sd } => Some((mean, sd, range.lo, range.hi)),
            Distribution::Lognormal { median, beta } => {
                Some((median.ln(), beta, range.lo.ln(), range.hi.ln()))
            }
            Distribution::Uniform { .. } => None,
        }
    }

    /// Probability the (untruncated) distribution puts outside `range`.
    pub fn mass_outside(&self, range: Range) -> f64 {
        if self.is_degenerate() {
            let c = self.centre();
            return if c > range.lo && c <= range.hi {
                0.0
            } else {
                1.0
            };
        }
        match self.normal_form(range) {
            Some((m, s, lo, hi)) => normal::cdf((lo - m) / s) + normal::cdf(-(hi - m) / s),
            None => {
                let Distribution::Uniform { lo, hi } = *self else {
                    unreachable!("normal_form is None only for a uniform")
                };
                let inside = (hi.min(range.hi) - lo.max(range.lo)).max(0.0);
                1.0 - inside / (hi - lo)
            }
        }
    }

    /// The value at probability `u` ∈ (0, 1) of the distribution truncated to `range`
    /// (inversion: equal steps of u are equal probability, which a Latin hypercube needs).
    /// A degenerate distribution gives its centre exactly, whatever u.
    pub fn value(&self, u: f64, range: Range) -> f64 {
        if self.is_degenerate() {
            return self.centre();
        }
        match self.normal_form(range) {
            Some((m, s, lo, hi)) => {
                let below = normal::cdf((lo - m) / s);
                let above = normal::cdf((hi - m) / s);
                let z = normal::quantile(below + u * (above - below));
                let x = m + s * z;
                match self {
                    Distribution::Lognormal { .. } => x.exp(),
                    _ => x,
                }
            }
            None => {
                let Distribution::Uniform { lo, hi } = *self else {
                    unreachable!("normal_form is None only for a uniform")
                };
                lo + u * (hi - lo)
            }
        }
    }
}

impl Uncertain {
    /// The uncertain parameters with their distributions, in the section's (fixed) order:
    /// the order their uniforms are drawn in.
    pub fn parameters(&self) -> Vec<(Param, Distribution)> {
        [
            (Param::Alpha, self.alpha),
            (Param::Size, self.size),
            (Param::P, self.p),
            (Param::Restitution, self.restitution),
            (Param::KTheta, self.k_theta),
            (Param::ClutchFrequencyRatio, self.clutch_frequency_ratio),
            (Param::Cbar, self.cbar),
            (Param::XiTheta, self.xi_theta),
        ]
        .into_iter()
        .filter_map(|(p, d)| d.map(|d| (p, d)))
        .collect()
    }
}

impl Distribution {
    /// `normal(mean 0.244, sd 0.0175)`, numbers at 4 significant digits.
    fn text(&self) -> String {
        let n = |v: f64| crate::numfmt::fmt_digits(v, 4);
        match *self {
            Distribution::Normal { mean, sd } => format!("normal(mean {}, sd {})", n(mean), n(sd)),
            Distribution::Lognormal { median, beta } => {
                format!("lognormal(median {}, β {})", n(median), n(beta))
            }
            Distribution::Uniform { lo, hi } => format!("uniform({}, {})", n(lo), n(hi)),
        }
    }
}

impl Uncertain {
    /// One line on what is drawn and how, for the fragility report (`per_record`: an IDA's
    /// draws).
    pub fn describe(&self, per_record: bool) -> String {
        let each: Vec<String> = (self.parameters().into_iter())
            .map(|(p, d)| format!("{} ~ {}", p.label(), d.text()))
            .collect();
        let sampling = match self.sampling {
            Sampling::MonteCarlo => "Monte Carlo",
            Sampling::LatinHypercube => "Latin hypercube",
        };
        format!(
            "{}; {sampling}, seed {}, one draw per record{}",
            each.join(", "),
            self.seed,
            if per_record { "" } else { " × stripe" }
        )
    }
}

fn field(param: Param) -> String {
    format!("uncertain.{}", param.field())
}

/// Check one distribution: its own numbers, then against its parameter's range.
fn check_distribution(param: Param, d: &Distribution) -> Result<(), StudyError> {
    let bad = |message: String, hint: &str| Err(StudyError::field(field(param), message, hint));
    let numbers: &[f64] = match d {
        Distribution::Normal { mean, sd } => &[*mean, *sd],
        Distribution::Lognormal { median, beta } => &[*median, *beta],
        Distribution::Uniform { lo, hi } => &[*lo, *hi],
    };
    if numbers.iter().any(|v| !v.is_finite()) {
        return bad("a distribution's numbers must be finite".into(), "");
    }
    match *d {
        Distribution::Normal { sd, .. } if sd < 0.0 => {
            return bad(
                format!("sd {} is negative", fmt_exact(sd)),
                "a standard deviation is ≥ 0 (0: no uncertainty)",
            );
        }
        Distribution::Lognormal { median, .. } if median <= 0.0 => {
            return bad(
                format!("lognormal median {} is not positive", fmt_exact(median)),
                "a lognormal's median is > 0",
            );
        }
        Distribution::Lognormal { beta, .. } if beta < 0.0 => {
            return bad(
                format!("beta {} is negative", fmt_exact(beta)),
                "β, the standard deviation of ln x, is ≥ 0 (0: no uncertainty)",
            );
        }
        Distribution::Uniform { lo, hi } if lo > hi => {
            return bad(
                format!("uniform lo {} is above hi {}", fmt_exact(lo), fmt_exact(hi)),
                "uniform(lo: a, hi: b) with a ≤ b",
            );
        }
        _ => {}
    }
    let range = Range::of(param);
    let outside = d.mass_outside(range);
    let uniform = matches!(d, Distribution::Uniform { .. });
    if (uniform && outside > 0.0) || outside > MAX_MASS_OUTSIDE {
        return bad(
            format!(
                "{:.3} % of this distribution lies outside {}'s physical range {}",
                100.0 * outside,
                param.field(),
                range.text()
            ),
            &format!(
                "a uniform must lie inside the range; a normal or lognormal may put at most \
                 {} % outside it (those draws are truncated to the range): narrow it",
                100.0 * MAX_MASS_OUTSIDE
            ),
        );
    }
    Ok(())
}

/// Check a study's uncertain section against the rest of the study.
pub fn validate(study: &Study) -> Result<(), StudyError> {
    let Some(u) = &study.uncertain else {
        return Ok(());
    };
    let parameters = u.parameters();
    if parameters.is_empty() {
        return Err(StudyError::field(
            "uncertain",
            "no uncertain parameter",
            "e.g. uncertain: (seed: 7, alpha: normal(mean: deg(14), sd: deg(1)), \
             restitution: uniform(lo: 0.8, hi: 0.95))",
        ));
    }
    let kind = study.kind();
    if !matches!(kind, super::StudyKind::Stripes | super::StudyKind::Ida) {
        return Err(StudyError::field(
            "uncertain",
            "uncertain parameters are drawn per record and stripe of a fragility study",
            "give the study a `fragility` section over records (stripes or ida), without a \
             map or a design",
        ));
    }
    for (param, d) in &parameters {
        check_distribution(*param, d)?;
        check_applies(study, *param)?;
    }
    Ok(())
}

/// A drawn parameter must be one the study's scenes have, given one value on the grid.
fn check_applies(study: &Study, param: Param) -> Result<(), StudyError> {
    let refuse = |message: &str, hint: &str| Err(StudyError::field(field(param), message, hint));
    let rigid = matches!(study.structure, StructureFamily::Rigid { .. });
    let clutches = || {
        study.devices.iter().any(|d| match d {
            DeviceVariant::Mechanistic { .. } => true,
            DeviceVariant::Inerter { coupling, .. } => {
                matches!(coupling, super::CouplingFamily::Flywheel { .. })
            }
            _ => false,
        })
    };
    match param {
        Param::Size | Param::P if !rigid => {
            return refuse(
                "a flexible structure has no block size",
                "draw alpha, or the clutch's parameters",
            );
        }
        Param::Size | Param::P if study.uncertain_both_sizes() => {
            return refuse(
                "size and p describe the same block: draw one",
                "keep size or p",
            );
        }
        Param::Restitution if !rigid => {
            return refuse(
                "a flexible structure's impacts follow the VVEL model, with no restitution",
                "draw alpha or the clutch's parameters",
            );
        }
        Param::Restitution if matches!(study.impact, Impact::Dirac { .. }) => {
            return refuse(
                "a Dirac impact has no coefficient of restitution",
                "impact: housner() (the default) takes a drawn restitution",
            );
        }
        Param::KTheta | Param::ClutchFrequencyRatio | Param::Cbar | Param::XiTheta
            if !clutches() =>
        {
            return refuse(
                "no device of the study has a clutch spring or damper",
                "a mechanistic clutch or an inerter with coupling: flywheel(…) has them",
            );
        }
        _ => {}
    }
    let layout = study.layout()?;
    for variant in &layout.variants {
        let varies = variant.params.iter().any(|p| {
            let same = p.param == param
                || matches!(
                    (p.param, param),
                    (Param::Size, Param::P) | (Param::P, Param::Size)
                );
            same && p.varies()
        });
        if varies {
            return Err(StudyError::field(
                field(param),
                format!(
                    "{} varies on the study's grid and is drawn as well",
                    param.field()
                ),
                "give it one value on the grid (the draws replace it), or leave it certain",
            ));
        }
    }
    Ok(())
}

impl Study {
    fn uncertain_both_sizes(&self) -> bool {
        self.uncertain
            .as_ref()
            .is_some_and(|u| u.size.is_some() && u.p.is_some())
    }
}

#[cfg(test)]
mod tests;
