//! Intensity measures (`excitation::ims`): `rocklab records --ims`, the FEMA P695 near-field
//! records' pulse calls against FEMA's pulse / no-pulse split, and the Sa / Sa_avg / Arias
//! scalings of a study.

use crate::util::{rocklab, rocklab_json};
use rocklab::excitation::Library;
use rocklab::excitation::ims::{self, Accelerogram};
use rocklab::scene::{Excitation, RecordScale};
use std::path::PathBuf;

fn records_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("records")
}

fn accelerogram(name: &str) -> Accelerogram {
    let lib = Library::open(Some(records_dir())).unwrap();
    Accelerogram::from_series(&lib.load(name, false).unwrap().series).unwrap()
}

/// Every near-field component's JSON row has the IM keys, Sa aligned with the periods and
/// RotD50 between the two components' Sa; Tp only where pulse-like.
#[test]
fn records_ims_json_lists_every_measure() {
    let dir = records_dir();
    let list = rocklab_json(&[
        "records",
        "--records-dir",
        dir.to_str().unwrap(),
        "--suite",
        "near_field",
        "--ims",
        "--periods",
        "0.5,1.0,2.0",
        "--json",
    ]);
    let rows = list.as_array().unwrap();
    assert_eq!(rows.len(), 56);
    for r in rows {
        for key in [
            "pga_g",
            "pgv_m_s",
            "pgd_m",
            "arias_m_s",
            "cav_m_s",
            "d5_75_s",
            "d5_95_s",
            "tm_s",
        ] {
            assert!(r[key].as_f64().is_some_and(|v| v > 0.0), "{key}: {r}");
        }
        assert_eq!(r["periods_s"], serde_json::json!([0.5, 1.0, 2.0]));
        assert_eq!(r["sa_g"].as_array().unwrap().len(), 3);
        assert!(r["d5_75_s"].as_f64() < r["d5_95_s"].as_f64());
        assert_eq!(
            r["pulse_like"].as_bool().unwrap(),
            !r["tp_s"].is_null(),
            "{r}"
        );
        // PGA in g as index.csv gives it; PGV at standard gravity, never below the index's
        // sample maximum and at most PGA·dt/2 above it.
        let pga = r["pga_g"].as_f64().unwrap();
        assert!((pga / r["index_pga_g"].as_f64().unwrap() - 1.0).abs() < 2e-6);
        let excess = r["pgv_m_s"].as_f64().unwrap() - r["index_pgv"].as_f64().unwrap();
        let dt = r["dt"].as_f64().unwrap();
        assert!((-1e-9..=0.5 * pga * 9.80665 * dt).contains(&excess), "{r}");
        // RotD50 lies between the smaller and the larger... of the rotated peaks, so at least
        // the smaller of the two as-recorded components' Sa times cos 45° and at most their
        // vector sum.
        let rot = r["rotd50_g"].as_array().expect("both components listed");
        let mate = rows
            .iter()
            .find(|m| {
                m["record_id"] == r["record_id"] && m["set"] == r["set"] && m["name"] != r["name"]
            })
            .unwrap();
        for i in 0..3 {
            let (a, b) = (
                r["sa_g"][i].as_f64().unwrap(),
                mate["sa_g"][i].as_f64().unwrap(),
            );
            let x = rot[i].as_f64().unwrap();
            assert!(
                x <= (a * a + b * b).sqrt() + 1e-12 && x >= a.min(b) * 0.5f64.sqrt(),
                "{r}"
            );
        }
    }
}

