//! The workbench as a state machine: keys in, state changes and effects out. The app holds
//! what the screens share ([`Shared`]: the open study and its expansion, the results), routes
//! keys to the component of the current screen (or the prompt, or the help overlay) and
//! carries out the [`Action`]s they return: runs, scenes, saving, opening. Drawing reads the
//! state (`draw.rs`); the terminal loop (`mod.rs`) only feeds keys and ticks. Background work
//! (calibration here, the sweep in the Run screen, the scene in the Scene screen) runs on
//! [`AsyncSingleJob`]s polled by `tick`.

use super::components::help::Help;
use super::components::results::ResultsScreen;
use super::components::run::RunScreen;
use super::components::scene::SceneScreen;
use super::components::study::StudyScreen;
use super::components::{Action, Component};
use super::edit::{EditOutcome, LineEdit};
use super::job::{AsyncSingleJob, JobEvent};
use crate::excitation::library::Library;
use crate::report;
use crate::study::{ScenePoint, Study};
use crate::sweep::SweepResults;
use crate::sweep::estimate::{CostModel, Strata};
use crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers};
use expansion::Expanded;
use std::path::PathBuf;

pub use super::files::{is_results_path, load_results_at};
use std::time::{Duration, Instant};

pub use super::components::prompt::{
    DropComments, OverwriteResults, Pending, Prompt, StopSweep, backup_path,
};
pub use super::components::results::{Results, ResultsTab};
pub use super::components::run::{GroupProgress, RunState};
pub use super::components::scene::{SceneState, SceneView};
pub use super::components::study::Row;
pub use super::components::{Check, EXPAND_AT_ONCE, Shared};

mod background;
mod expansion;

all_variants! {
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Screen {
    Study,
    Run,
    Results,
    Scene,
}
}

impl Screen {
    pub fn title(self) -> &'static str {
        match self {
            Screen::Study => "Study",
            Screen::Run => "Run",
            Screen::Results => "Results",
            Screen::Scene => "Scene",
        }
    }
}

/// What the terminal loop must do after a key.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Effect {
    None,
    Quit,
}

#[derive(Clone, Debug)]
pub struct Options {
    /// Hide everything that depends on the wall clock (rates, ETAs, run-time estimates) so
    /// that frames are reproducible; used by the snapshot tests.
    pub deterministic: bool,
    /// Worker threads for sweeps (None: all cores).
    pub jobs: Option<usize>,
    /// Where a study's results go unless the user picks a directory: `<out_root>/<study
    /// name>/`, as `rocklab run` does (tests point it at a temporary directory).
    pub out_root: PathBuf,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            deterministic: false,
            jobs: None,
            out_root: PathBuf::from("out"),
        }
    }
}

pub struct App {
    pub screen: Screen,
    pub shared: Shared,
    pub editor: StudyScreen,
    pub runs: RunScreen,
    pub browser: ResultsScreen,
    pub scene: SceneScreen,
    pub help: Help,
    pub prompt: Option<Prompt>,
    /// One-line message on the status bar (cleared by the next key); true for an error.
    pub message: Option<(String, bool)>,
    /// Times a few scenes of every stratum of the study for the run-time estimate.
    calibration: AsyncSingleJob<(), Option<(Strata, CostModel)>>,
    /// Expands a large study off the UI thread; its output carries the generation it was
    /// asked for and is dropped unless that is still the study's.
    expansion: AsyncSingleJob<(), Expanded>,
    /// Counts the studies set (opened or edited): what a landing expansion is checked against.
    generation: u64,
    /// Set by a first Ctrl-C with unsaved changes: a second one quits anyway.
    ctrl_c_armed: bool,
}

/// The built-in default study's file, comments included.
const BUILTIN_DEFAULT: &str = include_str!("../../studies/default.ron");

fn key_press(code: KeyCode) -> KeyEvent {
    KeyEvent::new(code, KeyModifiers::NONE)
}

