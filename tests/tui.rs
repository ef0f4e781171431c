//! Helpers shared by the workbench's headless tests (tui_study, tui_run, tui_results,
//! tui_scene, tui_compare, tui_saving, tui_workflow): the app state machine driven by key
//! sequences, rendered with ratatui's TestBackend, snapshotted by insta into the top-level
//! `snapshots/` directory. Frames are deterministic (`Options::deterministic` hides rates,
//! ETAs and estimates).

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::buffer::Buffer;
use ratatui::style::{Color, Modifier};
use rocklab::study::Study;
use rocklab::sweep::SweepResults;
use rocklab::tui::app::{App, Check, Effect, Options, Screen};
use rocklab::tui::draw::draw;
use rocklab::tui::theme::Theme;
use std::path::PathBuf;
use std::time::Duration;

use KeyCode::Enter;

pub(crate) const SMALL: (u16, u16) = (80, 24);

pub(crate) const LARGE: (u16, u16) = (160, 48);

pub(crate) fn new_app() -> App {
    new_app_in(scratch_dir())
}

/// Where this test's runs write (never into out/): target/tui-tests/<test name>, emptied
/// first: a fixed path, so frames that show it are reproducible, and fresh, so no journal of
/// an earlier test run is resumed.
pub(crate) fn scratch_dir() -> PathBuf {
    let name = std::thread::current()
        .name()
        .unwrap_or("main")
        .replace("::", "-");
    let dir = PathBuf::from("target/tui-tests").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// An app whose runs write under `out_root` (as `out/` for the real workbench).
pub(crate) fn new_app_in(out_root: PathBuf) -> App {
    app_for(Study::builtin_default(), out_root)
}

/// A deterministic app on `study` running two jobs, its runs under `out_root`.
pub(crate) fn app_for(study: Study, out_root: PathBuf) -> App {
    App::new(
        study,
        None,
        Options {
            deterministic: true,
            jobs: Some(2),
            out_root,
        },
    )
}

pub(crate) fn render(app: &App, theme: Theme, (w, h): (u16, u16)) -> Buffer {
    let mut terminal = Terminal::new(TestBackend::new(w, h)).unwrap();
    terminal.draw(|f| draw(app, theme, f)).unwrap();
    terminal.backend().buffer().clone()
}

pub(crate) fn text(buf: &Buffer) -> String {
    let w = buf.area.width as usize;
    buf.content
        .chunks(w)
        .map(|row| {
            let line: String = row.iter().map(|c| c.symbol()).collect();
            line.trim_end().to_string()
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// One letter per cell for its foreground colour (`.` default), upper case when reversed:
/// the colours of map cells and spectrum bars, readable in a diff.
pub(crate) fn styles(buf: &Buffer) -> String {
    let w = buf.area.width as usize;
    buf.content
        .chunks(w)
        .map(|row| {
            let line: String = row
                .iter()
                .map(|c| {
                    let ch = match c.fg {
                        Color::Red => 'r',
                        Color::Green => 'g',
                        Color::Yellow => 'y',
                        Color::Magenta => 'm',
                        Color::Cyan => 'c',
                        Color::Blue => 'b',
                        Color::White => 'w',
                        Color::DarkGray => 'd',
                        Color::LightBlue => 'l',
                        Color::LightRed => 'p',
                        _ => '.',
                    };
                    if c.modifier.contains(Modifier::REVERSED) || c.bg == Color::Blue {
                        if ch == '.' {
                            '#'
                        } else {
                            ch.to_ascii_uppercase()
                        }
                    } else {
                        ch
                    }
                })
                .collect();
            line.trim_end_matches('.').to_string()
        })
        .collect::<Vec<_>>()
        .join("\n")
}

pub(crate) fn snap(name: &str, value: String) {
    insta::with_settings!({
        snapshot_path => concat!(env!("CARGO_MANIFEST_DIR"), "/snapshots"),
        prepend_module_to_snapshot => false,
        omit_expression => true,
    }, {
        insta::assert_snapshot!(format!("tui_{name}"), value);
    });
}

pub(crate) fn snap_text(app: &App, name: &str) {
    for (size, tag) in [(SMALL, "80x24"), (LARGE, "160x48")] {
        snap(
            &format!("{name}_{tag}"),
            text(&render(app, Theme::COLOR, size)),
        );
    }
}

pub(crate) fn snap_text_and_styles(app: &App, name: &str) {
    for (size, tag) in [(SMALL, "80x24"), (LARGE, "160x48")] {
        let buf = render(app, Theme::COLOR, size);
        snap(
            &format!("{name}_{tag}"),
            format!(
                "{}\n--- foreground colours ---\n{}",
                text(&buf),
                styles(&buf)
            ),
        );
    }
}

pub(crate) fn key(app: &mut App, code: KeyCode) -> Effect {
    app.handle_key(KeyEvent::new(code, KeyModifiers::NONE))
}

pub(crate) fn keys(app: &mut App, codes: &[KeyCode]) {
    for c in codes {
        key(app, *c);
    }
}

pub(crate) fn typed(app: &mut App, text: &str) {
    app.type_text(text);
}

pub(crate) fn ctrl(app: &mut App, c: char) -> Effect {
    app.handle_key(KeyEvent::new(KeyCode::Char(c), KeyModifiers::CONTROL))
}

/// Jump to a field with `/`, open its editor, replace the value, apply.
pub(crate) fn set_field(app: &mut App, field: &str, value: &str) {
    key(app, KeyCode::Char('/'));
    typed(app, field);
    key(app, Enter);
    key(app, Enter);
    ctrl(app, 'u');
    ctrl(app, 'k');
    typed(app, value);
    key(app, Enter);
}

pub(crate) fn scene_count(app: &App) -> usize {
    match &app.shared.check {
        Check::Ok(points) => points.len(),
        Check::Invalid(msg) => panic!("study invalid: {msg}"),
        Check::Pending { scenes } => panic!("{scenes} scenes still being expanded"),
    }
}

/// Shrink the default study to a few quick scenes, by keys.
/// Shrink the default study's frequency grid and add an overturning map over frequency ×
/// amplitude, by keys: 3 variants × 4 frequencies × 3 amplitudes.
pub(crate) fn small_map_study(app: &mut App) {
    set_field(app, "frequency", "ratio([2.0, 4.0, 6.0, 8.0])");
    set_field(app, "amplitude", "alpha_ratio([1.0, 2.0, 4.0])");
    set_field(app, "map", "(x: frequency, y: amplitude)");
    assert!(
        app.editor.edit_error.is_none(),
        "{:?}",
        app.editor.edit_error
    );
}

pub(crate) fn run_to_completion(app: &mut App) {
    key(app, KeyCode::Char('r'));
    assert_eq!(app.screen, Screen::Run);
    assert!(
        app.wait_idle(Duration::from_secs(120)),
        "sweep did not finish"
    );
}

/// Results of [`small_map_study`] computed once and kept (tests/data), so that the results
/// screens' snapshots test the drawing, not the physics: they do not change when the solver
/// or a model does. tests/data/tui_small_map.ron says how to regenerate them (after a
/// deliberate change of the default study, the solver or the results format).
pub(crate) fn fixed_results() -> SweepResults {
    rocklab::report::load_results(std::path::Path::new(
        "tests/data/tui_small_map_results.json",
    ))
    .unwrap()
}
