//! The Study screen: the study as a tree of rows, edited in place as RON. An edit is parsed
//! and expanded once by the study's own code; a refused edit keeps the editor open with the
//! parser's message. Help and the unset optional fields come from `study::fields`.

use super::super::edit::{EditOutcome, LineEdit};
use super::super::theme::Theme;
pub use super::super::tree::Row;
use super::super::tree::StudyTree;
use super::super::widgets::{Hint, edit_spans, fmt_duration, pad, scroll_offset, truncate};
use super::prompt::{Pending, Prompt};
use super::{Action, Check, Command, Component, EXPAND_AT_ONCE, Shared, command};
use crate::study::Study;
use crate::study::fields;
use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Modifier;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph, Wrap};

pub struct StudyScreen {
    /// The study's text as a tree: what the rows show and an edit changes.
    pub tree: StudyTree,
    pub rows: Vec<Row>,
    pub cursor: usize,
    pub edit: Option<LineEdit>,
    /// Why the last edit was refused (parse error), shown under the editor.
    pub edit_error: Option<String>,
    /// The edit is a new list element, to go after the selected one (`a`).
    pub inserting: bool,
    /// Where the cursor goes once the edited study is back: the item edited or added.
    cursor_to: Option<Vec<usize>>,
    /// The last `/` search, for `n` / `N` (next / previous match, as in vim and less).
    last_search: Option<String>,
}

impl StudyScreen {
    /// The screen on `study`, as `text` (its file) writes it.
    pub fn new(study: &Study, text: Option<&str>) -> Self {
        let mut screen = StudyScreen {
            tree: StudyTree::new(study, None),
            rows: Vec::new(),
            cursor: 0,
            edit: None,
            edit_error: None,
            inserting: false,
            cursor_to: None,
            last_search: None,
        };
        screen.study_changed(study, text);
        screen
    }

    /// Rebuild the rows from a new study as `text` writes it (the file it was read from, or
    /// the text of the edit that made it), keeping the cursor on the same row if it still
    /// exists, or moving it onto the item the last edit changed or added.
    pub fn study_changed(&mut self, study: &Study, text: Option<&str>) {
        let keep = self
            .rows
            .get(self.cursor)
            .map(|r| (r.path.clone(), r.absent.clone()));
        let target = self.cursor_to.take().map(|path| (path, None));
        self.tree = StudyTree::new(study, text);
        self.rows = self.tree.rows();
        self.cursor = self.cursor.min(self.rows.len().saturating_sub(1));
        for (path, absent) in [keep, target].into_iter().flatten() {
            if let Some(i) = self
                .rows
                .iter()
                .position(|r| r.path == path && r.absent == absent)
            {
                self.cursor = i;
            }
        }
    }

    /// Move to the next row (after the cursor, wrapping) whose label contains `text`.
    pub fn search(&mut self, text: &str) -> Action {
        self.last_search = Some(text.to_string());
        self.find(text, true)
    }

    /// `n` / `N`: the next / previous match of the last search.
    fn search_again(&mut self, forward: bool) -> Action {
        match self.last_search.clone() {
            Some(text) => self.find(&text, forward),
            None => Action::Complain("no search yet: / finds a field".into()),
        }
    }

    fn find(&mut self, text: &str, forward: bool) -> Action {
        let needle = text.trim().to_lowercase();
        let rows = &self.rows;
        let n = rows.len();
        let cursor = self.cursor;
        // An exact name first, then any name containing the text.
        let order = || {
            (1..=n).map(move |k| {
                if forward {
                    (cursor + k) % n.max(1)
                } else {
                    (cursor + n - k % n.max(1)) % n.max(1)
                }
            })
        };
        let found = order()
            .find(|&i| rows[i].label.to_lowercase() == needle)
            .or_else(|| order().find(|&i| rows[i].label.to_lowercase().contains(&needle)));
        match found {
            Some(i) if !needle.is_empty() => {
                self.cursor = i;
                Action::None
            }
            _ => Action::Complain(format!("no field named like \"{}\"", text.trim())),
        }
    }

