//! Paper-figure primitives shared by every rocklab figure: physical size and resolution, a
//! proportional font, a colour-blind-safe palette with line styles and markers that survive
//! greyscale printing, clean tick labels, light major grid, and a legend drawn outside the
//! panels (so it never hides data). Plotters draws; this module decides how it looks.

use crate::error::Context;
use crate::numfmt::fmt_digits;
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;
use std::sync::Once;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    Svg,
    Png,
}

impl ImageFormat {
    pub fn extension(self) -> &'static str {
        match self {
            ImageFormat::Svg => "svg",
            ImageFormat::Png => "png",
        }
    }
}

/// The family name plotters knows our bundled DejaVu Sans by; SVG viewers fall back to their
/// own sans-serif, which keeps the SVG small and editable.
pub const FONT: &str = "sans-serif";

/// A figure's physical size (mm) and raster resolution (dots per inch; SVG uses CSS's 96).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FigureSize {
    pub width_mm: f64,
    pub height_mm: f64,
}

impl FigureSize {
    pub fn mm(width_mm: f64, height_mm: f64) -> Self {
        FigureSize {
            width_mm,
            height_mm,
        }
    }

    /// Parse `160x80mm`, `6.3x3.2in`, `16x8cm` or `1200x600px` (px at 96 per inch).
    pub fn parse(text: &str) -> Result<Self, String> {
        let t = text.trim().to_ascii_lowercase();
        let (numbers, per_mm) = [("mm", 1.0), ("cm", 10.0), ("in", 25.4), ("px", 25.4 / 96.0)]
            .into_iter()
            .find_map(|(unit, f)| t.strip_suffix(unit).map(|n| (n.to_string(), f)))
            .ok_or_else(|| {
                format!("--size {text}: give a unit, e.g. 160x80mm, 6.3x3.2in, 16x8cm, 1200x600px")
            })?;
        let (w, h) = numbers
            .split_once(['x', '×'])
            .ok_or_else(|| format!("--size {text}: expected WIDTHxHEIGHT, e.g. 160x80mm"))?;
        let parse = |s: &str| -> Result<f64, String> {
            let v: f64 = s
                .trim()
                .parse()
                .map_err(|_| format!("--size {text}: `{s}` is not a number"))?;
            // 5 mm … 2 m: anything else is a typo (and a 2 m PNG at 300 dpi is already 24k px).
            if (5.0..=2000.0).contains(&(v * per_mm)) {
                Ok(v * per_mm)
            } else {
                Err(format!(
                    "--size {text}: each side must be between 5 mm and 2 m"
                ))
            }
        };
        Ok(FigureSize::mm(parse(w)?, parse(h)?))
    }
}

/// How a figure is written: format, size and resolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FigureOptions {
    pub format: ImageFormat,
    /// None: each figure picks a size that suits its panels.
    pub size: Option<FigureSize>,
    /// PNG resolution; SVG is laid out at 96 px per inch (CSS pixels).
    pub dpi: f64,
    /// Largest PNG in megapixels (each takes 3 MB while drawn), whatever the size came from.
    pub max_megapixels: f64,
}

/// The default of [`FigureOptions::max_megapixels`] (`plot --max-megapixels`).
pub const MAX_MEGAPIXELS: f64 = 100.0;
/// The most `--max-megapixels` may allow: plotters' bitmap backend indexes pixels with 32-bit
/// signed integers (2 147 megapixels), past which it panics (issue 29: 2000x2000mm at 2400 dpi).
pub const MEGAPIXELS_CEILING: f64 = 2000.0;
/// The smallest a figure may be drawn, as a fraction of the size that suits its panels: text
/// keeps its point size, so below this the panels have no room left (at 5x5 mm plotters'
/// rasteriser spent minutes and gigabytes filling panels of negative size).
pub const MIN_SIZE_FRACTION: f64 = 0.5;

impl FigureOptions {
    pub fn new(format: ImageFormat) -> Self {
        FigureOptions {
            format,
            size: None,
            dpi: 300.0,
            max_megapixels: MAX_MEGAPIXELS,
        }
    }

