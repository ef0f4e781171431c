//! Drawing: a pure function of the app state. Every screen fits 80×24; smaller terminals get
//! fewer details, and below 40×10 a notice.

use super::app::{
    App, Check, Prompt, ResultsTab, ResultsView, RunState, SceneState, Screen, field_help,
};
use super::theme::{self, Theme};
use crate::report::{self, OverturningMap, Quantity, Spectrum};
use crate::sim::History;
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Modifier, Style};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Block, Borders, Chart, Clear, Dataset, GraphType, Paragraph, Wrap};

pub const MIN_WIDTH: u16 = 40;
pub const MIN_HEIGHT: u16 = 10;

pub fn draw(app: &App, theme: Theme, frame: &mut Frame) {
    let area = frame.area();
    if area.width < MIN_WIDTH || area.height < MIN_HEIGHT {
        let text = vec![
            Line::styled("rocklab", theme.title()),
            Line::raw(format!(
                "terminal {}×{} is too small",
                area.width, area.height
            )),
            Line::raw(format!("need {MIN_WIDTH}×{MIN_HEIGHT}; q quits")),
        ];
        frame.render_widget(Paragraph::new(text).wrap(Wrap { trim: true }), area);
        return;
    }
    let [top, body, status] = Layout::vertical([
        Constraint::Length(1),
        Constraint::Min(1),
        Constraint::Length(1),
    ])
    .areas(area);
    draw_tabs(app, theme, frame, top);
    match app.screen {
        Screen::Study => draw_study(app, theme, frame, body),
        Screen::Run => draw_run(app, theme, frame, body),
        Screen::Results => draw_results(app, theme, frame, body),
        Screen::Scene => draw_scene(app, theme, frame, body),
    }
    draw_status(app, theme, frame, status);
    if app.help {
        draw_help(theme, frame, area);
    }
}

fn draw_tabs(app: &App, theme: Theme, frame: &mut Frame, area: Rect) {
    let mut spans = vec![Span::styled("rocklab ", theme.title())];
    for (i, s) in Screen::ALL.iter().enumerate() {
        let style = if *s == app.screen {
            theme.tab_active()
        } else {
            theme.base()
        };
        spans.push(Span::styled(format!(" {} {} ", i + 1, s.title()), style));
    }
    if app.is_running()
        && let Some(run) = &app.run
    {
        spans.push(Span::styled(
            format!(" ⟳ {}/{}", run.done, run.total),
            theme.warn(),
        ));
    }
    let used: usize = spans.iter().map(|s| s.width()).sum();
    let label = app.file_label();
    let room = (area.width as usize).saturating_sub(used + 2);
    if room > 3 {
        spans.push(Span::raw("  "));
        spans.push(Span::styled(truncate_left(&label, room), theme.dim()));
    }
    frame.render_widget(Paragraph::new(Line::from(spans)), area);
}

/// Key hints per screen; the most useful first, since narrow terminals cut the end.
fn hints(app: &App) -> Vec<(&'static str, &'static str)> {
    if let Some(prompt) = &app.prompt {
        return match prompt {
            Prompt::Discard(_) => vec![("y", "discard"), ("s", "save first"), ("n", "stay")],
            _ => vec![("Enter", "ok"), ("Esc", "cancel")],
        };
    }
    if app.editor.edit.is_some() && app.screen == Screen::Study {
        let enter = if app.editor.inserting {
            "add as a new element after this one"
        } else {
            "apply"
        };
        return vec![("Enter", enter), ("Esc", "cancel"), ("←→", "move")];
    }
    let mut keys = vec![("?", "help"), ("q", "quit")];
    keys.extend(match app.screen {
        Screen::Study => vec![
            ("↑↓", "move"),
            ("Enter", "edit"),
            ("/", "find"),
            ("a", "add"),
            ("d", "del/unset"),
            ("r", "run"),
            ("s", "save"),
            ("S", "save as"),
            ("o", "open"),
            ("n", "new"),
        ],
        Screen::Run => {
            if app.is_running() {
                vec![("c", "cancel")]
            } else {
                vec![("r", "run"), ("Enter", "results")]
            }
        }
        Screen::Results => vec![
            ("s/m/c", "spectra/maps/compare"),
            ("←→↑↓", "cursor"),
            ("[ ]", "quantity"),
            ("Enter", "scene"),
            ("w", "write results"),
        ],
        Screen::Scene => vec![("Esc", "back")],
    });
    keys
}

fn draw_status(app: &App, theme: Theme, frame: &mut Frame, area: Rect) {
    let line = if let Some((msg, error)) = &app.message {
        let style = if *error { theme.error() } else { theme.ok() };
        Line::styled(msg.clone(), style)
    } else if let Some(prompt) = &app.prompt {
        match prompt {
            Prompt::Discard(_) => {
                let mut spans = vec![Span::styled("Unsaved changes. ", theme.warn())];
                spans.extend(hint_spans(theme, &hints(app)));
                Line::from(spans)
            }
            Prompt::SaveAs(line)
            | Prompt::Open(line)
            | Prompt::Search(line)
            | Prompt::SaveResults(line) => {
                let label = match prompt {
                    Prompt::SaveAs(_) => "save study as: ",
                    Prompt::Open(_) => "open study: ",
                    Prompt::SaveResults(_) => "write results to: ",
                    _ => "find field: ",
                };
                let mut spans = vec![Span::styled(label, theme.key())];
                let room = (area.width as usize).saturating_sub(label.chars().count());
                spans.extend(edit_spans(theme, line, room));
                Line::from(spans)
            }
        }
    } else {
        Line::from(hint_spans(theme, &hints(app)))
    };
    frame.render_widget(Paragraph::new(line), area);
}

