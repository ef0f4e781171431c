//! Fragility curves: P(reach the damage state | IM) per variant for one damage state, drawn
//! from the fragility.json beside the results (the report computed at the end of the run; no
//! statistics here). ↑↓ pick a variant, ←→ move along the IM, [ ] change the damage state; the
//! readout gives the variant's median and β with their bootstrap intervals, its ratio to the
//! bare variant, and the fitted probability and observed fraction at the cursor.

use super::super::super::theme::Theme;
use super::super::super::widgets::{fmt_num, more_marker, truncate};
use crate::report::fragility::{
    self as summary, Curve, FitStatus, FragilityReport, Method, data_points, with_interval,
};
use crossterm::event::{KeyCode, KeyEvent};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Block, Borders, Chart, Dataset, GraphType, Paragraph};

/// IM positions of the cursor when the curves have no stripes (IDA).
const IDA_STEPS: usize = 16;

#[derive(Clone, Debug, Default)]
pub struct FragilityView {
    /// Index of the damage state shown (in the report's order).
    pub state: usize,
    /// Index of the selected variant among the curves of that state.
    pub variant: usize,
    /// Cursor position along the IM grid.
    pub x: usize,
}

/// The damage states in the report's order.
fn states(report: &FragilityReport) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for c in &report.curves {
        if !out.contains(&c.damage_state) {
            out.push(c.damage_state);
        }
    }
    out
}

impl FragilityView {
    /// The curves of the damage state shown, one per variant.
    pub fn curves<'a>(&self, report: &'a FragilityReport) -> Vec<&'a Curve> {
        let ds = states(report).get(self.state).copied();
        report
            .curves
            .iter()
            .filter(|c| Some(c.damage_state) == ds)
            .collect()
    }

    /// The IMs the cursor steps through: the stripes of the state's curves, or an even grid.
    /// The selected curve, if any.
    pub fn selected<'a>(&self, report: &'a FragilityReport) -> Option<&'a Curve> {
        self.curves(report).get(self.variant).copied()
    }

    pub fn grid(&self, report: &FragilityReport) -> Vec<f64> {
        let curves = self.curves(report);
        let mut ims: Vec<f64> = curves
            .iter()
            .flat_map(|c| c.stripes.iter().map(|p| p.im))
            .collect();
        ims.sort_by(f64::total_cmp);
        ims.dedup();
        if ims.is_empty() {
            let top = x_max(&curves);
            ims = (1..=IDA_STEPS)
                .map(|k| top * k as f64 / IDA_STEPS as f64)
                .collect();
        }
        ims
    }

    pub fn handle_key(&mut self, key: KeyEvent, report: Option<&FragilityReport>) {
        let Some(report) = report else { return };
        let ns = states(report).len();
        match key.code {
            KeyCode::Char(']') if ns > 0 => self.state = (self.state + 1) % ns,
            KeyCode::Char('[') if ns > 0 => self.state = (self.state + ns - 1) % ns,
            KeyCode::Up | KeyCode::Char('k') => self.variant = self.variant.saturating_sub(1),
            KeyCode::Down | KeyCode::Char('j') => self.variant += 1,
            KeyCode::Left | KeyCode::Char('h') => self.x = self.x.saturating_sub(1),
            KeyCode::Right | KeyCode::Char('l') => self.x += 1,
            _ => {}
        }
        self.variant = self
            .variant
            .min(self.curves(report).len().saturating_sub(1));
        self.x = self.x.min(self.grid(report).len().saturating_sub(1));
    }

    pub fn draw(
        &self,
        report: Option<&FragilityReport>,
        theme: Theme,
        frame: &mut Frame,
        area: Rect,
    ) {
        let Some(report) = report.filter(|r| !r.curves.is_empty()) else {
            frame.render_widget(
                Paragraph::new("no fragility curves: these results have no fragility.json"),
                area,
            );
            return;
        };
        let all_states = states(report);
        let curves = self.curves(report);
        let ds = all_states.get(self.state).copied().unwrap_or(f64::NAN);
        let measure = if report.damage_measure.is_empty() {
            "DM"
        } else {
            &report.damage_measure
        };
        let im = if report.im.is_empty() {
            "IM"
        } else {
            &report.im
        };
        let method = curves.first().map_or("", |c| c.method.name());
        // Rows named by what tells them apart; a parameter all share is said once, below.
        let labels: Vec<String> = curves.iter().map(|c| summary::variant_name(c)).collect();
        let (shared, names) = crate::report::naming::factor_shared(&labels);
        let first = self.variant.saturating_sub(5);
        let shown = curves.len().saturating_sub(first).min(6);
        let mut notes = Vec::new();
        if !shared.is_empty() {
            notes.push(format!("all: {shared}"));
        }
        notes.extend(more_marker(first, curves.len() - first - shown));
        let header = Line::from(vec![
            Span::styled("[ ] ", theme.key()),
            Span::styled(format!("{measure} ≥ {}", fmt_num(ds)), theme.title()),
            Span::styled(
                format!(
                    "  ({}/{})  {method}, {} resamples, {:.0} % intervals",
                    self.state + 1,
                    all_states.len(),
                    report.bootstrap,
                    100.0 * report.confidence
                ),
                theme.dim(),
            ),
        ]);
        let notes_h = u16::from(!notes.is_empty());
        let [head, chart_area, note_area, table, readout] = Layout::vertical([
            Constraint::Length(1),
            Constraint::Min(5),
            Constraint::Length(notes_h),
            Constraint::Length(curves.len().min(6) as u16),
            Constraint::Length(2),
        ])
        .areas(area);
        frame.render_widget(Paragraph::new(header), head);
        frame.render_widget(
            Paragraph::new(Line::styled(notes.join("  "), theme.dim())),
            note_area,
        );
        let grid = self.grid(report);
        let cursor_x = grid.get(self.x).copied();
        draw_curves(frame, chart_area, theme, &curves, cursor_x, im);
        let longest = names.iter().map(|n| n.chars().count()).max().unwrap_or(0);
        let name_w = longest.clamp(8, (area.width as usize / 4).clamp(8, 28));
        // Below this width a row gives β without its interval (the readout has it).
        let wide = area.width >= 110;
        let rows: Vec<Line> = curves
            .iter()
            .enumerate()
            .skip(first)
            .take(6)
            .map(|(i, c)| {
                let row = Row {
                    selected: i == self.variant,
                    name: &names[i],
                    name_w,
                    wide,
                };
                variant_row(report, c, i, row, theme)
            })
            .collect();
        frame.render_widget(Paragraph::new(rows), table);
        let lines = curves
            .get(self.variant)
            .map_or_else(Vec::new, |c| readout_lines(c, cursor_x, im, theme));
        frame.render_widget(Paragraph::new(lines), readout);
    }
}

