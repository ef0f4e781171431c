//! The help overlay: every key of every screen, from each screen's own list
//! ([`super::Component::commands`]) after the keys that work everywhere; any key closes it.

use super::super::theme::Theme;
use super::super::widgets::{more_marker, popup};
use super::{Command, command};
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};

#[derive(Default)]
pub struct Help {
    pub visible: bool,
}

/// The keys every screen answers (the app's own, `App::handle_key`).
pub const EVERYWHERE: &[Command] = &[
    command("1 2 3 4", "Study / Run / Results / Scene (Tab cycles)"),
    command("r  ?", "run or resume the study  /  this help"),
    command(
        "q ^C  o ^O",
        "quit (asks if need be) / open a study or results",
    ),
];

impl Help {
    /// `sections`: a title and its keys, in order.
    pub fn draw(
        &self,
        theme: Theme,
        frame: &mut Frame,
        area: Rect,
        sections: &[(&str, &[Command])],
    ) {
        if !self.visible {
            return;
        }
        // As wide as the terminal allows (up to 78 columns); a description longer than its
        // room wraps between words onto indented lines, never cut inside a word.
        let width = area.width.min(78);
        let keys_w = 12;
        let text_w = (width as usize).saturating_sub(2 + keys_w).max(10);
        let mut lines = Vec::new();
        for (title, commands) in sections {
            lines.push(Line::styled(title.to_string(), theme.title()));
            for c in commands.iter() {
                for (i, part) in crate::report::naming::wrap(c.what, text_w)
                    .into_iter()
                    .enumerate()
                {
                    let keys = if i == 0 { c.keys } else { "" };
                    lines.push(Line::from(vec![
                        Span::styled(format!("{keys:>10}  "), theme.key()),
                        Span::raw(part),
                    ]));
                }
            }
        }
        // Too many lines for the terminal: the last one says how many are left out.
        let room = area.height.saturating_sub(2) as usize;
        if lines.len() > room && room > 0 {
            let hidden = lines.len() - (room - 1);
            lines.truncate(room - 1);
            let more = more_marker(0, hidden).unwrap_or_default();
            lines.push(Line::styled(
                format!("{more} lines: a taller terminal shows them"),
                theme.dim(),
            ));
        }
        let height = lines.len() as u16;
        popup(
            frame,
            theme,
            area,
            " help (any key closes) ",
            lines,
            width,
            height,
        );
    }
}
