//! Adaptive explicit Runge–Kutta integration with dense output and event location.
//!
//! Why not a crate: `differential-equations` and `diffsol` were considered. Both are general
//! frameworks; rocklab needs four things from its integrator that neither gives directly:
//! (1) fixed-size, stack-allocated states (`[f64; N]`) with no allocation per right-hand side,
//! (2) direction-aware event location that returns the *post-crossing* side of the bracket, so a
//! restart after a switching event (clutch contact, pivot switch) is never ambiguous about which
//! side it is on, (3) cheap stops at forcing breakpoints (record samples) that keep the FSAL
//! derivative, and (4) a step budget and per-call statistics. That is ~300 lines here, tested
//! against closed forms in this module's unit tests.
//!
//! Methods ([`Method`]): Dormand–Prince 5(4) (Hairer, Nørsett & Wanner, Solving ODEs I, §II.5)
//! with its 4th-order continuous extension and a PI step-size controller, and DOP853 (§II.10),
//! the 8(5,3) pair with its 7th-order continuous extension, for tight tolerances. Both share
//! everything else: the event scan and root refinement, restarts, FSAL, stops, budget, stats.

mod dense;
mod dop853;
mod dp54;
mod events;
pub mod search;
#[cfg(test)]
mod tests;

pub use dense::Dense;
pub use events::no_root_inside;

use thiserror::Error;

/// The Runge–Kutta pair that advances the solution.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Method {
    /// Dormand–Prince 5(4), 6 RHS calls per step.
    #[default]
    Dp54,
    /// DOP853, 12 RHS calls per step plus 3 for its dense output.
    Dop853,
}

impl Method {
    /// Order used in the step-size formulas (the error estimate behaves as h^(q+1)).
    fn order(self) -> f64 {
        match self {
            Method::Dp54 => 5.0,
            Method::Dop853 => 8.0,
        }
    }
}

/// At most this many event functions per system.
pub const MAX_EVENTS: usize = 12;

/// Which sign change of an event function stops the integration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// From negative to positive.
    Rising,
    /// From positive to negative.
    Falling,
    /// Either way.
    Either,
}

impl Direction {
    fn triggers(self, before: f64, after: f64) -> bool {
        match self {
            Direction::Rising => before < 0.0 && after > 0.0,
            Direction::Falling => before > 0.0 && after < 0.0,
            Direction::Either => before * after < 0.0,
        }
    }
}

/// `*dst = v`, stored two components at a time (one SSE2 store per pair on x86-64).
///
/// The stage sums read each derivative back as pairs of components (vectorised over the
/// state), and a processor cannot forward two separate 8-byte stores to one 16-byte load: the
/// load waits until the stores reach the cache. Written component by component, the bare
/// block's derivative (N = 2) held up every stage of the chain that way (perf: 23 % of its
/// time on the load after the call). A right-hand side that builds its derivative in a local
/// array stores it with this. (The compiler does not merge the stores itself, and returning
/// the array by value put the same split store and wide load inside the callee.)
#[inline(always)]
pub fn store_pairs<const N: usize>(dst: &mut [f64; N], v: [f64; N]) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_set_pd, _mm_storeu_pd};
        for i in (0..N - N % 2).step_by(2) {
            // SAFETY: i + 1 < N, so both lanes lie in `dst`; SSE2 is part of x86-64.
            unsafe { _mm_storeu_pd(dst.as_mut_ptr().add(i), _mm_set_pd(v[i + 1], v[i])) };
        }
        if N % 2 == 1 {
            dst[N - 1] = v[N - 1];
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        *dst = v;
    }
}

