//! One scene, start to finish: build the model the scene needs, run the event loop (step,
//! locate event, apply jump, restart), track peaks and the energy balance.

use crate::excitation::{
    G, Gravity, Horizontal, KinkPolicy, Library, Motion, Pulse, RecordMotion, Vertical,
};
pub use crate::model::column::{ColumnInfo, EnergyRole, HistoryColumn};
use crate::model::device::{DeviceModel, Flywheels};
use crate::model::flexible::FlexibleModel;
use crate::model::rigid::RigidModel;
use crate::model::{Action, ClosedFormEnd, Counters, EndReason, Energy, SimModel};
pub use crate::model::{Measures, Peaks};
use crate::scene::{Excitation, Impact, RigidBlock, Scene, Structure, VerticalMotion};
use crate::solver::{Integrator, Method, Options, SolverError, Stats, StepOutcome};
use history::Recorder;
pub use history::{MAX_GRID_ROWS, Sampling, auto_step};
pub use quantity::{Quantity, QuantityInfo};

/// The integrator's work counters, as reported with a scene's result.
pub type SceneStats = Stats;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use thiserror::Error;

pub mod check;
mod history;
mod quantity;

/// Accepted + rejected steps allowed per scene before it is reported as failed.
pub const STEP_BUDGET: u64 = 5_000_000;

#[derive(Clone, Debug, Error, PartialEq)]
pub enum SimError {
    #[error("invalid scene: {0}")]
    Invalid(String),
    // Transparent: the solver's message once, not "msg: msg" through the error chain.
    #[error(transparent)]
    Solver(#[from] SolverError),
    #[error("stopped (cancelled while running)")]
    Cancelled,
    #[error(
        "the history reached its cap of {0} rows at t = {1:.6} s (an event every few steps, or \
         --dt steps over a long run); raise the cap with --max-history-rows, give a coarser \
         --dt or a shorter --duration"
    )]
    HistoryCap(usize, f64),
    #[error(
        "wall-clock limit of {0} s per scene reached at t = {1:.6} s (raise it with --scene-time-limit)"
    )]
    TimeLimit(f64, f64),
}

/// Everything a scene produces besides its histories.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneResult {
    pub overturned: bool,
    pub end_reason: EndReason,
    pub end_time: f64,
    pub peaks: Peaks,
    /// |θ|max / α.
    pub peak_rotation_ratio: f64,
    pub counters: Counters,
    /// Energy partition at the end of the run.
    pub energy: Energy,
    /// |input − Δstored − dissipated| / energy scale of the run.
    pub energy_residual: f64,
    pub stats: Stats,
    pub wall_seconds: f64,
    /// Equations integrated for a rigid block (`auto` resolved); None for other structures.
    #[serde(default)]
    pub form_used: Option<crate::scene::Form>,
    /// What was computed ([`Bounds::measures`]); peaks and energies not measured read 0.
    #[serde(default)]
    pub measured: Measures,
}

impl SceneResult {
    /// A result made of its peaks alone, without a run: it ended at `end_time`, overturned or
    /// at the end of its duration, every measure computed, no energies, counters or solver
    /// statistics. For tests and made-up results that exercise aggregation, reports and
    /// drawing.
    pub fn from_peaks(overturned: bool, end_time: f64, peaks: Peaks, rotation_ratio: f64) -> Self {
        SceneResult {
            overturned,
            end_reason: if overturned {
                EndReason::Overturned
            } else {
                EndReason::Duration
            },
            end_time,
            peaks,
            peak_rotation_ratio: rotation_ratio,
            counters: Counters::default(),
            energy: Energy::default(),
            energy_residual: 0.0,
            stats: Stats::default(),
            wall_seconds: 0.0,
            form_used: None,
            measured: Measures::ALL,
        }
    }
}

