//! Rows on the mechanisms §3–§5 describe around their figures: the Dirac-Delta impact's phase
//! and dissipation (Fig. 5), the clutch law's smoothing ε (Fig. 6) and re-engagement reset
//! (§4), and the engagement cycle of Figs. 9–10. The rigid block is Fig. 8's (rows_rigid).

use super::fair::{self, Relation};
use super::histories;
use super::rows_rigid::{FIG5, FIG8, fig5, one};
use super::runs::{self, col};
use super::{Measure as RowFn, Row, judged};
use crate::presets::{self, mechanistic, rigid_fig8, sequential};
use crate::scene::*;
use crate::sim::{History, SceneResult};
use std::sync::Arc;

pub const ROWS: [RowFn; 7] = [
    fig5_phase_shift,
    fig5_equivalent_dissipation,
    fig6_epsilon_distortion,
    s4_reset_needed,
    fig9_sudden_loss,
    fig9_limited_time,
    fig10_coincide,
];

/// The Fig. 5 block's history with Housner's impact (None) or a Dirac impact of width n.
fn fig5_history(width: Option<f64>) -> crate::error::Result<Arc<(SceneResult, History)>> {
    let impact = width.map_or(Impact::default(), |width| Impact::Dirac { width });
    runs::history(&fig5(impact))
}

/// The θ zero crossings (impacts) of the Fig. 5 block.
fn fig5_crossings(width: Option<f64>) -> crate::error::Result<Vec<f64>> {
    let h = fig5_history(width)?;
    Ok(histories::crossings(
        &runs::column(&h.1, col::T)?,
        &runs::column(&h.1, col::THETA)?,
    ))
}

/// The largest shift of the k-th impact time from Housner's, as a share of Housner's
/// half-cycle there (the time to its next impact).
fn phase_shift(width: f64) -> crate::error::Result<f64> {
    let (h, d) = (fig5_crossings(None)?, fig5_crossings(Some(width))?);
    Ok((0..h.len().min(d.len()).saturating_sub(1))
        .map(|k| (d[k] - h[k]).abs() / (h[k + 1] - h[k]))
        .fold(0.0, f64::max))
}

/// A phase shift a reader sees on Fig. 5's plot: a tenth of a half-cycle.
const VISIBLE_SHIFT: f64 = 0.10;

fn fig5_phase_shift() -> crate::error::Result<Row> {
    let wide = phase_shift(0.005)?;
    let j = fair::at_least(
        "largest impact-time shift / half-cycle, n = 0.005",
        wide,
        VISIBLE_SHIFT,
    )
    .on(&format!(
        "the k-th impact (θ = 0 crossing) of the Dirac model against Housner's, over the impacts both reach; {FIG5}; histories as `simulate --history` writes them"
    ))
    .with("beside: largest shift / half-cycle, n = 1e-4", phase_shift(1e-4)?)
    .with("impacts, Housner", fig5_crossings(None)?.len() as f64)
    .with("impacts, n = 0.005", fig5_crossings(Some(0.005))?.len() as f64);
    Ok(judged("fig5-phase-shift", j, ""))
}

/// The energy lost in the block's first impact after the pulse, as a share of the energy
/// before it: the structure energy at the extremes (θ̇ = 0) either side of that impact, with
/// no input and no damping between them.
fn impact_loss(width: Option<f64>) -> crate::error::Result<f64> {
    let h = fig5_history(width)?;
    let t = runs::column(&h.1, col::T)?;
    let e = runs::column(&h.1, col::E_STRUCTURE)?;
    let pulse_end = 2.0 * std::f64::consts::PI / (4.0 * presets::RIGID_P);
    let impact = histories::crossings(&t, &runs::column(&h.1, col::THETA)?)
        .into_iter()
        .find(|&x| x > pulse_end)
        .ok_or_else(|| crate::error::error!("paper: Fig. 5's block has no free impact"))?;
    let extremes = histories::crossings(&t, &runs::column(&h.1, col::THETA_DOT)?);
    let before = extremes.iter().rev().find(|&&x| x < impact);
    let after = extremes.iter().find(|&&x| x > impact);
    let (Some(&before), Some(&after)) = (before, after) else {
        crate::error::bail!("paper: no rocking extreme either side of Fig. 5's free impact");
    };
    let at = |x: f64| e[t.partition_point(|s| *s < x).min(t.len() - 1)];
    Ok(1.0 - at(after) / at(before))
}

