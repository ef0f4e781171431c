//! The design chart (`rocklab plot` on a design study's results): the least value of the
//! sized parameter over the first axis of the design points (e.g. α or p), one line per
//! device (and per value of any further axis), with the points the search could not turn
//! into a threshold marked: not achievable within the bracket (drawn at its top), non-monotone
//! (a value above the answer fails again), and the bare reference where it meets the target.

use super::design::design_rows;
use super::export::parameter;
use super::figure::{
    Axes, Canvas, FigureOptions, FigureSize, LINE_PT, LegendEntry, Marker, SeriesStyle, Swatch,
    build_chart, draw_line, draw_markers, render, split_figure,
};
use crate::numfmt::fmt_num;
use crate::sweep::SweepResults;
use crate::sweep::design::{DesignRow, DesignStatus};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// One line of the chart: a device at fixed values of the axes past the first.
struct Line {
    label: String,
    /// (x, least value) where the search found one; non-monotone points are flagged.
    points: Vec<(f64, f64, bool)>,
    /// x where not achievable within the bracket.
    not_achievable: Vec<f64>,
}

const NOT_ACHIEVABLE: RGBColor = RGBColor(213, 94, 0);

/// Write design.svg/png into `dir` if the results are a design study's; None otherwise (or
/// when its design points have no axis to draw over: design.csv says it all then).
pub fn plot_design(
    dir: &Path,
    options: &FigureOptions,
    results: &SweepResults,
) -> crate::error::Result<Option<PathBuf>> {
    let (Some(study), Some(rows)) = (&results.study, design_rows(results)) else {
        return Ok(None);
    };
    let Some(design) = &study.design else {
        return Ok(None);
    };
    let Some(x_label) = rows
        .iter()
        .find_map(|r| r.axes.first().map(|a| a.0.clone()))
    else {
        eprintln!("design chart: the design points vary over no axis; design.csv has the answer");
        return Ok(None);
    };
    let x_of = |r: &DesignRow| r.axes.iter().find(|(l, _)| *l == x_label).map(|(_, v)| *v);
    let line_label = |r: &DesignRow| {
        let mut label = r.device.clone();
        for (l, v) in r.axes.iter().filter(|(l, _)| *l != x_label) {
            label.push_str(&format!(" {l}={}", fmt_num(*v)));
        }
        if let Some(rec) = &r.record {
            label.push_str(&format!(" · {rec}"));
        }
        label
    };
    let (low, top) = design.bracket;
    let param = design.parameter;
    let mut lines: Vec<Line> = Vec::new();
    let mut bare_meets: Vec<f64> = Vec::new();
    for r in &rows {
        let Some(x) = x_of(r) else { continue };
        if r.parameter.is_none() {
            if r.status == DesignStatus::ReferenceMet {
                bare_meets.push(x);
            }
            continue;
        }
        let label = line_label(r);
        let at = match lines.iter().position(|l| l.label == label) {
            Some(i) => i,
            None => {
                lines.push(Line {
                    label,
                    points: Vec::new(),
                    not_achievable: Vec::new(),
                });
                lines.len() - 1
            }
        };
        // σ = 0 is the bare structure: a point met at σ = 0 is one the bare block meets.
        if r.status == DesignStatus::MetAtLow
            && low == 0.0
            && param == crate::study::design::DesignParameter::Sigma
        {
            bare_meets.push(x);
        }
        match (r.status, r.value) {
            (DesignStatus::NotAchievable, _) => lines[at].not_achievable.push(x),
            (s, Some(v)) => lines[at]
                .points
                .push((x, v, s == DesignStatus::NonMonotone)),
            _ => {}
        }
    }
    for l in &mut lines {
        l.points.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    let xs: Vec<f64> = rows.iter().filter_map(x_of).collect();
    let (x0, x1) = xs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(*x), b.max(*x))
        });
    let pad = if x1 > x0 { 0.04 * (x1 - x0) } else { 0.5 };
    let y_max = lines
        .iter()
        .flat_map(|l| l.points.iter().map(|p| p.1))
        .chain(
            lines
                .iter()
                .filter(|l| !l.not_achievable.is_empty())
                .map(|_| top),
        )
        .fold(low, f64::max);
    let y_pad = 0.08 * (y_max - low).max(1e-9);
    let mut legend: Vec<LegendEntry> = lines
        .iter()
        .enumerate()
        .map(|(i, l)| LegendEntry {
            label: l.label.clone(),
            swatch: Swatch::Line(SeriesStyle::nth(i)),
        })
        .collect();
    if lines.iter().any(|l| l.points.iter().any(|p| p.2)) {
        legend.push(LegendEntry {
            label: "non-monotone: fails again above".into(),
            swatch: Swatch::Marker(Marker::Cross, BLACK),
        });
    }
    if lines.iter().any(|l| !l.not_achievable.is_empty()) {
        legend.push(LegendEntry {
            label: format!("not achievable with {} ≤ {}", param.label(), fmt_num(top)),
            swatch: Swatch::Marker(Marker::Triangle, NOT_ACHIEVABLE),
        });
    }
    if !bare_meets.is_empty() {
        legend.push(LegendEntry {
            label: "bare structure meets the target".into(),
            swatch: Swatch::Marker(Marker::Square, RGBColor(0, 158, 115)),
        });
    }
    // A parameter every line has is said once, in the title.
    let labels: Vec<String> = lines.iter().map(|l| l.label.clone()).collect();
    let (shared, own) = super::naming::factor_shared(&labels);
    for (entry, own) in legend.iter_mut().zip(own) {
        entry.label = own;
    }
    let title = super::with_shared(&design_title(study, design), &shared);
    let x_title = match parameter(&x_label).unit {
        "" => x_label.clone(),
        unit => format!("{x_label} ({unit})"),
    };
    let y_title = format!("least {}", param.label());
    let canvas = options.canvas(FigureSize::mm(140.0, 100.0), "the design chart")?;
    let chart = Chart {
        title: &title,
        legend: &legend,
        axes: Axes {
            x: (x0 - pad, x1 + pad),
            y: (
                if low >= 0.0 {
                    (low - y_pad).max(0.0)
                } else {
                    low - y_pad
                },
                y_max + y_pad,
            ),
            x_label: &x_title,
            y_label: &y_title,
            title: "",
            y_labels_below: None,
        },
        lines: &lines,
        bare_meets: &bare_meets,
        low,
        top,
    };
    let path = dir.join(format!("design.{}", options.format.extension()));
    render(
        &path,
        options,
        canvas,
        |r| draw(r, canvas, &chart),
        |r| draw(r, canvas, &chart),
    )?;
    Ok(Some(path))
}