/// A time history: column names and one row per sample time of its [`Sampling`], plus two
/// rows (before and after the jump) at each event.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct History {
    pub columns: Vec<HistoryColumn>,
    pub rows: Vec<Vec<f64>>,
    /// Located events in order: (time, name).
    pub events: Vec<(f64, &'static str)>,
}

impl History {
    pub fn column(&self, column: HistoryColumn) -> Option<Vec<f64>> {
        let i = self.columns.iter().position(|c| *c == column)?;
        Some(self.rows.iter().map(|r| r[i]).collect())
    }
}

/// Compile the scene's excitation into a ground motion, resolving a record's name in
/// `library`.
pub fn motion_for(scene: &Scene, library: &Library) -> Result<Motion, SimError> {
    let (horizontal, factor) = horizontal_for(scene, library)?;
    let Some(vertical) = &scene.vertical else {
        return Ok(Motion::horizontal(horizontal));
    };
    let alpha = scene.structure.alpha();
    let p = scene.structure.p();
    let vertical = match vertical {
        VerticalMotion::Constant(c) => Vertical::Constant(c * G),
        VerticalMotion::Ratio(r) => Vertical::Ratio(*r, horizontal.clone()),
        VerticalMotion::Pulse {
            shape,
            amplitude,
            frequency,
        } => Vertical::Own(Horizontal::Pulse(Pulse::new(
            *shape,
            amplitude.absolute(alpha),
            frequency.absolute(p),
        ))),
        VerticalMotion::Record(file) => {
            let baseline = matches!(scene.excitation, Excitation::Record { baseline: true, .. });
            let record = library
                .load(file, baseline)
                .map_err(|e| SimError::Invalid(format!("vertical record '{file}': {e}")))?;
            Vertical::Own(Horizontal::Record(RecordMotion {
                factor,
                series: Arc::clone(&record.series),
                kinks: KinkPolicy::default(),
            }))
        }
    };
    let gravity = Gravity::with_vertical(vertical);
    gravity.check_contact().map_err(SimError::Invalid)?;
    Ok(Motion::with_gravity(horizontal, gravity))
}

/// The scene's horizontal ground motion and the factor its record is scaled by (1 for a
/// pulse), which a vertical record shares.
fn horizontal_for(scene: &Scene, library: &Library) -> Result<(Horizontal, f64), SimError> {
    let alpha = scene.structure.alpha();
    let p = scene.structure.p();
    match &scene.excitation {
        Excitation::Pulse {
            shape,
            amplitude,
            frequency,
        } => Ok((
            Horizontal::Pulse(Pulse::new(
                *shape,
                amplitude.absolute(alpha),
                frequency.absolute(p),
            )),
            1.0,
        )),
        Excitation::MpPulse { tp, pgv, gamma, nu } => Ok((
            Horizontal::Pulse(Pulse::mavroeidis_papageorgiou(*tp, *pgv, *gamma, *nu)),
            1.0,
        )),
        Excitation::Record {
            name,
            scale,
            baseline,
            kinks,
        } => {
            // Parsed once per library and shared by every scene that names it.
            let record = library
                .load(name, *baseline)
                .map_err(|e| SimError::Invalid(e.to_string()))?;
            let series = Arc::clone(&record.series);
            let (pga, pgv) = (series.pga(), series.pgv());
            let factor = scale.factor(pga, pgv, alpha, p);
            if !factor.is_finite() {
                let corrected = if *baseline {
                    " after baseline correction"
                } else {
                    ""
                };
                return Err(SimError::Invalid(
                    if !(pga.is_finite() && pgv.is_finite()) {
                        format!(
                            "record '{name}' cannot be scaled: its PGA or PGV overflows{corrected} \
                         (values near {:.1e} m/s²); check the file's units and values",
                            series.samples().iter().fold(0.0f64, |m, a| m.max(a.abs()))
                        )
                    } else if pga == 0.0 || pgv == 0.0 {
                        format!(
                            "record '{name}' is all zeros{corrected} and cannot be scaled to a \
                         target PGA or PGV"
                        )
                    } else {
                        format!(
                            "record '{name}' cannot be scaled by {factor:e}: the factor overflows \
                         (PGA {pga:.3e} m/s², PGV {pgv:.3e} m/s)"
                        )
                    },
                ));
            }
            Ok((
                Horizontal::Record(RecordMotion {
                    factor,
                    series,
                    kinks: *kinks,
                }),
                factor,
            ))
        }
    }
}

