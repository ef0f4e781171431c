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

mod dop853;
pub mod search;

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
    /// tangent, one more call of `events`.
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
    /// First step after a switch of the dynamics from the local dynamics
    /// ([`Integrator::restart_switched`]) instead of the last step size.
    pub restart_estimate: bool,
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
            restart_estimate: true,
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

// Dormand–Prince 5(4) tableau.
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
// Dense output (Hairer's DOPRI5 `contd5`).
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// Sub-intervals of each step on which event signs are sampled, so that a function crossing
/// twice inside one step is still seen.
const EVENT_SAMPLES: usize = 4;

/// Steps without the event screen after it failed on three steps in a row.
const SCREEN_PAUSE: u32 = 16;

/// Dense output of the last accepted step: y(t0 + τh), τ ∈ [0, 1]. Both methods' continuous
/// extensions have Hairer's nested form
/// y = r0 + τ(r1 + (1−τ)(r2 + τ(r3 + (1−τ)(r4 + τ(r5 + (1−τ)(r6 + τ r7)))))),
/// Dormand–Prince 5(4) with r5 = r6 = r7 = 0 (`top` = 4), DOP853 with all eight (`top` = 7).
#[derive(Clone, Copy, Debug)]
pub struct Dense<const N: usize> {
    pub t0: f64,
    pub h: f64,
    r: [[f64; N]; 8],
    top: usize,
}

impl<const N: usize> Dense<N> {
    pub fn t1(&self) -> f64 {
        self.t0 + self.h
    }

    fn tau(&self, t: f64) -> f64 {
        if self.h == 0.0 {
            0.0
        } else {
            (t - self.t0) / self.h
        }
    }

    /// State at time t (t within the step).
    pub fn state(&self, t: f64) -> [f64; N] {
        self.state_head(t, N)
    }

    /// The first `n` components of the state at time t; the rest hold the step's start values
    /// (for readers of the leading components only, [`OdeSystem::event_inputs`]).
    #[inline]
    pub fn state_head(&self, t: f64, n: usize) -> [f64; N] {
        let th = self.tau(t);
        let th1 = 1.0 - th;
        let r = &self.r;
        let mut y = r[0];
        if self.top == 4 {
            for i in 0..n.min(N) {
                y[i] += th * (r[1][i] + th1 * (r[2][i] + th * (r[3][i] + th1 * r[4][i])));
            }
        } else {
            for i in 0..n.min(N) {
                let inner = r[4][i] + th * (r[5][i] + th1 * (r[6][i] + th * r[7][i]));
                y[i] += th * (r[1][i] + th1 * (r[2][i] + th * (r[3][i] + th1 * inner)));
            }
        }
        y
    }

    /// No |y_i(t)| of the interpolant on the step exceeds this. In the nested form
    /// y = r0 + τ(r1 + (1−τ)(r2 + …)) every multiplier lies in [0, 1], so
    /// y = (1−τ)y(t0) + τy(t1) + τ(1−τ)Q with |Q| ≤ Σ_{k≥2}|r_k| and τ(1−τ) ≤ ¼.
    pub fn bound(&self, i: usize) -> f64 {
        let ends = self.r[0][i].abs().max((self.r[0][i] + self.r[1][i]).abs());
        ends + 0.25 * self.r[2..].iter().map(|r| r[i].abs()).sum::<f64>()
    }

    /// No |ẏ_i(t)| of the interpolant on the step exceeds this. With V_k = r_k + m_k V_(k+1)
    /// (m_k = τ or 1 − τ, |m_k| ≤ 1, |m_k'| = 1): |V_k| ≤ A_k = Σ_{j≥k}|r_j| and
    /// |V_k'| ≤ A_(k+1) + B_(k+1) =: B_k; ẏ = V_0'/h.
    pub fn rate_bound(&self, i: usize) -> f64 {
        if self.h == 0.0 {
            return f64::INFINITY;
        }
        // (A_j, B_j) from the top down, starting past the last coefficient (0, 0).
        let (mut a, mut b) = (0.0, 0.0);
        for r in self.r[1..].iter().rev() {
            b += a;
            a += r[i].abs();
        }
        (a + b) / self.h.abs()
    }

    /// Time derivative of the interpolant at t.
    pub fn derivative(&self, t: f64) -> [f64; N] {
        self.derivative_head(t, N)
    }

    /// The first `n` components of the interpolant's time derivative at t; the rest are 0.
    #[inline]
    pub fn derivative_head(&self, t: f64, n: usize) -> [f64; N] {
        let th = self.tau(t);
        let th1 = 1.0 - th;
        let r = &self.r;
        let mut d = [0.0; N];
        if self.top == 4 {
            // v3 = r3 + (1−τ)r4, v2 = r2 + τv3, v1 = r1 + (1−τ)v2, y = r0 + τv1.
            for (i, di) in d.iter_mut().enumerate().take(n) {
                let v3 = r[3][i] + th1 * r[4][i];
                let dv3 = -r[4][i];
                let v2 = r[2][i] + th * v3;
                let dv2 = v3 + th * dv3;
                let v1 = r[1][i] + th1 * v2;
                let dv1 = -v2 + th1 * dv2;
                *di = (v1 + th * dv1) / self.h;
            }
            return d;
        }
        for (i, di) in d.iter_mut().enumerate().take(n) {
            // Inside out: v_k = r_k + m_k v_(k+1), m_k = τ for even k, 1 − τ for odd k.
            let mut v = r[self.top][i];
            let mut dv = 0.0;
            for k in (0..self.top).rev() {
                let (m, dm) = if k % 2 == 0 { (th, 1.0) } else { (th1, -1.0) };
                dv = dm * v + m * dv;
                v = r[k][i] + m * v;
            }
            *di = dv / self.h;
        }
        d
    }
}

/// Integrator state. Create with [`Integrator::new`], then `restart`, then `step` repeatedly.
pub struct Integrator<const N: usize> {
    pub opts: Options<N>,
    pub stats: Stats,
    t: f64,
    y: [f64; N],
    f: [f64; N],
    h: f64,
    err_old: f64,
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
    needs_restart: bool,
    /// The system's [`OdeSystem::max_step`] at the last restart.
    h_cap: f64,
}

/// The step's error estimate and its end point.
struct Trial<const N: usize> {
    y1: [f64; N],
    f1: [f64; N],
    err: f64,
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
            err_old: 1e-4,
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

    /// Dense output of the last step (None right after a restart).
    pub fn dense(&self) -> Option<&Dense<N>> {
        self.dense.as_ref()
    }

    /// (Re)start at (t, y): after an event's jump, or when the right-hand side changes form.
    /// The last step size is kept as the first guess (Hairer's estimate on the first start).
    pub fn restart<S: OdeSystem<N>>(&mut self, sys: &S, t: f64, y: [f64; N]) {
        self.start_at(sys, t, y, false);
    }

