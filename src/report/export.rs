//! Sweep results to files: a tidy long CSV, a JSON results file (study, hash, every scene with
//! its result, spectra, maps) and a plain-text summary with sparklines.

use super::aggregate::{OverturningMap, Spectrum, maps, quantities, sparkline, spectra};
use crate::study::fmt_num;
use crate::sweep::SweepResults;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

/// Spectra and maps stored next to the results for readers outside rocklab.
#[derive(Serialize)]
struct Derived {
    spectra: Vec<Spectrum>,
    maps: Vec<OverturningMap>,
}

pub fn results_json(results: &SweepResults) -> anyhow::Result<Vec<u8>> {
    let derived = Derived {
        spectra: spectra(results),
        maps: maps(results),
    };
    crate::sweep::results_file_json(results, &derived)
}

pub fn save_results(path: &Path, results: &SweepResults) -> anyhow::Result<()> {
    super::write_atomic(path, &results_json(results)?)
}

/// CSV, summary and the canonical study next to the results file (`rocklab run`, `merge` and
/// the workbench's runs write the same set).
pub fn write_tables(
    out: &Path,
    study: &crate::study::Study,
    results: &SweepResults,
) -> anyhow::Result<()> {
    super::write_atomic(&out.join("results.csv"), &results_csv(results)?)?;
    super::write_atomic(&out.join("summary.txt"), summary(results).as_bytes())?;
    study.save(&out.join("study.ron"))
}

