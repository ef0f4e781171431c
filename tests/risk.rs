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
    fragility: (damage_states: levels([0.5, 1.0]), bootstrap: 200, seed: 3),
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
        assert!(0.0 < lo && lo <= maf && maf <= hi, "{lo} {maf} {hi}");
        let p: f64 = row[column(&header, "p_years")].parse().unwrap();
        assert!((p - (1.0 - (-30.0 * maf).exp())).abs() < 1e-15);
    }
    assert!(fitted >= 3, "{fitted} fitted curves");
    // The ratio to bare at each state: the two rows' MAFs, and so Cornell's ratio
    // (θ/θb)^−k exp(k²(β² − βb²)/2) of the two fits.
    let mut ratios = 0;
    for (row, curve) in rows.iter().zip(&fragility.curves) {
        if curve.variant.is_bare() || curve.median.is_none() {
            continue;
        }
        let Some((brow, bare)) = rows.iter().zip(&fragility.curves).find(|(_, b)| {
            b.variant.is_bare() && b.damage_state == curve.damage_state && b.median.is_some()
        }) else {
            continue;
        };
        ratios += 1;
        let get = |r: &csv::StringRecord, name: &str| -> f64 {
            r[column(&header, name)].parse().unwrap()
        };
        let ratio = get(row, "maf_ratio");
        assert!((ratio / (get(row, "maf") / get(brow, "maf")) - 1.0).abs() < 1e-12);
        let (m, b) = (curve.median.unwrap(), curve.beta.unwrap());
        let (mb, bb) = (bare.median.unwrap(), bare.beta.unwrap());
        let closed = (m / mb).powf(-K) * (K * K * (b * b - bb * bb) / 2.0).exp();
        // Both MAFs are the closed form to within what lies below the table.
        let below = get(row, "share_below_table").max(get(brow, "share_below_table"));
        assert!(
            (ratio / closed - 1.0).abs() < 1e-9 + 2.0 * below,
            "{ratio} vs {closed}"
        );
        let (lo, hi) = (get(row, "maf_ratio_lo"), get(row, "maf_ratio_hi"));
        assert!(0.0 < lo && lo <= hi, "{lo} {hi}");
    }
    assert!(ratios >= 1, "no protected curve beside a fitted bare one");
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

    // P695 margins from Table 7-2's ratings (β_RTR = 0.4 at μT = 3, 0.2 at μT = 1): β_TOT as
    // Table 7-2 prints it, ACMR(p) = exp(√2 β erfc⁻¹(2p)) = exp(β z_{1−p}) with the standard
    // normal quantiles z_0.9 and z_0.8, and Table 7-3's two-decimal values.
    const Z90: f64 = 1.2815515655446004;
    const Z80: f64 = 0.8416212335729143;
    for (ratings, mu_t, beta, table_10, table_20) in [
        ("A,A,A", "3", 0.425, 1.72, 1.43),
        ("B,B,B", "3", 0.525, 1.96, 1.56),
        ("C,C,C", "3", 0.725, 2.53, 1.84),
        ("D,D,D", "3", 0.95, 3.38, 2.22),
        ("B,B,B", "1", 0.4, 1.67, 1.40),
    ] {
        let margins = dir.path().join(format!("p695-{ratings}-{mu_t}"));
        let o = crate::util::rocklab(&[
            "risk",
            out.to_str().unwrap(),
            "--hazard",
            hazard.to_str().unwrap(),
            "--mce",
            "0.7",
            "--ratings",
            ratings,
            "--mu-t",
            mu_t,
            "--out",
            margins.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let text = std::fs::read_to_string(margins.join("risk.csv")).unwrap();
        let mut reader = csv::Reader::from_reader(text.as_bytes());
        let header = reader.headers().unwrap().clone();
        let mut checked = 0;
        for row in reader.records().map(Result::unwrap) {
            if row[column(&header, "cmr")].is_empty() {
                continue;
            }
            checked += 1;
            let get = |name: &str| -> f64 { row[column(&header, name)].parse().unwrap() };
            assert!((get("beta_total") - beta).abs() < 1e-12, "{ratings}");
            let (a10, a20) = (get("acmr_10"), get("acmr_20"));
            assert!(
                ((beta * Z90).exp() / a10 - 1.0).abs() < 1e-12,
                "{ratings} {a10}"
            );
            assert!(
                ((beta * Z80).exp() / a20 - 1.0).abs() < 1e-12,
                "{ratings} {a20}"
            );
            assert!((a10 - table_10).abs() < 0.005 && (a20 - table_20).abs() < 0.005);
            let pass = get("cmr") * get("ssf") >= a10;
            assert_eq!(&row[column(&header, "pass_10")], pass.to_string());
        }
        assert!(checked >= 1, "no margin row for {ratings}");
    }

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