/// Run one scene; a record it names is resolved in `library` (a scene depends on nothing
/// else).
pub fn run(scene: &Scene, library: &Library) -> Result<SceneResult, SimError> {
    run_with_history(scene, library, false).map(|(r, _)| r)
}

/// Limits on one running scene besides the step budget (which counts closed-form steps too):
/// a cancel flag and a wall-clock limit, checked inside the step loops.
#[derive(Clone, Copy, Debug, Default)]
pub struct Bounds<'a> {
    pub cancel: Option<&'a AtomicBool>,
    pub time_limit: Option<Duration>,
    /// The optional quantities to compute (default: all).
    pub measures: Measures,
    /// Measure the time in the integrator's stages (`Stats::stage_nanos`; the bench).
    pub time_stages: bool,
    /// Most rows a recorded history may hold (None: [`DEFAULT_HISTORY_ROWS`]): a run that
    /// would record more stops with [`SimError::HistoryCap`] instead of filling memory.
    pub history_rows: Option<usize>,
}

/// Rows a recorded history holds at most unless raised (`simulate --max-history-rows`): about
/// 200 MB for the widest rows.
pub const DEFAULT_HISTORY_ROWS: usize = 2_000_000;

/// The bounds of a scene that started at `started`, checked every few steps.
struct Watch<'a> {
    bounds: Bounds<'a>,
    started: Instant,
    checks: std::cell::Cell<u64>,
}

impl Watch<'_> {
    /// An error once `steps` (integrator steps, rejected ones and closed-form intervals)
    /// exceed the budget, the scene is cancelled, or its time is up.
    fn check(&self, steps: u64, t: f64) -> Result<(), SimError> {
        if steps >= STEP_BUDGET {
            return Err(SolverError::StepBudget {
                t,
                budget: STEP_BUDGET,
            }
            .into());
        }
        // Reading the clock costs ~20 ns; every 64th check (the first included) is plenty.
        let n = self.checks.get();
        self.checks.set(n + 1);
        if n.is_multiple_of(64) {
            if self
                .bounds
                .cancel
                .is_some_and(|c| c.load(Ordering::Relaxed))
            {
                return Err(SimError::Cancelled);
            }
            if let Some(limit) = self.bounds.time_limit
                && self.started.elapsed() > limit
            {
                return Err(SimError::TimeLimit(limit.as_secs_f64(), t));
            }
        }
        Ok(())
    }
}

/// [`run`] within `bounds`.
pub fn run_bounded(
    scene: &Scene,
    library: &Library,
    bounds: Bounds,
) -> Result<SceneResult, SimError> {
    run_with_history_bounded(scene, library, false, bounds).map(|(r, _)| r)
}

pub fn run_with_history(
    scene: &Scene,
    library: &Library,
    record_history: bool,
) -> Result<(SceneResult, Option<History>), SimError> {
    run_with_history_bounded(scene, library, record_history, Bounds::default())
}

pub fn run_with_history_bounded(
    scene: &Scene,
    library: &Library,
    record_history: bool,
    bounds: Bounds,
) -> Result<(SceneResult, Option<History>), SimError> {
    run_sampled(
        scene,
        library,
        record_history.then_some(&Sampling::Steps),
        bounds,
    )
}

/// The scene a history is recorded from: the whole duration the scene asks for (the
/// settled-tail cut makes sweeps fast; a history shows the tail).
pub fn history_scene(scene: &Scene) -> Scene {
    Scene {
        stop_when_settled: false,
        ..scene.clone()
    }
}

