//! Rows of §6 (Figs. 14–16) and §7 (Figs. 17–23): the flexible rocking column of Fig. 14
//! (R0 = 10 m, α = 0.2, ξ = 0.02, ωn/p = 8, one-sine A/(g tan α) = 1.5; σ = 0.5). The clutch's
//! √(kθ/J) = 25 p, ρ = 0.05 m and η = 100 s/rad are not stated by the paper (README
//! "Defaults"). Acceleration: the absolute horizontal |ẍ + a_g|max/g, the paper's for these
//! structures.

use super::fair::{self, Judgement, Relation, Series};
use super::histories;
use super::runs::{self, Measure, clutch_with, col};
use super::{Measure as RowFn, Row, explained, judged};
use crate::presets::{self, flexible_fig14, mechanistic, mechanistic_xi_theta, sequential};
use crate::scene::*;
use crate::sim::SceneResult;
use crate::study::Param;
use std::sync::Arc;

pub const ROWS: [RowFn; 28] = [
    fig14_inerter_uplift,
    fig14_inerter_deformation,
    fig14_inerter_acceleration,
    fig14_clutch_further,
    fig14_clutch_deformation,
    fig14_quick_rest,
    fig14_clutch_acceleration,
    fig15_inerter_returns,
    fig15_clutch_prevents,
    fig15_damping_improves,
    fig15_xi_similar,
    fig16_rocking_dominated,
    fig16_limited_deformation,
    fig16_acceleration_most,
    fig17_judder,
    fig17_soft_delay,
    fig18_not_determinant,
    fig19_operational_immaterial,
    fig19_halves,
    fig19_overturning_stiffer,
    fig19_deformation_less,
    fig19_full_range,
    fig21_operational_negligible,
    fig21_strong_reduces,
    fig21_eliminates_rocking,
    fig22_first_engagement,
    fig23_play_unnoticeable,
    s9_play_acceleration,
];

pub(super) const FIG14: &str = "Fig. 14 scene (R0 = 10 m, α = 0.2, ξ = 0.02, ωn/p = 8, A/(g tan α) = 1.5, ωg/p = 8, 30 s; σ = 0.5; clutch and dissipative inerter c̄ = 1 s⁻¹)";

/// The Fig. 14 scene's peak `m` with `device`, as a one-point series.
fn fig14(device: Device, m: Measure) -> crate::error::Result<Series> {
    Ok(vec![m.of(&*runs::result(&flexible_fig14(device))?)])
}

/// Several devices' one-point series stacked (each claim about "clutches" covers both).
fn fig14_many(devices: &[Device], m: Measure) -> crate::error::Result<Series> {
    let mut v = Vec::new();
    for d in devices {
        v.extend(fig14(d.clone(), m)?);
    }
    Ok(v)
}

pub(super) fn clutches() -> [Device; 2] {
    [sequential(), mechanistic()]
}

/// The single inerter against the bare structure in the Fig. 14 scene.
fn inerter_against_bare(relation: Relation, m: Measure) -> crate::error::Result<Judgement> {
    Ok(fair::compare(
        relation,
        &fig14(Device::None, m)?,
        &fig14(presets::inerter(), m)?,
    ))
}

fn fig14_inerter_uplift() -> crate::error::Result<Row> {
    let j = inerter_against_bare(Relation::MuchLower, Measure::Rotation)?.on(&format!(
        "θmax/α, single inerter (no dissipation) against bare; {FIG14}"
    ));
    Ok(judged("fig14-inerter-uplift", j, ""))
}

fn fig14_inerter_deformation() -> crate::error::Result<Row> {
    let j = fair::immaterial(
        &fig14(Device::None, Measure::Deformation)?,
        &[("inerter", &fig14(presets::inerter(), Measure::Deformation)?)],
    )
    .on(&format!("peak |u|, single inerter against bare; {FIG14}"));
    Ok(judged("fig14-inerter-deformation", j, ""))
}

fn fig14_inerter_acceleration() -> crate::error::Result<Row> {
    let j = inerter_against_bare(Relation::Lower, Measure::Acceleration)?.on(&format!(
        "|ẍ + a_g|max/g, single inerter against bare; {FIG14}"
    ));
    Ok(judged("fig14-inerter-acceleration", j, ""))
}