    fn pixels_per_inch(&self) -> f64 {
        match self.format {
            ImageFormat::Svg => 96.0,
            ImageFormat::Png => self.dpi,
        }
    }

    /// Pixel size of the figure `what` (whose panels suit `default`) and the scale from
    /// typographic points to pixels. Refused before anything is allocated: a `--size` under
    /// [`MIN_SIZE_FRACTION`] of the default, and a PNG over [`Self::max_megapixels`].
    pub fn canvas(&self, default: FigureSize, what: &str) -> crate::error::Result<Canvas> {
        let size = self.size.unwrap_or(default);
        let (min_w, min_h) = (
            (default.width_mm * MIN_SIZE_FRACTION).ceil(),
            (default.height_mm * MIN_SIZE_FRACTION).ceil(),
        );
        if size.width_mm < min_w || size.height_mm < min_h {
            crate::error::bail!(
                "--size {}x{}mm is too small for {what}: its panels and labels need at least \
                 {min_w}x{min_h}mm (its own size is {}x{}mm); give a larger --size, or leave \
                 --size out",
                fmt_digits(size.width_mm, 4),
                fmt_digits(size.height_mm, 4),
                fmt_digits(default.width_mm, 4),
                fmt_digits(default.height_mm, 4),
            );
        }
        let ppi = self.pixels_per_inch();
        let px = |mm: f64| ((mm / 25.4 * ppi).round() as u32).max(16);
        let canvas = Canvas {
            size,
            pixels: (px(size.width_mm), px(size.height_mm)),
            pt: ppi / 72.0,
        };
        let (w, h) = canvas.pixels;
        let megapixels = f64::from(w) * f64::from(h) / 1e6;
        let cap = self.max_megapixels.min(MEGAPIXELS_CEILING);
        if self.format == ImageFormat::Png && megapixels > cap {
            crate::error::bail!(
                "{what} at {}x{}mm and --dpi {} is a {w}×{h} px PNG ({} megapixels), over the \
                 limit of {} megapixels; lower --size or --dpi, or raise --max-megapixels (at \
                 most {MEGAPIXELS_CEILING})",
                fmt_digits(size.width_mm, 4),
                fmt_digits(size.height_mm, 4),
                fmt_digits(self.dpi, 4),
                fmt_digits(megapixels, 3),
                fmt_digits(cap, 4),
            );
        }
        Ok(canvas)
    }
}

/// A figure's pixel size and the size of one typographic point in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Canvas {
    pub size: FigureSize,
    pub pixels: (u32, u32),
    pub pt: f64,
}

impl Canvas {
    /// `v` points in pixels (at least 1).
    pub fn px(&self, v: f64) -> u32 {
        (v * self.pt).round().max(1.0) as u32
    }

    pub fn font(&self, points: f64) -> TextStyle<'static> {
        // Plotters' font size is the line height; 1.24 × the em size (see plotters-svg).
        (FONT, points * self.pt * 1.24).into_font().color(&BLACK)
    }

    pub fn line(&self, color: RGBColor, points: f64) -> ShapeStyle {
        color.stroke_width(self.px(points))
    }
}

pub fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let bytes = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
        for style in [FontStyle::Normal, FontStyle::Bold] {
            // The font is compiled in and known to parse; a failure would only lose text.
            let _ = plotters::style::register_font(FONT, style, bytes);
        }
    });
}

pub fn err<E: std::fmt::Debug>(e: E) -> crate::error::Error {
    crate::error::error!("drawing failed: {e:?}")
}