fn hint_spans(theme: Theme, keys: &[(&str, &str)]) -> Vec<Span<'static>> {
    let mut spans = Vec::new();
    for (i, (key, what)) in keys.iter().enumerate() {
        if i > 0 {
            spans.push(Span::raw("  "));
        }
        spans.push(Span::styled(key.to_string(), theme.key()));
        spans.push(Span::styled(format!(" {what}"), theme.dim()));
    }
    spans
}

/// The edited text with its cursor, scrolled sideways so the cursor stays within `width`.
fn edit_spans(theme: Theme, line: &super::edit::LineEdit, width: usize) -> Vec<Span<'static>> {
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

// ----- Study -----

fn draw_study(app: &App, theme: Theme, frame: &mut Frame, area: Rect) {
    let summary = study_summary(app, theme);
    let summary_height = (summary.len() as u16).min(area.height / 3).max(1);
    let edit_error = app.editor.edit_error.as_ref();
    let row_help = study_row_help(app);
    let [head, list, help, foot] = Layout::vertical([
        Constraint::Length(summary_height),
        Constraint::Min(1),
        Constraint::Length(if row_help.is_some() && area.height >= 16 {
            1
        } else {
            0
        }),
        Constraint::Length(if edit_error.is_some() { 2 } else { 0 }),
    ])
    .areas(area);
    if let Some(text) = row_help {
        frame.render_widget(Paragraph::new(Line::styled(text, theme.dim())), help);
    }
    frame.render_widget(Paragraph::new(summary).wrap(Wrap { trim: false }), head);
    let block = Block::default().borders(Borders::TOP).title(" study ");
    let inner = block.inner(list);
    frame.render_widget(block, list);

    let rows = &app.editor.rows;
    let height = inner.height as usize;
    let cursor = app.editor.cursor;
    let offset = scroll_offset(cursor, rows.len(), height);
    let label_width = rows
        .iter()
        .map(|r| r.depth * 2 + r.label.chars().count())
        .max()
        .unwrap_or(0)
        .min(inner.width as usize / 2);
    let mut lines = Vec::new();
    for (i, row) in rows.iter().enumerate().skip(offset).take(height) {
        let selected = i == cursor;
        let indent = "  ".repeat(row.depth);
        let label = format!("{indent}{}", row.label);
        let label = pad(&truncate(&label, label_width), label_width);
        let mut spans = vec![Span::styled(
            label,
            if selected {
                theme.selected()
            } else {
                theme.field()
            },
        )];
        spans.push(Span::raw(" "));
        let value_room = (inner.width as usize).saturating_sub(label_width + 1);
        match (&app.editor.edit, selected) {
            (Some(line), true) => spans.extend(edit_spans(theme, line, value_room)),
            _ => {
                let style = if row.leaf && row.absent.is_none() {
                    theme.value()
                } else {
                    theme.dim()
                };
                spans.push(Span::styled(truncate(&row.text, value_room), style));
            }
        }
        lines.push(Line::from(spans));
    }
    frame.render_widget(Paragraph::new(lines), inner);
    if let Some(err) = edit_error {
        frame.render_widget(
            Paragraph::new(Line::styled(format!("✗ {err}"), theme.error()))
                .wrap(Wrap { trim: true }),
            foot,
        );
    }
    if let Some(Prompt::Discard(_)) = &app.prompt {
        let text = vec![
            Line::raw("The study has unsaved changes."),
            Line::raw(""),
            Line::from(vec![
                Span::styled("y", theme.key()),
                Span::raw(" discard   "),
                Span::styled("s", theme.key()),
                Span::raw(" save first   "),
                Span::styled("n", theme.key()),
                Span::raw(" stay"),
            ]),
        ];
        popup(frame, theme, area, " unsaved changes ", text, 44, 5);
    }
}

/// Study parameters that take a value, a list or a range.
const GRID_FIELDS: &[&str] = &[
    "p",
    "size",
    "alpha",
    "mass",
    "r0",
    "xi",
    "omega_n",
    "omega_ratio",
    "sigma",
    "k_theta",
    "clutch_frequency_ratio",
    "cbar",
    "xi_theta",
    "friction",
    "eta",
    "play",
    "epsilon",
    "rho",
    "amplitude",
    "frequency",
    "scale",
];

