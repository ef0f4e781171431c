//! The paper's figures from sweep results: spectra with one panel per quantity (and per facet
//! value), overturning maps with one panel per group, and a scene's histories stacked like the
//! paper's Figs. 8/9/14 with the energy partition as a stacked area (Fig. 15). Looks (size,
//! font, styles, ticks, legend) live in `figure.rs`.

// Over 800 lines: spectra, maps and histories share the curve and panel code here (looks live
// in figure.rs, selection in select.rs).

use super::aggregate::{Group, OverturningMap, PointState, Spectrum};
use super::compare::{MapCell, MapComparison, compare_maps};
use super::export::parameter;
use super::figure::{
    Axes, Canvas, Dash, FigureOptions, FigureSize, LINE_PT, LegendEntry, Marker, SeriesStyle,
    Swatch, build_chart, draw_line, draw_markers, err, render, split_figure,
};
use super::select::{Selector, select};
use crate::sim::History;
use crate::study::Quantity;
use crate::study::fmt_num;
use crate::sweep::{SceneOutcome, SweepResults};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// What to draw: which series (selectors), one panel row per value of a parameter (facet),
/// record suites as mean ± one standard deviation (band), and the most series in one panel.
#[derive(Clone, Debug, Default)]
pub struct PlotChoice {
    /// A series is drawn if it matches any selector (all if none given).
    pub select: Vec<String>,
    pub facet: Option<String>,
    pub band: bool,
    pub max_series: usize,
}

/// Most series in one panel unless `--max-series` says otherwise.
pub const MAX_SERIES: usize = 12;

/// A spectrum with what the figure needs to select, facet and style it.
struct Curve<'a> {
    spectrum: &'a Spectrum,
    record: Option<String>,
    /// The group without its record: the device label and its grid parameters.
    variant: String,
    /// Grid parameters of the group (coordinate label, value).
    params: Vec<(String, f64)>,
    /// Per x: whether the structure overturned there.
    overturned: Vec<bool>,
}

fn record_of(o: &SceneOutcome) -> Option<String> {
    match &o.point.scene.excitation {
        crate::scene::Excitation::Record { name, .. } => Some(name.clone()),
        _ => None,
    }
}

fn curves<'a>(results: &SweepResults, spectra: &'a [Spectrum]) -> Vec<Curve<'a>> {
    spectra
        .iter()
        .map(|s| {
            // A spectrum carries the indices of its outcomes: nothing here parses a label.
            let first = s.outcomes.first().and_then(|&i| results.outcomes.get(i));
            let record = s
                .group
                .record()
                .map(str::to_string)
                .or_else(|| first.and_then(record_of));
            let variant = match &record {
                Some(r) => s
                    .label
                    .strip_suffix(&format!(" · {r}"))
                    .unwrap_or(&s.label)
                    .to_string(),
                None => s.label.clone(),
            };
            let params = first.map_or(vec![], |o| o.point.coords.iter().skip(1).cloned().collect());
            let overturned = s
                .states
                .iter()
                .map(|st| *st == PointState::Overturned)
                .collect();
            Curve {
                spectrum: s,
                record,
                variant,
                params,
                overturned,
            }
        })
        .collect()
}

/// Whether a parameter name given by the user (study field `play`, CSV name `play`, or the
/// coordinate label `up`) names coordinate `label`.
fn names_parameter(given: &str, label: &str) -> bool {
    let p = parameter(label);
    given == label || given == p.name || given == p.field
}

/// Which of `groups` the `--select` selectors pick (the union; all without selectors), in
/// `compare`'s selector language (report/select.rs): `mechanistic`, `bare`,
/// `mechanistic(k_theta: 3.0, play: 0.005)`, `sequential(record: landers)`. A selector that
/// is malformed is an error; one that matches nothing says what there is and picks nothing.
fn selection(choice: &PlotChoice, groups: &[&Group]) -> anyhow::Result<Vec<bool>> {
    if choice.select.is_empty() {
        return Ok(vec![true; groups.len()]);
    }
    let mut picked = vec![false; groups.len()];
    for text in &choice.select {
        let sel = Selector::parse(text).map_err(|e| anyhow::anyhow!("--select: {e}"))?;
        match select(groups, &sel) {
            Ok(found) => found.into_iter().for_each(|i| picked[i] = true),
            Err(e) => eprintln!("--select {text}: {e}"),
        }
    }
    Ok(picked)
}

/// The label of a quantity's axis, with its symbol and unit.
fn quantity_axis(q: Quantity) -> &'static str {
    match q {
        Quantity::PeakRotation => "θmax [rad]",
        Quantity::PeakRotationRatio => "θmax/α",
        Quantity::PeakDeformation => "umax [m]",
        Quantity::PeakDrift => "drift |X|max/H",
        Quantity::PeakAbsAcceleration => "ẍmax [g]",
        Quantity::PeakAngularAcceleration => "θ̈max/p²",
    }
}

/// A coordinate's axis label with its unit, e.g. `ωn [rad/s]`.
fn coordinate_axis(label: &str) -> String {
    let unit = parameter(label).unit;
    if unit.is_empty() {
        label.to_string()
    } else {
        format!("{label} [{unit}]")
    }
}

fn figure_title(results: &SweepResults) -> String {
    results.study.as_ref().map_or("results".into(), |s| {
        if s.description.is_empty() {
            s.name.clone()
        } else {
            s.description.clone()
        }
    })
}

fn panel_letter(i: usize) -> char {
    (b'a' + (i % 26) as u8) as char
}

