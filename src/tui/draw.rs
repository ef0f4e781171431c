//! Drawing: a pure function of the app state. The frame is the tab bar, the current screen's
//! component, its dialog if any, the status line (message, prompt or key hints) and the help
//! overlay. Every screen fits 80×24; a smaller terminal gets fewer details and a notice line
//! saying so (what is cut, and to enlarge it), and below 40×10 only a notice.

use super::app::{App, Screen};
use super::components::help::EVERYWHERE;
use super::theme::Theme;
use super::widgets::{Hint, hint_spans_fit, truncate_left};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

pub const MIN_WIDTH: u16 = 40;
pub const MIN_HEIGHT: u16 = 10;
/// The size every screen is made for: below it a notice line says what is cut.
pub const FULL_WIDTH: u16 = 80;
pub const FULL_HEIGHT: u16 = 24;

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
    let notice = cut_notice(area.width, area.height);
    let [top, body, notice_row, status] = Layout::vertical([
        Constraint::Length(1),
        Constraint::Min(1),
        Constraint::Length(u16::from(notice.is_some())),
        Constraint::Length(1),
    ])
    .areas(area);
    draw_tabs(app, theme, frame, top);
    app.component(app.screen)
        .draw(&app.shared, theme, frame, body);
    // Questions (unsaved changes, stopping a sweep) show as a dialog over any screen.
    if let Some(prompt) = &app.prompt {
        prompt.draw_dialog(theme, frame, body);
    }
    if let Some(notice) = notice {
        frame.render_widget(
            Paragraph::new(Line::styled(notice, theme.warn())),
            notice_row,
        );
    }
    draw_status(app, theme, frame, status);
    let mut sections: Vec<(&str, &[_])> = vec![("everywhere", EVERYWHERE)];
    sections.extend(Screen::ALL.map(|screen| (screen.title(), app.component(screen).commands())));
    app.help.draw(theme, frame, area, &sections);
}

/// Below 80×24 (and from 40×10): the size, the remedy and what the size cuts, most important
/// first (a narrow terminal cuts the end of this line too).
fn cut_notice(width: u16, height: u16) -> Option<String> {
    let cut = match (width < FULL_WIDTH, height < FULL_HEIGHT) {
        (false, false) => return None,
        (true, false) => "long labels cut at the right",
        (false, true) => "fewer rows and smaller charts",
        (true, true) => "labels cut, fewer rows",
    };
    Some(format!(
        "{width}×{height} < {FULL_WIDTH}×{FULL_HEIGHT}: enlarge the terminal ({cut})"
    ))
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
    if let Some(run) = &app.runs.state
        && run.running()
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

/// Key hints: the prompt's, or the screen's (after the global ones unless the screen takes
/// every key).
fn hints(app: &App) -> Vec<Hint> {
    if let Some(prompt) = &app.prompt {
        return prompt.hints();
    }
    let component = app.component(app.screen);
    let own = component.hints(&app.shared);
    if component.captures_keys() {
        return own;
    }
    let mut keys = vec![("?", "help"), ("q", "quit")];
    keys.extend(own);
    keys
}

fn draw_status(app: &App, theme: Theme, frame: &mut Frame, area: Rect) {
    let line = if let Some((msg, error)) = &app.message {
        let style = if *error { theme.error() } else { theme.ok() };
        Line::styled(msg.clone(), style)
    } else if let Some(prompt) = &app.prompt {
        prompt.line(theme, area.width)
    } else {
        Line::from(hint_spans_fit(theme, &hints(app), area.width as usize))
    };
    frame.render_widget(Paragraph::new(line), area);
}