/// One line about the selected field: what it means, and what a number can be.
fn study_row_help(app: &App) -> Option<String> {
    let row = app.editor.rows.get(app.editor.cursor)?;
    let help = field_help(&row.label)?;
    let mut text = format!("{}: {help}", row.label);
    if matches!(row.label.as_str(), "excitation" | "names") && !app.record_names.is_empty() {
        text.push_str(&format!("; records: {}", app.record_names.join(", ")));
    } else if GRID_FIELDS.contains(&row.label.as_str()) {
        text.push_str(
            "; a value 0.5, a list [0.5, 1.0] or a range (from: 1.0, to: 12.0, steps: 12)",
        );
    }
    Some(text)
}

fn study_summary(app: &App, theme: Theme) -> Vec<Line<'static>> {
    let mut lines = Vec::new();
    match &app.check {
        Check::Ok(points) => {
            let mut groups: Vec<&str> = Vec::new();
            for p in points.iter() {
                if !groups.contains(&p.group.as_str()) {
                    groups.push(&p.group);
                }
            }
            let mut spans = vec![
                Span::styled("✓ valid  ", theme.ok()),
                Span::styled(
                    format!("{}", points.len()),
                    theme.value().add_modifier(Modifier::BOLD),
                ),
                Span::raw(format!(
                    " scenes in {} variant{}",
                    groups.len(),
                    if groups.len() == 1 { "" } else { "s" }
                )),
            ];
            if !app.options.deterministic {
                let est = app
                    .estimated_seconds()
                    .map_or("estimating…".to_string(), |s| {
                        if s < 1.0 {
                            "< 1 s".to_string()
                        } else {
                            format!("≈ {}", fmt_duration(s))
                        }
                    });
                spans.push(Span::raw(format!("  run time {est}")));
            }
            lines.push(Line::from(spans));
        }
        Check::Invalid(msg) => {
            lines.push(Line::styled(format!("✗ {msg}"), theme.error()));
        }
    }
    lines
}

/// First row to show so that the cursor stays visible, with context above it.
fn scroll_offset(cursor: usize, len: usize, height: usize) -> usize {
    if height == 0 || len <= height {
        return 0;
    }
    cursor.saturating_sub(height / 2).min(len - height)
}

// ----- Run -----

fn draw_run(app: &App, theme: Theme, frame: &mut Frame, area: Rect) {
    let Some(run) = &app.run else {
        let text = match &app.check {
            Check::Ok(points) => format!(
                "No sweep yet. Press r to run the study ({} scenes).",
                points.len()
            ),
            Check::Invalid(msg) => format!("The study is invalid: {msg}"),
        };
        frame.render_widget(Paragraph::new(text).wrap(Wrap { trim: true }), area);
        return;
    };
    let mut lines = Vec::new();
    let state = match run.finished {
        None if run.cancel_requested => Span::styled("cancelling…", theme.warn()),
        None => Span::styled("running", theme.warn()),
        Some(true) => Span::styled("cancelled (finished scenes kept)", theme.warn()),
        Some(false) => Span::styled("finished", theme.ok()),
    };
    let bar_width = (area.width as usize).saturating_sub(44).clamp(5, 40);
    let failed = run.failed.len();
    lines.push(Line::from(vec![
        Span::styled(pad("overall", 14), theme.field()),
        Span::raw(" "),
        gauge(theme, run.done, run.total, bar_width),
        Span::raw(format!(" {:>5}/{:<5}", run.done, run.total)),
        Span::styled(
            format!(" {failed} failed"),
            if failed > 0 {
                theme.error()
            } else {
                theme.dim()
            },
        ),
    ]));
    lines.push(Line::from(vec![
        state,
        Span::raw("  "),
        Span::raw(timing(app, run)),
    ]));
    lines.push(Line::raw(""));
    for g in &run.groups {
        lines.push(Line::from(vec![
            Span::styled(pad(&truncate(&g.name, 14), 14), theme.field()),
            Span::raw(" "),
            gauge(theme, g.done, g.total, bar_width),
            Span::raw(format!(" {:>5}/{:<5}", g.done, g.total)),
            Span::styled(
                if g.failed > 0 {
                    format!(" {} failed", g.failed)
                } else {
                    String::new()
                },
                theme.error(),
            ),
        ]));
    }
    if failed > 0 {
        lines.push(Line::raw(""));
        lines.push(Line::styled("failures:", theme.error()));
        for &i in run.failed.iter() {
            let Some(p) = run.points.get(i) else { continue };
            let message = run
                .failure_messages
                .iter()
                .find(|(j, _)| *j == i)
                .map_or(String::new(), |(_, m)| format!(": {m}"));
            lines.push(Line::raw(format!(
                "  #{i} {} {}{message}",
                p.group,
                fmt_coords(&p.coords)
            )));
        }
    }
    frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), area);
}

fn timing(app: &App, run: &RunState) -> String {
    if app.options.deterministic {
        return String::new();
    }
    let elapsed = fmt_duration(run.elapsed.as_secs_f64());
    match (run.running(), run.rate_and_eta()) {
        (true, Some((rate, eta))) => {
            format!(
                "{elapsed} elapsed  {rate:.1} scenes/s  ETA {}",
                fmt_duration(eta)
            )
        }
        (false, Some((rate, _))) => format!("{elapsed}  {rate:.1} scenes/s"),
        _ => format!("{elapsed} elapsed"),
    }
}