    /// [`Self::restart`] where the dynamics just switched (a clutch engaged or released, an
    /// impact of a clutched structure): the
    /// last step size was fitted to the dynamics *before* the switch, and after a clutch
    /// engages (a stiff spring in series) it is often far too long — each such restart cost
    /// a rejected step, a full set of stages. With `opts.restart_estimate` Hairer's starting
    /// estimate (Solving ODEs I, §II.4: from the derivative and its change along the tangent
    /// at the new point, one RHS call) caps it: h = min(h_old, h_est). For the caller to
    /// choose: where the old step fits (the bare block's impacts, measured on Fig. 8) the
    /// estimate, built for an unknown start, is conservative and cost 10–35 % more RHS calls.
    pub fn restart_switched<S: OdeSystem<N>>(&mut self, sys: &S, t: f64, y: [f64; N]) {
        self.start_at(sys, t, y, self.opts.restart_estimate);
    }

    fn start_at<S: OdeSystem<N>>(&mut self, sys: &S, t: f64, y: [f64; N], estimate: bool) {
        self.t = t;
        self.y = y;
        self.h_cap = sys.max_step();
        sys.rhs(t, &self.y, &mut self.f);
        self.stats.rhs_evals += 1;
        if self.h == 0.0 {
            self.h = self.initial_step(sys);
        } else if estimate {
            self.h = self.h.min(self.initial_step(sys));
        }
        self.err_old = 1e-4;
        self.dense = None;
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

    /// Event signs at the start. A function that is exactly zero (a jump put the state on its
    /// surface: θ = 0 after an impact, δ = 0 after a clutch reset) takes the sign the system
    /// says it will have ([`OdeSystem::sign_after_zero`]); if the system cannot tell, it stays
    /// undetermined and adopts the sign of its first sub-sample, so no crossing is reported at
    /// the restart point itself. (A generic probe along y + δ·f is not used: where the rate is
    /// also ~0, e.g. a reset at a velocity crossing, its sign is decided by roundoff.)
    /// Where the system has the rates in closed form they come with the values, for the first
    /// step's screen (one call of the kinematics per restart instead of two).
    fn reset_event_signs<S: OdeSystem<N>>(&mut self, sys: &S) {
        let m = sys.event_count();
        let mut rates = [0.0; MAX_EVENTS];
        self.rates_valid =
            sys.events_with_rates(self.t, &self.y, &self.f, &mut self.g[..m], &mut rates[..m]);
        if self.rates_valid {
            self.g_rate = rates;
        } else {
            sys.events(self.t, &self.y, &mut self.g[..m]);
        }
        self.stats.event_calls += 1;
        self.g_val = self.g;
        self.force_scan = false;
        for i in 0..m {
            self.sign_only[i] = self.g[i] == 0.0;
            if self.sign_only[i] {
                self.g[i] = sys.sign_after_zero(i, self.t, &self.y);
            }
        }
    }

    fn error_scale(&self, i: usize, a: f64, b: f64) -> f64 {
        self.opts.atol[i] + self.opts.rtol * a.abs().max(b.abs())
    }

    /// The two groups of components of the error norm: the leading `opts.controlled` state
    /// components, and the trailing quadratures. Each is normed on its own and the larger
    /// counts, so adding well-behaved quadratures never dilutes the state's error.
    fn groups(&self) -> [std::ops::Range<usize>; 2] {
        let split = self.opts.controlled.min(N);
        [0..split, split..N]
    }

    /// Error norm: the larger of the RMS norms over the two groups.
    fn norm(&self, v: &[f64; N], y0: &[f64; N], y1: &[f64; N]) -> f64 {
        let rms = |range: std::ops::Range<usize>| {
            let mut sum = 0.0;
            let mut n = 0;
            for i in range {
                if self.opts.atol[i].is_finite() {
                    let s = v[i] / self.error_scale(i, y0[i], y1[i]);
                    sum += s * s;
                    n += 1;
                }
            }
            if n == 0 { 0.0 } else { (sum / n as f64).sqrt() }
        };
        let [a, b] = self.groups();
        rms(a).max(rms(b))
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
            let Trial { y1, f1, err } = match self.opts.method {
                Method::Dp54 => self.trial_dp54(sys, h),
                Method::Dop853 => self.trial_dop853(sys, h),
            };
            if !err.is_finite() || y1.iter().any(|v| !v.is_finite()) {
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
            // The step factors' powers in single precision: a factor needs no 16 digits, and
            // f32 powf cost the bare Fig. 8 scene 5 % less time than f64's (glibc).
            let expo = 1.0 / self.opts.method.order() as f32;
            let pow = |x: f64, e: f32| f64::from((x as f32).powf(e));
            if err <= 1.0 {
                let fac = match self.opts.method {
                    // PI controller (β = 0.04), as in DOPRI5.
                    Method::Dp54 => (pow(err, expo - 0.75 * 0.04) * pow(self.err_old, -0.04) / 0.9)
                        .clamp(0.1, 5.0),
                    // As in DOP853 (β = 0, step ratio within [1/3, 6]).
                    Method::Dop853 => (pow(err, expo) / 0.9).clamp(1.0 / 6.0, 3.0),
                };
                self.err_old = err.max(1e-4);
                let h_new = h / fac;
                self.stats.steps += 1;
                let dense = match self.opts.method {
                    Method::Dp54 => self.dense_dp54(h, &y1),
                    Method::Dop853 => self.dense_dop853(sys, h, &y1),
                };
                if let Some(clock) = clock {
                    self.stats.stage_nanos += clock.elapsed().as_nanos() as u64;
                }
                let event = self.locate_event(sys, &dense, &y1, &f1, hits_stop);
                self.dense = Some(dense);
                self.h = if hits_stop { self.h.max(h_new) } else { h_new };
                if let Some((index, t_event)) = event {
                    self.stats.events += 1;
                    self.t = t_event;
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
            let shrink = match self.opts.method {
                Method::Dp54 => 10.0,
                Method::Dop853 => 3.0,
            };
            self.h = h / (pow(err, expo) / 0.9).min(shrink);
        }
    }

    /// One Dormand–Prince 5(4) step of size h from the current point; stages in `self.k[..7]`.
    fn trial_dp54<S: OdeSystem<N>>(&mut self, sys: &S, h: f64) -> Trial<N> {
        let t = self.t;
        let y = self.y;
        let k1 = self.f;
        let mut k2 = [0.0; N];
        let mut k3 = [0.0; N];
        let mut k4 = [0.0; N];
        let mut k5 = [0.0; N];
        let mut k6 = [0.0; N];
        let mut k7 = [0.0; N];
        let s: [f64; N] = std::array::from_fn(|i| y[i] + h * A21 * k1[i]);
        sys.rhs(t + C2 * h, &s, &mut k2);
        let s: [f64; N] = std::array::from_fn(|i| y[i] + h * (A31 * k1[i] + A32 * k2[i]));
        sys.rhs(t + C3 * h, &s, &mut k3);
        let s: [f64; N] =
            std::array::from_fn(|i| y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i]));
        sys.rhs(t + C4 * h, &s, &mut k4);
        let s: [f64; N] = std::array::from_fn(|i| {
            y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i])
        });
        sys.rhs(t + C5 * h, &s, &mut k5);
        let s: [f64; N] = std::array::from_fn(|i| {
            y[i] + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i])
        });
        sys.rhs(t + h, &s, &mut k6);
        let y1: [f64; N] = std::array::from_fn(|i| {
            y[i] + h * (B1 * k1[i] + B3 * k3[i] + B4 * k4[i] + B5 * k5[i] + B6 * k6[i])
        });
        sys.rhs(t + h, &y1, &mut k7);
        self.stats.rhs_evals += 6;
        let e: [f64; N] = std::array::from_fn(|i| {
            h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i])
        });
        let err = self.norm(&e, &y, &y1);
        self.k[..7].copy_from_slice(&[k1, k2, k3, k4, k5, k6, k7]);
        Trial { y1, f1: k7, err }
    }

    fn dense_dp54(&self, h: f64, y1: &[f64; N]) -> Dense<N> {
        let y0 = &self.y;
        let k = &self.k;
        let mut r = [[0.0; N]; 8];
        for i in 0..N {
            let ydiff = y1[i] - y0[i];
            let bspl = h * k[0][i] - ydiff;
            r[0][i] = y0[i];
            r[1][i] = ydiff;
            r[2][i] = bspl;
            r[3][i] = ydiff - h * k[6][i] - bspl;
            r[4][i] = h
                * (D1 * k[0][i]
                    + D3 * k[2][i]
                    + D4 * k[3][i]
                    + D5 * k[4][i]
                    + D6 * k[5][i]
                    + D7 * k[6][i]);
        }
        Dense {
            t0: self.t,
            h,
            r,
            top: 4,
        }
    }

    /// Stage `s` of the extended DOP853 tableau into `self.k[s]`.
    fn dop853_stage<S: OdeSystem<N>>(&mut self, sys: &S, h: f64, s: usize) {
        let a = &dop853::A[s];
        let k = &self.k;
        let y = &self.y;
        let ys: [f64; N] = std::array::from_fn(|i| {
            let mut acc = 0.0;
            for j in 0..s {
                acc += a[j] * k[j][i];
            }
            y[i] + h * acc
        });
        let mut ks = [0.0; N];
        sys.rhs(self.t + dop853::C[s] * h, &ys, &mut ks);
        self.k[s] = ks;
    }

    /// One DOP853 step of size h; stages in `self.k[..13]` (k[12] = f(t + h, y1)). The error
    /// is Hairer's: the 5th-order estimate, damped where the 3rd-order one is much smaller,
    /// err = |h|·‖e5‖² / √(‖e5‖² + 0.01‖e3‖²), per norm group.
    fn trial_dop853<S: OdeSystem<N>>(&mut self, sys: &S, h: f64) -> Trial<N> {
        self.k[0] = self.f;
        for s in 1..dop853::STAGES {
            self.dop853_stage(sys, h, s);
        }
        let k = &self.k;
        let y = self.y;
        let y1: [f64; N] = std::array::from_fn(|i| {
            let mut acc = 0.0;
            for (j, b) in dop853::B.iter().enumerate() {
                acc += b * k[j][i];
            }
            y[i] + h * acc
        });
        let mut f1 = [0.0; N];
        sys.rhs(self.t + h, &y1, &mut f1);
        self.k[12] = f1;
        self.stats.rhs_evals += 12;
        let k = &self.k;
        let mut err: f64 = 0.0;
        for range in self.groups() {
            let (mut e5sum, mut e3sum, mut n) = (0.0, 0.0, 0);
            for i in range {
                if !self.opts.atol[i].is_finite() {
                    continue;
                }
                let (mut e5, mut e3) = (0.0, 0.0);
                for (j, kj) in k.iter().take(dop853::STAGES).enumerate() {
                    e5 += dop853::E5[j] * kj[i];
                    e3 += dop853::E3[j] * kj[i];
                }
                let sc = self.error_scale(i, y[i], y1[i]);
                e5sum += (e5 / sc) * (e5 / sc);
                e3sum += (e3 / sc) * (e3 / sc);
                n += 1;
            }
            if n > 0 && (e5sum > 0.0 || e3sum > 0.0) {
                let denominator = (e5sum + 0.01 * e3sum) * n as f64;
                err = err.max(h.abs() * e5sum / denominator.sqrt());
            }
        }
        Trial { y1, f1, err }
    }

    /// DOP853's 7th-order dense output: three more stages, then the coefficients.
    fn dense_dop853<S: OdeSystem<N>>(&mut self, sys: &S, h: f64, y1: &[f64; N]) -> Dense<N> {
        for s in dop853::STAGES + 1..dop853::STAGES_EXTENDED {
            self.dop853_stage(sys, h, s);
        }
        self.stats.rhs_evals += 3;
        let y0 = &self.y;
        let k = &self.k;
        let mut r = [[0.0; N]; 8];
        for i in 0..N {
            let dy = y1[i] - y0[i];
            r[0][i] = y0[i];
            r[1][i] = dy;
            r[2][i] = h * k[0][i] - dy;
            r[3][i] = 2.0 * dy - h * (k[12][i] + k[0][i]);
            for (row, d) in dop853::D.iter().enumerate() {
                let mut acc = 0.0;
                for (j, dj) in d.iter().enumerate() {
                    acc += dj * k[j][i];
                }
                r[4 + row][i] = h * acc;
            }
        }
        Dense {
            t0: self.t,
            h,
            r,
            top: 7,
        }
    }

    /// Event values and rates at (t, y) with dy/dt = `f`: from the system if it provides them
    /// (returns true), else by differencing along the tangent over `eps` (negative: backward,
    /// staying inside the step just taken; positive: forward, inside the step to come — the
    /// rate jumps at forcing kinks, and each step needs its own side's).
    #[allow(clippy::too_many_arguments)]
    fn event_rates<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &[f64; N],
        f: &[f64; N],
        eps: f64,
        g: &mut [f64; MAX_EVENTS],
        rates: &mut [f64; MAX_EVENTS],
        values_known: bool,
    ) -> bool {
        let m = sys.event_count();
        self.stats.event_calls += 1;
        if sys.events_with_rates(t, y, f, &mut g[..m], &mut rates[..m]) {
            return true;
        }
        if !values_known {
            sys.events(t, y, &mut g[..m]);
            self.stats.event_calls += 1;
        }
        let y_eps: [f64; N] = std::array::from_fn(|i| y[i] + eps * f[i]);
        let mut g_eps = [0.0; MAX_EVENTS];
        sys.events(t + eps, &y_eps, &mut g_eps[..m]);
        for i in 0..m {
            rates[i] = (g_eps[i] - g[i]) / eps;
        }
        false
    }

    /// Look for a triggering sign change in the step just accepted; return the earliest
    /// located event, or update the tracked signs to the end of the step.
    ///
    /// Screen (`opts.event_screen`): with the values g and rates g' of every event function
    /// at both ends, the cubic Hermite interpolant H of g over the step is known, and where H
    /// provably stays away from zero the sub-samples of [`Self::scan`] are skipped.
    /// Why no root can be missed: g − H = g⁗(ξ) h⁴ τ²(1−τ)²/24 (the Hermite remainder), so a
    /// root inside needs |g − H| ≥ |H| somewhere. [`no_root_inside`] demands
    /// |H(τ)| > (V/2)·τ²(1−τ)² on the whole step, V = |Δg| + h|g'₀| + h|g'₁| the step's
    /// first-order variation of g: it assumes h⁴|g⁗|/24 ≤ V/2, i.e. the fourth Taylor term of
    /// g over an accepted step is below half its first — g resolved on the step's scale, the
    /// same assumption under which the scan's samples h/4 apart cannot miss a pair of
    /// crossings. Grazing and double roots (g and g' both near zero inside) put H within the
    /// margin, so those steps are scanned exactly as without the screen; so are steps after a
    /// jump of the right-hand side, steps whose start value is exactly zero (undetermined
    /// sign), and steps where any function changes sign. Event functions whose form depends
    /// on the state (a clutch's reset guard) switch form only where another event function
    /// crosses zero, and that function's own screen sends the step to the scan.
    ///
    /// The screen costs two calls of the event functions per step (values and a tangent
    /// difference) against the scan's four, five when it fails; where it keeps failing (event-
    /// dense stretches: a chattering clutch) it pauses for [`SCREEN_PAUSE`] steps. With rates
    /// in closed form it costs one call, the end values the scan needs anyway, so it never
    /// pauses.
    fn locate_event<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        dense: &Dense<N>,
        y1: &[f64; N],
        f1: &[f64; N],
        ends_at_stop: bool,
    ) -> Option<(usize, f64)> {
        let m = sys.event_count();
        if m == 0 {
            return None;
        }
        let paused = self.screen_pause > 0;
        self.screen_pause = self.screen_pause.saturating_sub(1);
        if !self.opts.event_screen || self.force_scan || paused {
            self.force_scan = false;
            self.rates_valid = false;
            let t1 = dense.t1();
            sys.events(t1, y1, &mut self.g_val[..m]);
            self.stats.event_calls += 1;
            return self.scan(sys, dense, Some(&self.g_val.clone()));
        }
        let h = dense.h;
        let eps = 1e-7 * h;
        if !self.rates_valid {
            let (t0, y0, f0) = (self.t, self.y, self.f);
            let mut g0 = self.g_val;
            let mut rates0 = [0.0; MAX_EVENTS];
            self.event_rates(sys, t0, &y0, &f0, eps, &mut g0, &mut rates0, true);
            self.g_rate = rates0;
        }
        let t1 = dense.t1();
        let mut g1 = [0.0; MAX_EVENTS];
        let mut rates1 = [0.0; MAX_EVENTS];
        let closed_form = self.event_rates(sys, t1, y1, f1, -eps, &mut g1, &mut rates1, false);
        let clear = (0..m).all(|i| {
            no_root_inside(
                (self.g_val[i], self.g[i]),
                h * self.g_rate[i],
                g1[i],
                h * rates1[i],
            )
        });
        if clear || closed_form {
            self.screen_fails = 0;
        } else {
            self.screen_fails += 1;
            if self.screen_fails >= 3 {
                self.screen_fails = 0;
                self.screen_pause = SCREEN_PAUSE;
            }
        }
        let found = if clear {
            self.g[..m].copy_from_slice(&g1[..m]);
            self.sign_only = [false; MAX_EVENTS];
            None
        } else {
            self.scan(sys, dense, Some(&g1))
        };
        if found.is_none() {
            self.g_val = g1;
            self.g_rate = rates1;
            // At a forcing breakpoint the rates change side.
            self.rates_valid = !ends_at_stop;
        }
        found
    }

    /// Sample every event function at [`EVENT_SAMPLES`] points of the step (the last one is
    /// the end point, whose values `at_end` may already hold); refine the earliest
    /// triggering sign change.
    fn scan<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        dense: &Dense<N>,
        at_end: Option<&[f64; MAX_EVENTS]>,
    ) -> Option<(usize, f64)> {
        let m = sys.event_count();
        let mut g_prev = self.g;
        let mut t_prev = dense.t0;
        for sample in 1..=EVENT_SAMPLES {
            let t_s = if sample == EVENT_SAMPLES {
                dense.t1()
            } else {
                dense.t0 + dense.h * sample as f64 / EVENT_SAMPLES as f64
            };
            let mut g_s = [0.0; MAX_EVENTS];
            match at_end {
                Some(g_end) if sample == EVENT_SAMPLES => g_s = *g_end,
                _ => {
                    sys.events(
                        t_s,
                        &dense.state_head(t_s, sys.event_inputs()),
                        &mut g_s[..m],
                    );
                    self.stats.event_calls += 1;
                }
            }
            let mut best: Option<(usize, f64)> = None;
            for i in 0..m {
                if g_prev[i] == 0.0 {
                    continue; // undetermined sign: adopt the new one below
                }
                let direction = sys.event_direction(i);
                if !direction.triggers(g_prev[i], g_s[i]) {
                    continue;
                }
                // Only a crossing before the earliest one found so far matters: one look at
                // that time decides whether this function has crossed by then, and if so its
                // bracket ends there (refining it over the whole interval cost ~15 calls).
                let end = match best {
                    None => (t_s, g_s[i]),
                    Some((_, t_best)) => {
                        let g_best =
                            sys.event(i, t_best, &dense.state_head(t_best, sys.event_inputs()));
                        self.stats.refine_calls += 1;
                        if !direction.triggers(g_prev[i], g_best) {
                            continue;
                        }
                        (t_best, g_best)
                    }
                };
                // (The flag is cleared where g_prev[i] is replaced by a sample, so it holds for
                // a later sub-interval too when the function sat exactly on zero until then.)
                let start = (t_prev, g_prev[i], self.sign_only[i]);
                let (t_root, calls) = refine_root(sys, dense, i, start, end.0, end.1);
                self.stats.refine_calls += calls;
                // Roots within the refinement's resolution of each other are one time: the
                // lower index keeps it, as when every function was refined over the same
                // bracket (a bracket ending at t_best can return a point just short of it).
                let resolution = 4.0 * f64::EPSILON * t_s.abs().max(dense.h.abs());
                if best.is_none_or(|(_, tb)| t_root < tb - resolution) {
                    best = Some((i, t_root));
                }
            }
            if best.is_some() {
                return best;
            }
            for i in 0..m {
                if g_s[i] != 0.0 {
                    g_prev[i] = g_s[i];
                    self.sign_only[i] = false;
                }
            }
            t_prev = t_s;
        }
        self.g = g_prev;
        None
    }
}

