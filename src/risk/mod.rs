//! Seismic risk from fragility: the mean annual frequency (MAF) of reaching each damage state
//! at a site, λ_DS = ∫ P(DS | x) |dλ(x)/dx| dx, from the site's hazard curve λ(x)
//! (`hazard.rs`, integrated exactly over its log-log interpolation in `maf.rs`), with an
//! interval from the fragility bootstrap's own resamples, the probability in a number of years
//! (Poisson, 1 − e^{−λ t}, OpenQuake's poe), the ratio to the bare structure, the deaggregation
//! of the integrand, and FEMA P695 collapse margins (`p695.rs`).
//!
//! Pure computation on a `stats::FragilityReport`: the caller (`report::risk`) says how the
//! hazard's intensity measure converts to each variant's scaling measure.

mod error;
pub mod hazard;
pub mod maf;
pub mod p695;

pub use error::RiskError;
pub use hazard::{HazardCurve, HazardIm, PowerLaw};
pub use maf::{Maf, maf};
pub use p695::{Margin, Ratings};

use crate::stats::{Curve, FitStatus, FragilityReport, Variant, interval};
use serde::{Deserialize, Serialize};

/// Above this share of the MAF, the table's ends are warned about.
pub const END_SHARE_WARNING: f64 = 0.01;

/// What a risk computation is asked for besides the hazard.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RiskOptions {
    /// Years of exposure for `p_years`.
    pub years: f64,
    /// P695 margins: the MCE intensity in the hazard's IM, and β_TOT.
    pub mce: Option<f64>,
    pub beta_total: Option<f64>,
}

/// One variant × damage state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RiskRow {
    pub variant: Variant,
    pub damage_state: f64,
    /// "ok", the fit's status when there is no fit, or the flags that make the fit under the
    /// MAF doubtful, separated by `;`.
    pub status: String,
    pub maf: Option<f64>,
    pub maf_lo: Option<f64>,
    pub maf_hi: Option<f64>,
    pub p_years: Option<f64>,
    pub p_years_lo: Option<f64>,
    pub p_years_hi: Option<f64>,
    /// MAF over the bare variant's (same parameters and state), paired over resamples.
    pub ratio_to_bare: Option<f64>,
    pub ratio_lo: Option<f64>,
    pub ratio_hi: Option<f64>,
    /// The intensities (hazard IM) below which 10 %, 50 %, 90 % of the MAF accrue.
    pub deagg_p10: Option<f64>,
    pub deagg_p50: Option<f64>,
    pub deagg_p90: Option<f64>,
    pub share_below: Option<f64>,
    pub share_above: Option<f64>,
    /// Resamples whose fit gave a MAF (the interval's sample).
    pub n_resamples: usize,
    /// The fitted median and β converted to the hazard's IM.
    pub median: Option<f64>,
    pub beta: Option<f64>,
}

/// P695 margins of a variant's collapse curve.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VariantMargin {
    pub variant: Variant,
    /// The damage state taken as collapse (the report's highest, θmax/α = 1 for overturning).
    pub damage_state: f64,
    pub margin: Margin,
}

/// The hazard as used, for readers of risk.json.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HazardSummary {
    pub source: String,
    pub curve: HazardCurve,
    /// The least-squares power law through the points (in the hazard's IM).
    pub power_law: PowerLaw,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RiskReport {
    pub hazard: HazardSummary,
    pub years: f64,
    pub confidence: f64,
    pub rows: Vec<RiskRow>,
    pub margins: Vec<VariantMargin>,
    pub warnings: Vec<String>,
}

/// p = 1 − e^{−λ t}.
pub fn probability_in(maf: f64, years: f64) -> f64 {
    -(-maf * years).exp_m1()
}

/// The risk of every curve in `report` over `hazard`; `factor(variant)` converts the hazard's
/// IM into the variant's scaling IM (x* = factor · x), None if it cannot.
pub fn assess(
    report: &FragilityReport,
    hazard: &HazardCurve,
    source: &str,
    factor: impl Fn(&Variant) -> Option<f64>,
    opts: &RiskOptions,
) -> RiskReport {
    let mut warnings = Vec::new();
    let mut rows: Vec<RiskRow> = Vec::new();
    // Per row, the resamples' MAFs (None where degenerate), for the paired ratios.
    let mut draws: Vec<Vec<Option<f64>>> = Vec::new();
    for c in &report.curves {
        let f = factor(&c.variant);
        let (row, sample) = assess_curve(c, hazard, f, opts, report.confidence);
        if let Some(share) = row.share_below.filter(|s| *s > END_SHARE_WARNING) {
            warnings.push(format!(
                "{} state {}: the hazard's points below {} {} could hold {:.1} % of the MAF \
                 (not counted): extend the curve to weaker shaking",
                c.variant.label(),
                c.damage_state,
                hazard.x[0],
                hazard.im.unit(),
                100.0 * share
            ));
        }
        if let Some(share) = row.share_above.filter(|s| *s > END_SHARE_WARNING) {
            warnings.push(format!(
                "{} state {}: {:.1} % of the MAF comes from above {} {}, where the last \
                 segment's power law is extrapolated: extend the curve to stronger shaking",
                c.variant.label(),
                c.damage_state,
                100.0 * share,
                hazard.x[hazard.x.len() - 1],
                hazard.im.unit()
            ));
        }
        rows.push(row);
        draws.push(sample);
    }
    pair_with_bare(report, &mut rows, &draws);
    // A study with uncertain parameters measured its own β_total: each variant's collapse
    // curve's total β (records and parameters) serves where none is given.
    let margins = match (opts.mce, opts.beta_total) {
        (Some(mce), Some(beta_total)) => margins(&rows, mce, Some(beta_total)),
        (Some(mce), None) if !report.uncertainty.is_empty() => margins(&rows, mce, None),
        _ => Vec::new(),
    };
    RiskReport {
        hazard: HazardSummary {
            source: source.to_string(),
            curve: hazard.clone(),
            power_law: hazard.power_law(),
        },
        years: opts.years,
        confidence: report.confidence,
        rows,
        margins,
        warnings,
    }
}