fn gauge(theme: Theme, done: usize, total: usize, width: usize) -> Span<'static> {
    let filled = (done * width).checked_div(total).unwrap_or(0).min(width);
    Span::styled(
        format!("{}{}", "█".repeat(filled), "░".repeat(width - filled)),
        theme.ok(),
    )
}

// ----- Results -----

fn draw_results(app: &App, theme: Theme, frame: &mut Frame, area: Rect) {
    let Some(view) = &app.results else {
        frame.render_widget(
            Paragraph::new("No results yet. Press r to run the study.").wrap(Wrap { trim: true }),
            area,
        );
        return;
    };
    let [tabs, body] = Layout::vertical([Constraint::Length(1), Constraint::Min(1)]).areas(area);
    let mut spans = Vec::new();
    for (tab, key, name) in [
        (ResultsTab::Spectra, "s", "spectra"),
        (ResultsTab::Maps, "m", "maps"),
        (ResultsTab::Compare, "c", "compare"),
    ] {
        let style = if view.tab == tab {
            theme.tab_active()
        } else {
            theme.base()
        };
        spans.push(Span::styled(format!(" {key} {name} "), style));
    }
    if view.cancelled {
        spans.push(Span::styled("  partial: sweep cancelled", theme.warn()));
    }
    if view.results.study.as_ref().is_some_and(|s| *s != app.study) {
        spans.push(Span::styled(
            "  study edited since this run (r reruns)",
            theme.warn(),
        ));
    }
    frame.render_widget(Paragraph::new(Line::from(spans)), tabs);
    match view.tab {
        ResultsTab::Spectra => draw_spectra(view, theme, frame, body),
        ResultsTab::Maps => draw_map(view, theme, frame, body),
        ResultsTab::Compare => draw_compare(view, theme, frame, body),
    }
}

fn quantity_line(view: &ResultsView, theme: Theme) -> Line<'static> {
    let name = view
        .current_quantity()
        .map_or("no spectra", Quantity::label);
    Line::from(vec![
        Span::styled("[ ] ", theme.key()),
        Span::styled(name.to_string(), theme.title()),
        Span::styled(
            format!("  ({}/{})", view.quantity + 1, view.quantities.len().max(1)),
            theme.dim(),
        ),
    ])
}

/// Columns of a spectrum that fit `width`: each point gets `cell` columns, and when the
/// spectrum is longer than the room, a window that keeps the cursor in view.
struct Strip {
    first: usize,
    count: usize,
    cell: usize,
}

fn strip(n: usize, width: usize, cursor: usize) -> Strip {
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

/// Where and how tall spectrum bars are drawn.
#[derive(Clone, Copy)]
struct Bars<'a> {
    strip: &'a Strip,
    cursor: usize,
    height: usize,
    theme: Theme,
}

/// One spectrum as `height` rows of styled cells (top row first). One row uses the bars of
/// `report::sparkline`; taller blocks use eighth-blocks over the rows, scaled from 0 to the
/// spectrum's maximum. `×` marks a missing value (overturned or failed); the cursor column is
/// reversed.
fn bar_rows(values: &[Option<f64>], style: Style, layout: &Bars) -> Vec<Vec<Span<'static>>> {
    let Bars {
        strip: st,
        cursor,
        height,
        theme,
    } = *layout;
    const EIGHTHS: [char; 9] = [' ', '▁', '▂', '▃', '▄', '▅', '▆', '▇', '█'];
    let glyphs: Vec<char> = report::sparkline(values).chars().collect();
    let max = values.iter().flatten().copied().fold(0.0, f64::max);
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
            let glyph = match value {
                None if level == 0 => '×',
                None => ' ',
                Some(_) if height == 1 => glyphs.get(i).copied().unwrap_or(' '),
                Some(_) => EIGHTHS[eighths.saturating_sub(8 * level).min(8)],
            };
            let mut s = if value.is_none() {
                theme.overturned()
            } else {
                style
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
fn series_lines(
    label: Span<'static>,
    label_width: usize,
    values: &[Option<f64>],
    style: Style,
    layout: &Bars,
) -> Vec<Line<'static>> {
    let max = values.iter().flatten().copied().fold(f64::NAN, f64::max);
    let theme = layout.theme;
    bar_rows(values, style, layout)
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
                spans.push(Span::styled(format!(" max {}", fmt_num(max)), theme.dim()));
            }
            Line::from(spans)
        })
        .collect()
}

fn axis_line(xs: &[f64], st: &Strip, indent: usize, axis: &str) -> Line<'static> {
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
    Line::raw(format!(
        "{}{}  {axis}",
        " ".repeat(indent),
        cells.into_iter().collect::<String>()
    ))
}

/// Width of the variant names left of the bars: the longest name, within limits.
fn label_width(rows: &[&Spectrum], extra: usize, area: Rect) -> usize {
    let longest = rows
        .iter()
        .map(|s| s.label.chars().count() + extra)
        .max()
        .unwrap_or(0);
    longest.clamp(8, (area.width as usize / 3).max(8))
}