/// Tidy long CSV: one row per scene and quantity, one column per varying axis.
pub fn results_csv(results: &SweepResults) -> anyhow::Result<Vec<u8>> {
    let mut axes: Vec<String> = Vec::new();
    for o in &results.outcomes {
        for (name, _) in &o.point.coords {
            if !axes.contains(name) {
                axes.push(name.clone());
            }
        }
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header: Vec<String> = ["scene", "key", "group", "device", "excitation"]
        .map(String::from)
        .to_vec();
    header.extend(axes.iter().cloned());
    header.extend(["quantity", "value", "overturned", "status"].map(String::from));
    w.write_record(&header)?;
    let quantities = quantities(results);
    for o in &results.outcomes {
        for q in &quantities {
            let mut row = vec![
                o.point.index.to_string(),
                o.point.key.clone(),
                o.point.group.clone(),
                o.point.scene.device.name().to_string(),
                excitation_name(&o.point.scene.excitation),
            ];
            for axis in &axes {
                row.push(
                    o.point
                        .coord(axis)
                        .map(|v| format!("{v}"))
                        .unwrap_or_default(),
                );
            }
            row.push(q.name().to_string());
            match &o.result {
                Ok(r) => {
                    row.push(q.of(r).map(|v| format!("{v:.9e}")).unwrap_or_default());
                    row.push(r.overturned.to_string());
                    row.push("ok".into());
                }
                Err(reason) => {
                    row.extend([String::new(), String::new(), format!("failed: {reason}")]);
                }
            }
            w.write_record(&row)?;
        }
    }
    Ok(w.into_inner()?)
}

/// Plain-text summary: counts, one sparkline per spectrum, maps as character grids.
pub fn summary(results: &SweepResults) -> String {
    let mut s = String::new();
    let name = results
        .study
        .as_ref()
        .map_or("(points)", |s| s.name.as_str());
    let failed = results
        .outcomes
        .iter()
        .filter(|o| o.result.is_err())
        .count();
    let overturned = results
        .outcomes
        .iter()
        .filter(|o| o.result.as_ref().is_ok_and(|r| r.overturned))
        .count();
    let _ = writeln!(
        s,
        "study {name} (hash {}): {} scenes, {overturned} overturned, {failed} failed{}",
        results.study_hash,
        results.outcomes.len(),
        if results.cancelled {
            ", INCOMPLETE (cancelled or missing shards)"
        } else {
            ""
        }
    );
    for o in results
        .outcomes
        .iter()
        .filter(|o| o.result.is_err())
        .take(5)
    {
        let _ = writeln!(
            s,
            "  failed scene {} ({}): {}",
            o.point.index,
            o.point.group,
            o.result.as_ref().err().map_or("", |e| e.as_str())
        );
    }
    let mut spectra = spectra(results);
    // Maps over a fine amplitude grid make hundreds of spectra: show the first few per quantity.
    const SHOWN: usize = 24;
    let mut hidden = 0;
    let mut seen: Vec<(crate::report::Quantity, usize)> = Vec::new();
    spectra.retain(|sp| {
        let count = match seen.iter_mut().find(|(q, _)| *q == sp.quantity) {
            Some((_, n)) => {
                *n += 1;
                *n
            }
            None => {
                seen.push((sp.quantity, 1));
                1
            }
        };
        if count > SHOWN {
            hidden += 1;
        }
        count <= SHOWN
    });
    let width = spectra
        .iter()
        .map(|sp| sp.label.chars().count())
        .max()
        .unwrap_or(0);
    let mut last_q = None;
    for sp in &spectra {
        if last_q != Some(sp.quantity) {
            let (lo, hi) = (sp.xs.first(), sp.xs.last());
            let _ = writeln!(
                s,
                "\n{} over {} ({} … {}); blank = overturned or failed",
                sp.quantity.label(),
                sp.axis,
                lo.map_or(String::new(), |v| fmt_num(*v)),
                hi.map_or(String::new(), |v| fmt_num(*v))
            );
            last_q = Some(sp.quantity);
        }
        let peak = sp
            .xs
            .iter()
            .zip(&sp.ys)
            .filter_map(|(x, y)| y.map(|y| (*x, y)))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let peak = peak.map_or("—".to_string(), |(x, y)| {
            format!("max {} at {}={}", fmt_sig(y), sp.axis, fmt_num(x))
        });
        let _ = writeln!(
            s,
            "  {:width$}  {}  {peak}",
            sp.label,
            sparkline(&sp.ys),
            width = width
        );
    }
    if hidden > 0 {
        let _ = writeln!(
            s,
            "  … {hidden} more spectra in results.csv / results.json (`rocklab plot` draws them all)"
        );
    }
    s.push_str(&super::compare::suite_summary(
        results,
        &super::aggregate::spectra(results),
    ));
    let maps = maps(results);
    const MAPS_SHOWN: usize = 6;
    if maps.len() > MAPS_SHOWN {
        let _ = writeln!(
            s,
            "\n{} overturning maps; the first {MAPS_SHOWN} follow (`rocklab plot` draws them all)",
            maps.len()
        );
    }
    for m in maps.into_iter().take(MAPS_SHOWN) {
        let _ = writeln!(
            s,
            "\noverturning map, {}: {} (→) × {} (↑); █ overturned, · safe, ? missing",
            m.label, m.x_axis, m.y_axis
        );
        for (iy, row) in m.cells.iter().enumerate().rev() {
            let line: String = row
                .iter()
                .map(|c| match c {
                    Some(true) => '█',
                    Some(false) => '·',
                    None => '?',
                })
                .collect();
            let _ = writeln!(s, "  {:>8} {line}", fmt_num(m.ys[iy]));
        }
    }
    s
}

fn fmt_sig(v: f64) -> String {
    if v != 0.0 && (v.abs() < 1e-3 || v.abs() >= 1e5) {
        format!("{v:.3e}")
    } else {
        format!("{v:.4}")
    }
}

/// The record's name, or the pulse's shape: the categorical part of the excitation.
fn excitation_name(e: &crate::scene::Excitation) -> String {
    use crate::scene::Excitation;
    match e {
        Excitation::Record { name, .. } => name.clone(),
        Excitation::Pulse { shape, .. } => ron::to_string(shape).unwrap_or_default(),
        Excitation::MpPulse { .. } => "mp_pulse".into(),
    }
}
