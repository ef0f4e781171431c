//! `rocklab paper`: every claim of the paper one row (src/paper). These tests check the rows'
//! numbers against independent recomputations (closed forms, the CLI's own `simulate
//! --history` output, the fair checks on series with known answers), that PAPER.md is the
//! command's current output, and that the JSON carries every row's fields.

use crate::util::rocklab;
use rocklab::paper::{self, Agreement, fair};

/// Every row once per test process (the scene cache makes later calls cheap).
fn rows() -> Vec<paper::Row> {
    paper::rows(None).expect("the paper's rows run")
}

fn value(row: &paper::Row, name: &str) -> f64 {
    row.value(name)
        .unwrap_or_else(|| panic!("{}: no value '{name}' in {:?}", row.id, row.values))
}

#[test]
fn paper_md_is_current() {
    let md = paper::markdown(&rows());
    let committed = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/PAPER.md"))
        .expect("PAPER.md");
    assert!(
        md == committed,
        "PAPER.md is stale: regenerate it with `cargo run --release -- paper > PAPER.md`"
    );
}

#[test]
fn every_claim_is_a_row_with_numbers_and_reasons() {
    let rows = rows();
    assert!(rows.len() >= 75, "{} rows", rows.len());
    // Every measurable claim is measured: the one untestable row is El Centro, which ships
    // as a stand-in pulse, not the record.
    let untestable: Vec<&str> = rows
        .iter()
        .filter(|r| r.verdict == Agreement::Untestable)
        .map(|r| r.id)
        .collect();
    assert_eq!(untestable, ["fig24-el-centro"]);
    assert_eq!(rows.len(), paper::claim_count());
    let mut ids: Vec<&str> = rows.iter().map(|r| r.id).collect();
    ids.sort();
    ids.dedup();
    assert_eq!(ids.len(), rows.len(), "ids are unique");
    for r in &rows {
        assert!(r.claim.len() > 20, "{}: the claim is quoted", r.id);
        if r.verdict != Agreement::Agrees {
            assert!(
                !r.reason.is_empty(),
                "{}: a {:?} row says why",
                r.id,
                r.verdict
            );
        }
        if r.verdict != Agreement::Untestable {
            assert!(!r.values.is_empty(), "{}: a checked row has numbers", r.id);
            assert!(r.values.iter().any(|(_, x)| x.is_finite()), "{}", r.id);
        }
    }
    // The counts line adds up to the rows.
    let line = paper::counts(&rows);
    let total: usize = Agreement::ALL
        .iter()
        .map(|v| rows.iter().filter(|r| r.verdict == *v).count())
        .sum();
    assert_eq!(total, rows.len());
    assert!(
        line.starts_with(&format!("{} claims:", rows.len())),
        "{line}"
    );
}

