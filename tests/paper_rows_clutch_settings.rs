//! The flexible structure's further device rows (Figs. 15f, 16, 21, §7.4, §9) recomputed (see
//! paper_rows.rs).

use crate::paper_rows::*;
use crate::paper_rows_flexible::{M, friction, play, spectrum, stiffness, xi};
use rocklab::paper::runs::col;
use rocklab::presets::{flexible_fig14, mechanistic, mechanistic_xi_theta, sequential};
use rocklab::scene::Device;
use rocklab::sim::{EnergyRole, HistoryColumn};

pub const TABLE: [Entry; 5] = [
    ("fig15-conservation", fig15_conservation),
    ("fig16-similar-peaks", fig16_similar_peaks),
    ("s7-series-of-collisions", s7_series_of_collisions),
    ("fig21-similar-to-viscous", fig21_similar_to_viscous),
    (
        "s9-damping-friction-more-significant",
        s9_damping_friction_more_significant,
    ),
];

fn fig15_conservation() -> Expect {
    let h = history(&flexible_fig14(mechanistic_xi_theta(0.02)));
    let columns: Vec<(f64, Vec<f64>)> = HistoryColumn::ALL
        .into_iter()
        .filter_map(|c| {
            let sign = match c.energy()? {
                EnergyRole::Input => 1.0,
                EnergyRole::Stored | EnergyRole::Dissipated => -1.0,
            };
            Some((sign, column(&h, c)))
        })
        .collect();
    let rows = columns[0].1.len();
    let mut worst = 0.0f64;
    for i in 0..rows {
        let r: f64 = columns.iter().map(|(s, v)| s * v[i]).sum();
        worst = worst.max(r.abs());
    }
    let input = *column(&h, HistoryColumn::EInput).last().unwrap();
    small(
        "largest |energy residual| over the history / input",
        worst / input.abs(),
        1e-3,
    )
}

fn drift(r: &rocklab::sim::SceneResult) -> Option<f64> {
    (!r.overturned).then_some(r.peaks.drift)
}

fn fig16_similar_peaks() -> Expect {
    immaterial(
        &spectrum(sequential(), drift),
        &[("mechanistic", &spectrum(mechanistic(), drift))],
    )
}

/// (half-cycles of Ẋ with a contact event, the share of them with three or more).
fn series_share(device: Device) -> (f64, f64) {
    let h = history(&flexible_fig14(device));
    let t = column(&h, col::T);
    let cuts = crossings(&t, &column(&h, col::X_DOT));
    // Half-cycle k spans [cuts[k − 1], cuts[k]) with cuts[−1] = −∞ and cuts[n] = +∞.
    let mut counts = vec![0usize; cuts.len() + 1];
    for (s, name) in &h.events {
        if *name == "contact_a" || *name == "contact_b" {
            counts[cuts.partition_point(|c| *c <= *s)] += 1;
        }
    }
    let engaging: Vec<usize> = counts.into_iter().filter(|n| *n > 0).collect();
    let series = engaging.iter().filter(|n| **n >= 3).count();
    (engaging.len() as f64, series as f64 / engaging.len() as f64)
}

fn s7_series_of_collisions() -> Expect {
    let (n, share) = series_share(play(0.01));
    at_least(
        "share of engaging half-cycles with three contact events or more, up = 1 cm",
        share,
        0.8,
    )
    .with("engaging half-cycles, up = 1 cm", n)
    .with(
        "beside: the same share without play",
        series_share(play(0.0)).1,
    )
}

fn fig21_similar_to_viscous() -> Expect {
    let per = |m: M| {
        let (mut v, mut f) = (Vec::new(), Vec::new());
        for (x, mu) in [(0.02, 0.1), (0.2, 0.2)] {
            v.extend(ratio_series(&xi(0.0, m), &xi(x, m)));
            f.extend(ratio_series(
                &spectrum(friction(0.0), m),
                &spectrum(friction(mu), m),
            ));
        }
        immaterial(&v, &[("friction", &f)])
    };
    both(per(rot), "rotation", per(deformation), "deformation")
}

fn ratio_series(a: &S, b: &S) -> S {
    a.iter()
        .zip(b)
        .map(|(a, b)| match (a, b) {
            (Some(a), Some(b)) if *a > 0.0 => Some(b / a),
            _ => None,
        })
        .collect()
}

/// The largest |difference| over the reference's peak.
fn spread(a: Device, b: Device, m: M) -> f64 {
    let (x, y) = (spectrum(a, m), spectrum(b, m));
    let top = x.iter().flatten().fold(f64::NEG_INFINITY, |p, v| p.max(*v));
    x.iter()
        .zip(&y)
        .filter_map(|(a, b)| Some((a.as_ref()? - b.as_ref()?).abs()))
        .fold(0.0, f64::max)
        / top
}

fn s9_damping_friction_more_significant() -> Expect {
    let (mut k, mut other, mut named) = (Vec::new(), Vec::new(), Vec::new());
    for (m, name) in [(rot as M, "rotation"), (deformation as M, "deformation")] {
        let by_k = spread(stiffness(25.0), stiffness(100.0), m);
        let by_xi = spread(mechanistic_xi_theta(0.0), mechanistic_xi_theta(0.2), m);
        let by_mu = spread(friction(0.0), friction(0.2), m);
        named.push((format!("{name}: kθ 25 → 100 p"), by_k));
        named.push((format!("{name}: ξθ 0 → 0.2"), by_xi));
        named.push((format!("{name}: fμ 0 → 0.2 mr g"), by_mu));
        k.extend([Some(by_k), Some(by_k)]);
        other.extend([Some(by_xi), Some(by_mu)]);
    }
    let mut e = compare(Claim::Larger, &k, &other);
    e.values.extend(named);
    e
}
