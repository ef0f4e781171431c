//! Figure legends: entries (a line sample, a filled box or a marker with its label) laid out
//! in centred rows in their own strip below the panels, so a legend never hides data.

use super::figure::{Canvas, LINE_PT, MARKER_PT, Marker, SeriesStyle, err, register_font};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// How an entry of a legend is drawn.
#[derive(Clone, Debug, PartialEq)]
pub enum Swatch {
    /// A line sample in a series style.
    Line(SeriesStyle),
    /// A filled box (map cells, stacked areas, bands).
    Fill(RGBColor),
    /// A marker alone (e.g. overturned points).
    Marker(Marker, RGBColor),
}

#[derive(Clone, Debug, PartialEq)]
pub struct LegendEntry {
    pub label: String,
    pub swatch: Swatch,
}

const LEGEND_FONT_PT: f64 = 7.5;
const LEGEND_SAMPLE_PT: f64 = 18.0;

fn entry_width(canvas: Canvas, e: &LegendEntry) -> u32 {
    let font = canvas.font(LEGEND_FONT_PT);
    let text = font.font.box_size(&e.label).map(|(w, _)| w).unwrap_or(0);
    canvas.px(LEGEND_SAMPLE_PT + 4.0 + 10.0) + text
}

/// Height in pixels the legend needs below panels `width` pixels wide.
pub fn legend_height(canvas: Canvas, width: u32, entries: &[LegendEntry]) -> u32 {
    if entries.is_empty() {
        return 0;
    }
    register_font();
    legend_rows(canvas, width, entries).len() as u32 * canvas.px(11.0) + canvas.px(4.0)
}

fn legend_rows(canvas: Canvas, width: u32, entries: &[LegendEntry]) -> Vec<Vec<usize>> {
    let mut rows: Vec<Vec<usize>> = vec![vec![]];
    let mut used = 0;
    let avail = width.saturating_sub(canvas.px(10.0));
    for (i, e) in entries.iter().enumerate() {
        let w = entry_width(canvas, e);
        if used + w > avail && !rows.last().is_some_and(Vec::is_empty) {
            rows.push(vec![]);
            used = 0;
        }
        rows.last_mut().expect("non-empty").push(i);
        used += w;
    }
    rows
}

/// A legend in rows, centred, in its own strip of the figure.
pub fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    canvas: Canvas,
    entries: &[LegendEntry],
) -> crate::error::Result<()> {
    let (width, _) = area.dim_in_pixel();
    let row_h = canvas.px(11.0) as i32;
    let sample = canvas.px(LEGEND_SAMPLE_PT) as i32;
    let font = canvas.font(LEGEND_FONT_PT);
    for (r, row) in legend_rows(canvas, width, entries).iter().enumerate() {
        let total: u32 = row.iter().map(|&i| entry_width(canvas, &entries[i])).sum();
        let mut x = (width.saturating_sub(total) / 2) as i32;
        let y = canvas.px(2.0) as i32 + r as i32 * row_h + row_h / 2;
        for &i in row {
            let e = &entries[i];
            match &e.swatch {
                Swatch::Line(style) => {
                    let line = canvas.line(style.color, LINE_PT);
                    let path = vec![(x, y), (x + sample, y)];
                    match style.dash.pattern() {
                        None => area.draw(&PathElement::new(path, line)).map_err(err)?,
                        Some((d, g)) => area
                            .draw(&DashedPathElement::new(
                                path,
                                canvas.px(d),
                                canvas.px(g),
                                line,
                            ))
                            .map_err(err)?,
                    }
                    if let Some(m) = style.marker {
                        draw_marker_px(area, canvas, (x + sample / 2, y), m, style.color)?;
                    }
                }
                Swatch::Fill(color) => {
                    let s = canvas.px(3.5) as i32;
                    area.draw(&Rectangle::new(
                        [
                            (x + sample / 2 - 2 * s, y - s),
                            (x + sample / 2 + 2 * s, y + s),
                        ],
                        color.filled(),
                    ))
                    .map_err(err)?;
                    area.draw(&Rectangle::new(
                        [
                            (x + sample / 2 - 2 * s, y - s),
                            (x + sample / 2 + 2 * s, y + s),
                        ],
                        canvas.line(RGBColor(120, 120, 120), 0.4),
                    ))
                    .map_err(err)?;
                }
                Swatch::Marker(m, color) => {
                    draw_marker_px(area, canvas, (x + sample / 2, y), *m, *color)?
                }
            }
            area.draw(&Text::new(
                e.label.clone(),
                (x + sample + canvas.px(4.0) as i32, y),
                font.pos(Pos::new(HPos::Left, VPos::Center)),
            ))
            .map_err(err)?;
            x += entry_width(canvas, e) as i32;
        }
    }
    Ok(())
}

fn draw_marker_px<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    canvas: Canvas,
    at: (i32, i32),
    marker: Marker,
    color: RGBColor,
) -> crate::error::Result<()> {
    let r = canvas.px(MARKER_PT) as i32;
    let (x, y) = at;
    let fill = color.filled();
    match marker {
        Marker::Circle => area.draw(&Circle::new(at, r, fill)),
        Marker::Square => {
            let s = r * 8 / 10;
            area.draw(&Rectangle::new([(x - s, y - s), (x + s, y + s)], fill))
        }
        Marker::Triangle => area.draw(&Polygon::new(
            vec![(x, y - r), (x + r, y + r * 7 / 10), (x - r, y + r * 7 / 10)],
            fill,
        )),
        Marker::Diamond => area.draw(&Polygon::new(
            vec![(x, y - r), (x + r, y), (x, y + r), (x - r, y)],
            fill,
        )),
        Marker::Cross => area.draw(&Cross::new(at, r, canvas.line(color, 0.8))),
    }
    .map_err(err)
}