impl App {
    pub fn new(study: Study, path: Option<PathBuf>, options: Options) -> App {
        // The text a save keeps comments and spelling from: the file the study came from,
        // or the built-in default's.
        let original = match &path {
            Some(p) => std::fs::read_to_string(p).ok(),
            None if study == Study::builtin_default() => Some(BUILTIN_DEFAULT.to_string()),
            None => None,
        };
        let mut app = App {
            screen: Screen::Study,
            editor: StudyScreen::new(&study, original.as_deref()),
            shared: Shared {
                options,
                check: Check::Pending { scenes: 0 },
                groups: 0,
                study: study.clone(),
                path,
                original,
                dirty: false,
                results: None,
                out_dir: None,
                costs: None,
                record_names: Library::open(Library::default_dir())
                    .map(|l| l.names())
                    .unwrap_or_default(),
            },
            runs: RunScreen::default(),
            browser: ResultsScreen::default(),
            scene: SceneScreen::default(),
            help: Help::default(),
            prompt: None,
            message: None,
            calibration: AsyncSingleJob::default(),
            expansion: AsyncSingleJob::default(),
            generation: 0,
            ctrl_c_armed: false,
        };
        app.begin_check(&study, None);
        app
    }

    /// The component drawn on (and taking the keys of) `screen`.
    pub fn component(&self, screen: Screen) -> &dyn Component {
        match screen {
            Screen::Study => &self.editor,
            Screen::Run => &self.runs,
            Screen::Results => &self.browser,
            Screen::Scene => &self.scene,
        }
    }

    pub fn file_label(&self) -> String {
        let name = match (&self.shared.path, &self.shared.out_dir) {
            (Some(p), _) => p.display().to_string(),
            // Opened results carry their study but no study file.
            (None, Some(dir)) => format!("study of {}/", dir.display()),
            (None, None) => "built-in default study".to_string(),
        };
        if self.shared.dirty {
            format!("{name} [+]")
        } else {
            name
        }
    }

    pub fn is_running(&self) -> bool {
        self.runs.is_running()
    }

    /// The study's expansion is being computed in the background.
    pub fn expansion_pending(&self) -> bool {
        matches!(self.shared.check, Check::Pending { .. })
    }

    /// Scenes of the open study, once expanded (None if invalid or pending).
    pub fn scene_count(&self) -> Option<usize> {
        match &self.shared.check {
            Check::Ok(points) => Some(points.len()),
            _ => None,
        }
    }

    fn say(&mut self, msg: impl Into<String>) {
        self.message = Some((msg.into(), false));
    }

    fn complain(&mut self, msg: impl Into<String>) {
        self.message = Some((msg.into(), true));
    }

    /// The study was opened although invalid: say why (file, line, field, hint) until the
    /// user edits it; runs are refused with the same message meanwhile.
    pub fn show_invalid(&mut self, why: String) {
        self.complain(format!("{why} (fix it here: Enter edits the value)"));
    }

    /// Put results on the Results screen (a finished or cancelled sweep), cursors reset.
    pub fn show_results(&mut self, results: SweepResults, cancelled: bool) {
        let data = Results::new(results, cancelled);
        self.browser.reset(&data);
        self.shared.results = Some(data);
    }

    /// Browse finished results with the study they came from; a later run of that study goes
    /// to (and resumes in) the directory they were read from.
    pub fn open_results(&mut self, results: SweepResults, dir: PathBuf) {
        let Some(study) = results.study.clone() else {
            self.complain(
                "these results carry no study (written by `rocklab merge` of ad-hoc points)",
            );
            return;
        };
        self.shared.path = None;
        self.shared.original = None;
        self.shared.dirty = false;
        self.shared.out_dir = Some(dir.clone());
        self.editor.cursor = 0;
        self.set_study(study, None, None);
        let cancelled = results.cancelled;
        let n = results.outcomes.len();
        self.show_results(results, cancelled);
        self.screen = Screen::Results;
        let beside = self.load_beside(&dir);
        self.say(format!(
            "opened {n} scenes of results in {}/{beside}",
            dir.display()
        ));
    }

