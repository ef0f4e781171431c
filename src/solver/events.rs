//! Event location: the signs at a restart, the per-step screen, the sub-sampled scan and the
//! root refinement on the dense output.

use super::search::newton_root;
use super::{Dense, Integrator, MAX_EVENTS, OdeSystem, Step};

/// Sub-intervals of each step on which event signs are sampled, so that a function crossing
/// twice inside one step is still seen.
const EVENT_SAMPLES: usize = 4;

/// Steps without the event screen after it failed on three steps in a row.
const SCREEN_PAUSE: u32 = 16;

impl<const N: usize> Integrator<N> {
    /// Event signs at the start. A function that is exactly zero (a jump put the state on its
    /// surface: θ = 0 after an impact, δ = 0 after a clutch reset) takes the sign the system
    /// says it will have ([`OdeSystem::sign_after_zero`]); if the system cannot tell, it stays
    /// undetermined and adopts the sign of its first sub-sample, so no crossing is reported at
    /// the restart point itself. (A generic probe along y + δ·f is not used: where the rate is
    /// also ~0, e.g. a reset at a velocity crossing, its sign is decided by roundoff.)
    /// Where the system has the rates in closed form they come with the values, for the first
    /// step's screen (one call of the kinematics per restart instead of two).
    pub(super) fn reset_event_signs<S: OdeSystem<N>>(&mut self, sys: &S) {
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
    pub(super) fn locate_event<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        step: &Step<N>,
        f1: &[f64; N],
        ends_at_stop: bool,
    ) -> Option<(usize, f64)> {
        let (y1, h, t1) = (&step.y1, step.h, step.t0 + step.h);
        let m = sys.event_count();
        if m == 0 {
            return None;
        }
        let paused = self.screen_pause > 0;
        self.screen_pause = self.screen_pause.saturating_sub(1);
        if !self.opts.event_screen || self.force_scan || paused {
            self.force_scan = false;
            self.rates_valid = false;
            sys.events(t1, y1, &mut self.g_val[..m]);
            self.stats.event_calls += 1;
            return self.scan(sys, Some(&self.g_val.clone()));
        }
        let eps = 1e-7 * h;
        if !self.rates_valid {
            let (t0, y0, f0) = (self.t, self.y, self.f);
            let mut g0 = self.g_val;
            let mut rates0 = [0.0; MAX_EVENTS];
            self.event_rates(sys, t0, &y0, &f0, eps, &mut g0, &mut rates0, true);
            self.g_rate = rates0;
        }
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
            // The whole array: a copy of a fixed size is a few vector moves, where one of
            // `m` elements was a call of memcpy (~1 % of the bare block's time). Past `m` no
            // function is read, and `g1` holds zeros there.
            self.g = g1;
            self.sign_only = [false; MAX_EVENTS];
            None
        } else {
            self.scan(sys, Some(&g1))
        };
        if found.is_none() {
            self.g_val = g1;
            self.g_rate = rates1;
            // At a forcing breakpoint differenced rates change side; closed-form ones are
            // functions of y and dy/dt, both continuous at a kink (a jump of the forcing
            // refreshes the derivative and invalidates them), so they serve the next step as
            // they are: one call of the event functions per stop saved, which a record scene
            // makes at every sample.
            self.rates_valid = !ends_at_stop || closed_form;
        }
        found
    }

    /// Sample every event function at [`EVENT_SAMPLES`] points of the step (the last one is
    /// the end point, whose values `at_end` may already hold); refine the earliest
    /// triggering sign change.
    fn scan<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        at_end: Option<&[f64; MAX_EVENTS]>,
    ) -> Option<(usize, f64)> {
        let dense = &self
            .dense_now(sys)
            .expect("the step just accepted has a dense output");
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
pub fn no_root_inside((a, tracked): (f64, f64), da: f64, b: f64, db: f64) -> bool {
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
    // Cubic Bernstein coefficients of H, s·(a, a + da/3, b − db/3, b), elevated to degree 4:
    // c₁ = (b₀ + 3b₁)/4, c₂ = (b₁ + b₂)/2, c₃ = (3b₂ + b₃)/4, and τ²(1−τ)² = B₂,₄(τ)/6. Only
    // their signs matter, so they are tested times 4, 12 and 4: no division waits on the
    // step's end values.
    let c1 = s * (4.0 * a + da);
    let c2 = 2.0 * s * (3.0 * (a + b) + da - db) - v;
    let c3 = s * (4.0 * b - db);
    c1 > 0.0 && c2 > 0.0 && c3 > 0.0
}

/// A root of event function `index` on the dense interpolant, from the bracket's start
/// (a, g(a), whether g(a) is only a sign) to (b, g(b)): bracketed Newton where the system
/// gives the function's rate in closed form ([`newton_root`]; ~4 evaluations where Illinois
/// took 14–19 on the Fig. 8 mechanistic scene), Illinois (modified regula falsi) otherwise.
/// Both stop at a bracket of a few ulps of t and return its right end, where the function
/// was seen with its post-crossing sign, and the evaluations made.
pub(super) fn refine_root<const N: usize, S: OdeSystem<N>>(
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