/// A drawn series of one panel: points (gaps break the line), overturned xs, style.
struct Drawn {
    segments: Vec<Vec<(f64, f64)>>,
    overturned: Vec<f64>,
    style: SeriesStyle,
    /// Mean ± s.d. band: (x, low, high).
    band: Vec<BandPoint>,
}

struct Panel {
    title: String,
    x_label: String,
    y_label: String,
    series: Vec<Drawn>,
}

fn segments(xs: &[f64], ys: &[Option<f64>]) -> Vec<Vec<(f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64)>> = vec![vec![]];
    for (x, y) in xs.iter().zip(ys) {
        match y {
            Some(y) if y.is_finite() => out.last_mut().expect("non-empty").push((*x, *y)),
            _ => out.push(vec![]),
        }
    }
    out.retain(|s| !s.is_empty());
    out
}

/// (x, low, high) of a band.
type BandPoint = (f64, f64, f64);

/// Mean and standard deviation over records per x (records that did not overturn there).
fn band_of(members: &[&Curve]) -> (Vec<Option<f64>>, Vec<BandPoint>) {
    let xs = &members[0].spectrum.xs;
    let mut mean = Vec::new();
    let mut band = Vec::new();
    for x in xs {
        let v: Vec<f64> = members
            .iter()
            .filter_map(|c| {
                let j = c.spectrum.xs.iter().position(|cx| cx == x)?;
                c.spectrum.ys[j]
            })
            .collect();
        if v.is_empty() {
            mean.push(None);
            continue;
        }
        let m = v.iter().sum::<f64>() / v.len() as f64;
        let sd = if v.len() > 1 {
            (v.iter().map(|y| (y - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64).sqrt()
        } else {
            0.0
        };
        mean.push(Some(m));
        // Every quantity is a magnitude: the band stops at zero.
        band.push((*x, (m - sd).max(0.0), m + sd));
    }
    (mean, band)
}

/// Spectra as one figure: a panel per quantity (columns) and per facet value (rows). Returns
/// the file written, or None with a message when nothing matched or a panel would hold too
/// many series.
pub fn plot_spectra(
    dir: &Path,
    options: &FigureOptions,
    results: &SweepResults,
    spectra: &[Spectrum],
    choice: &PlotChoice,
) -> anyhow::Result<Option<PathBuf>> {
    let all = curves(results, spectra);
    let groups: Vec<&Group> = all.iter().map(|c| &c.spectrum.group).collect();
    let picked = selection(choice, &groups)?;
    let chosen: Vec<&Curve> = all
        .iter()
        .zip(&picked)
        .filter(|(_, p)| **p)
        .map(|(c, _)| c)
        .collect();
    if chosen.is_empty() {
        if !choice.select.is_empty() {
            eprintln!(
                "no spectra match --select {}; series here: {}",
                choice.select.join(" / "),
                list_variants(&all)
            );
        }
        return Ok(None);
    }
    let mut quantities: Vec<Quantity> = Vec::new();
    for c in &chosen {
        if !quantities.contains(&c.spectrum.quantity) {
            quantities.push(c.spectrum.quantity);
        }
    }
    // Facet rows.
    let facet_label: Option<String> = match &choice.facet {
        None => None,
        Some(name) => {
            let labels: Vec<&String> = chosen
                .iter()
                .flat_map(|c| c.params.iter().map(|(l, _)| l))
                .collect();
            match labels.iter().find(|l| names_parameter(name, l)) {
                Some(l) => Some((*l).clone()),
                None => anyhow::bail!(
                    "--facet {name}: no such parameter among the chosen spectra (parameters: {})",
                    parameter_names(&chosen)
                ),
            }
        }
    };
    let facet_of = |c: &Curve| -> Option<f64> {
        let l = facet_label.as_ref()?;
        c.params.iter().find(|(n, _)| n == l).map(|(_, v)| *v)
    };
    let mut facets: Vec<Option<f64>> = Vec::new();
    for c in &chosen {
        let f = facet_of(c);
        if !facets.contains(&f) {
            facets.push(f);
        }
    }
    facets.sort_by(|a, b| a.unwrap_or(f64::NAN).total_cmp(&b.unwrap_or(f64::NAN)));
    const MAX_FACETS: usize = 8;
    if facets.len() > MAX_FACETS {
        anyhow::bail!(
            "--facet {}: {} values, more than {MAX_FACETS} rows of panels; narrow it with \
             --select (e.g. --select '{}')",
            choice.facet.as_deref().unwrap_or(""),
            facets.len(),
            example_selector(&chosen)
        );
    }
    // Series identity without the facet parameter, so a series keeps its style across rows.
    let facet_token = |c: &Curve| -> String {
        match (&facet_label, facet_of(c)) {
            (Some(l), Some(v)) => format!("{l}={}", fmt_num(v)),
            _ => String::new(),
        }
    };
    let variant_of = |c: &Curve| -> String {
        let t = facet_token(c);
        let v: Vec<&str> = c.variant.split(' ').filter(|w| *w != t).collect();
        v.join(" ")
    };
    let mut records: Vec<String> = Vec::new();
    let mut variants: Vec<String> = Vec::new();
    for c in &chosen {
        if let Some(r) = c.record.as_ref().filter(|r| !records.contains(r)) {
            records.push(r.clone());
        }
        let v = variant_of(c);
        if !variants.contains(&v) {
            variants.push(v);
        }
    }
    let suite = records.len() > 1;
    let band = choice.band && suite;
    let two_way = suite && variants.len() > 1 && !band;
    // Too many series in one panel: say how to choose.
    let per_panel = chosen
        .iter()
        .filter(|c| c.spectrum.quantity == quantities[0] && facet_of(c) == facets[0])
        .count();
    // A record suite drawn two-way (colour: record, line style: device) needs one legend key
    // per record and per device, not per line.
    let per_panel = if band {
        variants.len()
    } else if two_way {
        variants.len().max(records.len())
    } else {
        per_panel
    };
    let max = if choice.max_series == 0 {
        MAX_SERIES
    } else {
        choice.max_series
    };
    if per_panel > max {
        eprintln!(
            "{}: {per_panel} spectra per panel, more than {max}: spectra skipped (the maps \
             and results.csv have them all). Choose with --select, e.g. --select '{}' or \
             --select '{}' (a device kind or label with parameter values in the study's \
             syntax, as for `compare`; repeat --select for more series), split with \
             --facet PARAM (parameters: {}), or raise --max-series.",
            figure_title(results),
            example_selector(&chosen),
            example_record(&chosen),
            parameter_names(&chosen),
        );
        return Ok(None);
    }
    let style_of = |c: &Curve| -> SeriesStyle {
        let v = variants
            .iter()
            .position(|x| *x == variant_of(c))
            .unwrap_or(0);
        if two_way {
            let r = c
                .record
                .as_ref()
                .and_then(|r| records.iter().position(|x| x == r))
                .unwrap_or(0);
            SeriesStyle {
                color: super::figure::PALETTE[r % super::figure::PALETTE.len()],
                ..SeriesStyle::nth(v)
            }
        } else if suite && !band && variants.len() == 1 {
            let r = c
                .record
                .as_ref()
                .and_then(|r| records.iter().position(|x| x == r))
                .unwrap_or(0);
            SeriesStyle::nth(r)
        } else {
            SeriesStyle::nth(v)
        }
    };
    // Legend.
    let mut legend: Vec<LegendEntry> = Vec::new();
    if two_way {
        for (i, v) in variants.iter().enumerate() {
            legend.push(LegendEntry {
                label: v.clone(),
                swatch: Swatch::Line(SeriesStyle {
                    color: BLACK,
                    ..SeriesStyle::nth(i)
                }),
            });
        }
        for (i, r) in records.iter().enumerate() {
            legend.push(LegendEntry {
                label: r.clone(),
                swatch: Swatch::Line(SeriesStyle {
                    color: super::figure::PALETTE[i % super::figure::PALETTE.len()],
                    dash: Dash::Solid,
                    marker: None,
                }),
            });
        }
    } else if suite && !band && variants.len() == 1 {
        for (i, r) in records.iter().enumerate() {
            legend.push(LegendEntry {
                label: r.clone(),
                swatch: Swatch::Line(SeriesStyle::nth(i)),
            });
        }
    } else {
        for (i, v) in variants.iter().enumerate() {
            let label = if band {
                format!("{v}: mean ± 1 s.d. over {} records", records.len())
            } else {
                v.clone()
            };
            legend.push(LegendEntry {
                label,
                swatch: Swatch::Line(SeriesStyle::nth(i)),
            });
        }
    }
    let any_overturned = chosen.iter().any(|c| c.overturned.iter().any(|o| *o));
    if any_overturned {
        legend.push(LegendEntry {
            label: "overturned (drawn above the data, no peak)".into(),
            swatch: Swatch::Marker(Marker::Cross, RGBColor(90, 90, 90)),
        });
    }
    // Panels: rows = facets, columns = quantities (4 quantities without facets: 2 × 2).
    let mut panels: Vec<Panel> = Vec::new();
    for f in &facets {
        for q in &quantities {
            let in_panel: Vec<&&Curve> = chosen
                .iter()
                .filter(|c| c.spectrum.quantity == *q && facet_of(c) == *f)
                .collect();
            let mut series = Vec::new();
            if band {
                for v in &variants {
                    let members: Vec<&Curve> = in_panel
                        .iter()
                        .filter(|c| variant_of(c) == *v)
                        .map(|c| **c)
                        .collect();
                    if members.is_empty() {
                        continue;
                    }
                    let (mean, band) = band_of(&members);
                    let xs = &members[0].spectrum.xs;
                    let overturned = xs
                        .iter()
                        .filter(|x| {
                            members.iter().any(|c| {
                                c.spectrum
                                    .xs
                                    .iter()
                                    .position(|cx| cx == *x)
                                    .is_some_and(|j| c.overturned[j])
                            })
                        })
                        .copied()
                        .collect();
                    series.push(Drawn {
                        segments: segments(xs, &mean),
                        overturned,
                        style: style_of(members[0]),
                        band,
                    });
                }
            } else {
                for c in &in_panel {
                    let s = c.spectrum;
                    series.push(Drawn {
                        segments: segments(&s.xs, &s.ys),
                        overturned: s
                            .xs
                            .iter()
                            .zip(&c.overturned)
                            .filter(|(_, o)| **o)
                            .map(|(x, _)| *x)
                            .collect(),
                        style: style_of(c),
                        band: vec![],
                    });
                }
            }
            let letter = panel_letter(panels.len());
            let title = match (&facet_label, f) {
                (Some(l), Some(v)) => format!("({letter}) {l} = {}", with_unit(l, *v)),
                _ => format!("({letter})"),
            };
            panels.push(Panel {
                title,
                x_label: coordinate_axis(&in_panel[0].spectrum.axis),
                y_label: quantity_axis(*q).to_string(),
                series,
            });
        }
    }
    let cols = if facets.len() == 1 && quantities.len() == 4 {
        2
    } else {
        quantities.len()
    };
    let rows = panels.len().div_ceil(cols);
    let default = FigureSize::mm(
        if cols == 1 { 120.0 } else { 85.0 * cols as f64 },
        62.0 * rows as f64 + 12.0 + 6.0 * (legend.len() as f64 / 3.0).ceil(),
    );
    let canvas = options.canvas(default);
    let title = figure_title(results);
    let name = match &facet_label {
        Some(l) => format!("spectra-by-{}", parameter(l).name),
        None => "spectra".to_string(),
    };
    let path = dir.join(format!("{name}.{}", options.format.extension()));
    render(
        &path,
        options,
        canvas,
        |r| draw_panels(r, canvas, &title, &legend, &panels, cols),
        |r| draw_panels(r, canvas, &title, &legend, &panels, cols),
    )?;
    Ok(Some(path))
}

fn with_unit(label: &str, v: f64) -> String {
    let unit = parameter(label).unit;
    if unit.is_empty() {
        fmt_num(v)
    } else {
        format!("{} {unit}", fmt_num(v))
    }
}

fn list_variants(curves: &[Curve]) -> String {
    let mut v: Vec<&str> = Vec::new();
    for c in curves {
        if !v.contains(&c.spectrum.label.as_str()) {
            v.push(&c.spectrum.label);
        }
    }
    let n = v.len();
    let mut s = v.into_iter().take(8).collect::<Vec<_>>().join(", ");
    if n > 8 {
        s.push_str(&format!(", … ({n} in all)"));
    }
    s
}

fn parameter_names(curves: &[&Curve]) -> String {
    let mut names: Vec<String> = Vec::new();
    for c in curves {
        for (l, _) in &c.params {
            let n = format!("{} ({l})", parameter(l).name);
            if !names.contains(&n) {
                names.push(n);
            }
        }
    }
    if names.is_empty() {
        "none vary".into()
    } else {
        names.join(", ")
    }
}

/// A selector for the first chosen series: its device and first varying parameter.
fn example_selector(curves: &[&Curve]) -> String {
    example_of(&curves[0].spectrum.group)
}

/// A selector for the last chosen series' device, with its record when there is one.
fn example_record(curves: &[&Curve]) -> String {
    let g = &curves[curves.len() - 1].spectrum.group;
    let device = device_name(g);
    match g.record() {
        Some(r) => format!("{device}(record: {r})"),
        None => device,
    }
}

fn device_name(g: &Group) -> String {
    match g.device {
        crate::study::DeviceKind::None => "bare".into(),
        k => k.name().into(),
    }
}

fn range_of(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    if hi > lo {
        (lo, hi)
    } else {
        (lo - 0.5, hi + 0.5)
    }
}

fn draw_panels<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    canvas: Canvas,
    title: &str,
    legend: &[LegendEntry],
    panels: &[Panel],
    cols: usize,
) -> anyhow::Result<()> {
    let (body, _) = split_figure(&root, canvas, title, legend)?;
    let rows = panels.len().div_ceil(cols);
    let areas = body.split_evenly((rows, cols));
    for (area, panel) in areas.iter().zip(panels) {
        draw_spectrum_panel(area, canvas, panel)?;
    }
    root.present().map_err(err)
}

fn draw_spectrum_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    canvas: Canvas,
    panel: &Panel,
) -> anyhow::Result<()> {
    let points = || {
        panel
            .series
            .iter()
            .flat_map(|s| s.segments.iter().flatten())
    };
    let (x0, x1) = range_of(
        points().map(|p| p.0).chain(
            panel
                .series
                .iter()
                .flat_map(|s| s.overturned.iter().copied()),
        ),
    );
    let y_hi = range_of(
        points()
            .map(|p| p.1)
            .chain(panel.series.iter().flat_map(|s| s.band.iter().map(|b| b.2))),
    )
    .1
    .max(0.0);
    let y_lo = range_of(
        points()
            .map(|p| p.1)
            .chain(panel.series.iter().flat_map(|s| s.band.iter().map(|b| b.1))),
    )
    .0
    .min(0.0);
    let y_hi = if y_hi > y_lo { y_hi } else { y_lo + 1.0 };
    // Overturned points sit in a strip above the data, one row per series that has any.
    let rows_over = panel
        .series
        .iter()
        .filter(|s| !s.overturned.is_empty())
        .count();
    let row = 0.045 * (y_hi - y_lo);
    let top = y_hi + 0.04 * (y_hi - y_lo) + rows_over as f64 * row;
    let mut chart = build_chart(
        area,
        canvas,
        &Axes {
            x: (x0, x1),
            y: (y_lo, top),
            x_label: &panel.x_label,
            y_label: &panel.y_label,
            title: &panel.title,
            y_labels_below: (rows_over > 0).then_some(y_hi),
        },
    )?;
    if rows_over > 0 {
        // The strip of overturned marks: no grid, a rule below it.
        let strip = y_hi + 0.02 * (y_hi - y_lo);
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(x0, strip), (x1, top)],
                WHITE.filled(),
            )))
            .map_err(err)?;
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(x0, strip), (x1, strip)],
                canvas.line(RGBColor(150, 150, 150), 0.4),
            )))
            .map_err(err)?;
    }
    for s in &panel.series {
        if !s.band.is_empty() {
            let mut poly: Vec<(f64, f64)> = s.band.iter().map(|b| (b.0, b.2)).collect();
            poly.extend(s.band.iter().rev().map(|b| (b.0, b.1.max(y_lo))));
            chart
                .draw_series(std::iter::once(Polygon::new(
                    poly,
                    s.style.color.mix(0.13).filled(),
                )))
                .map_err(err)?;
        }
    }
    let mut grid: Vec<f64> = points().map(|p| p.0).collect();
    grid.sort_by(f64::total_cmp);
    grid.dedup();
    let mut over_row = 0;
    for (i, s) in panel.series.iter().enumerate() {
        for seg in &s.segments {
            if seg.len() == 1 {
                continue;
            }
            draw_line(&mut chart, canvas, seg, s.style, LINE_PT)?;
        }
        if let Some(m) = s.style.marker {
            // About 8 markers per series on a grid of the panel's x values, staggered so
            // series that coincide (inerter and sequential accelerations) both show.
            let every = (grid.len() / 8).max(1);
            let offset = (i * every / panel.series.len().max(1)) % every;
            let on_grid = |x: f64| grid.iter().position(|g| *g == x).unwrap_or(0);
            let mut marks: Vec<(f64, f64)> = s
                .segments
                .iter()
                .flatten()
                .filter(|p| on_grid(p.0) % every == offset)
                .copied()
                .collect();
            // Isolated points (a single x between gaps) always get a marker.
            marks.extend(s.segments.iter().filter(|g| g.len() == 1).map(|g| g[0]));
            draw_markers(&mut chart, canvas, &marks, m, s.style.color)?;
        }
        if !s.overturned.is_empty() {
            let y = y_hi + 0.04 * (y_hi - y_lo) + (over_row as f64 + 0.5) * row;
            over_row += 1;
            let pts: Vec<(f64, f64)> = s.overturned.iter().map(|x| (*x, y)).collect();
            draw_markers(&mut chart, canvas, &pts, Marker::Cross, s.style.color)?;
        }
    }
    Ok(())
}

