//! Is a scene's answer reproducible? A peak can be off at the scene's tolerance for two
//! reasons that call for different remedies: the integration has not converged yet (tighten
//! the tolerance), or the peak is ill-conditioned, so sensitive to its inputs that a relative
//! change of 1e-7 moves it visibly (no ordinary tolerance reproduces it, and the input data
//! do not fix it that finely). [`check`] tells them apart by rerunning the scene at a
//! tolerance 1000× tighter and, there, with its inputs (the excitation's amplitude and the
//! initial rotation) scaled by 1 ± [`INPUT_CHANGE`].
//!
//! κ is local: it says how the peak responds to tiny changes, which is what numerical
//! reproducibility needs. How a spectrum point responds to realistic uncertainty of a record
//! (1e-3 and more) is a different, physical question, for a sweep over `scale`: a scene can
//! be well-conditioned here and still move by percent for a 1e-3 change.
//!
//! The measured case: a rigid block (R = 3 m, α = 0.25) with a 50 p mechanistic clutch under
//! Landers rocks at θ ~ 1e-4 rad with impacts every 5–10 ms before the main pulse, and there
//! perturbations grow by ~1e5: at rtol 1e-12, scaling the record by 1 + 1e-7 moves the peak
//! rotation by 1.2 %, while the same scene with the 25, 100 or 200 p clutch, the sequential
//! law or no device moves by less than 1e-5 (`tests/hard_cases.rs`).

use super::Quantity;
use super::{SceneResult, SimError, run_bounded};
use crate::excitation::Library;
use crate::numfmt::fmt_condition;
use crate::scene::Scene;
use serde::{Deserialize, Serialize};

/// Relative change of the inputs the condition number is measured with: 100× the default
/// rtol's 1e-5 below it, so a peak that moves visibly for it cannot be reproduced by an
/// ordinary tolerance either (local errors act like input changes of about rtol).
pub const INPUT_CHANGE: f64 = 1e-7;
/// The reference tolerance is the scene's times this.
pub const TIGHTENING: f64 = 1e-3;
/// A peak that moves by more than this against the reference is not converged.
pub const CONVERGED: f64 = 1e-3;
/// Condition number from which a peak counts as ill-conditioned: a change of 1e-7 in the
/// input moves it by more than 1e-3.
pub const ILL_CONDITIONED: f64 = 1e4;
/// A rotation (or drift) peak below this × α is negligible (see [`PeakCheck::negligible`]):
/// an engineering threshold (θ/α = 1e-3: no rocking to speak of, for slender and stocky
/// blocks alike, since overturning scales with α), not a numerical one.
/// Measured: the flexible Fig. 14 structures at ωg/p = 14.5 barely lift off, θ = 2e-6 rad
/// (1e-5 α), and that peak moves by 57 % between rtol 1e-5 and 1e-8, by 1e-6 rad.
pub const NEGLIGIBLE: f64 = 1e-3;

/// One peak under the check.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PeakCheck {
    pub quantity: &'static str,
    /// At the scene's tolerance.
    pub value: f64,
    /// At the reference tolerance.
    pub reference: f64,
    /// |value − reference| / |reference| (infinite, `null` in JSON, if only the reference
    /// is 0).
    #[serde(serialize_with = "finite_or_null")]
    pub change: f64,
    /// Relative change of the reference peak per relative change of the inputs (the larger
    /// of the two sides): 1 for a linear response, 0 where the peak does not depend on them,
    /// infinite where it appears or vanishes (the reference is 0 and a scaled run's is not,
    /// e.g. an uplift that barely happens), NaN if a run's peak is NaN; `null` in JSON for
    /// both.
    #[serde(serialize_with = "finite_or_null")]
    pub condition: f64,
    /// A rotation or drift below [`NEGLIGIBLE`] × α in every run (the structure barely
    /// rocks), or θ̈ between impacts of such rocking: reported but left out of the verdict,
    /// since the integrator controls the rotation only to rtol × α absolutely and no
    /// engineering reading depends on it.
    pub negligible: bool,
}

/// A number to rank by, NaN ranked as infinite.
fn key(v: f64) -> f64 {
    if v.is_nan() { f64::INFINITY } else { v }
}

/// A peak's name for people (`rotation`, `abs. accel.`, …) from its key in check.csv.
pub fn short_name(key: &str) -> &'static str {
    Quantity::from_key(key).map_or("peak", |q| q.info().short)
}

