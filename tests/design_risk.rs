//! The design inverse's risk target (`target: risk(state: d, maf_at_most: x)` with a `risk`
//! section): the answer checked by rerunning the suite at the answer and just below it,
//! fitting those scenes with the fragility report's own fit and integrating the fitted curve
//! over a power-law hazard by Cornell et al.'s closed form k0 θ^−k exp(k²β²/2) (θ in g =
//! the PGA* median × tan α), not by rocklab's integration; and bad risk targets refused.

use crate::design::run;
use crate::design_fragility::{SMALL, refit};
use rocklab::study::Study;
use rocklab::sweep::design::{DesignStatus, replay};

const K0: f64 = 1.41e-4;
const K: f64 = 2.95;
const TAN_ALPHA: f64 = 0.20271003550867248; // tan 0.2

/// λ = K0 PGA^−K at 80 points from 0.001 g to 50 g: the closed form's integrand lies inside.
fn hazard_text() -> String {
    let mut text = String::from("# a power law for the test (PGA in g)\npga,annual_rate\n");
    for i in 0..80 {
        let x = 0.001 * (50_000f64).powf(i as f64 / 79.0);
        text.push_str(&format!("{x},{:e}\n", K0 * x.powf(-K)));
    }
    text
}

/// SMALL (five records, six stripes, a sequential clutch sized) with `target` and a risk
/// section on the test's hazard, loaded from a file so the hazard's path resolves. The
/// bracket's top is 0.6: with five records no one overturns at σ = 3, and a curve without a
/// fit fails a risk target (its MAF is unknown).
fn study(dir: &std::path::Path, target: &str) -> Result<Study, String> {
    std::fs::write(dir.join("site.csv"), hazard_text()).unwrap();
    let text = SMALL
        .replace("fragility(state: 1.0, median_at_least: 6.5)", target)
        .replace("bracket: (0.0, 3.0)", "bracket: (0.0, 0.6)")
        .replace(
            "    design: (",
            "    risk: (hazard: \"site.csv\", years: 50.0),\n    design: (",
        );
    let path = dir.join("design_risk.ron");
    std::fs::write(&path, text).unwrap();
    Study::load(&path).map_err(|e| e.to_string())
}

/// Cornell's MAF of a fitted PGA* curve over the power law.
fn cornell(median: f64, beta: f64) -> f64 {
    K0 * (median * TAN_ALPHA).powf(-K) * (K * K * beta * beta / 2.0).exp()
}

#[test]
fn a_risk_target_is_met_at_the_answer_and_missed_just_below() {
    let dir = tempfile::tempdir().unwrap();
    for (target, bound) in [
        ("risk(state: 1.0, maf_at_most: 2e-4)", 2e-4),
        // 2 % in 50 years: MAF ≤ −ln(0.98)/50.
        (
            "risk(state: 1.0, p_years_at_most: 0.02)",
            -(0.98f64).ln() / 50.0,
        ),
    ] {
        let study = study(dir.path(), target).unwrap_or_else(|e| panic!("{e}"));
        let design = study.design.as_ref().unwrap();
        let rows = replay(&study, &run(&study).outcomes).unwrap();
        let bare = rows.iter().find(|r| r.device == "bare").unwrap();
        assert_eq!(bare.status, DesignStatus::ReferenceFails, "{bare:?}");
        let row = rows.iter().find(|r| r.device == "sequential").unwrap();
        assert_eq!(row.status, DesignStatus::Found, "{target}: {row:?}");
        let value = row.value.unwrap();
        assert!(value > 0.0 && row.hi - row.lo <= design.resolution * row.hi);
        let maf_at = |sigma: f64| {
            let c = refit(&study, row.variant, sigma, 1.0);
            cornell(c.median.unwrap(), c.beta.unwrap())
        };
        let at = maf_at(value);
        assert!(at <= bound, "{target}: MAF {at} at σ = {value}");
        // The final bracket's low end, within the resolution below the answer, fails.
        let below = row.lo;
        assert!(below > 0.0 && below < value, "{row:?}");
        let at_below = maf_at(below);
        assert!(at_below > bound, "{target}: MAF {at_below} at σ = {below}");
        // What the row achieved: the MAF (or its probability in 50 years) at the answer.
        let achieved = row.achieved.unwrap();
        let expected = if target.contains("p_years") {
            1.0 - (-50.0 * at).exp()
        } else {
            at
        };
        assert!(
            (achieved / expected - 1.0).abs() < 1e-6,
            "{achieved} vs {expected}"
        );
        // The governing text gives the MAF with its bootstrap interval around it.
        assert!(row.governing.starts_with("MAF "), "{}", row.governing);
        let interval = &row.governing[row.governing.find('[').unwrap() + 1..];
        let interval = &interval[..interval.find(']').unwrap()];
        let ends: Vec<f64> = interval.split(", ").map(|v| v.parse().unwrap()).collect();
        assert!(
            ends[0] <= at * 1.001 && at <= ends[1] * 1.001,
            "{}",
            row.governing
        );
    }
}

#[test]
fn bad_risk_targets_are_refused_naming_the_field() {
    let dir = tempfile::tempdir().unwrap();
    for (target, field) in [
        ("risk(state: 1.0)", "design.target"),
        (
            "risk(state: 1.0, maf_at_most: 1e-4, p_years_at_most: 0.02)",
            "design.target.p_years_at_most",
        ),
        (
            "risk(state: 1.0, maf_at_most: -1.0)",
            "design.target.maf_at_most",
        ),
        (
            "risk(state: 1.0, p_years_at_most: 1.0)",
            "design.target.p_years_at_most",
        ),
        ("risk(state: 0.7, maf_at_most: 1e-4)", "design.target.state"),
    ] {
        let err = study(dir.path(), target).unwrap_err();
        assert!(
            err.contains(field) && err.contains("hint"),
            "{target}: {err}"
        );
    }
    // Without a risk section there is no hazard: refused, with the section as the hint.
    let text = SMALL.replace(
        "fragility(state: 1.0, median_at_least: 6.5)",
        "risk(state: 1.0, maf_at_most: 1e-4)",
    );
    let err = Study::from_ron_str(&text, "no_site.ron")
        .unwrap_err()
        .to_string();
    assert!(err.contains("hazard") && err.contains("risk:"), "{err}");
    // A hazard in PGV for a PGA* study: refused when the search starts, naming the file.
    let pgv = hazard_text().replace("pga,annual_rate", "pgv,annual_rate");
    let study = study(dir.path(), "risk(state: 1.0, maf_at_most: 1e-4)").unwrap();
    std::fs::write(dir.path().join("site.csv"), pgv).unwrap();
    let err = rocklab::sweep::design::Search::new(&study)
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("site.csv") && err.contains("`pgv`"), "{err}");
}
