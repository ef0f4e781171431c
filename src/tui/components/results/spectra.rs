//! Spectra: one strip of bars per variant for the current quantity, a cursor along the axis,
//! and every variant's value at the cursor. Rows are named by what varies among them (the
//! words every row shares are said once, above), and `f` filters them with a selector of
//! report/select.rs (`mechanistic(play: 0.005)`; Esc clears).

use super::super::super::edit::{EditOutcome, LineEdit};
use super::super::super::theme::Theme;
use super::super::super::widgets::strip::{Bars, Strip, axis_line, series_lines};
use super::super::super::widgets::{
    edit_spans, fmt_num, more_marker, pad, scroll_offset, truncate,
};
use super::{Mark, Results, ResultsScreen, label_width};
use crate::report::naming;
use crate::report::select::{Selector, select};
use crate::report::{Group, Spectrum};
use crossterm::event::{KeyCode, KeyEvent};
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

/// The cursor over the spectra, shared with the comparison.
#[derive(Clone, Debug, Default)]
pub struct SpectraView {
    /// Index of the quantity shown (among those with spectra).
    pub quantity: usize,
    /// Selected spectrum row (among those of the current quantity).
    pub row: usize,
    /// Cursor along the spectrum axis.
    pub x: usize,
    /// Rows shown: those this selector picks (all without one).
    pub filter: Option<Selector>,
    /// The filter being typed (`f`), and why the last one typed was refused.
    pub filter_edit: Option<LineEdit>,
    pub filter_error: Option<String>,
}

/// Points on the longest spectrum among `rows`.
pub fn axis_len(rows: &[&Spectrum]) -> usize {
    rows.iter().map(|s| s.xs.len()).max().unwrap_or(0)
}

impl SpectraView {
    /// Cursor keys, for `nrows` spectra of `nx` points and `nq` quantities.
    pub fn handle_key(&mut self, key: KeyEvent, nrows: usize, nx: usize, nq: usize) {
        match key.code {
            KeyCode::Left | KeyCode::Char('h') => self.x = self.x.saturating_sub(1),
            KeyCode::Right | KeyCode::Char('l') => self.x = (self.x + 1).min(nx.saturating_sub(1)),
            KeyCode::Home => self.x = 0,
            KeyCode::End => self.x = nx.saturating_sub(1),
            KeyCode::Up | KeyCode::Char('k') => self.row = self.row.saturating_sub(1),
            KeyCode::Down | KeyCode::Char('j') => {
                self.row = (self.row + 1).min(nrows.saturating_sub(1))
            }
            KeyCode::Char(']') if nq > 0 => self.quantity = (self.quantity + 1) % nq,
            KeyCode::Char('[') if nq > 0 => self.quantity = (self.quantity + nq - 1) % nq,
            _ => {}
        }
    }

    /// `f` opens the filter line (with the filter in force); Esc clears the filter. Returns
    /// whether the key was one of these.
    pub fn filter_start(&mut self, key: KeyEvent) -> bool {
        match key.code {
            KeyCode::Char('f') => {
                let text = self.filter.as_ref().map_or("", |f| f.text.as_str());
                self.filter_edit = Some(LineEdit::new(text));
                true
            }
            KeyCode::Esc if self.filter.is_some() => {
                self.filter = None;
                true
            }
            _ => false,
        }
    }

    /// A key for the open filter line: Enter applies a selector that picks rows among
    /// `groups` (else says why and stays open), Esc clears the filter.
    pub fn filter_key(&mut self, key: KeyEvent, groups: &[&Group]) {
        let Some(edit) = self.filter_edit.as_mut() else {
            return;
        };
        match edit.handle_key(key) {
            EditOutcome::Editing => {}
            EditOutcome::Cancel => {
                self.filter_edit = None;
                self.filter = None;
                self.filter_error = None;
            }
            EditOutcome::Commit if edit.text.trim().is_empty() => {
                self.filter_edit = None;
                self.filter = None;
                self.filter_error = None;
            }
            EditOutcome::Commit => {
                match Selector::parse(&edit.text).and_then(|sel| select(groups, &sel).map(|_| sel))
                {
                    Ok(sel) => {
                        self.filter = Some(sel);
                        self.filter_edit = None;
                        self.filter_error = None;
                        self.row = 0;
                    }
                    Err(e) => self.filter_error = Some(e.0),
                }
            }
        }
    }

    pub fn clamp(&mut self, nrows: usize, nx: usize) {
        self.row = self.row.min(nrows.saturating_sub(1));
        self.x = self.x.min(nx.saturating_sub(1));
    }
}

