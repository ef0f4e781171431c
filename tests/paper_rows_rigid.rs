//! The rigid-block rows (Fig. 3, Fig. 5, Figs. 8–12, §9) recomputed (see paper_rows.rs).

use crate::paper_rows::*;
use rocklab::paper::{Agreement, runs::col};
use rocklab::presets::{self, inerter, inerter_with_dissipation, mechanistic, sequential};
use rocklab::scene::{Clutch, Damping, Device, Impact, Scene};
use rocklab::sim::SceneResult;
use std::sync::Arc;

pub const TABLE: [Entry; 28] = [
    ("fig3-restitution-grows", fig3_restitution_grows),
    ("fig3-stocky", fig3_stocky),
    ("fig5-converge", fig5_converge),
    ("fig5-spikes", fig5_spikes),
    ("fig5-spikes-disappear", fig5_spikes_disappear),
    ("fig5-similar-rotation", fig5_similar_rotation),
    ("fig8-inerter-stabilizes", fig8_inerter_stabilizes),
    ("fig8-inerter-amplified-later", fig8_inerter_amplified_later),
    ("fig8-clutch-eliminates", fig8_clutch_eliminates),
    ("fig8-faster-decrease", fig8_faster_decrease),
    ("fig9-weak-reengagement", fig9_weak_reengagement),
    ("fig9-sequential-reengages", fig9_sequential_reengages),
    ("fig10-intensive-engagement", fig10_intensive_engagement),
    ("fig11-comparable-peaks", fig11_comparable_peaks),
    (
        "fig11-inerter-slightly-higher",
        fig11_inerter_slightly_higher,
    ),
    ("fig11-energy-back-and-forth", fig11_energy_back_and_forth),
    ("s53-mechanistic-may-dissipate-more", s53_dissipate_more),
    ("fig12-overturning", fig12_overturning),
    ("fig12-largely-comparable", fig12_largely_comparable),
    ("fig12-marginally-lower", fig12_marginally_lower),
    ("fig12-trend", fig12_trend),
    ("fig12-acceleration", fig12_acceleration),
    ("fig12-suppression", fig12_suppression),
    ("s9-restitution-slender", s9_restitution_slender),
    ("s9-dirac-window", s9_dirac_window),
    ("s9-clutch-below-single", s9_clutch_below_single),
    (
        "s9-clutch-larger-acceleration",
        s9_clutch_larger_acceleration,
    ),
    ("s9-protected-smaller", s9_protected_smaller),
];

/// Housner's r (Eq. 3).
fn housner(a: f64) -> f64 {
    (1.0 - 1.5 * a.sin().powi(2)).powi(2)
}

/// Eq. 16.
fn r_sigma(a: f64, sigma: f64) -> f64 {
    let q = 0.75 * sigma * a.cos().powi(2);
    ((1.0 - 1.5 * a.sin().powi(2) + q) / (1.0 + q)).powi(2)
}

const ALPHAS: [f64; 5] = [0.05, 0.1, 0.2, 0.3, 0.4];

/// Rising steps and steps over the curves: all rising agrees, half roughly.
fn rising(curves: &[Vec<f64>]) -> Expect {
    let rises: usize = curves
        .iter()
        .map(|c| c.windows(2).filter(|w| w[1] > w[0]).count())
        .sum();
    let steps: usize = curves.iter().map(|c| c.len() - 1).sum();
    let agreement = if rises == steps {
        Agreement::Agrees
    } else if 2 * rises >= steps {
        Agreement::Roughly
    } else {
        Agreement::Disagrees
    };
    Expect::new(agreement)
        .with("rising steps", rises as f64)
        .with("steps", steps as f64)
}