/// A first-order system y' = f(t, y) with event functions g_i(t, y).
pub trait OdeSystem<const N: usize> {
    fn rhs(&self, t: f64, y: &[f64; N], dydt: &mut [f64; N]);
    /// Number of event functions (≤ MAX_EVENTS).
    fn event_count(&self) -> usize {
        0
    }
    fn event_direction(&self, _index: usize) -> Direction {
        Direction::Either
    }
    fn events(&self, _t: f64, _y: &[f64; N], _g: &mut [f64]) {}
    /// How many leading components of the state the event functions read (the rest, energy
    /// accumulators say, are left unevaluated on the dense output in the event search).
    fn event_inputs(&self) -> usize {
        N
    }
    /// Event function `index` alone at (t, y): what the root refinement reads. By default all
    /// of them are computed; a system whose functions cost more together overrides it.
    fn event(&self, index: usize, t: f64, y: &[f64; N]) -> f64 {
        let mut g = [0.0; MAX_EVENTS];
        self.events(t, y, &mut g[..self.event_count()]);
        g[index]
    }
    /// The sign event function `index` takes just after (t, y), where it is exactly zero
    /// because a jump put the state on its surface; 0 if the system cannot tell.
    fn sign_after_zero(&self, _index: usize, _t: f64, _y: &[f64; N]) -> f64 {
        0.0
    }
    /// The longest step the system allows until the next restart: a force that acts only over
    /// a short stretch of the motion (an impact window) must be sampled by the stages, or the
    /// error estimate, built from the same stages, cannot see it. Queried at every restart.
    fn max_step(&self) -> f64 {
        f64::INFINITY
    }
    /// How many leading state components [`OdeSystem::event_with_rate`] reads for function
    /// `index` in the current phase; 0 where it does not answer (root refinement then reads
    /// values alone).
    fn event_rate_inputs(&self, _index: usize) -> usize {
        0
    }
    /// Event function `index` and its time rate at (t, y) moving at `dydt`, in closed form;
    /// `None` where there is none (the refinement then bisects that iteration).
    fn event_with_rate(
        &self,
        _index: usize,
        _t: f64,
        _y: &[f64; N],
        _dydt: &[f64; N],
    ) -> Option<(f64, f64)> {
        None
    }
    /// Event values `g` and their time derivatives `rates` along the solution at (t, y), where
    /// dy/dt = `dydt`, computed together (they share trigonometry and kinematics). Return
    /// false if not provided: the integrator then differences [`OdeSystem::events`] along the
    /// tangent, one more call of `events`. Where provided, the values and rates must depend on
    /// t only through y and dy/dt: the integrator keeps a step's end values and rates for the
    /// next step across a stop at a forcing kink (where dy/dt is continuous).
    fn events_with_rates(
        &self,
        _t: f64,
        _y: &[f64; N],
        _dydt: &[f64; N],
        _g: &mut [f64],
        _rates: &mut [f64],
    ) -> bool {
        false
    }
}

#[derive(Clone, Copy, Debug)]
pub struct Options<const N: usize> {
    pub rtol: f64,
    /// Absolute tolerance per component; a component with `f64::INFINITY` is not error controlled
    /// (quadratures such as energy accumulators).
    pub atol: [f64; N],
    pub h_max: f64,
    /// The first `controlled` components form the state group of the error norm, the rest the
    /// quadrature group (use N when there are no quadratures).
    pub controlled: usize,
    /// Accepted plus rejected steps allowed over the integrator's lifetime.
    pub max_steps: u64,
    pub method: Method,
    /// Skip the event scan's sub-samples on steps where the end values and rates prove no
    /// sign change inside ([`no_root_inside`]); `false` samples every step (the reference).
    pub event_screen: bool,
    /// Measure the time spent in the stages (`Stats::stage_nanos`); costs two clock reads
    /// per step.
    pub time_stages: bool,
}

impl<const N: usize> Options<N> {
    /// Defaults for everything but the tolerances.
    pub fn new(rtol: f64, atol: [f64; N]) -> Self {
        Options {
            rtol,
            atol,
            h_max: f64::INFINITY,
            controlled: N,
            max_steps: u64::MAX,
            method: Method::Dp54,
            event_screen: true,
            time_stages: false,
        }
    }
}

