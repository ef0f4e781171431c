//! The workbench: a thin terminal shell around the [`app::App`] state machine and the pure
//! [`draw::draw`] function. Screens are components (`components/`), drawing pieces they share
//! are widgets (`widgets/`), background work runs on one job type (`job.rs`). The shell owns the terminal (raw mode, alternate screen), restores
//! it on every exit path (normal, error, panic), and redraws only when something changed:
//! after a key, a resize, or a tick that brought news from a background run.

pub mod app;
pub mod components;
pub mod draw;
pub mod edit;
mod files;
mod hangup;
pub mod job;
pub mod theme;
pub mod tree;
pub mod widgets;

use crate::study::Study;
use app::{App, Effect, Options};
use crossterm::event::{self, Event, KeyEventKind};
use crossterm::execute;
use crossterm::terminal::{
    EnterAlternateScreen, LeaveAlternateScreen, disable_raw_mode, enable_raw_mode,
};
use ratatui::Terminal;
use ratatui::backend::CrosstermBackend;
use std::io::{self, Stdout};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use theme::Theme;

/// How often background progress is polled and, if it changed, drawn. Slow enough not to
/// flood a slow SSH link, fast enough to feel live.
const TICK: Duration = Duration::from_millis(100);
const MIN_REDRAW: Duration = Duration::from_millis(250);

/// A study file for the workbench: the study, and why it is invalid if it parses but does not
/// validate (it opens in the editor with the error shown, to be fixed there). Err: it does not
/// parse (no tree to show), with the study parser's message.
pub fn open_study(path: &std::path::Path) -> Result<(Study, Option<String>), String> {
    match Study::load(path) {
        Ok(study) => Ok((study, None)),
        Err(e) => std::fs::read_to_string(path)
            .ok()
            .and_then(|text| Study::parse_ron(&text, &path.display().to_string()).ok())
            .map(|study| (study, Some(e.to_string())))
            .ok_or_else(|| e.to_string()),
    }
}

/// The workbench on `study` (from `path`, if a file); `invalid`: why the file was refused
/// (it parsed but does not validate), shown at once so the user fixes it in the editor.
pub fn run(
    study: Study,
    path: Option<PathBuf>,
    invalid: Option<String>,
    mono: bool,
) -> anyhow::Result<()> {
    let mut app = App::new(study, path, Options::default());
    if let Some(why) = invalid {
        app.show_invalid(why);
    }
    run_app(app, mono)
}

/// Open the workbench on finished results (a results directory, results file or journal),
/// with the study they came from.
pub fn run_results(path: &std::path::Path, mono: bool) -> anyhow::Result<()> {
    let (results, dir) = app::load_results_at(path)?;
    let study = results
        .study
        .clone()
        .ok_or_else(|| anyhow::anyhow!("{}: these results carry no study", path.display()))?;
    let mut app = App::new(study, None, Options::default());
    app.open_results(results, dir);
    run_app(app, mono)
}

fn run_app(mut app: App, mono: bool) -> anyhow::Result<()> {
    let theme = Theme::from_env(mono);
    // In raw mode Ctrl-C is a key; a SIGINT sent from outside (kill -INT), a lost SSH
    // session (SIGHUP) or a `kill` (SIGTERM) end the workbench through the same clean exit:
    // the sweep stops and writes its results; finished scenes are in the journal already.
    let interrupted = Arc::new(AtomicBool::new(false));
    for signal in [
        signal_hook::consts::SIGINT,
        signal_hook::consts::SIGHUP,
        signal_hook::consts::SIGTERM,
    ] {
        let _ = signal_hook::flag::register(signal, interrupted.clone());
    }
    let shutting_down = Arc::new(AtomicBool::new(false));
    hangup::watch(interrupted.clone(), shutting_down.clone());
    let mut terminal = setup()?;
    let outcome = event_loop(&mut terminal, &mut app, theme, &interrupted, &shutting_down);
    restore();
    outcome
}

type Term = Terminal<CrosstermBackend<Stdout>>;

fn setup() -> anyhow::Result<Term> {
    // Restore the terminal before the panic message is printed, or it would be lost in the
    // alternate screen and leave the shell in raw mode.
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        restore();
        previous(info);
    }));
    enable_raw_mode()?;
    if let Err(e) = execute!(io::stdout(), EnterAlternateScreen) {
        restore();
        return Err(e.into());
    }
    match Terminal::new(CrosstermBackend::new(io::stdout())) {
        Ok(t) => Ok(t),
        Err(e) => {
            restore();
            Err(e.into())
        }
    }
}

/// Leave the alternate screen, show the cursor, leave raw mode. Safe to call twice.
pub fn restore() {
    let _ = disable_raw_mode();
    let _ = execute!(io::stdout(), LeaveAlternateScreen, crossterm::cursor::Show);
}

fn event_loop(
    terminal: &mut Term,
    app: &mut App,
    theme: Theme,
    interrupted: &AtomicBool,
    shutting_down: &AtomicBool,
) -> anyhow::Result<()> {
    terminal.draw(|f| draw::draw(app, theme, f))?;
    let mut last_draw = Instant::now();
    let mut pending = false;
    loop {
        if interrupted.load(Ordering::Relaxed) {
            shutting_down.store(true, Ordering::Relaxed);
            app.shutdown();
            return Ok(());
        }
        if event::poll(TICK)? {
            match event::read()? {
                Event::Key(key) if key.kind != KeyEventKind::Release => {
                    if app.handle_key(key) == Effect::Quit {
                        return Ok(());
                    }
                    // Draw keys at once: typing must feel immediate.
                    terminal.draw(|f| draw::draw(app, theme, f))?;
                    last_draw = Instant::now();
                    pending = false;
                }
                Event::Resize(_, _) => {
                    terminal.autoresize()?;
                    pending = true;
                }
                _ => {}
            }
        }
        pending |= app.tick();
        if pending && last_draw.elapsed() >= MIN_REDRAW {
            terminal.draw(|f| draw::draw(app, theme, f))?;
            last_draw = Instant::now();
            pending = false;
        }
    }
}
