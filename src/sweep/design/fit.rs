//! A design's fragility target (`target: fragility(state: d, …)` in a fragility study): each
//! probe's scenes, every record at every stripe with the sized parameter at the probe's value,
//! are fitted exactly as the fragility report fits a study's stripes
//! ([`crate::stats::analyse_stripes`]: the binomial maximum-likelihood lognormal and the
//! bootstrap over records, with the study's `fragility` options), and the verdict is read off
//! the fitted curve of state `d`: its median against `median_at_least`, or its probability at
//! `at` against `exceedance_at_most`. The verdict is on the fit itself; the bootstrap interval
//! of the median is reported beside it (`governing`) so a reader sees the margin.
//!
//! A curve that cannot be fitted (too few records reach the state, or the stripes separate
//! them: `no_exceedance`, `separated`, …) is judged on its stripes instead, the data the fit
//! would have used: the largest fraction of records reaching the state at any stripe up to the
//! first stripe at or above the target's intensity must be within the goal (a median of at
//! least x is P(x) ≤ 1/2). Any curve rising with intensity through those fractions is then
//! within the goal at the target's intensity; a target above the highest stripe cannot be
//! judged so and fails (no fit is no proof). A failed scene fails the probe, as for a
//! response target.
//!
//! A risk target (`target: risk(state: d, maf_at_most: x)` or `p_years_at_most`) reads the
//! same fitted curve, converted to the hazard's measure with the probe's structure (α, p), as
//! the risk report does (`crate::risk::maf` over the study's `risk` section's hazard): the
//! MAF against x, or 1 − exp(−MAF · years) against the bound. Its interval is the MAF of each
//! bootstrap resample's fit (as risk.csv's), reported beside. A curve without a fit fails a
//! risk target: the MAF needs the whole curve.

use super::Finished;
use crate::numfmt::{fmt_num, fmt_sig};
use crate::risk::{HazardCurve, probability_in};
use crate::scene::Excitation;
use crate::sim::Quantity;
use crate::stats::{
    FitStatus, FragilityOptions, StripeObservation, StripePoint, Variant, analyse_stripes, interval,
};
use crate::study::design::FragilityGoal;
use crate::study::risk::ImFactor;
use crate::study::{ScenePoint, Study, StudyError};

/// A risk target's site: the hazard, its conversion to the study's measure, the years.
struct Site {
    hazard: HazardCurve,
    factor: ImFactor,
    years: f64,
}

/// What a fragility probe is fitted with: the study's damage measure and fit options, the
/// damage state and the goal.
pub(super) struct FragilityFit {
    state: f64,
    goal: FragilityGoal,
    measure: Quantity,
    options: FragilityOptions,
    site: Option<Site>,
}

/// A fitted probe: the curve of the target's state and the verdict.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct FitSummary {
    pub pass: bool,
    pub status: FitStatus,
    pub median: Option<f64>,
    pub beta: Option<f64>,
    pub median_lo: Option<f64>,
    pub median_hi: Option<f64>,
    /// The fitted probability of reaching the state at the goal's intensity.
    pub probability: Option<f64>,
    pub records: usize,
    pub stripes: usize,
    /// The stripes' bound at the goal's intensity: the first stripe at or above it, and the
    /// largest fraction reaching the state up to it (None: the intensity is above them all).
    pub bound: Option<(f64, f64)>,
    /// A risk target's MAF of the fitted curve at the site and its bootstrap interval.
    pub maf: Option<f64>,
    pub maf_lo: Option<f64>,
    pub maf_hi: Option<f64>,
}

