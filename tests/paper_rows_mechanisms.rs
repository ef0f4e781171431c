//! The mechanism rows (Figs. 5, 6, 9, 10, §4) recomputed (see paper_rows.rs).

use crate::paper_rows::*;
use rocklab::paper::runs::col;
use rocklab::presets::{self, mechanistic, sequential};
use rocklab::scene::{Device, Impact, ResetRule, Scene};
use rocklab::sim::History;
use std::sync::Arc;

pub const TABLE: [Entry; 7] = [
    ("fig5-phase-shift", fig5_phase_shift),
    ("fig5-equivalent-dissipation", fig5_equivalent_dissipation),
    ("fig6-epsilon-distortion", fig6_epsilon_distortion),
    ("s4-reset-needed", s4_reset_needed),
    ("fig9-sudden-loss", fig9_sudden_loss),
    ("fig9-limited-time", fig9_limited_time),
    ("fig10-coincide", fig10_coincide),
];

/// Fig. 5's block (Fig. 8's, bare, rtol 1e-8) with Housner's impact or a Dirac of width n.
fn fig5(width: Option<f64>) -> Arc<History> {
    let impact = width.map_or(Impact::default(), |width| Impact::Dirac { width });
    history(&Scene {
        impact,
        rtol: 1e-8,
        ..presets::rigid_fig8(Device::None)
    })
}

fn impacts(width: Option<f64>) -> Vec<f64> {
    let h = fig5(width);
    crossings(&column(&h, col::T), &column(&h, col::THETA))
}

fn shift(width: f64) -> f64 {
    let (a, b) = (impacts(None), impacts(Some(width)));
    let n = a.len().min(b.len());
    let mut worst = 0.0f64;
    for k in 0..n.saturating_sub(1) {
        worst = worst.max((b[k] - a[k]).abs() / (a[k + 1] - a[k]));
    }
    worst
}

fn fig5_phase_shift() -> Expect {
    at_least(
        "largest impact-time shift / half-cycle, n = 0.005",
        shift(0.005),
        0.10,
    )
    .with("beside: largest shift / half-cycle, n = 1e-4", shift(1e-4))
    .with("impacts, Housner", impacts(None).len() as f64)
    .with("impacts, n = 0.005", impacts(Some(0.005)).len() as f64)
}

/// 1 − E(after) / E(before) around the first impact after the pulse (2π/ωg, ωg = 4 p), the
/// energies at the rocking extremes either side.
fn loss(width: Option<f64>) -> f64 {
    let h = fig5(width);
    let t = column(&h, col::T);
    let e = column(&h, col::E_STRUCTURE);
    let end = std::f64::consts::TAU / (4.0 * presets::RIGID_P);
    let hit = *crossings(&t, &column(&h, col::THETA))
        .iter()
        .find(|&&x| x > end)
        .unwrap();
    let ext = crossings(&t, &column(&h, col::THETA_DOT));
    let before = *ext.iter().rfind(|&&x| x < hit).unwrap();
    let after = *ext.iter().find(|&&x| x > hit).unwrap();
    let row = |x: f64| t.iter().position(|s| *s >= x).unwrap_or(t.len() - 1);
    1.0 - e[row(after)] / e[row(before)]
}

fn fig5_equivalent_dissipation() -> Expect {
    let (h, a, b) = (loss(None), loss(Some(1e-4)), loss(Some(0.005)));
    let alpha = 10f64.to_radians();
    let r = (1.0 - 1.5 * alpha.sin().powi(2)).powi(2);
    immaterial(&one(h), &[("n = 1e-4", &one(a)), ("n = 0.005", &one(b))])
        .with("Housner", h)
        .with("Dirac n = 1e-4", a)
        .with("Dirac n = 0.005", b)
        .with("beside: 1 − Housner's r (Eq. 3)", 1.0 - r)
}

/// max over Δθ < 0 of −½ (1 + tanh εΔθ) Δθ, on u = εΔθ ∈ [−10, 0) step 1e-4, over ε.
fn distortion(eps: f64) -> f64 {
    let mut best = 0.0f64;
    for i in 1..=100_000 {
        let u = -1e-4 * i as f64;
        best = best.max(-0.5 * (1.0 + u.tanh()) * u);
    }
    best / eps
}