/// Work counters of a run. Equality compares the persisted counters only (the diagnostic ones
/// are not stored, so a run read back equals the run that wrote it).
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Stats {
    pub steps: u64,
    pub rejected: u64,
    pub rhs_evals: u64,
    pub events: u64,
    /// Intervals advanced in closed form instead of integrated (no RHS evaluations; not
    /// counted in `steps`). Set by the simulation driver.
    #[serde(default, rename = "exact_steps")]
    pub closed_form_steps: u64,
    /// Wall time in the Runge–Kutta stages and dense-output construction (ns), measured only
    /// with `Options::time_stages` (for the bench; not persisted).
    #[serde(skip)]
    pub stage_nanos: u64,
    /// Calls of the system's event functions (all paths but root refinement; not persisted).
    #[serde(skip)]
    pub event_calls: u64,
    /// Evaluations of one event function by root refinement (not persisted).
    #[serde(skip)]
    pub refine_calls: u64,
}

impl PartialEq for Stats {
    fn eq(&self, other: &Self) -> bool {
        let persisted = |s: &Stats| {
            (
                s.steps,
                s.rejected,
                s.rhs_evals,
                s.events,
                s.closed_form_steps,
            )
        };
        persisted(self) == persisted(other)
    }
}

impl Eq for Stats {}

#[derive(Clone, Debug, Error, PartialEq)]
pub enum SolverError {
    #[error(
        "step budget of {budget} steps exhausted at t = {t:.6} s (raise the budget or loosen rtol)"
    )]
    StepBudget { t: f64, budget: u64 },
    #[error("step size underflow at t = {t:.6} s (h = {h:.3e}); the equations may be too stiff")]
    StepTooSmall { t: f64, h: f64 },
    #[error("non-finite state at t = {t:.6} s")]
    NonFinite { t: f64 },
}

/// What one call to [`Integrator::step`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepOutcome {
    /// An ordinary accepted step.
    Stepped,
    /// The step ended exactly at the requested stop time.
    Reached,
    /// Event `index` was located; the integrator sits just past the crossing and must be
    /// restarted (after any jump) before stepping on.
    Event(usize),
}

/// log2 of the smallest error the PI controller remembers (1e-4, as in DOPRI5).
const ERR_OLD_FLOOR_LOG2: f32 = -13.287_712;

/// Integrator state. Create with [`Integrator::new`], then `restart`, then `step` repeatedly.
pub struct Integrator<const N: usize> {
    pub opts: Options<N>,
    pub stats: Stats,
    t: f64,
    y: [f64; N],
    f: [f64; N],
    h: f64,
    /// log2 of the last accepted step's error, at least [`ERR_OLD_FLOOR_LOG2`] (the PI
    /// controller's memory).
    err_old_log2: f32,
    /// Tracked event signs (a zero value is an undetermined sign, see `reset_event_signs`).
    g: [f64; MAX_EVENTS],
    /// Which of `g` stand in (±1) for an exact zero at a restart: a sign without a scale.
    sign_only: [bool; MAX_EVENTS],
    /// Event values at the current point, as computed (no sign substitution).
    g_val: [f64; MAX_EVENTS],
    /// Their time derivatives, valid when `rates_valid`.
    g_rate: [f64; MAX_EVENTS],
    rates_valid: bool,
    /// The next step scans with sub-samples whatever the screen says (after a jump of the
    /// right-hand side the stored values belong to the other side of the jump).
    force_scan: bool,
    /// Consecutive steps the screen failed on, and steps left of a pause of the screen.
    screen_fails: u32,
    screen_pause: u32,
    /// Stage derivatives of the last trial step.
    k: [[f64; N]; 16],
    dense: Option<Dense<N>>,
    /// The last accepted DOP853 step while its dense output is not built yet: the three extra
    /// stages are computed only when something reads the step's interior ([`Self::ensure_dense`],
    /// [`Self::dense_now`]).
    pending: Option<Step<N>>,
    needs_restart: bool,
    /// The system's [`OdeSystem::max_step`] at the last restart.
    h_cap: f64,
}