fn x_max(curves: &[&Curve]) -> f64 {
    curves
        .iter()
        .filter_map(|c| c.im_range.map(|r| r[1]))
        .chain(curves.iter().filter_map(|c| c.median_hi))
        .fold(1e-9, f64::max)
}

fn draw_curves(
    frame: &mut Frame,
    area: Rect,
    theme: Theme,
    curves: &[&Curve],
    cursor: Option<f64>,
    im: &str,
) {
    let top = 1.05 * x_max(curves);
    let samples = (area.width as usize * 2).max(8);
    let lines: Vec<Vec<(f64, f64)>> = curves
        .iter()
        .map(|c| {
            (1..=samples)
                .filter_map(|k| {
                    let x = top * k as f64 / samples as f64;
                    c.probability(x).map(|p| (x, p))
                })
                .collect()
        })
        .collect();
    let points: Vec<Vec<(f64, f64)>> = curves.iter().map(|c| data_points(c)).collect();
    let cursor_line: Vec<(f64, f64)> = cursor.map_or_else(Vec::new, |x| vec![(x, 0.0), (x, 1.0)]);
    let mut datasets: Vec<Dataset> = vec![
        Dataset::default()
            .marker(Marker::Braille)
            .graph_type(GraphType::Line)
            .style(theme.dim())
            .data(&cursor_line),
    ];
    for (i, (line, pts)) in lines.iter().zip(&points).enumerate() {
        datasets.push(
            Dataset::default()
                .marker(if theme.mono {
                    Marker::Dot
                } else {
                    Marker::Braille
                })
                .graph_type(GraphType::Line)
                .style(theme.series(i))
                .data(line),
        );
        datasets.push(
            Dataset::default()
                .marker(Marker::Block)
                .graph_type(GraphType::Scatter)
                .style(theme.series(i))
                .data(pts),
        );
    }
    let chart = Chart::new(datasets)
        .block(Block::default().borders(Borders::ALL))
        .legend_position(None)
        .x_axis(Axis::default().bounds([0.0, top]).labels([
            "0".to_string(),
            im.to_string(),
            fmt_num(top),
        ]))
        .y_axis(Axis::default().bounds([0.0, 1.0]).labels(["0", "P", "1"]));
    frame.render_widget(chart, area);
}