fn draw_spectra(view: &ResultsView, theme: Theme, frame: &mut Frame, area: Rect) {
    let rows = view.rows();
    let mut lines = vec![quantity_line(view, theme)];
    if rows.is_empty() {
        lines.push(Line::raw("no spectra in these results"));
        frame.render_widget(Paragraph::new(lines), area);
        return;
    }
    let n = rows.iter().map(|s| s.xs.len()).max().unwrap_or(0);
    let label_width = label_width(&rows, 0, area);
    let width = (area.width as usize).saturating_sub(label_width + 11);
    let st = strip(n, width, view.x);
    // Blocks that fit, up to 4 rows tall each; keep the selected one in view.
    let room = (area.height as usize).saturating_sub(5 + rows.len().min(4));
    let height = (room / rows.len()).clamp(1, 4);
    let visible = (room / height).max(1);
    let offset = scroll_offset(view.row, rows.len(), visible);
    for (i, s) in rows.iter().enumerate().skip(offset).take(visible) {
        let selected = i == view.row;
        let label = Span::styled(
            pad(&truncate(&s.label, label_width), label_width),
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
        };
        lines.extend(series_lines(label, label_width, &s.ys, style, &layout));
    }
    let axis = rows[0].axis.clone();
    lines.push(axis_line(&rows[0].xs, &st, label_width + 1, &axis));
    lines.push(Line::raw(""));
    let sel = rows[view.row.min(rows.len() - 1)];
    let at = sel.xs.get(view.x).copied();
    let value = sel.ys.get(view.x).copied().flatten();
    lines.push(Line::from(vec![
        Span::styled("cursor ", theme.dim()),
        Span::raw(format!(
            "{} = {}  {}: {}",
            sel.axis,
            at.map_or("–".into(), fmt_num),
            sel.label,
            value.map_or("overturned/failed".into(), fmt_num)
        )),
        Span::styled("  Enter: open scene", theme.dim()),
    ]));
    let values: Vec<String> = rows
        .iter()
        .map(|s| {
            let v = s.ys.get(view.x).copied().flatten();
            format!("{} {}", s.label, v.map_or("×".into(), fmt_num))
        })
        .collect();
    // Every variant's value at the cursor, when that fits in two lines.
    let all = values.join("  │  ");
    if all.chars().count() <= 2 * area.width as usize {
        lines.push(Line::styled(all, theme.base()));
    }
    frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), area);
}

