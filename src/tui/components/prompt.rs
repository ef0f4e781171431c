//! The status-line prompts (file names, search text) and the unsaved-changes question. The
//! app decides what a committed prompt does; this draws them and names their keys.

use super::super::edit::LineEdit;
use super::super::theme::Theme;
use super::super::widgets::{Hint, edit_spans, hint_spans, popup, truncate_left};
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use std::path::PathBuf;

pub enum Prompt {
    SaveAs(LineEdit),
    Open(LineEdit),
    /// Jump to the next row whose name contains the text.
    Search(LineEdit),
    /// The output directory of the next run.
    OutDir(LineEdit),
    /// Write the results on screen as a results file (JSON, as `rocklab run` writes).
    SaveResults(LineEdit),
    /// Unsaved changes would be lost by `then`: y to go on, s to save first, n/Esc to stay.
    Discard(Pending),
    /// A running sweep would stop (to quit, or cancelled): Enter/y stops it keeping its
    /// finished scenes (journalled, a later `r` resumes), n/Esc lets it run.
    StopSweep(StopSweep),
}

#[derive(Clone, Debug)]
pub struct StopSweep {
    /// Quit the workbench after stopping (else only cancel the sweep).
    pub quit: bool,
    pub done: usize,
    pub total: usize,
    pub out_dir: PathBuf,
}

/// Something that would lose unsaved changes.
#[derive(Clone, Debug)]
pub enum Pending {
    Quit,
    Open(PathBuf),
    New,
}

impl Prompt {
    pub fn hints(&self) -> Vec<Hint> {
        match self {
            Prompt::Discard(_) => vec![("y", "discard"), ("s", "save first"), ("n", "stay")],
            Prompt::StopSweep(stop) if stop.quit => {
                vec![
                    ("Enter", "keep finished scenes, quit"),
                    ("n", "keep running"),
                ]
            }
            Prompt::StopSweep(_) => {
                vec![
                    ("Enter", "keep finished scenes, stop"),
                    ("n", "keep running"),
                ]
            }
            _ => vec![("Enter", "ok"), ("Esc", "cancel")],
        }
    }

    /// The status line while the prompt is open.
    pub fn line(&self, theme: Theme, width: u16) -> Line<'static> {
        let (label, line) = match self {
            Prompt::Discard(_) => {
                let mut spans = vec![Span::styled("Unsaved changes. ", theme.warn())];
                spans.extend(hint_spans(theme, &self.hints()));
                return Line::from(spans);
            }
            Prompt::StopSweep(_) => {
                let mut spans = vec![Span::styled("Sweep running. ", theme.warn())];
                spans.extend(hint_spans(theme, &self.hints()));
                return Line::from(spans);
            }
            Prompt::SaveAs(line) => ("save study as: ", line),
            Prompt::Open(line) => ("open study or results: ", line),
            Prompt::SaveResults(line) => ("write results to: ", line),
            Prompt::OutDir(line) => ("results directory: ", line),
            Prompt::Search(line) => ("find field: ", line),
        };
        let mut spans = vec![Span::styled(label, theme.key())];
        let room = (width as usize).saturating_sub(label.chars().count());
        spans.extend(edit_spans(theme, line, room));
        Line::from(spans)
    }

    /// The questions (unsaved changes, stopping a sweep) as a dialog over `area`, on any
    /// screen (other prompts live on the status line only).
    pub fn draw_dialog(&self, theme: Theme, frame: &mut Frame, area: Rect) {
        if let Prompt::StopSweep(stop) = self {
            let verb = if stop.quit { "quit" } else { "stop" };
            let text = vec![
                Line::raw(format!(
                    "A sweep is running: {}/{} scenes done.",
                    stop.done, stop.total
                )),
                Line::raw("Finished scenes are kept in"),
                Line::raw(format!(
                    "  {}/",
                    truncate_left(&stop.out_dir.display().to_string(), 45)
                )),
                Line::raw("and r resumes the sweep from them later."),
                Line::raw(""),
                Line::from(vec![
                    Span::styled("Enter", theme.key()),
                    Span::raw(format!(" keep finished scenes and {verb}")),
                ]),
                Line::from(vec![
                    Span::styled("n", theme.key()),
                    Span::raw("/"),
                    Span::styled("Esc", theme.key()),
                    Span::raw(" keep running"),
                ]),
            ];
            let height = text.len() as u16;
            popup(frame, theme, area, " stop the sweep? ", text, 50, height);
            return;
        }
        if !matches!(self, Prompt::Discard(_)) {
            return;
        }
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
