//! The fragility engine's output of a fragility study (study/fragility.rs): one stripes.csv
//! row per scene (variant, record, component, IM, the scale factor the scene used, the asked
//! quantities, overturned), the stripe observations fitted by `report::fragility`, and the
//! fitted report as fragility.csv and fragility.json. Written by [`super::write_tables`], so
//! `rocklab run`, `merge` (Slurm shards) and the workbench's runs all write them.

use super::fragility::{
    FRAGILITY_CSV, FRAGILITY_JSON, FragilityOptions, FragilityReport, StripeObservation, Variant,
    analyse_stripes, write_fragility_csv, write_fragility_json,
};
use crate::excitation::library::{self, Library};
use crate::scene::Excitation;
use crate::study::fragility::{Fragility, im_name};
use crate::study::uncertain::Sample;
use crate::study::{DeviceKind, ExcitationFamily, Layout, Param, Quantity, ScenePoint, Study};
use crate::sweep::{SceneOutcome, SweepResults};
use std::path::Path;

pub const STRIPES_CSV: &str = "stripes.csv";

/// One scene of a fragility study, as stripes.csv has it.
#[derive(Clone, Debug, PartialEq)]
pub struct StripeRow {
    pub variant: Variant,
    pub record: String,
    /// `a` / `b` for suite records, else the record's component as its index gives it.
    pub component: String,
    /// The stripe's intensity-measure value.
    pub im: f64,
    /// The factor the record was multiplied by to reach `im` (NaN if it cannot be loaded).
    pub scale: f64,
    /// The study's quantities (None: overturned, failed, or not measured).
    pub values: Vec<Option<f64>>,
    pub overturned: bool,
    /// Why the scene failed, if it did (failed scenes are not observations).
    pub failed: Option<String>,
    /// An uncertain study: the scene's uncertain parameters (drawn, or at their centres for a
    /// deterministic companion), by CSV name; empty otherwise.
    pub drawn: Vec<(String, f64)>,
    /// An uncertain study: the draw's place (record × stripe), None for a deterministic
    /// companion (and in a study without uncertain parameters).
    pub draw: Option<usize>,
    /// Whether the scene is a drawn scene's deterministic companion (fitted apart: the
    /// records-only dispersion).
    pub companion: bool,
}

/// The fragility variant of a scene: the device (its label if the study gives one) and every
/// varying parameter that is neither the IM (`scale`) nor the record, by its results.csv name.
/// A scene off the study's grid (an IDA's bisection probe) takes its device from a study
/// point of the same group in `on_grid`.
pub(super) fn variant_of(layout: &Layout, point: &ScenePoint, on_grid: &[&ScenePoint]) -> Variant {
    // A deterministic companion is the variant of the drawn scene it stands beside.
    let (point, index) = match &point.uncertain {
        Some(Sample::Companion { of }) => (point, *of),
        _ if point.index >= layout.len() => {
            let p = on_grid
                .iter()
                .find(|p| p.group == point.group)
                .copied()
                .unwrap_or(point);
            (p, p.index)
        }
        _ => (point, point.index),
    };
    let device = layout
        .locate(index)
        .map(|(v, _)| &layout.variants[v])
        .map_or_else(
            || point.scene.device.name().to_string(),
            |v| {
                let default = if v.kind == DeviceKind::None {
                    "bare"
                } else {
                    v.kind.name()
                };
                if v.label == default {
                    v.kind.name().to_string()
                } else {
                    v.label.clone()
                }
            },
        );
    let params = point
        .coords
        .iter()
        .filter(|(label, _)| label != Param::Scale.label())
        .map(|(label, v)| (super::export::parameter(label).name, *v))
        .collect();
    Variant { device, params }
}

pub(super) fn component_of(library: Option<&Library>, name: &str) -> String {
    let Some(library) = library else {
        return String::new();
    };
    if let Some(e) = library.suite_entry(name) {
        return e.row.component.clone();
    }
    library
        .index()
        .iter()
        .find(|m| m.name == name)
        .map_or_else(String::new, |m| m.component.clone())
}

/// The scale factor a scene's record was multiplied by.
fn scale_of(library: Option<&Library>, o: &SceneOutcome) -> f64 {
    let Excitation::Record {
        name,
        scale,
        baseline,
        ..
    } = &o.point.scene.excitation
    else {
        return f64::NAN;
    };
    let s = &o.point.scene.structure;
    library
        .and_then(|l| l.load(name, *baseline).ok())
        .map_or(f64::NAN, |r| {
            scale.factor(r.series.pga(), r.series.pgv(), s.alpha(), s.p())
        })
}

