//! Equations of motion, event functions and jumps of each structure family. A model is an
//! [`OdeSystem`] plus the discrete logic the simulation driver calls between steps.

pub mod clutch;
pub mod column;
pub mod contact;
pub mod device;
pub mod flexible;
pub mod rigid;
pub mod sdof;
pub mod shell;

use crate::solver::search::{brent_max, illinois_root, newton_root};
use crate::solver::{Dense, OdeSystem};
use column::HistoryColumn;
use serde::{Deserialize, Serialize};

/// Why a simulation ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EndReason {
    Duration,
    Overturned,
    Rest,
    /// The ground had stopped and no reachable motion could raise any peak
    /// (`Scene::stop_when_settled`).
    Settled,
}

impl EndReason {
    /// The reason in words, as results files name it (`end_reason`).
    pub fn name(self) -> &'static str {
        match self {
            EndReason::Duration => "duration",
            EndReason::Overturned => "overturned",
            EndReason::Rest => "rest",
            EndReason::Settled => "settled",
        }
    }
}

/// What the driver does after the model handled an event.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Action {
    /// Restart the integrator at the (possibly modified) state.
    Continue,
    /// Nothing moves until this time: skip there and call [`SimModel::wake`].
    Idle {
        until: f64,
    },
    Stop(EndReason),
}

/// How a closed-form advance ([`SimModel::advance_closed_form`]) ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClosedFormEnd {
    /// The end of the interval was reached.
    Reached,
    /// Event `index` was located at the new time; its jump is not applied yet.
    Event(usize),
}

/// Energy partition at one instant (J), following the paper's Fig. 15.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Energy {
    /// Work of the ground motion, ∫ −m a_g Ẋ dt (relative frame).
    pub input: f64,
    /// Kinetic + potential (+ column strain) energy of the structure.
    pub structure: f64,
    /// Flywheel kinetic energy (coupled or explicit) and clutch spring energy.
    pub inerter: f64,
    pub column_damping: f64,
    pub device_damping: f64,
    pub friction: f64,
    pub impact: f64,
    /// Sequential law: lost at disengagement, negative for energy created at engagement.
    pub disengagement: f64,
    /// Clutch re-engagement resets and snapping to rest.
    pub reset: f64,
}

impl Energy {
    /// Every term of the partition, in the order of [`HistoryColumn::ENERGY`].
    pub fn terms(&self) -> [f64; 9] {
        [
            self.input,
            self.structure,
            self.inerter,
            self.column_damping,
            self.device_damping,
            self.friction,
            self.impact,
            self.disengagement,
            self.reset,
        ]
    }

    pub fn dissipated(&self) -> f64 {
        self.column_damping
            + self.device_damping
            + self.friction
            + self.impact
            + self.disengagement
            + self.reset
    }

    /// Input minus stored minus dissipated.
    pub fn imbalance(&self) -> f64 {
        self.input - self.structure - self.inerter - self.dissipated()
    }
}

/// Discrete energy losses booked at jumps.
#[derive(Clone, Copy, Debug, Default)]
pub struct Ledger {
    pub impact: f64,
    pub disengagement: f64,
    pub reset: f64,
}

/// Counts of discrete events.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Counters {
    pub impacts: u64,
    pub uplifts: u64,
    pub engagements: u64,
    pub resets: u64,
}

/// Peak responses (docs/MODEL.md "reported").
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Peaks {
    pub rotation: f64,
    pub deformation: f64,
    pub drift: f64,
    /// |absolute horizontal acceleration| / g, impact jumps excluded.
    pub abs_acceleration_g: f64,
    /// Rigid block: |θ̈|max / p² (rad), the angular acceleration between impacts (paper §3):
    /// the instants of Housner's velocity jump are excluded (the one-sided values on either
    /// side count), a Dirac-delta impact moment is included (it is a finite force, the
    /// acceleration Fig. 5b shows). None for structures without this measure.
    #[serde(default)]
    pub angular_acceleration_p2: Option<f64>,
}

/// Which optional measures a run computes. Rotation (and overturning) are always tracked; a
/// sweep of rotation spectra skips the acceleration peak searches, the drift and deformation
/// extrema and the energy ledger's per-step evaluation. Every measure asked for is computed
/// exactly as in a run that asks for all of them: the integrator takes the same steps
/// (the energy accumulators stay in the state and in the error control), so the asked
/// results are bit-identical.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Measures {
    pub deformation: bool,
    pub drift: bool,
    pub abs_acceleration: bool,
    pub angular_acceleration: bool,
    /// The energy partition at the end and its balance residual.
    pub energy: bool,
}

impl Measures {
    pub const ALL: Measures = Measures {
        deformation: true,
        drift: true,
        abs_acceleration: true,
        angular_acceleration: true,
        energy: true,
    };
    /// Peak rotation alone.
    pub const ROTATION: Measures = Measures {
        deformation: false,
        drift: false,
        abs_acceleration: false,
        angular_acceleration: false,
        energy: false,
    };