/// Each clutch (sequential, mechanistic) against the single inerter in the Fig. 14 scene.
fn clutches_against_single(relation: Relation, m: Measure) -> crate::error::Result<Judgement> {
    let single = [presets::inerter(), presets::inerter()];
    Ok(fair::compare(
        relation,
        &fig14_many(&single, m)?,
        &fig14_many(&clutches(), m)?,
    ))
}

fn fig14_clutch_further() -> crate::error::Result<Row> {
    let j = fair::both(
        clutches_against_single(Relation::Lower, Measure::Rotation)?,
        "rotation",
        clutches_against_single(Relation::Lower, Measure::Drift)?,
        "drift",
    )
    .on(&format!(
        "sequential and mechanistic each against the single inerter; {FIG14}"
    ));
    Ok(judged("fig14-clutch-further", j, ""))
}

fn fig14_clutch_deformation() -> crate::error::Result<Row> {
    let j = clutches_against_single(Relation::SlightlyLower, Measure::Deformation)?.on(&format!(
        "peak |u|, sequential and mechanistic each against the single inerter; {FIG14}"
    ));
    Ok(judged("fig14-clutch-deformation", j, ""))
}

/// (t, θ) of a flexible scene's history (as `simulate --history` writes it).
fn theta(scene: &Scene) -> crate::error::Result<(Vec<f64>, Vec<f64>)> {
    let h = runs::history(scene)?;
    Ok((runs::column(&h.1, col::T)?, runs::column(&h.1, col::THETA)?))
}

fn fig14_quick_rest() -> crate::error::Result<Row> {
    let single = theta(&flexible_fig14(presets::inerter()))?;
    let decay = |d: Device| -> crate::error::Result<Judgement> {
        let c = theta(&flexible_fig14(d))?;
        Ok(fair::faster_decrease((&c.0, &c.1), (&single.0, &single.1)))
    };
    let j = fair::both(
        decay(sequential())?,
        "sequential",
        decay(mechanistic())?,
        "mechanistic",
    )
    .on(&format!("each clutch (claimed faster) against the single inerter, uplift θ; {FIG14}; histories as `simulate --history` writes them"));
    Ok(judged("fig14-quick-rest", j, ""))
}

fn fig14_clutch_acceleration() -> crate::error::Result<Row> {
    let j = clutches_against_single(Relation::Larger, Measure::Acceleration)?.on(&format!(
        "|ẍ + a_g|max/g, sequential and mechanistic each against the single inerter; {FIG14}"
    ));
    Ok(judged("fig14-clutch-acceleration", j, ""))
}

fn returned(device: Device) -> crate::error::Result<f64> {
    runs::returned_fraction(&flexible_fig14(device))
}

fn fig15_inerter_returns() -> crate::error::Result<Row> {
    let j = fair::both(
        fair::energy_back(returned(presets::inerter())?, true),
        "inerter",
        fair::energy_back(returned(presets::inerter_with_dissipation())?, true),
        "inerter c̄ = 1",
    )
    .on(&format!(
        "{FIG14}; histories as `simulate --history` writes them"
    ));
    Ok(judged("fig15-inerter-returns", j, ""))
}

fn fig15_clutch_prevents() -> crate::error::Result<Row> {
    let j = fair::both(
        fair::energy_back(returned(sequential())?, false),
        "sequential",
        fair::energy_back(returned(mechanistic())?, false),
        "mechanistic",
    )
    .on(&format!(
        "{FIG14}; histories as `simulate --history` writes them"
    ));
    Ok(judged("fig15-clutch-prevents", j, ""))
}

/// Structure energy left at the end over the input, the measure of "energy dissipation" a
/// reader sees in Fig. 15a.
fn structure_energy_left(device: Device) -> crate::error::Result<Series> {
    let r = runs::result(&flexible_fig14(device))?;
    Ok(vec![Some(r.energy.structure / r.energy.input)])
}

fn fig15_damping_improves() -> crate::error::Result<Row> {
    let j = fair::compare(
        Relation::Lower,
        &structure_energy_left(presets::inerter())?,
        &structure_energy_left(presets::inerter_with_dissipation())?,
    )
    .on(&format!(
        "energy left in the structure at the end over the input, single inerter with c̄ = 1 s⁻¹ against without; {FIG14}"
    ))
    .with("returned / taken without", returned(presets::inerter())?)
    .with("returned / taken with", returned(presets::inerter_with_dissipation())?);
    Ok(judged("fig15-damping-improves", j, ""))
}

