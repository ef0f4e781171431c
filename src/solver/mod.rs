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
//! Method: Dormand–Prince 5(4) (Hairer, Nørsett & Wanner, Solving ODEs I, §II.5) with its
//! 4th-order continuous extension and a PI step-size controller.

use thiserror::Error;

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
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Stats {
    pub steps: u64,
    pub rejected: u64,
    pub rhs_evals: u64,
    pub events: u64,
    /// Intervals advanced in closed form instead of integrated (no RHS evaluations; not
    /// counted in `steps`). Set by the simulation driver.
    #[serde(default, rename = "exact_steps")]
    pub closed_form_steps: u64,
}

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

/// Dense output of the last accepted step: y(t0 + τh), τ ∈ [0, 1].
#[derive(Clone, Copy, Debug)]
pub struct Dense<const N: usize> {
    pub t0: f64,
    pub h: f64,
    r: [[f64; N]; 5],
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
        let th = self.tau(t);
        let th1 = 1.0 - th;
        let r = &self.r;
        std::array::from_fn(|i| {
            r[0][i] + th * (r[1][i] + th1 * (r[2][i] + th * (r[3][i] + th1 * r[4][i])))
        })
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
        let th = self.tau(t);
        let th1 = 1.0 - th;
        let r = &self.r;
        std::array::from_fn(|i| {
            let a = r[2][i] + th * (r[3][i] + th1 * r[4][i]);
            let da = r[3][i] + (1.0 - 2.0 * th) * r[4][i];
            let b = r[1][i] + th1 * a;
            let db = -a + th1 * da;
            (b + th * db) / self.h
        })
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
    g: [f64; MAX_EVENTS],
    dense: Option<Dense<N>>,
    needs_restart: bool,
    /// The system's [`OdeSystem::max_step`] at the last restart.
    h_cap: f64,
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
    /// The last step size is kept as the first guess.
    pub fn restart<S: OdeSystem<N>>(&mut self, sys: &S, t: f64, y: [f64; N]) {
        self.t = t;
        self.y = y;
        self.h_cap = sys.max_step();
        sys.rhs(t, &self.y, &mut self.f);
        self.stats.rhs_evals += 1;
        if self.h == 0.0 {
            self.h = self.initial_step(sys);
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
    }

    /// Event signs at the start. A function that is exactly zero (a jump put the state on its
    /// surface: θ = 0 after an impact, δ = 0 after a clutch reset) takes the sign the system
    /// says it will have ([`OdeSystem::sign_after_zero`]); if the system cannot tell, it stays
    /// undetermined and adopts the sign of its first sub-sample, so no crossing is reported at
    /// the restart point itself. (A generic probe along y + δ·f is not used: where the rate is
    /// also ~0, e.g. a reset at a velocity crossing, its sign is decided by roundoff.)
    fn reset_event_signs<S: OdeSystem<N>>(&mut self, sys: &S) {
        let m = sys.event_count();
        sys.events(self.t, &self.y, &mut self.g[..m]);
        for i in 0..m {
            if self.g[i] == 0.0 {
                self.g[i] = sys.sign_after_zero(i, self.t, &self.y);
            }
        }
    }

    fn error_scale(&self, i: usize, a: f64, b: f64) -> f64 {
        self.opts.atol[i] + self.opts.rtol * a.abs().max(b.abs())
    }

    /// Error norm: the larger of the RMS norms over the two groups of components (the leading
    /// `opts.controlled` state components, and the trailing quadratures), so adding well-behaved
    /// quadratures never dilutes the state's error.
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
        let split = self.opts.controlled.min(N);
        rms(0..split).max(rms(split..N))
    }