/// Overturning maps, one panel per group, in one figure.
pub fn plot_maps(
    dir: &Path,
    options: &FigureOptions,
    results: &SweepResults,
    maps: &[OverturningMap],
    choice: &PlotChoice,
) -> anyhow::Result<Option<PathBuf>> {
    let groups: Vec<&Group> = maps.iter().map(|m| &m.group).collect();
    let picked = selection(choice, &groups)?;
    let chosen: Vec<&OverturningMap> = maps
        .iter()
        .zip(&picked)
        .filter(|(_, p)| **p)
        .map(|(m, _)| m)
        .collect();
    if chosen.is_empty() {
        return Ok(None);
    }
    const MAX_MAPS: usize = 12;
    if chosen.len() > MAX_MAPS {
        eprintln!(
            "{} overturning maps, more than {MAX_MAPS} in one figure: skipped; choose with --select",
            chosen.len()
        );
        return Ok(None);
    }
    let cols = chosen.len().min(3);
    let rows = chosen.len().div_ceil(cols);
    let legend = vec![
        LegendEntry {
            label: "overturned".into(),
            swatch: Swatch::Fill(OVERTURNED),
        },
        LegendEntry {
            label: "survived".into(),
            swatch: Swatch::Fill(SURVIVED),
        },
        LegendEntry {
            label: "failed or not run".into(),
            swatch: Swatch::Fill(WHITE),
        },
    ];
    let canvas = options.canvas(FigureSize::mm(
        if cols == 1 { 100.0 } else { 65.0 * cols as f64 },
        60.0 * rows as f64 + 18.0,
    ));
    let title = figure_title(results);
    let path = dir.join(format!("maps.{}", options.format.extension()));
    render(
        &path,
        options,
        canvas,
        |r| draw_maps(r, canvas, &title, &legend, &chosen, cols),
        |r| draw_maps(r, canvas, &title, &legend, &chosen, cols),
    )?;
    Ok(Some(path))
}