/// The stripes.csv rows of a fragility study's results, in expansion order.
pub fn rows(study: &Study, results: &SweepResults) -> crate::error::Result<Vec<StripeRow>> {
    let layout = study.layout()?;
    let library = library::global().ok();
    let on_grid: Vec<&ScenePoint> = results
        .outcomes
        .iter()
        .map(|o| &o.point)
        .filter(|p| p.index < layout.len())
        .collect();
    let centres: Vec<(String, f64)> = (study.uncertain.iter())
        .flat_map(|u| u.parameters())
        .map(|(p, d)| (p.info().name.to_string(), d.centre()))
        .collect();
    Ok(results
        .outcomes
        .iter()
        .map(|o| {
            let (record, scale) = match &o.point.scene.excitation {
                Excitation::Record { name, scale, .. } => (name.clone(), scale.value()),
                _ => (String::new(), f64::NAN),
            };
            let (values, overturned, failed) = match &o.result {
                Ok(r) => (
                    study.quantities.iter().map(|q| q.of(r)).collect(),
                    r.overturned,
                    None,
                ),
                Err(why) => (vec![None; study.quantities.len()], false, Some(why.clone())),
            };
            let (drawn, draw, companion) = match &o.point.uncertain {
                Some(Sample::Drawn { draw, values }) => (values.clone(), Some(*draw), false),
                Some(Sample::Companion { .. }) => (centres.clone(), None, true),
                None => (Vec::new(), None, false),
            };
            StripeRow {
                drawn,
                draw,
                companion,
                variant: variant_of(&layout, &o.point, &on_grid),
                component: component_of(library, &record),
                scale: scale_of(library, o),
                record,
                im: scale,
                values,
                overturned,
                failed,
            }
        })
        .collect())
}

/// The varying parameters' names over these variants, in order of first appearance, and the
/// name of the study's intensity measure: the leading columns of stripes.csv and ida.csv.
pub(super) fn csv_axes<'a>(
    study: &Study,
    variants: impl Iterator<Item = &'a Variant>,
) -> (Vec<String>, String) {
    let mut params: Vec<String> = Vec::new();
    for v in variants {
        for (k, _) in &v.params {
            if !params.contains(k) {
                params.push(k.clone());
            }
        }
    }
    let im = match &study.excitation {
        ExcitationFamily::Record { scale_to, .. } => {
            im_name(*scale_to).unwrap_or_else(|| "im".into())
        }
        _ => "im".into(),
    };
    (params, im)
}

/// stripes.csv: device, the varying parameters, record, component, the IM (named by its
/// measure, e.g. `pga_star`), scale, the study's quantities, overturned, status.
pub fn stripes_csv(study: &Study, rows: &[StripeRow]) -> crate::error::Result<Vec<u8>> {
    let (params, im) = csv_axes(study, rows.iter().map(|r| &r.variant));
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header = vec!["device".to_string()];
    header.extend(params.iter().cloned());
    header.extend(["record", "component", "im", "im_measure", "scale"].map(String::from));
    // An uncertain study: the draw (its place, or `nominal` for a deterministic companion)
    // and the uncertain parameters' values.
    let uncertain: Vec<String> = (study.uncertain.iter())
        .flat_map(|u| u.parameters())
        .map(|(p, _)| p.info().name.to_string())
        .collect();
    if !uncertain.is_empty() {
        header.push("draw".into());
        header.extend(uncertain.iter().cloned());
    }
    header.extend(study.quantities.iter().map(|q| q.name().to_string()));
    header.extend(["overturned", "status"].map(String::from));
    w.write_record(&header)?;
    for r in rows {
        let mut row = vec![r.variant.device.clone()];
        for p in &params {
            let v = r.variant.params.iter().find(|(k, _)| k == p);
            row.push(v.map_or_else(String::new, |(_, v)| v.to_string()));
        }
        row.extend([
            r.record.clone(),
            r.component.clone(),
            r.im.to_string(),
            im.to_string(),
            format!("{:.9e}", r.scale),
        ]);
        if !uncertain.is_empty() {
            row.push(r.draw.map_or_else(|| "nominal".into(), |d| d.to_string()));
            for name in &uncertain {
                let v = r.drawn.iter().find(|(k, _)| k == name);
                row.push(v.map_or_else(String::new, |(_, v)| v.to_string()));
            }
        }
        row.extend(
            r.values
                .iter()
                .map(|v| v.map_or_else(String::new, |v| format!("{v:.9e}"))),
        );
        row.push(if r.failed.is_some() {
            String::new()
        } else {
            r.overturned.to_string()
        });
        row.push(
            r.failed
                .as_ref()
                .map_or_else(|| "ok".to_string(), |why| format!("failed: {why}")),
        );
        w.write_record(&row)?;
    }
    Ok(w.into_inner()?)
}

