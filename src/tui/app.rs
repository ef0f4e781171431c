//! The workbench as a pure state machine: keys in, state changes and effects out. Drawing reads
//! the state (`draw.rs`); the terminal loop (`mod.rs`) only feeds keys and ticks. Sweeps and
//! single-scene runs happen on background threads that report over channels polled by `tick`.

use super::edit::{EditOutcome, LineEdit};
use super::tree::{self, Node};
use crate::excitation::library::Library;
use crate::report::{self, OverturningMap, Quantity, Spectrum};
use crate::sim::{self, History, SceneResult};
use crate::study::{ScenePoint, Study};
use crate::sweep::{self, Progress, SweepOptions, SweepResults};
use crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Screen {
    Study,
    Run,
    Results,
    Scene,
}

impl Screen {
    pub const ALL: [Screen; 4] = [Screen::Study, Screen::Run, Screen::Results, Screen::Scene];

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

#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Hide everything that depends on the wall clock (rates, ETAs, run-time estimates) so
    /// that frames are reproducible; used by the snapshot tests.
    pub deterministic: bool,
    /// Worker threads for sweeps (None: all cores).
    pub jobs: Option<usize>,
}

/// One row of the Study screen: a node of the study tree.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub depth: usize,
    pub label: String,
    pub path: Vec<usize>,
    /// Inline value (leaf rows) or a short tag (rows whose children follow).
    pub text: String,
    pub leaf: bool,
    /// The row is an element of a list: it can be duplicated or deleted.
    pub in_list: bool,
    /// An optional field that is not set: editing it adds the field to the struct at `path`.
    pub absent: Option<&'static str>,
}

/// Optional study fields that serialisation leaves out when unset, so the tree would not show
/// them: (struct or variant, field, text the editor starts with).
const OPTIONAL_FIELDS: &[(&str, &str, &str)] = &[
    ("study", "description", "\"\""),
    ("study", "map", "(x: frequency, y: amplitude)"),
    ("rigid", "size", "1.0"),
    ("rigid", "p", "2.0"),
    ("flexible", "omega_n", "10.0"),
    ("flexible", "omega_ratio", "5.0"),
    ("inerter", "label", "\"\""),
    ("sequential", "label", "\"\""),
    ("mechanistic", "k_theta", "[1000.0, 10000.0]"),
    ("mechanistic", "clutch_frequency_ratio", "50.0"),
    ("mechanistic", "cbar", "1.0"),
    ("mechanistic", "xi_theta", "0.1"),
    ("mechanistic", "label", "\"\""),
];

/// One line of help per study field, shown under the tree for the selected row.
const FIELD_HELP: &[(&str, &str)] = &[
    ("version", "schema version of the study file (1)"),
    ("name", "study name; `rocklab run` writes to out/<name>"),
    ("description", "free text"),
    (
        "structure",
        "rigid(p or size, alpha, mass, form) or flexible(r0, alpha, xi, omega_n or omega_ratio, mass)",
    ),
    ("p", "frequency parameter p (rad/s), instead of size"),
    ("size", "half-diagonal R (m), instead of p"),
    ("alpha", "slenderness α (rad)"),
    ("mass", "structure mass (kg)"),
    ("form", "exact or slender (small-α) equations"),
    ("r0", "R0 = √(B² + H²) (m)"),
    ("xi", "column damping ratio ξ"),
    ("omega_n", "column natural frequency ωn (rad/s)"),
    ("omega_ratio", "column frequency as ωn/p"),
    (
        "devices",
        "variants: none, inerter(sigma, coupling), sequential(sigma), mechanistic(sigma, …); a: duplicate",
    ),
    ("sigma", "inerter mass ratio σ = mr/m"),
    (
        "k_theta",
        "clutch stiffness kθ (N·m/rad), instead of clutch_frequency_ratio",
    ),
    (
        "clutch_frequency_ratio",
        "clutch frequency √(k/mr) as a multiple of p (default 50)",
    ),
    (
        "cbar",
        "flywheel damping c̄ = c/J (1/s), instead of xi_theta (default 1)",
    ),
    ("xi_theta", "flywheel damping ratio ξθ, instead of cbar"),
    ("friction", "dry friction fμ / (mr·g)"),
    ("eta", "friction transition η (s/rad)"),
    ("play", "gear play up (m)"),
    ("epsilon", "clutch tanh smoothing ε (per rad)"),
    ("rho", "pinion radius ρ (m)"),
    ("reset", "re-engagement reset with play: paper or strict"),
    ("label", "name of the variant in results"),
    (
        "excitation",
        "pulse(shape, amplitude, frequency) or record(names: [\"…\"], scale: …)",
    ),
    ("shape", "sine, cosine, ricker, …"),
    (
        "amplitude",
        "alpha_ratio(A/(g·α)), tan_alpha_ratio(A/(g·tanα)) or g(A/g)",
    ),
    ("frequency", "ratio(ωg/p) or rad_per_sec(ωg)"),
    ("names", "ground-motion records"),
    ("scale", "record scale factors"),
    (
        "quantities",
        "peak_rotation, peak_rotation_ratio, peak_deformation, peak_drift, peak_abs_acceleration, \
         peak_angular_acceleration (rigid blocks: |θ̈|max/p² between impacts)",
    ),
    (
        "spectrum",
        "x axis of the spectra: frequency, amplitude, scale, alpha, size, p, …",
    ),
    (
        "map",
        "overturning map over two axes: (x: frequency, y: amplitude)",
    ),
    (
        "impact",
        "housner(restitution: None or r) or dirac(width: n)",
    ),
    ("duration", "simulated time per scene (s)"),
    ("rtol", "integrator relative tolerance"),
    (
        "stop_when_settled",
        "end a scene once the structure has settled after the motion",
    ),
];

