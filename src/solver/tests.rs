//! Unit tests of the integrator against closed forms.

use super::events::{no_root_inside, refine_root};
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
    let d = it.dense_now(&Harmonic).unwrap();
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
    let d = it.dense_now(&Harmonic).unwrap();
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