/// Energy dissipated in the device by the end over the input.
fn device_share(device: Device) -> crate::error::Result<Series> {
    let r = runs::result(&flexible_fig14(device))?;
    let e = &r.energy;
    Ok(vec![Some(
        (e.device_damping + e.friction + e.disengagement + e.reset) / e.input,
    )])
}

fn fig15_xi_similar() -> crate::error::Result<Row> {
    let j = fair::immaterial(
        &device_share(sequential())?,
        &[("mechanistic ξθ = 0.02", &device_share(mechanistic_xi_theta(0.02))?)],
    )
    .on(&format!(
        "energy dissipated in the device by the end over the input, mechanistic ξθ = 0.02 against sequential; {FIG14}"
    ))
    .with("sequential", device_share(sequential())?[0].unwrap_or(f64::NAN))
    .with("mechanistic ξθ = 0.02", device_share(mechanistic_xi_theta(0.02))?[0].unwrap_or(f64::NAN));
    Ok(judged("fig15-xi-similar", j, ""))
}

pub(super) const SPECTRA: &str = "Fig. 14's structure, ωg/p = 3…20 step 1, 15 s";

pub(super) fn spectrum(device: Device, m: Measure) -> crate::error::Result<Series> {
    Ok(m.series(&runs::flexible_spectrum(device)?))
}

fn stacked(devices: &[Device], m: Measure) -> crate::error::Result<Series> {
    let mut v = Vec::new();
    for d in devices {
        v.extend(spectrum(d.clone(), m)?);
    }
    Ok(v)
}

fn fig16_rocking_dominated() -> crate::error::Result<Row> {
    let h = presets::FLEXIBLE_R0 * presets::FLEXIBLE_ALPHA.cos();
    let devices = [Device::None, sequential(), mechanistic()];
    let drift = stacked(&devices, Measure::Drift)?;
    let elastic: Series = stacked(&devices, Measure::Deformation)?
        .iter()
        .map(|u| u.map(|u| u / h))
        .collect();
    let j = fair::compare(Relation::MuchLower, &drift, &elastic).on(&format!(
        "the elastic part of the drift, peak |u|/H, against the peak drift |X|/H (H = R0 cos α), bare, sequential and mechanistic; {SPECTRA}"
    ));
    Ok(judged("fig16-rocking-dominated", j, ""))
}

fn fig16_limited_deformation() -> crate::error::Result<Row> {
    let bare = stacked(&[Device::None, Device::None], Measure::Deformation)?;
    let j = fair::compare(
        Relation::SlightlyLower,
        &bare,
        &stacked(&clutches(), Measure::Deformation)?,
    )
    .on(&format!(
        "peak |u|, sequential and mechanistic (c̄ = 1 s⁻¹) each against bare; {SPECTRA}"
    ));
    Ok(judged("fig16-limited-deformation", j, ""))
}

fn fig16_acceleration_most() -> crate::error::Result<Row> {
    let j = fair::compare(
        Relation::Larger,
        &spectrum(sequential(), Measure::Acceleration)?,
        &spectrum(mechanistic(), Measure::Acceleration)?,
    )
    .on(&format!(
        "|ẍ + a_g|max/g, mechanistic (c̄ = 1 s⁻¹) against sequential; {SPECTRA}"
    ));
    Ok(judged("fig16-acceleration-most", j, ""))
}

pub(super) fn stiffness(k: f64) -> Device {
    clutch_with(|c| c.stiffness = ClutchStiffness::FrequencyRatio(k))
}