    /// Hairer's starting step guess (Solving ODEs I, §II.4).
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
            (0.01 / d1.max(d2)).powf(0.2)
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
            let (y1, f1, err, k) = self.trial(sys, h);
            if !err.is_finite() || y1.iter().any(|v| !v.is_finite()) {
                // Treat as a failed step; shrink hard. A genuinely non-finite solution ends
                // in StepTooSmall, reported by the caller with its time.
                self.stats.rejected += 1;
                self.h = h * 0.1;
                if self.h < 1e-14 * self.t.abs().max(1.0) {
                    return Err(SolverError::NonFinite { t: self.t });
                }
                continue;
            }
            if err <= 1.0 {
                // PI controller (β = 0.04), as in DOPRI5.
                let fac = (err.powf(0.17) * self.err_old.powf(-0.04) / 0.9).clamp(0.1, 5.0);
                self.err_old = err.max(1e-4);
                let h_new = h / fac;
                self.stats.steps += 1;
                let dense = self.build_dense(h, &y1, &k);
                let event = self.locate_event(sys, &dense);
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
            self.stats.rejected += 1;
            self.h = h / (err.powf(0.2) / 0.9).min(10.0);
        }
    }

    #[allow(clippy::type_complexity)]
    fn trial<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        h: f64,
    ) -> ([f64; N], [f64; N], f64, [[f64; N]; 7]) {
        let t = self.t;
        let y = &self.y;
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
        let err = self.norm(&e, y, &y1);
        (y1, k7, err, [k1, k2, k3, k4, k5, k6, k7])
    }

    fn build_dense(&self, h: f64, y1: &[f64; N], k: &[[f64; N]; 7]) -> Dense<N> {
        let y0 = &self.y;
        let mut r = [[0.0; N]; 5];
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
        Dense { t0: self.t, h, r }
    }

    /// Scan the step for triggering sign changes; return the earliest located event, and
    /// update the tracked signs to the end of the step otherwise.
    fn locate_event<S: OdeSystem<N>>(&mut self, sys: &S, dense: &Dense<N>) -> Option<(usize, f64)> {
        let m = sys.event_count();
        if m == 0 {
            return None;
        }
        let mut g_prev = self.g;
        let mut t_prev = dense.t0;
        for sample in 1..=EVENT_SAMPLES {
            let t_s = if sample == EVENT_SAMPLES {
                dense.t1()
            } else {
                dense.t0 + dense.h * sample as f64 / EVENT_SAMPLES as f64
            };
            let y_s = dense.state(t_s);
            let mut g_s = [0.0; MAX_EVENTS];
            sys.events(t_s, &y_s, &mut g_s[..m]);
            let mut best: Option<(usize, f64)> = None;
            for i in 0..m {
                if g_prev[i] == 0.0 {
                    continue; // undetermined sign: adopt the new one below
                }
                if sys.event_direction(i).triggers(g_prev[i], g_s[i]) {
                    let t_root = refine_root(sys, dense, i, t_prev, g_prev[i], t_s, g_s[i]);
                    if best.is_none_or(|(_, tb)| t_root < tb) {
                        best = Some((i, t_root));
                    }
                }
            }
            if best.is_some() {
                return best;
            }
            for i in 0..m {
                if g_s[i] != 0.0 {
                    g_prev[i] = g_s[i];
                }
            }
            t_prev = t_s;
        }
        self.g = g_prev;
        None
    }
}

/// Illinois (modified regula falsi) on the dense interpolant. Returns the right end of the final
/// bracket, where the function already has its post-crossing sign.
fn refine_root<const N: usize, S: OdeSystem<N>>(
    sys: &S,
    dense: &Dense<N>,
    index: usize,
    mut a: f64,
    mut ga: f64,
    mut b: f64,
    mut gb: f64,
) -> f64 {
    let m = sys.event_count();
    let mut g = [0.0; MAX_EVENTS];
    let tol = 4.0 * f64::EPSILON * b.abs().max(dense.h.abs());
    let mut side = 0i8;
    for _ in 0..200 {
        if b - a <= tol {
            break;
        }
        let mut c = b - gb * (b - a) / (gb - ga);
        // Keep c strictly inside the bracket; fall back to bisection when it is not.
        if !(c > a && c < b) {
            c = 0.5 * (a + b);
        }
        sys.events(c, &dense.state(c), &mut g[..m]);
        let gc = g[index];
        if gc == 0.0 {
            // Exactly on the surface: step just past it, onto the post-crossing side.
            return (c + tol).min(b);
        }
        if gc.signum() == gb.signum() {
            b = c;
            gb = gc;
            if side == 1 {
                ga *= 0.5;
            }
            side = 1;
        } else {
            a = c;
            ga = gc;
            if side == -1 {
                gb *= 0.5;
            }
            side = -1;
        }
    }
    b
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
            rtol,
            atol: [rtol; 2],
            h_max: f64::INFINITY,
            controlled: 2,
            max_steps: 1_000_000,
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
}