/// Whether g has provably no root on a step, from its values a, b and rates times h, da, db,
/// at the ends: the cubic Hermite interpolant H keeps the sign s of a on (0, 1] with the
/// margin (V/2)·τ²(1−τ)², V = |b − a| + |da| + |db| — see [`Integrator::locate_event`] for
/// why. The test is on the Bernstein coefficients c₀…c₄ of s·H(τ) − margin(τ), a degree-4
/// polynomial: c₁…c₄ positive and c₀ ≥ 0 imply it is positive on (0, 1] (convex hull).
///
/// `a` is (value, tracked sign). A start exactly on zero (the function whose event was just
/// applied) has c₀ = 0 and passes when g leaves zero with its tracked sign (s·da > 0) and
/// stays on that side: the scan would see no sign change there either. An untracked zero
/// (tracked 0) takes the side g leaves to, as the scan adopts whatever sign it samples next.
fn no_root_inside((a, tracked): (f64, f64), da: f64, b: f64, db: f64) -> bool {
    let s = if a != 0.0 {
        a.signum()
    } else if tracked != 0.0 {
        tracked.signum()
    } else {
        da.signum()
    };
    // A strict common sign at the ends (NaN fails here), and a zero start leaving on its side
    // (da = 0 fails).
    let ends_agree = s * b > 0.0 && (a != 0.0 || s * da > 0.0);
    if !ends_agree {
        return false;
    }
    let v = (b - a).abs() + da.abs() + db.abs();
    // Cubic Bernstein coefficients of H, then elevated to degree 4.
    let (b0, b1, b2, b3) = (s * a, s * (a + da / 3.0), s * (b - db / 3.0), s * b);
    let c1 = (b0 + 3.0 * b1) / 4.0;
    let c2 = (b1 + b2) / 2.0;
    let c3 = (3.0 * b2 + b3) / 4.0;
    // τ²(1−τ)² = B₂,₄(τ)/6.
    c1 > 0.0 && c2 - v / 12.0 > 0.0 && c3 > 0.0
}