/// Of the Fig. 14 scene's history with `device`, over every contact of either flywheel: the
/// velocity mismatch rms(ẏ − Ẋ) / rms(Ẋ) (juddering: the flywheel not following the
/// structure while engaged), and the mean disengagement delay, from the contact's force peak
/// (where the two velocities coincide, Fig. 10 B) to separation (C).
fn contact_motion(device: Device) -> crate::error::Result<(f64, f64)> {
    let h = runs::history(&flexible_fig14(device))?;
    let t = runs::column(&h.1, col::T)?;
    let xdot = runs::column(&h.1, col::X_DOT)?;
    let (mut mismatch, mut speed, mut delays) = (0.0, 0.0, Vec::new());
    for (force, flywheel) in [
        (col::CLUTCH_A, col::FLYWHEEL_A),
        (col::CLUTCH_B, col::FLYWHEEL_B),
    ] {
        let f = runs::column(&h.1, force)?;
        let y = runs::column(&h.1, flywheel)?;
        for r in histories::contacts(&f) {
            for i in r.clone() {
                mismatch += (y[i] - xdot[i]).powi(2);
                speed += xdot[i].powi(2);
            }
            let peak = r
                .clone()
                .max_by(|&i, &j| f[i].abs().total_cmp(&f[j].abs()))
                .unwrap_or(r.start);
            delays.push(t[r.end - 1] - t[peak]);
        }
    }
    Ok(((mismatch / speed).sqrt(), fair::mean(&delays)))
}

const STIFFNESSES: [f64; 3] = [25.0, 50.0, 100.0];

/// The clutch stiffness is the variable of the §7.1 claims: the other unstated settings vary.
fn unstated_but_stiffness() -> Vec<runs::Unstated> {
    runs::UNSTATED
        .iter()
        .filter(|u| u.param != Some(Param::ClutchFrequencyRatio))
        .copied()
        .collect()
}

/// A §7.1 claim on the contact motion at 25, 50 and 100 p: `pick` reads (mismatch, delay);
/// the stiffest against the softest by `relation`.
fn stiffness_row(
    id: &'static str,
    relation: Relation,
    what: &str,
    pick: fn((f64, f64)) -> f64,
    finding: &str,
) -> crate::error::Result<Row> {
    let check = |change: fn(&mut Clutch)| -> crate::error::Result<Judgement> {
        let at: Vec<f64> = STIFFNESSES
            .iter()
            .map(|&k| Ok(pick(contact_motion(runs::changed(&stiffness(k), change))?)))
            .collect::<crate::error::Result<_>>()?;
        let mut j = fair::compare(relation, &vec![Some(at[0])], &vec![Some(at[2])]).on(&format!(
            "{what}, √(kθ/J) = 100 p against 25 p (the paper gives no kθ); {FIG14}; histories as `simulate --history` writes them"
        ));
        for (k, x) in STIFFNESSES.iter().zip(&at) {
            j = j.with(format!("at {k} p"), *x);
        }
        Ok(j)
    };
    explained(&unstated_but_stiffness(), id, finding, check)
}

fn fig17_judder() -> crate::error::Result<Row> {
    stiffness_row(
        "fig17-judder",
        Relation::Lower,
        "velocity mismatch while engaged, rms(flywheel − structure velocity) / rms(structure velocity) over every contact (juddering = the flywheel not following)",
        |(mismatch, _)| mismatch,
        "the stiffer clutch does not follow the structure more closely; ",
    )
}

fn fig17_soft_delay() -> crate::error::Result<Row> {
    stiffness_row(
        "fig17-soft-delay",
        Relation::Lower,
        "disengagement delay: mean time from a contact's force peak (velocities coincide) to separation",
        |(_, delay)| delay,
        "the softer clutch does not separate later; ",
    )
}

fn fig18_not_determinant() -> crate::error::Result<Row> {
    let at = |k: f64, m: Measure| {
        spectrum(
            clutch_with(|c| c.stiffness = ClutchStiffness::FrequencyRatio(k)),
            m,
        )
    };
    let per = |m: Measure| -> crate::error::Result<Judgement> {
        Ok(fair::immaterial(
            &at(25.0, m)?,
            &[("50 p", &at(50.0, m)?), ("100 p", &at(100.0, m)?)],
        ))
    };
    let j = runs::rotation_and_deformation(per)?.on(&format!(
        "√(kθ/J) = 50 and 100 p against 25 p (the paper gives no kθ), c̄ = 1 s⁻¹ held; {SPECTRA}"
    ));
    Ok(judged("fig18-not-determinant", j, ""))
}

pub(super) fn xi(x: f64, m: Measure) -> crate::error::Result<Series> {
    spectrum(mechanistic_xi_theta(x), m)
}