fn fig3_restitution_grows() -> Expect {
    let curves: Vec<Vec<f64>> = ALPHAS
        .iter()
        .map(|&a| (0..=20).map(|i| r_sigma(a, i as f64 * 0.05)).collect())
        .collect();
    let at_zero = ALPHAS
        .iter()
        .map(|&a| (r_sigma(a, 0.0) - housner(a)).abs())
        .fold(0.0, f64::max);
    rising(&curves).with("largest |r_σ(σ = 0) − Housner's r|", at_zero)
}

fn fig3_stocky() -> Expect {
    let gains: Vec<f64> = ALPHAS
        .iter()
        .map(|&a| r_sigma(a, 1.0) - housner(a))
        .collect();
    let mut e = rising(std::slice::from_ref(&gains));
    for (a, g) in ALPHAS.iter().zip(&gains) {
        e = e.with(format!("r_σ(1) − r at α = {a}"), *g);
    }
    e
}

/// Fig. 5's block: Fig. 8's, bare, rtol 1e-8; (θmax/α, |θ̈|max/p²) for the impact model.
fn fig5(width: Option<f64>) -> (f64, f64) {
    let impact = width.map_or(Impact::default(), |width| Impact::Dirac { width });
    let r = result(&Scene {
        impact,
        rtol: 1e-8,
        ..presets::rigid_fig8(Device::None)
    });
    (rot(&r).unwrap(), angular(&r).unwrap())
}

fn fig5_converge() -> Expect {
    let (h, d) = (fig5(None).0, fig5(Some(1e-4)).0);
    let err = (d - h).abs() / h;
    Expect::new(ladder(err, 0.01, 0.05))
        .with("value", d)
        .with("limit", h)
        .with("relative difference", err)
}

fn fig5_spikes() -> Expect {
    compare(
        Claim::MarkedlyLarger,
        &one(fig5(None).1),
        &one(fig5(Some(1e-4)).1),
    )
}

fn fig5_spikes_disappear() -> Expect {
    let (h, sharp, wide) = (fig5(None).1, fig5(Some(1e-4)).1, fig5(Some(0.005)).1);
    immaterial(&one(h), &[("n = 0.005", &one(wide))])
        .with("Housner between impacts", h)
        .with("Dirac n = 1e-4", sharp)
        .with("Dirac n = 0.005", wide)
}

fn fig5_similar_rotation() -> Expect {
    immaterial(
        &one(fig5(None).0),
        &[
            ("n = 1e-4", &one(fig5(Some(1e-4)).0)),
            ("n = 0.005", &one(fig5(Some(0.005)).0)),
        ],
    )
}

fn fig8(device: Device) -> Arc<SceneResult> {
    result(&presets::rigid_fig8(device))
}

/// (t, θ) of the Fig. 8 scene's history.
fn fig8_theta(device: Device) -> (Vec<f64>, Vec<f64>) {
    let h = history(&presets::rigid_fig8(device));
    (column(&h, col::T), column(&h, col::THETA))
}

/// max |θ|/α from `from` seconds on (α = 10°).
fn late(device: Device, from: f64) -> f64 {
    let (t, th) = fig8_theta(device);
    let m = t
        .iter()
        .zip(&th)
        .filter(|(t, _)| **t >= from)
        .map(|(_, x)| x.abs())
        .fold(0.0, f64::max);
    m / 10f64.to_radians()
}

fn fig8_inerter_stabilizes() -> Expect {
    let (b, i) = (
        rot(&fig8(Device::None)).unwrap(),
        rot(&fig8(inerter())).unwrap(),
    );
    compare(Claim::MuchLower, &one(b), &one(i))
        .with("bare θmax/α", b)
        .with("inerter θmax/α", i)
}

fn fig8_inerter_amplified_later() -> Expect {
    let (b, i) = (late(Device::None, 5.0), late(inerter(), 5.0));
    let mut e = compare(Claim::Larger, &one(b), &one(i))
        .with("bare late max|θ|/α", b)
        .with("inerter late max|θ|/α", i);
    for from in [2.0, 3.0, 4.0, 6.0, 8.0] {
        e = e.with(
            format!("inerter/bare from t = {from} s"),
            late(inerter(), from) / late(Device::None, from),
        );
    }
    e
}

