//! The flexible-column rows (Figs. 14–23, §9) recomputed (see paper_rows.rs).

use crate::paper_rows::*;
use rocklab::model::device::ClutchEvent::{ContactA, ContactB};
use rocklab::paper::{Agreement, runs::col};
use rocklab::presets::{
    self, flexible_fig14, inerter, inerter_with_dissipation, mechanistic, mechanistic_xi_theta,
    sequential,
};
use rocklab::scene::{Clutch, ClutchStiffness, Damping, Device, Scene};
use rocklab::sim::SceneResult;
use std::sync::Arc;

pub const TABLE: [Entry; 28] = [
    ("fig14-inerter-uplift", fig14_inerter_uplift),
    ("fig14-inerter-deformation", fig14_inerter_deformation),
    ("fig14-inerter-acceleration", fig14_inerter_acceleration),
    ("fig14-clutch-further", fig14_clutch_further),
    ("fig14-clutch-deformation", fig14_clutch_deformation),
    ("fig14-quick-rest", fig14_quick_rest),
    ("fig14-clutch-acceleration", fig14_clutch_acceleration),
    ("fig15-inerter-returns", fig15_inerter_returns),
    ("fig15-clutch-prevents", fig15_clutch_prevents),
    ("fig15-damping-improves", fig15_damping_improves),
    ("fig15-xi-similar", fig15_xi_similar),
    ("fig16-rocking-dominated", fig16_rocking_dominated),
    ("fig16-limited-deformation", fig16_limited_deformation),
    ("fig16-acceleration-most", fig16_acceleration_most),
    ("fig17-judder", fig17_judder),
    ("fig17-soft-delay", fig17_soft_delay),
    ("fig18-not-determinant", fig18_not_determinant),
    ("fig19-operational-immaterial", fig19_operational_immaterial),
    ("fig19-halves", fig19_halves),
    ("fig19-overturning-stiffer", fig19_overturning_stiffer),
    ("fig19-deformation-less", fig19_deformation_less),
    ("fig19-full-range", fig19_full_range),
    ("fig21-operational-negligible", fig21_operational_negligible),
    ("fig21-strong-reduces", fig21_strong_reduces),
    ("fig21-eliminates-rocking", fig21_eliminates_rocking),
    ("fig22-first-engagement", fig22_first_engagement),
    ("fig23-play-unnoticeable", fig23_play_unnoticeable),
    ("s9-play-acceleration", s9_play_acceleration),
];

pub type M = fn(&SceneResult) -> Option<f64>;

pub fn fig14(device: Device) -> Arc<SceneResult> {
    result(&flexible_fig14(device))
}

/// The Fig. 14 scene's measure `m` for each device, one point each.
fn at14(devices: &[Device], m: M) -> S {
    devices.iter().map(|d| m(&fig14(d.clone()))).collect()
}

fn clutches() -> [Device; 2] {
    [sequential(), mechanistic()]
}

fn fig14_inerter_uplift() -> Expect {
    compare(
        Claim::MuchLower,
        &at14(&[Device::None], rot),
        &at14(&[inerter()], rot),
    )
}

fn fig14_inerter_deformation() -> Expect {
    immaterial(
        &at14(&[Device::None], deformation),
        &[("inerter", &at14(&[inerter()], deformation))],
    )
}

fn fig14_inerter_acceleration() -> Expect {
    compare(
        Claim::Lower,
        &at14(&[Device::None], horizontal),
        &at14(&[inerter()], horizontal),
    )
}

/// Each clutch against the single inerter in the Fig. 14 scene.
fn against_single(claim: Claim, m: M) -> Expect {
    compare(
        claim,
        &at14(&[inerter(), inerter()], m),
        &at14(&clutches(), m),
    )
}

fn fig14_clutch_further() -> Expect {
    both(
        against_single(Claim::Lower, rot),
        "rotation",
        against_single(Claim::Lower, drift),
        "drift",
    )
}

fn fig14_clutch_deformation() -> Expect {
    against_single(Claim::SlightlyLower, deformation)
}

fn theta(device: Device) -> (Vec<f64>, Vec<f64>) {
    let h = history(&flexible_fig14(device));
    (column(&h, col::T), column(&h, col::THETA))
}

fn fig14_quick_rest() -> Expect {
    let single = theta(inerter());
    both(
        faster(&theta(sequential()), &single),
        "sequential",
        faster(&theta(mechanistic()), &single),
        "mechanistic",
    )
}

