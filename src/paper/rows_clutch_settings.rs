//! Rows on the flexible structure's device (§6.3, §7, §9) that need a check of their own:
//! energy conservation (Fig. 15f), the models' similar peaks (Fig. 16), gear play's series of
//! collisions (§7.4), friction against viscous damping (Fig. 21) and the settings' ranking
//! (§9). Fig. 14's structure and spectra (rows_flexible).

use super::fair::{self, Judgement, Relation, Series};
use super::histories;
use super::rows_flexible::{FIG14, SPECTRA, friction, play, spectrum, stiffness, xi};
use super::runs::{self, Measure, col};
use super::{Measure as RowFn, Row, judged};
use crate::presets::{flexible_fig14, mechanistic, mechanistic_xi_theta, sequential};
use crate::scene::Device;
use crate::sim::{EnergyRole, HistoryColumn};

pub const ROWS: [RowFn; 5] = [
    fig15_conservation,
    fig16_similar_peaks,
    s7_series_of_collisions,
    fig21_similar_to_viscous,
    s9_damping_friction_more_significant,
];

/// The largest |input − stored − dissipated| over the history, over the final input.
fn largest_residual(device: Device) -> crate::error::Result<f64> {
    let h = runs::history(&flexible_fig14(device))?;
    let input = runs::column(&h.1, HistoryColumn::EInput)?;
    let mut residual = vec![0.0; input.len()];
    for c in HistoryColumn::ENERGY {
        let sign = match c.energy() {
            Some(EnergyRole::Input) => 1.0,
            _ => -1.0,
        };
        for (r, x) in residual.iter_mut().zip(runs::column(&h.1, c)?) {
            *r += sign * x;
        }
    }
    let scale = input.last().copied().unwrap_or(0.0).abs();
    Ok(residual.iter().fold(0.0f64, |m, r| m.max(r.abs())) / scale)
}

/// "Maintains the conservation of energy": the balance's residual a thousandth of the input.
const CONSERVED: f64 = 1e-3;

fn fig15_conservation() -> crate::error::Result<Row> {
    let j = fair::small(
        "largest |energy residual| over the history / input",
        largest_residual(mechanistic_xi_theta(0.02))?,
        CONSERVED,
    )
    .on(&format!(
        "mechanistic ξθ = 0.02 (Fig. 15f), every row of the history: input − structure − flywheels and clutch spring − everything dissipated; {FIG14}; histories as `simulate --history` writes them"
    ));
    Ok(judged("fig15-conservation", j, ""))
}

fn fig16_similar_peaks() -> crate::error::Result<Row> {
    let j = fair::immaterial(
        &spectrum(sequential(), Measure::Drift)?,
        &[("mechanistic", &spectrum(mechanistic(), Measure::Drift)?)],
    )
    .on(&format!(
        "peak drift |X|, mechanistic (c̄ = 1 s⁻¹) against sequential; {SPECTRA}"
    ));
    Ok(judged("fig16-similar-peaks", j, ""))
}

/// Of the Fig. 14 scene with `device`: the half-cycles of the structure's velocity Ẋ (between
/// its zero crossings) in which a clutch contact event falls (the events are exact; bounces
/// shorter than the resampled grid leave no row), and the share of them with three contact
/// events or more (two collisions or more: a series).
fn collision_series(device: Device) -> crate::error::Result<(f64, f64)> {
    use crate::model::device::ClutchEvent::{ContactA, ContactB};
    let h = runs::history(&flexible_fig14(device))?;
    let t = runs::column(&h.1, col::T)?;
    let mut bounds = histories::crossings(&t, &runs::column(&h.1, col::X_DOT)?);
    bounds.insert(0, f64::NEG_INFINITY);
    bounds.push(f64::INFINITY);
    let contacts: Vec<f64> =
        h.1.events
            .iter()
            .filter(|(_, n)| *n == ContactA.name() || *n == ContactB.name())
            .map(|(t, _)| *t)
            .collect();
    let per_half: Vec<usize> = bounds
        .windows(2)
        .map(|w| contacts.iter().filter(|&&s| w[0] <= s && s < w[1]).count())
        .filter(|&n| n > 0)
        .collect();
    let series = per_half.iter().filter(|&&n| n >= 3).count();
    Ok((
        per_half.len() as f64,
        series as f64 / per_half.len().max(1) as f64,
    ))
}

