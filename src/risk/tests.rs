//! The risk of whole fragility reports: conversions, intervals, pairing, margins.

use super::*;
use crate::stats::tests::{capacities, ida_obs, variant};
use crate::stats::{FragilityOptions, analyse_ida};

pub(crate) fn power_law_hazard(k0: f64, k: f64) -> HazardCurve {
    let x: Vec<f64> = (0..40).map(|i| 0.002 * 1.3f64.powi(i)).collect();
    HazardCurve {
        im: HazardIm::Pga,
        rate: x.iter().map(|x| k0 * x.powf(-k)).collect(),
        x,
    }
}

/// Bare capacities (in PGA*) median 3, the inerter's 1.6 times higher.
pub(crate) fn report() -> FragilityReport {
    let bare = capacities(11, 40, 3.0, 0.4);
    let protected: Vec<f64> = bare.iter().map(|c| 1.6 * c).collect();
    let mut obs = ida_obs(&variant("none"), &bare, 1e3);
    obs.extend(ida_obs(&variant("inerter"), &protected, 1e3));
    let opts = FragilityOptions {
        damage_states: vec![1.0],
        bootstrap: 200,
        ..Default::default()
    };
    analyse_ida(&obs, &opts)
}

pub(crate) fn options() -> RiskOptions {
    RiskOptions {
        years: 50.0,
        mce: Some(0.5),
        beta_total: Some(0.525),
    }
}

#[test]
fn risk_converts_the_hazard_im_and_follows_cornells_form() {
    let (k0, k) = (1e-4, 2.4);
    let hazard = power_law_hazard(k0, k);
    let report = report();
    // PGA* = PGA/tan α: the hazard in g becomes the study's measure with factor 1/tan 0.2.
    let factor = 1.0 / 0.2f64.tan();
    let risk = assess(&report, &hazard, "test", |_| Some(factor), &options());
    assert_eq!(risk.rows.len(), 2);
    for (row, curve) in risk.rows.iter().zip(&report.curves) {
        let (theta, beta) = (curve.median.unwrap() / factor, curve.beta.unwrap());
        let closed = k0 * theta.powf(-k) * (k * k * beta * beta / 2.0).exp();
        let maf = row.maf.unwrap();
        assert!((maf / closed - 1.0).abs() < 1e-4, "{maf} vs {closed}");
        let (lo, hi) = (row.maf_lo.unwrap(), row.maf_hi.unwrap());
        assert!(lo < maf && maf < hi, "{lo} {maf} {hi}");
        assert!((row.p_years.unwrap() - (1.0 - (-50.0 * maf).exp())).abs() < 1e-15);
        assert_eq!(row.n_resamples, 200);
    }
    // Capacities 1.6 times higher in every record: the ratio of MAFs is 1.6^−k in every
    // resample (the same β), so its interval collapses onto it.
    let ratio = risk.rows[1].ratio_to_bare.unwrap();
    let expected = 1.6f64.powf(-k);
    assert!(
        (ratio / expected - 1.0).abs() < 1e-6,
        "{ratio} vs {expected}"
    );
    assert!((risk.rows[1].ratio_lo.unwrap() / expected - 1.0).abs() < 1e-6);
    assert!((risk.rows[1].ratio_hi.unwrap() / expected - 1.0).abs() < 1e-6);
    assert!(risk.rows[0].ratio_to_bare.is_none());
    // Margins on the collapse state: CMR = median (in g) / MCE.
    assert_eq!(risk.margins.len(), 2);
    let m = &risk.margins[0].margin;
    assert!((m.cmr - report.curves[0].median.unwrap() / factor / 0.5).abs() < 1e-12);
    assert!((m.acmr_10 - p695::acmr(0.525, 0.1)).abs() < 1e-15);
}

#[test]
fn no_conversion_or_no_fit_is_a_status_not_a_number() {
    let hazard = power_law_hazard(1e-4, 2.0);
    let mut report = report();
    report.curves[1].status = FitStatus::NoExceedance;
    let risk = assess(
        &report,
        &hazard,
        "test",
        |v| (!v.is_bare()).then_some(1.0),
        &options(),
    );
    assert_eq!(risk.rows[0].status, "no_im_conversion");
    assert_eq!(risk.rows[1].status, "no_exceedance");
    assert!(risk.rows.iter().all(|r| r.maf.is_none()));
}

#[test]
fn doubtful_fits_are_flagged() {
    let mut report = report();
    let original = report.curves[0].clone();
    assert!(original.warnings().is_empty());
    let c = &mut report.curves[0];
    c.median = Some(c.im_range.unwrap()[1] * 2.0);
    c.bootstrap_degenerate = 3;
    assert_eq!(
        c.warnings(),
        ["median_above_data", "degenerate_resamples=3"]
    );
    // A median interval wider (as a ratio) than the data's span.
    c.median = Some(2.0);
    c.im_range = Some([1.0, 4.0]);
    (c.median_lo, c.median_hi) = (Some(0.5), Some(3.0));
    c.bootstrap_degenerate = 0;
    assert_eq!(c.warnings(), ["interval_wider_than_data"]);
    report.curves[0] = original;
    let hazard = power_law_hazard(1e-4, 2.0);
    // A table that starts at the bare median: most of the risk lies below it.
    let short = HazardCurve {
        im: HazardIm::Pga,
        x: vec![2.0, 4.0],
        rate: vec![1e-4, 2e-5],
    };
    let risk = assess(&report, &short, "short", |_| Some(1.0), &options());
    assert!(
        risk.warnings.iter().any(|w| w.contains("below 2 g")),
        "{:?}",
        risk.warnings
    );
    let fine = assess(&report, &hazard, "fine", |_| Some(1.0), &options());
    assert!(fine.warnings.is_empty(), "{:?}", fine.warnings);
}

/// A study with uncertain parameters gives each variant's margin its own fitted total β when
/// none is given; without them, no β means no margins.
#[test]
fn margins_take_the_fitted_total_beta_of_an_uncertain_study() {
    let hazard = power_law_hazard(1e-4, 2.4);
    let mut report = report();
    let opts = RiskOptions {
        beta_total: None,
        ..options()
    };
    let plain = assess(&report, &hazard, "plain", |_| Some(1.0), &opts);
    assert!(plain.margins.is_empty());
    report.uncertainty = "α ~ normal(mean 0.2, sd 0.01)".into();
    let risk = assess(&report, &hazard, "uncertain", |_| Some(1.0), &opts);
    assert_eq!(risk.margins.len(), 2);
    for (m, c) in risk.margins.iter().zip(&report.curves) {
        let beta = c.beta.unwrap();
        assert_eq!(m.margin.beta_total, beta);
        assert!((m.margin.acmr_20 - p695::acmr(beta, 0.2)).abs() < 1e-15);
    }
}