struct Chart<'a> {
    title: &'a str,
    legend: &'a [LegendEntry],
    axes: Axes<'a>,
    lines: &'a [Line],
    bare_meets: &'a [f64],
    low: f64,
    top: f64,
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    canvas: Canvas,
    c: &Chart,
) -> crate::error::Result<()> {
    let (body, _) = split_figure(&root, canvas, c.title, c.legend)?;
    let mut chart = build_chart(&body, canvas, &c.axes)?;
    for (i, line) in c.lines.iter().enumerate() {
        let style = SeriesStyle::nth(i);
        let pts: Vec<(f64, f64)> = line.points.iter().map(|p| (p.0, p.1)).collect();
        draw_line(&mut chart, canvas, &pts, style, LINE_PT)?;
        if let Some(m) = style.marker {
            draw_markers(&mut chart, canvas, &pts, m, style.color)?;
        }
        let flagged: Vec<(f64, f64)> = line
            .points
            .iter()
            .filter(|p| p.2)
            .map(|p| (p.0, p.1))
            .collect();
        draw_markers(&mut chart, canvas, &flagged, Marker::Cross, BLACK)?;
        let na: Vec<(f64, f64)> = line.not_achievable.iter().map(|x| (*x, c.top)).collect();
        draw_markers(&mut chart, canvas, &na, Marker::Triangle, NOT_ACHIEVABLE)?;
    }
    let bare: Vec<(f64, f64)> = c.bare_meets.iter().map(|x| (*x, c.low)).collect();
    draw_markers(
        &mut chart,
        canvas,
        &bare,
        Marker::Square,
        RGBColor(0, 158, 115),
    )?;
    Ok(())
}

/// The design chart's title in words: the study's title, what is sized and for which target,
/// over which excitation axes (`σ`, `|θ|max/α ≤ 0.5`, never `peak_rotation_ratio <= 0.5`).
pub fn design_title(study: &crate::study::Study, design: &crate::study::design::Design) -> String {
    use crate::study::design::DesignTarget;
    let target = match design.target {
        DesignTarget::Limit { quantity, max } => {
            format!(
                "{} ≤ {} without overturning",
                quantity.label(),
                fmt_num(max)
            )
        }
        other => other.describe().replace(">=", "≥").replace("<=", "≤"),
    };
    let over = design
        .over_ids(study)
        .iter()
        .map(|id| match *id {
            "frequency" => "pulse frequency",
            "amplitude" => "pulse amplitude",
            "scale" => "record scale",
            other => other,
        })
        .collect::<Vec<_>>()
        .join(" and ");
    format!(
        "{}: least {} for {target} at every {over}",
        super::study_title(study),
        design.parameter.label(),
    )
}