/// Help for a study field, by name (list elements have none).
pub fn field_help(label: &str) -> Option<&'static str> {
    FIELD_HELP
        .iter()
        .find(|(f, _)| *f == label)
        .map(|(_, h)| *h)
}

/// Rows for the optional fields that `node` (a struct named `owner`) does not set.
fn absent_rows(owner: &str, node: &Node, depth: usize, path: &[usize], out: &mut Vec<Row>) {
    let present: Vec<String> = node.children().into_iter().map(|(l, _)| l).collect();
    for (o, field, _) in OPTIONAL_FIELDS {
        if *o == owner && !present.iter().any(|p| p == field) {
            out.push(Row {
                depth,
                label: field.to_string(),
                path: path.to_vec(),
                text: "unset".into(),
                leaf: true,
                in_list: false,
                absent: Some(field),
            });
        }
    }
}

pub struct StudyEditor {
    pub tree: Node,
    pub rows: Vec<Row>,
    pub cursor: usize,
    pub edit: Option<LineEdit>,
    /// Why the last edit was refused (parse error), shown under the editor.
    pub edit_error: Option<String>,
    /// The edit is a new list element, to go after the selected one (`a`).
    pub inserting: bool,
}

/// Result of validating and expanding the study being edited.
pub enum Check {
    Ok(Arc<Vec<ScenePoint>>),
    Invalid(String),
}

pub enum Prompt {
    SaveAs(LineEdit),
    Open(LineEdit),
    /// Jump to the next row whose name contains the text.
    Search(LineEdit),
    /// Write the results on screen as a results file (JSON, as `rocklab run` writes).
    SaveResults(LineEdit),
    /// Unsaved changes would be lost by `then`: y to go on, s to save first, n/Esc to stay.
    Discard(Pending),
}

#[derive(Clone, Debug)]
pub enum Pending {
    Quit,
    Open(PathBuf),
    New,
}

pub struct GroupProgress {
    pub name: String,
    pub total: usize,
    pub done: usize,
    pub failed: usize,
}

enum RunMsg {
    Progress(Progress),
    Done(Box<SweepResults>),
}

pub struct RunState {
    pub points: Arc<Vec<ScenePoint>>,
    pub total: usize,
    pub done: usize,
    pub failed: Vec<usize>,
    /// Failure messages, known once the sweep returns.
    pub failure_messages: Vec<(usize, String)>,
    pub groups: Vec<GroupProgress>,
    group_of: Vec<usize>,
    pub started: Instant,
    pub elapsed: Duration,
    /// None while running; Some(cancelled) once finished.
    pub finished: Option<bool>,
    pub cancel_requested: bool,
    cancel: Arc<AtomicBool>,
    rx: Option<Receiver<RunMsg>>,
}

impl RunState {
    pub fn running(&self) -> bool {
        self.finished.is_none()
    }