fn fig5_equivalent_dissipation() -> crate::error::Result<Row> {
    let housner = impact_loss(None)?;
    let (sharp, wide) = (impact_loss(Some(1e-4))?, impact_loss(Some(0.005))?);
    let alpha = 10f64.to_radians();
    let j = fair::immaterial(
        &one(housner),
        &[("n = 1e-4", &one(sharp)), ("n = 0.005", &one(wide))],
    )
    .on(&format!(
        "energy lost in the first free impact over the energy before it (structure energy at the extremes either side), Dirac n = 1e-4 and 0.005 against Housner; {FIG5}; histories as `simulate --history` writes them"
    ))
    .with("Housner", housner)
    .with("Dirac n = 1e-4", sharp)
    .with("Dirac n = 0.005", wide)
    .with(
        "beside: 1 − Housner's r (Eq. 3)",
        1.0 - crate::model::rigid::housner_restitution(alpha),
    );
    Ok(judged("fig5-equivalent-dissipation", j, ""))
}

/// Eq. 19's largest negative torque over Δθ < 0, in units of kθ·rad: ½ (1 + tanh εΔθ) Δθ is
/// a function of u = εΔθ over ε, so the distortion is the u-maximum over ε (u on a fine grid).
fn distortion(epsilon: f64) -> f64 {
    (1..=100_000)
        .map(|i| -(i as f64) * 1e-4)
        .map(|u| -0.5 * (1.0 + u.tanh()) * u)
        .fold(0.0, f64::max)
        / epsilon
}

fn fig6_epsilon_distortion() -> crate::error::Result<Row> {
    let eps = [1e4, 1e5, 1e6];
    let d: Vec<f64> = eps.iter().map(|&e| distortion(e)).collect();
    let mut j = fair::compare(
        Relation::MuchLower,
        &vec![Some(d[0]), Some(d[1])],
        &vec![Some(d[1]), Some(d[2])],
    )
    .on("Eq. 19's largest negative torque over Δθ < 0 (the distortion near negative zero), each ε against the tenfold smaller one; closed form");
    for (e, x) in eps.iter().zip(&d) {
        j = j.with(format!("distortion / kθ (µrad) at ε = {e:e}"), 1e6 * x);
    }
    Ok(judged("fig6-epsilon-distortion", j, ""))
}

fn s4_reset_needed() -> crate::error::Result<Row> {
    let count = |change: fn(&mut Clutch)| -> crate::error::Result<f64> {
        let device = runs::changed(&mechanistic(), change);
        Ok(runs::result(&rigid_fig8(device))?.counters.engagements as f64)
    };
    let never: fn(&mut Clutch) = |c| c.reset = ResetRule::Never;
    let (with, without) = (count(runs::as_is)?, count(never)?);
    let j = fair::compare(Relation::MuchLower, &one(with), &one(without))
        .on(&format!(
            "engagement events without the re-engagement reset (the clutch's local coordinate never reset) against with it; {FIG8}"
        ))
        .with("engagements with the reset", with)
        .with("engagements without", without);
    Ok(judged("s4-reset-needed", j, ""))
}

/// The share of the fall of the flywheels' energy (kinetic + clutch spring) that happens at
/// instants (an event's jump) in the Fig. 8 scene with `device`.
fn sudden_share(device: Device) -> crate::error::Result<f64> {
    let h = runs::history(&rigid_fig8(device))?;
    Ok(histories::sudden_share(
        &runs::column(&h.1, col::T)?,
        &runs::column(&h.1, col::E_INERTER)?,
    ))
}

fn fig9_sudden_loss() -> crate::error::Result<Row> {
    let (seq, mech) = (sudden_share(sequential())?, sudden_share(mechanistic())?);
    let j = fair::compare(Relation::MuchLower, &one(seq), &one(mech))
        .on(&format!(
            "share of the fall of the flywheels' energy that happens at an instant (across an event's jump) rather than over time, mechanistic against sequential; {FIG8}; histories as `simulate --history` writes them"
        ))
        .with("sequential sudden share", seq)
        .with("mechanistic sudden share", mech);
    Ok(judged("fig9-sudden-loss", j, ""))
}