/// Draw with `draw` into `path` (atomically: a temporary file in the same directory, then
/// rename). The two closures are the same drawing for the two backends.
pub fn render(
    path: &Path,
    options: &FigureOptions,
    canvas: Canvas,
    draw_svg: impl Fn(DrawingArea<SVGBackend, Shift>) -> crate::error::Result<()>,
    draw_png: impl Fn(DrawingArea<BitMapBackend, Shift>) -> crate::error::Result<()>,
) -> crate::error::Result<()> {
    register_font();
    match options.format {
        ImageFormat::Svg => {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, canvas.pixels).into_drawing_area();
                draw_svg(root)?;
            }
            super::write_atomic(path, physical_svg_size(&svg, canvas).as_bytes())
        }
        ImageFormat::Png => {
            let dir = match path.parent() {
                Some(d) if !d.as_os_str().is_empty() => d,
                _ => Path::new("."),
            };
            let tmp = tempfile::Builder::new()
                .suffix(".png")
                .tempfile_in(dir)
                .with_context(|| format!("cannot create a file in {}", dir.display()))?;
            let mut pixels = pixel_buffer(canvas.pixels)?;
            {
                let root =
                    BitMapBackend::with_buffer(&mut pixels, canvas.pixels).into_drawing_area();
                draw_png(root)?;
            }
            let (w, h) = canvas.pixels;
            image::save_buffer(tmp.path(), &pixels, w, h, image::ColorType::Rgb8)
                .with_context(|| format!("cannot write {}", tmp.path().display()))?;
            super::readable_by_all(tmp.as_file())?;
            tmp.persist(path)
                .with_context(|| format!("cannot write {}", path.display()))?;
            Ok(())
        }
    }
}

/// A PNG's RGB pixels, zeroed, or an error if memory cannot hold them. Plotters' own
/// `BitMapBackend::new` allocates them infallibly, and a large figure on a machine short of
/// memory then aborts the process ("memory allocation of 5832842508 bytes failed"); drawn
/// into this buffer and encoded with `image` (as plotters does), it is a message instead.
fn pixel_buffer((w, h): (u32, u32)) -> crate::error::Result<Vec<u8>> {
    let bytes = 3 * w as usize * h as usize;
    let mut pixels = Vec::new();
    pixels.try_reserve_exact(bytes).map_err(|_| {
        crate::error::error!(
            "a {w}×{h} px PNG needs {} of memory for its pixels, more than this machine can \
             give now; lower --size or --dpi, or write an SVG",
            fmt_bytes(bytes)
        )
    })?;
    pixels.resize(bytes, 0);
    Ok(pixels)
}

/// `5.8 GB`, `350 MB`: a byte count as a message gives it.
fn fmt_bytes(bytes: usize) -> String {
    let b = bytes as f64;
    if b >= 1e9 {
        format!("{:.1} GB", b / 1e9)
    } else {
        format!("{:.0} MB", (b / 1e6).max(1.0))
    }
}

/// Plotters writes `width="W" height="H"` in pixels; a paper figure wants its size in mm
/// (the viewBox keeps the drawing's pixel coordinates).
fn physical_svg_size(svg: &str, canvas: Canvas) -> String {
    let (w, h) = canvas.pixels;
    let old = format!("width=\"{w}\" height=\"{h}\"");
    let new = format!(
        "width=\"{:.2}mm\" height=\"{:.2}mm\"",
        canvas.size.width_mm, canvas.size.height_mm
    );
    svg.replacen(&old, &new, 1)
}

/// Okabe & Ito's colour-blind-safe palette, ordered so neighbours also differ in lightness
/// (yellow last: it is faint on white).
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 0, 0),
    RGBColor(230, 159, 0),
    RGBColor(0, 114, 178),
    RGBColor(0, 158, 115),
    RGBColor(213, 94, 0),
    RGBColor(86, 180, 233),
    RGBColor(204, 121, 167),
    RGBColor(240, 228, 66),
];

pub const GRID: RGBColor = RGBColor(225, 225, 225);

/// Line patterns, as (dash, gap) in points; `None` is solid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Dash {
    Solid,
    Long,
    Short,
    Dotted,
}

impl Dash {
    pub const ALL: [Dash; 4] = [Dash::Solid, Dash::Long, Dash::Short, Dash::Dotted];

