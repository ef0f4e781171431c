//! Figures (plotters): spectra, overturning maps and a scene's histories, as SVG or PNG.
//! Text uses DejaVu Sans Mono shipped in `assets/fonts` (the machines have no system fonts).

use super::aggregate::{OverturningMap, Spectrum};
use crate::sim::History;
use crate::study::fmt_num;
use anyhow::{Context, anyhow};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Once;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    Svg,
    Png,
}

impl ImageFormat {
    fn extension(self) -> &'static str {
        match self {
            ImageFormat::Svg => "svg",
            ImageFormat::Png => "png",
        }
    }
}

const FONT: &str = "sans-serif";
const SIZE: (u32, u32) = (900, 600);
/// Most series drawn in one spectra figure.
const MAX_SERIES: usize = 16;

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let bytes = include_bytes!("../../assets/fonts/DejaVuSansMono.ttf");
        for style in [FontStyle::Normal, FontStyle::Bold] {
            // The font is compiled in and known to parse; a failure would only lose text.
            let _ = plotters::style::register_font(FONT, style, bytes);
        }
    });
}

/// Draw with `draw` into `path` (atomically: a temporary file in the same directory, then
/// rename).
fn render(
    path: &Path,
    format: ImageFormat,
    size: (u32, u32),
    draw: impl Fn(DrawingArea<SVGBackend, Shift>) -> anyhow::Result<()>,
    draw_png: impl Fn(DrawingArea<BitMapBackend, Shift>) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    register_font();
    match format {
        ImageFormat::Svg => {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
                draw(root)?;
            }
            super::write_atomic(path, svg.as_bytes())
        }
        ImageFormat::Png => {
            let dir = path.parent().unwrap_or(Path::new("."));
            let tmp = tempfile::Builder::new()
                .suffix(".png")
                .tempfile_in(dir)
                .with_context(|| format!("cannot create a file in {}", dir.display()))?;
            {
                let root = BitMapBackend::new(tmp.path(), size).into_drawing_area();
                draw_png(root)?;
            }
            super::readable_by_all(tmp.as_file())?;
            tmp.persist(path)
                .with_context(|| format!("cannot write {}", path.display()))?;
            Ok(())
        }
    }
}

fn err<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow!("drawing failed: {e:?}")
}

fn palette(i: usize) -> RGBColor {
    const COLORS: [RGBColor; 8] = [
        RGBColor(0, 0, 0),
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
        RGBColor(255, 127, 14),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(23, 190, 207),
    ];
    COLORS[i % COLORS.len()]
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

/// All spectra of one quantity in one chart; gaps (overturned or failed) break the lines.
fn draw_spectra<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    spectra: &[&Spectrum],
) -> anyhow::Result<()> {
    root.fill(&WHITE).map_err(err)?;
    let (x0, x1) = range_of(spectra.iter().flat_map(|s| s.xs.iter().copied()));
    let (_, y1) = range_of(spectra.iter().flat_map(|s| s.ys.iter().flatten().copied()));
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT, 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(x0..x1, 0.0..y1 * 1.05)
        .map_err(err)?;
    let first = spectra.first().ok_or_else(|| anyhow!("no spectra"))?;
    chart
        .configure_mesh()
        .x_desc(first.axis.as_str())
        .y_desc(first.quantity.label())
        .label_style((FONT, 14))
        .draw()
        .map_err(err)?;
    for (i, s) in spectra.iter().enumerate() {
        let color = palette(i);
        let mut segments: Vec<Vec<(f64, f64)>> = vec![vec![]];
        for (x, y) in s.xs.iter().zip(&s.ys) {
            match y {
                Some(y) => segments.last_mut().expect("non-empty").push((*x, *y)),
                None => segments.push(vec![]),
            }
        }
        let mut labelled = false;
        for seg in segments.into_iter().filter(|s| !s.is_empty()) {
            let series = chart
                .draw_series(LineSeries::new(seg.clone(), color.stroke_width(2)))
                .map_err(err)?;
            if !labelled {
                series.label(s.label.as_str()).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
                });
                labelled = true;
            }
            chart
                .draw_series(seg.iter().map(|p| Circle::new(*p, 2, color.filled())))
                .map_err(err)?;
        }
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font((FONT, 13))
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(err)?;
    root.present().map_err(err)
}