    /// Scenes per second and seconds left, from the wall clock.
    pub fn rate_and_eta(&self) -> Option<(f64, f64)> {
        let secs = self.elapsed.as_secs_f64();
        if self.done == 0 || secs <= 0.0 {
            return None;
        }
        let rate = self.done as f64 / secs;
        Some((rate, (self.total - self.done) as f64 / rate))
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ResultsTab {
    Spectra,
    Maps,
    Compare,
}

pub struct ResultsView {
    pub results: SweepResults,
    pub spectra: Vec<Spectrum>,
    pub maps: Vec<OverturningMap>,
    pub quantities: Vec<Quantity>,
    pub tab: ResultsTab,
    pub quantity: usize,
    /// Selected spectrum row (among those of the current quantity).
    pub row: usize,
    /// Cursor along the spectrum axis.
    pub x: usize,
    pub map: usize,
    /// Map cursor (ix, iy).
    pub cell: (usize, usize),
    pub cmp_a: usize,
    pub cmp_b: usize,
    pub cancelled: bool,
}

impl ResultsView {
    fn new(results: SweepResults, cancelled: bool) -> Self {
        let spectra = report::spectra(&results);
        let maps = report::maps(&results);
        let mut quantities: Vec<Quantity> = Vec::new();
        for s in &spectra {
            if !quantities.contains(&s.quantity) {
                quantities.push(s.quantity);
            }
        }
        let mut view = ResultsView {
            results,
            spectra,
            maps,
            quantities,
            tab: ResultsTab::Spectra,
            quantity: 0,
            row: 0,
            x: 0,
            map: 0,
            cell: (0, 0),
            cmp_a: 0,
            cmp_b: 1,
            cancelled,
        };
        if view.spectra.is_empty() && !view.maps.is_empty() {
            view.tab = ResultsTab::Maps;
        }
        view.default_comparison();
        view
    }

    /// Start the comparison on two device variants with the same other parameters (the
    /// spectra names differ only in their first word): sequential vs mechanistic if there,
    /// else the pair with the most points where both survive; else the first two spectra.
    fn default_comparison(&mut self) {
        let rows = self.rows();
        let split = |g: &str| -> (String, String) {
            let g = g.to_lowercase();
            match g.split_once(' ') {
                Some((device, rest)) => (device.to_string(), rest.to_string()),
                None => (g, String::new()),
            }
        };
        let mut best: Option<((bool, usize), usize, usize)> = None;
        for (a, sa) in rows.iter().enumerate() {
            for (b, sb) in rows.iter().enumerate().skip(a + 1) {
                let ((da, ra), (db, rb)) = (split(&sa.group), split(&sb.group));
                if da == db || ra != rb {
                    continue;
                }
                let classic = da.contains("sequential") && db.contains("mechanistic");
                let score = (classic, report::compare(sa, sb).iter().flatten().count());
                if best.as_ref().is_none_or(|(s, _, _)| score > *s) {
                    best = Some((score, a, b));
                }
            }
        }
        (self.cmp_a, self.cmp_b) = match best {
            Some((_, a, b)) => (a, b),
            None => (0, rows.len().saturating_sub(1).min(1)),
        };
    }

    pub fn current_quantity(&self) -> Option<Quantity> {
        self.quantities.get(self.quantity).copied()
    }

    /// The spectra of the current quantity, one per variant (and axis).
    pub fn rows(&self) -> Vec<&Spectrum> {
        let q = self.current_quantity();
        self.spectra
            .iter()
            .filter(|s| Some(s.quantity) == q)
            .collect()
    }

    fn axis_len(&self) -> usize {
        self.rows().iter().map(|s| s.xs.len()).max().unwrap_or(0)
    }

    /// The scene behind the spectrum point under the cursor.
    pub fn point_at_cursor(&self) -> Option<&ScenePoint> {
        match self.tab {
            ResultsTab::Spectra | ResultsTab::Compare => {
                let rows = self.rows();
                let idx = if self.tab == ResultsTab::Compare {
                    self.cmp_b
                } else {
                    self.row
                };
                let s = rows.get(idx)?;
                let x = *s.xs.get(self.x)?;
                self.find_point(&s.group, &[(&s.axis, x)])
            }
            ResultsTab::Maps => {
                let m = self.maps.get(self.map)?;
                let x = *m.xs.get(self.cell.0)?;
                let y = *m.ys.get(self.cell.1)?;
                self.find_point(&m.group, &[(&m.x_axis, x), (&m.y_axis, y)])
            }
        }
    }

    /// The point of a spectrum or map. A spectrum of a study with a map is named after its
    /// group and the other map axis (`"{group} {label}={value}"`): match that too.
    fn find_point(&self, group: &str, coords: &[(&String, f64)]) -> Option<&ScenePoint> {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1e-300);
        let same_group = |p: &ScenePoint| {
            if p.group == group {
                return true;
            }
            let Some(rest) = group
                .strip_prefix(p.group.as_str())
                .and_then(|r| r.strip_prefix(' '))
            else {
                return false;
            };
            rest.rsplit_once('=').is_some_and(|(label, value)| {
                p.coord(label).map(crate::study::fmt_num).as_deref() == Some(value)
            })
        };
        self.results.outcomes.iter().map(|o| &o.point).find(|p| {
            same_group(p)
                && coords.iter().all(|(axis, v)| {
                    p.coords
                        .iter()
                        .any(|(name, value)| name == *axis && close(*value, *v))
                })
        })
    }
}

pub enum SceneState {
    Running(Receiver<Result<(SceneResult, Option<History>), String>>),
    Done(Box<SceneResult>, History),
    Failed(String),
}

pub struct SceneView {
    pub point: ScenePoint,
    pub state: SceneState,
}

pub struct App {
    pub screen: Screen,
    pub options: Options,
    pub study: Study,
    pub path: Option<PathBuf>,
    pub dirty: bool,
    pub editor: StudyEditor,
    pub check: Check,
    pub prompt: Option<Prompt>,
    pub help: bool,
    /// One-line message on the status bar (cleared by the next key).
    pub message: Option<(String, bool)>,
    pub run: Option<RunState>,
    pub results: Option<ResultsView>,
    pub scene: Option<SceneView>,
    /// Mean seconds per scene, from the last run or a calibration (None until known).
    pub seconds_per_scene: Option<f64>,
    calibration: Option<(u64, Receiver<f64>)>,
    generation: u64,
    /// Set by a first Ctrl-C with unsaved changes: a second one quits anyway.
    ctrl_c_armed: bool,
    /// Names of the ground-motion records available to `record(names: …)`.
    pub record_names: Vec<String>,
}

fn key_press(code: KeyCode) -> KeyEvent {
    KeyEvent::new(code, KeyModifiers::NONE)
}

impl App {
    pub fn new(study: Study, path: Option<PathBuf>, options: Options) -> App {
        let tree = Node::from_value(&study).unwrap_or(Node::Unit);
        let mut app = App {
            screen: Screen::Study,
            options,
            study,
            path,
            dirty: false,
            editor: StudyEditor {
                rows: Vec::new(),
                tree,
                cursor: 0,
                edit: None,
                edit_error: None,
                inserting: false,
            },
            check: Check::Invalid(String::new()),
            prompt: None,
            help: false,
            message: None,
            run: None,
            results: None,
            scene: None,
            seconds_per_scene: None,
            calibration: None,
            generation: 0,
            ctrl_c_armed: false,
            record_names: Library::open(Library::default_dir())
                .map(|l| l.names())
                .unwrap_or_default(),
        };
        app.study_changed();
        app
    }

    pub fn file_label(&self) -> String {
        let name = self.path.as_ref().map_or_else(
            || "built-in default study".to_string(),
            |p| p.display().to_string(),
        );
        if self.dirty {
            format!("{name} [+]")
        } else {
            name
        }
    }

