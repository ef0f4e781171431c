//! Colours, with a monochrome variant (NO_COLOR, `--mono`, monochrome terminals) in which every
//! distinction is carried by glyphs and modifiers instead.

use ratatui::style::{Color, Modifier, Style};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Theme {
    pub mono: bool,
}

/// Glyphs of an overturning-map cell; distinct in both themes so maps read without colour.
pub const CELL_OVERTURNED: &str = "█";
pub const CELL_SAFE: &str = "·";
pub const CELL_FAILED: &str = "?";
pub const CELL_MISSING: &str = " ";

impl Theme {
    pub const COLOR: Theme = Theme { mono: false };
    pub const MONO: Theme = Theme { mono: true };

    /// Monochrome when asked for, when NO_COLOR is set (any non-empty value, no-color.org),
    /// or when the terminal says it has no colours.
    pub fn from_env(mono_flag: bool) -> Theme {
        let no_color = std::env::var_os("NO_COLOR").is_some_and(|v| !v.is_empty());
        let term = std::env::var("TERM").unwrap_or_default();
        let mono_term = term == "dumb" || term.ends_with("-m") || term.ends_with("-mono");
        Theme {
            mono: mono_flag || no_color || mono_term,
        }
    }

    fn fg(&self, c: Color) -> Style {
        if self.mono {
            Style::default()
        } else {
            Style::default().fg(c)
        }
    }

    pub fn base(&self) -> Style {
        Style::default()
    }
    pub fn title(&self) -> Style {
        self.fg(Color::Cyan).add_modifier(Modifier::BOLD)
    }
    pub fn dim(&self) -> Style {
        if self.mono {
            Style::default()
        } else {
            Style::default().fg(Color::DarkGray)
        }
    }
    pub fn key(&self) -> Style {
        self.fg(Color::Yellow).add_modifier(Modifier::BOLD)
    }
    pub fn selected(&self) -> Style {
        if self.mono {
            Style::default().add_modifier(Modifier::REVERSED)
        } else {
            Style::default().bg(Color::Blue).fg(Color::White)
        }
    }
    pub fn tab_active(&self) -> Style {
        Style::default().add_modifier(Modifier::REVERSED | Modifier::BOLD)
    }
    pub fn error(&self) -> Style {
        self.fg(Color::Red).add_modifier(Modifier::BOLD)
    }
    pub fn ok(&self) -> Style {
        self.fg(Color::Green)
    }
    pub fn warn(&self) -> Style {
        self.fg(Color::Yellow)
    }
    pub fn field(&self) -> Style {
        self.fg(Color::Cyan)
    }
    pub fn value(&self) -> Style {
        self.fg(Color::White)
    }
    /// The spectrum bars of the a-th / b-th variant in a comparison.
    pub fn series(&self, i: usize) -> Style {
        const PALETTE: [Color; 6] = [
            Color::Green,
            Color::Magenta,
            Color::Cyan,
            Color::Yellow,
            Color::LightBlue,
            Color::LightRed,
        ];
        self.fg(PALETTE[i % PALETTE.len()])
    }
    pub fn cursor(&self) -> Style {
        Style::default().add_modifier(Modifier::REVERSED)
    }
    pub fn overturned(&self) -> Style {
        self.fg(Color::Red)
    }
    pub fn safe(&self) -> Style {
        self.fg(Color::Green)
    }
    pub fn failed(&self) -> Style {
        self.fg(Color::Yellow).add_modifier(Modifier::BOLD)
    }
}
