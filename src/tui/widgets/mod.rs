//! Reusable drawing pieces, apart from the screens that use them (as bottom keeps its widgets
//! apart from its canvas): spectrum strips of bars, a downsampled line chart, a text gauge, a
//! centred popup, key hints, a scrolled line editor and the text helpers they share. Nothing
//! here knows the app state.

pub mod chart;
pub mod strip;

use super::edit::LineEdit;
use super::theme::Theme;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph};

/// A key and what it does, as shown on the status line.
pub type Hint = (&'static str, &'static str);

/// `key what  key what …`, keys highlighted.
pub fn hint_spans(theme: Theme, keys: &[Hint]) -> Vec<Span<'static>> {
    hint_spans_fit(theme, keys, usize::MAX)
}

/// The hints that fit in `width` columns, whole, most important (first) kept: a narrow
/// terminal loses the last hints, never half a word.
pub fn hint_spans_fit(theme: Theme, keys: &[Hint], width: usize) -> Vec<Span<'static>> {
    let mut spans = Vec::new();
    let mut used = 0;
    for (key, what) in keys {
        let sep = if spans.is_empty() { 0 } else { 2 };
        let need = sep + key.chars().count() + 1 + what.chars().count();
        if used + need > width {
            continue;
        }
        used += need;
        if sep > 0 {
            spans.push(Span::raw("  "));
        }
        spans.push(Span::styled(key.to_string(), theme.key()));
        spans.push(Span::styled(format!(" {what}"), theme.dim()));
    }
    spans
}

/// The edited text with its cursor, scrolled sideways so the cursor stays within `width`.
pub fn edit_spans(theme: Theme, line: &LineEdit, width: usize) -> Vec<Span<'static>> {
    let (before, at, after) = line.split();
    let width = width.max(2);
    let shown_before = before.chars().count().min(width - 1);
    let before: String = before
        .chars()
        .skip(before.chars().count() - shown_before)
        .collect();
    let after: String = after.chars().take(width - 1 - shown_before).collect();
    vec![
        Span::styled(before, theme.value()),
        Span::styled(at, theme.cursor()),
        Span::styled(after, theme.value()),
    ]
}

/// A progress bar of `width` cells.
pub fn gauge(theme: Theme, done: usize, total: usize, width: usize) -> Span<'static> {
    let filled = (done * width).checked_div(total).unwrap_or(0).min(width);
    Span::styled(
        format!("{}{}", "█".repeat(filled), "░".repeat(width - filled)),
        theme.ok(),
    )
}

/// A bordered box of `width` × `height` text lines (plus borders) centred in `area`, over
/// whatever was drawn there.
pub fn popup(
    frame: &mut Frame,
    theme: Theme,
    area: Rect,
    title: &str,
    lines: Vec<Line<'static>>,
    width: u16,
    height: u16,
) {
    let w = width.min(area.width);
    let h = (height + 2).min(area.height);
    let rect = Rect {
        x: area.x + (area.width - w) / 2,
        y: area.y + (area.height - h) / 2,
        width: w,
        height: h,
    };
    frame.render_widget(Clear, rect);
    let block = Block::default()
        .borders(Borders::ALL)
        .title(title.to_string())
        .border_style(theme.title());
    frame.render_widget(Paragraph::new(lines).block(block), rect);
}

/// First row to show so that the cursor stays visible, with context above it.
pub fn scroll_offset(cursor: usize, len: usize, height: usize) -> usize {
    if height == 0 || len <= height {
        return 0;
    }
    cursor.saturating_sub(height / 2).min(len - height)
}

// ----- text -----

/// Numbers read as in study labels and reports: one formatter for the whole program.
pub use crate::numfmt::{fmt_duration, fmt_num};

/// `name=value name=value …` of a scene's coordinates.
pub fn fmt_coords(coords: &[(String, f64)]) -> String {
    coords
        .iter()
        .map(|(k, v)| format!("{k}={}", fmt_num(*v)))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The one marker of a list cut to fit (`▴ 3 more  ▾ 37 more`): how many entries lie above
/// and below what is shown; None when nothing is hidden. Every view that cuts a list says so
/// with it, so a cut is never silent and always reads the same.
pub fn more_marker(above: usize, below: usize) -> Option<String> {
    let parts: Vec<String> = [(above, '▴'), (below, '▾')]
        .into_iter()
        .filter(|(n, _)| *n > 0)
        .map(|(n, arrow)| format!("{arrow} {n} more"))
        .collect();
    (!parts.is_empty()).then(|| parts.join("  "))
}

/// At most `width` characters; a cut end is marked with `…`.
pub fn truncate(s: &str, width: usize) -> String {
    if s.chars().count() <= width {
        s.to_string()
    } else if width == 0 {
        String::new()
    } else {
        let mut t: String = s.chars().take(width - 1).collect();
        t.push('…');
        t
    }
}

/// At most `width` characters, keeping the end (file paths).
pub fn truncate_left(s: &str, width: usize) -> String {
    let n = s.chars().count();
    if n <= width {
        s.to_string()
    } else {
        let mut t = String::from("…");
        t.extend(s.chars().skip(n - width + 1));
        t
    }
}

pub fn pad(s: &str, width: usize) -> String {
    let n = s.chars().count();
    format!("{s}{}", " ".repeat(width.saturating_sub(n)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cut_list_says_how_much_is_hidden_on_each_side() {
        assert_eq!(more_marker(0, 0), None);
        assert_eq!(more_marker(0, 37).as_deref(), Some("▾ 37 more"));
        assert_eq!(more_marker(3, 0).as_deref(), Some("▴ 3 more"));
        assert_eq!(more_marker(3, 37).as_deref(), Some("▴ 3 more  ▾ 37 more"));
    }

    #[test]
    fn a_long_edit_scrolls_to_keep_the_cursor_in_view() {
        let shown = |line: &LineEdit| -> String {
            edit_spans(Theme::MONO, line, 10)
                .iter()
                .map(|s| s.content.to_string())
                .collect()
        };
        let mut line = LineEdit::new("[1.0, 2.0, 3.0, 4.0]");
        assert_eq!(shown(&line), "3.0, 4.0] ");
        line.cursor = 0;
        assert_eq!(shown(&line), "[1.0, 2.0,");
        line.cursor = 5;
        assert_eq!(shown(&line), "[1.0, 2.0,");
    }
}
