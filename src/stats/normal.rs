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