/// Run `scene` as it is and record its history with `sampling` (see [`history_scene`] for a
/// scene view's full length).
pub fn run_history(
    scene: &Scene,
    library: &Library,
    sampling: &Sampling,
) -> Result<(SceneResult, History), SimError> {
    let (result, history) = run_sampled(scene, library, Some(sampling), Bounds::default())?;
    Ok((result, history.unwrap_or_default()))
}

/// [`run_bounded`], recording a history when `sampling` is given.
pub fn run_sampled(
    scene: &Scene,
    library: &Library,
    sampling: Option<&Sampling>,
    bounds: Bounds,
) -> Result<(SceneResult, Option<History>), SimError> {
    scene
        .validate()
        .map_err(|e| SimError::Invalid(e.to_string()))?;
    let motion = motion_for(scene, library)?;
    if let Some(Sampling::Uniform(dt)) = sampling
        && !(*dt > 0.0 && scene.duration / dt <= MAX_GRID_ROWS)
    {
        return Err(SimError::Invalid(format!(
            "history sample step {dt} s: give a positive step of at least {:.3e} s \
             (duration / {MAX_GRID_ROWS:.0})",
            scene.duration / MAX_GRID_ROWS
        )));
    }
    let rows = bounds.history_rows.unwrap_or(DEFAULT_HISTORY_ROWS);
    let mut history =
        sampling.map(|s| Recorder::new(s, scene.duration, &motion).with_max_rows(rows));
    let started = Instant::now();
    let watch = &Watch {
        bounds,
        started,
        checks: Default::default(),
    };
    let mut form_used = None;
    // The energy accumulators only for a run that reports the energy or records a history
    // (whose rows show it); see [`drive`].
    let ledger = bounds.measures.energy || sampling.is_some();
    let mut result = match &scene.structure {
        Structure::Rigid(block) => {
            let device = DeviceModel::new(
                &scene.device,
                block.mass,
                scene.structure.p(),
                motion.gravity().g(),
            );
            let block = &RigidBlock {
                form: block.form.resolve(block.alpha, scene.rtol),
                ..block.clone()
            };
            form_used = Some(block.form);
            let mut model =
                RigidModel::new(block, device, scene.impact, &motion, scene.initial_rotation)
                    .with_ledger(ledger);
            model.set_measures(bounds.measures);
            let h = history.as_mut();
            // Two coordinates (θ, θ̇), two per flywheel, four accumulators with the ledger.
            match (device.flywheels(), ledger) {
                (Flywheels::Zero, false) => drive::<2, _>(&mut model, &motion, scene, h, watch),
                (Flywheels::One, false) => drive::<4, _>(&mut model, &motion, scene, h, watch),
                (Flywheels::Two, false) => drive::<6, _>(&mut model, &motion, scene, h, watch),
                (Flywheels::Zero, true) => drive::<6, _>(&mut model, &motion, scene, h, watch),
                (Flywheels::One, true) => drive::<8, _>(&mut model, &motion, scene, h, watch),
                (Flywheels::Two, true) => drive::<10, _>(&mut model, &motion, scene, h, watch),
            }?
        }
        Structure::Flexible(flex) => {
            if scene.impact != Impact::default() {
                return Err(SimError::Invalid(
                    "impact: the flexible structure uses the VVEL impact (docs/MODEL.md); \
                     Housner restitution and Dirac impacts apply to rigid blocks only"
                        .into(),
                ));
            }
            let p = scene.structure.p();
            let device = DeviceModel::new(&scene.device, flex.mass, p, motion.gravity().g());
            let mut model = FlexibleModel::new(flex, device, &motion, scene.initial_rotation)
                .with_ledger(ledger)
                .with_closed_form_contact(scene.closed_form_contact);
            model.set_measures(bounds.measures);
            let h = history.as_mut();
            // Four coordinates (u, θ and their rates), two per flywheel, four accumulators.
            match (device.flywheels(), ledger) {
                (Flywheels::Zero, false) => drive::<4, _>(&mut model, &motion, scene, h, watch),
                (Flywheels::One, false) => drive::<6, _>(&mut model, &motion, scene, h, watch),
                (Flywheels::Two, false) => drive::<8, _>(&mut model, &motion, scene, h, watch),
                (Flywheels::Zero, true) => drive::<8, _>(&mut model, &motion, scene, h, watch),
                (Flywheels::One, true) => drive::<10, _>(&mut model, &motion, scene, h, watch),
                (Flywheels::Two, true) => drive::<12, _>(&mut model, &motion, scene, h, watch),
            }?
        }
    };
    result.peak_rotation_ratio = result.peaks.rotation / scene.structure.alpha();
    result.wall_seconds = started.elapsed().as_secs_f64();
    result.form_used = form_used;
    result.measured = bounds.measures;
    Ok((result, history.map(Recorder::finish)))
}

