//! A fragility study's seismic risk at a site: how the site hazard's intensity measure
//! converts to each variant's scaling measure (PGA* = PGA/(g tan α), PGV* = PGV·p/(g tan α)
//! from the variant's own structure), and risk.csv / risk.json beside fragility.csv. The
//! numbers are `crate::risk`'s; the figure is `risk_plot.rs`.

use super::fragility::{FRAGILITY_JSON, FragilityReport, Variant};
use super::stripes::variant_of;
use crate::fsutil::write_atomic;
use crate::risk::{HazardCurve, RiskError, RiskOptions, RiskReport, RiskRow};
use crate::study::{ScenePoint, Study};
use crate::sweep::SweepResults;
use std::path::Path;

pub const RISK_CSV: &str = "risk.csv";
pub const RISK_JSON: &str = "risk.json";

/// Each variant's factor from the hazard's IM to the study's scaling IM (x* = factor · x).
pub fn im_factors(
    study: &Study,
    results: &SweepResults,
    hazard: &HazardCurve,
    hazard_path: &Path,
) -> Result<Vec<(Variant, f64)>, RiskError> {
    let factor = crate::study::risk::im_factor(study, hazard.im).map_err(|(scaling, hint)| {
        RiskError::ImMismatch {
            path: hazard_path.to_path_buf(),
            header: hazard.im.name(),
            scaling: scaling.to_string(),
            hint: hint.to_string(),
        }
    })?;
    let layout = study.layout().map_err(|e| RiskError::Results {
        path: hazard_path.to_path_buf(),
        message: e.to_string(),
        hint: "the results' study no longer expands; rerun it".into(),
    })?;
    let on_grid: Vec<&ScenePoint> = results
        .outcomes
        .iter()
        .map(|o| &o.point)
        .filter(|p| p.index < layout.len())
        .collect();
    let mut out: Vec<(Variant, f64)> = Vec::new();
    for o in &results.outcomes {
        let v = variant_of(&layout, &o.point, &on_grid);
        if !out.iter().any(|(u, _)| *u == v) {
            let s = &o.point.scene.structure;
            out.push((v, factor(s.alpha(), s.p())));
        }
    }
    Ok(out)
}

/// The risk of a fragility report over a hazard, with the variants' IM factors.
pub fn assess(
    report: &FragilityReport,
    hazard: &HazardCurve,
    source: &str,
    factors: &[(Variant, f64)],
    opts: &RiskOptions,
) -> RiskReport {
    let factor = |v: &Variant| factors.iter().find(|(u, _)| u == v).map(|(_, f)| *f);
    crate::risk::assess(report, hazard, source, factor, opts)
}

/// The risk figure's options: an SVG at its own size.
pub fn svg_options() -> super::FigureOptions {
    super::FigureOptions {
        format: super::ImageFormat::Svg,
        size: None,
        dpi: 300.0,
        max_megapixels: super::MAX_MEGAPIXELS,
    }
}

/// A study's `risk` section: risk.csv, risk.json and risk.svg beside fragility.csv.
pub fn write_section(
    out: &Path,
    study: &Study,
    results: &SweepResults,
    report: &FragilityReport,
) -> Result<(), RiskError> {
    let Some(section) = &study.risk else {
        return Ok(());
    };
    let path = section.hazard_path();
    let hazard = HazardCurve::read(&path)?;
    let factors = im_factors(study, results, &hazard, &path)?;
    let risk = assess(
        report,
        &hazard,
        &section.hazard,
        &factors,
        &section.options(),
    );
    write_risk(out, &risk)?;
    keep_hazard(out, section, &path)?;
    super::plot_risk(out, &svg_options(), &risk).map_err(|e| RiskError::Write {
        path: out.join("risk.svg"),
        message: e.to_string(),
    })?;
    Ok(())
}

/// A copy of the hazard file at the same relative path in `out`, so the study.ron saved there
/// finds it (and the results say which curve they used). A path that leaves its directory
/// (absolute, or with `..`) is not copied.
fn keep_hazard(
    out: &Path,
    section: &crate::study::risk::Risk,
    from: &Path,
) -> Result<(), RiskError> {
    let relative = Path::new(&section.hazard);
    let inside = relative.components().all(|c| {
        matches!(
            c,
            std::path::Component::Normal(_) | std::path::Component::CurDir
        )
    });
    if !inside {
        return Ok(());
    }
    let to = out.join(relative);
    let failed = |e: &dyn std::fmt::Display| RiskError::Write {
        path: to.clone(),
        message: e.to_string(),
    };
    let bytes = std::fs::read(from).map_err(|e| failed(&e))?;
    std::fs::create_dir_all(crate::fsutil::parent_dir(&to)).map_err(|e| failed(&e))?;
    write_atomic(&to, &bytes).map_err(|e| failed(&e))
}