/// "Whenever the clutch engages": four in five of the engaging half-cycles.
const WHENEVER: f64 = 0.8;

fn s7_series_of_collisions() -> crate::error::Result<Row> {
    let (halves, share) = collision_series(play(0.01))?;
    let (_, without) = collision_series(play(0.0))?;
    let j = fair::at_least(
        "share of engaging half-cycles with three contact events or more, up = 1 cm",
        share,
        WHENEVER,
    )
    .on(&format!(
        "the half-cycles of Ẋ (between its zero crossings) with a clutch contact event, gear play up = 1 cm, ξθ = 0.02; {FIG14}; histories as `simulate --history` writes them"
    ))
    .with("engaging half-cycles, up = 1 cm", halves)
    .with("beside: the same share without play", without);
    Ok(judged("s7-series-of-collisions", j, ""))
}

/// The pointwise reduction `damped / undamped` of `m` over the spectrum.
fn reduction(undamped: &Series, damped: &Series) -> Series {
    undamped
        .iter()
        .zip(damped)
        .map(|(a, b)| match (a, b) {
            (Some(a), Some(b)) if *a > 0.0 => Some(b / a),
            _ => None,
        })
        .collect()
}

fn fig21_similar_to_viscous() -> crate::error::Result<Row> {
    let per = |m: Measure| -> crate::error::Result<Judgement> {
        let (mut viscous, mut dry) = (Vec::new(), Vec::new());
        // The paper's operational and high levels of each.
        for (x, f) in [(0.02, 0.1), (0.2, 0.2)] {
            viscous.extend(reduction(&xi(0.0, m)?, &xi(x, m)?));
            dry.extend(reduction(
                &spectrum(friction(0.0, 100.0), m)?,
                &spectrum(friction(f, 100.0), m)?,
            ));
        }
        Ok(fair::immaterial(&viscous, &[("friction", &dry)]))
    };
    let j = runs::rotation_and_deformation(per)?
    .on(&format!(
        "the pointwise reduction (damped / undamped) by friction fμ = 0.1 and 0.2 mr g (η = 100 s/rad) against the viscous ξθ = 0.02 and 0.2 (the paper's operational and high levels), one after the other on the axis; {SPECTRA}"
    ));
    let reason = if j.verdict == super::Agreement::Agrees {
        ""
    } else {
        "friction's reductions are not the viscous damping's: the friction torque brakes the flywheel whenever it spins, so at the same level it cuts the rotation far more (fig21-operational-negligible)"
    };
    Ok(judged("fig21-similar-to-viscous", j, reason))
}

/// The largest difference of `m`'s spectrum from `reference`'s, over its peak.
fn spread(reference: Device, variant: Device, m: Measure) -> crate::error::Result<f64> {
    let j = fair::immaterial(&spectrum(reference, m)?, &[("v", &spectrum(variant, m)?)]);
    Ok(j.value("v: largest difference / reference peak")?)
}

fn s9_damping_friction_more_significant() -> crate::error::Result<Row> {
    let (mut k, mut other) = (Vec::new(), Vec::new());
    let mut values = Vec::new();
    for (m, name) in [
        (Measure::Rotation, "rotation"),
        (Measure::Deformation, "deformation"),
    ] {
        let by_k = spread(stiffness(25.0), stiffness(100.0), m)?;
        let by_xi = spread(mechanistic_xi_theta(0.0), mechanistic_xi_theta(0.2), m)?;
        let by_mu = spread(friction(0.0, 100.0), friction(0.2, 100.0), m)?;
        values.push((format!("{name}: kθ 25 → 100 p"), by_k));
        values.push((format!("{name}: ξθ 0 → 0.2"), by_xi));
        values.push((format!("{name}: fμ 0 → 0.2 mr g"), by_mu));
        k.extend([Some(by_k), Some(by_k)]);
        other.extend([Some(by_xi), Some(by_mu)]);
    }
    let mut j = fair::compare(Relation::Larger, &k, &other).on(&format!(
        "the largest change of the spectrum over its peak, damping (ξθ 0 → 0.2) and friction (fμ 0 → 0.2 mr g) each against clutch stiffness (√(kθ/J) 25 → 100 p), rotation and deformation; {SPECTRA}"
    ));
    j.values.extend(values);
    Ok(judged("s9-damping-friction-more-significant", j, ""))
}