fn draw_compare(view: &ResultsView, theme: Theme, frame: &mut Frame, area: Rect) {
    let rows = view.rows();
    let mut lines = vec![quantity_line(view, theme)];
    if rows.len() < 2 {
        lines.push(Line::raw("comparison needs two variants"));
        frame.render_widget(Paragraph::new(lines), area);
        return;
    }
    let a: &Spectrum = rows[view.cmp_a.min(rows.len() - 1)];
    let b: &Spectrum = rows[view.cmp_b.min(rows.len() - 1)];
    let ratio = report::compare(a, b);
    let n = a.xs.len().max(b.xs.len());
    let label_width = label_width(&[a, b], 2, area);
    let width = (area.width as usize).saturating_sub(label_width + 11);
    let st = strip(n, width, view.x);
    let height = ((area.height as usize).saturating_sub(10) / 3).clamp(1, 4);
    let layout = Bars {
        strip: &st,
        cursor: view.x,
        height,
        theme,
    };
    let block = |name: String, values: &[Option<f64>], style: Style| {
        let label = Span::styled(
            pad(&truncate(&name, label_width), label_width),
            theme.field(),
        );
        series_lines(label, label_width, values, style, &layout)
    };
    lines.extend(block(format!("A {}", a.label), &a.ys, theme.series(0)));
    lines.extend(block(format!("B {}", b.label), &b.ys, theme.series(1)));
    lines.extend(block("B/A".into(), &ratio, theme.warn()));
    lines.push(axis_line(&a.xs, &st, label_width + 1, &a.axis));
    lines.push(Line::raw(""));
    let at = |v: &[Option<f64>]| v.get(view.x).copied().flatten().map_or("–".into(), fmt_num);
    lines.push(Line::raw(format!(
        "{} = {}   A {}   B {}   B/A {}",
        a.axis,
        a.xs.get(view.x).map_or("–".into(), |x| fmt_num(*x)),
        at(&a.ys),
        at(&b.ys),
        at(&ratio)
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

fn draw_map(view: &ResultsView, theme: Theme, frame: &mut Frame, area: Rect) {
    let Some(map) = view.maps.get(view.map) else {
        frame.render_widget(Paragraph::new("no overturning maps in these results"), area);
        return;
    };
    let mut lines = vec![Line::from(vec![
        Span::styled("[ ] ", theme.key()),
        Span::styled(map.label.clone(), theme.title()),
        Span::styled(
            format!("  (map {}/{})", view.map + 1, view.maps.len()),
            theme.dim(),
        ),
    ])];
    let ylabel = 8;
    let (nx, ny) = (map.xs.len(), map.ys.len());
    let cell = ((area.width as usize).saturating_sub(ylabel + 12) / nx.max(1)).clamp(1, 6);
    let room_x = ((area.width as usize).saturating_sub(ylabel + 12) / cell).max(1);
    let (cx, cy) = view.cell;
    let first_x = cx.saturating_sub(room_x / 2).min(nx.saturating_sub(room_x));
    let count_x = room_x.min(nx);
    let room_y = (area.height as usize).saturating_sub(6).max(1);
    // Cells about square: two rows each when there is room.
    let cell_h = (room_y / ny.max(1)).clamp(1, 2);
    let count_y = (room_y / cell_h).min(ny);
    // Largest y on top: display row r shows iy = top - r.
    let top = (cy + count_y / 2)
        .min(ny.saturating_sub(1))
        .max(count_y.saturating_sub(1));
    lines.push(Line::styled(map.y_axis.clone(), theme.dim()));
    for r in 0..count_y * cell_h {
        let iy = top - r / cell_h;
        let label = if r % cell_h == 0 {
            format!("{:>7} ", fmt_num(map.ys[iy]))
        } else {
            " ".repeat(8)
        };
        let mut spans = vec![Span::styled(label, theme.dim())];
        for ix in first_x..first_x + count_x {
            let (glyph, style) = map_cell(map, ix, iy, theme);
            let style = if (ix, iy) == (cx, cy) {
                style.add_modifier(Modifier::REVERSED)
            } else {
                style
            };
            spans.push(Span::styled(glyph.repeat(cell), style));
        }
        lines.push(Line::from(spans));
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
        Span::raw(" failed"),
    ]));
    let state = match map.cells.get(cy).and_then(|r| r.get(cx)) {
        Some(Some(true)) => "overturned",
        Some(Some(false)) => "safe",
        Some(None) => "failed",
        None => "–",
    };
    lines.push(Line::raw(format!(
        "{} = {}  {} = {}: {state}",
        map.x_axis,
        map.xs.get(cx).map_or("–".into(), |v| fmt_num(*v)),
        map.y_axis,
        map.ys.get(cy).map_or("–".into(), |v| fmt_num(*v)),
    )));
    frame.render_widget(Paragraph::new(lines), area);
}

fn map_cell(map: &OverturningMap, ix: usize, iy: usize, theme: Theme) -> (&'static str, Style) {
    match map.cells.get(iy).and_then(|r| r.get(ix)) {
        Some(Some(true)) => (theme::CELL_OVERTURNED, theme.overturned()),
        Some(Some(false)) => (theme::CELL_SAFE, theme.safe()),
        Some(None) => (theme::CELL_FAILED, theme.failed()),
        None => (theme::CELL_MISSING, theme.base()),
    }
}

// ----- Scene -----

fn draw_scene(app: &App, theme: Theme, frame: &mut Frame, area: Rect) {
    let Some(view) = &app.scene else {
        frame.render_widget(
            Paragraph::new(
                "No scene open. On the Results screen, put the cursor on a point of a spectrum or a map cell and press Enter.",
            )
            .wrap(Wrap { trim: true }),
            area,
        );
        return;
    };
    let [head, body] = Layout::vertical([Constraint::Length(2), Constraint::Min(1)]).areas(area);
    let mut lines = vec![Line::from(vec![
        Span::styled(view.point.group.clone(), theme.title()),
        Span::raw(format!("  {}", fmt_coords(&view.point.coords))),
    ])];
    match &view.state {
        SceneState::Running(_) => lines.push(Line::styled("simulating…", theme.warn())),
        SceneState::Failed(e) => lines.push(Line::styled(format!("failed: {e}"), theme.error())),
        SceneState::Done(r, _) => {
            let mut text = format!(
                "{}  θmax/α {}  impacts {}  engagements {}",
                if r.overturned { "OVERTURNED" } else { "safe" },
                fmt_num(r.peak_rotation_ratio),
                r.counters.impacts,
                r.counters.engagements,
            );
            // The energy residual is at the level of the solver tolerance: it changes with
            // any change to the integrator, so reproducible frames leave it out.
            if !app.options.deterministic {
                text.push_str(&format!("  energy residual {:.1e}", r.energy_residual));
            }
            lines.push(Line::raw(text));
        }
    }
    frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: true }), head);
    if let SceneState::Done(_, history) = &view.state {
        draw_histories(history, theme, frame, body);
    }
}