const OVERTURNED: RGBColor = RGBColor(213, 94, 0);
const SURVIVED: RGBColor = RGBColor(232, 232, 232);

fn draw_maps<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    canvas: Canvas,
    title: &str,
    legend: &[LegendEntry],
    maps: &[&OverturningMap],
    cols: usize,
) -> anyhow::Result<()> {
    let (body, _) = split_figure(&root, canvas, title, legend)?;
    let areas = body.split_evenly((maps.len().div_ceil(cols), cols));
    for (i, (area, map)) in areas.iter().zip(maps).enumerate() {
        draw_map(
            area,
            canvas,
            map,
            &format!("({}) {}", panel_letter(i), map.label),
        )?;
    }
    root.present().map_err(err)
}

fn draw_map<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    canvas: Canvas,
    map: &OverturningMap,
    title: &str,
) -> anyhow::Result<()> {
    let grid = CellGrid {
        xs: &map.xs,
        ys: &map.ys,
        x_axis: &map.x_axis,
        y_axis: &map.y_axis,
        boundary_of: Some(&map.cells),
    };
    draw_cells(area, canvas, &grid, title, |ix, iy| {
        match map.cells[iy][ix] {
            Some(true) => OVERTURNED,
            Some(false) => SURVIVED,
            None => WHITE,
        }
    })
}