    fn edit_key(&mut self, key: KeyEvent) -> Action {
        let Some(line) = self.edit.as_mut() else {
            return Action::None;
        };
        match line.handle_key(key) {
            EditOutcome::Editing => Action::None,
            EditOutcome::Cancel => {
                self.edit = None;
                self.edit_error = None;
                self.inserting = false;
                Action::None
            }
            EditOutcome::Commit => {
                let text = line.text.clone();
                let Some(row) = self.rows.get(self.cursor) else {
                    return Action::None;
                };
                let mut said = None;
                let (doc, target) = match &row.absent {
                    None if self.inserting => {
                        let mut next = row.path.clone();
                        if let Some(last) = next.last_mut() {
                            *last += 1;
                        }
                        (self.tree.inserted_after(&row.path, &text), next)
                    }
                    Some(field) => {
                        let (doc, at, replaced) = self.tree.added(&row.path, field, &text);
                        said = replaced.map(|other| format!("{field} set in place of {other}"));
                        (doc, at)
                    }
                    None => (self.tree.replaced(&row.path, &text), row.path.clone()),
                };
                let mut action = self.apply_document(doc, true);
                if let Action::StudyEdited { note, .. } = &mut action {
                    self.cursor_to = Some(target);
                    if said.is_some() {
                        *note = said;
                    }
                }
                action
            }
        }
    }

    /// Parse an edited document with the study's own parser, validating it by expanding it
    /// (once: the scenes go to the app with the study). A refused edit says why: under the
    /// editor, or on the status line for edits without one (deletions).
    fn apply_document(&mut self, doc: String, from_editor: bool) -> Action {
        // A large study's expansion (seconds at 300 000 scenes) is left to the background:
        // its layout (cheap) is checked here, the scenes by the app's worker.
        let checked = match Study::parse_ron(&doc, "edit") {
            Ok(mut study) => match study.layout().map(|l| l.len()) {
                Ok(n) if n > EXPAND_AT_ONCE => Ok((study, None, doc, None)),
                _ => match study.expand() {
                    Ok(points) => Ok((study, Some(points), doc, None)),
                    Err(e) => {
                        // An excitation of another kind: the fields that depend on it follow,
                        // by the library's rule (study/follow.rs), and the note says what
                        // changed.
                        let notes = study.follow_excitation();
                        match study.expand() {
                            Ok(points) if !notes.is_empty() => {
                                let text = study.to_ron_keeping(Some(&doc)).text;
                                Ok((study, Some(points), text, Some(notes.join(", "))))
                            }
                            _ => Err(e.located(&doc, "edit")),
                        }
                    }
                },
            },
            Err(e) => Err(e),
        };
        match checked {
            Ok((study, points, text, note)) => {
                self.edit = None;
                self.edit_error = None;
                self.inserting = false;
                Action::StudyEdited {
                    study: Box::new(study),
                    points,
                    text,
                    note,
                }
            }
            Err(e) => {
                let msg = strip_position(&e.to_string());
                if from_editor {
                    self.edit_error = Some(msg);
                    Action::None
                } else {
                    Action::Complain(msg)
                }
            }
        }
    }

    /// Add a list element after the selected one: the editor opens on a copy of it, to be
    /// changed before it goes in (two identical device variants would be refused).
    fn duplicate_row(&mut self) -> Action {
        let Some(row) = self.rows.get(self.cursor) else {
            return Action::None;
        };
        if !row.in_list {
            return Action::Complain("a adds a list element; this row is not in a list".into());
        }
        self.edit = Some(LineEdit::new(self.tree.item_text(&row.path)));
        self.edit_error = None;
        self.inserting = true;
        Action::None
    }

    /// Delete a list element, or unset a field (the study's default applies, or the parser
    /// says the field is required).
    fn delete_row(&mut self) -> Action {
        let Some(row) = self.rows.get(self.cursor) else {
            return Action::None;
        };
        if row.absent.is_some() || row.path.is_empty() {
            return Action::None;
        }
        let doc = self.tree.removed(&row.path);
        self.apply_document(doc, false)
    }