/// FEMA P695's near-field sets split records into pulse and no-pulse by Baker's (2007)
/// classification of the fault-normal component (`a`). rocklab's Shahi & Baker (2014) calls
/// agree with that split on 22 of the 28 records, whether a record counts as pulse-like by
/// its `a` component or by either component (measured; 79 %; the earlier extraction, ten
/// wavelets on the L²-normalised transform, agreed on 16 by the `a` component, calling 11
/// of the 14 no-pulse records pulse-like). The disagreements, all pulse records that rocklab
/// does not call pulse-like: Irpinia Sturno (3), Loma Prieta Saratoga (5), Cape Mendocino
/// Petrolia (7), Kocaeli Izmit (11, PGV 0.23–0.30 m/s, which the indicator's PGV term
/// counts against), Chi-Chi TCU102 (13) and Duzce (14) by the `a` component; by either
/// component Duzce's `b` is pulse-like and Kocaeli Yarimca (25, no-pulse set) is, by its `b`.
#[test]
fn near_field_pulse_calls_follow_femas_split() {
    let dir = records_dir();
    let list = rocklab_json(&[
        "records",
        "--records-dir",
        dir.to_str().unwrap(),
        "--suite",
        "near_field",
        "--ims",
        "--periods",
        "1.0",
        "--json",
    ]);
    // record -> (FEMA's pulse set, our call on `a`, our call on either component)
    let mut records: std::collections::BTreeMap<String, (bool, bool, bool)> = Default::default();
    let mut calls = Vec::new();
    for r in list.as_array().unwrap() {
        let name = r["name"].as_str().unwrap();
        let record = name.trim_end_matches(['a', 'b']).to_string();
        let fema = r["pulse"].as_bool().unwrap();
        let ours = r["pulse_like"].as_bool().unwrap();
        let entry = records.entry(record).or_insert((fema, false, false));
        assert_eq!(entry.0, fema, "{name}");
        if r["component"] == "a" {
            entry.1 = ours;
        }
        entry.2 |= ours;
        calls.push(format!("{name} fema {fema} ours {ours} tp {}", r["tp_s"]));
    }
    assert_eq!(records.len(), 28);
    let by_a = records.values().filter(|(f, a, _)| f == a).count();
    let by_either = records.values().filter(|(f, _, e)| f == e).count();
    assert!(
        by_a >= 22 && by_either >= 22,
        "{by_a}/28 and {by_either}/28 agree:\n{}",
        calls.join("\n")
    );
}

/// `scale_to: sa(period: T)`, `sa_avg(from:, to:)` and `arias` give each scene the factor that
/// takes the record to the target, which the IMs of the scaled samples confirm.
#[test]
fn studies_scale_records_to_sa_sa_avg_and_arias() {
    for (scale_to, target, measure) in [
        (
            "sa(period: 1.0)",
            0.4,
            (&|r: &Accelerogram| {
                ims::spectrum::sa(r, &[1.0], 0.05).unwrap()[0] / ims::STANDARD_GRAVITY
            }) as &dyn Fn(&Accelerogram) -> f64,
        ),
        (
            "sa(period: 0.5, damping: 0.02)",
            0.7,
            &|r: &Accelerogram| {
                ims::spectrum::sa(r, &[0.5], 0.02).unwrap()[0] / ims::STANDARD_GRAVITY
            },
        ),
        ("sa_avg(from: 0.5, to: 2.0)", 0.3, &|r: &Accelerogram| {
            ims::spectrum::sa_avg(r, 0.5, 2.0, 0.05).unwrap() / ims::STANDARD_GRAVITY
        }),
        ("arias", 1.5, &|r: &Accelerogram| ims::arias(r)),
    ] {
        let s = rocklab::study::Study::from_ron_str(
            &format!(
                "(version: 1, name: \"s\", structure: rigid(p: 2.0, alpha: 0.2), devices: [none], \
                 excitation: record(suite: (name: \"far_field\", records: [7]), scale: {target}, \
                 scale_to: {scale_to}), spectrum: scale, duration: 30.0)"
            ),
            "s.ron",
        )
        .unwrap();
        let points = s.expand().unwrap();
        assert_eq!(points.len(), 2);
        for p in &points {
            let Excitation::Record { name, scale, .. } = &p.scene.excitation else {
                panic!()
            };
            let RecordScale::Factor(k) = scale else {
                panic!("{scale:?}")
            };
            let rec = accelerogram(name);
            let scaled =
                Accelerogram::new(rec.dt, rec.accel.iter().map(|a| a * k).collect()).unwrap();
            let got = measure(&scaled);
            assert!(
                (got / target - 1.0).abs() < 1e-12,
                "{scale_to} {name}: {got}"
            );
        }
    }
}