/// How a variant's row is laid out.
struct Row<'a> {
    selected: bool,
    /// The variant's own words (what all rows share is said once, above).
    name: &'a str,
    name_w: usize,
    /// β with its interval.
    wide: bool,
}

fn variant_row(
    report: &FragilityReport,
    c: &Curve,
    i: usize,
    Row {
        selected,
        name,
        name_w,
        wide,
    }: Row,
    theme: Theme,
) -> Line<'static> {
    let marker = if selected { "▶ " } else { "  " };
    let name = format!("{:<name_w$}", truncate(name, name_w));
    let mut spans = vec![
        Span::styled(marker, theme.key()),
        Span::styled(
            name,
            if selected {
                theme.selected()
            } else {
                theme.series(i)
            },
        ),
    ];
    if c.status == FitStatus::Fitted {
        // A median the data do not bracket is marked `!` (the readout says why).
        let mark = if c.extrapolation().is_some() { "!" } else { "" };
        spans.push(Span::raw(format!(
            "  {} {}{mark}  β {}",
            report.im_name(),
            with_interval(c.median, c.median_lo, c.median_hi),
            match wide {
                true => with_interval(c.beta, c.beta_lo, c.beta_hi),
                false => with_interval(c.beta, None, None),
            }
        )));
        if let Some(r) = report.ratio_of(c) {
            // Narrow: the ratio without its interval, so the row ends within the width
            // (the readout and fragility.csv have the interval).
            let ratio = match wide {
                true => with_interval(r.ratio, r.lo, r.hi),
                false => with_interval(r.ratio, None, None),
            };
            let cross = if r.curves_cross { ", crosses bare" } else { "" };
            spans.push(Span::styled(format!("  {ratio}× bare{cross}"), theme.ok()));
        }
    } else {
        spans.push(Span::styled(
            format!("  {}", c.status.explain()),
            theme.warn(),
        ));
    }
    Line::from(spans)
}

fn readout_lines(c: &Curve, x: Option<f64>, im: &str, theme: Theme) -> Vec<Line<'static>> {
    let mut first = format!("{}: ", summary::variant_name(c));
    if c.status == FitStatus::Fitted {
        let beta = with_interval(c.beta, c.beta_lo, c.beta_hi);
        first.push_str(&format!("β {beta}, "));
    }
    first.push_str(&format!("{} records", c.n_records));
    match c.method {
        Method::Stripes => first.push_str(&format!(", {} stripes", c.n_stripes)),
        Method::Ida => first.push_str(&format!(
            ", {} censored, {} resurrections",
            c.n_censored, c.resurrections
        )),
    }
    if c.bootstrap_degenerate > 0 {
        first.push_str(&format!(
            ", {} degenerate resamples",
            c.bootstrap_degenerate
        ));
    }
    let mut second = match x {
        Some(x) => format!("{im} = {}: ", fmt_num(x)),
        None => String::new(),
    };
    if let Some(x) = x {
        match c.probability(x) {
            Some(p) => second.push_str(&format!("fitted P = {:.3}", p)),
            None => second.push_str(c.status.explain()),
        }
        if let Some(p) = c.stripes.iter().find(|p| p.im == x) {
            second.push_str(&format!(", observed {}/{} reached", p.exceed, p.n));
        }
    }
    match c.extrapolation() {
        // The warning outranks the cursor's readout.
        Some(e) => vec![
            Line::raw(first),
            Line::styled(format!("! {}", e.explain()), theme.warn()),
        ],
        None => vec![Line::raw(first), Line::styled(second, theme.dim())],
    }
}