fn fig8_clutch_eliminates() -> Expect {
    let (i, s, m) = (
        late(inerter(), 5.0),
        late(sequential(), 5.0),
        late(mechanistic(), 5.0),
    );
    compare(
        Claim::Lower,
        &vec![Some(i), Some(i)],
        &vec![Some(s), Some(m)],
    )
    .with("inerter", i)
    .with("sequential", s)
    .with("mechanistic", m)
}

fn fig8_faster_decrease() -> Expect {
    faster(&fig8_theta(sequential()), &fig8_theta(mechanistic()))
}

/// The device force's impulse after 3 s over before, and its engaged share of 3–6 s.
fn late_impulse(device: Device) -> (f64, f64) {
    let h = history(&presets::rigid_fig8(device));
    let (t, f) = (column(&h, col::T), column(&h, col::DEVICE_FORCE));
    (
        impulse(&t, &f, 3.0, f64::INFINITY) / impulse(&t, &f, 0.0, 3.0),
        engaged(&t, &f, 3.0, 6.0),
    )
}

fn fig9_weak_reengagement() -> Expect {
    let (s, se) = late_impulse(sequential());
    let (m, me) = late_impulse(mechanistic());
    compare(Claim::MuchLower, &one(s), &one(m))
        .with("sequential impulse after / before", s)
        .with("mechanistic impulse after / before", m)
        .with("beside: sequential engaged share of 3–6 s", se)
        .with("beside: mechanistic engaged share of 3–6 s", me)
}

fn fig9_sequential_reengages() -> Expect {
    let (t, th) = fig8_theta(sequential());
    let rest = envelope_time(&t, &th, 0.05);
    let h = history(&presets::rigid_fig8(sequential()));
    let last = h
        .events
        .iter()
        .filter(|(_, n)| *n == rocklab::paper::runs::SEQUENTIAL_SWITCH)
        .map(|(t, _)| *t)
        .fold(f64::NAN, f64::max);
    compare(Claim::Larger, &one(rest), &one(last))
        .with("envelope below 5 % (s)", rest)
        .with("last switch (s)", last)
}

fn fig10_intensive_engagement() -> Expect {
    let h = history(&presets::rigid_fig8(mechanistic()));
    let t = column(&h, col::T);
    let mut lengths = Vec::new();
    for c in [col::CLUTCH_A, col::CLUTCH_B] {
        for (a, b) in contacts(&column(&h, c)) {
            if t[a] < 3.0 {
                lengths.push(t[b] - t[a]);
            }
        }
    }
    let impacts = h
        .events
        .iter()
        .filter(|(t, n)| *n == "impact" && *t < 3.0)
        .count() as f64;
    let n = lengths.len() as f64;
    compare(Claim::MarkedlyLarger, &one(impacts), &one(n))
        .with("contacts before 3 s", n)
        .with("impacts before 3 s", impacts)
        .with("mean contact (s)", mean(&lengths))
}

fn fig11_comparable_peaks() -> Expect {
    let (s, m) = (
        rot(&fig8(sequential())).unwrap(),
        rot(&fig8(mechanistic())).unwrap(),
    );
    immaterial(&one(s), &[("mechanistic", &one(m))])
        .with("sequential", s)
        .with("mechanistic", m)
}

fn fig11_inerter_slightly_higher() -> Expect {
    let i = rot(&fig8(inerter_with_dissipation())).unwrap();
    let (s, m) = (
        rot(&fig8(sequential())).unwrap(),
        rot(&fig8(mechanistic())).unwrap(),
    );
    compare(
        Claim::SlightlyHigher,
        &vec![Some(s), Some(m)],
        &vec![Some(i), Some(i)],
    )
    .with("inerter c̄ = 1", i)
    .with(
        "beside: rigidly coupled inerter (no dissipation)",
        rot(&fig8(inerter())).unwrap(),
    )
}