fn fig14_clutch_acceleration() -> Expect {
    against_single(Claim::Larger, horizontal)
}

fn back(device: Device) -> f64 {
    returned(&flexible_fig14(device))
}

fn fig15_inerter_returns() -> Expect {
    both(
        energy_back(back(inerter()), true),
        "inerter",
        energy_back(back(inerter_with_dissipation()), true),
        "inerter c̄ = 1",
    )
}

fn fig15_clutch_prevents() -> Expect {
    both(
        energy_back(back(sequential()), false),
        "sequential",
        energy_back(back(mechanistic()), false),
        "mechanistic",
    )
}

fn fig15_damping_improves() -> Expect {
    let left = |d: Device| {
        let r = fig14(d);
        one(r.energy.structure / r.energy.input)
    };
    compare(
        Claim::Lower,
        &left(inerter()),
        &left(inerter_with_dissipation()),
    )
    .with("returned / taken without", back(inerter()))
    .with("returned / taken with", back(inerter_with_dissipation()))
}

fn fig15_xi_similar() -> Expect {
    let share = |d: Device| {
        let e = fig14(d).energy;
        (e.device_damping + e.friction + e.disengagement + e.reset) / e.input
    };
    let (s, m) = (share(sequential()), share(mechanistic_xi_theta(0.02)));
    immaterial(&one(s), &[("mechanistic ξθ = 0.02", &one(m))])
        .with("sequential", s)
        .with("mechanistic ξθ = 0.02", m)
}

/// §7's spectra: Fig. 14's structure with the column at ωn/p, ωg/p over `xs`, 15 s.
fn spectrum_on(device: Device, omega_n_p: f64, xs: &[f64]) -> Vec<Arc<SceneResult>> {
    let scene = Scene {
        duration: 15.0,
        structure: presets::flexible_structure(omega_n_p * presets::flexible_p()),
        ..flexible_fig14(device)
    };
    sweep(&scene, xs)
}

fn xs() -> Vec<f64> {
    axis(3.0, 20.0, 1.0)
}

pub fn spectrum(device: Device, m: M) -> S {
    series(&spectrum_on(device, 8.0, &xs()), m)
}

fn stacked(devices: &[Device], m: M) -> S {
    devices
        .iter()
        .flat_map(|d| spectrum(d.clone(), m))
        .collect()
}

fn fig16_rocking_dominated() -> Expect {
    let h = presets::FLEXIBLE_R0 * presets::FLEXIBLE_ALPHA.cos();
    let devices = [Device::None, sequential(), mechanistic()];
    let elastic: S = stacked(&devices, deformation)
        .into_iter()
        .map(|u| u.map(|u| u / h))
        .collect();
    compare(Claim::MuchLower, &stacked(&devices, drift), &elastic)
}

fn fig16_limited_deformation() -> Expect {
    compare(
        Claim::SlightlyLower,
        &stacked(&[Device::None, Device::None], deformation),
        &stacked(&clutches(), deformation),
    )
}

fn fig16_acceleration_most() -> Expect {
    compare(
        Claim::Larger,
        &spectrum(sequential(), horizontal),
        &spectrum(mechanistic(), horizontal),
    )
}

pub fn clutch(f: impl FnOnce(&mut Clutch)) -> Device {
    let mut c = Clutch::paper_default(presets::SIGMA);
    f(&mut c);
    Device::Mechanistic(c)
}

pub fn stiffness(k: f64) -> Device {
    clutch(|c| c.stiffness = ClutchStiffness::FrequencyRatio(k))
}

/// Over every contact of either flywheel in the Fig. 14 scene: rms(ẏ − Ẋ) / rms(Ẋ), and the
/// mean time from the force peak to the contact's last row.
fn contact_motion(device: Device) -> (f64, f64) {
    let h = history(&flexible_fig14(device));
    let (t, v) = (column(&h, col::T), column(&h, col::X_DOT));
    let (mut num, mut den, mut delays) = (0.0, 0.0, Vec::new());
    for (fc, yc) in [
        (col::CLUTCH_A, col::FLYWHEEL_A),
        (col::CLUTCH_B, col::FLYWHEEL_B),
    ] {
        let (f, y) = (column(&h, fc), column(&h, yc));
        for (a, b) in contacts(&f) {
            for i in a..=b {
                num += (y[i] - v[i]) * (y[i] - v[i]);
                den += v[i] * v[i];
            }
            delays.push(t[b] - t[peak_row(&f, a, b)]);
        }
    }
    ((num / den).sqrt(), mean(&delays))
}

