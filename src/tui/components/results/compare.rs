//! The comparison, paired as `rocklab compare` pairs (report/compare.rs, report/select.rs): A
//! and B are picked by device and parameter values, every A is paired with the Bs of the
//! same situation (record, structure, excitation), one row per pair sorted by a statistic;
//! the selected pair is drawn as A, B (on one y scale unless toggled) and B/A around a marked
//! 1.0, with the overturning-aware statistics; `d` shows the two overturning maps' difference.

use super::super::super::theme::Theme;
use super::super::super::widgets::strip::{Bars, Strip, axis_line, series_lines};
use super::super::super::widgets::{fmt_num, more_marker, pad, scroll_offset, truncate};
use super::{Mark, Results, ResultsScreen};
use crate::report::compare::{self, MapCell, MapComparison, PairStats, PointPair, SpectrumPair};
use crate::report::naming;
use crate::report::select::{SelectError, Selector};
use crate::report::{Group, PointState, Quantity, Spectrum};
use crossterm::event::{KeyCode, KeyEvent};
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::{Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

mod map;
use map::draw_map;

/// One side of the comparison: a device (a variant's label) and the parameter values picked
/// (the rest free: a grid side).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Side {
    pub device: String,
    /// (setting id, exact value, record name) picked.
    pub picks: Vec<(String, f64, Option<String>)>,
}

impl Side {
    /// The side as a selector of report/select.rs (what `compare --a/--b` takes).
    pub fn selector_text(&self) -> String {
        if self.picks.is_empty() {
            return self.device.clone();
        }
        let fields: Vec<String> = self
            .picks
            .iter()
            .map(|(id, v, name)| match name {
                Some(n) => format!("{id}: {n}"),
                // Display of f64 is its shortest exact form: the value itself is selected.
                None => format!("{id}: {v}"),
            })
            .collect();
        format!("{}({})", self.device, fields.join(", "))
    }

    pub fn selector(&self) -> Result<Selector, SelectError> {
        Selector::parse(&self.selector_text())
    }
}

/// Row order of the pairs (as `compare --sort`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SortBy {
    #[default]
    Mean,
    Median,
    Peak,
    BSaves,
    Study,
}

impl SortBy {
    fn next(self) -> SortBy {
        match self {
            SortBy::Mean => SortBy::Median,
            SortBy::Median => SortBy::Peak,
            SortBy::Peak => SortBy::BSaves,
            SortBy::BSaves => SortBy::Study,
            SortBy::Study => SortBy::Mean,
        }
    }

    fn name(self) -> &'static str {
        match self {
            SortBy::Mean => "mean B/A",
            SortBy::Median => "median B/A",
            SortBy::Peak => "peak ratio",
            SortBy::BSaves => "B survives where A overturns",
            SortBy::Study => "study order",
        }
    }

    fn key(self, s: &PairStats) -> f64 {
        match self {
            SortBy::Study => 0.0,
            SortBy::Mean => s.mean_ratio.unwrap_or(f64::INFINITY),
            SortBy::Median => s.median_ratio.unwrap_or(f64::INFINITY),
            SortBy::Peak => s.peak_ratio.unwrap_or(f64::INFINITY),
            SortBy::BSaves => -(s.a_overturns_b_survives as f64),
        }
    }
}

/// Which side the picker edits, and its field (0: device, then the parameters).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Picking {
    pub b: bool,
    pub field: usize,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct CompareView {
    pub a: Side,
    pub b: Side,
    /// Selected pair (row).
    pub pair: usize,
    pub sort: SortBy,
    /// Each of A and B on its own y scale (default: one scale for both).
    pub per_row_scale: bool,
    /// Show the overturning maps' difference instead of the spectra.
    pub show_map: bool,
    pub picking: Option<Picking>,
}

/// A parameter the picker offers for a device: its id, label and the values there are.
struct Choice {
    id: String,
    label: String,
    /// (exact value, as shown, record name)
    values: Vec<(f64, String, Option<String>)>,
}

/// The devices (variant labels) among `groups`, in order.
fn devices(groups: &[&Group]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for g in groups {
        if !out.contains(&g.device_label) {
            out.push(g.device_label.clone());
        }
    }
    out
}