/// The axes of a map of cells.
struct CellGrid<'a> {
    xs: &'a [f64],
    ys: &'a [f64],
    x_axis: &'a str,
    y_axis: &'a str,
    /// Overturned verdicts whose boundary is drawn as a line (a single map's panel).
    boundary_of: Option<&'a [Vec<Option<bool>>]>,
}

/// A map panel: one filled rectangle per cell, coloured by `color(ix, iy)`.
fn draw_cells<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    canvas: Canvas,
    grid: &CellGrid,
    title: &str,
    color: impl Fn(usize, usize) -> RGBColor,
) -> anyhow::Result<()> {
    let edges = |v: &[f64]| -> Vec<f64> {
        // Cell edges halfway between grid values.
        let n = v.len();
        if n == 0 {
            return vec![0.0, 1.0];
        }
        if n == 1 {
            return vec![v[0] - 0.5, v[0] + 0.5];
        }
        let mut e = vec![v[0] - (v[1] - v[0]) / 2.0];
        e.extend(v.windows(2).map(|w| (w[0] + w[1]) / 2.0));
        e.push(v[n - 1] + (v[n - 1] - v[n - 2]) / 2.0);
        e
    };
    let (ex, ey) = (edges(grid.xs), edges(grid.ys));
    let (x_label, y_label) = (coordinate_axis(grid.x_axis), coordinate_axis(grid.y_axis));
    let mut chart = build_chart(
        area,
        canvas,
        &Axes {
            x: (ex[0], ex[ex.len() - 1]),
            y: (ey[0], ey[ey.len() - 1]),
            x_label: &x_label,
            y_label: &y_label,
            title,
            y_labels_below: None,
        },
    )?;
    let (nx, ny) = (grid.xs.len(), grid.ys.len());
    let cells = (0..ny).flat_map(|iy| {
        let (ex, ey, color) = (&ex, &ey, &color);
        (0..nx).map(move |ix| {
            Rectangle::new(
                [(ex[ix], ey[iy]), (ex[ix + 1], ey[iy + 1])],
                color(ix, iy).filled(),
            )
        })
    });
    chart.draw_series(cells).map_err(err)?;
    // The overturning boundary: the cell edges between an overturned and a survived cell.
    let Some(cells) = grid.boundary_of else {
        return Ok(());
    };
    let verdict = |ix: usize, iy: usize| cells.get(iy).and_then(|r| r.get(ix)).copied().flatten();
    let mut edges = Vec::new();
    for iy in 0..ny {
        for ix in 0..nx {
            let Some(here) = verdict(ix, iy) else {
                continue;
            };
            if verdict(ix + 1, iy).is_some_and(|v| v != here) {
                edges.push(vec![(ex[ix + 1], ey[iy]), (ex[ix + 1], ey[iy + 1])]);
            }
            if verdict(ix, iy + 1).is_some_and(|v| v != here) {
                edges.push(vec![(ex[ix], ey[iy + 1]), (ex[ix + 1], ey[iy + 1])]);
            }
        }
    }
    chart
        .draw_series(
            edges
                .into_iter()
                .map(|e| PathElement::new(e, BLACK.stroke_width(2))),
        )
        .map_err(err)?;
    Ok(())
}