/// The integrator is instantiated for the state sizes the models have (structure coordinates,
/// two per flywheel, four accumulators with the energy ledger): [`run_sampled`]'s dispatch
/// matches every (flywheels, ledger) pair, so a device with a new state size does not compile
/// until it has its instance. A dispatch arm with the wrong N is refused here, loudly,
/// instead of running.
fn no_instance(n: usize, model_len: usize) -> SimError {
    SimError::Invalid(format!(
        "internal: a model with {model_len} state components dispatched to the integrator \
         instance for {n} (fix sim::run_sampled's dispatch)"
    ))
}

/// The event loop, generic over the model and its state size N. Only the physical state is
/// error controlled; the energy accumulators, when the model has them, are quadratures riding
/// on its steps (`atol` infinite). So a run that asks for the energy takes the very steps of one
/// that does not (which leaves the accumulators out: N = 2 instead of 6 for a bare block),
/// and every result both report is bit-identical. (They were controlled before: with a sharp
/// friction law, η large, the uncontrolled friction work then left more of the balance
/// unexplained; the energy-balance tests of `tests/rigid.rs` and `tests/flexible.rs` bound the residual.)
fn drive<const N: usize, M: SimModel<N>>(
    model: &mut M,
    motion: &Motion,
    scene: &Scene,
    mut history: Option<&mut Recorder>,
    watch: &Watch,
) -> Result<SceneResult, SimError> {
    if model.state_len() != N {
        return Err(no_instance(N, model.state_len()));
    }
    let duration = scene.duration;
    let state_scales = model.tolerance_scales();
    let controlled = state_scales.len();
    let atol: [f64; N] = std::array::from_fn(|i| {
        state_scales
            .get(i)
            .map_or(f64::INFINITY, |scale| scene.rtol * scale)
    });
    let mut integ = Integrator::new(Options {
        controlled,
        max_steps: STEP_BUDGET,
        time_stages: watch.bounds.time_stages,
        method: match scene.method.resolve(scene) {
            crate::scene::Method::Dop853 => Method::Dop853,
            _ => Method::Dp54,
        },
        ..Options::new(scene.rtol, atol)
    });
    let mut y = [0.0; N];
    let mut t = 0.0;
    let mut action = model.start(&mut y);
    // The ledger's per-step evaluation only when asked (a history keeps the accumulators
    // without it).
    let ledger = watch.bounds.measures.energy;
    let e0 = model.energy(&y);
    let initial_stored = e0.structure + e0.inerter;
    let mut energy_scale = initial_stored.abs();
    let mut closed_form_steps = 0;
    let mut stalls = 0;
    model.observe_point(t, &y);
    if let Some(h) = history.as_deref_mut() {
        h.start(model, t, &y);
    }
    let end_reason = 'run: loop {
        match action {
            Action::Stop(reason) => break reason,
            Action::Idle { until } => {
                let until = until.min(duration);
                model.observe_idle(t, until);
                if let Some(h) = history.as_deref_mut() {
                    h.hold(model, until, &y);
                }
                t = until;
                if t >= duration {
                    break EndReason::Duration;
                }
                action = model.wake(t, &mut y);
                model.observe_point(t, &y);
                // The history shows the end of an idle period (an uplift from rest) as the
                // located events are shown.
                if let Some(h) = history.as_deref_mut() {
                    if action == Action::Continue
                        && let Some(name) = model.wake_name()
                    {
                        h.event(t, name);
                    }
                    h.exact(model, t, &y);
                }
                continue;
            }
            Action::Continue => {
                let mut run = Run {
                    model: &mut *model,
                    motion,
                    scene,
                    history: history.as_deref_mut(),
                    energy_scale: &mut energy_scale,
                    ledger,
                };
                let integrated = integ.stats.steps + integ.stats.rejected;
                if let Some(next) = run.advance_closed_form(
                    &mut t,
                    &mut y,
                    &mut closed_form_steps,
                    integrated,
                    watch,
                )? {
                    action = next;
                    continue;
                }
                integ.restart(model, t, y)
            }
        }
        action = loop {
            let breakpoint = if model.events_read_ground() {
                motion.next_kink(t)
            } else {
                motion.next_breakpoint(t)
            };
            let t_stop = breakpoint.map_or(duration, |b| b.min(duration));
            let start = (t, y, *integ.derivative());
            let outcome = integ.step(model, t_stop)?;
            // No step is taken when the stop lies within rounding of t (intervals below what
            // f64 resolves at this t): nothing to observe then, but it counts as work. The
            // dense output (DOP853's three extra stages) is built only for a step whose
            // interior someone reads: the history, a located event, or the peaks.
            let dense = if !integ.stepped() {
                stalls += 1;
                None
            } else if integ.dense().is_some()
                || history.is_some()
                || model.step_reads_interior(
                    (start.0, &start.1, &start.2),
                    (integ.t(), integ.y(), integ.derivative()),
                )
            {
                integ.ensure_dense(model);
                let dense = integ.dense();
                if let Some(dense) = dense {
                    model.observe_step(dense, integ.t());
                }
                dense
            } else {
                None
            };
            watch.check(
                integ.stats.steps + integ.stats.rejected + closed_form_steps + stalls,
                integ.t(),
            )?;
            t = integ.t();
            y = *integ.y();
            if let Some(h) = history.as_deref_mut() {
                let at_event = matches!(outcome, StepOutcome::Event(_));
                h.step(model, dense, t, &y, at_event);
                h.within_cap(t)?;
            }
            if ledger {
                let e = model.energy(&y);
                energy_scale = energy_scale.max(e.input.abs()).max(e.structure + e.inerter);
            }
            match outcome {
                StepOutcome::Event(index) => {
                    break Run {
                        model: &mut *model,
                        motion,
                        scene,
                        history: history.as_deref_mut(),
                        energy_scale: &mut energy_scale,
                        ledger,
                    }
                    .event(index, t, &mut y);
                }
                StepOutcome::Reached if t >= duration => break 'run EndReason::Duration,
                StepOutcome::Reached if motion.jumps_at(t) => integ.refresh(model),
                StepOutcome::Reached | StepOutcome::Stepped => {}
            }
            // A model may settle between breakpoints (a flexible column's free vibration decays
            // with no event to mark it).
            if let Some(reason) = stop_after_ground(model, motion, scene, t, &y) {
                break 'run reason;
            }
        };
    };
    if let Some(h) = history {
        h.end(model, t, &y, end_reason, duration);
    }
    let (energy, energy_residual) = if ledger {
        let energy = model.energy(&y);
        let imbalance = energy.imbalance() + initial_stored;
        let scale = energy_scale
            .max(energy.dissipated().abs())
            .max(f64::MIN_POSITIVE);
        (energy, imbalance.abs() / scale)
    } else {
        (Energy::default(), 0.0)
    };
    Ok(SceneResult {
        overturned: end_reason == EndReason::Overturned,
        end_reason,
        end_time: t,
        peaks: model.peaks(),
        peak_rotation_ratio: 0.0,
        counters: model.counters(),
        energy,
        energy_residual,
        stats: Stats {
            closed_form_steps,
            ..integ.stats
        },
        wall_seconds: 0.0,
        form_used: None,
        measured: Measures::ALL,
    })
}