/// The parameters that vary among the groups of `device`, with their values sorted.
fn choices(groups: &[&Group], device: &str) -> Vec<Choice> {
    let mut out: Vec<Choice> = Vec::new();
    for g in groups.iter().filter(|g| g.device_label == device) {
        for s in g.settings.iter().filter(|s| s.varies) {
            let i = match out.iter().position(|c| c.id == s.id) {
                Some(i) => i,
                None => {
                    out.push(Choice {
                        id: s.id.clone(),
                        label: s.label.clone(),
                        values: vec![],
                    });
                    out.len() - 1
                }
            };
            if !out[i].values.iter().any(|v| v.0 == s.value) {
                out[i]
                    .values
                    .push((s.value, s.text.clone(), s.name.clone()));
            }
        }
    }
    for c in &mut out {
        c.values.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    out.retain(|c| c.values.len() > 1);
    out
}

impl CompareView {
    /// A and B of the default pair ([`compare::default_sides`], as `rocklab compare` without
    /// `--a`/`--b`): each side its whole device, so a grid side compares with every member
    /// and a record suite record by record.
    pub fn default_pair(rows: &[&Spectrum]) -> Self {
        let side = |device: String| Side {
            device,
            picks: vec![],
        };
        let (a, b) = compare::default_sides(rows).unwrap_or_default();
        CompareView {
            a: side(a),
            b: side(b),
            ..Default::default()
        }
    }

    /// The pairs of `quantity`, sorted; or why there are none.
    pub fn pairs(&self, data: &Results, quantity: Quantity) -> Result<Vec<SpectrumPair>, String> {
        let (a, b) = (self.a.selector(), self.b.selector());
        let (a, b) = (a.map_err(|e| e.0)?, b.map_err(|e| e.0)?);
        let mut pairs =
            compare::compare_spectra(&data.spectra, quantity, &a, &b).map_err(|e| e.0)?;
        let by = self.sort;
        pairs.sort_by(|p, q| by.key(&p.stats).total_cmp(&by.key(&q.stats)));
        Ok(pairs)
    }

    /// The overturning maps paired as the spectra are.
    pub fn map_pairs(&self, data: &Results) -> Result<Vec<MapComparison>, String> {
        let (a, b) = (self.a.selector(), self.b.selector());
        compare::compare_maps(&data.maps, &a.map_err(|e| e.0)?, &b.map_err(|e| e.0)?)
            .map_err(|e| e.0)
    }

    fn side_mut(&mut self, b: bool) -> &mut Side {
        if b { &mut self.b } else { &mut self.a }
    }

    /// Keys of the picker (while open) and of the comparison. Returns whether it used the key.
    pub fn handle_key(&mut self, key: KeyEvent, groups: &[&Group], npairs: usize) -> bool {
        if let Some(mut p) = self.picking {
            let side = self.side_mut(p.b).clone();
            let params = choices(groups, &side.device);
            match key.code {
                KeyCode::Enter | KeyCode::Esc | KeyCode::Char('a') | KeyCode::Char('b') => {
                    self.picking = None;
                    return true;
                }
                KeyCode::Up | KeyCode::Char('k') => p.field = p.field.saturating_sub(1),
                KeyCode::Down | KeyCode::Char('j') => p.field = (p.field + 1).min(params.len()),
                KeyCode::Left | KeyCode::Right | KeyCode::Char('h') | KeyCode::Char('l') => {
                    let back = matches!(key.code, KeyCode::Left | KeyCode::Char('h'));
                    *self.side_mut(p.b) = step(&side, p.field, back, groups, &params);
                }
                _ => {}
            }
            self.picking = Some(p);
            self.pair = 0;
            return true;
        }
        match key.code {
            KeyCode::Char('a') => self.picking = Some(Picking { b: false, field: 0 }),
            KeyCode::Char('b') => self.picking = Some(Picking { b: true, field: 0 }),
            KeyCode::Char('x') => std::mem::swap(&mut self.a, &mut self.b),
            KeyCode::Char('o') => self.sort = self.sort.next(),
            KeyCode::Char('y') => self.per_row_scale = !self.per_row_scale,
            KeyCode::Char('d') => self.show_map = !self.show_map,
            KeyCode::Up | KeyCode::Char('k') => self.pair = self.pair.saturating_sub(1),
            KeyCode::Down | KeyCode::Char('j') => {
                self.pair = (self.pair + 1).min(npairs.saturating_sub(1))
            }
            _ => return false,
        }
        true
    }
}

/// The side with field `field` stepped to the next (or previous) choice: the device among
/// the devices there are (its picks dropped), a parameter among "any" and its values.
fn step(side: &Side, field: usize, back: bool, groups: &[&Group], params: &[Choice]) -> Side {
    let cycle = |i: usize, n: usize| if back { (i + n - 1) % n } else { (i + 1) % n };
    if field == 0 {
        let all = devices(groups);
        if all.is_empty() {
            return side.clone();
        }
        let i = all.iter().position(|d| *d == side.device).unwrap_or(0);
        return Side {
            device: all[cycle(i, all.len())].clone(),
            picks: vec![],
        };
    }
    let Some(param) = params.get(field - 1) else {
        return side.clone();
    };
    let mut out = side.clone();
    // Position 0 is "any"; 1.. the values.
    let now = out
        .picks
        .iter()
        .position(|(id, ..)| *id == param.id)
        .map(|k| out.picks.remove(k))
        .and_then(|(_, v, _)| param.values.iter().position(|x| x.0 == v))
        .map_or(0, |i| i + 1);
    let next = cycle(now, param.values.len() + 1);
    if next > 0 {
        let (v, _, name) = &param.values[next - 1];
        out.picks.push((param.id.clone(), *v, name.clone()));
        // Keep the study's parameter order.
        out.picks
            .sort_by_key(|(id, ..)| params.iter().position(|c| c.id == *id));
    }
    out
}

fn mark_of(state: PointState) -> Mark {
    match state {
        PointState::Survived => Mark::Value,
        PointState::Overturned => Mark::Overturned,
        PointState::Failed => Mark::Failed,
        PointState::NotRun => Mark::NotRun,
    }
}

/// What a point without a B/A stands for, as a glyph on the 1.0 line.
fn ratio_glyph(p: &PointPair) -> char {
    use PointState::*;
    match (p.a_state, p.b_state) {
        (NotRun, _) | (_, NotRun) => ' ',
        (Failed, _) | (_, Failed) => '?',
        (Overturned, Survived) => 'B',
        (Survived, Overturned) => 'A',
        (Overturned, Overturned) => '×',
        (Survived, Survived) => '0',
    }
}

/// The half-range of the B/A rows: the smallest of 1, 2, 5 × 10^k that holds every ratio's
/// distance from 1.0 (at least 0.01).
fn ratio_scale(points: &[PointPair]) -> f64 {
    let dev = points
        .iter()
        .filter_map(|p| p.ratio)
        .map(|r| (r - 1.0).abs())
        .fold(0.0, f64::max)
        .max(0.01);
    let mut k = 10f64.powf(dev.log10().floor());
    loop {
        for m in [1.0, 2.0, 5.0] {
            if m * k >= dev * (1.0 - 1e-12) {
                return m * k;
            }
        }
        k *= 10.0;
    }
}

/// B/A drawn around 1.0: `half` rows of bars rising above the 1.0 line for B > A, the line
/// itself (marked `1.0`), `half` rows of bars hanging below it for B < A, scaled to ±`scale`.
/// Points without a ratio show on the line what they are (`ratio_glyph`).
fn ratio_lines(
    points: &[PointPair],
    st: &Strip,
    cursor: usize,
    half: usize,
    label_width: usize,
    theme: Theme,
) -> Vec<Line<'static>> {
    const RISE: [char; 9] = [' ', '▁', '▂', '▃', '▄', '▅', '▆', '▇', '█'];
    let scale = ratio_scale(points);
    let levels = (8 * half) as f64;
    let mut lines = Vec::new();
    for r in 0..2 * half + 1 {
        let (label, right) = match r {
            0 => ("B/A".to_string(), format!(" {}", fmt_num(1.0 + scale))),
            r if r == half => ("1.0 ─".to_string(), " ─ 1.0".to_string()),
            r if r == 2 * half => (String::new(), format!(" {}", fmt_num(1.0 - scale))),
            _ => (String::new(), String::new()),
        };
        let label_style = if r == half {
            theme.title()
        } else {
            theme.field()
        };
        let mut spans = vec![
            Span::styled(
                format!("{:>label_width$}", truncate(&label, label_width)),
                label_style,
            ),
            Span::raw(" "),
        ];
        for i in st.first..st.first + st.count {
            let p = points.get(i);
            let ratio = p.and_then(|p| p.ratio);
            let (glyph, mut style) = if r == half {
                match (ratio, p) {
                    (Some(_), _) => ('─', theme.title()),
                    (None, Some(p)) => (
                        ratio_glyph(p),
                        match ratio_glyph(p) {
                            '?' => theme.failed(),
                            ' ' => theme.base(),
                            _ => theme.overturned(),
                        },
                    ),
                    (None, None) => (' ', theme.base()),
                }
            } else {
                let glyph = match ratio {
                    Some(v) => {
                        let e = (((v - 1.0).abs() / scale).min(1.0) * levels).round() as usize;
                        if r < half && v > 1.0 {
                            // Row r above the line holds eighths (half - 1 - r)*8 .. +8.
                            RISE[e.saturating_sub(8 * (half - 1 - r)).min(8)]
                        } else if r > half && v < 1.0 {
                            let got = e.saturating_sub(8 * (r - half - 1)).min(8);
                            match got {
                                0 => ' ',
                                1..=2 => '▔',
                                3..=5 => '▀',
                                _ => '█',
                            }
                        } else {
                            ' '
                        }
                    }
                    None => ' ',
                };
                (glyph, theme.warn())
            };
            if i == cursor {
                style = style.add_modifier(Modifier::REVERSED);
            }
            spans.push(Span::styled(glyph.to_string().repeat(st.cell), style));
        }
        spans.push(Span::styled(right, theme.dim()));
        lines.push(Line::from(spans));
    }
    lines
}