/// The colour of each kind of cell of two maps compared (Okabe–Ito, apart in greyscale too:
/// light grey, sky blue, vermillion, dark grey, white).
fn map_cell_color(c: MapCell) -> RGBColor {
    match c {
        MapCell::BothSurvive => SURVIVED,
        MapCell::OnlyBSurvives => super::figure::PALETTE[5],
        MapCell::OnlyASurvives => super::figure::PALETTE[4],
        MapCell::BothOverturn => RGBColor(64, 64, 64),
        MapCell::Missing => WHITE,
    }
}

/// Two variants' overturning maps compared, one panel per pair (`compare`'s pairing of the
/// selectors `a` and `b`): where both survive, only B survives (B's protective benefit), only
/// A survives, both overturn, or a side failed or did not run; a legend with what each
/// colour is. Returns the file written, or None when the results hold no maps.
pub fn plot_map_differences(
    dir: &Path,
    options: &FigureOptions,
    maps: &[OverturningMap],
    a: &str,
    b: &str,
) -> anyhow::Result<Option<PathBuf>> {
    if maps.is_empty() {
        return Ok(None);
    }
    let (sa, sb) = (
        Selector::parse(a).map_err(|e| anyhow::anyhow!("--a: {e}"))?,
        Selector::parse(b).map_err(|e| anyhow::anyhow!("--b: {e}"))?,
    );
    let pairs = compare_maps(maps, &sa, &sb).map_err(|e| anyhow::anyhow!("{e}"))?;
    const MAX_MAPS: usize = 12;
    if pairs.len() > MAX_MAPS {
        anyhow::bail!(
            "{} pairs of overturning maps, more than {MAX_MAPS} in one figure; narrow --a/--b \
             with parameter values, e.g. --b '{}'",
            pairs.len(),
            example_of(&pairs[0].b_group)
        );
    }
    let legend: Vec<LegendEntry> = MapCell::ALL
        .iter()
        .map(|c| LegendEntry {
            label: c.meaning().to_string(),
            swatch: Swatch::Fill(map_cell_color(*c)),
        })
        .collect();
    let cols = pairs.len().min(3);
    let rows = pairs.len().div_ceil(cols);
    let canvas = options.canvas(FigureSize::mm(
        if cols == 1 { 110.0 } else { 65.0 * cols as f64 },
        60.0 * rows as f64 + 24.0,
    ));
    let title = format!("Overturning maps compared: A = {a}, B = {b}");
    let path = dir.join(format!("maps-difference.{}", options.format.extension()));
    render(
        &path,
        options,
        canvas,
        |r| draw_map_differences(r, canvas, &title, &legend, &pairs, cols),
        |r| draw_map_differences(r, canvas, &title, &legend, &pairs, cols),
    )?;
    Ok(Some(path))
}