/// Read a results directory's fragility.json, written by `rocklab run`.
pub fn read_fragility(dir: &Path) -> Result<FragilityReport, RiskError> {
    let path = dir.join(FRAGILITY_JSON);
    let text = std::fs::read_to_string(&path).map_err(|source| RiskError::Read {
        path: path.clone(),
        source,
    })?;
    serde_json::from_str(&text).map_err(|e| RiskError::Results {
        path: path.clone(),
        message: format!("line {}: not a fragility report: {e}", e.line()),
        hint: "rerun `rocklab run` on the study to rewrite it".into(),
    })
}

fn num(v: Option<f64>) -> String {
    v.map_or_else(String::new, |v| v.to_string())
}

type Cell = fn(&RiskReport, &RiskRow) -> String;

/// The margin of a row, if it is its variant's collapse row.
fn margin<'a>(r: &'a RiskReport, row: &RiskRow) -> Option<&'a crate::risk::Margin> {
    r.margins
        .iter()
        .find(|m| m.variant == row.variant && m.damage_state == row.damage_state)
        .map(|m| &m.margin)
}

/// The columns after `device` and the varying parameters: header and value, one table.
const COLUMNS: [(&str, Cell); 27] = [
    ("damage_state", |_, r| r.damage_state.to_string()),
    ("status", |_, r| r.status.clone()),
    ("maf", |_, r| num(r.maf)),
    ("maf_lo", |_, r| num(r.maf_lo)),
    ("maf_hi", |_, r| num(r.maf_hi)),
    ("years", |rep, _| rep.years.to_string()),
    ("p_years", |_, r| num(r.p_years)),
    ("p_years_lo", |_, r| num(r.p_years_lo)),
    ("p_years_hi", |_, r| num(r.p_years_hi)),
    ("maf_ratio", |_, r| num(r.ratio_to_bare)),
    ("maf_ratio_lo", |_, r| num(r.ratio_lo)),
    ("maf_ratio_hi", |_, r| num(r.ratio_hi)),
    ("deagg_p10", |_, r| num(r.deagg_p10)),
    ("deagg_p50", |_, r| num(r.deagg_p50)),
    ("deagg_p90", |_, r| num(r.deagg_p90)),
    ("share_below_table", |_, r| num(r.share_below)),
    ("share_above_table", |_, r| num(r.share_above)),
    ("median", |_, r| num(r.median)),
    ("beta", |_, r| num(r.beta)),
    ("n_resamples", |_, r| r.n_resamples.to_string()),
    ("cmr", |rep, r| num(margin(rep, r).map(|m| m.cmr))),
    ("ssf", |rep, r| num(margin(rep, r).map(|m| m.ssf))),
    ("beta_total", |rep, r| {
        num(margin(rep, r).map(|m| m.beta_total))
    }),
    ("acmr_10", |rep, r| num(margin(rep, r).map(|m| m.acmr_10))),
    ("acmr_20", |rep, r| num(margin(rep, r).map(|m| m.acmr_20))),
    ("pass_10", |rep, r| {
        margin(rep, r).map_or_else(String::new, |m| m.pass_10.to_string())
    }),
    ("pass_20", |rep, r| {
        margin(rep, r).map_or_else(String::new, |m| m.pass_20.to_string())
    }),
];

/// risk.csv as bytes: device, each varying parameter, then [`COLUMNS`].
pub fn risk_csv(report: &RiskReport) -> Result<Vec<u8>, csv::Error> {
    let params = super::fragility::variant_parameter_names(report.rows.iter().map(|r| &r.variant));
    let mut w = csv::Writer::from_writer(Vec::new());
    let header = std::iter::once("device")
        .chain(params.iter().map(String::as_str))
        .chain(COLUMNS.iter().map(|(h, _)| *h));
    w.write_record(header)?;
    for r in &report.rows {
        let mut row = vec![r.variant.device.clone()];
        for p in &params {
            let v = r.variant.params.iter().find(|(k, _)| k == p);
            row.push(num(v.map(|(_, v)| *v)));
        }
        row.extend(COLUMNS.iter().map(|(_, cell)| cell(report, r)));
        w.write_record(&row)?;
    }
    w.into_inner().map_err(|e| e.into_error().into())
}

/// risk.csv and risk.json in `dir`.
pub fn write_risk(dir: &Path, report: &RiskReport) -> Result<(), RiskError> {
    let failed = |path: &Path, e: &dyn std::fmt::Display| RiskError::Write {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    let csv_path = dir.join(RISK_CSV);
    let bytes = risk_csv(report).map_err(|e| failed(&csv_path, &e))?;
    write_atomic(&csv_path, &bytes).map_err(|e| failed(&csv_path, &e))?;
    let json_path = dir.join(RISK_JSON);
    let mut json = serde_json::to_vec_pretty(report).map_err(|e| failed(&json_path, &e))?;
    json.push(b'\n');
    write_atomic(&json_path, &json).map_err(|e| failed(&json_path, &e))
}

/// Read a risk.json written by [`write_risk`] (None if the directory has none).
pub fn read_risk(dir: &Path) -> Option<RiskReport> {
    let text = std::fs::read_to_string(dir.join(RISK_JSON)).ok()?;
    serde_json::from_str(&text).ok()
}
