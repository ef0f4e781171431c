//! The comparison: two variants A and B of the current quantity and their ratio B/A, over the
//! spectra's axis cursor.

use super::super::super::theme::Theme;
use super::super::super::widgets::strip::{Bars, Strip, axis_line, series_lines};
use super::super::super::widgets::{fmt_num, pad, truncate};
use super::{Mark, Results, ResultsScreen, label_width};
use crate::report::{self, Spectrum};
use crossterm::event::{KeyCode, KeyEvent};
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

/// The pair compared: rows (of the current quantity) shown as A and B.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CompareView {
    pub a: usize,
    pub b: usize,
}

impl Default for CompareView {
    fn default() -> Self {
        CompareView { a: 0, b: 1 }
    }
}

impl CompareView {
    /// Two device variants paired by meaning (same record, structure and excitation):
    /// sequential vs mechanistic if there, else the pair with the most points where both
    /// survive; else the first two spectra.
    pub fn default_pair(rows: &[&Spectrum]) -> Self {
        match report::compare::default_pair(rows) {
            Some((a, b)) => CompareView { a, b },
            None => CompareView {
                a: 0,
                b: rows.len().saturating_sub(1).min(1),
            },
        }
    }

    /// a / b: next row as A / B; x: swap.
    pub fn handle_key(&mut self, key: KeyEvent, nrows: usize) {
        match key.code {
            KeyCode::Char('a') if nrows > 0 => self.a = (self.a + 1) % nrows,
            KeyCode::Char('b') if nrows > 0 => self.b = (self.b + 1) % nrows,
            KeyCode::Char('x') => std::mem::swap(&mut self.a, &mut self.b),
            _ => {}
        }
    }

    pub fn clamp(&mut self, nrows: usize) {
        self.a = self.a.min(nrows.saturating_sub(1));
        self.b = self.b.min(nrows.saturating_sub(1));
    }
}

pub fn draw(screen: &ResultsScreen, data: &Results, theme: Theme, frame: &mut Frame, area: Rect) {
    let (pair, x) = (&screen.compare, screen.spectra.x);
    let rows = screen.rows(data);
    let mut lines = vec![screen.quantity_line(data, theme)];
    if rows.len() < 2 {
        lines.push(Line::raw("comparison needs two variants"));
        frame.render_widget(Paragraph::new(lines), area);
        return;
    }
    let a: &Spectrum = rows[pair.a.min(rows.len() - 1)];
    let b: &Spectrum = rows[pair.b.min(rows.len() - 1)];
    let ratio = report::compare(a, b);
    let n = a.xs.len().max(b.xs.len());
    let label_width = label_width(&[a, b], 2, area);
    let width = (area.width as usize).saturating_sub(label_width + 11);
    let st = Strip::fit(n, width, x);
    let height = ((area.height as usize).saturating_sub(10) / 3).clamp(1, 4);
    let layout = Bars {
        strip: &st,
        cursor: x,
        height,
        theme,
    };
    let block = |name: String, values: &[Option<f64>], marks: &[Mark], style: Style| {
        let label = Span::styled(
            pad(&truncate(&name, label_width), label_width),
            theme.field(),
        );
        series_lines(label, label_width, values, marks, style, &layout)
    };
    let (a_marks, b_marks) = (data.marks_of(a), data.marks_of(b));
    // The ratio is missing where either is: it shows the first missing mark of the two.
    let ratio_marks: Vec<Mark> = (0..ratio.len())
        .map(|i| {
            [a_marks.get(i).copied(), b_marks.get(i).copied()]
                .into_iter()
                .flatten()
                .find(|m| *m != Mark::Value)
                .unwrap_or(Mark::Overturned)
        })
        .collect();
    lines.extend(block(
        format!("A {}", a.label),
        &a.ys,
        a_marks,
        theme.series(0),
    ));
    lines.extend(block(
        format!("B {}", b.label),
        &b.ys,
        b_marks,
        theme.series(1),
    ));
    lines.extend(block("B/A".into(), &ratio, &ratio_marks, theme.warn()));
    lines.push(axis_line(&a.xs, &st, label_width + 1, &a.axis));
    lines.push(Line::raw(""));
    let at = |v: &[Option<f64>], marks: &[Mark]| {
        v.get(x).copied().flatten().map_or_else(
            || marks.get(x).map_or("–", |m| m.describe()).to_string(),
            fmt_num,
        )
    };
    lines.push(Line::raw(format!(
        "{} = {}   A {}   B {}   B/A {}",
        a.axis,
        a.xs.get(x).map_or("–".into(), |x| fmt_num(*x)),
        at(&a.ys, a_marks),
        at(&b.ys, b_marks),
        at(&ratio, &ratio_marks)
    )));
    let finite: Vec<f64> = ratio.iter().flatten().copied().collect();
    if !finite.is_empty() {
        let mean = finite.iter().sum::<f64>() / finite.len() as f64;
        let min = finite.iter().copied().fold(f64::INFINITY, f64::min);
        let max = finite.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        lines.push(Line::raw(format!(
            "B/A over {} points: mean {}  min {}  max {}",
            finite.len(),
            fmt_num(mean),
            fmt_num(min),
            fmt_num(max)
        )));
    }
    lines.push(Line::styled(
        "a / b: next variant as A / B   x: swap",
        theme.dim(),
    ));
    frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), area);
}