    pub(super) fn pattern(self) -> Option<(f64, f64)> {
        match self {
            Dash::Solid => None,
            Dash::Long => Some((5.0, 2.5)),
            Dash::Short => Some((2.2, 1.6)),
            Dash::Dotted => Some((0.9, 1.4)),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Marker {
    Circle,
    Square,
    Triangle,
    Diamond,
    Cross,
}

impl Marker {
    pub const ALL: [Marker; 5] = [
        Marker::Circle,
        Marker::Square,
        Marker::Triangle,
        Marker::Diamond,
        Marker::Cross,
    ];
}

/// How one series looks: colour, line pattern and marker, each enough to tell it apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SeriesStyle {
    pub color: RGBColor,
    pub dash: Dash,
    pub marker: Option<Marker>,
}

impl SeriesStyle {
    /// The i-th style of a figure: colour, dash and marker all change with i, and (dash,
    /// marker) pairs repeat only after 20 series, so greyscale still tells them apart.
    pub fn nth(i: usize) -> Self {
        SeriesStyle {
            color: PALETTE[i % PALETTE.len()],
            dash: Dash::ALL[i % Dash::ALL.len()],
            marker: Some(Marker::ALL[i % Marker::ALL.len()]),
        }
    }
}

/// Line width of data series, points.
pub const LINE_PT: f64 = 1.1;
/// Marker radius, points.
pub const MARKER_PT: f64 = 2.2;

pub type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A polyline in the series' pattern.
pub fn draw_line<DB: DrawingBackend>(
    chart: &mut Chart<DB>,
    canvas: Canvas,
    points: &[(f64, f64)],
    style: SeriesStyle,
    width_pt: f64,
) -> crate::error::Result<()> {
    let line = canvas.line(style.color, width_pt);
    match style.dash.pattern() {
        None => {
            chart
                .draw_series(LineSeries::new(points.iter().copied(), line))
                .map_err(err)?;
        }
        Some((dash, gap)) => {
            let (dash, gap) = (canvas.px(dash), canvas.px(gap));
            chart
                .draw_series(DashedLineSeries::new(
                    points.iter().copied(),
                    dash,
                    gap,
                    line,
                ))
                .map_err(err)?;
        }
    }
    Ok(())
}

/// Markers at `points` (data coordinates).
pub fn draw_markers<DB: DrawingBackend>(
    chart: &mut Chart<DB>,
    canvas: Canvas,
    points: &[(f64, f64)],
    marker: Marker,
    color: RGBColor,
) -> crate::error::Result<()> {
    let r = canvas.px(MARKER_PT) as i32;
    let fill = color.filled();
    let stroke = canvas.line(color, 0.8);
    let pts = points.iter().copied();
    match marker {
        Marker::Circle => chart
            .draw_series(pts.map(|p| EmptyElement::at(p) + Circle::new((0, 0), r, fill)))
            .map(|_| ()),
        Marker::Square => chart
            .draw_series(pts.map(|p| {
                let s = r * 8 / 10;
                EmptyElement::at(p) + Rectangle::new([(-s, -s), (s, s)], fill)
            }))
            .map(|_| ()),
        Marker::Triangle => chart
            .draw_series(pts.map(|p| {
                EmptyElement::at(p)
                    + Polygon::new(vec![(0, -r), (r, r * 7 / 10), (-r, r * 7 / 10)], fill)
            }))
            .map(|_| ()),
        Marker::Diamond => chart
            .draw_series(pts.map(|p| {
                EmptyElement::at(p) + Polygon::new(vec![(0, -r), (r, 0), (0, r), (-r, 0)], fill)
            }))
            .map(|_| ()),
        Marker::Cross => chart
            .draw_series(pts.map(|p| EmptyElement::at(p) + Cross::new((0, 0), r, stroke)))
            .map(|_| ()),
    }
    .map_err(err)
}

/// Tick labels with as many decimals as the tick spacing needs: `0.5`, `1.0`, `1.5`, never
/// `1.0000001` or a bare `1.`.
pub fn tick_formatter(lo: f64, hi: f64, ticks: usize) -> impl Fn(&f64) -> String {
    // The tick spacing plotters will pick: range/ticks rounded up to 1, 2 or 5 × 10^k.
    let raw = ((hi - lo).abs() / ticks.max(1) as f64).max(f64::MIN_POSITIVE);
    let decade = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|s| *s >= raw * (1.0 - 1e-9))
        .unwrap_or(10.0 * decade);
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let scientific = hi.abs().max(lo.abs()) >= 1e5 || (hi.abs().max(lo.abs()) < 1e-3 && hi != lo);
    move |v: &f64| {
        if scientific {
            return format!("{v:.1e}").replace(".0e", "e");
        }
        // One more decimal where a tick is not on the expected grid (never a rounded lie).
        let mut d = decimals;
        let mut s = format!("{v:.d$}");
        while d < 6 && s.parse::<f64>().is_ok_and(|p| (p - v).abs() > step * 1e-6) {
            d += 1;
            s = format!("{v:.d$}");
        }
        // `-0.0` reads as a sign error on an axis.
        if s.trim_start_matches('-')
            .chars()
            .all(|c| c == '0' || c == '.')
        {
            s.trim_start_matches('-').to_string()
        } else {
            s
        }
    }
}

/// Number of tick labels for an axis `len_px` long (about one per 14 mm, 3…10).
pub fn tick_count(len_px: u32, canvas: Canvas) -> usize {
    let mm = len_px as f64 / canvas.pt / 72.0 * 25.4;
    ((mm / 14.0).round() as usize).clamp(3, 10)
}

/// How many labels to ask plotters for on an axis from `lo` to `hi` so that it draws at
/// least three ticks (or `wanted`, whichever is fewer ticks): plotters rounds the step up to
/// 1, 2 or 5 × 10^k within the count asked, and on a short axis (a history panel, 3 asked)
/// a range like −27 000…43 000 N then gets the one tick `0` and reads as unlabelled.
pub fn label_count(lo: f64, hi: f64, wanted: usize) -> usize {
    use plotters::coord::ranged1d::Ranged;
    let ticks = |n: usize| RangedCoordf64::from(lo..hi).key_points(n).len();
    let enough = wanted.min(3);
    (wanted..wanted + 12)
        .find(|n| ticks(*n) >= enough)
        .unwrap_or(wanted + 12)
}

/// The tick labels an axis from `lo` to `hi` shows when `len_px` long: what
/// [`build_chart`] draws (for tests).
#[cfg(test)]
pub fn tick_labels(lo: f64, hi: f64, len_px: u32, canvas: Canvas) -> Vec<String> {
    use plotters::coord::ranged1d::Ranged;
    let n = label_count(lo, hi, tick_count(len_px, canvas));
    let format = tick_formatter(lo, hi, n);
    RangedCoordf64::from(lo..hi)
        .key_points(n)
        .iter()
        .map(format)
        .collect()
}

/// A framed chart with light major grid lines only, axis titles and clean ticks.
pub struct Axes<'l> {
    pub x: (f64, f64),
    pub y: (f64, f64),
    pub x_label: &'l str,
    pub y_label: &'l str,
    pub title: &'l str,
    /// No tick labels above this value (a strip of marks above the data, e.g. overturned).
    pub y_labels_below: Option<f64>,
}