/// `—` for a missing statistic.
fn stat(v: Option<f64>) -> String {
    v.map_or("—".into(), |v| format!("{v:.3}"))
}

/// The list of pairs (at most `room` lines), each named by what tells it from the others
/// ([`naming::pair_names`]: the member of a grid, the situation) with the words every pair
/// has said once above; a name too long for one line with its statistics wraps.
fn pair_list(
    pairs: &[SpectrumPair],
    sel: usize,
    sort: SortBy,
    room: usize,
    width: u16,
    theme: Theme,
) -> Vec<Line<'static>> {
    let width = (width as usize).max(20);
    let labels: Vec<(&str, &str)> = pairs.iter().map(|p| (p.a.as_str(), p.b.as_str())).collect();
    let names = naming::pair_names(&labels);
    let head = format!(
        "{} pairs by {} (o sorts; A↯/B↯: only A/B overturns), all: {}",
        pairs.len(),
        sort.name(),
        names.shared
    );
    let mut lines: Vec<Line<'static>> = naming::wrap(&head, width)
        .into_iter()
        .take(room.saturating_sub(1).max(1))
        .map(|l| Line::styled(l, theme.dim()))
        .collect();
    let stats = |s: &PairStats| {
        format!(
            "mean {}  med {}  peak {}  A↯ {}  B↯ {}",
            stat(s.mean_ratio),
            stat(s.median_ratio),
            stat(s.peak_ratio),
            s.a_overturns_b_survives,
            s.b_overturns_a_survives
        )
    };
    let name_w = names
        .names
        .iter()
        .map(|n| n.chars().count())
        .max()
        .unwrap_or(0);
    let stats_w = pairs
        .iter()
        .map(|p| stats(&p.stats).chars().count())
        .max()
        .unwrap_or(0);
    let one_line = name_w + 2 + stats_w <= width;
    // Every pair takes as many lines as the longest name needs.
    let per_pair = if one_line {
        1
    } else {
        names
            .names
            .iter()
            .map(|n| naming::wrap(n, width).len())
            .max()
            .unwrap_or(1)
            + 1
    };
    let mut shown = (room.saturating_sub(lines.len()) / per_pair).min(pairs.len());
    if shown < pairs.len() {
        // Pairs are hidden: one line says how many.
        shown = (room.saturating_sub(lines.len() + 1) / per_pair).max(1);
    }
    let offset = scroll_offset(sel, pairs.len(), shown.max(1));
    let more = more_marker(offset, pairs.len().saturating_sub(offset + shown));
    for (i, p) in pairs.iter().enumerate().skip(offset).take(shown) {
        let style = if i == sel {
            theme.selected()
        } else {
            theme.base()
        };
        let name = &names.names[i];
        if one_line {
            lines.push(Line::styled(
                format!("{}  {}", pad(name, name_w), stats(&p.stats)),
                style,
            ));
            continue;
        }
        let mut wrapped = naming::wrap(name, width);
        wrapped.resize(per_pair - 1, String::new());
        lines.extend(wrapped.into_iter().map(|l| Line::styled(l, style)));
        lines.push(Line::styled(format!("  {}", stats(&p.stats)), style));
    }
    if let Some(more) = more {
        lines.push(Line::styled(
            format!("{more} pairs  ↑↓ scroll"),
            theme.dim(),
        ));
    }
    lines
}