    /// Whether everything `other` asks for is measured here.
    pub fn covers(self, other: Measures) -> bool {
        (self.deformation || !other.deformation)
            && (self.drift || !other.drift)
            && (self.abs_acceleration || !other.abs_acceleration)
            && (self.angular_acceleration || !other.angular_acceleration)
            && (self.energy || !other.energy)
    }
}

impl Default for Measures {
    fn default() -> Self {
        Measures::ALL
    }
}

/// One end of an accepted step: time, state and derivative.
pub type StepEnd<'a, const N: usize> = (f64, &'a [f64; N], &'a [f64; N]);

/// What the simulation driver needs from a structure family.
pub trait SimModel<const N: usize>: OdeSystem<N> {
    /// Number of state components the model needs (the driver refuses to run it with
    /// another N).
    fn state_len(&self) -> usize;
    /// State at t = 0 and the first action (e.g. idle until the ground lifts the block).
    fn start(&mut self, y: &mut [f64; N]) -> Action;
    /// Apply the jump of event `index` located at t.
    fn on_event(&mut self, index: usize, t: f64, y: &mut [f64; N]) -> Action;
    /// End of an idle period at t.
    fn wake(&mut self, t: f64, y: &mut [f64; N]) -> Action;
    /// Name of what [`SimModel::wake`] did when it started the motion again (for event
    /// logs); None when it only resumed integrating (nothing happened at that instant).
    fn wake_name(&self) -> Option<&'static str> {
        Some("wake")
    }
    /// The excitation has ended at t and the model is at rest: may the run stop?
    fn at_rest(&self, t: f64, y: &[f64; N]) -> bool;
    /// Whether an event function of the current phase reads a_g directly rather than through
    /// the state (a block resting on the ground uplifts when |a_g| passes a threshold). The
    /// error controller cannot see such a function's kinks, so the integrator must then stop
    /// at every kink of the ground motion whatever the record's kink policy.
    fn events_read_ground(&self) -> bool {
        false
    }
    /// The excitation has ended and the energy left can no longer raise any peak.
    fn settled(&self, _y: &[f64; N]) -> bool {
        false
    }
    /// If the current phase has a closed-form solution, advance y exactly from t over one
    /// interval ending at most at `t_stop`, updating peaks and energy accumulators on the way,
    /// and return the new time and how the interval ended. `None`: the driver integrates.
    fn advance_closed_form(
        &mut self,
        _t: f64,
        _t_stop: f64,
        _y: &mut [f64; N],
    ) -> Option<(f64, ClosedFormEnd)> {
        None
    }
    /// Characteristic magnitudes for the error control, of the physical state components
    /// (the leading ones; energy accumulators after them are not error controlled).
    fn tolerance_scales(&self) -> Vec<f64>;
    /// Whether [`SimModel::observe_step`] must read the interior of the step from (t0, y0) to
    /// (t1, y1), with derivatives f0 and f1 there: false only where no value inside the step
    /// can raise a peak, so the step's dense output need not be built.
    fn step_reads_interior(&self, _start: StepEnd<'_, N>, _end: StepEnd<'_, N>) -> bool {
        true
    }
    /// Update peaks over an accepted step (dense output over [t0, t1]).
    fn observe_step(&mut self, dense: &Dense<N>, t_end: f64);
    /// Update peaks at a single point (start, events, idle periods).
    fn observe_point(&mut self, t: f64, y: &[f64; N]);
    /// Peak ground acceleration felt while idle on [t0, t1] (the body moves with the ground).
    fn observe_idle(&mut self, t0: f64, t1: f64);
    fn energy(&self, y: &[f64; N]) -> Energy;
    fn peaks(&self) -> Peaks;
    fn counters(&self) -> Counters;
    /// Name of event `index` (for event logs).
    fn event_name(&self, index: usize) -> &'static str;
    fn history_columns(&self) -> Vec<HistoryColumn>;
    fn history_row(&self, t: f64, y: &[f64; N]) -> Vec<f64>;
}

/// Largest |value(y)| over the step, where `rate(y)` is its time derivative: endpoints plus
/// interior zeros of the rate, located on the dense output. The zero is located by Illinois
/// (regula falsi) to a bracket of 1e-12 of the sample spacing: |value| is flat there, so the
/// value's relative error is ~(1e-12)², far below roundoff.
pub fn extremum_on_step<const N: usize>(
    dense: &Dense<N>,
    t_end: f64,
    value: impl Fn(&[f64; N]) -> f64,
    rate: impl Fn(&[f64; N]) -> f64,
) -> f64 {
    let zero = |(a, ra), (b, rb)| illinois_root(|s| rate(&dense.state(s)), a, ra, b, rb);
    sampled_extremum(dense, t_end, &value, &rate, zero)
}