#[test]
fn json_has_every_field_for_a_row() {
    let out = rocklab(&["paper", "--only", "fig3", "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let rows = v.as_array().expect("an array of rows");
    assert_eq!(rows.len(), 2, "fig3-restitution-grows and fig3-stocky");
    for r in rows {
        for field in [
            "id", "figure", "claim", "check", "values", "verdict", "reason",
        ] {
            assert!(r.get(field).is_some(), "{field} missing in {r}");
        }
    }
    let stocky = &rows[1];
    assert_eq!(stocky["id"], "fig3-stocky");
    // Eq. 16 at σ = 1 against Housner's r at α = 0.4, by hand.
    let a: f64 = 0.4;
    let r = (1.0 - 1.5 * a.sin().powi(2)).powi(2);
    let q = 0.75 * a.cos().powi(2);
    let rs = ((1.0 - 1.5 * a.sin().powi(2) + q) / (1.0 + q)).powi(2);
    let got = stocky["values"]["r_σ(1) − r at α = 0.4"].as_f64().unwrap();
    assert!((got - (rs - r)).abs() < 1e-12, "{got} vs {}", rs - r);
}

/// The decay row's envelope times are those of the history a user gets from `rocklab simulate
/// --history` (resampled, not solver steps).
#[test]
fn fig8_decay_times_come_from_simulate_history() {
    let row = paper::row("fig8-faster-decrease").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let times = |device: &str, extra: &[&str]| -> Vec<f64> {
        let csv = dir.path().join(format!("{device}.csv"));
        let mut args = vec!["--device", device, "--sigma", "0.5"];
        args.extend(extra);
        args.extend(["--history", csv.to_str().unwrap()]);
        let out = rocklab(&crate::cli_simulate::with(&args));
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = std::fs::read_to_string(&csv).unwrap();
        let mut lines = text.lines().filter(|l| !l.starts_with('#'));
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let it = header.iter().position(|c| *c == "t").unwrap();
        let ith = header.iter().position(|c| *c == "theta").unwrap();
        let (mut t, mut th) = (Vec::new(), Vec::new());
        for l in lines {
            let f: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            t.push(f[it]);
            th.push(f[ith]);
        }
        fair::DECAY_FRACTIONS
            .iter()
            .map(|&f| fair::envelope_time(&t, &th, f))
            .collect()
    };
    let (seq, mech) = (
        times("sequential", &[]),
        times("mechanistic", &["--cbar", "1"]),
    );
    for (k, f) in fair::DECAY_FRACTIONS.iter().enumerate() {
        let pct = format!("{:.0}", 100.0 * f);
        let a = value(&row, &format!("claimed faster: time to {pct} % (s)"));
        let b = value(&row, &format!("other: time to {pct} % (s)"));
        assert!(
            (a - seq[k]).abs() < 1e-9,
            "sequential to {pct} %: row {a}, CLI {}",
            seq[k]
        );
        assert!(
            (b - mech[k]).abs() < 1e-9,
            "mechanistic to {pct} %: row {b}, CLI {}",
            mech[k]
        );
    }
}

/// Peaks in the rows are the simulator's: Fig. 5's Dirac convergence recomputed here.
#[test]
fn fig5_row_numbers_are_the_simulators() {
    use rocklab::presets::rigid_fig8;
    use rocklab::scene::{Device, Impact, Scene};
    let lib = rocklab::excitation::library::global().unwrap();
    let run = |impact| {
        let s = Scene {
            impact,
            rtol: 1e-8,
            ..rigid_fig8(Device::None)
        };
        rocklab::sim::run(&s, lib).unwrap().peak_rotation_ratio
    };
    let (h, d) = (run(Impact::default()), run(Impact::Dirac { width: 1e-4 }));
    let row = paper::row("fig5-converge").unwrap();
    assert_eq!(value(&row, "value"), d);
    assert_eq!(value(&row, "limit"), h);
    assert!((value(&row, "relative difference") - (d - h).abs() / h).abs() < 1e-15);
}

// The fair checks on series whose answers are known.

#[test]
fn immaterial_share_is_of_the_reference_peak() {
    let a: fair::Series = vec![Some(1.0), Some(4.0), Some(2.0)];
    let b: fair::Series = vec![Some(1.2), Some(4.1), Some(2.0)];
    let j = fair::immaterial(&a, &[("b", &b)]);
    // Largest |difference| 0.2 over the peak 4.
    assert!((j.value("b: largest difference / reference peak").unwrap() - 0.05).abs() < 1e-12);
    assert_eq!(j.verdict, Agreement::Agrees);
    let c: fair::Series = vec![Some(1.0), None, Some(2.0)];
    let j = fair::immaterial(&a, &[("c", &c)]);
    assert_eq!(j.value("c: overturning flips").unwrap(), 1.0);
    // A name the check did not report is an error, never a NaN that f64::max would drop.
    assert!(j.value("c: overturning flip").is_err());
    assert_eq!(j.verdict, Agreement::Roughly, "a flip caps the verdict");
    // 25 % at one point of three, nothing elsewhere: the verdict rests on that point, so
    // roughly, and the gap says so.
    let d: fair::Series = vec![Some(1.0), Some(3.0), Some(2.0)];
    let j = fair::immaterial(&a, &[("d", &d)]);
    assert_eq!(j.verdict, Agreement::Roughly);
    assert!(j.gap.contains("at one point only"), "{}", j.gap);
    // 25 % and 12.5 % at two points: above the threshold twice, and above "roughly" once.
    let e: fair::Series = vec![Some(1.5), Some(3.0), Some(2.0)];
    assert_eq!(
        fair::immaterial(&a, &[("e", &e)]).verdict,
        Agreement::Disagrees
    );
}

#[test]
fn envelope_time_of_a_decaying_oscillation() {
    // e^{−t}|cos(2π·10 t)|: peaks at every 0.05 s; the last sample with |y| ≥ f is the last
    // crest before ln(1/f).
    let t: Vec<f64> = (0..100_001).map(|i| i as f64 * 1e-4).collect();
    let y: Vec<f64> = t
        .iter()
        .map(|t| (-t).exp() * (2.0 * std::f64::consts::PI * 10.0 * t).cos())
        .collect();
    for f in fair::DECAY_FRACTIONS {
        let got = fair::envelope_time(&t, &y, f);
        let expected = (1.0 / f).ln();
        assert!(
            got <= expected && got > expected - 0.05,
            "f {f}: {got} vs {expected}"
        );
    }
}

#[test]
fn gap_shrinks_reads_the_plotted_difference() {
    let xs: Vec<f64> = (0..9).map(|i| i as f64).collect();
    // The reference falls as 1/(1 + x)², the variant is 10 % below at the start and 25 % at
    // the end: the ratio moves away from 1 but the plotted gap shrinks (0.1 of the peak at
    // x = 0, under 0.01 from x = 3 on).
    let a: fair::Series = xs.iter().map(|x| Some(1.0 / (1.0 + x).powi(2))).collect();
    let b: fair::Series = a
        .iter()
        .zip(&xs)
        .map(|(a, x)| Some(a.unwrap() * (0.9 - 0.15 * x / 8.0)))
        .collect();
    let j = fair::gap_shrinks(&xs, &a, &b);
    assert_eq!(j.verdict, Agreement::Agrees);
    // First third x = 0, 1, 2: gaps 0.1, 0.11875/4, 0.1375/9 of the peak 1.
    let first = (0.1 + 0.11875 / 4.0 + 0.1375 / 9.0) / 3.0;
    assert!(
        (j.value("mean |difference| / reference peak, third 1 (x 0.00–2.00)")
            .unwrap()
            - first)
            .abs()
            < 1e-12
    );
    assert_eq!(
        fair::gap_shrinks(&xs, &b, &b).verdict,
        Agreement::Disagrees,
        "no gap never shrinks"
    );
    // A constant offset of 5 % of the peak everywhere: no trend.
    let c: fair::Series = a.iter().map(|a| Some(a.unwrap() + 0.05)).collect();
    assert_eq!(fair::gap_shrinks(&xs, &a, &c).verdict, Agreement::Disagrees);
}

#[test]
fn the_dead_band_keeps_fifth_digits_from_deciding() {
    let one: fair::Series = vec![Some(1.0), Some(1.0)];
    // fig14-clutch-deformation's case: one clutch a hair above, one a hair below.
    let hair: fair::Series = vec![Some(1.000_000_4), Some(0.999_998_8)];
    let j = fair::compare(fair::Relation::SlightlyLower, &one, &hair);
    assert_eq!(j.verdict, Agreement::Roughly, "no measurable reduction");
    assert_eq!(j.value("share above").unwrap(), 0.0);
    assert_eq!(j.value("share below").unwrap(), 0.0);
    let lower: fair::Series = vec![Some(0.95), Some(0.9)];
    let j = fair::compare(fair::Relation::SlightlyLower, &one, &lower);
    assert_eq!(j.verdict, Agreement::Agrees);
    assert_eq!(
        fair::compare(
            fair::Relation::Larger,
            &one,
            &vec![Some(1.005), Some(1.009)]
        )
        .verdict,
        Agreement::Disagrees,
        "half a per cent is not larger"
    );
}

#[test]
fn immaterial_says_when_one_point_carries_the_verdict() {
    let a: fair::Series = vec![Some(1.0), Some(1.0), Some(1.0), Some(1.0)];
    // fig19-operational-immaterial's shape: one point 28.6 % off, the rest ≤ 6.9 %.
    let b: fair::Series = vec![Some(1.286), Some(1.069), Some(0.95), Some(1.0)];
    let j = fair::immaterial(&a, &[("b", &b)]);
    assert!((j.value("b: largest difference / reference peak").unwrap() - 0.286).abs() < 1e-12);
    assert!(
        (j.value("b: largest difference but one / reference peak")
            .unwrap()
            - 0.069)
            .abs()
            < 1e-12
    );
    assert_eq!(j.verdict, Agreement::Roughly);
    assert!(j.gap.contains("one point only"), "{}", j.gap);
    // Two points over: disagrees.
    let c: fair::Series = vec![Some(1.286), Some(1.25), Some(1.0), Some(1.0)];
    assert_eq!(
        fair::immaterial(&a, &[("c", &c)]).verdict,
        Agreement::Disagrees
    );
    // Within a point of the threshold the row says so, and still agrees.
    let d: fair::Series = vec![Some(1.095), Some(1.0), Some(1.0), Some(1.0)];
    let j = fair::immaterial(&a, &[("d", &d)]);
    assert_eq!(j.verdict, Agreement::Agrees);
    assert!(j.gap.contains("within a point"), "{}", j.gap);
}

#[test]
fn constant_offset_is_judged_per_third() {
    let xs: Vec<f64> = (0..9).map(|i| i as f64).collect();
    let a: fair::Series = vec![Some(1.0); 9];
    let flat: fair::Series = vec![Some(0.92); 9];
    let j = fair::constant_offset(&xs, &[(&a, &flat)], 0.08);
    assert_eq!(j.verdict, Agreement::Agrees);
    // 0.92 on average, but 0.80 / 0.92 / 1.04 by third: not constant.
    let tilted: fair::Series = (0..9).map(|i| Some([0.80, 0.92, 1.04][i / 3])).collect();
    let j = fair::constant_offset(&xs, &[(&a, &tilted)], 0.08);
    assert!((j.value("mean ratio, third 1 (x 0–2)").unwrap() - 0.80).abs() < 1e-12);
    assert_eq!(j.verdict, Agreement::Disagrees);
}