/// A root of event function `index` on the dense interpolant, from the bracket's start
/// (a, g(a), whether g(a) is only a sign) to (b, g(b)): bracketed Newton where the system
/// gives the function's rate in closed form ([`newton_root`]; ~4 evaluations where Illinois
/// took 14–19 on the Fig. 8 mechanistic scene), Illinois (modified regula falsi) otherwise.
/// Both stop at a bracket of a few ulps of t and return its right end, where the function
/// was seen with its post-crossing sign, and the evaluations made.
fn refine_root<const N: usize, S: OdeSystem<N>>(
    sys: &S,
    dense: &Dense<N>,
    index: usize,
    (mut a, mut ga, sign_only): (f64, f64, bool),
    mut b: f64,
    mut gb: f64,
) -> (f64, u64) {
    let tol = 4.0 * f64::EPSILON * b.abs().max(dense.h.abs());
    let mut calls = 0;
    let n = sys.event_rate_inputs(index);
    if n > 0 {
        // The function and its rate along the interpolant (the chain rule through the
        // interpolant's own derivative, so Newton converges on the interpolant's root).
        let with_rate = |t: f64| {
            let y = dense.state_head(t, n);
            sys.event_with_rate(index, t, &y, &dense.derivative_head(t, n))
                .unwrap_or_else(|| (sys.event(index, t, &y), f64::NAN))
        };
        if !sign_only {
            return newton_root(with_rate, (a, ga), (b, gb), tol);
        }
        // A start on the surface itself (g(a) = 0 after the jump that put it there) would
        // attract Newton: divide the known zero out, h = g/(t − a), whose value at a is
        // g'(a) and whose only root in (a, b] is the crossing sought. A parabola through the
        // start lands its first probe on the root (a flight between two impacts).
        let (g0, rate0) = with_rate(a);
        if g0 == 0.0 && rate0 != 0.0 && rate0.signum() == ga.signum() {
            let a0 = a;
            let divided = |t: f64| {
                let (g, rate) = with_rate(t);
                let (s, h) = (t - a0, g / (t - a0));
                (h, (rate - h) / s)
            };
            let (root, more) = newton_root(divided, (a, rate0), (b, gb / (b - a0)), tol);
            return (root, 1 + more);
        }
        calls += 1;
    }
    // How many times in a row the same end was replaced (+: b, −: a). A start value that is
    // only a sign has no scale for a secant: bisect until it is replaced.
    let mut streak: i32 = if sign_only { 3 } else { 0 };
    for _ in 0..200 {
        if b - a <= tol {
            break;
        }
        // Illinois halves the kept end's value each time the same end is replaced, which
        // recovers from a kept value off the function's scale only by halvings (a sign
        // standing in for a zero, ±1 where the function is 1e-4, took 40 iterations). A third
        // replacement in a row bisects instead.
        let mut c = if streak.abs() >= 3 {
            0.5 * (a + b)
        } else {
            b - gb * (b - a) / (gb - ga)
        };
        // Strictly inside, else bisect. (Stepping just inside an end that sits on the root
        // would save iterations, but it puts the returned end inside the band where the
        // function is rounding noise, ~1e-11 s wide for a slow clutch crossing, and the
        // restart found the same crossing again: pairs of events 1e-14–1e-11 s apart.)
        if !(c > a && c < b) {
            c = 0.5 * (a + b);
        }
        let gc = sys.event(index, c, &dense.state_head(c, sys.event_inputs()));
        calls += 1;
        // Exactly on the surface counts as not yet across: the point returned is always one
        // whose value was seen on the post-crossing side. (Returning c + tol unseen, as this
        // did, could restart a step short of the crossing where the function is rounding
        // noise, ~1e-17 m for a clutch contact, and detect the same event again.)
        if gc != 0.0 && gc.signum() == gb.signum() {
            b = c;
            gb = gc;
            if streak > 0 {
                ga *= 0.5;
            }
            streak = streak.max(0) + 1;
        } else {
            a = c;
            ga = gc;
            if streak < 0 {
                gb *= 0.5;
            }
            streak = streak.min(0) - 1;
        }
    }
    (b, calls)
}