pub fn draw(screen: &ResultsScreen, data: &Results, theme: Theme, frame: &mut Frame, area: Rect) {
    let view = &screen.spectra;
    let rows = screen.rows(data);
    let mut lines = vec![screen.quantity_line(data, theme)];
    let total = screen.all_rows(data).len();
    if let Some(edit) = &view.filter_edit {
        let mut spans = vec![Span::styled("filter ", theme.key())];
        spans.extend(edit_spans(
            theme,
            edit,
            (area.width as usize).saturating_sub(8),
        ));
        lines.push(Line::from(spans));
        lines.push(match &view.filter_error {
            Some(e) => Line::styled(e.clone(), theme.error()),
            None => Line::styled(
                "e.g. mechanistic(play: 0.005), sequential(record: landers)   Enter apply  Esc clear",
                theme.dim(),
            ),
        });
    } else if let Some(f) = &view.filter {
        lines.push(Line::from(vec![
            Span::styled(format!("filter {}", f.text), theme.key()),
            Span::styled(
                format!(": {} of {total} rows   f edit  Esc clear", rows.len()),
                theme.dim(),
            ),
        ]));
    }
    if rows.is_empty() {
        lines.push(Line::raw("no spectra in these results"));
        frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), area);
        return;
    }
    // Name rows by what tells them apart: the words all share are said once, above.
    let labels: Vec<&str> = rows.iter().map(|s| s.label.as_str()).collect();
    let naming::Names { shared, names } = naming::distinguish(&labels);
    if !shared.is_empty() {
        lines.extend(
            naming::wrap(&format!("all rows: {shared}"), area.width as usize)
                .into_iter()
                .map(|l| Line::styled(l, theme.dim())),
        );
    }
    let n = axis_len(&rows);
    let label_width = label_width(&names, area);
    let width = (area.width as usize).saturating_sub(label_width + 12);
    let st = Strip::fit(n, width, view.x);
    let sel = rows[view.row.min(rows.len() - 1)];
    let at = sel.xs.get(view.x).copied();
    let value = sel.ys.get(view.x).copied().flatten();
    let missing = |s: &Spectrum, x: usize| {
        data.marks_of(s)
            .get(x)
            .copied()
            .unwrap_or(Mark::Overturned)
            .describe()
    };
    // The point's check, if `rocklab check` wrote one beside the results.
    let checked = data
        .scene_at(sel, view.x)
        .and_then(|i| data.checks.get(&i))
        .map_or(String::new(), |c| {
            format!(
                "  check: {} (κ {})",
                c.verdict.label(),
                crate::numfmt::fmt_condition(c.condition)
            )
        });
    let readout = format!(
        "{} = {}  {}: {}{checked}",
        sel.axis,
        at.map_or("–".into(), fmt_num),
        sel.label,
        value.map_or_else(|| missing(sel, view.x).into(), fmt_num)
    );
    let values: Vec<String> = rows
        .iter()
        .map(|s| {
            let v = s.ys.get(view.x).copied().flatten();
            format!(
                "{} {}",
                s.label,
                v.map_or_else(|| missing(s, view.x).into(), fmt_num)
            )
        })
        .collect();
    // Every variant's value at the cursor, when that fits in two lines.
    let all = values.join("  │  ");
    let all_fits = all.chars().count() <= 2 * area.width as usize;
    // Blocks that fit, up to 4 rows tall each; keep the selected one in view.
    // Lines above the rows beyond the quantity line (filter, shared prefix).
    let above = lines.len() - 1;
    let mut room = (area.height as usize).saturating_sub(5 + above + rows.len().min(4));
    let mut height = (room / rows.len()).clamp(1, 4);
    if room / height < rows.len() {
        // Rows are hidden: every line the footer does not take shows one (the footer is the
        // axis, a blank line, the readout and, if it fits, the values at the cursor).
        let lines_of = |chars: usize| chars.div_ceil(area.width.max(1) as usize).max(1);
        let readout_lines = lines_of("cursor ".len() + readout.chars().count() + 20);
        let values_lines = if all_fits {
            lines_of(all.chars().count())
        } else {
            0
        };
        room = (area.height as usize).saturating_sub(3 + above + readout_lines + values_lines);
        height = 1;
    }
    let mut visible = (room / height).max(1);
    if visible < rows.len() {
        // Rows are hidden: one line says how many (the marker), taken from the rows.
        visible = (room.saturating_sub(1) / height).max(1);
    }
    let offset = scroll_offset(view.row, rows.len(), visible);
    for (i, s) in rows.iter().enumerate().skip(offset).take(visible) {
        let selected = i == view.row;
        let label = Span::styled(
            pad(&truncate(&names[i], label_width), label_width),
            if selected {
                theme.selected()
            } else {
                theme.field()
            },
        );
        let style = theme.series(i);
        let layout = Bars {
            strip: &st,
            cursor: view.x,
            height,
            theme,
            max: None,
        };
        let marks = data.marks_of(s);
        lines.extend(series_lines(
            label,
            label_width,
            &s.ys,
            marks,
            style,
            &layout,
        ));
    }
    let below = rows.len().saturating_sub(offset + visible);
    if let Some(more) = more_marker(offset, below) {
        lines.push(Line::styled(format!("{more} rows  ↑↓ scroll"), theme.dim()));
    }
    let axis = rows[0].axis.clone();
    lines.push(axis_line(&rows[0].xs, &st, label_width + 1, &axis));
    lines.push(Line::raw(""));
    lines.push(Line::from(vec![
        Span::styled("cursor ", theme.dim()),
        Span::raw(readout),
        Span::styled("  Enter: open scene", theme.dim()),
    ]));
    if all_fits {
        lines.push(Line::styled(all, theme.base()));
    }
    frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), area);
}
