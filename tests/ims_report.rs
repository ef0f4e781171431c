//! `rocklab ims RESULTS`: the IM report of the shipped IDA study, checked against numbers
//! computed here from its ida.csv and from `rocklab records --ims` (an independent path to
//! the same definitions): β of the scaling IM is the spread of the capacities themselves, a
//! constant factor (PGA → PGA*) leaves β alone, and β of IM k is the spread of
//! ln(capacity × IM_k / PGA*) over the records.

use crate::util::{rocklab, rocklab_json};
use std::collections::HashMap;
use std::path::PathBuf;

fn sample_std(x: &[f64]) -> f64 {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    (x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
}

#[test]
fn ims_report_matches_capacities_and_record_ims() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("ims_ida_near_field");
    let study = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("studies/ims_ida_near_field.ron");
    let run = rocklab(&[
        "run",
        study.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let rows = rocklab_json(&["ims", out.to_str().unwrap(), "--json"]);
    let rows = rows.as_array().unwrap();
    let beta = |device: &str, ds: f64, im: &str| -> (f64, usize, serde_json::Value) {
        let r = rows
            .iter()
            .find(|r| r["device"] == device && r["damage_state"] == ds && r["im"] == im)
            .unwrap_or_else(|| panic!("no row {device} {ds} {im}"));
        for key in ["beta_lo", "beta_hi", "p_magnitude"] {
            assert!(r.get(key).is_some(), "{key}");
        }
        (
            r["beta"].as_f64().unwrap(),
            r["n"].as_u64().unwrap() as usize,
            r.clone(),
        )
    };
    // ida.csv's capacities (PGA*), per (device, damage state): (record, capacity).
    let mut caps: HashMap<(String, String), Vec<(String, f64)>> = HashMap::new();
    let mut reader = csv::Reader::from_path(out.join("ida.csv")).unwrap();
    let header = reader.headers().unwrap().clone();
    let col = |n: &str| header.iter().position(|h| h == n).unwrap();
    for rec in reader.records() {
        let rec = rec.unwrap();
        if &rec[col("status")] != "done" || &rec[col("censored")] == "true" {
            continue;
        }
        caps.entry((rec[col("device")].into(), rec[col("damage_state")].into()))
            .or_default()
            .push((
                rec[col("record")].into(),
                rec[col("capacity")].parse().unwrap(),
            ));
    }
    // The unscaled records' PGA and PGV from `records --ims`.
    let list = rocklab_json(&[
        "records",
        "--suite",
        "near_field_pulse",
        "--ims",
        "--periods",
        "1.0",
        "--json",
    ]);
    let im_of: HashMap<String, (f64, f64, f64)> = list
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            (
                r["name"].as_str().unwrap().to_string(),
                (
                    r["pga_g"].as_f64().unwrap(),
                    r["pgv_m_s"].as_f64().unwrap(),
                    r["sa_g"][0].as_f64().unwrap(),
                ),
            )
        })
        .collect();
    let mut checked = 0;
    for ((device, ds), list) in &caps {
        let ds: f64 = ds.parse().unwrap();
        let device = device.as_str();
        let ln_cap: Vec<f64> = list.iter().map(|(_, c)| c.ln()).collect();
        let (b_star, n, row) = beta(device, ds, "pga_star");
        assert_eq!(n, list.len());
        assert!(
            (b_star - sample_std(&ln_cap)).abs() < 1e-12,
            "{device} {ds}"
        );
        let (lo, hi) = (
            row["beta_lo"].as_f64().unwrap(),
            row["beta_hi"].as_f64().unwrap(),
        );
        assert!(lo <= hi && lo >= 0.0, "{row}");
        let (b_pga, _, _) = beta(device, ds, "pga");
        assert!((b_pga - b_star).abs() < 1e-12, "{device} {ds}");
        // capacity in IM k ∝ capacity × IM_k / PGA (PGA* = PGA / (g tan α), α fixed).
        for (im, k) in [("pgv", 1), ("sa(1.0)", 2)] {
            let logs: Vec<f64> = list
                .iter()
                .map(|(r, c)| {
                    let (pga, pgv, sa) = im_of[r];
                    let v = if k == 1 { pgv } else { sa };
                    (c * v / pga).ln()
                })
                .collect();
            let (b, _, _) = beta(device, ds, im);
            assert!(
                (b - sample_std(&logs)).abs() < 1e-9,
                "{device} {ds} {im}: {b}"
            );
        }
        checked += 1;
    }
    assert_eq!(checked, 4, "two devices × two damage states");
    // The ranked table lists every variant and damage state.
    let table = rocklab(&["ims", out.to_str().unwrap()]);
    assert!(table.status.success());
    let text = String::from_utf8_lossy(&table.stdout);
    assert!(text.contains("none damage state 0.5"), "{text}");
    assert!(text.contains("mechanistic damage state 1"), "{text}");
}