/// [`extremum_on_step`] of a state component whose time derivative is another (θ and θ̇):
/// the rate's zero is refined by bracketed Newton on the interpolant, which gives the rate's
/// own slope ([`Dense::component_with_rate`]), to the same bracket. Newton takes ~4
/// evaluations where Illinois took ~10, each waiting on the last (perf: the Illinois search
/// was 9 % of the bare block's time at rtol 3e-7); the peak, flat in the root's time, is the
/// same to the last digit.
pub fn extremum_of_component<const N: usize>(
    dense: &Dense<N>,
    t_end: f64,
    value: usize,
    rate: usize,
) -> f64 {
    let zero = |(a, ra): (f64, f64), (b, rb): (f64, f64)| {
        let tol = (1e-12 * (b - a)).max(4.0 * f64::EPSILON * a.abs().max(b.abs()));
        newton_root(
            |s| dense.component_with_rate(s, rate),
            (a, ra),
            (b, rb),
            tol,
        )
        .0
    };
    sampled_extremum(
        dense,
        t_end,
        &|y: &[f64; N]| y[value],
        &|y: &[f64; N]| y[rate],
        zero,
    )
}

/// The endpoints and [`SAMPLES`](extremum_on_step) interior samples of the step, with each
/// sign change of the rate between samples refined by `zero`.
fn sampled_extremum<const N: usize>(
    dense: &Dense<N>,
    t_end: f64,
    value: &impl Fn(&[f64; N]) -> f64,
    rate: &impl Fn(&[f64; N]) -> f64,
    zero: impl Fn((f64, f64), (f64, f64)) -> f64,
) -> f64 {
    const SAMPLES: usize = 4;
    let t0 = dense.t0;
    let mut best = 0.0f64;
    let mut t_prev = t0;
    let y0 = dense.state(t0);
    let mut r_prev = rate(&y0);
    best = best.max(value(&y0).abs());
    for k in 1..=SAMPLES {
        let t = t0 + (t_end - t0) * k as f64 / SAMPLES as f64;
        let y = dense.state(t);
        let r = rate(&y);
        best = best.max(value(&y).abs());
        if r_prev * r < 0.0 {
            let root = zero((t_prev, r_prev), (t, r));
            best = best.max(value(&dense.state(root)).abs());
        }
        t_prev = t;
        r_prev = r;
    }
    best
}

/// Largest f over the sample points t_k = t0 + (t1 − t0)k/n, refined around the best sample
/// when that reaches `floor` (so only steps that can raise a peak pay for it).
pub fn refined_max(f: impl Fn(f64) -> f64, t0: f64, t1: f64, n: usize, floor: f64) -> f64 {
    let at = |k: usize| t0 + (t1 - t0) * k as f64 / n as f64;
    let values: Vec<f64> = (0..=n).map(|k| f(at(k))).collect();
    refine_sampled(f, t0, t1, &values, floor)
}

/// [`refined_max`] given f at its n + 1 sample points t_k = t0 + (t1 − t0)k/n (computed by the
/// caller, who may share work between several functions at the same points).
pub fn refine_sampled(f: impl Fn(f64) -> f64, t0: f64, t1: f64, values: &[f64], floor: f64) -> f64 {
    let n = values.len() - 1;
    let sample = |k: usize| (t0 + (t1 - t0) * k as f64 / n as f64, values[k]);
    let (best_k, best) = values
        .iter()
        .copied()
        .enumerate()
        .fold((0, f64::NEG_INFINITY), |a, b| if b.1 > a.1 { b } else { a });
    // A sample that only ties the running peak still gets refined: when a maximum lies just
    // past the previous step's end, this step's first sample equals the peak so far and the
    // true maximum is inside this step.
    if best < floor * (1.0 - 1e-9) {
        return best;
    }
    best.max(
        brent_max(
            f,
            sample(best_k.saturating_sub(1)),
            sample(best_k),
            sample((best_k + 1).min(n)),
        )
        .1,
    )
}

/// [`refined_max`] over samples (t_k, f(t_k)) the caller already has, refining also when the
/// best sample only ties the running peak (to 1e-9, for roundoff): a maximum just past the end
/// of one interval leaves the running peak at that end, which is the next interval's first
/// sample, and `best <= floor` would then never look between its samples.
pub fn refined_max_of_samples(f: impl Fn(f64) -> f64, samples: &[(f64, f64)], floor: f64) -> f64 {
    let (best_k, best) = samples
        .iter()
        .enumerate()
        .fold(
            (0, f64::NEG_INFINITY),
            |a, (k, s)| if s.1 > a.1 { (k, s.1) } else { a },
        );
    if best < floor - 1e-9 * floor.abs() {
        return best;
    }
    let lo = samples[best_k.saturating_sub(1)];
    let hi = samples[(best_k + 1).min(samples.len() - 1)];
    best.max(brent_max(f, lo, samples[best_k], hi).1)
}
