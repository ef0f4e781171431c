//! The status-line prompts (file names, search text) and the unsaved-changes question. The
//! app decides what a committed prompt does; this draws them and names their keys.

use super::super::edit::LineEdit;
use super::super::theme::Theme;
use super::super::widgets::{Hint, edit_spans, hint_spans, popup, truncate, truncate_left};
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
    /// finished scenes (journalled, a later `r` resumes), d stops it discarding what is only
    /// in memory (see [`StopSweep`]), n/Esc lets it run.
    StopSweep(StopSweep),
    /// Saving the study would drop comments of the file it came from: y saves anyway (the
    /// file as it was is kept as `<file>.bak`), n/Esc does not save.
    DropComments(DropComments),
    /// `w` would overwrite a results file (of this study or, worse, of another): y
    /// overwrites, n/Esc does not write.
    OverwriteResults(OverwriteResults),
}

#[derive(Clone, Debug)]
pub struct DropComments {
    pub path: PathBuf,
    /// The comments that cannot be placed (their field is gone).
    pub lost: Vec<String>,
}

#[derive(Clone, Debug)]
pub struct OverwriteResults {
    pub path: PathBuf,
    /// Scenes in the file there now.
    pub scenes: Option<usize>,
    /// The name of the study the file there belongs to, if not the study on screen.
    pub other_study: Option<String>,
}

/// `<file>.bak`: where a file's previous text is kept before a save drops part of it.
pub fn backup_path(path: &std::path::Path) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push(".bak");
    PathBuf::from(name)
}

/// Stopping a running sweep. The answers: keep (the default) stops it and shows its finished
/// scenes; discard stops it and throws away what exists only in memory: to quit, the unsaved
/// study edits (no second question); to cancel, its partial results (not shown). Either way
/// the scenes already finished stay in the output directory's journal, where `r` and
/// `rocklab run` find them; only `rocklab run --fresh` recomputes them.
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
                    ("d", "discard"),
                    ("n", "keep running"),
                ]
            }
            Prompt::StopSweep(_) => {
                vec![
                    ("Enter", "keep finished scenes, stop"),
                    ("d", "discard"),
                    ("n", "keep running"),
                ]
            }
            Prompt::DropComments(_) => vec![("y", "save, keep .bak"), ("n", "do not save")],
            Prompt::OverwriteResults(_) => vec![("y", "overwrite"), ("n", "do not write")],
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
            Prompt::DropComments(_) | Prompt::OverwriteResults(_) => {
                let mut spans = vec![Span::styled("Confirm. ", theme.warn())];
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
        let key_line = |key: &'static str, text: String| {
            Line::from(vec![Span::styled(key, theme.key()), Span::raw(text)])
        };
        if let Prompt::DropComments(drop) = self {
            let n = drop.lost.len();
            let mut text = vec![
                Line::raw(format!(
                    "{n} comment{} of the study file belong{} to",
                    if n == 1 { "" } else { "s" },
                    if n == 1 { "s" } else { "" }
                )),
                Line::raw("fields that are gone, and cannot be kept:"),
            ];
            for comment in drop.lost.iter().take(2) {
                text.push(Line::styled(
                    format!("  {}", truncate(comment, 50)),
                    theme.dim(),
                ));
            }
            if n > 2 {
                text.push(Line::styled(format!("  … and {} more", n - 2), theme.dim()));
            }
            let file = drop.path.file_name().map_or_else(
                || drop.path.display().to_string(),
                |f| f.to_string_lossy().into_owned(),
            );
            text.push(Line::raw(format!(
                "The file as it was is kept as {}.",
                truncate(&format!("{file}.bak"), 24)
            )));
            text.push(Line::raw(""));
            text.push(key_line("y", " save without them, keep the .bak".into()));
            text.push(key_line("n", "/Esc do not save".into()));
            let height = text.len() as u16;
            popup(frame, theme, area, " drop comments? ", text, 56, height);
            return;
        }
        if let Prompt::OverwriteResults(over) = self {
            let what = match (&over.other_study, over.scenes) {
                (Some(name), _) => format!("results of ANOTHER study ({})", truncate(name, 20)),
                (None, Some(n)) => format!("results of this study ({n} scenes)"),
                (None, None) => "a file".to_string(),
            };
            let text = vec![
                Line::raw(truncate_left(&over.path.display().to_string(), 54)),
                Line::raw(format!("holds {what}.")),
                Line::raw(""),
                key_line("y", " overwrite it".into()),
                key_line("n", "/Esc do not write".into()),
            ];
            let height = text.len() as u16;
            let title = if over.other_study.is_some() {
                " overwrite another study's results? "
            } else {
                " overwrite results? "
            };
            popup(frame, theme, area, title, text, 56, height);
            return;
        }
        if let Prompt::StopSweep(stop) = self {
            let verb = if stop.quit { "quit" } else { "stop" };
            let discard = if stop.quit {
                " quit, drop unsaved study edits"
            } else {
                " stop, do not show its results"
            };
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
                key_line("d", format!("     discard:{discard}")),
                Line::raw("      (scenes already finished stay on disk)"),
                Line::from(vec![
                    Span::styled("n", theme.key()),
                    Span::raw("/"),
                    Span::styled("Esc", theme.key()),
                    Span::raw(" keep running"),
                ]),
            ];
            let height = text.len() as u16;
            popup(frame, theme, area, " stop the sweep? ", text, 54, height);
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
