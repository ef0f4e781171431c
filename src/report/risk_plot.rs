//! The risk figure: (a) the site's hazard curve λ(x), (b) each variant's fragility at the
//! collapse state in the hazard's IM, (c) the MAF's integrand P(DS | x) |dλ/dx| x per unit
//! ln x, whose area is the MAF: where the risk comes from. Intensities on a log₁₀ axis.

use super::figure::{
    Axes, Canvas, Dash, FigureOptions, FigureSize, LINE_PT, LegendEntry, PALETTE, SeriesStyle,
    Swatch, build_chart, draw_line, err, render, split_figure,
};
use crate::risk::{RiskReport, RiskRow, maf::integrand};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

const SAMPLES: usize = 200;

fn style(i: usize) -> SeriesStyle {
    SeriesStyle {
        color: PALETTE[i % PALETTE.len()],
        dash: Dash::ALL[(i / PALETTE.len()) % Dash::ALL.len()],
        marker: None,
    }
}

/// The rows drawn: each variant's highest damage state with a MAF.
fn drawn(report: &RiskReport) -> Vec<&RiskRow> {
    let top = report
        .rows
        .iter()
        .map(|r| r.damage_state)
        .fold(f64::NEG_INFINITY, f64::max);
    report
        .rows
        .iter()
        .filter(|r| r.damage_state == top && r.maf.is_some())
        .collect()
}

/// risk.svg / risk.png in `dir`; None if no row has a MAF.
pub fn plot_risk(
    dir: &Path,
    options: &FigureOptions,
    report: &RiskReport,
) -> crate::error::Result<Option<PathBuf>> {
    let rows = drawn(report);
    if rows.is_empty() {
        return Ok(None);
    }
    let legend: Vec<LegendEntry> = rows
        .iter()
        .enumerate()
        .map(|(i, r)| LegendEntry {
            label: format!(
                "{}: MAF {}/yr",
                r.variant.label(),
                crate::numfmt::fmt_sig(r.maf.unwrap_or(f64::NAN))
            ),
            swatch: Swatch::Line(style(i)),
        })
        .collect();
    let canvas = options.canvas(FigureSize::mm(186.0, 86.0), "the risk figure")?;
    let path = dir.join(format!("risk.{}", options.format.extension()));
    let title = format!(
        "Seismic risk at damage state {} over {}",
        rows[0].damage_state, report.hazard.source
    );
    render(
        &path,
        options,
        canvas,
        |r| draw(r, canvas, &title, &legend, report, &rows),
        |r| draw(r, canvas, &title, &legend, report, &rows),
    )?;
    Ok(Some(path))
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    canvas: Canvas,
    title: &str,
    legend: &[LegendEntry],
    report: &RiskReport,
    rows: &[&RiskRow],
) -> crate::error::Result<()> {
    let (body, _) = split_figure(&root, canvas, title, legend)?;
    let areas = body.split_evenly((1, 3));
    let h = &report.hazard.curve;
    let unit = format!("log₁₀ {} ({})", h.im.name().to_uppercase(), h.im.unit());
    // Intensities from the table's first point to past every row's 90 % deaggregation point.
    let lo = h.x[0].log10();
    let hi = rows
        .iter()
        .filter_map(|r| r.deagg_p90)
        .fold(h.x[h.x.len() - 1], f64::max)
        .log10()
        + 0.2;
    let xs: Vec<f64> = (0..=SAMPLES)
        .map(|i| lo + (hi - lo) * i as f64 / SAMPLES as f64)
        .collect();

    let rates: Vec<(f64, f64)> = xs
        .iter()
        .map(|&u| (u, h.rate(10f64.powf(u)).log10()))
        .collect();
    let (rmin, rmax) = rates
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.1), b.max(p.1))
        });
    let mut chart = build_chart(
        &areas[0],
        canvas,
        &Axes {
            x: (lo, hi),
            y: (rmin.floor(), rmax.ceil()),
            x_label: &unit,
            y_label: "log₁₀ λ (1/yr)",
            title: "(a) hazard curve",
            y_labels_below: None,
        },
    )?;
    draw_line(&mut chart, canvas, &rates, style(0), LINE_PT)?;
    let points: Vec<(f64, f64)> =
        h.x.iter()
            .zip(&h.rate)
            .map(|(x, r)| (x.log10(), r.log10()))
            .collect();
    chart
        .draw_series(
            points
                .iter()
                .map(|&p| Circle::new(p, canvas.px(2.0) as i32, PALETTE[0].filled())),
        )
        .map_err(err)?;

    let mut chart = build_chart(
        &areas[1],
        canvas,
        &Axes {
            x: (lo, hi),
            y: (0.0, 1.0),
            x_label: &unit,
            y_label: "P(DS | x)",
            title: "(b) fragility",
            y_labels_below: None,
        },
    )?;
    for (i, r) in rows.iter().enumerate() {
        let (Some(m), Some(b)) = (r.median, r.beta) else {
            continue;
        };
        let curve: Vec<(f64, f64)> = xs
            .iter()
            .map(|&u| (u, crate::stats::normal::cdf((10f64.powf(u) / m).ln() / b)))
            .collect();
        draw_line(&mut chart, canvas, &curve, style(i), LINE_PT)?;
    }

    let densities: Vec<Vec<(f64, f64)>> = rows
        .iter()
        .map(|r| {
            let (m, b) = (r.median.unwrap_or(1.0), r.beta.unwrap_or(1.0));
            xs.iter()
                .map(|&u| (u, integrand(h, m, b, 10f64.powf(u))))
                .collect()
        })
        .collect();
    let top = densities
        .iter()
        .flatten()
        .map(|p| p.1)
        .fold(0.0, f64::max)
        .max(1e-300);
    let mut chart = build_chart(
        &areas[2],
        canvas,
        &Axes {
            x: (lo, hi),
            y: (0.0, 1.05 * top),
            x_label: &unit,
            y_label: "P |dλ/dx| x (1/yr)",
            title: "(c) integrand: area = MAF",
            y_labels_below: None,
        },
    )?;
    for (i, d) in densities.iter().enumerate() {
        draw_line(&mut chart, canvas, d, style(i), LINE_PT)?;
    }
    root.present().map_err(err)
}