fn fig6_epsilon_distortion() -> Expect {
    let d = [distortion(1e4), distortion(1e5), distortion(1e6)];
    compare(
        Claim::MuchLower,
        &vec![Some(d[0]), Some(d[1])],
        &vec![Some(d[1]), Some(d[2])],
    )
    .with("distortion / kθ (µrad) at ε = 1e4", 1e6 * d[0])
    .with("distortion / kθ (µrad) at ε = 1e5", 1e6 * d[1])
    .with("distortion / kθ (µrad) at ε = 1e6", 1e6 * d[2])
}

fn fig8_engagements(rule: ResetRule) -> f64 {
    let mut c = rocklab::scene::Clutch::paper_default(presets::SIGMA);
    c.reset = rule;
    result(&presets::rigid_fig8(Device::Mechanistic(c)))
        .counters
        .engagements as f64
}

fn s4_reset_needed() -> Expect {
    let (with, without) = (
        fig8_engagements(ResetRule::Paper),
        fig8_engagements(ResetRule::Never),
    );
    compare(Claim::MuchLower, &one(with), &one(without))
        .with("engagements with the reset", with)
        .with("engagements without", without)
}

fn sudden_of(device: Device) -> f64 {
    let h = history(&presets::rigid_fig8(device));
    sudden(&column(&h, col::T), &column(&h, col::E_INERTER))
}

fn fig9_sudden_loss() -> Expect {
    let (s, m) = (sudden_of(sequential()), sudden_of(mechanistic()));
    compare(Claim::MuchLower, &one(s), &one(m))
        .with("sequential sudden share", s)
        .with("mechanistic sudden share", m)
}

fn fig9_limited_time() -> Expect {
    let h = history(&presets::rigid_fig8(mechanistic()));
    let hits: Vec<f64> = h
        .events
        .iter()
        .filter(|(_, n)| *n == "impact")
        .map(|(t, _)| *t)
        .collect();
    let (mut early, mut late) = (Vec::new(), Vec::new());
    for w in hits.windows(2) {
        if w[0] >= 3.0 {
            late.push(w[1] - w[0]);
        } else {
            early.push(w[1] - w[0]);
        }
    }
    let (before, after) = (mean(&early), mean(&late));
    both(
        compare(Claim::MuchLower, &one(before), &one(after)),
        "rocking half-cycle after 3 s against before",
        compare(Claim::MuchLower, &one(1.0), &one(after)),
        "half-cycle after 3 s against the flywheel's deceleration time 1/c̄",
    )
    .with("half-cycle before 3 s (s)", before)
    .with("half-cycle after 3 s (s)", after)
    .with(
        "beside: flywheel speed kept over a half-cycle after 3 s, e^(−c̄ T)",
        (-after).exp(),
    )
}

fn fig10_coincide() -> Expect {
    let h = history(&presets::rigid_fig8(mechanistic()));
    let (t, v) = (column(&h, col::T), column(&h, col::X_DOT));
    let mut shares = Vec::new();
    for (fc, yc) in [
        (col::CLUTCH_A, col::FLYWHEEL_A),
        (col::CLUTCH_B, col::FLYWHEEL_B),
    ] {
        let (f, y) = (column(&h, fc), column(&h, yc));
        for (a, b) in contacts(&f) {
            let rel: Vec<f64> = (a..=b).map(|i| y[i] - v[i]).collect();
            let Some(meet) = crossings(&t[a..=b], &rel).first().copied() else {
                continue;
            };
            let k = peak_row(&f, a, b);
            if t[b] > t[a] {
                shares.push((t[k] - meet).abs() / (t[b] - t[a]));
            }
        }
    }
    small(
        "mean over contacts of |t(force peak) − t(ẏ = Ẋ)| / contact duration",
        mean(&shares),
        0.10,
    )
    .with("contacts", shares.len() as f64)
}