fn fig19_operational_immaterial() -> crate::error::Result<Row> {
    let xs = runs::flexible_axis();
    let (a, b) = (xi(0.0, Measure::Rotation)?, xi(0.02, Measure::Rotation)?);
    let worst = (0..xs.len())
        .filter_map(|i| Some(((a[i]? - b[i]?).abs(), xs[i])))
        .fold((0.0, f64::NAN), |a, b| if b.0 > a.0 { b } else { a });
    explained(
        &runs::unstated_but_damping(),
        "fig19-operational-immaterial",
        &format!(
            "the largest rotation difference is at ωg/p = {} (ξθ sets c̄ = 2 ξθ √(kθ/J), so the damping grows with the unstated kθ); ",
            worst.1
        ),
        |change| {
            let at =
                |x: f64, m: Measure| spectrum(runs::changed(&mechanistic_xi_theta(x), change), m);
            let per = |m: Measure| -> crate::error::Result<Judgement> {
                Ok(fair::immaterial(
                    &at(0.0, m)?,
                    &[("ξθ = 0.02", &at(0.02, m)?)],
                ))
            };
            Ok(runs::rotation_and_deformation(per)?
                .on(&format!("ξθ = 0.02 against ξθ = 0; {SPECTRA}"))
                .with("ωg/p of the largest rotation difference", worst.1))
        },
    )
}

fn fig19_halves() -> crate::error::Result<Row> {
    let xs = runs::flexible_axis();
    let near5: Vec<usize> = (0..xs.len())
        .filter(|&i| (4.0..=6.0).contains(&xs[i]))
        .collect();
    let pick = |s: Series| -> Series { near5.iter().map(|&i| s[i]).collect() };
    let j = fair::compare(
        Relation::Halved,
        &pick(xi(0.02, Measure::Rotation)?),
        &pick(xi(0.2, Measure::Rotation)?),
    )
    .on(&format!(
        "θmax/α, ξθ = 0.2 against ξθ = 0.02 at ωg/p = 4, 5, 6; {SPECTRA}"
    ));
    Ok(judged("fig19-halves", j, ""))
}

fn fig19_overturning_stiffer() -> crate::error::Result<Row> {
    // Overturning needs long pulses: this row's axis is ωg/p = 1…3 (step 0.5).
    let xs = runs::grid(1.0, 3.0, 0.5);
    let overturned = |x: f64, wn: f64| -> crate::error::Result<f64> {
        Ok(
            runs::flexible_spectrum_on(mechanistic_xi_theta(x), wn, &xs)?
                .iter()
                .filter(|r| r.overturned)
                .count() as f64,
        )
    };
    let (mut a, mut b) = (Vec::new(), Vec::new());
    let mut j_values = Vec::new();
    for wn in [8.0, 16.0, 32.0] {
        let (lo, hi) = (overturned(0.02, wn)?, overturned(0.2, wn)?);
        j_values.push((format!("ωn/p = {wn}: overturned with ξθ = 0.02"), lo));
        j_values.push((format!("ωn/p = {wn}: overturned with ξθ = 0.2"), hi));
        if wn > 8.0 {
            a.push(Some(lo));
            b.push(Some(hi));
        }
    }
    let mut j = fair::compare(Relation::Lower, &a, &b).on(
        "overturned scenes, ξθ = 0.2 against 0.02, for stiffer columns ωn/p = 16 and 32 (Fig. 14's structure otherwise, ωg/p = 1…3 step 0.5, 15 s)",
    );
    j.values.extend(j_values);
    let reason = if j.verdict == super::Agreement::Untestable {
        "no stiffer column overturns with ξθ = 0.02 at this amplitude (A/(g tan α) = 1.5) even for ωg/p down to 1, so there is no overturning to reduce; the paper does not state which stiffer structures overturn"
    } else {
        ""
    };
    Ok(judged("fig19-overturning-stiffer", j, reason))
}

fn fig19_deformation_less() -> crate::error::Result<Row> {
    let rot = fair::ratios(&xi(0.02, Measure::Rotation)?, &xi(0.2, Measure::Rotation)?);
    let def = fair::ratios(
        &xi(0.02, Measure::Deformation)?,
        &xi(0.2, Measure::Deformation)?,
    );
    let j = fair::both(
        fair::compare(
            Relation::Lower,
            &xi(0.02, Measure::Deformation)?,
            &xi(0.2, Measure::Deformation)?,
        ),
        "deformation reduced",
        fair::compare(
            Relation::Lower,
            &vec![Some(fair::mean(&def))],
            &vec![Some(fair::mean(&rot))],
        ),
        "rotation reduced more (mean ratio of ratios)",
    )
    .on(&format!("ξθ = 0.2 against ξθ = 0.02; {SPECTRA}"));
    Ok(judged("fig19-deformation-less", j, ""))
}