/// JSON has no infinity: a non-finite number is written as `null`.
fn finite_or_null<S: serde::Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    if v.is_finite() {
        s.serialize_f64(*v)
    } else {
        s.serialize_none()
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Reproducibility {
    /// Every peak within [`CONVERGED`] of the reference, none ill-conditioned (negligible
    /// peaks aside).
    Converged,
    /// Some peak is off but well-conditioned: a tighter tolerance fixes it.
    NotConverged,
    /// Some peak (or the overturn flag) responds to a [`INPUT_CHANGE`] in the input by more
    /// than [`CONVERGED`].
    IllConditioned,
}

impl Reproducibility {
    /// As people read it: `converged`, `not converged`, `ill-conditioned`.
    pub fn label(self) -> &'static str {
        match self {
            Reproducibility::Converged => "converged",
            Reproducibility::NotConverged => "not converged",
            Reproducibility::IllConditioned => "ill-conditioned",
        }
    }

    /// As `check.csv` and `--json` spell it.
    pub fn name(self) -> &'static str {
        match self {
            Reproducibility::Converged => "converged",
            Reproducibility::NotConverged => "not_converged",
            Reproducibility::IllConditioned => "ill_conditioned",
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Check {
    pub rtol: f64,
    pub reference_rtol: f64,
    pub input_change: f64,
    pub peaks: Vec<PeakCheck>,
    pub overturned: bool,
    pub reference_overturned: bool,
    /// The overturn flag differs between the scaled runs: the scene sits on the boundary.
    pub overturn_flips: bool,
    pub verdict: Reproducibility,
}

/// The peaks a result holds (those its run measured; a rigid block has no deformation; the
/// rotation ratio is the rotation's), by quantity.
fn peaks_of(r: &SceneResult, rigid: bool) -> Vec<(Quantity, f64)> {
    Quantity::ALL
        .into_iter()
        .filter(|q| match q {
            Quantity::PeakRotationRatio => false,
            Quantity::PeakDeformation => !rigid,
            _ => true,
        })
        .filter_map(|q| Some((q, q.peak(r)?)))
        .collect()
}

/// Relative difference, 0 when both are 0 and infinite when only the reference is.
fn relative(value: f64, reference: f64) -> f64 {
    let d = (value - reference).abs();
    if d == 0.0 { 0.0 } else { d / reference.abs() }
}

/// The tolerance a scene at `rtol` is checked against, or why there is none.
pub fn reference_rtol(rtol: f64) -> Result<f64, String> {
    let reference = rtol * TIGHTENING;
    if reference >= 1e-14 {
        Ok(reference)
    } else {
        Err(format!(
            "rtol {rtol:e} leaves no tighter reference for the check (rtol × {TIGHTENING:e} \
             must be ≥ 1e-14; check at rtol ≥ 1e-11)"
        ))
    }
}

/// Run `scene` as given (`result`, already computed by the caller), at its tolerance × 1e-3,
/// and there with its inputs scaled by 1 ± 1e-7; see the module doc.
pub fn check(
    scene: &Scene,
    result: &SceneResult,
    library: &Library,
    bounds: super::Bounds,
) -> Result<Check, SimError> {
    let reference_rtol = reference_rtol(scene.rtol).map_err(SimError::Invalid)?;
    let at = |factor: f64| {
        let mut s = scene.clone();
        s.rtol = reference_rtol;
        s.excitation = scene.excitation.scaled(factor);
        // An initial rotation within 1e-7 of α stays put rather than start beyond it.
        if (scene.initial_rotation * factor).abs() < scene.structure.alpha() {
            s.initial_rotation = scene.initial_rotation * factor;
        }
        run_bounded(&s, library, bounds)
    };
    let rigid = matches!(scene.structure, crate::scene::Structure::Rigid(_));
    let alpha = scene.structure.alpha();
    let reference = at(1.0)?;
    let scaled = [at(1.0 + INPUT_CHANGE)?, at(1.0 - INPUT_CHANGE)?];
    // Matched by name; a peak missing from a run (it cannot be: the runs measure the same
    // quantities) would read NaN and count as ill-conditioned rather than vanish.
    let peak = |r: &SceneResult, quantity: Quantity| {
        peaks_of(r, rigid)
            .into_iter()
            .find(|(n, _)| *n == quantity)
            .map_or(f64::NAN, |(_, v)| v)
    };
    let runs = [result, &reference, &scaled[0], &scaled[1]];
    let any_nan = |quantity: Quantity| runs.iter().any(|r| peak(r, quantity).is_nan());
    let rocking_negligible = runs
        .iter()
        .all(|r| r.peaks.rotation.abs() < NEGLIGIBLE * alpha);
    let peaks: Vec<PeakCheck> = peaks_of(result, rigid)
        .into_iter()
        .map(|(quantity, value)| {
            let reference_value = peak(&reference, quantity);
            let condition = scaled
                .iter()
                .map(|s| relative(peak(s, quantity), reference_value) / INPUT_CHANGE)
                .fold(0.0, |worst: f64, c| {
                    if worst.is_nan() || c.is_nan() {
                        f64::NAN
                    } else {
                        worst.max(c)
                    }
                });
            let largest = scaled
                .iter()
                .map(|s| peak(s, quantity).abs())
                .fold(value.abs().max(reference_value.abs()), f64::max);
            let negligible = match quantity {
                // `largest` drops a NaN (f64::max): a NaN peak is judged, not skipped.
                Quantity::PeakRotation | Quantity::PeakDrift => {
                    largest < NEGLIGIBLE * alpha && !any_nan(quantity)
                }
                // θ̈ between impacts describes the rocking: negligible with it.
                Quantity::PeakAngularAcceleration => rocking_negligible,
                _ => false,
            };
            PeakCheck {
                quantity: quantity.info().key,
                value,
                reference: reference_value,
                change: relative(value, reference_value),
                condition,
                negligible,
            }
        })
        .collect();
    let judged = || peaks.iter().filter(|p| !p.negligible);
    let overturn_flips = scaled.iter().any(|s| s.overturned != reference.overturned);
    let verdict = if overturn_flips
        || judged().any(|p| p.condition >= ILL_CONDITIONED || p.condition.is_nan())
    {
        Reproducibility::IllConditioned
    } else if judged().all(|p| p.change <= CONVERGED) && result.overturned == reference.overturned {
        Reproducibility::Converged
    } else {
        Reproducibility::NotConverged
    };
    Ok(Check {
        rtol: scene.rtol,
        reference_rtol,
        input_change: INPUT_CHANGE,
        peaks,
        overturned: result.overturned,
        reference_overturned: reference.overturned,
        overturn_flips,
        verdict,
    })
}

impl Check {
    /// The rule of thumb for a reproducible value: the integrator's local errors act like
    /// input changes of about rtol, so rtol ≲ 1e-3 / κ (rounded down to a decade, at most
    /// the scene's and at least 1e-11). On the measured 50 p case (κ = 1.2e5) it says 1e-9,
    /// where the peak is 4.5e-5 off (5e-3 at 1e-7).
    /// None where a peak's κ is not finite (it appears or vanishes: no tolerance settles
    /// that).
    pub fn suggested_rtol(&self) -> Option<f64> {
        let worst = self.worst_condition();
        if !worst.is_finite() {
            return None;
        }
        let rtol = 10f64.powf((CONVERGED / worst.max(1.0)).log10().floor());
        Some(rtol.clamp(1e-11, self.rtol))
    }

    /// The largest condition number of the judged peaks (infinite if any is NaN or
    /// infinite; 0 if every peak is negligible).
    pub fn worst_condition(&self) -> f64 {
        self.worst_peak().map_or(0.0, |p| key(p.condition))
    }

    /// The judged (not negligible) peak with the largest κ, the first of those within 5 %
    /// of it (the rotation before the drift it nearly equals); None if all are negligible.
    pub fn worst_peak(&self) -> Option<&PeakCheck> {
        let top = self.judged().map(|p| key(p.condition)).fold(0.0, f64::max);
        self.judged().find(|p| key(p.condition) >= top / 1.05)
    }

    /// The judged peak with the largest change against the reference.
    pub fn worst_change(&self) -> Option<&PeakCheck> {
        self.judged()
            .reduce(|w, p| if key(p.change) > key(w.change) { p } else { w })
    }

    fn judged(&self) -> impl Iterator<Item = &PeakCheck> {
        self.peaks.iter().filter(|p| !p.negligible)
    }

    /// The lines `simulate --check` prints.
    pub fn report(&self) -> String {
        let mut out = format!(
            "check: rtol {:e} against {:e}; condition κ = relative peak change per relative \
             change of the inputs (× 1 ± {:e}, at {:e})\n",
            self.rtol, self.reference_rtol, self.input_change, self.reference_rtol
        );
        out += &format!(
            "  {:<30} {:>14} {:>14} {:>10} {:>10}\n",
            "quantity", "value", "reference", "change", "κ"
        );
        for p in &self.peaks {
            out += &format!(
                "  {:<30} {:>14.6e} {:>14.6e} {:>10.1e} {:>10}{}\n",
                p.quantity,
                p.value,
                p.reference,
                p.change,
                fmt_condition(p.condition),
                if p.negligible {
                    "  negligible (< 1e-3 α), not judged"
                } else {
                    ""
                }
            );
        }
        let Some(worst) = self.worst_peak() else {
            return out + "verdict: converged: every peak is negligible (below 1e-3 α)\n";
        };
        if self.overturned != self.reference_overturned {
            out += &format!(
                "  overturned: {} at rtol {:e}, {} at {:e}\n",
                self.overturned, self.rtol, self.reference_overturned, self.reference_rtol
            );
        }
        out += &match self.verdict {
            Reproducibility::Converged => {
                format!(
                    "verdict: converged (every peak that is not negligible within {CONVERGED:e} \
                     of the reference)\n"
                )
            }
            Reproducibility::NotConverged => format!(
                "verdict: not converged at rtol {:e}, but well-conditioned: a tighter --rtol \
                 fixes it\n",
                self.rtol
            ),
            Reproducibility::IllConditioned if self.overturn_flips => format!(
                "verdict: ill-conditioned: the scene sits on the overturning boundary (a change \
                 of {:e} in the excitation flips it)\n",
                self.input_change
            ),
            Reproducibility::IllConditioned => match self.suggested_rtol() {
                Some(rtol) => format!(
                    "verdict: ill-conditioned: a relative change of {:e} in the inputs moves \
                     the {} by {:.1e}, so it is not reproducible to better than that; to \
                     reproduce it anyway, rtol ≲ 1e-3 / κ (here {rtol:.0e}) is the rule of \
                     thumb\n",
                    self.input_change,
                    worst.quantity,
                    worst.condition * self.input_change,
                ),
                None => format!(
                    "verdict: ill-conditioned: the {} appears or vanishes under a change of \
                     {:e} in the inputs (a threshold: an uplift that barely happens); no \
                     tolerance settles it\n",
                    worst.quantity, self.input_change,
                ),
            },
        };
        out
    }
}

/// One row of `check.csv`: one scene's check of one peak. `rocklab check` writes these and
/// the workbench reads them back: one type, its header [`CheckCsvRow::HEADER`] (serde's field
/// names, which a test holds it to).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CheckCsvRow {
    pub scene: usize,
    pub verdict: Reproducibility,
    #[serde(serialize_with = "exponent")]
    pub rtol: f64,
    #[serde(serialize_with = "exponent")]
    pub reference_rtol: f64,
    /// The quantity's key ([`Quantity::info`]).
    pub quantity: String,
    #[serde(serialize_with = "exponent")]
    pub value: f64,
    #[serde(serialize_with = "exponent")]
    pub reference: f64,
    #[serde(serialize_with = "exponent")]
    pub change: f64,
    #[serde(serialize_with = "exponent")]
    pub condition: f64,
    pub negligible: bool,
    pub overturn_flips: bool,
}

/// Numbers in check.csv read as `1e-5`, `3.2e6` (Rust's `{:e}`, which parses back exactly).
fn exponent<S: serde::Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&format!("{v:e}"))
}