    /// Read what is written beside the results shown (check.csv, fragility.json) from
    /// `dir`: after `o` and after a run, so a fragility study's curves are there at once.
    /// Returns what was read, as a message tail ("; fragility curves: p").
    pub(super) fn load_beside(&mut self, dir: &std::path::Path) -> String {
        let mut checks = match self.shared.results.as_mut().map(|r| r.load_checks(dir)) {
            Some(Ok(0)) | None => String::new(),
            Some(Ok(m)) => format!("; check.csv: {m} scenes checked"),
            Some(Err(e)) => format!("; not read: {e}"),
        };
        match self.shared.results.as_mut().map(|r| r.load_fragility(dir)) {
            Some(Ok(true)) => {
                checks.push_str("; fragility curves: p");
                if let Some(data) = &self.shared.results
                    && data.spectra.is_empty()
                    && data.maps.is_empty()
                {
                    self.browser.tab = ResultsTab::Fragility;
                }
            }
            Some(Err(e)) => checks.push_str(&format!("; not read: {e}")),
            _ => {}
        }
        checks
    }

    /// A new study: its check (the expansion, computed by the caller, here, or in the
    /// background for a large study), the editor's rows and the run-time estimate follow.
    fn set_study(&mut self, study: Study, points: Option<Vec<ScenePoint>>, text: Option<&str>) {
        self.editor.study_changed(&study, text);
        self.shared.study = study;
        let study = self.shared.study.clone();
        self.begin_check(&study, points);
    }

    // ----- keys -----

    pub fn handle_key(&mut self, key: KeyEvent) -> Effect {
        if key.kind == KeyEventKind::Release {
            return Effect::None;
        }
        // Over a slow link Esc and the next key can arrive in one read and be decoded as
        // Alt+key: take it as the two keys the user typed.
        if key.modifiers.contains(KeyModifiers::ALT) && matches!(key.code, KeyCode::Char(_)) {
            if self.handle_key(key_press(KeyCode::Esc)) == Effect::Quit {
                return Effect::Quit;
            }
            return self.handle_key(KeyEvent::new(key.code, key.modifiers - KeyModifiers::ALT));
        }
        let ctrl_c =
            key.code == KeyCode::Char('c') && key.modifiers.contains(KeyModifiers::CONTROL);
        if ctrl_c {
            return self.ctrl_c();
        }
        self.ctrl_c_armed = false;
        self.message = None;
        if self.help.visible {
            self.help.visible = false;
            return Effect::None;
        }
        if self.prompt.is_some() {
            return self.prompt_key(key);
        }
        let open = || Some(Prompt::Open(LineEdit::new("")));
        if key.code == KeyCode::Char('o') && key.modifiers.contains(KeyModifiers::CONTROL) {
            self.prompt = open();
            return Effect::None;
        }
        if !self.component(self.screen).captures_keys() {
            // `o` opens on every screen but the comparison, where it sorts the pairs.
            let o_sorts = self.screen == Screen::Results
                && self.browser.tab == super::components::results::ResultsTab::Compare;
            match key.code {
                KeyCode::Char('o') if !o_sorts => self.prompt = open(),
                KeyCode::Char('q') => return self.request(Pending::Quit),
                KeyCode::Char('?') => self.help.visible = true,
                KeyCode::Char('1') => self.screen = Screen::Study,
                KeyCode::Char('2') => self.screen = Screen::Run,
                KeyCode::Char('3') => self.screen = Screen::Results,
                KeyCode::Char('4') => self.screen = Screen::Scene,
                KeyCode::Tab => self.cycle_screen(1),
                KeyCode::BackTab => self.cycle_screen(Screen::ALL.len() - 1),
                _ => return self.route(key),
            }
            return Effect::None;
        }
        self.route(key)
    }

    /// Give a key to the current screen and do what it asks.
    fn route(&mut self, key: KeyEvent) -> Effect {
        let action = match self.screen {
            Screen::Study => self.editor.handle_key(key, &self.shared),
            Screen::Run => self.runs.handle_key(key, &self.shared),
            Screen::Results => self.browser.handle_key(key, &self.shared),
            Screen::Scene => self.scene.handle_key(key, &self.shared),
        };
        self.act(action)
    }