impl FragilityFit {
    /// The fit of a study whose design target is a fragility target (validated: a stripes
    /// study with the state among its damage states).
    /// A risk target reads the study's `risk` hazard (Err: unreadable, or in another
    /// measure than the study's).
    pub fn of(study: &Study) -> Result<Option<FragilityFit>, StudyError> {
        let Some((state, goal)) = study.design.as_ref().and_then(|d| d.target.fragility()) else {
            return Ok(None);
        };
        let Some(f) = study.fragility.as_ref() else {
            return Ok(None);
        };
        let site = match (goal, &study.risk) {
            (FragilityGoal::MafAtMost(_) | FragilityGoal::PYearsAtMost(_), Some(r)) => {
                let hazard = HazardCurve::read(&r.hazard_path()).map_err(|e| {
                    StudyError::field(
                        "risk.hazard",
                        e.to_string(),
                        "the hazard file's path is relative to the study file's directory",
                    )
                })?;
                let factor = crate::study::risk::im_factor(study, hazard.im).map_err(
                    |(scaling, hint)| {
                        StudyError::field(
                            "risk.hazard",
                            format!(
                                "{}: the hazard is in `{}`, but the study scales its records \
                                 to {scaling}",
                                r.hazard,
                                hazard.im.name()
                            ),
                            hint,
                        )
                    },
                )?;
                Some(Site {
                    hazard,
                    factor,
                    years: r.years,
                })
            }
            _ => None,
        };
        Ok(Some(FragilityFit {
            state,
            goal,
            measure: f.measure,
            // Only the target's state is fitted: each curve's fit and bootstrap depend on its
            // own data and the record resample alone, so it is the curve fragility.csv has.
            options: FragilityOptions {
                damage_states: vec![state],
                ..f.fit_options()
            },
            site,
        }))
    }

    /// The probe's fit once every scene has finished (None before); Err(i): scene i failed or
    /// has no damage measure.
    pub fn evaluate(
        &self,
        scenes: &[ScenePoint],
        done: &Finished,
    ) -> Option<Result<FitSummary, usize>> {
        let mut obs = Vec::with_capacity(scenes.len());
        let mut failed = None;
        // The probe's structure (every scene of a probe has the same), for a risk's IM factor.
        let structure = &scenes.first()?.scene.structure;
        for (i, sc) in scenes.iter().enumerate() {
            let response = match done.get(&sc.key)? {
                Ok(r) if r.overturned => Some(f64::INFINITY),
                Ok(r) => self.measure.of(r).filter(|v| v.is_finite()),
                Err(_) => None,
            };
            let (Some(response), Excitation::Record { name, scale, .. }) =
                (response, &sc.scene.excitation)
            else {
                failed = failed.or(Some(i));
                continue;
            };
            obs.push(StripeObservation {
                variant: Variant {
                    device: String::new(),
                    params: Vec::new(),
                },
                record: name.clone(),
                im: scale.value(),
                response,
                overturned: response == f64::INFINITY,
            });
        }
        if let Some(i) = failed {
            return Some(Err(i));
        }
        let report = analyse_stripes(&obs, &self.options);
        let curve = report
            .curves
            .into_iter()
            .find(|c| c.damage_state == self.state)?;
        let bound = self
            .goal
            .im()
            .and_then(|im| stripe_bound(&curve.stripes, im));
        let probability = self.goal.im().and_then(|im| curve.probability(im));
        let (mut maf, mut maf_lo, mut maf_hi) = (None, None, None);
        if let Some(site) = &self.site
            && curve.status == FitStatus::Fitted
            && let (Some(median), Some(beta)) = (curve.median, curve.beta)
        {
            let factor = (site.factor)(structure.alpha(), structure.p());
            let of = |m: f64, b: f64| crate::risk::maf(&site.hazard, m / factor, b).maf;
            maf = Some(of(median, beta));
            let sample: Vec<f64> = curve
                .resamples
                .iter()
                .flatten()
                .map(|[m, b]| of(*m, *b))
                .collect();
            [maf_lo, maf_hi] = interval(&sample, self.options.confidence);
        }
        let years = self.site.as_ref().map_or(f64::NAN, |s| s.years);
        let pass = match (curve.status, self.goal) {
            (_, FragilityGoal::MafAtMost(most)) => maf.is_some_and(|m| m <= most),
            (_, FragilityGoal::PYearsAtMost(most)) => {
                maf.is_some_and(|m| probability_in(m, years) <= most)
            }
            (FitStatus::Fitted, FragilityGoal::MedianAtLeast(x)) => curve.median? >= x,
            (FitStatus::Fitted, FragilityGoal::ExceedanceAtMost { most, .. }) => {
                probability? <= most
            }
            _ => bound.is_some_and(|(_, fraction)| fraction <= self.goal.most()),
        };
        Some(Ok(FitSummary {
            pass,
            status: curve.status,
            median: curve.median,
            beta: curve.beta,
            median_lo: curve.median_lo,
            median_hi: curve.median_hi,
            probability,
            records: curve.n_records,
            stripes: curve.n_stripes,
            bound,
            maf,
            maf_lo,
            maf_hi,
        }))
    }

