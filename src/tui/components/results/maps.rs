//! Overturning maps: one character cell per scene over two axes, largest y on top, with a
//! cell cursor and the verdict under it.

use super::super::super::theme::{self, Theme};
use super::super::super::widgets::strip::{Strip, axis_line};
use super::super::super::widgets::{fmt_num, more_marker};
use super::{Mark, Results};
use crate::report::OverturningMap;
use crossterm::event::{KeyCode, KeyEvent};
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::{Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

#[derive(Clone, Debug, Default)]
pub struct MapsView {
    /// Index of the map shown.
    pub map: usize,
    /// Map cursor (ix, iy).
    pub cell: (usize, usize),
}

impl MapsView {
    pub fn handle_key(&mut self, key: KeyEvent, data: &Results) {
        let nmaps = data.maps.len();
        let (mx, my) = data
            .maps
            .get(self.map)
            .map_or((0, 0), |m| (m.xs.len(), m.ys.len()));
        let (cx, cy) = &mut self.cell;
        match key.code {
            KeyCode::Left | KeyCode::Char('h') => *cx = cx.saturating_sub(1),
            KeyCode::Right | KeyCode::Char('l') => *cx = (*cx + 1).min(mx.saturating_sub(1)),
            // Rows are drawn with the largest y on top.
            KeyCode::Up | KeyCode::Char('k') => *cy = (*cy + 1).min(my.saturating_sub(1)),
            KeyCode::Down | KeyCode::Char('j') => *cy = cy.saturating_sub(1),
            KeyCode::Char(']') if nmaps > 0 => self.map = (self.map + 1) % nmaps,
            KeyCode::Char('[') if nmaps > 0 => self.map = (self.map + nmaps - 1) % nmaps,
            _ => {}
        }
    }

    pub fn draw(&self, data: &Results, theme: Theme, frame: &mut Frame, area: Rect) {
        let marks = data.map_marks.get(self.map).map_or(&[][..], Vec::as_slice);
        let Some(map) = data.maps.get(self.map) else {
            frame.render_widget(Paragraph::new("no overturning maps in these results"), area);
            return;
        };
        let mut lines = vec![Line::from(vec![
            Span::styled("[ ] ", theme.key()),
            Span::styled(map.label.clone(), theme.title()),
            Span::styled(
                format!("  (map {}/{})", self.map + 1, data.maps.len()),
                theme.dim(),
            ),
        ])];
        let ylabel = 8;
        let (nx, ny) = (map.xs.len(), map.ys.len());
        let cell = ((area.width as usize).saturating_sub(ylabel + 12) / nx.max(1)).clamp(1, 6);
        let room_x = ((area.width as usize).saturating_sub(ylabel + 12) / cell).max(1);
        let (cx, cy) = self.cell;
        let first_x = cx.saturating_sub(room_x / 2).min(nx.saturating_sub(room_x));
        let count_x = room_x.min(nx);
        // A window on x says which columns it shows: past the axis, on a line of its own.
        let x_cut = usize::from(count_x < nx);
        let mut room_y = (area.height as usize).saturating_sub(6 + x_cut).max(1);
        if room_y < ny {
            // Rows are hidden: the line under the map says how many.
            room_y = room_y.saturating_sub(1).max(1);
        }
        // Cells about square: two rows each when there is room.
        let cell_h = (room_y / ny.max(1)).clamp(1, 2);
        let count_y = (room_y / cell_h).min(ny);
        // Largest y on top: display row r shows iy = top - r.
        let top = (cy + count_y / 2)
            .min(ny.saturating_sub(1))
            .max(count_y.saturating_sub(1));
        lines.push(Line::styled(map.y_axis.clone(), theme.dim()));
        let hidden = more_marker(ny - 1 - top, (top + 1).saturating_sub(count_y));
        for r in 0..count_y * cell_h {
            let iy = top - r / cell_h;
            let label = if r % cell_h == 0 {
                format!("{:>7} ", fmt_num(map.ys[iy]))
            } else {
                " ".repeat(8)
            };
            let mut spans = vec![Span::styled(label, theme.dim())];
            for ix in first_x..first_x + count_x {
                let (glyph, style) = map_cell(map, marks, ix, iy, theme);
                // An adaptive map's inferred cells are dim: only the bright ones ran.
                let style = if map.inferred(ix, iy) {
                    style.add_modifier(Modifier::DIM)
                } else {
                    style
                };
                let style = if (ix, iy) == (cx, cy) {
                    style.add_modifier(Modifier::REVERSED)
                } else {
                    style
                };
                spans.push(Span::styled(glyph.repeat(cell), style));
            }
            lines.push(Line::from(spans));
        }
        if let Some(more) = hidden {
            lines.push(Line::styled(
                format!("{more} rows of {}  ↑↓ scroll", map.y_axis),
                theme.dim(),
            ));
        }
        let st = Strip {
            first: first_x,
            count: count_x,
            cell,
        };
        lines.push(axis_line(&map.xs, &st, ylabel, &map.x_axis));
        lines.push(Line::from(vec![
            Span::styled(theme::CELL_OVERTURNED, theme.overturned()),
            Span::raw(" overturned  "),
            Span::styled(theme::CELL_SAFE, theme.safe()),
            Span::raw(" safe  "),
            Span::styled(theme::CELL_FAILED, theme.failed()),
            Span::raw(" failed  blank not run"),
            Span::raw(
                if (0..ny).any(|iy| (0..nx).any(|ix| map.inferred(ix, iy))) {
                    "  dim inferred"
                } else {
                    ""
                },
            ),
        ]));
        let state = match map.cells.get(cy).and_then(|r| r.get(cx)) {
            Some(Some(true)) => "overturned",
            Some(Some(false)) => "safe",
            Some(None) => mark_at(marks, (cx, cy)).describe(),
            None => "–",
        };
        let state = if map.inferred(cx, cy) {
            format!("{state} (inferred by refinement, not run)")
        } else if let Some(r) = data.map_result(map, cx, cy).filter(|r| !r.overturned) {
            format!(
                "{state}, {} {}",
                crate::study::Quantity::PeakRotationRatio.label(),
                fmt_num(r.peak_rotation_ratio)
            )
        } else {
            state.to_string()
        };
        lines.push(Line::raw(format!(
            "{} = {}  {} = {}: {state}",
            map.x_axis,
            map.xs.get(cx).map_or("–".into(), |v| fmt_num(*v)),
            map.y_axis,
            map.ys.get(cy).map_or("–".into(), |v| fmt_num(*v)),
        )));
        frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), area);
    }
}

/// What the cell without a verdict at (ix, iy) stands for (failed if unknown).
fn mark_at(marks: &[Vec<Mark>], (ix, iy): (usize, usize)) -> Mark {
    marks
        .get(iy)
        .and_then(|r| r.get(ix))
        .copied()
        .unwrap_or(Mark::Failed)
}

fn map_cell(
    map: &OverturningMap,
    marks: &[Vec<Mark>],
    ix: usize,
    iy: usize,
    theme: Theme,
) -> (&'static str, Style) {
    match map.cells.get(iy).and_then(|r| r.get(ix)) {
        Some(Some(true)) => (theme::CELL_OVERTURNED, theme.overturned()),
        Some(Some(false)) => (theme::CELL_SAFE, theme.safe()),
        Some(None) if mark_at(marks, (ix, iy)) == Mark::NotRun => {
            (theme::CELL_MISSING, theme.base())
        }
        Some(None) => (theme::CELL_FAILED, theme.failed()),
        None => (theme::CELL_MISSING, theme.base()),
    }
}