    fn act(&mut self, action: Action) -> Effect {
        match action {
            Action::None => {}
            Action::Show(screen) => self.screen = screen,
            Action::StartRun => self.start_run(),
            Action::OpenScene(point) => {
                self.scene.open(*point);
                self.screen = Screen::Scene;
            }
            Action::Prompt(prompt) => self.prompt = Some(prompt),
            Action::Request(then) => return self.request(then),
            Action::Save => {
                self.save();
            }
            Action::StudyEdited {
                study,
                points,
                text,
                note,
            } => {
                self.shared.dirty = true;
                self.set_study(*study, points, Some(&text));
                if let Some(note) = note {
                    self.say(note);
                }
            }
            Action::Say(msg) => self.say(msg),
            Action::Complain(msg) => self.complain(msg),
        }
        Effect::None
    }

    fn ctrl_c(&mut self) -> Effect {
        // A first Ctrl-C during a sweep asks; a second one answers with the default (keep
        // the finished scenes and quit).
        if !matches!(self.prompt, Some(Prompt::StopSweep(_)))
            && let Some(stop) = self.runs.stop_question(true)
        {
            self.prompt = Some(Prompt::StopSweep(stop));
            return Effect::None;
        }
        self.prompt = None;
        if self.shared.dirty && !self.ctrl_c_armed {
            self.ctrl_c_armed = true;
            self.complain("unsaved changes: press Ctrl-C again to quit without saving, s to save");
            return Effect::None;
        }
        self.shutdown();
        Effect::Quit
    }

    fn cycle_screen(&mut self, by: usize) {
        let i = Screen::ALL
            .iter()
            .position(|s| *s == self.screen)
            .unwrap_or(0);
        self.screen = Screen::ALL[(i + by) % Screen::ALL.len()];
    }

    /// Do `then` now, or ask first if it would stop a running sweep or lose unsaved changes.
    fn request(&mut self, then: Pending) -> Effect {
        if matches!(then, Pending::Quit)
            && let Some(stop) = self.runs.stop_question(true)
        {
            self.prompt = Some(Prompt::StopSweep(stop));
            return Effect::None;
        }
        self.request_unsaved(then)
    }

    /// Do `then` now, or ask first if it would lose unsaved changes.
    fn request_unsaved(&mut self, then: Pending) -> Effect {
        if self.shared.dirty {
            self.prompt = Some(Prompt::Discard(then));
            Effect::None
        } else {
            self.perform(then)
        }
    }

    fn perform(&mut self, then: Pending) -> Effect {
        match then {
            Pending::Quit => {
                self.shutdown();
                return Effect::Quit;
            }
            Pending::Open(path) if is_results_path(&path) => match load_results_at(&path) {
                Ok((results, dir)) => self.open_results(results, dir),
                Err(e) => self.complain(format!("{e:#}")),
            },
            Pending::Open(path) => match Study::load(&path) {
                Ok(study) => {
                    self.shared.original = std::fs::read_to_string(&path).ok();
                    self.shared.path = Some(path.clone());
                    self.shared.dirty = false;
                    self.editor.cursor = 0;
                    let folder = self.forget_out_dir();
                    let text = self.shared.original.clone();
                    self.set_study(study, None, text.as_deref());
                    self.say(format!("opened {}{folder}", path.display()));
                }
                Err(e) => self.complain(e.to_string()),
            },
            Pending::New => {
                // The default's values, not its file: no header comment, no description.
                let study = Study {
                    name: "new_study".into(),
                    description: String::new(),
                    ..Study::builtin_default()
                };
                self.shared.path = None;
                self.shared.original = None;
                self.shared.dirty = false;
                self.editor.cursor = 0;
                let folder = self.forget_out_dir();
                self.set_study(study, None, None);
                self.say(format!("new study (the built-in default's values){folder}"));
            }
        }
        Effect::None
    }

    /// Another study is opened: an output folder chosen with `d` (or the results opened) was
    /// for the one before, so the next run goes to out/<name>/ again. Says so if it changes.
    fn forget_out_dir(&mut self) -> String {
        match self.shared.out_dir.take() {
            Some(dir) => format!(
                "; results go to out/<study name>/ again, not {}/ (d changes it)",
                dir.display()
            ),
            None => String::new(),
        }
    }