/// The observations of the fit: every scene that ran (failed ones are left out; stripes.csv
/// lists them). An overturned scene's response is +∞ and it exceeds every state.
pub fn observations<'a>(
    f: &Fragility,
    study: &Study,
    rows: impl IntoIterator<Item = &'a StripeRow>,
) -> Vec<StripeObservation> {
    let measure = study.quantities.iter().position(|q| *q == f.measure);
    rows.into_iter()
        .filter(|r| r.failed.is_none())
        .map(|r| StripeObservation {
            variant: r.variant.clone(),
            record: r.record.clone(),
            im: r.im,
            response: if r.overturned {
                f64::INFINITY
            } else {
                measure.and_then(|i| r.values[i]).unwrap_or(f64::NAN)
            },
            overturned: r.overturned,
        })
        .collect()
}

/// The fitted report of a fragility study's results. With uncertain parameters the curves
/// are fitted over the drawn scenes (the total dispersion, records and parameters), and each
/// also carries the fit over the deterministic companions (records alone, without bootstrap).
pub fn analyse(f: &Fragility, study: &Study, rows: &[StripeRow]) -> FragilityReport {
    let opts = options(f);
    let drawn = rows.iter().filter(|r| !r.companion);
    let mut report = analyse_stripes(&observations(f, study, drawn), &opts);
    if let Some(u) = &study.uncertain {
        let companions: Vec<&StripeRow> = rows.iter().filter(|r| r.companion).collect();
        let records_only = analyse_stripes(
            &observations(f, study, companions),
            &FragilityOptions {
                bootstrap: 0,
                ..opts
            },
        );
        for c in &mut report.curves {
            if let Some(r) = (records_only.curves.iter())
                .find(|r| r.variant == c.variant && r.damage_state == c.damage_state)
            {
                c.median_records = r.median;
                c.beta_records = r.beta;
            }
        }
        report.uncertainty = u.describe(false);
    }
    name_axes(&mut report, f, study);
    report
}

/// The options of a fragility section's fits.
pub(super) fn options(f: &Fragility) -> FragilityOptions {
    f.fit_options()
}

/// Name a report's intensity measure and damage measure for its figure and readouts.
pub(super) fn name_axes(report: &mut FragilityReport, f: &Fragility, study: &Study) {
    report.im = match &study.excitation {
        ExcitationFamily::Record { scale_to, .. } => im_label(*scale_to),
        _ => String::new(),
    };
    report.damage_measure = match f.measure {
        Quantity::PeakRotationRatio => "θmax/α".to_string(),
        q => q.label().to_string(),
    };
}

fn im_label(scale_to: crate::study::RecordScaling) -> String {
    use crate::study::RecordScaling as S;
    match scale_to {
        S::Pga => "PGA (g)".into(),
        S::Pgv => "PGV (m/s)".into(),
        S::PgaStar => "PGA* = PGA/(g·tanα)".into(),
        S::PgvStar => "PGV* = PGV·p/(g·tanα)".into(),
        S::Sa { period, .. } => format!("Sa({period} s) (g)"),
        S::SaAvg { from, to } => format!("Sa_avg({from}–{to} s) (g)"),
        S::Arias => "Arias intensity (m/s)".into(),
        S::Factor | S::Fema => "scale".into(),
    }
}

/// stripes.csv, fragility.csv and fragility.json of a fragility study, in `out`.
pub fn write(out: &Path, study: &Study, results: &SweepResults) -> crate::error::Result<()> {
    let Some(f) = &study.fragility else {
        return Ok(());
    };
    let rows = rows(study, results)?;
    super::write_atomic(&out.join(STRIPES_CSV), &stripes_csv(study, &rows)?)?;
    if f.method.ida_resolution().is_some() {
        // An IDA's scenes are its hunts' probes: ida.csv and the capacities' fit.
        return super::ida::write(out, study, results);
    }
    let Some(report) = fit(study, results)? else {
        return Ok(());
    };
    write_fragility_csv(&report, &out.join(FRAGILITY_CSV))?;
    write_fragility_json(&report, &out.join(FRAGILITY_JSON))?;
    Ok(super::risk::write_section(out, study, results, &report)?)
}

/// The fitted fragility report of a fragility study's results (stripes or IDA), or None: no
/// fragility section, or results not complete (a fit of part of the scenes would read as the
/// study's; the rerun that finishes them gives it).
pub fn fit(study: &Study, results: &SweepResults) -> crate::error::Result<Option<FragilityReport>> {
    let Some(f) = &study.fragility else {
        return Ok(None);
    };
    if results.cancelled {
        return Ok(None);
    }
    if f.method.ida_resolution().is_some() {
        let ida = super::ida::ida(study, results)?;
        return Ok(ida
            .complete
            .then(|| super::ida::analyse(f, study, &ida.rows)));
    }
    Ok(Some(analyse(f, study, &rows(study, results)?)))
}
