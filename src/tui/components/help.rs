//! The help overlay: every key of every screen; any key closes it.

use super::super::theme::Theme;
use super::super::widgets::popup;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};

#[derive(Default)]
pub struct Help {
    pub visible: bool,
}

impl Help {
    pub fn draw(&self, theme: Theme, frame: &mut Frame, area: Rect) {
        if !self.visible {
            return;
        }
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
            k("r  ?", "run or resume the study  /  this help"),
            k(
                "q ^C  o ^O",
                "quit (asks if need be) / open a study or results",
            ),
            h("Study"),
            k(
                "↑↓ PgUp/Dn",
                "move; g/G first/last; / find, n/N next/previous",
            ),
            k(
                "Enter / e",
                "edit the value (RON: 0.5, [1.0, 2.0], name(…))",
            ),
            k(
                "a / d",
                "add from a copy / delete list element; unset a field",
            ),
            k("s S ^N", "save, save as, new study (the default's values)"),
            h("Run"),
            k(
                "c / Esc",
                "stop (asks; finished scenes are kept, r resumes)",
            ),
            k("↑↓ d Enter", "scroll (PgUp/Dn g/G) / results dir / results"),
            h("Results"),
            k("s m c p g", "spectra / maps / compare / fragility / design"),
            k(
                "←→ ↑↓",
                "cursor along the axis / variant, cell or design point",
            ),
            k("[ ]  f", "prev/next quantity, map or state; f filter rows"),
            k("a b x", "compare: pick A / B (device, values), swap"),
            k("o y d", "compare: sort pairs, one y scale or two, maps"),
            k(
                "Enter  w",
                "open the scene under the cursor / write results",
            ),
            h("Scene"),
            k(
                "Esc  c",
                "back / check; `rocklab plot DIR --scene N` draws it",
            ),
        ];
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