    /// Cancel background work before leaving, so that the process exits promptly. A sweep
    /// gets a few seconds to write its results files (its finished scenes are journalled
    /// already, so a slower stop loses nothing: the next run resumes from the journal).
    pub fn shutdown(&mut self) {
        self.runs.shutdown();
        if self.is_running() {
            let until = Instant::now() + Duration::from_secs(3);
            while self.is_running() && Instant::now() < until {
                self.runs.poll();
                std::thread::sleep(Duration::from_millis(10));
            }
        }
    }

    fn prompt_key(&mut self, key: KeyEvent) -> Effect {
        let Some(prompt) = self.prompt.take() else {
            return Effect::None;
        };
        match prompt {
            Prompt::Discard(then) => match key.code {
                KeyCode::Char('y') => return self.perform(then),
                KeyCode::Char('s') => {
                    if self.save() {
                        return self.perform(then);
                    }
                }
                KeyCode::Char('n') | KeyCode::Esc => {}
                _ => self.prompt = Some(Prompt::Discard(then)),
            },
            Prompt::StopSweep(stop) => match key.code {
                KeyCode::Enter | KeyCode::Char('y') | KeyCode::Char('k') => {
                    let action = self.runs.cancel();
                    self.act(action);
                    if stop.quit {
                        return self.request_unsaved(Pending::Quit);
                    }
                }
                KeyCode::Char('d') => {
                    let discarding = self.runs.discard();
                    if stop.quit {
                        return self.perform(Pending::Quit);
                    }
                    if discarding {
                        self.say(format!(
                            "discarding the sweep: its finished scenes stay in {}/",
                            stop.out_dir.display()
                        ));
                    }
                }
                KeyCode::Char('n') | KeyCode::Esc => {}
                _ => self.prompt = Some(Prompt::StopSweep(stop)),
            },
            Prompt::DropComments(drop) => match key.code {
                KeyCode::Char('y') => {
                    self.save_to(drop.path, true);
                }
                KeyCode::Char('n') | KeyCode::Esc => self.say("not saved"),
                _ => self.prompt = Some(Prompt::DropComments(drop)),
            },
            Prompt::OverwriteResults(over) => match key.code {
                KeyCode::Char('y') => self.write_results(over.path),
                KeyCode::Char('n') | KeyCode::Esc => self.say("results not written"),
                _ => self.prompt = Some(Prompt::OverwriteResults(over)),
            },
            Prompt::SaveAs(mut line) => match line.handle_key(key) {
                EditOutcome::Editing => self.prompt = Some(Prompt::SaveAs(line)),
                EditOutcome::Cancel => {}
                EditOutcome::Commit => {
                    let path = PathBuf::from(line.text.trim());
                    if line.text.trim().is_empty() {
                        self.complain("no file name given");
                    } else {
                        self.save_to(path, false);
                    }
                }
            },
            Prompt::SaveResults(mut line) => match line.handle_key(key) {
                EditOutcome::Editing => self.prompt = Some(Prompt::SaveResults(line)),
                EditOutcome::Cancel => {}
                EditOutcome::Commit => self.save_results(PathBuf::from(line.text.trim())),
            },
            Prompt::Search(mut line) => match line.handle_key(key) {
                EditOutcome::Editing => self.prompt = Some(Prompt::Search(line)),
                EditOutcome::Cancel => {}
                EditOutcome::Commit => {
                    let action = self.editor.search(&line.text);
                    return self.act(action);
                }
            },
            Prompt::OutDir(mut line) => match line.handle_key(key) {
                EditOutcome::Editing => self.prompt = Some(Prompt::OutDir(line)),
                EditOutcome::Cancel => {}
                EditOutcome::Commit => {
                    let dir = line.text.trim();
                    if dir.is_empty() {
                        self.shared.out_dir = None;
                    } else {
                        self.shared.out_dir = Some(PathBuf::from(dir));
                    }
                    let shown = self.shared.output_dir_shown();
                    self.say(format!("results of the next run go to {shown}/"));
                }
            },
            Prompt::Open(mut line) => match line.handle_key(key) {
                EditOutcome::Editing => self.prompt = Some(Prompt::Open(line)),
                EditOutcome::Cancel => {}
                EditOutcome::Commit => {
                    let path = PathBuf::from(line.text.trim());
                    return self.request(Pending::Open(path));
                }
            },
        }
        Effect::None
    }