    pub fn is_running(&self) -> bool {
        self.run.as_ref().is_some_and(|r| r.running())
    }

    fn say(&mut self, msg: impl Into<String>) {
        self.message = Some((msg.into(), false));
    }

    fn complain(&mut self, msg: impl Into<String>) {
        self.message = Some((msg.into(), true));
    }

    /// Rebuild the tree rows, revalidate and re-expand after the study changed.
    fn study_changed(&mut self) {
        self.editor.tree = Node::from_value(&self.study).unwrap_or(Node::Unit);
        let mut rows = Vec::new();
        // The root is the whole study: list its fields at the top level.
        for (i, (label, child)) in self.editor.tree.children().into_iter().enumerate() {
            flatten(child, 0, &mut vec![i], &label, false, &mut rows);
        }
        absent_rows("study", &self.editor.tree, 0, &[], &mut rows);
        self.editor.rows = rows;
        self.editor.cursor = self
            .editor
            .cursor
            .min(self.editor.rows.len().saturating_sub(1));
        let expanded = match self.study.validate() {
            Ok(()) => self.study.expand().map_err(|e| e.to_string()),
            Err(e) => Err(e.to_string()),
        };
        self.check = match expanded {
            Ok(points) => Check::Ok(Arc::new(points)),
            Err(msg) => Check::Invalid(msg),
        };
        self.generation += 1;
        self.start_calibration();
    }