/// An accepted step: its start, size and end state.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Step<const N: usize> {
    pub(crate) t0: f64,
    pub(crate) h: f64,
    pub(crate) y0: [f64; N],
    pub(crate) y1: [f64; N],
}

/// The step's error estimate and its end point.
struct Trial<const N: usize> {
    y1: [f64; N],
    f1: [f64; N],
    /// The square of the error norm (accepted at ≤ 1).
    err2: f64,
}

impl<const N: usize> Integrator<N> {
    pub fn new(opts: Options<N>) -> Self {
        Integrator {
            opts,
            stats: Stats::default(),
            t: 0.0,
            y: [0.0; N],
            f: [0.0; N],
            h: 0.0,
            err_old_log2: ERR_OLD_FLOOR_LOG2,
            g: [0.0; MAX_EVENTS],
            sign_only: [false; MAX_EVENTS],
            g_val: [0.0; MAX_EVENTS],
            g_rate: [0.0; MAX_EVENTS],
            rates_valid: false,
            force_scan: false,
            screen_fails: 0,
            screen_pause: 0,
            k: [[0.0; N]; 16],
            dense: None,
            pending: None,
            needs_restart: true,
            h_cap: f64::INFINITY,
        }
    }

    pub fn t(&self) -> f64 {
        self.t
    }

    pub fn y(&self) -> &[f64; N] {
        &self.y
    }

    /// Derivative at the current point (valid after restart or a non-event step).
    pub fn derivative(&self) -> &[f64; N] {
        &self.f
    }

    /// Dense output of the last step if it is built (None right after a restart, and after a
    /// DOP853 step until [`Self::ensure_dense`] or [`Self::dense_now`] builds it).
    pub fn dense(&self) -> Option<&Dense<N>> {
        self.dense.as_ref()
    }

    /// Whether the last call of [`Self::step`] took a step (its dense output can be had).
    pub fn stepped(&self) -> bool {
        self.dense.is_some() || self.pending.is_some()
    }

    /// Dense output of the last step, built now if it is not yet (DOP853's three extra stages:
    /// 3 of its 15 RHS calls per step, which a step nobody reads inside does not pay).
    pub fn dense_now<S: OdeSystem<N>>(&mut self, sys: &S) -> Option<Dense<N>> {
        self.ensure_dense(sys);
        self.dense
    }

    /// Build the dense output of the last step if it is not yet, for [`Self::dense`] to lend
    /// (no copy of its coefficients, as [`Self::dense_now`] makes).
    pub fn ensure_dense<S: OdeSystem<N>>(&mut self, sys: &S) {
        if let Some(step) = self.pending.take() {
            let clock = self.opts.time_stages.then(std::time::Instant::now);
            self.dense = Some(self.dense_dop853(sys, &step));
            if let Some(clock) = clock {
                self.stats.stage_nanos += clock.elapsed().as_nanos() as u64;
            }
        }
    }

    /// (Re)start at (t, y): after an event's jump, or when the right-hand side changes form.
    /// The last step size is kept as the first guess (Hairer's estimate on the first start).
    pub fn restart<S: OdeSystem<N>>(&mut self, sys: &S, t: f64, y: [f64; N]) {
        self.t = t;
        self.y = y;
        self.h_cap = sys.max_step();
        sys.rhs(t, &self.y, &mut self.f);
        self.stats.rhs_evals += 1;
        if self.h == 0.0 {
            self.h = self.initial_step(sys);
        }
        self.err_old_log2 = ERR_OLD_FLOOR_LOG2;
        self.dense = None;
        self.pending = None;
        self.needs_restart = false;
        self.reset_event_signs(sys);
    }

