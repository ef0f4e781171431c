//! Spectrum strips: a series of values over an axis drawn as a row (or a block of rows) of
//! bars, one cell per point, with a cursor column and a sideways window when the series is
//! longer than the room; plus the axis line under them.

use super::super::theme::Theme;
use super::fmt_num;
use crate::report;
use ratatui::style::{Modifier, Style};
use ratatui::text::{Line, Span};

/// Columns of a spectrum that fit: each point gets `cell` columns, and when the spectrum is
/// longer than the room, a window (`first`, `count`) that keeps the cursor in view.
pub struct Strip {
    pub first: usize,
    pub count: usize,
    pub cell: usize,
}

impl Strip {
    /// The window of `n` points that fits `width` columns around `cursor`.
    pub fn fit(n: usize, width: usize, cursor: usize) -> Strip {
        if n == 0 || width == 0 {
            return Strip {
                first: 0,
                count: 0,
                cell: 1,
            };
        }
        let cell = (width / n).clamp(1, 8);
        let count = (width / cell).min(n);
        let first = cursor.saturating_sub(count / 2).min(n - count);
        Strip { first, count, cell }
    }
}

/// What a point stands for: honest partial results tell a point that overturned from one
/// that failed from one that never ran (a stopped sweep).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mark {
    Value,
    Overturned,
    Failed,
    NotRun,
}

impl Mark {
    /// The readout of a point without a value.
    pub fn describe(self) -> &'static str {
        match self {
            Mark::Value => "–",
            Mark::Overturned => "overturned",
            Mark::Failed => "failed",
            Mark::NotRun => "not run",
        }
    }
}

/// Where and how tall spectrum bars are drawn.
#[derive(Clone, Copy)]
pub struct Bars<'a> {
    pub strip: &'a Strip,
    pub cursor: usize,
    pub height: usize,
    pub theme: Theme,
    /// The value drawn full height: a scale shared with other strips (None: the strip's own
    /// maximum).
    pub max: Option<f64>,
}

/// One spectrum as `height` rows of styled cells (top row first). One row uses the bars of
/// `report::sparkline`; taller blocks (and strips on a shared scale) use eighth-blocks over the
/// rows, scaled from 0 to the spectrum's maximum (or the shared `max`). A point without a value shows what it stands for (`marks`; missing
/// ones read as overturned): `×` overturned, `?` failed, blank not run. The cursor column is
/// reversed.
pub fn bar_rows(
    values: &[Option<f64>],
    marks: &[Mark],
    style: Style,
    layout: &Bars,
) -> Vec<Vec<Span<'static>>> {
    let Bars {
        strip: st,
        cursor,
        height,
        theme,
        max: shared_max,
    } = *layout;
    const EIGHTHS: [char; 9] = [' ', '▁', '▂', '▃', '▄', '▅', '▆', '▇', '█'];
    let glyphs: Vec<char> = report::sparkline(values).chars().collect();
    let max = shared_max.unwrap_or_else(|| values.iter().flatten().copied().fold(0.0, f64::max));
    let mut rows = vec![Vec::new(); height];
    for i in st.first..st.first + st.count {
        let value = values.get(i).copied().flatten();
        // A present value always shows at least ▁, so it never reads as a gap.
        let eighths = match value {
            Some(v) if max > 0.0 => {
                (((v.max(0.0) / max) * (8 * height) as f64).round() as usize).max(1)
            }
            Some(_) => 1,
            None => 0,
        };
        for (r, row) in rows.iter_mut().enumerate() {
            // r = 0 is the top row.
            let level = height - 1 - r;
            let mark = marks.get(i).copied().unwrap_or(Mark::Overturned);
            let glyph = match value {
                None if level > 0 => ' ',
                None => match mark {
                    Mark::Failed => '?',
                    Mark::NotRun => ' ',
                    _ => '×',
                },
                Some(_) if height == 1 && shared_max.is_none() => {
                    glyphs.get(i).copied().unwrap_or(' ')
                }
                Some(_) => EIGHTHS[eighths.saturating_sub(8 * level).min(8)],
            };
            let mut s = match (value, mark) {
                (Some(_), _) => style,
                (None, Mark::Failed) => theme.failed(),
                (None, Mark::NotRun) => theme.base(),
                (None, _) => theme.overturned(),
            };
            if i == cursor {
                s = s.add_modifier(Modifier::REVERSED);
            }
            row.push(Span::styled(glyph.to_string().repeat(st.cell), s));
        }
    }
    rows
}

/// A labelled block of bars: label on the top row, the maximum beside it.
pub fn series_lines(
    label: Span<'static>,
    label_width: usize,
    values: &[Option<f64>],
    marks: &[Mark],
    style: Style,
    layout: &Bars,
) -> Vec<Line<'static>> {
    let max = values.iter().flatten().copied().reduce(f64::max);
    let theme = layout.theme;
    bar_rows(values, marks, style, layout)
        .into_iter()
        .enumerate()
        .map(|(r, bars)| {
            let mut spans = if r == 0 {
                vec![label.clone()]
            } else {
                vec![Span::raw(" ".repeat(label_width))]
            };
            spans.push(Span::raw(" "));
            spans.extend(bars);
            if r == 0 {
                let max = max.map_or("–".into(), fmt_num);
                spans.push(Span::styled(format!(" max {max}"), theme.dim()));
            }
            Line::from(spans)
        })
        .collect()
}

/// The axis under a strip: first, middle and last values of the window, then the axis name,
/// and `[a–b of n]` when the window shows only part of the axis.
pub fn axis_line(xs: &[f64], st: &Strip, indent: usize, axis: &str) -> Line<'static> {
    if st.count == 0 {
        return Line::raw("");
    }
    let width = st.count * st.cell;
    let mut cells = vec![' '; width];
    let mut put = |col: usize, text: &str| {
        let text: Vec<char> = text.chars().collect();
        let start = col.min(width.saturating_sub(text.len()));
        for (k, c) in text.iter().enumerate() {
            if let Some(cell) = cells.get_mut(start + k) {
                *cell = *c;
            }
        }
    };
    let first = st.first;
    let last = st.first + st.count - 1;
    put(0, &fmt_num(xs[first]));
    if st.count > 2 {
        let mid = (first + last) / 2;
        let label = fmt_num(xs[mid]);
        put(
            ((mid - first) * st.cell).saturating_sub(label.len() / 2),
            &label,
        );
    }
    put(width, &fmt_num(xs[last]));
    // A window narrower than the axis says which part it shows: never data cut unmarked.
    // The mark goes in the label column (blank on this line) so the line is no wider than
    // the rows above it; after the axis name only if that column is too narrow.
    let more = if st.count < xs.len() {
        format!("[{}–{} of {}] ", first + 1, last + 1, xs.len())
    } else {
        String::new()
    };
    let more_len = more.chars().count();
    let (lead, tail) = if more_len <= indent {
        (
            format!("{}{more}", " ".repeat(indent - more_len)),
            String::new(),
        )
    } else {
        (" ".repeat(indent), format!("  {}", more.trim_end()))
    };
    Line::raw(format!(
        "{lead}{}  {axis}{tail}",
        cells.into_iter().collect::<String>()
    ))
}