/// One chart: title and (legend name, history column) of each series.
struct Panel {
    title: String,
    series: Vec<(String, &'static str)>,
}

/// The charts of a scene, from the columns its model records: rotation (and the column
/// deformation of a flexible structure), flywheel velocities, clutch forces, and every
/// energy term.
fn panels(history: &History) -> [Panel; 4] {
    let has = |c: &str| history.columns.contains(&c);
    let mut rotation = Panel {
        title: "rotation θ (rad)".into(),
        series: vec![("θ".into(), "theta")],
    };
    if has("u") {
        rotation.title = "rotation θ (rad), deformation u (m)".into();
        rotation.series.push(("u".into(), "u"));
    }
    let pair = |title: &str, a: &'static str, b: &'static str| Panel {
        title: title.into(),
        series: vec![("a".into(), a), ("b".into(), b)],
    };
    let energy = Panel {
        title: "energy (J)".into(),
        series: history
            .columns
            .iter()
            .filter_map(|c| Some((c.strip_prefix("e_")?.replace('_', " "), *c)))
            .collect(),
    };
    [
        rotation,
        pair("flywheel velocities", "flywheel_a_vel", "flywheel_b_vel"),
        pair("clutch force (N)", "clutch_force_a", "clutch_force_b"),
        energy,
    ]
}

fn draw_histories(history: &History, theme: Theme, frame: &mut Frame, area: Rect) {
    let [top, bottom] =
        Layout::vertical([Constraint::Percentage(50), Constraint::Percentage(50)]).areas(area);
    let [a, b] =
        Layout::horizontal([Constraint::Percentage(50), Constraint::Percentage(50)]).areas(top);
    let [c, d] =
        Layout::horizontal([Constraint::Percentage(50), Constraint::Percentage(50)]).areas(bottom);
    let t = history.column("t").unwrap_or_default();
    for (panel, rect) in panels(history).iter().zip([a, b, c, d]) {
        draw_chart(panel, &t, history, theme, frame, rect);
    }
}

fn draw_chart(
    panel: &Panel,
    t: &[f64],
    history: &History,
    theme: Theme,
    frame: &mut Frame,
    area: Rect,
) {
    let title = &panel.title;
    let points = (area.width as usize * 2).max(2);
    let series: Vec<(&str, Vec<(f64, f64)>)> = panel
        .series
        .iter()
        .filter_map(|(name, col)| {
            Some((name.as_str(), downsample(t, &history.column(col)?, points)))
        })
        .collect();
    let block = Block::default()
        .borders(Borders::ALL)
        .title(format!(" {title} "));
    if series.is_empty() || t.is_empty() {
        frame.render_widget(Paragraph::new("not recorded").block(block), area);
        return;
    }
    let (t0, t1) = (t[0], *t.last().unwrap_or(&t[0]));
    let (lo, hi) = series
        .iter()
        .flat_map(|(_, s)| s.iter().map(|p| p.1))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    let (lo, hi) = if hi > lo {
        (lo, hi)
    } else {
        (lo - 1.0, hi + 1.0)
    };
    let markers = [Marker::Braille, Marker::Dot, Marker::Block, Marker::Bar];
    let datasets = series
        .iter()
        .enumerate()
        .map(|(i, (name, data))| {
            Dataset::default()
                .name(*name)
                .marker(if theme.mono {
                    markers[i % markers.len()]
                } else {
                    Marker::Braille
                })
                .graph_type(GraphType::Line)
                .style(theme.series(i))
                .data(data)
        })
        .collect();
    let chart = Chart::new(datasets)
        .block(block)
        .x_axis(
            Axis::default()
                .bounds([t0, t1.max(t0 + 1e-9)])
                .labels([fmt_num(t0), format!("{} s", fmt_num(t1))]),
        )
        .y_axis(
            Axis::default()
                .bounds([lo, hi])
                .labels([fmt_num(lo), fmt_num(hi)]),
        );
    frame.render_widget(chart, area);
}

/// About `n` points: the extremes of the samples in each of n/2 equal time windows, placed at
/// the window's centre, so peaks stay visible and the picture depends on the trajectory, not on
/// where the integrator happened to step.
fn downsample(t: &[f64], v: &[f64], n: usize) -> Vec<(f64, f64)> {
    let len = t.len().min(v.len());
    if len <= n {
        return (0..len).map(|i| (t[i], v[i])).collect();
    }
    let buckets = (n / 2).max(1);
    let (t0, t1) = (t[0], t[len - 1]);
    let width = (t1 - t0) / buckets as f64;
    let mut out = Vec::with_capacity(n);
    let mut i = 0;
    for k in 0..buckets {
        let end = if k + 1 == buckets {
            f64::INFINITY
        } else {
            t0 + (k + 1) as f64 * width
        };
        let start = i;
        while i < len && t[i] < end {
            i += 1;
        }
        if i == start {
            continue;
        }
        let window = &v[start..i];
        let (imin, imax) = (0..window.len()).fold((0, 0), |(lo, hi), j| {
            (
                if window[j] < window[lo] { j } else { lo },
                if window[j] > window[hi] { j } else { hi },
            )
        });
        let centre = t0 + (k as f64 + 0.5) * width;
        let (first, second) = if imin <= imax {
            (imin, imax)
        } else {
            (imax, imin)
        };
        out.push((centre, window[first]));
        if second != first {
            out.push((centre, window[second]));
        }
    }
    out
}

// ----- help -----

fn draw_help(theme: Theme, frame: &mut Frame, area: Rect) {
    let k = |key: &'static str, what: &'static str| {
        Line::from(vec![
            Span::styled(format!("{key:>10}  "), theme.key()),
            Span::raw(what),
        ])
    };
    let h = |title: &'static str| Line::styled(title, theme.title());
    let lines = vec![
        h("everywhere"),
        k("1 2 3 4", "Study / Run / Results / Scene (Tab cycles)"),
        k("r", "run the study in the background"),
        k("?", "this help (any key closes it)"),
        k("q  Ctrl-C", "quit (asks if there are unsaved changes)"),
        h("Study"),
        k("↑↓ PgUp/Dn", "move; g/G first/last row; / find a field"),
        k(
            "Enter / e",
            "edit the value (RON: 0.5, [1.0, 2.0], name(…))",
        ),
        k(
            "a / d",
            "add from a copy / delete list element; unset a field",
        ),
        k("s S o n", "save, save as, open, new from default"),
        h("Run"),
        k("c / Esc", "cancel (finished scenes are kept)"),
        k("Enter", "results"),
        h("Results"),
        k("s m c", "spectra / overturning maps / compare A and B"),
        k("←→ ↑↓", "cursor along the axis / variant or map cell"),
        k("[ ]", "previous / next quantity or map"),
        k("a b x", "compare: next A, next B, swap"),
        k("Enter", "open the scene under the cursor"),
        k("w", "write the results file (JSON) for rocklab plot"),
        h("Scene"),
        k("Esc", "back to results"),
    ];
    popup(frame, theme, area, " help (any key closes) ", lines, 66, 22);
}

fn popup(
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

// ----- text helpers -----

pub fn fmt_num(v: f64) -> String {
    if !v.is_finite() {
        return "–".into();
    }
    let a = v.abs();
    if a != 0.0 && !(0.01..10_000.0).contains(&a) {
        format!("{v:.2e}")
    } else {
        let decimals = if a >= 100.0 {
            0
        } else if a >= 10.0 {
            1
        } else {
            3
        };
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    }
}

fn fmt_duration(s: f64) -> String {
    if s < 1.0 {
        "< 1 s".into()
    } else if s < 60.0 {
        format!("{s:.0} s")
    } else if s < 3600.0 {
        format!("{:.0} min {:.0} s", (s / 60.0).floor(), s % 60.0)
    } else {
        format!("{:.1} h", s / 3600.0)
    }
}

fn fmt_coords(coords: &[(String, f64)]) -> String {
    coords
        .iter()
        .map(|(k, v)| format!("{k}={}", fmt_num(*v)))
        .collect::<Vec<_>>()
        .join(" ")
}

fn truncate(s: &str, width: usize) -> String {
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

fn truncate_left(s: &str, width: usize) -> String {
    let n = s.chars().count();
    if n <= width {
        s.to_string()
    } else {
        let mut t = String::from("…");
        t.extend(s.chars().skip(n - width + 1));
        t
    }
}

fn pad(s: &str, width: usize) -> String {
    let n = s.chars().count();
    format!("{s}{}", " ".repeat(width.saturating_sub(n)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn downsampling_keeps_every_window_extreme_and_ignores_step_placement() {
        // A spike at t = 0.503 in a 0..1 s signal sampled finely, two ways.
        let spike = |t: f64| {
            if (t - 0.503).abs() < 1e-3 {
                5.0
            } else {
                t.sin()
            }
        };
        let fine: Vec<f64> = (0..=10_000).map(|i| i as f64 * 1e-4).collect();
        let shifted: Vec<f64> = (0..=9_001)
            .map(|i| (i as f64 * 1.111e-4).min(1.0))
            .collect();
        let a = downsample(
            &fine,
            &fine.iter().map(|&t| spike(t)).collect::<Vec<_>>(),
            100,
        );
        let b = downsample(
            &shifted,
            &shifted.iter().map(|&t| spike(t)).collect::<Vec<_>>(),
            100,
        );
        assert!(a.len() <= 100 && b.len() <= 100);
        let peak = |s: &[(f64, f64)]| s.iter().map(|p| p.1).fold(f64::MIN, f64::max);
        assert_eq!(peak(&a), 5.0);
        assert_eq!(peak(&b), 5.0);
        // Same windows, same centres: the two samplings put the spike at the same time.
        let at = |s: &[(f64, f64)]| s.iter().find(|p| p.1 == 5.0).unwrap().0;
        assert_eq!(at(&a), at(&b));
        // Short histories pass through untouched.
        assert_eq!(
            downsample(&[0.0, 1.0], &[2.0, 3.0], 10),
            vec![(0.0, 2.0), (1.0, 3.0)]
        );
    }

    #[test]
    fn a_long_edit_scrolls_to_keep_the_cursor_in_view() {
        let shown = |line: &super::super::edit::LineEdit| -> String {
            edit_spans(Theme::MONO, line, 10)
                .iter()
                .map(|s| s.content.to_string())
                .collect()
        };
        let mut line = super::super::edit::LineEdit::new("[1.0, 2.0, 3.0, 4.0]");
        assert_eq!(shown(&line), "3.0, 4.0] ");
        line.cursor = 0;
        assert_eq!(shown(&line), "[1.0, 2.0,");
        line.cursor = 5;
        assert_eq!(shown(&line), "[1.0, 2.0,");
    }

    #[test]
    fn numbers_read_well_at_every_magnitude() {
        assert_eq!(fmt_num(0.0), "0");
        assert_eq!(fmt_num(0.5), "0.5");
        assert_eq!(fmt_num(12.34), "12.3");
        assert_eq!(fmt_num(1234.0), "1234");
        assert_eq!(fmt_num(1e-5), "1.00e-5");
        assert_eq!(fmt_num(f64::NAN), "–");
    }
}