fn draw_map_differences<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    canvas: Canvas,
    title: &str,
    legend: &[LegendEntry],
    pairs: &[MapComparison],
    cols: usize,
) -> anyhow::Result<()> {
    let (body, _) = split_figure(&root, canvas, title, legend)?;
    let areas = body.split_evenly((pairs.len().div_ceil(cols), cols));
    for (i, (area, m)) in areas.iter().zip(pairs).enumerate() {
        let grid = CellGrid {
            xs: &m.xs,
            ys: &m.ys,
            x_axis: &m.x_axis,
            y_axis: &m.y_axis,
            boundary_of: None,
        };
        let title = format!("({}) {} vs {}", panel_letter(i), m.a, m.b);
        draw_cells(area, canvas, &grid, &title, |ix, iy| {
            map_cell_color(m.cells[iy][ix])
        })?;
    }
    root.present().map_err(err)
}

/// A selector naming a group's device and its first varying parameter.
fn example_of(g: &Group) -> String {
    let device = device_name(g);
    match g.settings.iter().find(|s| s.varies && s.id != "record") {
        Some(s) => format!("{device}({}: {})", s.id, s.text),
        None => device,
    }
}

/// One panel of a scene's histories: lines, or a stacked area with a line on top.
struct HistoryPanel {
    y_label: String,
    lines: Vec<(Vec<f64>, SeriesStyle)>,
    stack: Vec<(Vec<f64>, RGBColor)>,
}

/// At most `n` points per series: the min and max of each bucket, so peaks survive.
fn decimate(t: &[f64], y: &[f64], n: usize) -> Vec<(f64, f64)> {
    if t.len() <= n {
        return t.iter().copied().zip(y.iter().copied()).collect();
    }
    let bucket = t.len().div_ceil(n / 2);
    let mut out = Vec::with_capacity(n + 2);
    for (tc, yc) in t.chunks(bucket).zip(y.chunks(bucket)) {
        let (imin, imax) = yc.iter().enumerate().fold((0, 0), |(a, b), (i, v)| {
            (
                if *v < yc[a] { i } else { a },
                if *v > yc[b] { i } else { b },
            )
        });
        for i in if imin <= imax {
            [imin, imax]
        } else {
            [imax, imin]
        } {
            out.push((tc[i], yc[i]));
        }
    }
    out
}

/// A scene's histories as the paper's Figs. 8/9/14/15: rotation (and deformation), ground
/// acceleration, flywheel velocities, device force, and the energy partition stacked.
pub fn plot_history(
    path: &Path,
    options: &FigureOptions,
    title: &str,
    scene: &crate::scene::Scene,
    history: &History,
) -> anyhow::Result<()> {
    let t = history
        .column("t")
        .ok_or_else(|| anyhow::anyhow!("the history has no time column"))?;
    let col = |n: &str| history.column(n);
    let nonzero = |v: &Option<Vec<f64>>| v.as_ref().is_some_and(|v| v.iter().any(|x| *x != 0.0));
    let solid = |i: usize| SeriesStyle {
        marker: None,
        dash: Dash::Solid,
        ..SeriesStyle::nth(i)
    };
    let mut panels: Vec<HistoryPanel> = Vec::new();
    let mut legend: Vec<LegendEntry> = Vec::new();
    let alpha = scene.structure.alpha();
    let flexible = col("u").is_some();
    if let Some(theta) = col("theta") {
        panels.push(if flexible {
            HistoryPanel {
                y_label: "θ [rad]".into(),
                lines: vec![(theta, solid(0))],
                stack: vec![],
            }
        } else {
            HistoryPanel {
                y_label: "θ/α".into(),
                lines: vec![(theta.iter().map(|v| v / alpha).collect(), solid(0))],
                stack: vec![],
            }
        });
    }
    if let Some(u) = col("u") {
        panels.push(HistoryPanel {
            y_label: "u [m]".into(),
            lines: vec![(u, solid(0))],
            stack: vec![],
        });
    }
    if let Some(ag) = col("ground_accel") {
        panels.push(HistoryPanel {
            y_label: "ag [g]".into(),
            lines: vec![(ag.iter().map(|v| v / 9.81).collect(), solid(0))],
            stack: vec![],
        });
    }
    let (va, vb) = (col("flywheel_a_vel"), col("flywheel_b_vel"));
    if nonzero(&va) || nonzero(&vb) {
        let mut lines = Vec::new();
        let a_style = solid(2);
        let b_style = SeriesStyle {
            dash: Dash::Short,
            ..solid(4)
        };
        if let Some(v) = va.filter(|v| v.iter().any(|x| *x != 0.0)) {
            lines.push((v, a_style));
            legend.push(LegendEntry {
                label: "flywheel a".into(),
                swatch: Swatch::Line(a_style),
            });
        }
        if let Some(v) = vb.filter(|v| v.iter().any(|x| *x != 0.0)) {
            lines.push((v, b_style));
            legend.push(LegendEntry {
                label: "flywheel b".into(),
                swatch: Swatch::Line(b_style),
            });
        }
        panels.push(HistoryPanel {
            y_label: "ẏ [m/s]".into(),
            lines,
            stack: vec![],
        });
    }
    let fd = col("device_force");
    if nonzero(&fd) {
        panels.push(HistoryPanel {
            y_label: "Fd [N]".into(),
            lines: vec![(fd.expect("checked"), solid(0))],
            stack: vec![],
        });
    }
    // Energy partition: every stored or dissipated term stacked, the input work on top.
    let terms: Vec<&str> = history
        .columns
        .iter()
        .copied()
        .filter(|c| c.starts_with("e_") && *c != "e_input")
        .collect();
    if !terms.is_empty() {
        let mut stack = Vec::new();
        for (i, name) in terms.iter().enumerate() {
            let v = col(name).expect("listed");
            if v.iter().all(|x| *x == 0.0) {
                continue;
            }
            let color = super::figure::PALETTE[(i + 1) % super::figure::PALETTE.len()];
            legend.push(LegendEntry {
                label: energy_label(name),
                swatch: Swatch::Fill(color.mix(0.55).rgb_blend()),
            });
            stack.push((v, color));
        }
        let input_style = solid(0);
        let mut lines = vec![];
        if let Some(e) = col("e_input") {
            lines.push((e, input_style));
            legend.push(LegendEntry {
                label: "input work".into(),
                swatch: Swatch::Line(input_style),
            });
        }
        panels.push(HistoryPanel {
            y_label: "E [J]".into(),
            lines,
            stack,
        });
    }
    let canvas = options.canvas(FigureSize::mm(160.0, 32.0 * panels.len() as f64 + 22.0));
    render(
        path,
        options,
        canvas,
        |r| draw_history(r, canvas, title, &legend, &t, &panels),
        |r| draw_history(r, canvas, title, &legend, &t, &panels),
    )
}

