//! Overturning maps, one panel per group, and two variants' maps compared cell by cell.

use super::{
    PlotChoice, coordinate_axis, example_of, figure_title, keep_on_axes, kept, panel_title,
    selection,
};
use crate::report::aggregate::{Group, OverturningMap};
use crate::report::compare::{MapCell, MapComparison, compare_maps};
use crate::report::figure::{
    Axes, Canvas, FigureOptions, FigureSize, LegendEntry, Swatch, build_chart, err, render,
    split_figure,
};
use crate::report::select::{Selector, axis_id};
use crate::sweep::SweepResults;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Overturning maps, one panel per group, in one figure.
pub fn plot_maps(
    dir: &Path,
    options: &FigureOptions,
    results: &SweepResults,
    maps: &[OverturningMap],
    choice: &PlotChoice,
) -> crate::error::Result<Option<PathBuf>> {
    let groups: Vec<&Group> = maps.iter().map(|m| &m.group).collect();
    let axes: Vec<&str> = maps
        .first()
        .into_iter()
        .flat_map(|m| [axis_id(&m.x_axis), axis_id(&m.y_axis)])
        .flatten()
        .collect();
    let (picked, on_axes) = selection(choice, &groups, &axes)?;
    // Filters on a map's axes (`amplitude: 1.5`) keep those rows and columns.
    let mut cropped: Vec<OverturningMap> = Vec::new();
    for (m, _) in maps.iter().zip(&picked).filter(|(_, p)| **p) {
        let keep_x = keep_on_axes(axis_id(&m.x_axis), &m.xs, &on_axes)?;
        let keep_y = keep_on_axes(axis_id(&m.y_axis), &m.ys, &on_axes)?;
        let rows = |grid: &[Vec<Option<_>>]| -> Vec<Vec<Option<_>>> {
            kept(grid, &keep_y)
                .iter()
                .map(|r| kept(r, &keep_x))
                .collect()
        };
        cropped.push(OverturningMap {
            xs: kept(&m.xs, &keep_x),
            ys: kept(&m.ys, &keep_y),
            cells: rows(&m.cells),
            outcomes: kept(&m.outcomes, &keep_y)
                .iter()
                .map(|r| kept(r, &keep_x))
                .collect(),
            ..m.clone()
        });
    }
    let chosen: Vec<&OverturningMap> = cropped.iter().collect();
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
    let canvas = options.canvas(
        FigureSize::mm(
            if cols == 1 { 100.0 } else { 65.0 * cols as f64 },
            60.0 * rows as f64 + 18.0,
        ),
        "the overturning maps",
    )?;
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
) -> crate::error::Result<()> {
    let (body, _) = split_figure(&root, canvas, title, legend)?;
    let areas = body.split_evenly((maps.len().div_ceil(cols), cols));
    for (i, (area, map)) in areas.iter().zip(maps).enumerate() {
        draw_map(area, canvas, map, &panel_title(i, maps.len(), &map.label))?;
    }
    root.present().map_err(err)
}

fn draw_map<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    canvas: Canvas,
    map: &OverturningMap,
    title: &str,
) -> crate::error::Result<()> {
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
) -> crate::error::Result<()> {
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
        MapCell::OnlyBSurvives => crate::report::figure::PALETTE[5],
        MapCell::OnlyASurvives => crate::report::figure::PALETTE[4],
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
) -> crate::error::Result<Option<PathBuf>> {
    if maps.is_empty() {
        return Ok(None);
    }
    let (sa, sb) = (
        Selector::parse(a).map_err(|e| crate::error::error!("--a: {e}"))?,
        Selector::parse(b).map_err(|e| crate::error::error!("--b: {e}"))?,
    );
    let pairs = compare_maps(maps, &sa, &sb).map_err(|e| crate::error::error!("{e}"))?;
    const MAX_MAPS: usize = 12;
    if pairs.len() > MAX_MAPS {
        crate::error::bail!(
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
    let canvas = options.canvas(
        FigureSize::mm(
            if cols == 1 { 110.0 } else { 65.0 * cols as f64 },
            60.0 * rows as f64 + 24.0,
        ),
        "the maps compared",
    )?;
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
) -> crate::error::Result<()> {
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
        let title = panel_title(i, pairs.len(), &format!("{} vs {}", m.a, m.b));
        draw_cells(area, canvas, &grid, &title, |ix, iy| {
            map_cell_color(m.cells[iy][ix])
        })?;
    }
    root.present().map_err(err)
}