    /// Write the current results where `rocklab plot/compare/merge` can read them, asking
    /// first if a file is there (saying whether it holds results of another study).
    fn save_results(&mut self, path: PathBuf) {
        let Some(data) = &self.shared.results else {
            return;
        };
        if path.exists() {
            let identity = crate::sweep::results_identity(&path).ok();
            let scenes = crate::sweep::load_results(&path)
                .ok()
                .map(|r| r.outcomes.len());
            let other_study = identity.and_then(|(hash, name)| {
                (hash != data.results.study_hash)
                    .then(|| name.unwrap_or_else(|| format!("study {hash}")))
            });
            self.prompt = Some(Prompt::OverwriteResults(OverwriteResults {
                path,
                scenes,
                other_study,
            }));
            return;
        }
        self.write_results(path);
    }

    /// Write the current results (atomically), no questions asked.
    fn write_results(&mut self, path: PathBuf) {
        let Some(data) = &self.shared.results else {
            return;
        };
        let written = path
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .map_or(Ok(()), std::fs::create_dir_all)
            .map_err(anyhow::Error::from)
            .and_then(|()| report::save_results(&path, &data.results).map_err(Into::into));
        match written {
            Ok(()) => self.say(format!("results written to {}", path.display())),
            Err(e) => self.complain(format!("cannot write {}: {e:#}", path.display())),
        }
    }

    /// Save to the current path (atomically). False if there is no path, the save waits for
    /// an answer, or the write failed.
    fn save(&mut self) -> bool {
        let Some(path) = self.shared.path.clone() else {
            self.prompt = Some(Prompt::SaveAs(LineEdit::new("study.ron")));
            return false;
        };
        self.save_to(path, false)
    }

    /// Save the study to `path` (which becomes the study's path), keeping the comments and
    /// spelling of the file it came from. If some comments cannot be kept, ask first (unless
    /// `drop_comments`), and keep the file it came from as `<path>.bak`.
    fn save_to(&mut self, path: PathBuf, drop_comments: bool) -> bool {
        // The editor's text keeps what the user typed (`deg(10)`, field order, comments); the
        // comments of the file it came from that the edits removed are lost too.
        let mut written = self
            .shared
            .study
            .to_ron_keeping(Some(&self.editor.tree.text()));
        if let Some(original) = &self.shared.original {
            written.lost = crate::study::writer::lost_comments(original, &written.text);
        }
        if !written.lost.is_empty() && !drop_comments {
            self.prompt = Some(Prompt::DropComments(DropComments {
                path,
                lost: written.lost,
            }));
            return false;
        }
        let mut saved = Ok(());
        if !written.lost.is_empty()
            && let Some(original) = &self.shared.original
        {
            saved = crate::fsutil::write_atomic(&backup_path(&path), original.as_bytes());
        }
        let saved =
            saved.and_then(|()| crate::fsutil::write_atomic(&path, written.text.as_bytes()));
        match saved {
            Ok(()) => {
                self.shared.dirty = false;
                self.shared.original = Some(written.text);
                self.say(format!("saved {}", path.display()));
                self.shared.path = Some(path);
                true
            }
            Err(e) => {
                self.complain(format!("cannot save {}: {e:#}", path.display()));
                false
            }
        }
    }

    /// Feed a key sequence (tests, demos).
    pub fn keys(&mut self, codes: &[KeyCode]) -> Effect {
        let mut effect = Effect::None;
        for code in codes {
            effect = self.handle_key(key_press(*code));
        }
        effect
    }

    /// Type text as individual key presses.
    pub fn type_text(&mut self, text: &str) {
        for c in text.chars() {
            self.handle_key(key_press(KeyCode::Char(c)));
        }
    }
}
