//! `rocklab bench --tui STUDY`: the workbench's latency on a study, driven headlessly as a user
//! drives it. The real [`App`] gets key events and draws on an 80×24 `TestBackend` after each,
//! as the terminal loop does; times are the key's handling plus its frame. Edits change the
//! scene count (a `steps:` of the study alternately one down and back); an edit is timed until
//! input is handled again, and separately until the new expansion has landed.

use crate::study::Study;
use crate::tui::app::{App, Options, Screen};
use crate::tui::draw::draw;
use crate::tui::edit::LineEdit;
use crate::tui::theme::Theme;
use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use std::path::Path;
use std::time::{Duration, Instant};

type Term = Terminal<TestBackend>;

/// Median and worst of some latencies, in milliseconds.
fn stats(ms: &mut [f64]) -> (f64, f64) {
    if ms.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    ms.sort_by(f64::total_cmp);
    (ms[ms.len() / 2], ms[ms.len() - 1])
}

/// One key as the terminal loop handles it: the key, then a frame. Milliseconds.
fn timed_key(app: &mut App, term: &mut Term, code: KeyCode) -> anyhow::Result<f64> {
    let start = Instant::now();
    app.handle_key(KeyEvent::new(code, KeyModifiers::NONE));
    app.tick();
    term.draw(|f| draw(app, Theme::COLOR, f))?;
    Ok(start.elapsed().as_secs_f64() * 1e3)
}

/// Arrow moves across the screens (Study, Run, Results, Scene and back).
const KEYS: [KeyCode; 10] = [
    KeyCode::Down,
    KeyCode::Down,
    KeyCode::Up,
    KeyCode::Tab,
    KeyCode::Down,
    KeyCode::Tab,
    KeyCode::Down,
    KeyCode::Tab,
    KeyCode::Up,
    KeyCode::Tab,
];

/// The study row whose text holds a `steps:` (the deepest such, so an edit of it changes only
/// one axis), and its text.
fn steps_row(app: &App) -> Option<(usize, String)> {
    let editor = &app.editor;
    (0..editor.rows.len()).rev().find_map(|i| {
        let row = &editor.rows[i];
        if row.absent.is_some() {
            return None;
        }
        let text = editor.tree.item_text(&row.path);
        text.contains("steps:").then_some((i, text))
    })
}

/// `text` with the number after its last `steps:` changed by `by`.
fn with_steps(text: &str, by: i64) -> Option<String> {
    let at = text.rfind("steps:")? + "steps:".len();
    let rest = &text[at..];
    let digits: String = rest
        .trim_start()
        .chars()
        .take_while(char::is_ascii_digit)
        .collect();
    let skip = rest.len() - rest.trim_start().len();
    let n: i64 = digits.parse().ok()?;
    Some(format!(
        "{} {}{}",
        &text[..at],
        (n + by).max(2),
        &rest[skip + digits.len()..]
    ))
}

pub fn run(path: &Path, keys: usize, edits: usize) -> anyhow::Result<()> {
    let study = Study::load(path)?;
    let out_root = tempfile::tempdir()?;
    let options = Options {
        deterministic: false,
        jobs: None,
        out_root: out_root.path().to_path_buf(),
    };
    let mut term = Terminal::new(TestBackend::new(80, 24))?;
    let start = Instant::now();
    let mut app = App::new(study, Some(path.to_path_buf()), options);
    term.draw(|f| draw(&app, Theme::COLOR, f))?;
    let open_ms = start.elapsed().as_secs_f64() * 1e3;
    let start = Instant::now();
    while app.expansion_pending() && start.elapsed() < Duration::from_secs(120) {
        app.tick();
        std::thread::sleep(Duration::from_millis(1));
    }
    let expanded_ms = open_ms + start.elapsed().as_secs_f64() * 1e3;
    println!(
        "rocklab bench --tui {}: {} scenes, 80×24, {} threads",
        path.display(),
        app.scene_count().unwrap_or(0),
        rayon::current_num_threads()
    );
    println!(
        "open (App::new + first frame): {open_ms:.1} ms; expansion landed after {expanded_ms:.1} ms"
    );

    let mut key_ms = Vec::new();
    for i in 0..keys {
        key_ms.push(timed_key(&mut app, &mut term, KEYS[i % KEYS.len()])?);
    }
    app.screen = Screen::Study;

    let mut edit_ms = Vec::new();
    let mut landed_ms = Vec::new();
    let mut counts = Vec::new();
    for i in 0..edits {
        let Some((row, text)) = steps_row(&app) else {
            anyhow::bail!("{}: no `steps:` in the study to edit", path.display());
        };
        let by = if i % 2 == 0 { -1 } else { 1 };
        let Some(edited) = with_steps(&text, by) else {
            anyhow::bail!("cannot change the steps of {text}");
        };
        app.editor.cursor = row;
        app.editor.edit = Some(LineEdit::new(edited));
        let start = Instant::now();
        app.handle_key(KeyEvent::new(KeyCode::Enter, KeyModifiers::NONE));
        app.tick();
        term.draw(|f| draw(&app, Theme::COLOR, f))?;
        edit_ms.push(start.elapsed().as_secs_f64() * 1e3);
        if app.editor.edit.is_some() {
            anyhow::bail!("the edit was refused: {:?}", app.editor.edit_error);
        }
        // Keys typed while the expansion runs in the background.
        for k in 0..4 {
            key_ms.push(timed_key(&mut app, &mut term, KEYS[k % 3])?);
        }
        while app.expansion_pending() && start.elapsed() < Duration::from_secs(120) {
            app.tick();
            std::thread::sleep(Duration::from_millis(1));
        }
        term.draw(|f| draw(&app, Theme::COLOR, f))?;
        landed_ms.push(start.elapsed().as_secs_f64() * 1e3);
        counts.push(app.scene_count().unwrap_or(0));
    }
    let (key_median, key_worst) = stats(&mut key_ms);
    let (edit_median, edit_worst) = stats(&mut edit_ms);
    let (landed_median, landed_worst) = stats(&mut landed_ms);
    println!("| what | n | median (ms) | worst (ms) |");
    println!("|---|---|---|---|");
    println!(
        "| keystroke (key + frame) | {} | {key_median:.1} | {key_worst:.1} |",
        key_ms.len()
    );
    println!(
        "| edit: input handled again | {} | {edit_median:.1} | {edit_worst:.1} |",
        edit_ms.len()
    );
    println!(
        "| edit: new expansion landed | {} | {landed_median:.1} | {landed_worst:.1} |",
        landed_ms.len()
    );
    println!("scene counts after the edits: {counts:?}");
    app.shutdown();
    Ok(())
}