fn draw_map<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    map: &OverturningMap,
) -> anyhow::Result<()> {
    root.fill(&WHITE).map_err(err)?;
    let edges = |v: &[f64]| -> Vec<f64> {
        // Cell edges halfway between grid values.
        let n = v.len();
        if n == 0 {
            return vec![0.0, 1.0];
        }
        let step = |i: usize| {
            if n > 1 {
                v[i.min(n - 1)] - v[i.min(n - 1).saturating_sub(1).min(n - 2)]
            } else {
                1.0
            }
        };
        let mut e = vec![v[0] - step(1) / 2.0];
        e.extend(v.windows(2).map(|w| (w[0] + w[1]) / 2.0));
        e.push(v[n - 1] + step(n - 1) / 2.0);
        e
    };
    let (ex, ey) = (edges(&map.xs), edges(&map.ys));
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("overturning map: {} (red: overturned)", map.label),
            (FONT, 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(ex[0]..ex[ex.len() - 1], ey[0]..ey[ey.len() - 1])
        .map_err(err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(map.x_axis.as_str())
        .y_desc(map.y_axis.as_str())
        .label_style((FONT, 14))
        .draw()
        .map_err(err)?;
    let cells = map.cells.iter().enumerate().flat_map(|(iy, row)| {
        let (ex, ey) = (&ex, &ey);
        row.iter().enumerate().map(move |(ix, c)| {
            let color = match c {
                Some(true) => RGBColor(214, 39, 40),
                Some(false) => RGBColor(220, 220, 220),
                None => WHITE,
            };
            Rectangle::new([(ex[ix], ey[iy]), (ex[ix + 1], ey[iy + 1])], color.filled())
        })
    });
    chart.draw_series(cells).map_err(err)?;
    root.present().map_err(err)
}

/// Histories of one scene: rotation and ground acceleration over time, one panel each.
fn draw_history<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    history: &History,
    columns: &[&str],
) -> anyhow::Result<()> {
    root.fill(&WHITE).map_err(err)?;
    let t = history
        .column("t")
        .ok_or_else(|| anyhow!("the history has no time column"))?;
    let panels = root.split_evenly((columns.len(), 1));
    for (i, (panel, name)) in panels.iter().zip(columns).enumerate() {
        let Some(values) = history.column(name) else {
            continue;
        };
        let (t0, t1) = range_of(t.iter().copied());
        let (y0, y1) = range_of(values.iter().copied());
        let mut chart = ChartBuilder::on(panel)
            .caption(
                if i == 0 {
                    title.to_string()
                } else {
                    String::new()
                },
                (FONT, 18),
            )
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(70)
            .build_cartesian_2d(t0..t1, y0..y1)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("t (s)")
            .y_desc(*name)
            .y_labels(5)
            .label_style((FONT, 13))
            .draw()
            .map_err(err)?;
        chart
            .draw_series(LineSeries::new(
                t.iter().copied().zip(values.iter().copied()),
                // Width 1: plotters leaves gaps between many short wide segments.
                palette(i + 1).stroke_width(1),
            ))
            .map_err(err)?;
    }
    root.present().map_err(err)
}

fn slug(text: &str) -> String {
    let s: String = text
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    let mut out = String::new();
    for part in s.split('-').filter(|p| !p.is_empty()) {
        if !out.is_empty() {
            out.push('-');
        }
        out.push_str(part);
    }
    out
}

/// One spectra figure per quantity; returns the files written.
pub fn plot_spectra(
    dir: &Path,
    format: ImageFormat,
    study_name: &str,
    spectra: &[Spectrum],
) -> anyhow::Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let mut quantities = Vec::new();
    for s in spectra {
        if !quantities.contains(&s.quantity) {
            quantities.push(s.quantity);
        }
    }
    for q in quantities {
        let of_q: Vec<&Spectrum> = spectra.iter().filter(|s| s.quantity == q).collect();
        if of_q.len() > MAX_SERIES {
            // A fine map grid: one spectrum per amplitude would be unreadable; the map says it.
            eprintln!(
                "{} spectra of {}: too many for one figure, skipped (see results.csv)",
                of_q.len(),
                q.name()
            );
            continue;
        }
        let path = dir.join(format!("spectrum-{}.{}", q.name(), format.extension()));
        let title = format!("{study_name}: {} (gaps: overturned or failed)", q.label());
        render(
            &path,
            format,
            SIZE,
            |root| draw_spectra(root, &title, &of_q),
            |root| draw_spectra(root, &title, &of_q),
        )?;
        written.push(path);
    }
    Ok(written)
}

pub fn plot_maps(
    dir: &Path,
    format: ImageFormat,
    maps: &[OverturningMap],
) -> anyhow::Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    for (i, map) in maps.iter().enumerate() {
        let path = dir.join(format!(
            "map-{i}-{}.{}",
            slug(&map.label),
            format.extension()
        ));
        render(
            &path,
            format,
            SIZE,
            |r| draw_map(r, map),
            |r| draw_map(r, map),
        )?;
        written.push(path);
    }
    Ok(written)
}

pub fn plot_history(
    path: &Path,
    format: ImageFormat,
    title: &str,
    history: &History,
) -> anyhow::Result<()> {
    let wanted = ["theta", "u", "ground_accel", "device_force"];
    let columns: Vec<&str> = wanted
        .into_iter()
        .filter(|c| history.columns.contains(c))
        .collect();
    let size = (SIZE.0, 80 + 220 * columns.len() as u32);
    render(
        path,
        format,
        size,
        |r| draw_history(r, title, history, &columns),
        |r| draw_history(r, title, history, &columns),
    )
}

/// A readable label for a scene, for history plots.
pub fn scene_title(index: usize, group: &str, coords: &[(String, f64)]) -> String {
    let c: Vec<String> = coords
        .iter()
        .map(|(n, v)| format!("{n}={}", fmt_num(*v)))
        .collect();
    format!("scene {index}: {group} {}", c.join(" "))
}
