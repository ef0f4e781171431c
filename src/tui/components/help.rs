//! The help overlay: every key of every screen, from each screen's own list
//! ([`super::Component::commands`]) after the keys that work everywhere; any key closes it.

use super::super::theme::Theme;
use super::super::widgets::popup;
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
        let mut lines = Vec::new();
        for (title, commands) in sections {
            lines.push(Line::styled(title.to_string(), theme.title()));
            lines.extend(commands.iter().map(|c| {
                Line::from(vec![
                    Span::styled(format!("{:>10}  ", c.keys), theme.key()),
                    Span::raw(c.what),
                ])
            }));
        }
        let height = lines.len() as u16;
        popup(
            frame,
            theme,
            area,
            " help (any key closes) ",
            lines,
            66,
            height,
        );
    }
}