trait Blend {
    fn rgb_blend(&self) -> RGBColor;
}

impl Blend for RGBAColor {
    /// The colour of this translucent colour over white, for legend boxes.
    fn rgb_blend(&self) -> RGBColor {
        let (r, g, b) = self.rgb();
        let a = self.alpha();
        let f = |c: u8| (c as f64 * a + 255.0 * (1.0 - a)).round() as u8;
        RGBColor(f(r), f(g), f(b))
    }
}

fn energy_label(column: &str) -> String {
    match column {
        "e_structure" => "structure (kinetic + potential)".into(),
        "e_inerter" => "flywheels + clutch spring".into(),
        "e_dissipated" => "dissipated".into(),
        "e_column_damping" => "column damping".into(),
        "e_device_damping" => "device damping".into(),
        "e_friction" => "friction".into(),
        "e_impact" => "impacts".into(),
        "e_disengagement" => "disengagement".into(),
        "e_reset" => "clutch resets".into(),
        other => other.trim_start_matches("e_").replace('_', " "),
    }
}

fn draw_history<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    canvas: Canvas,
    title: &str,
    legend: &[LegendEntry],
    t: &[f64],
    panels: &[HistoryPanel],
) -> anyhow::Result<()> {
    let (body, _) = split_figure(&root, canvas, title, legend)?;
    let areas = body.split_evenly((panels.len().max(1), 1));
    let (t0, t1) = range_of(t.iter().copied());
    const POINTS: usize = 4000;
    for (i, (area, panel)) in areas.iter().zip(panels).enumerate() {
        // Cumulative sums of the stack.
        let mut cumulative: Vec<Vec<f64>> = Vec::new();
        let mut acc = vec![0.0; t.len()];
        for (v, _) in &panel.stack {
            for (a, x) in acc.iter_mut().zip(v) {
                *a += x;
            }
            cumulative.push(acc.clone());
        }
        let (y0, y1) = range_of(
            panel
                .lines
                .iter()
                .flat_map(|(v, _)| v.iter().copied())
                .chain(cumulative.iter().flatten().copied())
                .chain(if panel.stack.is_empty() {
                    None
                } else {
                    Some(0.0)
                }),
        );
        let pad = 0.05 * (y1 - y0);
        let mut chart = build_chart(
            area,
            canvas,
            &Axes {
                x: (t0, t1),
                y: (y0 - pad, y1 + pad),
                x_label: if i + 1 == panels.len() { "t [s]" } else { "" },
                y_label: &panel.y_label,
                title: "",
                y_labels_below: None,
            },
        )?;
        let mut lower = vec![0.0; t.len()];
        for (upper, (_, color)) in cumulative.iter().zip(&panel.stack) {
            let top = decimate(t, upper, POINTS);
            let bottom = decimate(t, &lower, POINTS);
            let mut poly = top;
            poly.extend(bottom.into_iter().rev());
            chart
                .draw_series(std::iter::once(Polygon::new(
                    poly,
                    color.mix(0.55).filled(),
                )))
                .map_err(err)?;
            lower.clone_from(upper);
        }
        for (v, style) in &panel.lines {
            let pts = decimate(t, v, POINTS);
            // Thin lines: plotters leaves gaps between many short wide segments.
            draw_line(&mut chart, canvas, &pts, *style, 0.7)?;
        }
    }
    root.present().map_err(err)
}

/// A readable label for a scene, for history plots.
pub fn scene_title(index: usize, group: &str, coords: &[(String, f64)]) -> String {
    let c: Vec<String> = coords
        .iter()
        .map(|(n, v)| format!("{n} = {}", fmt_num(*v)))
        .collect();
    format!("scene {index}: {group}, {}", c.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimation_keeps_the_extremes() {
        let t: Vec<f64> = (0..10_000).map(|i| i as f64).collect();
        let y: Vec<f64> = t
            .iter()
            .map(|x| (x * 0.01).sin() * if *x == 4321.0 { 5.0 } else { 1.0 })
            .collect();
        let d = decimate(&t, &y, 500);
        assert!(d.len() <= 502, "{}", d.len());
        let max = d.iter().map(|p| p.1).fold(f64::MIN, f64::max);
        let true_max = y.iter().copied().fold(f64::MIN, f64::max);
        assert_eq!(max, true_max);
    }
}