    /// Refresh only the derivative (the right-hand side jumped, e.g. at the end of a pulse with
    /// a nonzero final value), keeping event signs.
    pub fn refresh<S: OdeSystem<N>>(&mut self, sys: &S) {
        sys.rhs(self.t, &self.y, &mut self.f);
        self.stats.rhs_evals += 1;
        self.rates_valid = false;
        self.force_scan = true;
    }

    pub(super) fn error_scale(&self, i: usize, a: f64, b: f64) -> f64 {
        self.opts.atol[i] + self.opts.rtol * a.abs().max(b.abs())
    }

    /// The two groups of components of the error norm: the leading `opts.controlled` state
    /// components, and the trailing quadratures. Each is normed on its own and the larger
    /// counts, so adding well-behaved quadratures never dilutes the state's error.
    pub(super) fn groups(&self) -> [std::ops::Range<usize>; 2] {
        let split = self.opts.controlled.min(N);
        [0..split, split..N]
    }

    /// Error norm: the larger of the RMS norms over the two groups.
    pub(super) fn norm(&self, v: &[f64; N], y0: &[f64; N], y1: &[f64; N]) -> f64 {
        self.norm_squared(v, y0, y1).sqrt()
    }

    /// The square of [`Self::norm`]. A step's error waits on its last right-hand side and the
    /// next step's size on the error, so nothing here that can be done earlier is done after
    /// v: the scales' reciprocals depend on y0 and y1 alone, 1/n on nothing, and the step
    /// control reads log2 of the square (half the log2 of the norm) with no square root.
    pub(super) fn norm_squared(&self, v: &[f64; N], y0: &[f64; N], y1: &[f64; N]) -> f64 {
        let mean_square = |range: std::ops::Range<usize>| {
            let mut sum = 0.0;
            let mut n = 0;
            for i in range {
                if self.opts.atol[i].is_finite() {
                    let s = v[i] * (1.0 / self.error_scale(i, y0[i], y1[i]));
                    sum += s * s;
                    n += 1;
                }
            }
            if n == 0 { 0.0 } else { sum * (1.0 / n as f64) }
        };
        let [a, b] = self.groups();
        mean_square(a).max(mean_square(b))
    }

