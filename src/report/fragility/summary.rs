//! The fragility report as summary text: one line per variant and damage state with the
//! median (named as the intensity measure it is a value of, e.g. "median PGA*"), β, the ratio
//! to the bare variant, and a warning where the median is extrapolated beyond the data.
//! `rocklab run` prints it and summary.txt holds it.

use super::{Curve, FragilityReport};
use crate::numfmt::fmt_digits;
use std::fmt::Write as _;

/// A fitted number to three significant digits.
pub fn fmt_fit(v: f64) -> String {
    fmt_digits(v, 3)
}

/// `3.12 [2.8, 3.5]`, the value alone without an interval, or `–` without a value.
pub fn with_interval(v: Option<f64>, lo: Option<f64>, hi: Option<f64>) -> String {
    match (v, lo, hi) {
        (Some(v), Some(lo), Some(hi)) => {
            format!("{} [{}, {}]", fmt_fit(v), fmt_fit(lo), fmt_fit(hi))
        }
        (Some(v), _, _) => fmt_fit(v),
        _ => "–".into(),
    }
}

/// A variant as a reader names it: the bare structure is `bare`, not the study's `none`.
pub fn variant_name(c: &Curve) -> String {
    let label = c.variant.label();
    match label.strip_prefix(crate::stats::BARE_DEVICE) {
        Some(rest) if c.variant.is_bare() => format!("bare{rest}"),
        _ => label,
    }
}

/// The damage state as a reader expects it named: `damage state θmax/α ≥ 1`.
pub fn damage_state_name(report: &FragilityReport, c: &Curve) -> String {
    let measure = if report.damage_measure.is_empty() {
        "damage measure"
    } else {
        &report.damage_measure
    };
    format!("damage state {measure} ≥ {}", fmt_fit(c.damage_state))
}

/// One curve's line (without indent or newline): the variant, the damage state by its
/// measure and threshold, then the fit.
pub fn curve_line(report: &FragilityReport, c: &Curve) -> String {
    let mut line = format!("{}, {}: ", variant_name(c), damage_state_name(report, c));
    if c.median.is_none() {
        line.push_str(c.status.explain());
        return line;
    }
    let _ = write!(
        line,
        "median {} {}, β {}",
        report.im_name(),
        with_interval(c.median, c.median_lo, c.median_hi),
        with_interval(c.beta, c.beta_lo, c.beta_hi)
    );
    if let (Some(m), Some(b)) = (c.median_records, c.beta_records) {
        let _ = write!(
            line,
            " (records alone: median {}, β {}",
            fmt_fit(m),
            fmt_fit(b)
        );
        match c.beta_parameters() {
            Some(p) => {
                let _ = write!(line, "; parameters add β {})", fmt_fit(p));
            }
            None => line.push(')'),
        }
    }
    if let Some(r) = report.ratio_of(c) {
        let _ = write!(
            line,
            ", {}× bare{}",
            with_interval(r.ratio, r.lo, r.hi),
            if r.curves_cross { ", crosses bare" } else { "" }
        );
    }
    if let Some(e) = c.extrapolation() {
        let _ = write!(line, "; WARNING: {}", e.explain());
    }
    line
}

/// The whole report as summary text, a header line then one line per curve.
pub fn summary_text(report: &FragilityReport) -> String {
    let mut text = String::new();
    let method = report.curves.first().map_or("", |c| c.method.name());
    let _ = writeln!(
        text,
        "fragility over {} ({method}, {} bootstrap resamples, {} % intervals):",
        if report.im.is_empty() {
            "IM"
        } else {
            &report.im
        },
        report.bootstrap,
        fmt_fit(100.0 * report.confidence)
    );
    if !report.uncertainty.is_empty() {
        let _ = writeln!(
            text,
            "  uncertain parameters: {}. β is the total (records and parameters), the \
             β_total `rocklab risk --mce` takes for FEMA P695 margins when none is given{}",
            report.uncertainty,
            if method == "ida" {
                " (an IDA runs no companions: no records-only β)."
            } else {
                "; \"records alone\" fits the deterministic companion scenes (every uncertain \
                 parameter at its centre)."
            }
        );
    }
    for c in &report.curves {
        let _ = writeln!(text, "  {}", curve_line(report, c));
    }
    text
}
