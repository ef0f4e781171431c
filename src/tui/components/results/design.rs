//! The design view (`g` on the Results screen): one line per design point of a design study,
//! the least value of the sized parameter as a bar against the bracket, and the row under the
//! cursor read out in full (design.csv's columns: value, final bracket, probes, governing
//! excitation point, achieved response, status). The rows are the search replayed on the
//! results' scenes (`report::design::design_rows`), computed once when the results arrive.

use super::super::super::theme::Theme;
use super::super::super::widgets::{fmt_num, truncate};
use crate::study::Study;
use crate::sweep::design::{DesignRow, DesignStatus};
use crossterm::event::{KeyCode, KeyEvent};
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

#[derive(Clone, Debug, Default)]
pub struct DesignView {
    /// The design point under the cursor.
    pub row: usize,
}

impl DesignView {
    pub fn handle_key(&mut self, key: KeyEvent, rows: usize) {
        let last = rows.saturating_sub(1);
        match key.code {
            KeyCode::Up | KeyCode::Char('k') => self.row = self.row.saturating_sub(1),
            KeyCode::Down | KeyCode::Char('j') => self.row = (self.row + 1).min(last),
            KeyCode::Home => self.row = 0,
            KeyCode::End => self.row = last,
            _ => {}
        }
    }

    pub fn draw(
        &self,
        study: Option<&Study>,
        rows: &[DesignRow],
        theme: Theme,
        frame: &mut Frame,
        area: Rect,
    ) {
        let Some(design) = study.and_then(|s| s.design.as_ref()) else {
            frame.render_widget(
                Paragraph::new("no design answer: these results are not of a design study"),
                area,
            );
            return;
        };
        let (low, top) = design.bracket;
        let param = design.parameter.label();
        let mut lines = vec![Line::styled(
            format!(
                "least {param} in [{}, {}] for {} ({} design points)",
                fmt_num(low),
                fmt_num(top),
                design.target.describe(),
                rows.len()
            ),
            theme.title(),
        )];
        let names: Vec<String> = rows.iter().map(row_name).collect();
        let width = area.width as usize;
        let name_w = super::label_width(&names, area);
        // name, bar, value (9), status (15).
        let bar_w = width.saturating_sub(name_w + 26).clamp(4, 40);
        let readout = readout(rows.get(self.row), param);
        let room = (area.height as usize)
            .saturating_sub(2 + readout.len())
            .max(1);
        let first = self
            .row
            .saturating_sub(room / 2)
            .min(rows.len().saturating_sub(room));
        for (i, (row, name)) in rows.iter().zip(&names).enumerate().skip(first).take(room) {
            let selected = i == self.row;
            let style = if selected {
                theme.selected()
            } else {
                theme.base()
            };
            lines.push(Line::from(vec![
                Span::styled(if selected { "▶" } else { " " }, theme.key()),
                Span::styled(format!("{:<name_w$}", truncate(name, name_w)), style),
                Span::raw(" "),
                Span::styled(bar(row, (low, top), bar_w), theme.series(row.variant)),
                Span::styled(format!(" {:>8} ", value_text(row)), style),
                Span::styled(row.status.name(), status_style(row.status, theme)),
            ]));
        }
        lines.push(Line::raw(""));
        for (text, warn) in readout {
            let style = if warn { theme.warn() } else { theme.base() };
            lines.push(Line::styled(text, style));
        }
        frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), area);
    }
}

fn status_style(status: DesignStatus, theme: Theme) -> Style {
    match status {
        DesignStatus::Found | DesignStatus::MetAtLow | DesignStatus::ReferenceMet => theme.ok(),
        DesignStatus::NonMonotone | DesignStatus::Incomplete => theme.warn(),
        DesignStatus::NotAchievable | DesignStatus::ReferenceFails => theme.error(),
    }
}

/// The answer as a bar from the bracket's bottom: full up to the value; a not-achievable
/// point's bar is shaded through the top with an arrow (the answer lies beyond it).
fn bar(row: &DesignRow, (low, top): (f64, f64), width: usize) -> String {
    match (row.status, row.value) {
        (DesignStatus::NotAchievable, _) => format!("{}▶", "░".repeat(width)),
        (_, Some(v)) => {
            let fill = ((v - low) / (top - low)).clamp(0.0, 1.0) * width as f64;
            let fill = fill.round() as usize;
            format!("{}{}", "█".repeat(fill), " ".repeat(width - fill + 1))
        }
        _ => " ".repeat(width + 1),
    }
}

/// The value column: the least value, or what stands for it.
fn value_text(row: &DesignRow) -> String {
    match (row.value, row.status) {
        (Some(v), _) => fmt_num(v),
        (None, DesignStatus::NotAchievable) => format!(">{}", fmt_num(row.hi)),
        _ => "–".into(),
    }
}

/// A design point's name: its device, axis values and record.
fn row_name(row: &DesignRow) -> String {
    let mut name = row.device.clone();
    for (l, v) in &row.axes {
        name.push_str(&format!(" {l}={}", fmt_num(*v)));
    }
    if let Some(r) = &row.record {
        name.push_str(&format!(" {r}"));
    }
    name
}

/// The cursor's row in full, as lines of text (true: drawn as a warning): the answer and the
/// final bracket, the probes and scenes, the governing excitation point and the response
/// there, what the status means, and the values above the answer that fail again.
pub fn readout(row: Option<&DesignRow>, param: &str) -> Vec<(String, bool)> {
    let Some(row) = row else {
        return vec![("no design point".into(), false)];
    };
    let answer = match (row.status, row.value) {
        (_, Some(v)) => format!("least {param} = {}", fmt_num(v)),
        (DesignStatus::NotAchievable, _) => format!(
            "not achievable within the bracket: {param} = {} fails",
            fmt_num(row.hi)
        ),
        (DesignStatus::ReferenceMet, _) => "meets the target without a device".into(),
        (DesignStatus::ReferenceFails, _) => "fails the target without a device".into(),
        _ => "search not finished".into(),
    };
    let bracket = match (row.parameter, row.status) {
        (None, _) | (_, DesignStatus::NotAchievable | DesignStatus::Incomplete) => String::new(),
        _ => format!(", bracket lo {} hi {}", fmt_num(row.lo), fmt_num(row.hi)),
    };
    let achieved = match (row.achieved, row.achieved_note) {
        (Some(v), _) => fmt_num(v),
        (None, Some(note)) => note.to_string(),
        (None, None) => "–".into(),
    };
    let governing = if row.governing.is_empty() {
        "–"
    } else {
        &row.governing
    };
    let mut lines = vec![
        (format!("{}: {answer}{bracket}", row_name(row)), false),
        (
            format!(
                "{} probes ({} scenes); governing {governing}, achieved {achieved}",
                row.probes, row.scenes
            ),
            false,
        ),
        (
            format!("{}: {}", row.status.name(), row.status.help()),
            !matches!(
                row.status,
                DesignStatus::Found | DesignStatus::MetAtLow | DesignStatus::ReferenceMet
            ),
        ),
    ];
    if !row.fails_above.is_empty() {
        let values: Vec<String> = row.fails_above.iter().map(|v| fmt_num(*v)).collect();
        lines.push((
            format!(
                "fails again at {param} = {}: no threshold",
                values.join(", ")
            ),
            true,
        ));
    }
    lines
}
