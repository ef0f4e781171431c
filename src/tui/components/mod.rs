//! One component per screen (Study, Run, Results, Scene) plus the help overlay and the prompt
//! line, in the style of gitui and ratatui's component template: each owns its state, turns
//! keys into state changes or an [`Action`] for the app, draws itself from its state and the
//! [`Shared`] state, and says which keys it offers. The app holds what screens share (the open
//! study, its expansion, the results) and carries out the actions.

pub mod help;
pub mod prompt;
pub mod results;
pub mod run;
pub mod scene;
pub mod study;

use super::app::{Options, Screen};
use super::theme::Theme;
use super::widgets::Hint;
use crate::study::{ScenePoint, Study};
use crate::sweep::estimate::{self, CostModel, Strata};
use crossterm::event::KeyEvent;
use prompt::{Pending, Prompt};
use ratatui::Frame;
use ratatui::layout::Rect;
use results::Results;
use std::path::PathBuf;
use std::sync::Arc;

/// The study being edited, validated and expanded once per change.
pub enum Check {
    Ok(Arc<Vec<ScenePoint>>),
    Invalid(String),
    /// A large study is being expanded in the background (`scenes` by its layout); input
    /// goes on meanwhile and the expansion replaces this when it lands.
    Pending {
        scenes: usize,
    },
}

/// Studies of up to this many scenes are expanded at once on the UI thread (milliseconds);
/// larger ones in the background, so that an edit never blocks input.
pub const EXPAND_AT_ONCE: usize = 20_000;

/// State every screen may read.
pub struct Shared {
    pub options: Options,
    pub study: Study,
    pub path: Option<PathBuf>,
    /// The text of the file the study came from (comments, spelling), kept by a save.
    pub original: Option<String>,
    pub dirty: bool,
    pub check: Check,
    /// The results on screen: from the last sweep (finished or cancelled).
    pub results: Option<Results>,
    /// The output directory the user chose (None: the default, see [`Shared::output_dir`]).
    pub out_dir: Option<PathBuf>,
    /// Device variants (groups of scenes) of the expansion, counted once per expansion.
    pub groups: usize,
    /// What the open study's scenes cost, per stratum, from a timed sample or the last run
    /// (None until known).
    pub costs: Option<(Strata, CostModel)>,
    /// Names of the ground-motion records available to `record(names: …)`.
    pub record_names: Vec<String>,
}

impl Shared {
    /// Where a run of the open study writes: the chosen directory, or `out/<study name>/` by
    /// the rule `rocklab run` follows (an error for a name that would leave `out/`).
    pub fn output_dir(&self) -> Result<PathBuf, crate::sweep::OutputError> {
        match &self.out_dir {
            Some(dir) => Ok(dir.clone()),
            None => crate::sweep::default_out_dir(&self.options.out_root, &self.study.name),
        }
    }

    /// The output directory as a screen shows it: the directory, or why there is none.
    pub fn output_dir_shown(&self) -> String {
        match self.output_dir() {
            Ok(dir) => dir.display().to_string(),
            Err(e) => format!("(no directory: {e})"),
        }
    }

    /// Estimated wall time of the whole study (seconds), when a per-scene time is known.
    pub fn estimated_seconds(&self) -> Option<f64> {
        let Check::Ok(points) = &self.check else {
            return None;
        };
        let threads = self
            .options
            .jobs
            .unwrap_or_else(rayon::current_num_threads)
            .max(1);
        let (strata, model) = self.costs.as_ref()?;
        let scenes: usize = strata.counts().iter().sum();
        (scenes == points.len()).then(|| estimate::seconds_before_run(model, strata, threads))
    }
}

/// What a component asks the app to do after a key.
pub enum Action {
    None,
    Show(Screen),
    /// Run the study (refused if a sweep runs or the study is invalid).
    StartRun,
    /// Rerun one scene with its histories and show it.
    OpenScene(Box<ScenePoint>),
    Prompt(Prompt),
    /// Do something that may lose unsaved changes: ask first if it would.
    Request(Pending),
    /// Save the study to its file (or ask for one).
    Save,
    /// The editor produced a new study, already parsed and (if small) expanded, from `text`
    /// (kept: its spelling, order and comments are the study's from now on); `note` says
    /// what the edit did beyond the field edited.
    StudyEdited {
        study: Box<Study>,
        /// None for a large study: it is expanded in the background.
        points: Option<Vec<ScenePoint>>,
        text: String,
        note: Option<String>,
    },
    Say(String),
    Complain(String),
}

/// A key (or keys) of a screen and what it does, as the help overlay lists it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Command {
    pub keys: &'static str,
    pub what: &'static str,
}

pub const fn command(keys: &'static str, what: &'static str) -> Command {
    Command { keys, what }
}

/// A screen of the workbench.
pub trait Component {
    fn handle_key(&mut self, key: KeyEvent, shared: &Shared) -> Action;
    /// Pure: draws from the component's state and the shared state only.
    fn draw(&self, shared: &Shared, theme: Theme, frame: &mut Frame, area: Rect);
    /// Keys the status line offers on this screen, most useful first (narrow terminals cut
    /// the end).
    fn hints(&self, shared: &Shared) -> Vec<Hint>;
    /// Every key of the screen, for the help overlay (which lists each screen's own list,
    /// so a screen's keys are written beside its `handle_key`, never in the overlay).
    fn commands(&self) -> &'static [Command];
    /// True while the component takes every key itself (a line editor is open): the global
    /// keys (q, ?, 1–4, Tab) are off.
    fn captures_keys(&self) -> bool {
        false
    }
}