    /// Time a few scenes of the study in the background for the run-time estimate.
    /// One calibration at a time: while one runs, a newer study waits for it to finish
    /// (its result is then stale and a new one starts), so fast edits do not pile up threads.
    fn start_calibration(&mut self) {
        if self.options.deterministic || self.is_running() || self.calibration.is_some() {
            return;
        }
        let Check::Ok(points) = &self.check else {
            return;
        };
        if points.is_empty() {
            return;
        }
        let n = points.len();
        let sample: Vec<ScenePoint> = [0, n / 2, n - 1]
            .iter()
            .map(|&i| points[i].clone())
            .collect();
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let started = Instant::now();
            for p in &sample {
                let _ = sim::run(&p.scene);
            }
            let _ = tx.send(started.elapsed().as_secs_f64() / sample.len() as f64);
        });
        self.calibration = Some((self.generation, rx));
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
        let per = self.seconds_per_scene?;
        Some(per * points.len() as f64 / threads.min(points.len().max(1)) as f64)
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
        if self.help {
            self.help = false;
            return Effect::None;
        }
        if self.prompt.is_some() {
            return self.prompt_key(key);
        }
        if self.editor.edit.is_some() && self.screen == Screen::Study {
            self.edit_key(key);
            return Effect::None;
        }
        match key.code {
            KeyCode::Char('q') => return self.request(Pending::Quit),
            KeyCode::Char('?') => self.help = true,
            KeyCode::Char('1') => self.screen = Screen::Study,
            KeyCode::Char('2') => self.screen = Screen::Run,
            KeyCode::Char('3') => self.screen = Screen::Results,
            KeyCode::Char('4') => self.screen = Screen::Scene,
            KeyCode::Tab => self.cycle_screen(1),
            KeyCode::BackTab => self.cycle_screen(Screen::ALL.len() - 1),
            _ => match self.screen {
                Screen::Study => self.study_key(key),
                Screen::Run => self.run_key(key),
                Screen::Results => self.results_key(key),
                Screen::Scene => self.scene_key(key),
            },
        }
        Effect::None
    }

    fn ctrl_c(&mut self) -> Effect {
        if self.dirty && !self.ctrl_c_armed {
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

    /// Do `then` now, or ask first if it would lose unsaved changes.
    fn request(&mut self, then: Pending) -> Effect {
        if self.dirty {
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
            Pending::Open(path) => match Study::load(&path) {
                Ok(study) => {
                    self.study = study;
                    self.path = Some(path.clone());
                    self.dirty = false;
                    self.editor.cursor = 0;
                    self.study_changed();
                    self.say(format!("opened {}", path.display()));
                }
                Err(e) => self.complain(e.to_string()),
            },
            Pending::New => {
                self.study = Study::builtin_default();
                self.path = None;
                self.dirty = false;
                self.editor.cursor = 0;
                self.study_changed();
                self.say("new study from the built-in default");
            }
        }
        Effect::None
    }

    /// Cancel background work before leaving, so that the process exits promptly.
    pub fn shutdown(&mut self) {
        if let Some(run) = &self.run {
            run.cancel.store(true, Ordering::Relaxed);
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
            Prompt::SaveAs(mut line) => match line.handle_key(key) {
                EditOutcome::Editing => self.prompt = Some(Prompt::SaveAs(line)),
                EditOutcome::Cancel => {}
                EditOutcome::Commit => {
                    let path = PathBuf::from(line.text.trim());
                    if line.text.trim().is_empty() {
                        self.complain("no file name given");
                    } else {
                        let old = self.path.replace(path);
                        if !self.save() {
                            self.path = old;
                        }
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
                EditOutcome::Commit => self.search(&line.text),
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

    /// Write the current results (atomically) where `rocklab plot/compare/merge` can read them.
    fn save_results(&mut self, path: PathBuf) {
        let Some(view) = &self.results else {
            return;
        };
        let written = path
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .map_or(Ok(()), std::fs::create_dir_all)
            .map_err(anyhow::Error::from)
            .and_then(|()| report::save_results(&path, &view.results));
        match written {
            Ok(()) => self.say(format!("results written to {}", path.display())),
            Err(e) => self.complain(format!("cannot write {}: {e:#}", path.display())),
        }
    }

    /// Move to the next row (after the cursor, wrapping) whose label contains `text`.
    fn search(&mut self, text: &str) {
        let needle = text.trim().to_lowercase();
        let rows = &self.editor.rows;
        let n = rows.len();
        // An exact name first, then any name containing the text.
        let order = || (1..=n).map(|k| (self.editor.cursor + k) % n.max(1));
        let found = order()
            .find(|&i| rows[i].label.to_lowercase() == needle)
            .or_else(|| order().find(|&i| rows[i].label.to_lowercase().contains(&needle)));
        match found {
            Some(i) if !needle.is_empty() => self.editor.cursor = i,
            _ => self.complain(format!("no field named like \"{}\"", text.trim())),
        }
    }

    /// Save to the current path (atomically). False if there is no path or the write failed.
    fn save(&mut self) -> bool {
        let Some(path) = self.path.clone() else {
            self.prompt = Some(Prompt::SaveAs(LineEdit::new("study.ron")));
            return false;
        };
        match self.study.save(&path) {
            Ok(()) => {
                self.dirty = false;
                self.say(format!("saved {}", path.display()));
                true
            }
            Err(e) => {
                self.complain(format!("cannot save {}: {e:#}", path.display()));
                false
            }
        }
    }

    fn study_key(&mut self, key: KeyEvent) {
        let n = self.editor.rows.len();
        let ed = &mut self.editor;
        match key.code {
            KeyCode::Up | KeyCode::Char('k') => ed.cursor = ed.cursor.saturating_sub(1),
            KeyCode::Down | KeyCode::Char('j') => {
                ed.cursor = (ed.cursor + 1).min(n.saturating_sub(1))
            }
            KeyCode::PageUp => ed.cursor = ed.cursor.saturating_sub(10),
            KeyCode::PageDown => ed.cursor = (ed.cursor + 10).min(n.saturating_sub(1)),
            KeyCode::Home | KeyCode::Char('g') => ed.cursor = 0,
            KeyCode::End | KeyCode::Char('G') => ed.cursor = n.saturating_sub(1),
            KeyCode::Enter | KeyCode::Char('e') => {
                if let Some(row) = ed.rows.get(ed.cursor) {
                    let text = match row.absent {
                        Some(field) => OPTIONAL_FIELDS
                            .iter()
                            .find(|(_, f, _)| *f == field)
                            .map_or(String::new(), |(_, _, t)| t.to_string()),
                        None => ed.tree.get(&row.path).map_or(String::new(), tree::to_ron),
                    };
                    ed.edit = Some(LineEdit::new(text));
                    ed.edit_error = None;
                }
            }
            KeyCode::Char('a') => self.duplicate_row(),
            KeyCode::Char('d') => self.delete_row(),
            KeyCode::Char('s') => {
                self.save();
            }
            KeyCode::Char('S') => {
                let current = self
                    .path
                    .as_ref()
                    .map_or("study.ron".into(), |p| p.display().to_string());
                self.prompt = Some(Prompt::SaveAs(LineEdit::new(current)));
            }
            KeyCode::Char('o') => self.prompt = Some(Prompt::Open(LineEdit::new(""))),
            KeyCode::Char('/') => self.prompt = Some(Prompt::Search(LineEdit::new(""))),
            KeyCode::Char('n') => {
                self.request(Pending::New);
            }
            KeyCode::Char('r') => self.start_run(),
            _ => {}
        }
    }

    fn edit_key(&mut self, key: KeyEvent) {
        let Some(line) = self.editor.edit.as_mut() else {
            return;
        };
        match line.handle_key(key) {
            EditOutcome::Editing => {}
            EditOutcome::Cancel => {
                self.editor.edit = None;
                self.editor.edit_error = None;
                self.editor.inserting = false;
            }
            EditOutcome::Commit => {
                let text = line.text.clone();
                let Some(row) = self.editor.rows.get(self.editor.cursor) else {
                    return;
                };
                let inserting = self.editor.inserting;
                let doc = match row.absent {
                    None if inserting => {
                        let (parent, i) = row.path.split_at(row.path.len() - 1);
                        let mut tree = self.editor.tree.clone();
                        if let Some(Node::Seq(items)) = tree.get_mut(parent) {
                            items.insert(i[0] + 1, Node::Raw(text));
                        }
                        tree::to_ron(&tree)
                    }
                    Some(field) => {
                        let mut tree = self.editor.tree.clone();
                        if let Some(fields) = tree.get_mut(&row.path).and_then(tree::fields_mut) {
                            fields.push((field, Node::Raw(text)));
                        }
                        tree::to_ron(&tree)
                    }
                    None => tree::to_ron_with(&self.editor.tree, &row.path, &text),
                };
                // A new element: the cursor moves onto it once it is in.
                let new_path = inserting.then(|| {
                    let mut p = row.path.clone();
                    if let Some(last) = p.last_mut() {
                        *last += 1;
                    }
                    p
                });
                self.apply_document(&doc, true);
                if let Some(path) = new_path
                    && self.editor.edit.is_none()
                    && let Some(i) = self.editor.rows.iter().position(|r| r.path == path)
                {
                    self.editor.cursor = i;
                }
            }
        }
    }

    /// Parse an edited document with the study's own parser. On success the edit is applied
    /// (even if the study is then physically invalid: that is reported, not refused).
    fn apply_document(&mut self, doc: &str, from_editor: bool) {
        match Study::from_ron_str(doc, "edit") {
            Ok(study) => {
                self.study = study;
                self.dirty = true;
                self.editor.edit = None;
                self.editor.edit_error = None;
                self.editor.inserting = false;
                let path = self
                    .editor
                    .rows
                    .get(self.editor.cursor)
                    .map(|r| r.path.clone());
                self.study_changed();
                // Keep the cursor on the same node if it still exists.
                if let Some(path) = path
                    && let Some(i) = self.editor.rows.iter().position(|r| r.path == path)
                {
                    self.editor.cursor = i;
                }
                if let Check::Invalid(msg) = &self.check {
                    let msg = msg.clone();
                    self.complain(msg);
                }
            }
            Err(e) => {
                let msg = strip_position(&e.to_string());
                if from_editor {
                    self.editor.edit_error = Some(msg);
                } else {
                    self.complain(msg);
                }
            }
        }
    }

    /// Add a list element after the selected one: the editor opens on a copy of it, to be
    /// changed before it goes in (two identical device variants would be refused).
    fn duplicate_row(&mut self) {
        let ed = &mut self.editor;
        let Some(row) = ed.rows.get(ed.cursor) else {
            return;
        };
        if !row.in_list {
            self.complain("a adds a list element; this row is not in a list");
            return;
        }
        let text = ed.tree.get(&row.path).map_or(String::new(), tree::to_ron);
        ed.edit = Some(LineEdit::new(text));
        ed.edit_error = None;
        ed.inserting = true;
    }

    /// Delete a list element, or unset a field (the study's default applies, or the parser
    /// says the field is required).
    fn delete_row(&mut self) {
        let Some(row) = self.editor.rows.get(self.editor.cursor) else {
            return;
        };
        if row.in_list {
            self.edit_list(|items, i| {
                items.remove(i);
            });
            return;
        }
        if row.absent.is_some() || row.path.is_empty() {
            return;
        }
        let (parent, i) = row.path.split_at(row.path.len() - 1);
        let mut tree = self.editor.tree.clone();
        if let Some(fields) = tree.get_mut(parent).and_then(tree::fields_mut)
            && i[0] < fields.len()
        {
            fields.remove(i[0]);
            self.apply_document(&tree::to_ron(&tree), false);
        }
    }

    /// Change the list holding the selected row, then reparse the study.
    fn edit_list(&mut self, change: impl FnOnce(&mut Vec<Node>, usize)) {
        let Some(row) = self.editor.rows.get(self.editor.cursor) else {
            return;
        };
        let (parent, i) = row.path.split_at(row.path.len() - 1);
        let mut tree = self.editor.tree.clone();
        if let Some(Node::Seq(items)) = tree.get_mut(parent) {
            change(items, i[0]);
            self.apply_document(&tree::to_ron(&tree), false);
        }
    }

    pub fn start_run(&mut self) {
        if self.is_running() {
            self.complain("a sweep is already running (c cancels it)");
            return;
        }
        let points = match &self.check {
            Check::Ok(points) => points.clone(),
            Check::Invalid(msg) => {
                let msg = format!("cannot run: {msg}");
                self.complain(msg);
                return;
            }
        };
        let mut groups: Vec<GroupProgress> = Vec::new();
        let group_of = points
            .iter()
            .map(|p| match groups.iter().position(|g| g.name == p.group) {
                Some(i) => {
                    groups[i].total += 1;
                    i
                }
                None => {
                    groups.push(GroupProgress {
                        name: p.group.clone(),
                        total: 1,
                        done: 0,
                        failed: 0,
                    });
                    groups.len() - 1
                }
            })
            .collect();
        let cancel = Arc::new(AtomicBool::new(false));
        let (tx, rx) = channel();
        let thread_points = points.clone();
        let study = self.study.clone();
        let thread_cancel = cancel.clone();
        let opts = SweepOptions {
            jobs: self.options.jobs,
            shard: None,
            cache: None,
        };
        std::thread::spawn(move || {
            let progress_tx = Mutex::new(tx.clone());
            let progress = |p| {
                if let Ok(tx) = progress_tx.lock() {
                    let _ = tx.send(RunMsg::Progress(p));
                }
            };
            // The study itself goes along so that spectra and maps know its quantities and axes.
            let results = sweep::run_study(&study, &opts, &thread_cancel, &progress)
                .unwrap_or_else(|_| sweep::run(&thread_points, &opts, &thread_cancel, &progress));
            let _ = tx.send(RunMsg::Done(Box::new(results)));
        });
        self.calibration = None;
        self.run = Some(RunState {
            total: points.len(),
            points,
            done: 0,
            failed: Vec::new(),
            failure_messages: Vec::new(),
            groups,
            group_of,
            started: Instant::now(),
            elapsed: Duration::ZERO,
            finished: None,
            cancel_requested: false,
            cancel,
            rx: Some(rx),
        });
        self.screen = Screen::Run;
    }

    fn cancel_run(&mut self) {
        if let Some(run) = &mut self.run
            && run.running()
        {
            run.cancel.store(true, Ordering::Relaxed);
            run.cancel_requested = true;
            self.say("cancelling: finished scenes are kept");
        }
    }

    fn run_key(&mut self, key: KeyEvent) {
        match key.code {
            KeyCode::Char('r') => self.start_run(),
            KeyCode::Char('c') | KeyCode::Esc => self.cancel_run(),
            KeyCode::Enter if self.results.is_some() => self.screen = Screen::Results,
            _ => {}
        }
    }

    fn results_key(&mut self, key: KeyEvent) {
        let Some(view) = self.results.as_mut() else {
            if key.code == KeyCode::Char('r') {
                self.start_run();
            }
            return;
        };
        let nrows = view.rows().len();
        let nx = view.axis_len();
        let nq = view.quantities.len();
        match key.code {
            KeyCode::Char('s') => view.tab = ResultsTab::Spectra,
            KeyCode::Char('m') => view.tab = ResultsTab::Maps,
            KeyCode::Char('c') => view.tab = ResultsTab::Compare,
            KeyCode::Char('r') => {
                self.start_run();
                return;
            }
            KeyCode::Char('w') => {
                let name = view
                    .results
                    .study
                    .as_ref()
                    .map_or("study", |s| s.name.as_str());
                let default = format!("out/{name}/results.json");
                self.prompt = Some(Prompt::SaveResults(LineEdit::new(default)));
                return;
            }
            KeyCode::Enter => {
                self.open_scene();
                return;
            }
            _ => {}
        }
        let view = self.results.as_mut().expect("checked above");
        match view.tab {
            ResultsTab::Spectra | ResultsTab::Compare => match key.code {
                KeyCode::Left | KeyCode::Char('h') => view.x = view.x.saturating_sub(1),
                KeyCode::Right | KeyCode::Char('l') => {
                    view.x = (view.x + 1).min(nx.saturating_sub(1))
                }
                KeyCode::Home => view.x = 0,
                KeyCode::End => view.x = nx.saturating_sub(1),
                KeyCode::Up | KeyCode::Char('k') => view.row = view.row.saturating_sub(1),
                KeyCode::Down | KeyCode::Char('j') => {
                    view.row = (view.row + 1).min(nrows.saturating_sub(1))
                }
                KeyCode::Char(']') if nq > 0 => {
                    view.quantity = (view.quantity + 1) % nq;
                }
                KeyCode::Char('[') if nq > 0 => {
                    view.quantity = (view.quantity + nq - 1) % nq;
                }
                KeyCode::Char('a') if nrows > 0 => view.cmp_a = (view.cmp_a + 1) % nrows,
                KeyCode::Char('b') if nrows > 0 => view.cmp_b = (view.cmp_b + 1) % nrows,
                KeyCode::Char('x') => std::mem::swap(&mut view.cmp_a, &mut view.cmp_b),
                _ => {}
            },
            ResultsTab::Maps => {
                let nmaps = view.maps.len();
                let (mx, my) = view
                    .maps
                    .get(view.map)
                    .map_or((0, 0), |m| (m.xs.len(), m.ys.len()));
                let (cx, cy) = &mut view.cell;
                match key.code {
                    KeyCode::Left | KeyCode::Char('h') => *cx = cx.saturating_sub(1),
                    KeyCode::Right | KeyCode::Char('l') => {
                        *cx = (*cx + 1).min(mx.saturating_sub(1))
                    }
                    // Rows are drawn with the largest y on top.
                    KeyCode::Up | KeyCode::Char('k') => *cy = (*cy + 1).min(my.saturating_sub(1)),
                    KeyCode::Down | KeyCode::Char('j') => *cy = cy.saturating_sub(1),
                    KeyCode::Char(']') if nmaps > 0 => view.map = (view.map + 1) % nmaps,
                    KeyCode::Char('[') if nmaps > 0 => view.map = (view.map + nmaps - 1) % nmaps,
                    _ => {}
                }
            }
        }
        let view = self.results.as_mut().expect("checked above");
        let nrows = view.rows().len();
        view.row = view.row.min(nrows.saturating_sub(1));
        view.x = view.x.min(view.axis_len().saturating_sub(1));
        view.cmp_a = view.cmp_a.min(nrows.saturating_sub(1));
        view.cmp_b = view.cmp_b.min(nrows.saturating_sub(1));
    }

    /// Run the scene under the results cursor again, recording its histories.
    pub fn open_scene(&mut self) {
        let Some(point) = self
            .results
            .as_ref()
            .and_then(|v| v.point_at_cursor())
            .cloned()
        else {
            self.complain("no scene under the cursor");
            return;
        };
        let (tx, rx) = channel();
        let scene = point.scene.clone();
        std::thread::spawn(move || {
            let outcome = sim::run_with_history(&scene, true).map_err(|e| e.to_string());
            let _ = tx.send(outcome);
        });
        self.scene = Some(SceneView {
            point,
            state: SceneState::Running(rx),
        });
        self.screen = Screen::Scene;
    }

    fn scene_key(&mut self, key: KeyEvent) {
        match key.code {
            KeyCode::Esc | KeyCode::Backspace => self.screen = Screen::Results,
            KeyCode::Char('r') => self.start_run(),
            _ => {}
        }
    }

    // ----- background work -----

    /// Poll background work. Returns true if anything visible changed.
    pub fn tick(&mut self) -> bool {
        let mut changed = false;
        if let Some((generation, rx)) = &self.calibration {
            match rx.try_recv() {
                Ok(per) => {
                    let current = *generation == self.generation;
                    self.calibration = None;
                    if current {
                        self.seconds_per_scene = Some(per);
                        changed = true;
                    } else {
                        self.start_calibration();
                    }
                }
                Err(TryRecvError::Disconnected) => self.calibration = None,
                Err(TryRecvError::Empty) => {}
            }
        }
        changed |= self.poll_run();
        changed |= self.poll_scene();
        changed
    }

    fn poll_run(&mut self) -> bool {
        let Some(run) = self.run.as_mut() else {
            return false;
        };
        let Some(rx) = run.rx.as_ref() else {
            return false;
        };
        let mut changed = false;
        let mut finished = None;
        loop {
            match rx.try_recv() {
                Ok(RunMsg::Progress(Progress::Started { total })) => run.total = total,
                Ok(RunMsg::Progress(Progress::SceneDone { index, ok })) => {
                    run.done += 1;
                    if let Some(&g) = run.group_of.get(index) {
                        run.groups[g].done += 1;
                        if !ok {
                            run.groups[g].failed += 1;
                        }
                    }
                    if !ok {
                        run.failed.push(index);
                    }
                    changed = true;
                }
                Ok(RunMsg::Progress(Progress::Finished { .. })) => {}
                Ok(RunMsg::Done(results)) => {
                    finished = Some(results);
                    break;
                }
                Err(TryRecvError::Empty) => break,
                Err(TryRecvError::Disconnected) => {
                    run.rx = None;
                    run.finished = Some(true);
                    self.complain("the sweep stopped unexpectedly");
                    return true;
                }
            }
        }
        if run.running() {
            run.elapsed = run.started.elapsed();
        }
        if let Some(results) = finished {
            let cancelled = run.cancel.load(Ordering::Relaxed);
            run.finished = Some(cancelled);
            run.rx = None;
            run.failure_messages = results
                .outcomes
                .iter()
                .enumerate()
                .filter_map(|(i, o)| o.result.as_ref().err().map(|e| (i, e.clone())))
                .collect();
            let walls: Vec<f64> = results
                .outcomes
                .iter()
                .filter_map(|o| o.result.as_ref().ok().map(|r| r.wall_seconds))
                .collect();
            if !walls.is_empty() {
                self.seconds_per_scene = Some(walls.iter().sum::<f64>() / walls.len() as f64);
            }
            let done = results.outcomes.len();
            self.results = Some(ResultsView::new(*results, cancelled));
            if cancelled {
                self.say(format!("sweep cancelled: {done} finished scenes kept"));
            } else if self.screen == Screen::Run {
                self.screen = Screen::Results;
            }
            changed = true;
        }
        changed
    }

    fn poll_scene(&mut self) -> bool {
        let Some(view) = self.scene.as_mut() else {
            return false;
        };
        let SceneState::Running(rx) = &view.state else {
            return false;
        };
        view.state = match rx.try_recv() {
            Ok(Ok((result, history))) => {
                SceneState::Done(Box::new(result), history.unwrap_or_default())
            }
            Ok(Err(e)) => SceneState::Failed(e),
            Err(TryRecvError::Empty) => return false,
            Err(TryRecvError::Disconnected) => SceneState::Failed("the scene run stopped".into()),
        };
        true
    }

    /// Tick until background work settles or `deadline` passes (tests and scripts).
    /// True if everything finished in time.
    pub fn wait_idle(&mut self, deadline: Duration) -> bool {
        let until = Instant::now() + deadline;
        loop {
            self.tick();
            let scene_busy = matches!(
                self.scene.as_ref().map(|s| &s.state),
                Some(SceneState::Running(_))
            );
            if !self.is_running() && !scene_busy {
                return true;
            }
            if Instant::now() >= until {
                return false;
            }
            std::thread::sleep(Duration::from_millis(5));
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

/// Rows of the tree in display order. Scalars, short lists of scalars and short structs fit on
/// one row and are edited as one value; bigger nodes get a header row followed by children.
fn flatten(
    node: &Node,
    depth: usize,
    path: &mut Vec<usize>,
    label: &str,
    in_list: bool,
    out: &mut Vec<Row>,
) {
    let text = tree::to_ron(node);
    let children = node.children();
    let scalar_list =
        matches!(node, Node::Seq(items) if items.iter().all(|n| n.children().is_empty()));
    let owner = match node {
        Node::Variant(name, _) => *name,
        _ => "",
    };
    // Structs with optional parameters expand so that the unset ones show; an optional label
    // alone does not justify a row per field.
    let has_optional = OPTIONAL_FIELDS
        .iter()
        .any(|(o, f, _)| *o == owner && *f != "label");
    let inline =
        children.is_empty() || scalar_list || (text.chars().count() <= 40 && !has_optional);
    if inline {
        out.push(Row {
            depth,
            label: label.to_string(),
            path: path.clone(),
            text,
            leaf: true,
            in_list,
            absent: None,
        });
        return;
    }
    out.push(Row {
        depth,
        label: label.to_string(),
        path: path.clone(),
        text: node.tag(),
        leaf: false,
        in_list,
        absent: None,
    });
    let list = node.is_seq();
    for (i, (child_label, child)) in children.into_iter().enumerate() {
        path.push(i);
        flatten(child, depth + 1, path, &child_label, list, out);
        path.pop();
    }
    absent_rows(owner, node, depth + 1, path, out);
}

/// Parse errors of an edit name a position inside the generated one-line document, which
/// means nothing to the user; keep the message and the hint.
fn strip_position(msg: &str) -> String {
    match msg.strip_prefix("edit:") {
        Some(rest) => rest
            .trim_start_matches(|c: char| c.is_ascii_digit() || c == ':')
            .trim_start()
            .to_string(),
        None => msg.to_string(),
    }
}
