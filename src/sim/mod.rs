//! One scene, start to finish: build the model the scene needs, run the event loop (step,
//! locate event, apply jump, restart), track peaks and the energy balance.

use crate::excitation::{Motion, Pulse, RecordMotion, library};
use crate::model::device::DeviceModel;
use crate::model::flexible::FlexibleModel;
use crate::model::rigid::RigidModel;
use crate::model::{Action, Counters, EndReason, Energy, Exact, Peaks, SimModel};
use crate::scene::{Excitation, Impact, RigidBlock, Scene, Structure};
use crate::solver::{Integrator, Options, SolverError, Stats, StepOutcome};
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use std::time::Instant;
use thiserror::Error;

/// Accepted + rejected steps allowed per scene before it is reported as failed.
pub const STEP_BUDGET: u64 = 5_000_000;

#[derive(Clone, Debug, Error, PartialEq)]
pub enum SimError {
    #[error("invalid scene: {0}")]
    Invalid(String),
    #[error("{0}")]
    Solver(#[from] SolverError),
    #[error("{0} is not available yet")]
    Unsupported(&'static str),
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
}

/// A time history: column names and one row per accepted step or event.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct History {
    pub columns: Vec<&'static str>,
    pub rows: Vec<Vec<f64>>,
    /// Located events in order: (time, name).
    pub events: Vec<(f64, &'static str)>,
}

impl History {
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.columns.iter().position(|c| *c == name)?;
        Some(self.rows.iter().map(|r| r[i]).collect())
    }
}

/// Compile the scene's excitation into a ground motion.
pub fn motion_for(scene: &Scene) -> Result<Motion, SimError> {
    let alpha = scene.structure.alpha();
    let p = scene.structure.p();
    match &scene.excitation {
        Excitation::Pulse {
            shape,
            amplitude,
            frequency,
        } => Ok(Motion::Pulse(Pulse::new(
            *shape,
            amplitude.absolute(alpha),
            frequency.absolute(p),
        ))),
        Excitation::MpPulse { tp, pgv, gamma, nu } => Ok(Motion::Pulse(
            Pulse::mavroeidis_papageorgiou(*tp, *pgv, *gamma, *nu),
        )),
        Excitation::Record {
            name,
            scale,
            baseline,
            kinks,
        } => {
            // Parsed once per process and shared by every scene that names it.
            let record = library::global()
                .and_then(|lib| lib.load(name, *baseline))
                .map_err(|e| SimError::Invalid(e.to_string()))?;
            let series = Arc::clone(&record.series);
            let factor = scale.factor(series.pga(), series.pgv());
            if !factor.is_finite() {
                return Err(SimError::Invalid(format!(
                    "record '{name}' is all zeros and cannot be scaled to a target PGA or PGV"
                )));
            }
            Ok(Motion::Record(RecordMotion {
                factor,
                series,
                kinks: *kinks,
            }))
        }
    }
}

pub fn run(scene: &Scene) -> Result<SceneResult, SimError> {
    run_with_history(scene, false).map(|(r, _)| r)
}

pub fn run_with_history(
    scene: &Scene,
    record_history: bool,
) -> Result<(SceneResult, Option<History>), SimError> {
    scene
        .validate()
        .map_err(|e| SimError::Invalid(e.to_string()))?;
    let motion = motion_for(scene)?;
    let mut history = record_history.then(History::default);
    let started = Instant::now();
    let mut form_used = None;
    let mut result = match &scene.structure {
        Structure::Rigid(block) => {
            let device = DeviceModel::new(&scene.device, block.mass, scene.structure.p());
            let block = &RigidBlock {
                form: block.form.resolve(block.alpha, scene.rtol),
                ..block.clone()
            };
            form_used = Some(block.form);
            let mut model =
                RigidModel::new(block, device, scene.impact, &motion, scene.initial_rotation);
            let p = scene.structure.p();
            let a = block.alpha;
            let x = block.size * a;
            // Characteristic magnitudes: rotations ~α, rates ~pα. A flywheel position enters
            // the physics only through the spring deflection δ = x − y, whose scale is the
            // deflection that carries the uplift force m g tanα: resolving y to rtol·Rα left
            // clutch forces with ~1e-3 relative error and peaks drifting by 1% at rtol 1e-6.
            let deflection = match device {
                DeviceModel::Spring { k, .. } => block.mass * crate::excitation::G * a.tan() / k,
                DeviceModel::Clutch(c) => block.mass * crate::excitation::G * a.tan() / c.k,
                _ => x,
            }
            .min(x);
            let scales = [a, p * a, deflection, p * x, deflection, p * x];
            // Energies ~ the work to tip the block over its pivot.
            let energy = block.mass * crate::excitation::G * block.size * a * a;
            let s = Scales {
                state: &scales,
                energy,
            };
            match RigidModel::state_len(&device) {
                6 => drive::<6, _>(&mut model, &motion, scene, s, history.as_mut()),
                8 => drive::<8, _>(&mut model, &motion, scene, s, history.as_mut()),
                _ => drive::<10, _>(&mut model, &motion, scene, s, history.as_mut()),
            }?
        }
        Structure::Flexible(flex) => {
            if scene.impact != Impact::default() {
                return Err(SimError::Invalid(
                    "impact: the flexible structure uses the VVEL impact (MODEL.md); \
                     Housner restitution and Dirac impacts apply to rigid blocks only"
                        .into(),
                ));
            }
            let p = scene.structure.p();
            let device = DeviceModel::new(&scene.device, flex.mass, p);
            let mut model = FlexibleModel::new(flex, device, &motion, scene.initial_rotation)
                .with_exact_contact(scene.exact_contact);
            let (state, energy) = FlexibleModel::scales(flex, &motion, p);
            let s = Scales {
                state: &state,
                energy,
            };
            match FlexibleModel::state_len(&device) {
                8 => drive::<8, _>(&mut model, &motion, scene, s, history.as_mut()),
                10 => drive::<10, _>(&mut model, &motion, scene, s, history.as_mut()),
                _ => drive::<12, _>(&mut model, &motion, scene, s, history.as_mut()),
            }?
        }
    };
    result.peak_rotation_ratio = result.peaks.rotation / scene.structure.alpha();
    result.wall_seconds = started.elapsed().as_secs_f64();
    result.form_used = form_used;
    Ok((result, history))
}

/// Characteristic magnitudes for error control: of the leading state components, and of the
/// energies in the four trailing accumulators.
#[derive(Clone, Copy)]
pub struct Scales<'a> {
    pub state: &'a [f64],
    pub energy: f64,
}