fn side_line(name: &str, side: &Side, style: Style, theme: Theme) -> Line<'static> {
    Line::from(vec![
        Span::styled(format!("{name} "), theme.key()),
        Span::styled(side.selector_text(), style),
    ])
}

/// The picker: the side's device and the parameters that vary for it, each with its value.
fn picker_lines(
    side: &Side,
    picking: Picking,
    groups: &[&Group],
    theme: Theme,
) -> Vec<Line<'static>> {
    let params = choices(groups, &side.device);
    let mut lines = vec![Line::styled(
        format!(
            "pick {}: ↑↓ field  ←→ value  Enter done",
            if picking.b { "B" } else { "A" }
        ),
        theme.title(),
    )];
    let row = |i: usize, name: String, value: String, others: String| {
        let style = if i == picking.field {
            theme.selected()
        } else {
            theme.field()
        };
        Line::from(vec![
            Span::styled(pad(&truncate(&name, 14), 14), style),
            Span::styled(format!("‹{value}›"), theme.value()),
            Span::styled(format!("  {others}"), theme.dim()),
        ])
    };
    lines.push(row(
        0,
        "device".into(),
        side.device.clone(),
        devices(groups).join(", "),
    ));
    for (i, c) in params.iter().enumerate() {
        let value = side
            .picks
            .iter()
            .find(|(id, ..)| *id == c.id)
            .and_then(|(_, v, _)| c.values.iter().find(|x| x.0 == *v))
            .map_or("any".to_string(), |x| x.1.clone());
        let all: Vec<&str> = c.values.iter().map(|x| x.1.as_str()).collect();
        lines.push(row(
            i + 1,
            format!("{} ({})", c.id, c.label),
            value,
            all.join(", "),
        ));
    }
    lines
}