    /// Hairer's starting step guess (Solving ODEs I, §II.4), for the current method's order.
    fn initial_step<S: OdeSystem<N>>(&mut self, sys: &S) -> f64 {
        let d0 = self.norm(&self.y, &self.y, &self.y);
        let d1 = self.norm(&self.f, &self.y, &self.y);
        let h0 = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        };
        let h0 = h0.min(self.opts.h_max);
        let y1: [f64; N] = std::array::from_fn(|i| self.y[i] + h0 * self.f[i]);
        let mut f1 = [0.0; N];
        sys.rhs(self.t + h0, &y1, &mut f1);
        self.stats.rhs_evals += 1;
        let df: [f64; N] = std::array::from_fn(|i| f1[i] - self.f[i]);
        let d2 = self.norm(&df, &self.y, &self.y) / h0;
        let h1 = if d1.max(d2) <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / d1.max(d2)).powf(1.0 / self.opts.method.order())
        };
        (100.0 * h0).min(h1).min(self.opts.h_max)
    }

    /// Take one step toward `t_stop` (never past it). Returns what happened.
    pub fn step<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t_stop: f64,
    ) -> Result<StepOutcome, SolverError> {
        assert!(
            !self.needs_restart,
            "integrator must be restarted after an event"
        );
        loop {
            if self.stats.steps + self.stats.rejected >= self.opts.max_steps {
                return Err(SolverError::StepBudget {
                    t: self.t,
                    budget: self.opts.max_steps,
                });
            }
            let remaining = t_stop - self.t;
            let mut h = self.h.min(self.opts.h_max).min(self.h_cap);
            let mut hits_stop = false;
            if h >= remaining * (1.0 - 1e-12) {
                h = remaining;
                hits_stop = true;
            }
            if h <= 16.0 * f64::EPSILON * self.t.abs().max(1.0) {
                if remaining <= 16.0 * f64::EPSILON * self.t.abs().max(1.0) {
                    self.t = t_stop;
                    return Ok(StepOutcome::Reached);
                }
                return Err(SolverError::StepTooSmall { t: self.t, h });
            }
            let clock = self.opts.time_stages.then(std::time::Instant::now);
            let Trial { y1, f1, err2 } = match self.opts.method {
                Method::Dp54 => self.trial_dp54(sys, h),
                Method::Dop853 => self.trial_dop853(sys, h),
            };
            if !err2.is_finite() || y1.iter().any(|v| !v.is_finite()) {
                // Treat as a failed step; shrink hard. A genuinely non-finite solution ends
                // in StepTooSmall, reported by the caller with its time.
                if let Some(clock) = clock {
                    self.stats.stage_nanos += clock.elapsed().as_nanos() as u64;
                }
                self.stats.rejected += 1;
                self.h = h * 0.1;
                if self.h < 1e-14 * self.t.abs().max(1.0) {
                    return Err(SolverError::NonFinite { t: self.t });
                }
                continue;
            }
            // The step factors' powers in single precision, as 2^(e·log2 x): a factor needs
            // no 16 digits (f32 powf cost the bare Fig. 8 scene 5 % less time than f64's), and
            // the PI controller's two powers are then one log2 of this step's error (kept for
            // the next step) and one exp2. The next step's size waits on this one's error, so
            // the factors are written as the growth h_new/h: no division follows the powers.
            let expo = 1.0 / self.opts.method.order() as f32;
            let log2_err = 0.5 * (err2 as f32).log2();
            let exp2 = |e: f32| f64::from(e.exp2());
            if err2 <= 1.0 {
                let growth = match self.opts.method {
                    // PI controller (β = 0.04), as in DOPRI5: h_new/h within [1/5, 10].
                    Method::Dp54 => (0.9
                        * exp2((0.75 * 0.04 - expo) * log2_err + 0.04 * self.err_old_log2))
                    .clamp(0.2, 10.0),
                    // As in DOP853 (β = 0, step ratio within [1/3, 6]).
                    Method::Dop853 => (0.9 * exp2(-expo * log2_err)).clamp(1.0 / 3.0, 6.0),
                };
                self.err_old_log2 = log2_err.max(ERR_OLD_FLOOR_LOG2);
                let h_new = h * growth;
                self.stats.steps += 1;
                let step = Step {
                    t0: self.t,
                    h,
                    y0: self.y,
                    y1,
                };
                (self.dense, self.pending) = match self.opts.method {
                    Method::Dp54 => (Some(self.dense_dp54(h, &y1)), None),
                    Method::Dop853 => (None, Some(step)),
                };
                if let Some(clock) = clock {
                    self.stats.stage_nanos += clock.elapsed().as_nanos() as u64;
                }
                let event = self.locate_event(sys, &step, &f1, hits_stop);
                self.h = if hits_stop { self.h.max(h_new) } else { h_new };
                if let Some((index, t_event)) = event {
                    self.stats.events += 1;
                    self.t = t_event;
                    self.ensure_dense(sys);
                    let dense = self
                        .dense()
                        .expect("a located event built the dense output");
                    self.y = dense.state(t_event);
                    self.needs_restart = true;
                    return Ok(StepOutcome::Event(index));
                }
                self.t = if hits_stop { t_stop } else { self.t + h };
                self.y = y1;
                self.f = f1;
                return Ok(if hits_stop {
                    StepOutcome::Reached
                } else {
                    StepOutcome::Stepped
                });
            }
            if let Some(clock) = clock {
                self.stats.stage_nanos += clock.elapsed().as_nanos() as u64;
            }
            self.stats.rejected += 1;
            let least = match self.opts.method {
                Method::Dp54 => 0.1,
                Method::Dop853 => 1.0 / 3.0,
            };
            self.h = h * (0.9 * exp2(-expo * log2_err)).max(least);
        }
    }
}