/// A root of f in the bracket (a, f(a)), (b, f(b)) of opposite signs, from f and its rate:
/// bracketed Newton (rtsafe, Press et al.) from the secant of the ends, bisecting where a
/// Newton step leaves the bracket or does not halve the step before it (rounding noise near
/// the root). Every probe keeps tol/2 inside the bracket, so once Newton has converged from
/// one side the next probe closes the bracket from the other. Stops at a bracket of `tol`;
/// returns its post-crossing end, where that sign was seen, and the evaluations made.
fn newton_root(
    mut f: impl FnMut(f64) -> (f64, f64),
    (mut a, mut fa): (f64, f64),
    (mut b, mut fb): (f64, f64),
    tol: f64,
) -> (f64, u64) {
    let mut calls = 0;
    let mut c = b - fb * (b - a) / (fb - fa);
    let mut step = b - a;
    let (mut last_zero, mut on_zeros) = (false, false);
    for _ in 0..200 {
        if b - a <= tol {
            break;
        }
        if !(a..=b).contains(&c) {
            c = 0.5 * (a + b);
        }
        c = c.clamp(a + 0.5 * tol, b - 0.5 * tol);
        let (fc, rate) = f(c);
        calls += 1;
        // Exactly on the surface counts as not yet across (as in the Illinois search).
        if fc != 0.0 && fc.signum() == fb.signum() {
            (b, fb) = (c, fc);
        } else {
            (a, fa) = (c, fc);
        }
        // The Newton step must land in the bracket (its ends included: the clamp above then
        // steps tol/2 in) and be at most half the last step (rtsafe's test, stricter: rtsafe
        // compares with the step before the last). A point exactly on the surface counts as
        // not yet across, and Newton's zero step from it probes tol/2 further, which closes
        // the bracket at an isolated root; on a stretch of zeros it would creep by tol/2 a
        // probe, so once two probes in a row were 0, zeros are bisected.
        on_zeros |= fc == 0.0 && last_zero;
        last_zero = fc == 0.0;
        let newton = -fc / rate;
        let next = c + newton;
        let newton_ok =
            !(on_zeros && fc == 0.0) && (a..=b).contains(&next) && 2.0 * newton.abs() <= step.abs();
        if newton_ok {
            (step, c) = (newton, next);
        } else {
            (step, c) = (0.5 * (b - a), 0.5 * (a + b));
        }
    }
    let _ = fa;
    (b, calls)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Harmonic;
    impl OdeSystem<2> for Harmonic {
        fn rhs(&self, _t: f64, y: &[f64; 2], d: &mut [f64; 2]) {
            d[0] = y[1];
            d[1] = -y[0];
        }
        fn event_count(&self) -> usize {
            1
        }
        fn event_direction(&self, _i: usize) -> Direction {
            Direction::Falling
        }
        fn events(&self, _t: f64, y: &[f64; 2], g: &mut [f64]) {
            g[0] = y[0];
        }
    }

    fn opts(rtol: f64) -> Options<2> {
        Options {
            max_steps: 1_000_000,
            ..Options::new(rtol, [rtol; 2])
        }
    }

    #[test]
    fn harmonic_oscillator_matches_cosine_and_finds_falling_zero() {
        let mut it = Integrator::new(opts(1e-10));
        it.restart(&Harmonic, 0.0, [1.0, 0.0]);
        // cos t falls through zero at π/2 (a falling crossing of y0).
        loop {
            match it.step(&Harmonic, 10.0).unwrap() {
                StepOutcome::Event(0) => break,
                StepOutcome::Reached => panic!("event missed"),
                _ => {}
            }
        }
        let miss = (it.t() - std::f64::consts::FRAC_PI_2).abs();
        assert!(miss < 1e-9, "event time off by {miss:e}");
        assert!(it.y()[0] <= 0.0, "stops on the post-crossing side");
        // Restart and continue: the next falling zero is at 5π/2 (3π/2 is rising).
        let (t, y) = (it.t(), *it.y());
        it.restart(&Harmonic, t, y);
        loop {
            if let StepOutcome::Event(0) = it.step(&Harmonic, 10.0).unwrap() {
                break;
            }
        }
        assert!((it.t() - 2.5 * std::f64::consts::PI).abs() < 1e-9);
    }

    #[test]
    fn dense_output_is_fourth_order_accurate() {
        let mut it = Integrator::new(Options {
            h_max: 0.1,
            ..opts(1e-12)
        });
        it.restart(&Harmonic, 0.0, [1.0, 0.0]);
        it.h = 0.1;
        it.step(&Harmonic, 10.0).unwrap();
        let d = *it.dense().unwrap();
        for k in 0..=10 {
            let t = d.t0 + d.h * k as f64 / 10.0;
            let y = d.state(t);
            let dy = d.derivative(t);
            assert!((y[0] - t.cos()).abs() < 1e-9, "t={t} y={}", y[0]);
            assert!((dy[0] + t.sin()).abs() < 1e-7, "t={t} dy={}", dy[0]);
        }
    }

    #[test]
    fn error_shrinks_with_tolerance() {
        let mut errors = vec![];
        for rtol in [1e-4, 1e-7, 1e-10] {
            let mut it = Integrator::new(opts(rtol));
            it.restart(&NoEvents, 0.0, [1.0, 0.0]);
            while it.step(&NoEvents, 20.0).unwrap() != StepOutcome::Reached {}
            errors.push((it.y()[0] - 20f64.cos()).abs());
        }
        assert!(
            errors[1] < errors[0] / 30.0 && errors[2] < errors[1] / 30.0,
            "{errors:?}"
        );
    }

    struct NoEvents;
    impl OdeSystem<2> for NoEvents {
        fn rhs(&self, t: f64, y: &[f64; 2], d: &mut [f64; 2]) {
            Harmonic.rhs(t, y, d)
        }
    }

    #[test]
    fn step_budget_is_reported() {
        let mut it = Integrator::new(Options {
            max_steps: 5,
            ..opts(1e-10)
        });
        it.restart(&NoEvents, 0.0, [1.0, 0.0]);
        let err = loop {
            match it.step(&NoEvents, 100.0) {
                Ok(_) => {}
                Err(e) => break e,
            }
        };
        assert!(matches!(err, SolverError::StepBudget { budget: 5, .. }));
    }

    fn with_method(rtol: f64, method: Method) -> Options<2> {
        Options {
            method,
            ..opts(rtol)
        }
    }

    /// Global error at t = 5 of fixed steps h (all accepted: loose tolerance, h_max = h).
    fn fixed_step_error<S: OdeSystem<2>>(
        sys: &S,
        method: Method,
        h: f64,
        y0: [f64; 2],
        exact: impl Fn(f64) -> f64,
    ) -> f64 {
        let mut it = Integrator::new(Options {
            h_max: h,
            ..with_method(1.0, method)
        });
        it.opts.atol = [1.0; 2];
        it.restart(sys, 0.0, y0);
        it.h = h;
        while it.step(sys, 5.0).unwrap() != StepOutcome::Reached {}
        assert_eq!(it.stats.rejected, 0);
        (it.y()[0] - exact(5.0)).abs()
    }

    struct Decay;
    impl OdeSystem<2> for Decay {
        fn rhs(&self, _t: f64, y: &[f64; 2], d: &mut [f64; 2]) {
            d[0] = -y[0];
            d[1] = -2.0 * y[1];
        }
    }

    #[test]
    fn dop853_converges_at_eighth_order_and_dp54_at_fifth() {
        // Steps in the asymptotic range of each method (DP54's leading error term cancels
        // in part on these linear problems at h = 0.5).
        let dop853_steps = [0.5, 0.25, 0.125];
        let dp54_steps = [0.1, 0.05, 0.025];
        for (method, order, steps) in [
            (Method::Dop853, 8.0, dop853_steps),
            (Method::Dp54, 5.0, dp54_steps),
        ] {
            type Exact<'a> = &'a dyn Fn(f64) -> f64;
            let cases: [(Exact, [f64; 2]); 2] = [
                (&|t: f64| t.cos(), [1.0, 0.0]),
                (&|t: f64| (-t).exp(), [1.0, 1.0]),
            ];
            for (k, (exact, y0)) in cases.into_iter().enumerate() {
                if method == Method::Dp54 && k == 0 {
                    continue; // on the oscillator DP54's error terms partly cancel (slope 4.2–4.7)
                }
                let errors: Vec<f64> = steps
                    .iter()
                    .map(|&h| {
                        if k == 0 {
                            fixed_step_error(&NoEvents, method, h, y0, exact)
                        } else {
                            fixed_step_error(&Decay, method, h, y0, exact)
                        }
                    })
                    .collect();
                for w in errors.windows(2) {
                    let slope = (w[0] / w[1]).log2();
                    assert!(
                        (slope - order).abs() < 0.6,
                        "{method:?} case {k}: slope {slope:.2} from errors {errors:?}"
                    );
                }
            }
        }
    }

    /// Largest error of the dense output (state and derivative) over one step of size h of
    /// the harmonic oscillator from t = 0.3.
    fn dense_error(method: Method, h: f64) -> (f64, f64) {
        let mut it = Integrator::new(Options {
            h_max: h,
            ..with_method(1.0, method)
        });
        it.opts.atol = [1.0; 2];
        let t0: f64 = 0.3;
        it.restart(&Harmonic, t0, [t0.cos(), -t0.sin()]);
        it.h = h;
        it.step(&Harmonic, 10.0).unwrap();
        let d = *it.dense().unwrap();
        assert_eq!(d.h, h);
        let (mut ey, mut edy) = (0.0f64, 0.0f64);
        for k in 1..10 {
            let t = d.t0 + d.h * k as f64 / 10.0;
            ey = ey.max((d.state(t)[0] - t.cos()).abs());
            edy = edy.max((d.derivative(t)[0] + t.sin()).abs());
        }
        (ey, edy)
    }

    #[test]
    fn dop853_dense_output_is_seventh_order() {
        // A p-th order interpolant has local error O(h^(p+1)): halving h divides it by 2^8,
        // and its derivative's by 2^7.
        let (y1, dy1) = dense_error(Method::Dop853, 0.8);
        let (y2, dy2) = dense_error(Method::Dop853, 0.4);
        let slope = (y1 / y2).log2();
        let dslope = (dy1 / dy2).log2();
        assert!(
            (slope - 8.0).abs() < 0.7,
            "state slope {slope:.2} ({y1:e}, {y2:e})"
        );
        assert!((dslope - 7.0).abs() < 0.7, "rate slope {dslope:.2}");
        assert!(y2 < 1e-9, "{y2:e}");
        // Dormand–Prince's 4th-order extension: slope 5.
        let (p1, _) = dense_error(Method::Dp54, 0.1);
        let (p2, _) = dense_error(Method::Dp54, 0.05);
        let slope = (p1 / p2).log2();
        assert!((slope - 5.0).abs() < 0.7, "dp54 dense slope {slope:.2}");
    }

    /// cos t touching the level 1 − c from above near t = 2π (a grazing double root for
    /// c → 0): events of g = y0 − (1 − c), either direction.
    struct Level(f64);
    impl OdeSystem<2> for Level {
        fn rhs(&self, t: f64, y: &[f64; 2], d: &mut [f64; 2]) {
            Harmonic.rhs(t, y, d)
        }
        fn event_count(&self) -> usize {
            2
        }
        fn events(&self, _t: f64, y: &[f64; 2], g: &mut [f64]) {
            g[0] = y[0] - (1.0 - self.0);
            g[1] = y[1]; // −sin t: falling zeros at 2π, 4π
        }
        fn event_direction(&self, i: usize) -> Direction {
            if i == 0 {
                Direction::Either
            } else {
                Direction::Falling
            }
        }
    }

    /// Every event of `sys` on [0, t_end] as (index, time), and the event-function calls.
    fn event_log<S: OdeSystem<2>>(sys: &S, o: Options<2>, t_end: f64) -> (Vec<(usize, f64)>, u64) {
        let mut it = Integrator::new(o);
        it.restart(sys, 0.0, [1.0, 0.0]);
        let mut log = vec![];
        loop {
            match it.step(sys, t_end).unwrap() {
                StepOutcome::Event(i) => {
                    log.push((i, it.t()));
                    let (t, y) = (it.t(), *it.y());
                    it.restart(sys, t, y);
                }
                StepOutcome::Reached => break,
                StepOutcome::Stepped => {}
            }
        }
        (log, it.stats.event_calls)
    }

    #[test]
    fn events_are_found_alike_by_both_methods_with_and_without_the_screen() {
        for method in [Method::Dp54, Method::Dop853] {
            for rtol in [1e-5, 1e-9] {
                // From a wide crossing to a near-graze (the level 1e-6 below the maximum: two
                // crossings 2.8e-3 apart around 2π, inside one step) and beyond it.
                for c in [0.5, 0.05, 1e-3, 1e-6, -1e-6] {
                    let o = with_method(rtol, method);
                    let (screened, calls_screened) = event_log(&Level(c), o, 13.0);
                    let (scanned, calls_scanned) = event_log(
                        &Level(c),
                        Options {
                            event_screen: false,
                            ..o
                        },
                        13.0,
                    );
                    assert_eq!(
                        screened.len(),
                        scanned.len(),
                        "{method:?} rtol {rtol:e} c {c}: {screened:?} vs {scanned:?}"
                    );
                    for (a, b) in screened.iter().zip(&scanned) {
                        assert_eq!(a.0, b.0);
                        assert!(
                            (a.1 - b.1).abs() < 1e-9,
                            "{method:?} rtol {rtol:e} c {c}: {screened:?} vs {scanned:?}"
                        );
                    }
                    if c == 0.5 {
                        // Crossings at ±acos(0.5) + 2πk and the falling zeros of −sin t at
                        // 2π, 4π: four level crossings and two velocity events before t = 13.
                        let expected: Vec<f64> = {
                            let a = 0.5f64.acos();
                            let tau = std::f64::consts::TAU;
                            let mut v = vec![a, tau - a, tau + a, 2.0 * tau - a];
                            v.extend([tau, 2.0 * tau]);
                            v.sort_by(f64::total_cmp);
                            v
                        };
                        let times: Vec<f64> = screened.iter().map(|e| e.1).collect();
                        assert_eq!(times.len(), expected.len(), "{screened:?}");
                        for (t, e) in times.iter().zip(&expected) {
                            assert!((t - e).abs() < 10.0 * rtol, "{method:?}: {t} vs {e}");
                        }
                        assert!(
                            rtol > 1e-6 || calls_screened < calls_scanned,
                            "{calls_screened} vs {calls_scanned}"
                        );
                    }
                }
            }
        }
    }

    /// An event function of t alone (y = t on a linear interpolant over [0, 1]), counting its
    /// evaluations.
    struct EventOfTime<F: Fn(f64) -> f64>(F, std::cell::Cell<u32>);
    impl<F: Fn(f64) -> f64> OdeSystem<1> for EventOfTime<F> {
        fn rhs(&self, _t: f64, _y: &[f64; 1], d: &mut [f64; 1]) {
            d[0] = 1.0;
        }
        fn event_count(&self) -> usize {
            1
        }
        fn events(&self, _t: f64, y: &[f64; 1], g: &mut [f64]) {
            self.1.set(self.1.get() + 1);
            g[0] = (self.0)(y[0]);
        }
    }

    /// The same with the function's rate in closed form (`None`: no rate at that t).
    struct EventWithRate<F, R>(F, R, std::cell::Cell<u32>);
    impl<F: Fn(f64) -> f64, R: Fn(f64) -> Option<f64>> OdeSystem<1> for EventWithRate<F, R> {
        fn rhs(&self, _t: f64, _y: &[f64; 1], d: &mut [f64; 1]) {
            d[0] = 1.0;
        }
        fn event_count(&self) -> usize {
            1
        }
        fn events(&self, _t: f64, y: &[f64; 1], g: &mut [f64]) {
            self.2.set(self.2.get() + 1);
            g[0] = (self.0)(y[0]);
        }
        fn event_rate_inputs(&self, _index: usize) -> usize {
            1
        }
        fn event_with_rate(
            &self,
            _index: usize,
            _t: f64,
            y: &[f64; 1],
            dydt: &[f64; 1],
        ) -> Option<(f64, f64)> {
            let rate = (self.1)(y[0])?;
            self.2.set(self.2.get() + 1);
            Some(((self.0)(y[0]), rate * dydt[0]))
        }
    }

    #[test]
    fn newton_refinement_from_a_zero_start_lands_on_the_root() {
        // A flight between two impacts: leaves zero at 0, back through zero at 0.01. With the
        // known zero divided out the function is linear, so the first probe is on the root.
        let g = |t: f64| 1e-4 * t * (0.01 - t) / 0.01;
        let sys = EventWithRate(
            g,
            |t: f64| Some(1e-4 * (0.01 - 2.0 * t) / 0.01),
            <_>::default(),
        );
        let (root, calls) = refine_root(&sys, &unit_step(), 0, (0.0, 1.0, true), 1.0, g(1.0));
        assert!((root - 0.01).abs() < 1e-15 && g(root) < 0.0, "{root}");
        assert_eq!(calls, u64::from(sys.2.get()));
        // 16 by bisection and Illinois (the test above); the rate at the start, the root, and
        // one probe tol/2 across it.
        assert!(calls <= 3, "{calls} evaluations");
    }

    #[test]
    fn newton_refinement_converges_in_a_few_steps_and_closes_the_bracket() {
        let g = |t: f64| t * t * t - 0.3;
        let exact = 0.3f64.cbrt();
        let with_rate = EventWithRate(g, |t: f64| Some(3.0 * t * t), <_>::default());
        let (root, calls) = refine_root(&with_rate, &unit_step(), 0, (0.0, -0.3, false), 1.0, 0.7);
        assert!((root - exact).abs() < 1e-15 && g(root) > 0.0, "{root}");
        let values = EventOfTime(g, Default::default());
        let (_, illinois) = refine_root(&values, &unit_step(), 0, (0.0, -0.3, false), 1.0, 0.7);
        assert!(calls <= 7 && calls < illinois, "{calls} against {illinois}");
    }

    #[test]
    fn newton_refinement_leaves_a_stretch_of_exact_zeros_with_a_rate() {
        // Exactly 0 on [0.25, 0.75) while the rate reads 1 (a function on its surface whose
        // closed-form rate is not zero): zero Newton steps must hand over to bisection.
        let g = |t: f64| {
            if t < 0.25 {
                -1.0
            } else if t < 0.75 {
                0.0
            } else {
                1.0
            }
        };
        let sys = EventWithRate(g, |_| Some(1.0), <_>::default());
        let (root, calls) = refine_root(&sys, &unit_step(), 0, (0.0, -1.0, false), 1.0, 1.0);
        assert!((0.75..0.75 + 1e-15).contains(&root), "{root}");
        assert!(calls < 70, "{calls} evaluations");
    }

    #[test]
    fn newton_refinement_bisects_where_the_rate_is_flat_or_missing() {
        // Exactly zero, with rate 0, on [0.4, 0.6); no rate at all past 0.8.
        let g = |t: f64| {
            if t < 0.4 {
                -1.0 + t
            } else if t < 0.6 {
                0.0
            } else {
                1.0
            }
        };
        let rate = |t: f64| (t < 0.8).then_some(if t < 0.4 { 1.0 } else { 0.0 });
        let sys = EventWithRate(g, rate, <_>::default());
        let (root, _) = refine_root(&sys, &unit_step(), 0, (0.0, -1.0, false), 1.0, 1.0);
        assert!((0.6..0.6 + 1e-15).contains(&root), "{root}");
        assert_eq!(g(root), 1.0);
    }

    fn unit_step() -> Dense<1> {
        let mut r = [[0.0; 1]; 8];
        r[1][0] = 1.0;
        Dense {
            t0: 0.0,
            h: 1.0,
            r,
            top: 4,
        }
    }

    #[test]
    fn root_refinement_from_a_sign_standing_in_for_a_zero() {
        // Leaves zero upward at t = 0 with slope 1e-4 and comes back down through zero at
        // 0.01: the start's tracked value is the sign +1, four orders off the function's scale.
        let sys = EventOfTime(|t: f64| 1e-4 * t * (0.01 - t) / 0.01, Default::default());
        let g_end = (sys.0)(1.0);
        let (root, calls) = refine_root(&sys, &unit_step(), 0, (0.0, 1.0, true), 1.0, g_end);
        assert!((root - 0.01).abs() < 1e-15 && (sys.0)(root) < 0.0, "{root}");
        assert_eq!(calls, u64::from(sys.1.get()));
        // Illinois from (0, +1) took 28 evaluations here (40 in a chattering clutch scene);
        // bisecting until the start is replaced, then Illinois, takes 15.
        assert!(sys.1.get() <= 16, "{} evaluations", sys.1.get());
    }

    #[test]
    fn root_refinement_returns_a_point_seen_past_the_crossing() {
        // Exactly zero on [0.4, 0.6): the first secant lands on 0.5, where the function is 0.
        // The point returned must be one where it was seen positive (≥ 0.6), not 0.5 + 4 ulp.
        let sys = EventOfTime(
            |t: f64| {
                if t < 0.4 {
                    -1.0
                } else if t < 0.6 {
                    0.0
                } else {
                    1.0
                }
            },
            Default::default(),
        );
        let (root, _) = refine_root(&sys, &unit_step(), 0, (0.0, -1.0, false), 1.0, 1.0);
        assert!((0.6..0.6 + 1e-15).contains(&root), "{root}");
        assert_eq!((sys.0)(root), 1.0);
    }

    #[test]
    fn hermite_screen_rejects_dips_and_double_roots() {
        // g = (2τ − 1)²: a double root at τ = ½, ends 1 with slopes ∓4.
        let no_root = |a: f64, da, b, db| no_root_inside((a, a.signum()), da, b, db);
        assert!(!no_root(1.0, -4.0, 1.0, 4.0));
        // Dips below zero between positive ends.
        assert!(!no_root(1.0, -6.0, 1.0, 6.0));
        // Falling steeply into a near-zero end value.
        assert!(!no_root(1.0, -3.0, 1e-3, -0.1));
        // Opposite signs, an exact zero at the end.
        assert!(!no_root(1.0, 0.0, -1.0, 0.0));
        assert!(!no_root(1.0, -1.0, 0.0, -1.0));
        // Monotone and far from zero; a shallow dip well above it; growth from near zero.
        assert!(no_root(2.0, -0.5, 1.5, -0.5));
        assert!(no_root(-2.0, 0.5, -1.5, 0.5));
        assert!(no_root(1.0, -0.4, 1.0, 0.4));
        assert!(no_root(1e-9, 1e-6, 1e-6, 1e-6));
        // From an exact zero: clear only leaving on the tracked side and staying there.
        assert!(no_root_inside((0.0, 1.0), 1.0, 1.0, 1.0));
        assert!(no_root_inside((0.0, -1.0), -1.0, -0.5, 0.2));
        assert!(!no_root_inside((0.0, -1.0), 1.0, 1.0, 1.0));
        assert!(!no_root_inside((0.0, 1.0), 0.0, 1.0, 1.0));
        // Untracked (the scan would adopt either side): clear leaving either way and staying.
        assert!(no_root_inside((0.0, 0.0), -1.0, -1.0, -1.0));
        assert!(no_root_inside((0.0, 0.0), 1.0, 1.0, 1.0));
        assert!(!no_root_inside((0.0, 0.0), 0.0, 1.0, 1.0));
        // Leaving on its side but back across zero (τ(1 − τ)·4 − 0.1τ-ish: ends below zero).
        assert!(!no_root_inside((0.0, 1.0), 4.0, -0.1, -4.0));
        // Leaving on its side, then a dip that may cross before climbing back.
        assert!(!no_root_inside((0.0, 1.0), 0.1, 0.1, 1.0));
    }
}
