//! The rigid block's sine and cosine of sα − θ, on its right-hand side's critical path.
//!
//! Why not only the `libm` crate: its `sincos` is the right algorithm (fdlibm's kernels,
//! < 1 ulp) but a call behind a range test, a tiny-argument test and two kernel calls, each a
//! Horner chain; on the bare block every Runge–Kutta stage waits on it (BENCHMARKS.md,
//! "Session 13"). A rocking block's angle sα − θ stays within ±π/4 unless it is close to
//! overturning, so there this module evaluates the same fdlibm polynomials inline, in Estrin
//! form (independent pairs instead of one chain); beyond π/4, for tiny arguments and for NaN
//! it is `libm::sincos`. The results are within 1 ulp of `libm`'s (tested). `sin` and `cos`
//! are the same kernels, so that sin α computed once equals the S of the kinematics at θ = 0
//! exactly. (The pulses keep glibc's `sin`: the same reduction and kernels written here out
//! of line were slower on their phases, up to 2π.)

// fdlibm's k_sin and k_cos coefficients (musl, FreeBSD msun), written as published, as in
// the `libm` crate (each rounds to the intended double).
#[allow(clippy::excessive_precision)]
mod coefficients {
    pub const S1: f64 = -1.666_666_666_666_663_243_48e-01;
    pub const S2: f64 = 8.333_333_333_322_489_461_24e-03;
    pub const S3: f64 = -1.984_126_982_985_794_931_34e-04;
    pub const S4: f64 = 2.755_731_370_707_006_767_89e-06;
    pub const S5: f64 = -2.505_076_025_340_686_341_95e-08;
    pub const S6: f64 = 1.589_690_995_211_550_102_21e-10;
    pub const C1: f64 = 4.166_666_666_666_660_190_37e-02;
    pub const C2: f64 = -1.388_888_888_887_410_957_49e-03;
    pub const C3: f64 = 2.480_158_728_947_672_941_78e-05;
    pub const C4: f64 = -2.755_731_435_139_066_330_35e-07;
    pub const C5: f64 = 2.087_572_321_298_174_827_90e-09;
    pub const C6: f64 = -1.135_964_755_778_819_482_65e-11;
}
use coefficients::*;

/// Below this |x| (2⁻²⁷√2: fdlibm returns (x, 1) from just under it) `libm` itself is called,
/// so that the two agree bit for bit where the answer is exact.
const TINY: f64 = 1.053_671_212_772_350_9e-8;

/// (sin x, cos x).
#[inline(always)]
pub fn sincos(x: f64) -> (f64, f64) {
    if !(TINY..=std::f64::consts::FRAC_PI_4).contains(&x.abs()) {
        return libm::sincos(x);
    }
    let z = x * x;
    let w = z * z;
    let w2 = w * w;
    // fdlibm's __kernel_sin: x + x z (S1 + S2 z + … + S6 z⁵), the polynomial in pairs.
    let s = x + (z * x) * ((S1 + S2 * z) + w * (S3 + S4 * z) + w2 * (S5 + S6 * z));
    // fdlibm's __kernel_cos: 1 − z/2 + z² (C1 + … + C6 z⁵), with the correction of 1 − z/2's
    // rounding.
    let pc = (C1 + C2 * z) + w * (C3 + C4 * z) + w2 * (C5 + C6 * z);
    let hz = 0.5 * z;
    let one_minus_hz = 1.0 - hz;
    let c = one_minus_hz + (((1.0 - one_minus_hz) - hz) + w * pc);
    (s, c)
}

/// sin x, by [`sincos`].
#[inline]
pub fn sin(x: f64) -> f64 {
    sincos(x).0
}

/// cos x, by [`sincos`].
#[inline]
pub fn cos(x: f64) -> f64 {
    sincos(x).1
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in units in the last place.
    fn ulps(a: f64, b: f64) -> u64 {
        (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs()
    }

    #[test]
    fn within_one_ulp_of_libm_and_symmetric() {
        let mut differ = 0;
        let n = 200_000;
        for i in 0..=n {
            // Dense over ±1 (past π/4, where libm takes over), log-spaced down to tiny, and
            // near multiples of π/2 (libm's reduction).
            let lin = -1.0 + 2.0 * i as f64 / n as f64;
            let log = 10f64.powf(-12.0 + 12.0 * i as f64 / n as f64);
            let k = (1 + i % 6) as f64;
            let near = k * std::f64::consts::FRAC_PI_2 + (i as f64 - n as f64 / 2.0) * 1e-12;
            for x in [lin, log, -log, near, -near] {
                let (s, c) = sincos(x);
                let (ls, lc) = libm::sincos(x);
                assert!(ulps(s, ls) <= 1, "sin {x:e}: {s:e} against libm {ls:e}");
                assert!(ulps(c, lc) <= 1, "cos {x:e}: {c:e} against libm {lc:e}");
                differ += usize::from(s != ls || c != lc);
                assert_eq!(sincos(-x), (-s, c), "odd sine, even cosine at {x:e}");
            }
        }
        // The same polynomials in another order: most arguments agree to the bit.
        assert!(differ < n / 4, "{differ} of {} differ from libm", 5 * n);
        assert_eq!(sincos(0.0), (0.0, 1.0));
        assert!(sincos(f64::NAN).0.is_nan());
    }

    #[test]
    fn sin_and_cos_are_the_pair() {
        for x in [0.1745, 0.5, -0.7, 1.2, 3.0] {
            assert_eq!((sin(x), cos(x)), sincos(x));
        }
        // Pythagoras to roundoff on the fast range.
        for i in 0..1000 {
            let x = -0.78 + 1.56 * i as f64 / 1000.0;
            let (s, c) = sincos(x);
            assert!((s * s + c * c - 1.0).abs() < 4.0 * f64::EPSILON);
        }
    }
}