fn assess_curve(
    c: &Curve,
    hazard: &HazardCurve,
    factor: Option<f64>,
    opts: &RiskOptions,
    confidence: f64,
) -> (RiskRow, Vec<Option<f64>>) {
    let mut row = RiskRow {
        variant: c.variant.clone(),
        damage_state: c.damage_state,
        status: String::new(),
        maf: None,
        maf_lo: None,
        maf_hi: None,
        p_years: None,
        p_years_lo: None,
        p_years_hi: None,
        ratio_to_bare: None,
        ratio_lo: None,
        ratio_hi: None,
        deagg_p10: None,
        deagg_p50: None,
        deagg_p90: None,
        share_below: None,
        share_above: None,
        n_resamples: 0,
        median: None,
        beta: None,
    };
    let fit = c
        .median
        .zip(c.beta)
        .filter(|_| c.status == FitStatus::Fitted);
    let (Some((median, beta)), Some(factor)) = (fit, factor) else {
        row.status = if factor.is_none() {
            "no_im_conversion".to_string()
        } else {
            c.status.name().to_string()
        };
        return (row, Vec::new());
    };
    // The fragility in the hazard's IM: x* = factor · x, so the median divides by the factor
    // and β (a dispersion of ln x) is unchanged.
    let m = maf(hazard, median / factor, beta);
    let sample: Vec<Option<f64>> = c
        .resamples
        .iter()
        .map(|r| r.map(|[med, b]| maf(hazard, med / factor, b).maf))
        .collect();
    let values: Vec<f64> = sample.iter().flatten().copied().collect();
    [row.maf_lo, row.maf_hi] = interval(&values, confidence);
    let flags = c.warnings();
    row.status = if flags.is_empty() {
        "ok".to_string()
    } else {
        flags.join(";")
    };
    row.maf = Some(m.maf);
    row.p_years = Some(probability_in(m.maf, opts.years));
    row.p_years_lo = row.maf_lo.map(|v| probability_in(v, opts.years));
    row.p_years_hi = row.maf_hi.map(|v| probability_in(v, opts.years));
    [row.deagg_p10, row.deagg_p50, row.deagg_p90] = m.deaggregation.map(Some);
    row.share_below = Some(m.share_below);
    row.share_above = Some(m.share_above);
    row.n_resamples = values.len();
    row.median = Some(median / factor);
    row.beta = Some(beta);
    (row, sample)
}

/// Each protected row's MAF over its bare row's, the interval from the resamples where both
/// fits exist (the bootstrap drew the same records for every curve).
fn pair_with_bare(report: &FragilityReport, rows: &mut [RiskRow], draws: &[Vec<Option<f64>>]) {
    for i in 0..rows.len() {
        let c = &report.curves[i];
        if c.variant.is_bare() {
            continue;
        }
        let bare = report.curves.iter().position(|q| {
            q.variant.is_bare()
                && q.variant.params == c.variant.params
                && q.damage_state == c.damage_state
                && q.method == c.method
        });
        let Some(j) = bare else { continue };
        let (Some(a), Some(b)) = (rows[i].maf, rows[j].maf) else {
            continue;
        };
        let paired: Vec<f64> = draws[i]
            .iter()
            .zip(&draws[j])
            .filter_map(|(a, b)| Some(a.as_ref()? / b.as_ref()?))
            .filter(|r| r.is_finite())
            .collect();
        rows[i].ratio_to_bare = Some(a / b);
        [rows[i].ratio_lo, rows[i].ratio_hi] = interval(&paired, report.confidence);
    }
}

/// P695 margins per variant, on each variant's highest damage state (collapse), with
/// `beta_total`, or (None) each curve's own fitted β.
fn margins(rows: &[RiskRow], mce: f64, beta_total: Option<f64>) -> Vec<VariantMargin> {
    let mut out: Vec<VariantMargin> = Vec::new();
    for r in rows {
        let Some(median) = r.median else { continue };
        let Some(beta_total) = beta_total.or(r.beta) else {
            continue;
        };
        let top = rows
            .iter()
            .filter(|q| q.variant == r.variant)
            .map(|q| q.damage_state)
            .fold(f64::NEG_INFINITY, f64::max);
        if r.damage_state == top {
            out.push(VariantMargin {
                variant: r.variant.clone(),
                damage_state: r.damage_state,
                // A rigid rocking block has no period in P695's sense: SSF = 1.
                margin: p695::margin(median, mce, beta_total, 1.0),
            });
        }
    }
    out
}

#[cfg(test)]
pub(crate) mod tests;
