//! One-dimensional searches on smooth functions of time: a root in a sign-change bracket and
//! a maximum around a best sample. Used by the models' peak searches and the analytic pulses'
//! scans; they know nothing of either.

/// A zero of f in [a, b] where f(a) = fa and f(b) = fb have opposite signs: Illinois
/// (modified regula falsi), to a bracket of 1e-12 of b − a or a few ulps of t, whichever is
/// wider (or until f is exactly 0).
pub fn illinois_root(
    f: impl Fn(f64) -> f64,
    mut a: f64,
    mut fa: f64,
    mut b: f64,
    mut fb: f64,
) -> f64 {
    // A fraction of the bracket alone can fall below the spacing of floats at large t.
    let tol = (1e-12 * (b - a)).max(4.0 * f64::EPSILON * a.abs().max(b.abs()));
    // Which end the last step kept: an end kept twice has its value halved (Illinois).
    let mut kept = 0i8;
    for _ in 0..100 {
        if b - a <= tol {
            break;
        }
        let mut c = a - fa * (b - a) / (fb - fa);
        if !(c > a && c < b) {
            c = 0.5 * (a + b);
        }
        let fc = f(c);
        if fc == 0.0 {
            return c;
        }
        if (fc < 0.0) == (fa < 0.0) {
            (a, fa) = (c, fc);
            if kept == 1 {
                fb *= 0.5;
            }
            kept = 1;
        } else {
            (b, fb) = (c, fc);
            if kept == -1 {
                fa *= 0.5;
            }
            kept = -1;
        }
    }
    0.5 * (a + b)
}

/// Brent's (1973) parabolic-interpolation search for the maximum (t, f(t)) of f on [lo.0, hi.0],
/// started from the best sample `x` between its two neighbours, all three with their values
/// (the first step is the parabola through them): 8 evaluations typically (5–27 over sample
/// placements on a skewed peak) to a bracket of 1e-8 of the interval, where golden section
/// needed 52. The maximum's value is flat in the location, so its relative error is
/// ~(1e-8)², below roundoff. Written here rather than taken from a crate (argmin's
/// `BrentOpt`) because it starts from the samples the caller already has.
pub fn brent_max(
    f: impl Fn(f64) -> f64,
    lo: (f64, f64),
    x: (f64, f64),
    hi: (f64, f64),
) -> (f64, f64) {
    const CGOLD: f64 = 0.381_966_011_250_105_1;
    let (mut a, mut b) = (lo.0, hi.0);
    if b <= a {
        return x;
    }
    let width = b - a;
    let tol = (1e-8 * width).max(4.0 * f64::EPSILON * a.abs().max(b.abs()));
    // Minimise −f. x is the best point, w the second best, v the previous w.
    let (mut x, mut fx) = (x.0, -x.1);
    let ((mut w, mut fw), (mut v, mut fv)) = if -lo.1 <= -hi.1 {
        ((lo.0, -lo.1), (hi.0, -hi.1))
    } else {
        ((hi.0, -hi.1), (lo.0, -lo.1))
    };
    if x <= a || x >= b {
        // The best sample is an end of the bracket. If f falls from it into the bracket, that
        // end is the maximum: with at most one extremum inside (what the samples' spacing is
        // chosen for), an interior maximum above it would need a minimum between them too.
        let inward = if x >= b {
            b - 1e-6 * (b - a)
        } else {
            a + 1e-6 * (b - a)
        };
        if f(inward) < -fx {
            return (x, -fx);
        }
        // Else start inside it.
        x = a + CGOLD * (b - a);
        fx = -f(x);
        (w, fw, v, fv) = (x, fx, x, fx);
    }
    let (mut d, mut e) = (0.0f64, b - a);
    let mut last = false;
    for _ in 0..60 {
        let xm = 0.5 * (a + b);
        if (x - xm).abs() <= 2.0 * tol - 0.5 * (b - a) {
            break;
        }
        let golden = |x: f64| if x >= xm { a - x } else { b - x };
        if e.abs() > tol {
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            }
            q = q.abs();
            let e_before = e;
            e = d;
            if p.abs() >= (0.5 * q * e_before).abs() || p <= q * (a - x) || p >= q * (b - x) {
                e = golden(x);
                d = CGOLD * e;
            } else {
                d = p / q;
                let u = x + d;
                if u - a < 2.0 * tol || b - u < 2.0 * tol {
                    d = tol.copysign(xm - x);
                }
                // The parabola's own prediction of the gain at its vertex: below roundoff of
                // the value, one last evaluation there ends the search. Trusted only once its
                // points are within 1e-5 of the bracket of x (convex, as near a maximum): its
                // vertex is then off the true one by ~(spacing)²/scale, far below the
                // spacing, and the value's error below roundoff. (Through the raw samples the
                // prediction can be small by accident: 7e-7 errors were seen.)
                let spacing = (x - w).abs().max((x - v).abs());
                if (v - w) * (v - x) * (w - x) != 0.0 && spacing <= 1e-5 * width {
                    let curvature = 2.0 * ((fv - fx) / (v - x) - (fw - fx) / (w - x)) / (v - w);
                    last = curvature > 0.0 && 0.5 * curvature * d * d <= 1e-15 * fx.abs();
                }
            }
        } else {
            e = golden(x);
            d = CGOLD * e;
        }
        let u = if d.abs() >= tol {
            x + d
        } else {
            x + tol.copysign(d)
        };
        let fu = -f(u);
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
        if last {
            break;
        }
    }
    (x, -fx)
}