/// What the driver shares with the closed-form path and the event handling.
struct Run<'r, const N: usize, M: SimModel<N>> {
    model: &'r mut M,
    motion: &'r Motion,
    scene: &'r Scene,
    history: Option<&'r mut Recorder>,
    energy_scale: &'r mut f64,
    /// Whether the energy ledger is asked for.
    ledger: bool,
}

impl<const N: usize, M: SimModel<N>> Run<'_, N, M> {
    /// Apply event `index` located at t, as after an integrator step: history rows before and
    /// after the jump, the next action (a stop if the ground has ended and the model is at rest
    /// or settled).
    fn event(&mut self, index: usize, t: f64, y: &mut [f64; N]) -> Action {
        let model = &mut *self.model;
        if let Some(h) = self.history.as_deref_mut() {
            h.exact(model, t, y);
            h.event(t, model.event_name(index));
        }
        let next = model.on_event(index, t, y);
        model.observe_point(t, y);
        if let Some(h) = self.history.as_deref_mut() {
            h.exact(model, t, y);
        }
        if next == Action::Continue
            && let Some(reason) = stop_after_ground(model, self.motion, self.scene, t, y)
        {
            return Action::Stop(reason);
        }
        next
    }

    /// Advance in closed form while the model offers it, with the integrator path's stops
    /// (duration, rest, settled) and a history row per interval. `None` when the model has no
    /// closed form in its current phase: the integrator takes over at (t, y).
    fn advance_closed_form(
        &mut self,
        t: &mut f64,
        y: &mut [f64; N],
        steps: &mut u64,
        integrated: u64,
        watch: &Watch,
    ) -> Result<Option<Action>, SimError> {
        let duration = self.scene.duration;
        loop {
            // On a grid, intervals end at its sample times too (an exact state there).
            let stop = self
                .history
                .as_deref()
                .and_then(Recorder::next_stop)
                .map_or(duration, |s| s.min(duration));
            let Some((t1, how)) = self.model.advance_closed_form(*t, stop, y) else {
                return Ok(None);
            };
            *t = t1;
            *steps += 1;
            watch.check(*steps + integrated, *t)?;
            if let Some(h) = self.history.as_deref() {
                h.within_cap(*t)?;
            }
            if self.ledger {
                let e = self.model.energy(y);
                *self.energy_scale = self
                    .energy_scale
                    .max(e.input.abs())
                    .max(e.structure + e.inerter);
            }
            if let ClosedFormEnd::Event(index) = how {
                return Ok(Some(self.event(index, *t, y)));
            }
            if let Some(h) = self.history.as_deref_mut() {
                h.interval_end(&*self.model, *t, y);
            }
            if *t >= duration {
                return Ok(Some(Action::Stop(EndReason::Duration)));
            }
            if let Some(reason) = stop_after_ground(self.model, self.motion, self.scene, *t, y) {
                return Ok(Some(Action::Stop(reason)));
            }
        }
    }
}

/// The one stop check of the event loop, after every step, event and closed-form interval:
/// once the ground has stopped, the run ends when the model is at rest or, if the scene asks
/// for it, settled (no reachable motion can raise a peak).
fn stop_after_ground<const N: usize, M: SimModel<N>>(
    model: &M,
    motion: &Motion,
    scene: &Scene,
    t: f64,
    y: &[f64; N],
) -> Option<EndReason> {
    if t < motion.end() {
        None
    } else if model.at_rest(t, y) {
        Some(EndReason::Rest)
    } else if scene.stop_when_settled && model.settled(y) {
        Some(EndReason::Settled)
    } else {
        None
    }
}
