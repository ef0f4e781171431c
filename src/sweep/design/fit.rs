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

use super::Finished;
use crate::numfmt::fmt_num;
use crate::scene::Excitation;
use crate::sim::Quantity;
use crate::stats::{
    FitStatus, FragilityOptions, StripeObservation, StripePoint, Variant, analyse_stripes,
};
use crate::study::design::FragilityGoal;
use crate::study::{ScenePoint, Study};

/// What a fragility probe is fitted with: the study's damage measure and fit options, the
/// damage state and the goal.
pub(super) struct FragilityFit {
    state: f64,
    goal: FragilityGoal,
    measure: Quantity,
    options: FragilityOptions,
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
}

impl FragilityFit {
    /// The fit of a study whose design target is a fragility target (validated: a stripes
    /// study with the state among its damage states).
    pub fn of(study: &Study) -> Option<FragilityFit> {
        let (state, goal) = study.design.as_ref()?.target.fragility()?;
        let f = study.fragility.as_ref()?;
        Some(FragilityFit {
            state,
            goal,
            measure: f.measure,
            // Only the target's state is fitted: each curve's fit and bootstrap depend on its
            // own data and the record resample alone, so it is the curve fragility.csv has.
            options: FragilityOptions {
                damage_states: vec![state],
                ..f.fit_options()
            },
        })
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
        let bound = stripe_bound(&curve.stripes, self.goal.im());
        let probability = curve.probability(self.goal.im());
        let pass = match (curve.status, self.goal) {
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
        }))
    }

    /// What the target reads off the curve: the fitted median or probability (None: no fit).
    pub fn achieved(&self, s: &FitSummary) -> Option<f64> {
        match self.goal {
            FragilityGoal::MedianAtLeast(_) => s.median,
            FragilityGoal::ExceedanceAtMost { .. } => s.probability,
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
                None => format!("no stripe at or above IM {}", fmt_num(self.goal.im())),
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