fn fig11_energy_back_and_forth() -> Expect {
    energy_back(returned(&presets::rigid_fig8(inerter())), true)
}

/// Fig. 12's spectra: Fig. 8's block over ωg/p = 2…10 (step 0.25), 15 s.
fn fig12(device: Device) -> Vec<Arc<SceneResult>> {
    let scene = Scene {
        duration: 15.0,
        ..presets::rigid_fig8(device)
    };
    sweep(&scene, &axis(2.0, 10.0, 0.25))
}

fn fig12_of(device: Device, m: fn(&SceneResult) -> Option<f64>) -> S {
    series(&fig12(device), m)
}

fn s53_dissipate_more() -> Expect {
    compare(
        Claim::HigherSomewhere,
        &fig12_of(sequential(), device_share),
        &fig12_of(mechanistic(), device_share),
    )
}

fn fig12_overturning() -> Expect {
    let xs = axis(2.0, 10.0, 0.25);
    let bare = fig12(Device::None);
    // The first ωg/p from which no bare block overturns, midway from the last that does.
    let last_over = (0..xs.len()).rev().find(|&i| bare[i].overturned);
    let boundary = match last_over {
        None => xs[0],
        Some(i) if i + 1 < xs.len() => 0.5 * (xs[i] + xs[i + 1]),
        Some(_) => f64::NAN,
    };
    let err = (boundary - 3.0).abs() / 3.0;
    Expect::new(ladder(err, 0.15, 0.30))
        .with("measured", boundary)
        .with("stated", 3.0)
}

fn fig12_largely_comparable() -> Expect {
    let xs = axis(2.0, 10.0, 0.25);
    let s = fig12_of(sequential(), rot);
    let m = fig12_of(mechanistic(), rot);
    let (mut worst, mut at) = (0.0, f64::NAN);
    for i in 0..xs.len() {
        if let (Some(a), Some(b)) = (s[i], m[i])
            && (a - b).abs() > worst
        {
            (worst, at) = ((a - b).abs(), xs[i]);
        }
    }
    immaterial(&s, &[("mechanistic", &m)]).with("ωg/p of the largest difference", at)
}

fn fig12_marginally_lower() -> Expect {
    let low = thirds(axis(2.0, 10.0, 0.25).len())[0].clone();
    let s = fig12_of(sequential(), rot)[low.clone()].to_vec();
    let m = fig12_of(mechanistic(), rot)[low].to_vec();
    compare(Claim::SlightlyLower, &s, &m)
}

fn fig12_trend() -> Expect {
    gap_shrinks(
        &axis(2.0, 10.0, 0.25),
        &fig12_of(sequential(), rot),
        &fig12_of(mechanistic(), rot),
    )
}

fn fig12_acceleration() -> Expect {
    let other = compare(
        Claim::MarkedlyLarger,
        &fig12_of(sequential(), horizontal),
        &fig12_of(mechanistic(), horizontal),
    );
    compare(
        Claim::MarkedlyLarger,
        &fig12_of(sequential(), angular),
        &fig12_of(mechanistic(), angular),
    )
    .with("beside: |ẍ + a_g|max mean ratio", other.value("mean ratio"))
    .with(
        "beside: |ẍ + a_g|max share above",
        other.value("share above"),
    )
}

fn fig12_suppression() -> Expect {
    let mut damped = Clutch::paper_default(presets::SIGMA);
    damped.damping = Damping::CBar(4.0);
    compare(
        Claim::Lower,
        &fig12_of(Device::Mechanistic(damped), rot),
        &fig12_of(Device::Mechanistic(Clutch::paper_default(1.0)), rot),
    )
}

