//! A one-line text editor: the value being edited on the Study screen, and file-name prompts.

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LineEdit {
    pub text: String,
    /// Cursor position in characters.
    pub cursor: usize,
}

pub enum EditOutcome {
    Editing,
    Commit,
    Cancel,
}

impl LineEdit {
    pub fn new(text: impl Into<String>) -> Self {
        let text = text.into();
        let cursor = text.chars().count();
        LineEdit { text, cursor }
    }

    fn byte_at(&self, char_index: usize) -> usize {
        self.text
            .char_indices()
            .nth(char_index)
            .map_or(self.text.len(), |(b, _)| b)
    }

    pub fn handle_key(&mut self, key: KeyEvent) -> EditOutcome {
        let len = self.text.chars().count();
        let ctrl = key.modifiers.contains(KeyModifiers::CONTROL);
        // Alt+key arrives when Esc and a key come in one packet over a slow link: not text.
        let alt = key.modifiers.contains(KeyModifiers::ALT);
        match key.code {
            KeyCode::Enter => return EditOutcome::Commit,
            KeyCode::Esc => return EditOutcome::Cancel,
            KeyCode::Left => self.cursor = self.cursor.saturating_sub(1),
            KeyCode::Right => self.cursor = (self.cursor + 1).min(len),
            KeyCode::Home => self.cursor = 0,
            KeyCode::End => self.cursor = len,
            KeyCode::Char('a') if ctrl => self.cursor = 0,
            KeyCode::Char('e') if ctrl => self.cursor = len,
            KeyCode::Char('u') if ctrl => {
                let b = self.byte_at(self.cursor);
                self.text.replace_range(..b, "");
                self.cursor = 0;
            }
            KeyCode::Char('k') if ctrl => {
                let b = self.byte_at(self.cursor);
                self.text.truncate(b);
            }
            KeyCode::Backspace if self.cursor > 0 => {
                let b = self.byte_at(self.cursor - 1);
                self.text.remove(b);
                self.cursor -= 1;
            }
            KeyCode::Delete if self.cursor < len => {
                let b = self.byte_at(self.cursor);
                self.text.remove(b);
            }
            KeyCode::Char(c) if !ctrl && !alt => {
                let b = self.byte_at(self.cursor);
                self.text.insert(b, c);
                self.cursor += 1;
            }
            _ => {}
        }
        EditOutcome::Editing
    }

    /// The text split at the cursor, for drawing: (before, under cursor, after).
    pub fn split(&self) -> (String, String, String) {
        let before: String = self.text.chars().take(self.cursor).collect();
        let at: String = self.text.chars().skip(self.cursor).take(1).collect();
        let after: String = self.text.chars().skip(self.cursor + 1).collect();
        (before, if at.is_empty() { " ".into() } else { at }, after)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn press(e: &mut LineEdit, code: KeyCode, mods: KeyModifiers) {
        e.handle_key(KeyEvent::new(code, mods));
    }

    #[test]
    fn editing_keys_work_on_characters_not_bytes() {
        let mut e = LineEdit::new("ωx/y");
        assert_eq!(e.cursor, 4);
        press(&mut e, KeyCode::Home, KeyModifiers::NONE);
        press(&mut e, KeyCode::Delete, KeyModifiers::NONE);
        assert_eq!(e.text, "x/y");
        press(&mut e, KeyCode::Char('θ'), KeyModifiers::NONE);
        assert_eq!((e.text.as_str(), e.cursor), ("θx/y", 1));
        press(&mut e, KeyCode::End, KeyModifiers::NONE);
        press(&mut e, KeyCode::Backspace, KeyModifiers::NONE);
        assert_eq!(e.text, "θx/");
        press(&mut e, KeyCode::Left, KeyModifiers::NONE);
        press(&mut e, KeyCode::Char('k'), KeyModifiers::CONTROL);
        assert_eq!(e.text, "θx");
        press(&mut e, KeyCode::Char('u'), KeyModifiers::CONTROL);
        assert_eq!((e.text.as_str(), e.cursor), ("", 0));
        // Alt+key is not text (it is Esc + key over a slow link).
        press(&mut e, KeyCode::Char('q'), KeyModifiers::ALT);
        assert_eq!(e.text, "");
        assert_eq!(e.split(), (String::new(), " ".into(), String::new()));
    }
}