pub fn build_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    canvas: Canvas,
    axes: &Axes,
) -> crate::error::Result<Chart<'a, DB>> {
    let (w, h) = area.dim_in_pixel();
    let mut builder = ChartBuilder::on(area);
    builder
        .margin_top(canvas.px(if axes.title.is_empty() { 4.0 } else { 2.0 }))
        .margin_right(canvas.px(8.0))
        .margin_left(canvas.px(2.0))
        .x_label_area_size(canvas.px(26.0))
        .y_label_area_size(canvas.px(38.0));
    if !axes.title.is_empty() {
        builder.caption(axes.title, canvas.font(8.5));
    }
    let mut chart = builder
        .build_cartesian_2d(axes.x.0..axes.x.1, axes.y.0..axes.y.1)
        .map_err(err)?;
    let (nx, ny) = (
        label_count(axes.x.0, axes.x.1, tick_count(w, canvas)),
        label_count(axes.y.0, axes.y.1, tick_count(h, canvas)),
    );
    let fx = tick_formatter(axes.x.0, axes.x.1, nx);
    let fy_all = tick_formatter(axes.y.0, axes.y.1, ny);
    let limit = axes.y_labels_below.unwrap_or(f64::INFINITY);
    let fy = move |v: &f64| {
        if *v > limit { String::new() } else { fy_all(v) }
    };
    chart
        .configure_mesh()
        .x_labels(nx)
        .y_labels(ny)
        .max_light_lines(0)
        .bold_line_style(canvas.line(GRID, 0.5))
        .axis_style(canvas.line(BLACK, 0.6))
        .set_all_tick_mark_size(canvas.px(2.5))
        .label_style(canvas.font(7.5))
        .axis_desc_style(canvas.font(8.5))
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .x_desc(axes.x_label)
        .y_desc(axes.y_label)
        .draw()
        .map_err(err)?;
    Ok(chart)
}