/// The event loop, generic over the model and its state size N. The energy accumulators are
/// error controlled too: with a sharp friction law (η large) an uncontrolled quadrature of the
/// friction work left 5e-3 of the balance unexplained at rtol 1e-6.
fn drive<const N: usize, M: SimModel<N>>(
    model: &mut M,
    motion: &Motion,
    scene: &Scene,
    scales: Scales,
    mut history: Option<&mut History>,
) -> Result<SceneResult, SimError> {
    let duration = scene.duration;
    let controlled = N - 4;
    let atol: [f64; N] = std::array::from_fn(|i| {
        if i < controlled {
            scene.rtol * scales.state[i]
        } else {
            scene.rtol * scales.energy
        }
    });
    let mut integ = Integrator::new(Options {
        rtol: scene.rtol,
        atol,
        h_max: f64::INFINITY,
        controlled,
        max_steps: STEP_BUDGET,
    });
    let mut y = [0.0; N];
    let mut t = 0.0;
    let mut action = model.start(&mut y);
    let e0 = model.energy(&y);
    let initial_stored = e0.structure + e0.inerter;
    let mut energy_scale = initial_stored.abs();
    let mut exact_steps = 0;
    model.observe_point(t, &y);
    if let Some(h) = history.as_deref_mut() {
        h.columns = model.history_columns();
        h.rows.push(model.history_row(t, &y));
    }
    let end_reason = 'run: loop {
        match action {
            Action::Stop(reason) => break reason,
            Action::Idle { until } => {
                let until = until.min(duration);
                model.observe_idle(t, until);
                t = until;
                if t >= duration {
                    break EndReason::Duration;
                }
                action = model.wake(t, &mut y);
                model.observe_point(t, &y);
                // The history shows the end of an idle period (an uplift from rest) as the
                // located events are shown.
                if let Some(h) = history.as_deref_mut() {
                    if action == Action::Continue {
                        h.events.push((t, model.wake_name()));
                    }
                    h.rows.push(model.history_row(t, &y));
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
                };
                if let Some(next) = run.advance_exactly(&mut t, &mut y, &mut exact_steps) {
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
            let outcome = integ.step(model, t_stop)?;
            let dense = *integ.dense().expect("a step was taken");
            model.observe_step(&dense, integ.t());
            t = integ.t();
            y = *integ.y();
            let e = model.energy(&y);
            energy_scale = energy_scale.max(e.input.abs()).max(e.structure + e.inerter);
            match outcome {
                // A model may settle between breakpoints (a flexible column's free vibration
                // decays with no event to mark it).
                StepOutcome::Stepped if t >= motion.end() => {
                    if model.at_rest(t, &y) {
                        record(&mut history, model, t, &y);
                        break 'run EndReason::Rest;
                    }
                    if scene.stop_when_settled && model.settled(&y) {
                        record(&mut history, model, t, &y);
                        break 'run EndReason::Settled;
                    }
                }
                StepOutcome::Stepped => {}
                StepOutcome::Reached => {
                    if t >= duration {
                        record(&mut history, model, t, &y);
                        break 'run EndReason::Duration;
                    }
                    if motion.jumps_at(t) {
                        integ.refresh(model);
                    }
                    if t >= motion.end() && model.at_rest(t, &y) {
                        record(&mut history, model, t, &y);
                        break 'run EndReason::Rest;
                    }
                }
                StepOutcome::Event(index) => {
                    break Run {
                        model: &mut *model,
                        motion,
                        scene,
                        history: history.as_deref_mut(),
                        energy_scale: &mut energy_scale,
                    }
                    .event(index, t, &mut y);
                }
            }
            record(&mut history, model, t, &y);
        };
    };
    let energy = model.energy(&y);
    let imbalance = energy.imbalance() + initial_stored;
    let scale = energy_scale
        .max(energy.dissipated().abs())
        .max(f64::MIN_POSITIVE);
    Ok(SceneResult {
        overturned: end_reason == EndReason::Overturned,
        end_reason,
        end_time: t,
        peaks: model.peaks(),
        peak_rotation_ratio: 0.0,
        counters: model.counters(),
        energy,
        energy_residual: imbalance.abs() / scale,
        stats: Stats {
            exact_steps,
            ..integ.stats
        },
        wall_seconds: 0.0,
        form_used: None,
    })
}

/// What the driver shares with the closed-form path and the event handling.
struct Run<'r, const N: usize, M: SimModel<N>> {
    model: &'r mut M,
    motion: &'r Motion,
    scene: &'r Scene,
    history: Option<&'r mut History>,
    energy_scale: &'r mut f64,
}

