//! Spectra as one figure: a panel per quantity (columns) and per facet value (rows), record
//! suites as mean ± one standard deviation, overturned points in a strip above the data.

use super::{
    MAX_SERIES, PlotChoice, coordinate_axis, device_name, example_of, figure_title, keep_on_axes,
    kept, panel_title, range_of, selection, with_shared,
};
use crate::numfmt::fmt_num;
use crate::report::aggregate::{Group, PointState, Spectrum};
use crate::report::export::parameter;
use crate::report::figure::{
    Axes, Canvas, Dash, FigureOptions, FigureSize, LINE_PT, LegendEntry, Marker, SeriesStyle,
    Swatch, build_chart, draw_line, draw_markers, err, render, split_figure,
};
use crate::report::select::axis_id;
use crate::study::Quantity;
use crate::sweep::{SceneOutcome, SweepResults};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

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
) -> crate::error::Result<Option<PathBuf>> {
    let groups: Vec<&Group> = spectra.iter().map(|s| &s.group).collect();
    let axes: Vec<&str> = spectra
        .first()
        .and_then(|s| axis_id(&s.axis))
        .into_iter()
        .collect();
    let (picked, on_axes) = selection(choice, &groups, &axes)?;
    // Filters on the spectrum's axis (`frequency: [1.0, 2.0]`) keep those points.
    let mut cropped: Vec<Spectrum> = Vec::new();
    for (s, p) in spectra.iter().zip(&picked) {
        let keep = match p {
            true => keep_on_axes(axis_id(&s.axis), &s.xs, &on_axes)?,
            false => vec![true; s.xs.len()],
        };
        cropped.push(Spectrum {
            xs: kept(&s.xs, &keep),
            ys: kept(&s.ys, &keep),
            states: kept(&s.states, &keep),
            outcomes: kept(&s.outcomes, &keep),
            ..s.clone()
        });
    }
    let all = curves(results, &cropped);
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
                None => crate::error::bail!(
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
        crate::error::bail!(
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
                color: crate::report::figure::PALETTE[r % crate::report::figure::PALETTE.len()],
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
    // Legend: a parameter every series has is said once, in the title.
    let (shared, own_variants) = crate::report::naming::factor_shared(&variants);
    let mut legend: Vec<LegendEntry> = Vec::new();
    if two_way {
        for (i, v) in own_variants.iter().enumerate() {
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
                    color: crate::report::figure::PALETTE[i % crate::report::figure::PALETTE.len()],
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
        for (i, v) in own_variants.iter().enumerate() {
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
            let title = match (&facet_label, f) {
                (Some(l), Some(v)) => format!("{l} = {}", with_unit(l, *v)),
                _ => String::new(),
            };
            panels.push(Panel {
                title,
                x_label: coordinate_axis(&in_panel[0].spectrum.axis),
                y_label: q.info().axis.to_string(),
                series,
            });
        }
    }
    let cols = if facets.len() == 1 && quantities.len() == 4 {
        2
    } else {
        quantities.len()
    };
    let count = panels.len();
    for (i, p) in panels.iter_mut().enumerate() {
        p.title = panel_title(i, count, &p.title);
    }
    let rows = panels.len().div_ceil(cols);
    let default = FigureSize::mm(
        if cols == 1 { 120.0 } else { 85.0 * cols as f64 },
        62.0 * rows as f64 + 12.0 + 6.0 * (legend.len() as f64 / 3.0).ceil(),
    );
    let canvas = options.canvas(default, "the spectra")?;
    let title = with_shared(&figure_title(results), &shared);
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

fn draw_panels<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    canvas: Canvas,
    title: &str,
    legend: &[LegendEntry],
    panels: &[Panel],
    cols: usize,
) -> crate::error::Result<()> {
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
) -> crate::error::Result<()> {
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