pub use super::legend::{LegendEntry, Swatch, draw_legend, legend_height};

/// The figure's title strip, then the panel area and the legend strip below it.
pub fn split_figure<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    canvas: Canvas,
    title: &str,
    legend: &[LegendEntry],
) -> crate::error::Result<(DrawingArea<DB, Shift>, DrawingArea<DB, Shift>)> {
    root.fill(&WHITE).map_err(err)?;
    let (w, h) = root.dim_in_pixel();
    let body = if title.is_empty() {
        root.clone()
    } else {
        let title_h = canvas.px(14.0);
        let (top, body) = root.split_vertically(title_h);
        // Shrink a long title to fit the width (down to 6.5 pt), then cut it.
        let fits = |pt: f64, text: &str| {
            canvas
                .font(pt)
                .font
                .box_size(text)
                .map_or(true, |(tw, _)| tw + canvas.px(6.0) <= w)
        };
        let mut pt = 9.5;
        while pt > 6.5 && !fits(pt, title) {
            pt -= 0.5;
        }
        let mut chars: Vec<char> = title.chars().collect();
        let mut text = title.to_string();
        while !fits(pt, &text) && chars.len() > 8 {
            chars.pop();
            text = chars.iter().collect::<String>() + "…";
        }
        top.draw(&Text::new(
            text,
            (w as i32 / 2, title_h as i32 / 2),
            canvas.font(pt).pos(Pos::new(HPos::Center, VPos::Center)),
        ))
        .map_err(err)?;
        body
    };
    let legend_h = legend_height(canvas, w, legend).min(h / 2);
    let (_, body_h) = body.dim_in_pixel();
    let (panels, legend_area) = body.split_vertically(body_h - legend_h);
    draw_legend(&legend_area, canvas, legend)?;
    Ok((panels, legend_area))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_in_mm_inches_cm_and_px() {
        assert_eq!(
            FigureSize::parse("160x80mm").unwrap(),
            FigureSize::mm(160.0, 80.0)
        );
        let s = FigureSize::parse("6.3x3.2in").unwrap();
        assert!((s.width_mm - 160.02).abs() < 1e-9 && (s.height_mm - 81.28).abs() < 1e-9);
        assert_eq!(
            FigureSize::parse("16x8cm").unwrap(),
            FigureSize::mm(160.0, 80.0)
        );
        for bad in ["160x80", "160mm", "ax80mm", "0x80mm", "5000x80mm"] {
            let e = FigureSize::parse(bad).unwrap_err();
            assert!(e.contains("--size"), "{bad}: {e}");
        }
    }

    #[test]
    fn canvas_pixels_follow_size_and_dpi() {
        let mut o = FigureOptions::new(ImageFormat::Png);
        o.size = Some(FigureSize::mm(160.0, 80.0));
        o.dpi = 300.0;
        let c = o.canvas(FigureSize::mm(1.0, 1.0), "a figure").unwrap();
        // 160 mm = 6.299 in → 1890 px at 300 dpi; a point is 300/72 px.
        assert_eq!(c.pixels, (1890, 945));
        assert!((c.pt - 300.0 / 72.0).abs() < 1e-12);
        o.format = ImageFormat::Svg;
        assert_eq!(
            o.canvas(FigureSize::mm(1.0, 1.0), "a figure")
                .unwrap()
                .pixels,
            (605, 302)
        );
    }

    #[test]
    fn sizes_below_half_the_panels_and_pngs_over_the_pixel_cap_are_refused() {
        let mut o = FigureOptions::new(ImageFormat::Svg);
        let own = FigureSize::mm(160.0, 150.0);
        o.size = Some(FigureSize::mm(5.0, 5.0));
        let e = o.canvas(own, "the scene figure").unwrap_err().to_string();
        assert!(
            e.contains("--size 5x5mm is too small for the scene figure")
                && e.contains("at least 80x75mm"),
            "{e}"
        );
        // One side too small is enough.
        o.size = Some(FigureSize::mm(100.0, 5.0));
        assert!(o.canvas(own, "x").is_err());
        o.size = Some(FigureSize::mm(80.0, 75.0));
        assert_eq!(o.canvas(own, "x").unwrap().pixels, (302, 283));
        // A default size at a high resolution is held to the same cap as --size.
        o.size = None;
        o.format = ImageFormat::Png;
        o.dpi = 2400.0;
        let e = o.canvas(own, "the scene figure").unwrap_err().to_string();
        assert!(e.contains("15118×14173 px PNG (214 megapixels)"), "{e}");
        o.max_megapixels = 300.0;
        assert!(o.canvas(own, "x").is_ok());
        // Never past what plotters can index, whatever the flag says.
        o.size = Some(FigureSize::mm(2000.0, 2000.0));
        o.max_megapixels = f64::INFINITY;
        let e = o.canvas(own, "x").unwrap_err().to_string();
        assert!(e.contains("limit of 2000 megapixels"), "{e}");
        o.max_megapixels = f64::NAN;
        assert!(o.canvas(own, "x").is_err());
    }

    #[test]
    fn ticks_have_the_decimals_their_spacing_needs() {
        let f = tick_formatter(0.0, 10.0, 5);
        assert_eq!((f(&2.0), f(&10.0)), ("2".to_string(), "10".to_string()));
        let f = tick_formatter(0.0, 1.05, 5);
        assert_eq!(
            (f(&0.5), f(&1.0), f(&-0.0)),
            ("0.5".into(), "1.0".into(), "0.0".into())
        );
        // Off-grid ticks get the decimals they need rather than a rounded label.
        assert_eq!(f(&0.25), "0.25");
        let f = tick_formatter(0.0, 6.9, 10);
        assert_eq!((f(&1.0), f(&6.0)), ("1".into(), "6".into()));
        let f = tick_formatter(0.0, 0.012, 5);
        assert_eq!(f(&0.004), "0.004");
        assert!(!f(&0.004).contains(' '));
    }

    /// A short axis (three labels asked) over a range plotters would mark with one tick
    /// still gets at least three labelled ticks.
    #[test]
    fn a_short_axis_over_an_awkward_range_has_three_tick_labels() {
        use plotters::coord::ranged1d::Ranged;
        let canvas = FigureOptions::new(ImageFormat::Svg)
            .canvas(FigureSize::mm(160.0, 60.0), "x")
            .unwrap();
        let short = canvas.px(60.0);
        assert_eq!(tick_count(short, canvas), 3);
        for (lo, hi) in [(-27_000.0, 43_000.0), (0.12, 0.98), (-1.3, 1.3), (5.0, 5.4)] {
            // The failure this guards against: plotters alone gives one tick here.
            let plain = RangedCoordf64::from(lo..hi).key_points(3).len();
            let labels = tick_labels(lo, hi, short, canvas);
            assert!(
                labels.len() >= 3,
                "{lo}..{hi}: {labels:?} (plotters alone: {plain})"
            );
            assert!(labels.len() <= 10, "{lo}..{hi}: {labels:?}");
            let mut unique = labels.clone();
            unique.dedup();
            assert_eq!(unique, labels, "{lo}..{hi}: repeated labels");
        }
        assert_eq!(
            RangedCoordf64::from(-27_000.0..43_000.0)
                .key_points(3)
                .len(),
            1
        );
    }

    #[test]
    fn series_styles_differ_in_dash_or_marker_not_only_colour() {
        let styles: Vec<SeriesStyle> = (0..20).map(SeriesStyle::nth).collect();
        for (i, a) in styles.iter().enumerate() {
            for b in &styles[i + 1..] {
                assert!((a.dash, a.marker) != (b.dash, b.marker), "{a:?} {b:?}");
            }
        }
    }
}