    /// One line about the selected field: what it means, and what a number can be.
    fn row_help(&self, shared: &Shared) -> Option<String> {
        let row = self.rows.get(self.cursor)?;
        let help = fields::field_help(&row.label)?;
        let mut text = format!("{}: {help}", row.label);
        if matches!(row.label.as_str(), "excitation" | "names") && !shared.record_names.is_empty() {
            text.push_str(&format!("; records: {}", shared.record_names.join(", ")));
        } else if fields::takes_grid(&row.label) {
            text.push_str(
                "; a value 0.5, a list [0.5, 1.0] or a range (from: 1.0, to: 12.0, steps: 12)",
            );
        }
        Some(text)
    }
}

impl Component for StudyScreen {
    fn commands(&self) -> &'static [Command] {
        const COMMANDS: &[Command] = &[
            command(
                "↑↓ PgUp/Dn",
                "move; g/G first/last; / find, n/N next/previous",
            ),
            command(
                "Enter / e",
                "edit the value (RON: 0.5, [1.0, 2.0], name(…))",
            ),
            command(
                "a / d",
                "add from a copy / delete list element; unset a field",
            ),
            command("s S ^N", "save, save as, new study (the default's values)"),
        ];
        COMMANDS
    }

    fn captures_keys(&self) -> bool {
        self.edit.is_some()
    }

    fn handle_key(&mut self, key: KeyEvent, shared: &Shared) -> Action {
        if self.edit.is_some() {
            return self.edit_key(key);
        }
        let n = self.rows.len();
        match key.code {
            KeyCode::Up | KeyCode::Char('k') => self.cursor = self.cursor.saturating_sub(1),
            KeyCode::Down | KeyCode::Char('j') => {
                self.cursor = (self.cursor + 1).min(n.saturating_sub(1))
            }
            KeyCode::PageUp => self.cursor = self.cursor.saturating_sub(10),
            KeyCode::PageDown => self.cursor = (self.cursor + 10).min(n.saturating_sub(1)),
            KeyCode::Home | KeyCode::Char('g') => self.cursor = 0,
            KeyCode::End | KeyCode::Char('G') => self.cursor = n.saturating_sub(1),
            KeyCode::Enter | KeyCode::Char('e') => {
                if let Some(row) = self.rows.get(self.cursor) {
                    // A field not written starts from its default, or the table's template.
                    let text = match &row.absent {
                        Some(field) if row.text == "unset" => fields::OPTIONAL_FIELDS
                            .iter()
                            .find(|f| f.field == field)
                            .map_or(String::new(), |f| f.template.to_string()),
                        Some(_) => row.text.clone(),
                        None => self.tree.item_text(&row.path),
                    };
                    self.edit = Some(LineEdit::new(text));
                    self.edit_error = None;
                }
            }
            KeyCode::Char('a') => return self.duplicate_row(),
            KeyCode::Char('d') => return self.delete_row(),
            KeyCode::Char('s') => return Action::Save,
            KeyCode::Char('S') => {
                let current = shared
                    .path
                    .as_ref()
                    .map_or("study.ron".into(), |p| p.display().to_string());
                return Action::Prompt(Prompt::SaveAs(LineEdit::new(current)));
            }
            KeyCode::Char('/') => return Action::Prompt(Prompt::Search(LineEdit::new(""))),
            KeyCode::Char('n') if key.modifiers.contains(KeyModifiers::CONTROL) => {
                return Action::Request(Pending::New);
            }
            KeyCode::Char('n') => return self.search_again(true),
            KeyCode::Char('N') => return self.search_again(false),
            KeyCode::Char('r') => return Action::StartRun,
            _ => {}
        }
        Action::None
    }

    fn hints(&self, _: &Shared) -> Vec<Hint> {
        if self.edit.is_some() {
            let enter = if self.inserting {
                "add as a new element after this one"
            } else {
                "apply"
            };
            return vec![("Enter", enter), ("Esc", "cancel"), ("←→", "move")];
        }
        vec![
            ("↑↓", "move"),
            ("Enter", "edit"),
            ("r", "run"),
            ("s", "save"),
            ("/", "find"),
            ("o", "open"),
            ("a", "add"),
            ("d", "del/unset"),
            ("S", "save as"),
            ("n/N", "next/prev"),
            ("^N", "new"),
        ]
    }

    fn draw(&self, shared: &Shared, theme: Theme, frame: &mut Frame, area: Rect) {
        let summary = summary(shared, theme);
        let summary_height = (summary.len() as u16).min(area.height / 3).max(1);
        let edit_error = self.edit_error.as_ref();
        let row_help = self.row_help(shared);
        // The field's help, wrapped (up to 3 lines), never cut mid-word.
        let help_height = match &row_help {
            Some(text) if area.height >= 16 => {
                wrapped_line_count(text, area.width as usize).clamp(1, 3) as u16
            }
            _ => 0,
        };
        let [head, list, help, foot] = Layout::vertical([
            Constraint::Length(summary_height),
            Constraint::Min(1),
            Constraint::Length(help_height),
            Constraint::Length(if edit_error.is_some() { 2 } else { 0 }),
        ])
        .areas(area);
        if let Some(text) = row_help {
            frame.render_widget(
                Paragraph::new(Line::styled(text, theme.dim())).wrap(Wrap { trim: true }),
                help,
            );
        }
        frame.render_widget(Paragraph::new(summary).wrap(Wrap { trim: false }), head);
        let block = Block::default().borders(Borders::TOP).title(" study ");
        let inner = block.inner(list);
        frame.render_widget(block, list);

        let rows = &self.rows;
        let height = inner.height as usize;
        let offset = scroll_offset(self.cursor, rows.len(), height);
        let label_width = rows
            .iter()
            .map(|r| r.depth * 2 + r.label.chars().count())
            .max()
            .unwrap_or(0)
            .min(inner.width as usize / 2);
        let mut lines = Vec::new();
        for (i, row) in rows.iter().enumerate().skip(offset).take(height) {
            let selected = i == self.cursor;
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
            match (&self.edit, selected) {
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
    }
}

/// Whether the study is valid, how many scenes and variants it makes, and how long it runs.
fn summary(shared: &Shared, theme: Theme) -> Vec<Line<'static>> {
    let mut lines = Vec::new();
    match &shared.check {
        Check::Ok(points) => {
            let groups = shared.groups;
            let mut spans = vec![
                Span::styled("✓ valid  ", theme.ok()),
                Span::styled(
                    format!("{}", points.len()),
                    theme.value().add_modifier(Modifier::BOLD),
                ),
                Span::raw(format!(
                    " scenes in {} variant{}",
                    groups,
                    if groups == 1 { "" } else { "s" }
                )),
            ];
            if !shared.options.deterministic {
                let est = shared
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
        Check::Pending { scenes } => {
            lines.push(Line::from(vec![
                Span::styled("… expanding ", theme.warn()),
                Span::styled(
                    format!("{scenes}"),
                    theme.value().add_modifier(Modifier::BOLD),
                ),
                Span::styled(" scenes (keys work meanwhile; r waits for it)", theme.dim()),
            ]));
        }
    }
    lines
}

/// Parse errors of an edit name a position inside the generated one-line document, which
/// means nothing to the user; keep the message and the hint.
fn strip_position(msg: &str) -> String {
    match msg.strip_prefix("edit:") {
        Some(rest) => rest
            .trim_start_matches(|c: char| c.is_ascii_digit() || c == ':')
            .trim_start()
            .to_string(),
        None => msg.to_string(),
    }
}

/// Lines `text` takes when word-wrapped to `width` columns (as ratatui's `Wrap` does; its own
/// count is behind an unstable feature).
fn wrapped_line_count(text: &str, width: usize) -> usize {
    let width = width.max(1);
    let mut lines = 1;
    let mut used = 0;
    for word in text.split_whitespace() {
        let w = word.chars().count();
        let need = if used == 0 { w } else { used + 1 + w };
        if need <= width {
            used = need;
        } else {
            lines += 1 + w.saturating_sub(1) / width;
            used = (w - 1) % width + 1;
        }
    }
    lines
}