fn s9_restitution_slender() -> Expect {
    let slender = [0.05, 0.1, 0.15];
    let r: S = slender.iter().map(|&a| Some(housner(a))).collect();
    let rs: S = slender.iter().map(|&a| Some(r_sigma(a, 0.5))).collect();
    immaterial(&r, &[("r_σ(σ = 0.5)", &rs)])
        .with(
            "beside: stocky α = 0.4, r_σ / r − 1",
            r_sigma(0.4, 0.5) / housner(0.4) - 1.0,
        )
        .with(
            "beside: α = 0.15, energy lost per impact 1 − r_σ over 1 − r",
            (1.0 - r_sigma(0.15, 0.5)) / (1.0 - housner(0.15)),
        )
}

fn s9_dirac_window() -> Expect {
    let (h_rot, h_acc) = fig5(None);
    let mut best: Option<(f64, Expect)> = None;
    let mut scan = Vec::new();
    for n in [5e-4, 1e-3, 2e-3, 5e-3, 1e-2] {
        let (r, a) = fig5(Some(n));
        let e = both(
            immaterial(&one(h_rot), &[("rotation", &one(r))]),
            "rotation",
            immaterial(&one(h_acc), &[("acceleration", &one(a))]),
            "acceleration",
        );
        let worse = ((r - h_rot).abs() / h_rot).max((a - h_acc).abs() / h_acc);
        scan.push((format!("n = {n}: worse share"), worse));
        if best.as_ref().is_none_or(|(w, _)| worse < *w) {
            best = Some((worse, e.with("n", n)));
        }
    }
    let mut e = best.unwrap().1;
    e.values.extend(scan);
    e
}

fn s9_clutch_below_single() -> Expect {
    compare(
        Claim::Lower,
        &fig12_of(inerter_with_dissipation(), rot),
        &fig12_of(mechanistic(), rot),
    )
}

fn s9_clutch_larger_acceleration() -> Expect {
    let other = compare(
        Claim::Larger,
        &fig12_of(inerter_with_dissipation(), horizontal),
        &fig12_of(mechanistic(), horizontal),
    );
    let rigid = compare(
        Claim::Larger,
        &fig12_of(inerter(), angular),
        &fig12_of(mechanistic(), angular),
    );
    compare(
        Claim::Larger,
        &fig12_of(inerter_with_dissipation(), angular),
        &fig12_of(mechanistic(), angular),
    )
    .with("beside: |ẍ + a_g|max mean ratio", other.value("mean ratio"))
    .with(
        "beside: against the rigid inerter, mean ratio",
        rigid.value("mean ratio"),
    )
}

fn s9_protected_smaller() -> Expect {
    let stack = |m: fn(&SceneResult) -> Option<f64>| -> (S, S) {
        let bare = fig12_of(Device::None, m);
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for d in [inerter(), sequential(), mechanistic()] {
            a.extend(bare.iter().copied());
            b.extend(fig12_of(d, m));
        }
        (a, b)
    };
    let (ra, rb) = stack(rot);
    let (aa, ab) = stack(angular);
    let (oa, ob) = stack(horizontal);
    let other = compare(Claim::LowerEverywhere, &oa, &ob);
    both(
        compare(Claim::LowerEverywhere, &ra, &rb),
        "rotation",
        compare(Claim::LowerEverywhere, &aa, &ab),
        "acceleration",
    )
    .with(
        "beside: |ẍ + a_g|max share below",
        other.value("share below"),
    )
    .with("beside: |ẍ + a_g|max mean ratio", other.value("mean ratio"))
}

/// fig8-faster-decrease's verdict with the mechanistic clutch's c̄ changed.
pub fn decay_with_cbar(cbar: f64) -> Agreement {
    let mut c = Clutch::paper_default(presets::SIGMA);
    c.damping = Damping::CBar(cbar);
    faster(
        &fig8_theta(sequential()),
        &fig8_theta(Device::Mechanistic(c)),
    )
    .agreement
}