/// Mean time between the block's impacts (a rocking half-cycle) before and after t = 3 s,
/// mechanistic clutch.
fn half_cycles() -> crate::error::Result<(f64, f64)> {
    let h = runs::history(&rigid_fig8(mechanistic()))?;
    let impacts: Vec<f64> =
        h.1.events
            .iter()
            .filter(|(_, n)| *n == runs::IMPACT)
            .map(|(t, _)| *t)
            .collect();
    let mean_between = |late: bool| {
        let d: Vec<f64> = impacts
            .windows(2)
            .filter(|w| (w[0] >= 3.0) == late)
            .map(|w| w[1] - w[0])
            .collect();
        fair::mean(&d)
    };
    Ok((mean_between(false), mean_between(true)))
}

fn fig9_limited_time() -> crate::error::Result<Row> {
    let (before, after) = half_cycles()?;
    // The disengaged flywheel decelerates as e^{−c̄ t}: c̄ = 1 s⁻¹ (Fig. 8), time constant 1 s.
    let decay_time = 1.0;
    let j = fair::both(
        fair::compare(Relation::MuchLower, &one(before), &one(after)),
        "rocking half-cycle after 3 s against before",
        fair::compare(Relation::MuchLower, &one(decay_time), &one(after)),
        "half-cycle after 3 s against the flywheel's deceleration time 1/c̄",
    )
    .on(&format!(
        "mean time between impacts, mechanistic clutch; {FIG8}"
    ))
    .with("half-cycle before 3 s (s)", before)
    .with("half-cycle after 3 s (s)", after)
    .with(
        "beside: flywheel speed kept over a half-cycle after 3 s, e^(−c̄ T)",
        (-after / decay_time).exp(),
    );
    Ok(judged("fig9-limited-time", j, ""))
}

/// Over every contact of the Fig. 8 mechanistic clutch: the time from the velocities'
/// coincidence (ẏ − Ẋ crossing zero, interpolated) to the force peak, as a share of the
/// contact's duration.
fn peak_after_coincidence() -> crate::error::Result<(f64, usize)> {
    let h = runs::history(&rigid_fig8(mechanistic()))?;
    let t = runs::column(&h.1, col::T)?;
    let xdot = runs::column(&h.1, col::X_DOT)?;
    let mut shares = Vec::new();
    for (force, flywheel) in [
        (col::CLUTCH_A, col::FLYWHEEL_A),
        (col::CLUTCH_B, col::FLYWHEEL_B),
    ] {
        let f = runs::column(&h.1, force)?;
        let y = runs::column(&h.1, flywheel)?;
        for r in histories::contacts(&f) {
            let rel: Vec<f64> = r.clone().map(|i| y[i] - xdot[i]).collect();
            let Some(&meet) = histories::crossings(&t[r.clone()], &rel).first() else {
                continue;
            };
            let peak = r
                .clone()
                .max_by(|&i, &j| f[i].abs().total_cmp(&f[j].abs()))
                .unwrap_or(r.start);
            let duration = t[r.end - 1] - t[r.start];
            if duration > 0.0 {
                shares.push((t[peak] - meet).abs() / duration);
            }
        }
    }
    Ok((fair::mean(&shares), shares.len()))
}

/// Velocities that "coincide" at the force peak: within a tenth of the contact's duration.
const COINCIDE: f64 = 0.10;

fn fig10_coincide() -> crate::error::Result<Row> {
    let (share, contacts) = peak_after_coincidence()?;
    let j = fair::small(
        "mean over contacts of |t(force peak) − t(ẏ = Ẋ)| / contact duration",
        share,
        COINCIDE,
    )
    .on(&format!(
        "every contact of either flywheel with a velocity coincidence, mechanistic clutch (Fig. 10's A → B → C → D cycle: peak transmission B where the velocities coincide); {FIG8}; histories as `simulate --history` writes them"
    ))
    .with("contacts", contacts as f64);
    Ok(judged("fig10-coincide", j, ""))
}
