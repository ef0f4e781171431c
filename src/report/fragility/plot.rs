//! The fragility figure: P(reach the damage state | IM) against the intensity measure, one
//! panel per damage state, one colour (and marker) per variant, one line pattern per damage
//! state; the stripe fractions (or, for IDA, the capacities at their plotting positions) as
//! points, and the median's bootstrap interval as a whisker at P = 0.5. Degenerate fits are
//! named in their panel instead of drawn. Looks come from `report::figure`.

use super::super::figure::{
    Axes, Canvas, Dash, FigureOptions, FigureSize, LINE_PT, LegendEntry, Marker, PALETTE,
    SeriesStyle, Swatch, build_chart, draw_line, draw_markers, err, render, split_figure,
};
use super::{Curve, FitStatus, FragilityReport, Method, Variant};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::{Path, PathBuf};

/// Points along each fitted curve.
const SAMPLES: usize = 160;

/// The style of a variant (colour and marker) in a damage state's pattern.
fn style(variant: usize, state: usize) -> SeriesStyle {
    SeriesStyle {
        color: PALETTE[variant % PALETTE.len()],
        dash: Dash::ALL[state % Dash::ALL.len()],
        marker: Some(Marker::ALL[variant % Marker::ALL.len()]),
    }
}

/// Variants and damage states in the report's order.
fn variants_and_states(report: &FragilityReport) -> (Vec<&Variant>, Vec<f64>) {
    let mut variants: Vec<&Variant> = Vec::new();
    let mut states: Vec<f64> = Vec::new();
    for c in &report.curves {
        if !variants.contains(&&c.variant) {
            variants.push(&c.variant);
        }
        if !states.contains(&c.damage_state) {
            states.push(c.damage_state);
        }
    }
    (variants, states)
}

/// The data points of a curve: stripe fractions, or IDA capacities at plotting positions
/// (i + ½)/n over all records, censored ones included in n.
pub fn data_points(c: &Curve) -> Vec<(f64, f64)> {
    match c.method {
        Method::Stripes => c.stripes.iter().map(|p| (p.im, p.fraction())).collect(),
        Method::Ida => {
            let n = c.n_records.max(1) as f64;
            c.capacities
                .iter()
                .enumerate()
                .map(|(i, &x)| (x, (i as f64 + 0.5) / n))
                .collect()
        }
    }
}

/// The fitted curve sampled over [0, x_max].
pub fn curve_points(c: &Curve, x_max: f64) -> Vec<(f64, f64)> {
    (1..=SAMPLES)
        .filter_map(|k| {
            let x = x_max * k as f64 / SAMPLES as f64;
            c.probability(x).map(|p| (x, p))
        })
        .collect()
}

/// The largest IM the report covers (at least 1).
pub fn x_max(report: &FragilityReport) -> f64 {
    report
        .curves
        .iter()
        .filter_map(|c| c.im_range)
        .map(|[_, hi]| hi)
        .chain(report.curves.iter().filter_map(|c| c.median_hi))
        .fold(f64::NAN, f64::max)
        .max(1e-9)
}

/// `c` moved towards white by `f` (0: unchanged, 1: white).
fn lighten(c: RGBColor, f: f64) -> RGBColor {
    let mix = |v: u8| (v as f64 + f * (255.0 - v as f64)).round() as u8;
    RGBColor(mix(c.0), mix(c.1), mix(c.2))
}

fn state_label(report: &FragilityReport, ds: f64) -> String {
    let measure = if report.damage_measure.is_empty() {
        "DM"
    } else {
        &report.damage_measure
    };
    format!("{measure} ≥ {ds}")
}

fn im_label(report: &FragilityReport) -> &str {
    if report.im.is_empty() {
        "intensity measure"
    } else {
        &report.im
    }
}