fn fig19_full_range() -> crate::error::Result<Row> {
    let per = |m: Measure| -> crate::error::Result<Judgement> {
        Ok(fair::compare(
            Relation::LowerEverywhere,
            &xi(0.02, m)?,
            &xi(0.2, m)?,
        ))
    };
    let j = runs::rotation_and_deformation(per)?.on(&format!(
        "ξθ = 0.2 below ξθ = 0.02 at every ωg/p; {SPECTRA}"
    ));
    Ok(judged("fig19-full-range", j, ""))
}

/// §7.3: friction fμ (× mr g) replaces the viscous term.
pub(super) fn friction(f: f64, eta: f64) -> Device {
    clutch_with(|c| {
        c.damping = Damping::CBar(0.0);
        c.friction = f;
        c.eta = eta;
    })
}

fn negligible(f: f64, eta: f64) -> crate::error::Result<Judgement> {
    let per = |m: Measure| -> crate::error::Result<Judgement> {
        Ok(fair::immaterial(
            &spectrum(friction(0.0, eta), m)?,
            &[("friction", &spectrum(friction(f, eta), m)?)],
        ))
    };
    runs::rotation_and_deformation(per)
}

fn fig21_operational_negligible() -> crate::error::Result<Row> {
    let mut j = negligible(0.1, 100.0)?.on(&format!(
        "fμ = 0.1 mr g (the paper's lower, 'operational' level) against fμ = 0, no viscous damping, η = 100 s/rad (not stated by the paper); {SPECTRA}"
    ));
    let mut variants = Vec::new();
    for f in [0.01, 0.02, 0.05] {
        variants.push((format!("fμ = {f} mr g"), negligible(f, 100.0)?));
    }
    for eta in [10.0, 1000.0] {
        variants.push((
            format!("fμ = 0.1 mr g, η = {eta} s/rad"),
            negligible(0.1, eta)?,
        ));
    }
    let (sens, values) = fair::sensitivity("fμ and the unstated η", &variants);
    j.values.extend(values);
    let reason = format!(
        "fμ = 0.1 mr g is not an operational level in this model: the friction torque acts whenever the flywheel spins, so it brakes the flywheel between engagements like a strong damper; {sens}"
    );
    Ok(judged("fig21-operational-negligible", j, reason))
}

fn fig21_strong_reduces() -> crate::error::Result<Row> {
    let per = |m: Measure| -> crate::error::Result<Judgement> {
        Ok(fair::compare(
            Relation::MuchLower,
            &spectrum(friction(0.0, 100.0), m)?,
            &spectrum(friction(0.2, 100.0), m)?,
        ))
    };
    let j = runs::rotation_and_deformation(per)?.on(&format!(
        "fμ = 0.2 mr g against fμ = 0, no viscous damping, η = 100 s/rad; {SPECTRA}"
    ));
    Ok(judged("fig21-strong-reduces", j, ""))
}

fn rocks(rs: &[Arc<SceneResult>]) -> Series {
    rs.iter()
        .map(|r| Some(if r.counters.uplifts > 0 { 1.0 } else { 0.0 }))
        .collect()
}

fn fig21_eliminates_rocking() -> crate::error::Result<Row> {
    let xs = runs::flexible_axis();
    let free = rocks(&runs::flexible_spectrum(friction(0.0, 100.0))?);
    let strong = rocks(&runs::flexible_spectrum(friction(0.2, 100.0))?);
    let mut j = fair::compare(Relation::LowerSomewhere, &free, &strong).on(&format!(
        "uplift (1) or none (0) with fμ = 0.2 mr g against fμ = 0 at each ωg/p (the frictionless clutch no longer rocks above ωg/p ≈ 15); {SPECTRA}"
    ));
    for (i, x) in xs.iter().enumerate() {
        if free[i] == Some(1.0) && strong[i] == Some(0.0) {
            j = j.with(format!("rocking eliminated at ωg/p = {x}"), *x);
        }
    }
    Ok(judged("fig21-eliminates-rocking", j, ""))
}