    /// What the target reads off the curve: the fitted median or probability (None: no fit).
    pub fn achieved(&self, s: &FitSummary) -> Option<f64> {
        match self.goal {
            FragilityGoal::MedianAtLeast(_) => s.median,
            FragilityGoal::ExceedanceAtMost { .. } => s.probability,
            FragilityGoal::MafAtMost(_) => s.maf,
            FragilityGoal::PYearsAtMost(_) => {
                let years = self.site.as_ref()?.years;
                s.maf.map(|m| probability_in(m, years))
            }
        }
    }

    /// What governs the verdict, for design.csv's `governing`: the fitted curve (median with
    /// its bootstrap interval, β, the probability at the goal's intensity) or why there is
    /// none, and the data behind it.
    pub fn governing(&self, s: &FitSummary) -> String {
        let data = format!("{} records × {} stripes", s.records, s.stripes);
        let (Some(median), Some(beta)) = (s.median, s.beta) else {
            let on_stripes = match s.bound {
                Some((im, fraction)) => format!(
                    "at most {} % reach it at the stripes up to IM {}",
                    fmt_num(100.0 * fraction),
                    fmt_num(im)
                ),
                None => match self.goal.im() {
                    Some(im) => format!("no stripe at or above IM {}", fmt_num(im)),
                    None => "a risk needs the fitted curve".to_string(),
                },
            };
            return format!(
                "no fit ({}: {}); {on_stripes} ({data})",
                s.status.name(),
                s.status.explain()
            );
        };
        let interval = match (s.median_lo, s.median_hi) {
            (Some(lo), Some(hi)) => format!(" [{}, {}]", fmt_num(lo), fmt_num(hi)),
            _ => String::new(),
        };
        let mut text = format!(
            "median {}{interval} β {} ({data})",
            fmt_num(median),
            fmt_num(beta)
        );
        if let (FragilityGoal::ExceedanceAtMost { at, .. }, Some(p)) = (self.goal, s.probability) {
            text = format!("P(IM {}) {}; {text}", fmt_num(at), fmt_num(p));
        }
        if let Some(maf) = s.maf {
            let interval = match (s.maf_lo, s.maf_hi) {
                (Some(lo), Some(hi)) => format!(" [{}, {}]", fmt_sig(lo), fmt_sig(hi)),
                _ => String::new(),
            };
            let years = self.site.as_ref().map_or(f64::NAN, |s| s.years);
            text = format!(
                "MAF {}{interval} /yr, P({} yr) {}; {text}",
                fmt_sig(maf),
                fmt_num(years),
                fmt_sig(probability_in(maf, years))
            );
        }
        text
    }
}

/// The first stripe at or above `im` and the largest fraction of records reaching the state at
/// any stripe up to it (`stripes` sorted by intensity, as a curve holds them); None if every
/// stripe is below `im`.
impl FragilityFit {
    /// A median goal met or missed within the median's own bootstrap interval: the verdict
    /// rests on the records drawn, and the summary must say so.
    pub fn warning(&self, s: &FitSummary) -> Option<String> {
        let FragilityGoal::MedianAtLeast(goal) = self.goal else {
            return None;
        };
        let (lo, hi) = (s.median_lo?, s.median_hi?);
        (lo < goal && goal < hi).then(|| {
            format!(
                "the median's interval [{}, {}] straddles the goal {}: met or missed within \
                 its uncertainty",
                fmt_num(lo),
                fmt_num(hi),
                fmt_num(goal)
            )
        })
    }
}

fn stripe_bound(stripes: &[StripePoint], im: f64) -> Option<(f64, f64)> {
    let s = stripes.iter().position(|p| p.im >= im)?;
    let most = stripes[..=s]
        .iter()
        .map(StripePoint::fraction)
        .fold(0.0, f64::max);
    Some((stripes[s].im, most))
}
