//! The design answer to files and text: design.csv (one row per design point) and the
//! summary `rocklab design` prints. The rows come from replaying the search on the results'
//! scenes (`sweep::design::replay`), so a results file alone gives the answer back.

use super::export::parameter;
use crate::numfmt::fmt_num;
use crate::study::Study;
use crate::sweep::SweepResults;
use crate::sweep::design::{DesignRow, DesignStatus, replay};
use std::fmt::Write as _;

/// The columns of design.csv around the design point's axes (which come first, after
/// `device`): name and meaning. One table: the CSV header and the README's list read it.
pub const DESIGN_COLUMNS: [(&str, &str); 11] = [
    (
        "parameter",
        "the sized parameter (empty: a variant without it, evaluated once as a reference)",
    ),
    (
        "value",
        "least value meeting the target at every excitation point (empty if none)",
    ),
    (
        "lo",
        "final bracket's low end (fails the target, or the bracket's bottom)",
    ),
    ("hi", "final bracket's high end (meets the target)"),
    (
        "probes",
        "parameter values evaluated (each a full pass over the excitation axes)",
    ),
    ("scenes", "scenes those probes ran"),
    (
        "governing",
        "excitation point of the worst response at the answer (at the top if not achievable); \
         a fragility target: the fitted curve (median [interval] β, records × stripes)",
    ),
    (
        "achieved",
        "that response (overturned or failed when there is none); a fragility target: the \
         fitted median or probability (the fit's status when there is none)",
    ),
    (
        "status",
        "found, met_at_low, not_achievable, non_monotone, reference_met, reference_fails or incomplete",
    ),
    (
        "fails_above",
        "values above the answer that fail the target again (non_monotone)",
    ),
    ("target", "the target, as the study states it"),
];

/// The design rows of a design study's results (None for another study).
pub fn design_rows(results: &SweepResults) -> Option<Vec<DesignRow>> {
    let study = results.study.as_ref()?;
    study.design.as_ref()?;
    replay(study, &results.outcomes).ok()
}

/// The ASCII names of the design points' axis columns (labels as coordinates give them).
fn axis_columns(rows: &[DesignRow]) -> Vec<String> {
    let mut labels: Vec<String> = Vec::new();
    for r in rows {
        for (label, _) in &r.axes {
            if !labels.contains(label) {
                labels.push(label.clone());
            }
        }
    }
    labels
}

fn has_record(rows: &[DesignRow]) -> bool {
    rows.iter().any(|r| r.record.is_some())
}

fn num(v: Option<f64>) -> String {
    v.filter(|v| v.is_finite())
        .map_or(String::new(), |v| format!("{v}"))
}

/// design.csv: `device`, the design points' axes, `record` when a record is off the
/// excitation axes, then [`DESIGN_COLUMNS`].
pub fn design_csv(study: &Study, rows: &[DesignRow]) -> crate::error::Result<Vec<u8>> {
    let axes = axis_columns(rows);
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header = vec!["device".to_string()];
    header.extend(axes.iter().map(|a| parameter(a).name));
    if has_record(rows) {
        header.push("record".into());
    }
    header.extend(DESIGN_COLUMNS.iter().map(|c| c.0.to_string()));
    w.write_record(&header)?;
    let target = study
        .design
        .as_ref()
        .map_or(String::new(), |d| d.target.describe());
    for r in rows {
        let mut line = vec![r.device.clone()];
        for a in &axes {
            line.push(num(r.axes.iter().find(|(l, _)| l == a).map(|(_, v)| *v)));
        }
        if has_record(rows) {
            line.push(r.record.clone().unwrap_or_default());
        }
        line.extend([
            r.parameter.map_or(String::new(), |p| p.id().to_string()),
            num(r.value),
            num(r.parameter.map(|_| r.lo)),
            num(r.parameter.map(|_| r.hi)),
            r.probes.to_string(),
            r.scenes.to_string(),
            r.governing.clone(),
            match (r.achieved, r.achieved_note) {
                (Some(v), _) => format!("{v}"),
                (None, Some(note)) => note.to_string(),
                (None, None) => String::new(),
            },
            r.status.name().to_string(),
            r.fails_above
                .iter()
                .map(|v| format!("{v}"))
                .collect::<Vec<_>>()
                .join(";"),
            target.clone(),
        ]);
        w.write_record(&line)?;
    }
    Ok(w.into_inner()?)
}

/// Scenes a grid of the sized parameter at the study's resolution would run: per design
/// point with an answer, the bracket in steps of `resolution` × the answer, every step a full
/// pass over the excitation axes (points without an answer are left out: no grid step).
pub fn grid_scenes(study: &Study, rows: &[DesignRow]) -> usize {
    let Some(design) = &study.design else {
        return 0;
    };
    let (low, top) = design.bracket;
    rows.iter()
        .filter_map(|r| {
            let v = r.value.filter(|v| *v > 0.0)?;
            let per_probe = r.scenes / r.probes.max(1);
            let steps = ((top - low) / (design.resolution * v)).ceil() as usize + 1;
            Some(steps * per_probe)
        })
        .sum()
}

/// The answer as text: one line per design point, then the scene counts.
pub fn design_summary(study: &Study, rows: &[DesignRow], distinct: usize) -> String {
    let mut text = String::new();
    let Some(design) = &study.design else {
        return text;
    };
    let _ = writeln!(
        text,
        "design {}: least {} in [{}, {}] to {} % for {} at every {}",
        study.name,
        design.parameter.id(),
        fmt_num(design.bracket.0),
        fmt_num(design.bracket.1),
        fmt_num(design.resolution * 100.0),
        design.target.describe(),
        design.over_ids(study).join(" × "),
    );
    for r in rows {
        let mut name = r.device.clone();
        for (l, v) in &r.axes {
            let _ = write!(name, " {l}={}", fmt_num(*v));
        }
        if let Some(rec) = &r.record {
            let _ = write!(name, " · {rec}");
        }
        let answer = match r.status {
            DesignStatus::Found | DesignStatus::MetAtLow | DesignStatus::NonMonotone => {
                format!(
                    "{} = {} in ({}, {}]",
                    design.parameter.id(),
                    fmt_num(r.value.unwrap_or(f64::NAN)),
                    fmt_num(r.lo),
                    fmt_num(r.hi)
                )
            }
            _ => String::new(),
        };
        let achieved = match (r.achieved, r.achieved_note) {
            (Some(v), _) => fmt_num(v),
            (None, Some(n)) => n.to_string(),
            _ => "-".into(),
        };
        let _ = writeln!(
            text,
            "  {name:<28} {:<15} {answer:<28} {} probes, governing {} ({achieved}){}",
            r.status.name(),
            r.probes,
            if r.governing.is_empty() {
                "-"
            } else {
                &r.governing
            },
            if r.fails_above.is_empty() {
                String::new()
            } else {
                format!(
                    "; fails again at {}",
                    r.fails_above
                        .iter()
                        .map(|v| fmt_num(*v))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            }
        );
    }
    let _ = writeln!(
        text,
        "{distinct} scenes run by the search; a grid at {} % of each answer over the bracket: {} \
         scenes",
        fmt_num(design.resolution * 100.0),
        grid_scenes(study, rows)
    );
    text
}