fn stiffness_claim(pick: fn((f64, f64)) -> f64) -> Expect {
    let at = [25.0, 50.0, 100.0].map(|k| pick(contact_motion(stiffness(k))));
    compare(Claim::Lower, &one(at[0]), &one(at[2]))
        .with("at 25 p", at[0])
        .with("at 50 p", at[1])
        .with("at 100 p", at[2])
}

fn fig17_judder() -> Expect {
    stiffness_claim(|(mismatch, _)| mismatch)
}

fn fig17_soft_delay() -> Expect {
    stiffness_claim(|(_, delay)| delay)
}

/// The claim "immaterial" for rotation and deformation at once.
fn immaterial_both(reference: Device, variants: &[(&str, Device)]) -> Expect {
    let per = |m: M| {
        let vs: Vec<S> = variants
            .iter()
            .map(|(_, d)| spectrum(d.clone(), m))
            .collect();
        let named: Vec<(&str, &S)> = variants.iter().map(|(n, _)| *n).zip(&vs).collect();
        immaterial(&spectrum(reference.clone(), m), &named)
    };
    both(per(rot), "rotation", per(deformation), "deformation")
}

fn fig18_not_determinant() -> Expect {
    immaterial_both(
        stiffness(25.0),
        &[("50 p", stiffness(50.0)), ("100 p", stiffness(100.0))],
    )
}

fn fig19_operational_immaterial() -> Expect {
    let xs = xs();
    let (a, b) = (
        spectrum(mechanistic_xi_theta(0.0), rot),
        spectrum(mechanistic_xi_theta(0.02), rot),
    );
    let (mut worst, mut at) = (0.0, f64::NAN);
    for i in 0..xs.len() {
        if let (Some(a), Some(b)) = (a[i], b[i])
            && (a - b).abs() > worst
        {
            (worst, at) = ((a - b).abs(), xs[i]);
        }
    }
    immaterial_both(
        mechanistic_xi_theta(0.0),
        &[("ξθ = 0.02", mechanistic_xi_theta(0.02))],
    )
    .with("ωg/p of the largest rotation difference", at)
}

pub fn xi(x: f64, m: M) -> S {
    spectrum(mechanistic_xi_theta(x), m)
}

fn fig19_halves() -> Expect {
    // ωg/p = 4, 5, 6 are points 1, 2, 3 of the axis 3…20.
    let near5 = |s: S| -> S { s[1..4].to_vec() };
    compare(Claim::Halved, &near5(xi(0.02, rot)), &near5(xi(0.2, rot)))
}

fn fig19_overturning_stiffer() -> Expect {
    let xs = axis(1.0, 3.0, 0.5);
    let over = |x: f64, wn: f64| {
        spectrum_on(mechanistic_xi_theta(x), wn, &xs)
            .iter()
            .filter(|r| r.overturned)
            .count() as f64
    };
    let mut e = compare(
        Claim::Lower,
        &vec![Some(over(0.02, 16.0)), Some(over(0.02, 32.0))],
        &vec![Some(over(0.2, 16.0)), Some(over(0.2, 32.0))],
    );
    for wn in [8.0, 16.0, 32.0] {
        e = e
            .with(
                format!("ωn/p = {wn}: overturned with ξθ = 0.02"),
                over(0.02, wn),
            )
            .with(
                format!("ωn/p = {wn}: overturned with ξθ = 0.2"),
                over(0.2, wn),
            );
    }
    e
}

fn fig19_deformation_less() -> Expect {
    let def = ratios(&xi(0.02, deformation), &xi(0.2, deformation));
    let rot_q = ratios(&xi(0.02, rot), &xi(0.2, rot));
    both(
        compare(Claim::Lower, &xi(0.02, deformation), &xi(0.2, deformation)),
        "deformation reduced",
        compare(Claim::Lower, &one(mean(&def)), &one(mean(&rot_q))),
        "rotation reduced more (mean ratio of ratios)",
    )
}

fn fig19_full_range() -> Expect {
    both(
        compare(Claim::LowerEverywhere, &xi(0.02, rot), &xi(0.2, rot)),
        "rotation",
        compare(
            Claim::LowerEverywhere,
            &xi(0.02, deformation),
            &xi(0.2, deformation),
        ),
        "deformation",
    )
}