#[test]
fn bad_im_scalings_and_periods_are_clear_errors() {
    let e = rocklab::study::Study::from_ron_str(
        "(version: 1, name: \"s\", structure: rigid(p: 2.0, alpha: 0.2), devices: [none], \
         excitation: record(names: [\"landers\"], scale: 0.3, scale_to: sa(period: -1.0)), \
         spectrum: scale, duration: 30.0)",
        "s.ron",
    )
    .unwrap_err();
    assert_eq!(e.field.as_deref(), Some("excitation.scale_to"), "{e}");
    assert!(e.to_string().contains("period -1"), "{e}");
    let out = rocklab(&[
        "records",
        "--suite",
        "table1",
        "--ims",
        "--periods",
        "0.5,-2",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--periods: -2"));
}

/// Every FEMA P695 component's IMs against eqsig 1.2.17 (an independent implementation;
/// `scripts/ims-reference.py` wrote tests/data/fema_ims_eqsig.json). Where the conventions
/// differ the bound says by how much: eqsig's PGV is the largest sample of the trapezoid
/// velocity (rocklab's the continuous peak: never below, at most PGA·dt/2 above), its
/// displacement integrates the velocity by the trapezoid rule (rocklab's is exact: at sample
/// n the two differ by (a₀ − aₙ)dt²/12, and the continuous peak exceeds the samples' by at
/// most PGA·dt²/8), its durations are read at samples (rocklab interpolates: within a dt).
/// The issue's own PGV and PGD (exact integration, continuous peaks) are written again in
/// numpy in the script (`pgv_exact_m_s`, `pgd_exact_m`) and must agree to rounding: a
/// relative 1e-3 on eqsig's PGD failed on far_field/15b (dt 0.02 s), where that numpy
/// version confirmed rocklab's 0.207753 m against eqsig's trapezoid 0.207501 m.
#[test]
fn fema_components_match_an_independent_implementation() {
    let text = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/fema_ims_eqsig.json"),
    )
    .unwrap();
    let reference: serde_json::Value = serde_json::from_str(&text).unwrap();
    let periods: Vec<f64> = serde_json::from_value(reference["periods_s"].clone()).unwrap();
    let components = reference["components"].as_object().unwrap();
    assert_eq!(components.len(), 100);
    let rel = |a: f64, b: f64| (a / b - 1.0).abs();
    for (name, want) in components {
        let rec = accelerogram(name);
        let f = |key: &str| want[key].as_f64().unwrap();
        let dt = rec.dt;
        let kin = ims::kinematics(&rec);
        let pga = rec.accel.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
        assert!(
            rel(pga / ims::STANDARD_GRAVITY, f("pga_g")) < 1e-12,
            "{name}"
        );
        let excess = kin.pgv - f("pgv_m_s");
        assert!(
            (-1e-12..=0.5 * pga * dt).contains(&excess),
            "{name}: PGV {excess}"
        );
        let gap = kin.pgd - f("pgd_m");
        let step = pga * dt * dt;
        assert!(
            (-step / 6.0 - 1e-12..=step * (1.0 / 8.0 + 1.0 / 6.0) + 1e-12).contains(&gap),
            "{name}: PGD {} eqsig {}",
            kin.pgd,
            f("pgd_m")
        );
        assert!(
            rel(kin.pgv, f("pgv_exact_m_s")) < 1e-9,
            "{name}: PGV {} exact {}",
            kin.pgv,
            f("pgv_exact_m_s")
        );
        assert!(
            rel(kin.pgd, f("pgd_exact_m")) < 1e-9,
            "{name}: PGD {} exact {}",
            kin.pgd,
            f("pgd_exact_m")
        );
        assert!(
            rel(ims::arias(&rec), f("arias_m_s")) < 1e-10,
            "{name}: Arias"
        );
        assert!(rel(ims::cav(&rec), f("cav_m_s")) < 1e-10, "{name}: CAV");
        for (from, to, key) in [(0.05, 0.75, "d5_75_s"), (0.05, 0.95, "d5_95_s")] {
            let d = ims::significant_duration(&rec, from, to);
            assert!(
                (d - f(key)).abs() <= 2.0 * dt + 1e-9,
                "{name}: {key} {d} {}",
                f(key)
            );
        }
        let sa = ims::spectrum::sa(&rec, &periods, 0.05).unwrap();
        for (i, s) in sa.iter().enumerate() {
            let r = want["sa_g"][i].as_f64().unwrap();
            assert!(
                rel(s / ims::STANDARD_GRAVITY, r) < 1e-6,
                "{name}: Sa({}) {s} {r}",
                periods[i]
            );
        }
    }
}