impl<const N: usize, M: SimModel<N>> Run<'_, N, M> {
    /// Apply event `index` located at t, as after an integrator step: history rows before and
    /// after the jump, the next action (a stop if the ground has ended and the model is at rest
    /// or settled).
    fn event(&mut self, index: usize, t: f64, y: &mut [f64; N]) -> Action {
        let model = &mut *self.model;
        record(&mut self.history, model, t, y);
        if let Some(h) = self.history.as_deref_mut() {
            h.events.push((t, model.event_name(index)));
        }
        let next = model.on_event(index, t, y);
        model.observe_point(t, y);
        record(&mut self.history, model, t, y);
        if next == Action::Continue && t >= self.motion.end() {
            if model.at_rest(t, y) {
                return Action::Stop(EndReason::Rest);
            }
            if self.scene.stop_when_settled && model.settled(y) {
                return Action::Stop(EndReason::Settled);
            }
        }
        next
    }

    /// Advance in closed form while the model offers it, with the integrator path's stops
    /// (duration, rest, settled) and a history row per interval. `None` when the model has no
    /// closed form in its current phase: the integrator takes over at (t, y).
    fn advance_exactly(
        &mut self,
        t: &mut f64,
        y: &mut [f64; N],
        steps: &mut u64,
    ) -> Option<Action> {
        let duration = self.scene.duration;
        loop {
            let (t1, how) = self.model.advance_exact(*t, duration, y)?;
            *t = t1;
            *steps += 1;
            let e = self.model.energy(y);
            *self.energy_scale = self
                .energy_scale
                .max(e.input.abs())
                .max(e.structure + e.inerter);
            if let Exact::Event(index) = how {
                return Some(self.event(index, *t, y));
            }
            record(&mut self.history, self.model, *t, y);
            if *t >= duration {
                return Some(Action::Stop(EndReason::Duration));
            }
            if *t >= self.motion.end() {
                if self.model.at_rest(*t, y) {
                    return Some(Action::Stop(EndReason::Rest));
                }
                if self.scene.stop_when_settled && self.model.settled(y) {
                    return Some(Action::Stop(EndReason::Settled));
                }
            }
        }
    }
}

fn record<const N: usize, M: SimModel<N>>(
    history: &mut Option<&mut History>,
    model: &M,
    t: f64,
    y: &[f64; N],
) {
    if let Some(h) = history.as_deref_mut() {
        h.rows.push(model.history_row(t, y));
    }
}