/// §7.3: friction fμ (× mr g) in place of viscous damping, η = 100 s/rad.
pub fn friction(f: f64) -> Device {
    clutch(|c| {
        c.damping = Damping::CBar(0.0);
        c.friction = f;
        c.eta = 100.0;
    })
}

fn fig21_operational_negligible() -> Expect {
    immaterial_both(friction(0.0), &[("friction", friction(0.1))])
}

fn fig21_strong_reduces() -> Expect {
    let per = |m: M| {
        compare(
            Claim::MuchLower,
            &spectrum(friction(0.0), m),
            &spectrum(friction(0.2), m),
        )
    };
    both(per(rot), "rotation", per(deformation), "deformation")
}

fn fig21_eliminates_rocking() -> Expect {
    let rocks = |f: f64| -> S {
        spectrum_on(friction(f), 8.0, &xs())
            .iter()
            .map(|r| Some(f64::from(u8::from(r.counters.uplifts > 0))))
            .collect()
    };
    let (free, strong) = (rocks(0.0), rocks(0.2));
    let mut e = compare(Claim::LowerSomewhere, &free, &strong);
    for (i, x) in xs().iter().enumerate() {
        if free[i] == Some(1.0) && strong[i] == Some(0.0) {
            e = e.with(format!("rocking eliminated at ωg/p = {x}"), *x);
        }
    }
    e
}

pub fn play(up: f64) -> Device {
    clutch(|c| {
        c.damping = Damping::XiTheta(0.02);
        c.play = up;
    })
}

/// The first clutch contact's time, the largest |dω/dt| of that flywheel within 0.1 s after it
/// (finite differences of the resampled history, pairs of rows at one instant skipped) and
/// over the whole run.
fn first_engagement(device: Device) -> (f64, f64, f64) {
    let h = history(&flexible_fig14(device));
    let (t0, which) = h
        .events
        .iter()
        .find_map(|(t, n)| {
            if *n == ContactA.name() {
                Some((*t, col::FLYWHEEL_A))
            } else if *n == ContactB.name() {
                Some((*t, col::FLYWHEEL_B))
            } else {
                None
            }
        })
        .expect("the clutch engages");
    let (t, w) = (column(&h, col::T), column(&h, which));
    let spike = |from: f64, to: f64| {
        let mut best = 0.0f64;
        for i in 1..t.len() {
            let dt = t[i] - t[i - 1];
            if t[i - 1] >= from && t[i] <= to && dt > 1e-9 {
                best = best.max(((w[i] - w[i - 1]) / dt).abs());
            }
        }
        best
    };
    (t0, spike(t0, t0 + 0.1), spike(f64::MIN, f64::MAX))
}

fn fig22_first_engagement() -> Expect {
    let (t_none, none, none_all) = first_engagement(play(0.0));
    let (t_play, with, with_all) = first_engagement(play(0.01));
    compare(Claim::MarkedlyLarger, &one(none), &one(with))
        .with("first contact, up = 1 cm (s)", t_play)
        .with("first contact, no play (s)", t_none)
        .with("window peak, up = 1 cm", with)
        .with("window peak, no play", none)
        .with("beside: whole-run peak, up = 1 cm", with_all)
        .with("beside: whole-run peak, no play", none_all)
}

fn fig23_play_unnoticeable() -> Expect {
    immaterial_both(play(0.0), &[("up = 1 cm", play(0.01))])
}

fn s9_play_acceleration() -> Expect {
    compare(
        Claim::MarkedlyLarger,
        &spectrum(play(0.0), horizontal),
        &spectrum(play(0.01), horizontal),
    )
}

/// fig19-operational-immaterial's verdict with the clutch frequency √(kθ/J) = `k` p.
pub fn xi_immaterial_at_stiffness(k: f64) -> Agreement {
    let at = |x: f64| {
        clutch(|c| {
            c.damping = Damping::XiTheta(x);
            c.stiffness = ClutchStiffness::FrequencyRatio(k);
        })
    };
    immaterial_both(at(0.0), &[("ξθ = 0.02", at(0.02))]).agreement
}

/// fig21-operational-negligible's verdict at friction `f` (× mr g).
pub fn friction_negligible(f: f64) -> Agreement {
    immaterial_both(friction(0.0), &[("friction", friction(f))]).agreement
}