/// A root of f in the bracket (a, f(a)), (b, f(b)) of opposite signs, from f and its rate:
/// bracketed Newton (rtsafe, Press et al.) from the secant of the ends, bisecting where a
/// Newton step leaves the bracket or does not halve the step before it (rounding noise near
/// the root). Every probe keeps tol/2 inside the bracket, so once Newton has converged from
/// one side the next probe closes the bracket from the other. Stops at a bracket of `tol`;
/// returns its post-crossing end, where that sign was seen, and the evaluations made.
pub fn newton_root(
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

    #[test]
    fn illinois_stops_at_float_resolution_far_from_zero() {
        use std::cell::Cell;
        let calls = Cell::new(0);
        // A bracket of 2.5e-4 s at t = 100 s: 1e-12 of it is below the spacing of floats.
        // Its root lies between two floats, so f is never exactly zero there.
        let s0 = 0.000_123_456_789_f64.sin();
        let f = |t: f64| {
            calls.set(calls.get() + 1);
            (t - 100.0).sin() - s0
        };
        let root = illinois_root(f, 100.0, f(100.0), 100.00025, f(100.00025));
        assert!((root - 100.000_123_456_789).abs() < 1e-12, "{root}");
        assert!(calls.get() < 30, "{} evaluations", calls.get());
    }

    #[test]
    fn illinois_finds_the_root_of_a_cubic_to_roundoff() {
        // (t − 0.3)(t² + 1) has one real root, at 0.3.
        let f = |t: f64| (t - 0.3) * (t * t + 1.0);
        let root = illinois_root(f, -1.0, f(-1.0), 2.0, f(2.0));
        assert!((root - 0.3).abs() < 1e-11, "{root}");
    }

    #[test]
    fn brent_finds_a_skewed_maximum_from_three_samples() {
        // sin t e^{−t/3} peaks where tan t = 3: t* = atan 3.
        let f = |t: f64| t.sin() * (-t / 3.0).exp();
        let t_star = 3f64.atan();
        let want = f(t_star);
        let (t, v) = brent_max(f, (0.5, f(0.5)), (1.0, f(1.0)), (1.6, f(1.6)));
        assert!((v - want).abs() < 1e-15 * want, "{v} vs {want}");
        assert!((t - t_star).abs() < 1e-7, "{t} vs {t_star}");
        // The best sample at an end of the bracket: the search starts inside it.
        let (_, v) = brent_max(f, (1.0, f(1.0)), (1.0, f(1.0)), (1.5, f(1.5)));
        assert!((v - want).abs() < 1e-15 * want);
        // Samples placed so that the parabola through them peaks at the middle one (f(x − h) =
        // f(x + h)) while the true maximum is 1e-3 away: the search must not stop there.
        let h = 0.1;
        let symmetric = |x: f64| f(x - h) - f(x + h);
        let x = illinois_root(
            symmetric,
            t_star - 0.05,
            symmetric(t_star - 0.05),
            t_star + 0.05,
            symmetric(t_star + 0.05),
        );
        let (_, v) = brent_max(f, (x - h, f(x - h)), (x, f(x)), (x + h, f(x + h)));
        assert!((v - want).abs() < 1e-15 * want, "{v} vs {want}");
        // f still rising at the bracket's right end, or falling from its left end: the end.
        assert_eq!(
            brent_max(f, (0.5, f(0.5)), (1.0, f(1.0)), (1.0, f(1.0))),
            (1.0, f(1.0))
        );
        assert_eq!(
            brent_max(f, (1.5, f(1.5)), (1.5, f(1.5)), (2.0, f(2.0))),
            (1.5, f(1.5))
        );
    }
}