pub(super) fn play(up: f64) -> Device {
    clutch_with(|c| {
        c.damping = Damping::XiTheta(0.02);
        c.play = up;
    })
}

/// Fig. 22's window: the claim is about the response just after the clutch first engages, so
/// the spike is looked for from the first clutch contact to this many seconds after it.
pub const FIRST_ENGAGEMENT_WINDOW: f64 = 0.1;

/// The largest |dω/dt| of the flywheel that engages first (finite differences of the resampled
/// history, event row pairs at one instant skipped) within `[t0, t1]`.
fn flywheel_acceleration(t: &[f64], w: &[f64], t0: f64, t1: f64) -> f64 {
    (1..t.len())
        .filter(|&i| t[i - 1] >= t0 && t[i] <= t1 && t[i] - t[i - 1] > 1e-9)
        .map(|i| ((w[i] - w[i - 1]) / (t[i] - t[i - 1])).abs())
        .fold(0.0, f64::max)
}

/// Of the Fig. 14 scene with `device`: the first clutch contact's time, the largest flywheel
/// |dω/dt| in [`FIRST_ENGAGEMENT_WINDOW`] after it, and the largest over the whole run.
fn first_engagement(device: Device) -> crate::error::Result<(f64, f64, f64)> {
    let h = runs::history(&flexible_fig14(device))?;
    let (at, flywheel) =
        h.1.events
            .iter()
            .find_map(|(t, n)| {
                use crate::model::device::ClutchEvent::{ContactA, ContactB};
                [(ContactA, col::FLYWHEEL_A), (ContactB, col::FLYWHEEL_B)]
                    .into_iter()
                    .find(|(e, _)| e.name() == *n)
                    .map(|(_, c)| (*t, c))
            })
            .ok_or_else(|| {
                crate::error::error!("paper: the clutch never engages in Fig. 22's scene")
            })?;
    let t = runs::column(&h.1, col::T)?;
    let w = runs::column(&h.1, flywheel)?;
    Ok((
        at,
        flywheel_acceleration(&t, &w, at, at + FIRST_ENGAGEMENT_WINDOW),
        flywheel_acceleration(&t, &w, f64::NEG_INFINITY, f64::INFINITY),
    ))
}

fn fig22_first_engagement() -> crate::error::Result<Row> {
    let (t_smooth, smooth, smooth_all) = first_engagement(play(0.0))?;
    let (t_play, spike, spike_all) = first_engagement(play(0.01))?;
    let j = fair::compare(Relation::MarkedlyLarger, &vec![Some(smooth)], &vec![Some(spike)])
        .on(&format!(
            "largest |dω/dt| of the flywheel that engages first, from its first clutch contact to {FIRST_ENGAGEMENT_WINDOW} s after (the resampled history), up = 1 cm against none (ξθ = 0.02); {FIG14}"
        ))
        .with("first contact, up = 1 cm (s)", t_play)
        .with("first contact, no play (s)", t_smooth)
        .with("window peak, up = 1 cm", spike)
        .with("window peak, no play", smooth)
        .with("beside: whole-run peak, up = 1 cm", spike_all)
        .with("beside: whole-run peak, no play", smooth_all);
    Ok(judged("fig22-first-engagement", j, ""))
}

fn fig23_play_unnoticeable() -> crate::error::Result<Row> {
    let per = |m: Measure| -> crate::error::Result<Judgement> {
        Ok(fair::immaterial(
            &spectrum(play(0.0), m)?,
            &[("up = 1 cm", &spectrum(play(0.01), m)?)],
        ))
    };
    let j = runs::rotation_and_deformation(per)?.on(&format!(
        "gear play up = 1 cm against none, ξθ = 0.02, paper reset rule; {SPECTRA}"
    ));
    Ok(judged("fig23-play-unnoticeable", j, ""))
}

fn s9_play_acceleration() -> crate::error::Result<Row> {
    let j = fair::compare(
        Relation::MarkedlyLarger,
        &spectrum(play(0.0), Measure::Acceleration)?,
        &spectrum(play(0.01), Measure::Acceleration)?,
    )
    .on(&format!(
        "|ẍ + a_g|max/g, gear play up = 1 cm against none, ξθ = 0.02; {SPECTRA}"
    ));
    Ok(judged("s9-play-acceleration", j, ""))
}
