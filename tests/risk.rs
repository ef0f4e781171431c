//! Seismic risk end to end: a fragility study with a `risk` section writes risk.csv whose MAF
//! for every fitted curve is Cornell et al.'s closed form k0 θ^−k exp(k²β²/2) over the
//! power-law hazard it was given (θ the fitted median converted from PGA* to PGA), and
//! `rocklab risk` on the same results with the same hazard writes the same risk.csv; a hazard
//! in the wrong intensity measure is refused naming the file and its header.

use std::path::Path;

/// 44 far-field components × 3 stripes × 2 variants = 264 scenes.
const STUDY: &str = r#"(
    version: 1,
    name: "risk_run",
    structure: rigid(p: 2.0, alpha: 0.2),
    devices: [none, mechanistic(sigma: 0.5)],
    excitation: record(suite: (name: "far_field"), scale: [2.0, 4.0, 8.0], scale_to: pga_star, tail: 10.0),
    quantities: [peak_rotation_ratio],
    spectrum: scale,
    fragility: (damage_states: levels([0.5, 1.0]), bootstrap: 100, seed: 3),
    risk: (hazard: "site.csv", years: 30.0, mce: 0.7, beta_total: 0.5),
)"#;

const K0: f64 = 2.0e-4;
const K: f64 = 2.6;

/// λ = K0 PGA^−K at 60 points from 0.005 g to 20 g: the closed form's integrand lies inside.
fn write_hazard(path: &Path, header: &str) {
    let mut text = format!("# a power law for the test\n{header},annual_rate\n");
    for i in 0..60 {
        let x = 0.005 * (4000f64).powf(i as f64 / 59.0);
        text.push_str(&format!("{x},{:e}\n", K0 * x.powf(-K)));
    }
    std::fs::write(path, text).unwrap();
}

fn column(header: &csv::StringRecord, name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("{name}"))
}

#[test]
fn a_risk_section_and_the_risk_command_give_cornells_closed_form() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("risk_run.ron");
    std::fs::write(&study, STUDY).unwrap();
    write_hazard(&dir.path().join("site.csv"), "pga");
    let out = dir.path().join("out");
    let o = crate::util::run_into(study.to_str().unwrap(), &out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let fragility: rocklab::report::fragility::FragilityReport =
        serde_json::from_str(&std::fs::read_to_string(out.join("fragility.json")).unwrap())
            .unwrap();
    let section = std::fs::read_to_string(out.join("risk.csv")).unwrap();
    let mut reader = csv::Reader::from_reader(section.as_bytes());
    let header = reader.headers().unwrap().clone();
    let rows: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), fragility.curves.len());
    let tan = 0.2f64.tan();
    let mut fitted = 0;
    for (row, curve) in rows.iter().zip(&fragility.curves) {
        let (Some(median), Some(beta)) = (curve.median, curve.beta) else {
            assert_eq!(&row[column(&header, "maf")], "");
            continue;
        };
        fitted += 1;
        // PGA* = PGA/tan α: the median in g is the PGA* median times tan α.
        let theta = median * tan;
        let closed = K0 * theta.powf(-K) * (K * K * beta * beta / 2.0).exp();
        let maf: f64 = row[column(&header, "maf")].parse().unwrap();
        // The table starts at 0.005 g: with what its first segment continued below would add,
        // the MAF is the closed form to rounding; without it, within 1e-4 where that share is
        // negligible (a wide fit could leave more below the table).
        let below: f64 = row[column(&header, "share_below_table")].parse().unwrap();
        let whole = maf / (1.0 - below);
        assert!((whole / closed - 1.0).abs() < 1e-9, "{whole} vs {closed}");
        if below < 1e-6 {
            assert!((maf / closed - 1.0).abs() < 1e-4, "{maf} vs {closed}");
        }
        let lo: f64 = row[column(&header, "maf_lo")].parse().unwrap();
        let hi: f64 = row[column(&header, "maf_hi")].parse().unwrap();
        assert!(0.0 < lo && lo <= hi, "{lo} {hi}");
        let p: f64 = row[column(&header, "p_years")].parse().unwrap();
        assert!((p - (1.0 - (-30.0 * maf).exp())).abs() < 1e-15);
    }
    assert!(fitted >= 3, "{fitted} fitted curves");
    // The overturning rows carry the P695 margin: CMR = median (g) / 0.7.
    let top = rows
        .iter()
        .zip(&fragility.curves)
        .filter(|(_, c)| c.damage_state == 1.0 && c.median.is_some());
    for (row, curve) in top {
        let cmr: f64 = row[column(&header, "cmr")].parse().unwrap();
        assert!((cmr - curve.median.unwrap() * tan / 0.7).abs() < 1e-12);
    }
    assert!(out.join("risk.svg").exists());

    // The command on the same results and hazard: the same table.
    let again = dir.path().join("again");
    let hazard = dir.path().join("site.csv");
    let o = crate::util::rocklab(&[
        "risk",
        out.to_str().unwrap(),
        "--hazard",
        hazard.to_str().unwrap(),
        "--years",
        "30",
        "--mce",
        "0.7",
        "--beta-total",
        "0.5",
        "--out",
        again.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        std::fs::read_to_string(again.join("risk.csv")).unwrap(),
        section
    );
    let printed = String::from_utf8_lossy(&o.stdout);
    assert!(printed.contains("MAF (1/yr)"), "{printed}");

    // A PGV hazard for a PGA* study: refused, naming the file and the header.
    let pgv = dir.path().join("pgv.csv");
    write_hazard(&pgv, "pgv");
    let o = crate::util::rocklab(&[
        "risk",
        out.to_str().unwrap(),
        "--hazard",
        pgv.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("pgv.csv") && err.contains("`pgv`") && err.contains("hint"),
        "{err}"
    );
}