impl CheckCsvRow {
    /// The header line, also written when no scene could be checked.
    pub const HEADER: [&'static str; 11] = [
        "scene",
        "verdict",
        "rtol",
        "reference_rtol",
        "quantity",
        "value",
        "reference",
        "change",
        "condition",
        "negligible",
        "overturn_flips",
    ];

    /// The rows of scene `scene`'s check, one per peak.
    pub fn rows(scene: usize, c: &Check) -> impl Iterator<Item = CheckCsvRow> + '_ {
        c.peaks.iter().map(move |p| CheckCsvRow {
            scene,
            verdict: c.verdict,
            rtol: c.rtol,
            reference_rtol: c.reference_rtol,
            quantity: p.quantity.to_string(),
            value: p.value,
            reference: p.reference,
            change: p.change,
            condition: p.condition,
            negligible: p.negligible,
            overturn_flips: c.overturn_flips,
        })
    }
}

#[cfg(test)]
mod csv_tests {
    use super::*;

    /// The header is serde's field names, and a row reads back as written (numbers in
    /// `{:e}` form, the verdict in snake_case).
    #[test]
    fn check_csv_rows_round_trip_under_their_header() {
        let row = CheckCsvRow {
            scene: 7,
            verdict: Reproducibility::IllConditioned,
            rtol: 1e-5,
            reference_rtol: 1e-8,
            quantity: "peak_rotation".into(),
            value: 0.123,
            reference: 0.125,
            change: 0.016,
            condition: 3.2e6,
            negligible: false,
            overturn_flips: true,
        };
        let mut w = csv::Writer::from_writer(Vec::new());
        w.serialize(&row).unwrap();
        let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
        let mut lines = text.lines();
        assert_eq!(lines.next(), Some(CheckCsvRow::HEADER.join(",").as_str()));
        assert_eq!(
            lines.next(),
            Some(
                "7,ill_conditioned,1e-5,1e-8,peak_rotation,1.23e-1,1.25e-1,1.6e-2,3.2e6,false,true"
            )
        );
        let back: Vec<CheckCsvRow> = csv::Reader::from_reader(text.as_bytes())
            .deserialize()
            .collect::<Result<_, _>>()
            .unwrap();
        assert_eq!(back, vec![row]);
    }
}