pub fn draw(screen: &ResultsScreen, data: &Results, theme: Theme, frame: &mut Frame, area: Rect) {
    let view = &screen.compare;
    let groups: Vec<&Group> = screen.rows(data).iter().map(|s| &s.group).collect();
    let mut lines = vec![screen.quantity_line(data, theme)];
    lines.push(side_line("A", &view.a, theme.series(0), theme));
    lines.push(side_line("B", &view.b, theme.series(1), theme));
    let scale_line = lines.len() - 1;
    if let Some(p) = view.picking {
        let side = if p.b { &view.b } else { &view.a };
        lines.extend(picker_lines(side, p, &groups, theme));
    }
    if view.show_map {
        draw_map(view, data, theme, lines, frame, area);
        return;
    }
    let Some(q) = screen.current_quantity(data) else {
        lines.push(Line::raw("no spectra in these results"));
        frame.render_widget(Paragraph::new(lines), area);
        return;
    };
    let pairs = match view.pairs(data, q) {
        Ok(p) => p,
        Err(e) => {
            lines.push(Line::styled(e, theme.error()));
            frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), area);
            return;
        }
    };
    let sel = view.pair.min(pairs.len() - 1);
    let pair = &pairs[sel];
    // The labels take the width they need, leaving the bars at least a column per point
    // (up to a third of the width); only then are they cut (with `…`).
    let needed = [&pair.a, &pair.b]
        .iter()
        .map(|l| 2 + l.chars().count())
        .max()
        .unwrap_or(0);
    let bars_min = pair.points.len().min(area.width as usize / 3);
    let label_width = needed.clamp(
        8,
        (area.width as usize).saturating_sub(12 + bars_min).max(8),
    );
    let width = (area.width as usize).saturating_sub(label_width + 12);
    let x = screen.spectra.x.min(pair.points.len().saturating_sub(1));
    let st = Strip::fit(pair.points.len(), width, x);
    // Rows left for the list of pairs after the drawing (A, B: 2 rows each; B/A: 3; axis;
    // cursor; statistics: 2; legend).
    let fixed = lines.len() + 4 + 3 + 1 + 1 + 2 + 1;
    let list_room = (area.height as usize).saturating_sub(fixed);
    if pairs.len() > 1 && list_room > 1 {
        lines.extend(pair_list(
            &pairs, sel, view.sort, list_room, area.width, theme,
        ));
    }
    let a: Vec<Option<f64>> = pair.points.iter().map(|p| p.a).collect();
    let b: Vec<Option<f64>> = pair.points.iter().map(|p| p.b).collect();
    let a_marks: Vec<Mark> = pair.points.iter().map(|p| mark_of(p.a_state)).collect();
    let b_marks: Vec<Mark> = pair.points.iter().map(|p| mark_of(p.b_state)).collect();
    let shared = a.iter().chain(&b).flatten().copied().reduce(f64::max);
    lines[scale_line].spans.push(Span::styled(
        if view.per_row_scale {
            "   y: A and B each on its own scale".to_string()
        } else {
            format!(
                "   y: A and B on one scale, 0–{}",
                shared.map_or("–".into(), fmt_num)
            )
        },
        theme.dim(),
    ));
    let bars = Bars {
        strip: &st,
        cursor: x,
        height: 2,
        theme,
        max: if view.per_row_scale { None } else { shared },
    };
    let block = |name: String, values: &[Option<f64>], marks: &[Mark], style: Style| {
        let label = Span::styled(
            pad(&truncate(&name, label_width), label_width),
            theme.field(),
        );
        series_lines(label, label_width, values, marks, style, &bars)
    };
    lines.extend(block(
        format!("A {}", pair.a),
        &a,
        &a_marks,
        theme.series(0),
    ));
    lines.extend(block(
        format!("B {}", pair.b),
        &b,
        &b_marks,
        theme.series(1),
    ));
    lines.extend(ratio_lines(&pair.points, &st, x, 1, label_width, theme));
    let xs: Vec<f64> = pair.points.iter().map(|p| p.x).collect();
    lines.push(axis_line(&xs, &st, label_width + 1, &pair.axis));
    let at = |v: Option<f64>, state: PointState| {
        v.map_or_else(|| mark_of(state).describe().to_string(), fmt_num)
    };
    if let Some(p) = pair.points.get(x) {
        let ratio = match (p.ratio, ratio_glyph(p)) {
            (Some(r), _) => fmt_num(r),
            (None, 'B') => "— (only B survives)".into(),
            (None, 'A') => "— (only A survives)".into(),
            (None, '0') => "— (A is 0)".into(),
            (None, _) => "—".into(),
        };
        lines.push(Line::raw(format!(
            "{} = {}   A {}   B {}   B/A {}",
            pair.axis,
            fmt_num(p.x),
            at(p.a, p.a_state),
            at(p.b, p.b_state),
            ratio
        )));
    }
    let s = &pair.stats;
    lines.push(Line::raw(format!(
        "both survive {}/{} pts: B/A mean {}  median {}  peak ratio {}",
        s.ratio_points,
        s.points,
        stat(s.mean_ratio),
        stat(s.median_ratio),
        stat(s.peak_ratio)
    )));
    lines.push(Line::raw(format!(
        "A overturns, B not: {}  B overturns, A not: {}  both: {}  failed {}  not run {}",
        s.a_overturns_b_survives, s.b_overturns_a_survives, s.both_overturn, s.failed, s.not_run
    )));
    lines.push(Line::styled(
        "on 1.0: B/A only B/A survives, 0 A=0, × both overturn, ? failed, blank not run",
        theme.dim(),
    ));
    frame.render_widget(Paragraph::new(lines), area);
}