/// fragility.svg / fragility.png in `dir` from a report; None if it has no curve.
pub fn plot_fragility(
    dir: &Path,
    options: &FigureOptions,
    report: &FragilityReport,
) -> crate::error::Result<Option<PathBuf>> {
    if report.curves.is_empty() {
        return Ok(None);
    }
    let (variants, states) = variants_and_states(report);
    // A parameter every variant has (`sigma=0.5`) is said once, in the title.
    let labels: Vec<String> = variants.iter().map(|v| v.label()).collect();
    let (shared, own) = crate::report::naming::factor_shared(&labels);
    let mut legend: Vec<LegendEntry> = own
        .into_iter()
        .enumerate()
        .map(|(i, label)| LegendEntry {
            label,
            swatch: Swatch::Marker(
                style(i, 0).marker.unwrap_or(Marker::Circle),
                style(i, 0).color,
            ),
        })
        .collect();
    if states.len() > 1 {
        legend.extend(states.iter().enumerate().map(|(j, &ds)| LegendEntry {
            label: state_label(report, ds),
            swatch: Swatch::Line(SeriesStyle {
                color: BLACK,
                dash: Dash::ALL[j % 4],
                marker: None,
            }),
        }));
    }
    let cols = states.len().min(3);
    let rows = states.len().div_ceil(cols);
    let canvas = options.canvas(
        FigureSize::mm(
            if cols == 1 { 110.0 } else { 62.0 * cols as f64 },
            62.0 * rows as f64 + 24.0,
        ),
        "the fragility figure",
    )?;
    let path = dir.join(format!("fragility.{}", options.format.extension()));
    let title = crate::report::with_shared(
        &format!(
            "Fragility: P(damage state reached | {}), medians with {:.0} % bootstrap intervals",
            im_label(report),
            100.0 * report.confidence
        ),
        &shared,
    );
    render(
        &path,
        options,
        canvas,
        |r| draw(r, canvas, &title, &legend, report, cols),
        |r| draw(r, canvas, &title, &legend, report, cols),
    )?;
    Ok(Some(path))
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    canvas: Canvas,
    title: &str,
    legend: &[LegendEntry],
    report: &FragilityReport,
    cols: usize,
) -> crate::error::Result<()> {
    let (body, _) = split_figure(&root, canvas, title, legend)?;
    let (variants, states) = variants_and_states(report);
    let areas = body.split_evenly((states.len().div_ceil(cols), cols));
    let x_hi = 1.05 * x_max(report);
    for (j, (area, &ds)) in areas.iter().zip(&states).enumerate() {
        let panel_title = crate::report::panel_title(j, states.len(), &state_label(report, ds));
        let mut chart = build_chart(
            area,
            canvas,
            &Axes {
                x: (0.0, x_hi),
                y: (0.0, 1.0),
                x_label: im_label(report),
                y_label: "P(exceed)",
                title: &panel_title,
                y_labels_below: None,
            },
        )?;
        let mut notes = Vec::new();
        for c in report.curves.iter().filter(|c| c.damage_state == ds) {
            let i = variants.iter().position(|v| **v == c.variant).unwrap_or(0);
            let s = style(i, j);
            if let (Some(lo), Some(hi)) = (c.median_lo, c.median_hi) {
                // The median's interval: a whisker at P = ½, slightly offset per variant.
                let y = 0.5 + 0.012 * (i as f64 - (variants.len() as f64 - 1.0) / 2.0);
                let line = canvas.line(lighten(s.color, 0.45), 2.2);
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        vec![(lo, y), (hi, y)],
                        line,
                    )))
                    .map_err(err)?;
            }
            if c.status == FitStatus::Fitted {
                draw_line(&mut chart, canvas, &curve_points(c, x_hi), s, LINE_PT)?;
            } else {
                notes.push((
                    s.color,
                    format!("{}: {}", c.variant.label(), c.status.explain()),
                ));
            }
            if let Some(m) = s.marker {
                draw_markers(&mut chart, canvas, &data_points(c), m, s.color)?;
            }
        }
        // Degenerate fits, named in the panel's upper left.
        let (dx, dy) = (canvas.px(44.0) as i32, canvas.px(12.0) as i32);
        for (k, (color, text)) in notes.iter().enumerate() {
            area.draw(&Text::new(
                text.clone(),
                (dx, dy + k as i32 * canvas.px(9.0) as i32),
                canvas
                    .font(6.5)
                    .color(color)
                    .pos(Pos::new(HPos::Left, VPos::Top)),
            ))
            .map_err(err)?;
        }
    }
    root.present().map_err(err)
}
