//! The standard normal distribution as the fits need it: Φ, ln Φ and the inverse Mills ratio
//! φ/Φ, accurate far into the lower tail (where Φ underflows and the ratio still matters for
//! Newton steps on a poor start). Built on `libm::erfc` (already a dependency); no crate in the
//! tree offers the tail-safe ln Φ and Mills ratio, so these few lines are written out here.

const SQRT_2: f64 = std::f64::consts::SQRT_2;
/// ln √(2π).
const LN_SQRT_2PI: f64 = 0.918_938_533_204_672_8;
/// Below this, Φ(t) is taken from its asymptotic series (erfc is within a few ulps above it).
const TAIL: f64 = -30.0;

/// Standard normal density φ(t).
pub fn pdf(t: f64) -> f64 {
    (-0.5 * t * t - LN_SQRT_2PI).exp()
}

/// Standard normal distribution function Φ(t).
pub fn cdf(t: f64) -> f64 {
    0.5 * libm::erfc(-t / SQRT_2)
}

/// The standard normal quantile Φ⁻¹(u) for 0 < u < 1 (±∞ at 0 and 1, NaN outside).
/// Uncertain parameters are drawn by inversion (a Latin hypercube stratifies u, not t), and
/// no crate in the tree offers Φ⁻¹: Acklam's rational approximation (relative error
/// 1.15e-9) refined by one Halley step on `erfc`, which brings it to a few ulps.
pub fn quantile(u: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] = [
        7.784_695_709_041_462e-3,
        3.224_671_290_700_398e-1,
        2.445_134_137_142_996,
        3.754_408_661_907_416,
    ];
    const LOW: f64 = 0.024_25;
    if u.is_nan() || !(0.0..=1.0).contains(&u) {
        return f64::NAN;
    }
    if u == 0.0 {
        return f64::NEG_INFINITY;
    }
    if u == 1.0 {
        return f64::INFINITY;
    }
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    let t = if u < LOW {
        tail((-2.0 * u.ln()).sqrt())
    } else if u > 1.0 - LOW {
        -tail((-2.0 * (1.0 - u).ln()).sqrt())
    } else {
        let q = u - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    };
    // One Halley step on e = Φ(t) − u; above ½ as (1 − u) − Q(t), Q(t) = 1 − Φ(t) taken from
    // erfc, which keeps the upper tail's digits.
    let e = if u > 0.5 {
        (1.0 - u) - 0.5 * libm::erfc(t / SQRT_2)
    } else {
        cdf(t) - u
    };
    let step = e * (0.5 * t * t + LN_SQRT_2PI).exp();
    t - step / (1.0 + 0.5 * t * step)
}

/// Asymptotic series of Φ(t)·t/φ(t)·(−1) for t ≪ 0: 1 − 1/t² + 3/t⁴ − 15/t⁶.
fn tail_series(t: f64) -> f64 {
    let u = 1.0 / (t * t);
    1.0 - u + 3.0 * u * u - 15.0 * u * u * u
}

/// ln Φ(t), finite for every finite t.
pub fn ln_cdf(t: f64) -> f64 {
    if t < TAIL {
        -0.5 * t * t - LN_SQRT_2PI - (-t).ln() + tail_series(t).ln()
    } else {
        cdf(t).ln()
    }
}

/// Inverse Mills ratio φ(t)/Φ(t) (≈ −t for t ≪ 0, → 0 for t ≫ 0).
pub fn mills(t: f64) -> f64 {
    if t < TAIL {
        -t / tail_series(t)
    } else {
        pdf(t) / cdf(t)
    }
}

/// d/dt of [`mills`]: −λ(t)(t + λ(t)), which lies in (−1, 0).
pub fn mills_slope(t: f64) -> f64 {
    let l = mills(t);
    -l * (t + l)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cdf_matches_tabulated_values() {
        // Abramowitz & Stegun table 26.1.
        assert!((cdf(1.0) - 0.841_344_746_068_543).abs() < 1e-15);
        assert!((cdf(-1.959_963_984_540_054) - 0.025).abs() < 1e-15);
        assert!((cdf(0.0) - 0.5).abs() < 1e-16);
    }

    /// Φ⁻¹ inverts Φ to a few ulps over the body and both tails, and matches tabulated
    /// quantiles (A&S 26.2).
    #[test]
    fn quantile_inverts_the_distribution_function() {
        assert!((quantile(0.975) - 1.959_963_984_540_054).abs() < 1e-14);
        assert!((quantile(0.025) + 1.959_963_984_540_054).abs() < 1e-14);
        assert_eq!(quantile(0.5), 0.0);
        for t in [-8.0, -5.0, -2.2, -1.0, -0.01, 0.3, 1.7, 3.0, 5.0] {
            let back = quantile(cdf(t));
            assert!((back - t).abs() < 1e-9 * t.abs().max(1.0), "{t}: {back}");
        }
        // Symmetric: Φ⁻¹(1 − u) = −Φ⁻¹(u).
        for u in [1e-6, 0.01, 0.2, 0.4] {
            assert!((quantile(1.0 - u) + quantile(u)).abs() < 1e-9, "{u}");
        }
        assert!(quantile(-0.1).is_nan() && quantile(0.0) == f64::NEG_INFINITY);
    }

    #[test]
    fn tail_is_continuous_at_the_switch() {
        // Both branches of ln Φ and λ agree where they meet (relative 1e-9).
        let below = TAIL - 1e-9;
        let above = TAIL + 1e-9;
        assert!((ln_cdf(below) / ln_cdf(above) - 1.0).abs() < 1e-9);
        assert!((mills(below) / mills(above) - 1.0).abs() < 1e-9);
        // And far below, where Φ itself underflows, ln Φ is still finite and ≈ −t²/2.
        let t = -60.0;
        assert!(cdf(t) == 0.0 && ln_cdf(t).is_finite());
        assert!((ln_cdf(t) + 0.5 * t * t).abs() < 7.0);
    }

    #[test]
    fn mills_slope_is_the_derivative() {
        for t in [-40.0, -5.0, -0.3, 0.0, 2.0, 6.0] {
            let h = 1e-5;
            let numeric = (mills(t + h) - mills(t - h)) / (2.0 * h);
            assert!(
                (mills_slope(t) - numeric).abs() < 1e-6,
                "t = {t}: {} vs {numeric}",
                mills_slope(t)
            );
        }
    }
}
