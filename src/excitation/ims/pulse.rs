//! Pulse classification of one component (Shahi & Baker 2014, BSSA 104(5), 2456–2466; the
//! extraction of Baker 2007, BSSA 97(5)).
//!
//! 1. The continuous wavelet transform of the ground velocity with the Daubechies-4 mother
//!    wavelet ψ (support [0, 7], unit L² norm), C(s, τ) = ∫ v(t) ψ((t − τ)/s) dt / √s, over
//!    pseudo-periods s / f_c from [`MIN_PERIOD`] to [`MAX_PERIOD`] (f_c is ψ's centre
//!    frequency, the peak of |ψ̂|). The pulse's scale is the one of the largest
//!    |C(s, τ)| / √s (the L¹-normalised transform): for a harmonic v of period T that largest
//!    value is at s = f_c T exactly, so the pseudo-period of a pulse is its own period. The
//!    L²-normalised |C| of MATLAB's `cwt` peaks past it (√s |ψ̂(s/T)| still grows where
//!    |ψ̂| has begun to fall) and gives Mavroeidis–Papageorgiou pulses a Tp 14–17 % long.
//!    Only wavelets that lie in the record count (the central 99 % of ψ² within the record's
//!    duration): a pulse is an event in the record, and a wavelet hanging over an end fits
//!    whatever the record does there (the long-period drift of an unprocessed record, or
//!    the switch-on of a harmonic), not a pulse.
//! 2. At that scale the wavelet at the τ of the largest |C| is extracted (the least-squares
//!    projection of v onto ψ((t − τ)/s)); it is the pulse, v minus it the residual.
//! 3. PGV ratio = max|residual| / max|v| and energy ratio = ∫residual² / ∫v² (trapezoid on
//!    the samples) enter the published indicator with the PGV in cm/s; the record is
//!    pulse-like when the indicator is positive, the pulse arrives early (more than 5 % of
//!    its ∫v² before the record reaches 17 % of its own) and its period is at least
//!    [`MIN_TP`]. Tp is the extracted wavelet's pseudo-period.
//!
//! Where rocklab differs from Baker's MATLAB code, as far as the publications describe it:
//! the scale is chosen on the L¹-normalised transform and among wavelets inside the record
//! (above; MATLAB's `cwt` pads the record with zeros), so real records' Tp come out 10–13 %
//! below the published ones (docs/MODEL.md); f_c is the true peak of |ψ̂|
//! (0.6977; MATLAB's and PyWavelets' `centfrq` report 5/7 = 0.7143, the nearest multiple of
//! their FFT resolution 1/7); and the pulse is one wavelet, not a sum of several at the same
//! scale: summing ten (tried) fits the long-period drift of integrated white noise and calls
//! it pulse-like, and it turns more of FEMA P695's no-pulse records pulse-like (17–18 of 28
//! records agreeing with FEMA's split against 22 of 28 with one wavelet; the test
//! `near_field_pulse_calls_follow_femas_split` in tests/ims.rs lists the disagreements).
//!
//! Hand-written rather than a crate: no Rust crate offers a continuous wavelet transform with
//! the Daubechies wavelets (the Daubechies filters are 8 published numbers; ψ is built from
//! them by the exact dyadic refinement below).

use super::Accelerogram;
use rustfft::{FftPlanner, num_complex::Complex};
use serde::Serialize;
use std::sync::OnceLock;

/// Shortest pseudo-period searched (s).
pub const MIN_PERIOD: f64 = 0.1;
/// Longest pseudo-period searched (s); the search also stops at the record's duration.
pub const MAX_PERIOD: f64 = 15.0;
/// A pulse shorter than this (s) is not a pulse (Shahi & Baker 2014).
pub const MIN_TP: f64 = 0.25;
/// Scales on the search grid (log-spaced); the best is then refined by golden section.
const SCALES: usize = 60;

/// The Daubechies-4 scaling filter (8 taps, Σ h = √2; Daubechies 1992, Table 6.1).
const DB4: [f64; 8] = [
    0.230_377_813_308_855_23,
    0.714_846_570_552_541_5,
    0.630_880_767_929_590_4,
    -0.027_983_769_416_983_85,
    -0.187_034_811_718_881_14,
    0.030_841_381_835_986_965,
    0.032_883_011_666_982_945,
    -0.010_597_401_784_997_278,
];

/// The share of ψ²'s integral a wavelet may leave outside the record on either side: a
/// wavelet counts when the central 99 % of it lies in the record (2.5 % tails let the
/// switch-on of a harmonic raise |C| by 3 %; no tails at all bar pulses longer than a fifth
/// of the record).
const TAIL: f64 = 0.005;

/// Dyadic refinement levels of ψ's table (spacing 2⁻¹⁰ on [0, 7]).
const LEVELS: u32 = 10;

/// ψ tabulated at x = m / 2^LEVELS on [0, 7], unit L² norm, and its centre frequency f_c.
struct Mother {
    psi: Vec<f64>,
    centre: f64,
    /// The x interval holding the central 99 % of ψ²'s integral ([`TAIL`] on either side).
    core: (f64, f64),
}

fn mother() -> &'static Mother {
    static M: OnceLock<Mother> = OnceLock::new();
    M.get_or_init(|| {
        let sqrt2 = std::f64::consts::SQRT_2;
        // φ at the integers: the eigenvector of M_ij = √2 h_{2i−j} for eigenvalue 1 (the
        // others are at most ½), normalised to Σ φ(i) = 1, by power iteration.
        let mut phi = vec![1.0 / 8.0; 8];
        for _ in 0..200 {
            phi = (0..8)
                .map(|i| {
                    (0..8)
                        .filter_map(|j| {
                            let k = 2 * i as isize - j as isize;
                            (0..8)
                                .contains(&k)
                                .then(|| sqrt2 * DB4[k as usize] * phi[j])
                        })
                        .sum::<f64>()
                })
                .collect();
        }
        // Refine: φ(m/2^j) = √2 Σ h_k φ((m − k 2^{j−1}) / 2^{j−1}).
        for level in 1..=LEVELS {
            let half = 1usize << (level - 1);
            let coarse = phi;
            phi = (0..=7 * 2 * half)
                .map(|m| {
                    (0..8)
                        .filter_map(|k| {
                            let i = m as isize - (k * half) as isize;
                            (i >= 0 && (i as usize) < coarse.len())
                                .then(|| sqrt2 * DB4[k] * coarse[i as usize])
                        })
                        .sum::<f64>()
                })
                .collect();
        }
        // ψ(x) = √2 Σ g_k φ(2x − k), g_k = (−1)^k h_{7−k}.
        let full = 1usize << LEVELS;
        let n = 7 * full + 1;
        let mut psi: Vec<f64> = (0..n)
            .map(|m| {
                (0..8)
                    .filter_map(|k| {
                        let i = 2 * m as isize - (k * full) as isize;
                        let g = if k % 2 == 0 { DB4[7 - k] } else { -DB4[7 - k] };
                        (i >= 0 && (i as usize) < n).then(|| sqrt2 * g * phi[i as usize])
                    })
                    .sum::<f64>()
            })
            .collect();
        let dx = 1.0 / full as f64;
        let norm = (psi.iter().map(|p| p * p).sum::<f64>() * dx).sqrt();
        psi.iter_mut().for_each(|p| *p /= norm);
        let spectrum = |f: f64| {
            let (mut re, mut im) = (0.0, 0.0);
            for (m, p) in psi.iter().enumerate() {
                let (s, c) = (2.0 * std::f64::consts::PI * f * m as f64 * dx).sin_cos();
                re += p * c;
                im -= p * s;
            }
            -(re * re + im * im)
        };
        let coarse = (5..200)
            .map(|k| k as f64 * 0.01)
            .min_by(|a, b| spectrum(*a).total_cmp(&spectrum(*b)))
            .unwrap_or(0.7);
        let centre = golden_min(spectrum, coarse - 0.01, coarse + 0.01, 1e-9);
        let total: f64 = psi.iter().map(|p| p * p).sum();
        let mut cum = 0.0;
        let (mut lo, mut hi) = (0.0, 7.0);
        for (m, p) in psi.iter().enumerate() {
            let before = cum;
            cum += p * p;
            if before < TAIL * total && cum >= TAIL * total {
                lo = m as f64 * dx;
            }
            if before < (1.0 - TAIL) * total && cum >= (1.0 - TAIL) * total {
                hi = m as f64 * dx;
            }
        }
        Mother {
            psi,
            centre,
            core: (lo, hi),
        }
    })
}

/// ψ(x) by linear interpolation in the table, zero outside [0, 7].
fn psi_at(x: f64) -> f64 {
    let m = mother();
    let u = x * (1u32 << LEVELS) as f64;
    if !(0.0..(m.psi.len() - 1) as f64).contains(&u) {
        return 0.0;
    }
    let i = u as usize;
    let f = u - i as f64;
    m.psi[i] + f * (m.psi[i + 1] - m.psi[i])
}

/// The mother wavelet's centre frequency f_c (cycles per unit x): pseudo-period = s / f_c.
pub fn centre_frequency() -> f64 {
    mother().centre
}

/// Golden-section search for the minimum of f on [a, b].
fn golden_min(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64, tol: f64) -> f64 {
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - r * (b - a), a + r * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    while b - a > tol {
        if fc < fd {
            (b, d, fd) = (d, c, fc);
            c = b - r * (b - a);
            fc = f(c);
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + r * (b - a);
            fd = f(d);
        }
    }
    0.5 * (a + b)
}

/// The wavelet ψ((t_k − τ)/s) at the samples t_k = k dt for τ = j dt.
fn wavelet_samples(n: usize, dt: f64, scale: f64, j: isize) -> Vec<f64> {
    (0..n)
        .map(|k| psi_at((k as isize - j) as f64 * dt / scale))
        .collect()
}

/// C(s, τ_j) for τ_j = j dt, j from −K to n − 1 (K dt = the wavelet's support 7s), by FFT
/// correlation; returns (the coefficients, K).
fn cwt_at(v: &[f64], dt: f64, scale: f64) -> (Vec<f64>, usize) {
    let n = v.len();
    let k = (7.0 * scale / dt).floor() as usize;
    let w: Vec<f64> = (0..=k).map(|m| psi_at(m as f64 * dt / scale)).collect();
    let len = (n + k + 1).next_power_of_two();
    let mut planner = FftPlanner::new();
    let forward = planner.plan_fft_forward(len);
    let inverse = planner.plan_fft_inverse(len);
    let mut fv: Vec<Complex<f64>> = v.iter().map(|x| Complex::new(*x, 0.0)).collect();
    fv.resize(len, Complex::default());
    // conv(v, reversed w)[i] = Σ_m v[i − K + m] w[m] = C at j = i − K.
    let mut fw: Vec<Complex<f64>> = w.iter().rev().map(|x| Complex::new(*x, 0.0)).collect();
    fw.resize(len, Complex::default());
    forward.process(&mut fv);
    forward.process(&mut fw);
    for (a, b) in fv.iter_mut().zip(&fw) {
        *a *= *b;
    }
    inverse.process(&mut fv);
    let norm = dt / scale.sqrt() / len as f64;
    (fv[..n + k].iter().map(|c| c.re * norm).collect(), k)
}

/// The largest |C| at one scale over the wavelets that lie in the record (the central 99 %
/// of ψ² inside [0, duration]), and its τ index j; (0, 0) if none does.
fn peak_at(v: &[f64], dt: f64, scale: f64) -> (f64, isize) {
    let (c, k) = cwt_at(v, dt, scale);
    let (lo, hi) = mother().core;
    let duration = (v.len() - 1) as f64 * dt;
    // τ + s·lo ≥ 0 and τ + s·hi ≤ duration, τ = j dt, index i = j + K.
    let first = ((-scale * lo / dt).ceil() as isize + k as isize).max(0) as usize;
    let last = ((duration - scale * hi) / dt).floor() as isize + k as isize;
    if last < first as isize {
        return (0.0, 0);
    }
    let last = (last as usize).min(c.len() - 1);
    let (i, best) = c[first..=last]
        .iter()
        .enumerate()
        .fold((0, 0.0_f64), |(bi, bv), (i, x)| {
            if x.abs() > bv { (i, x.abs()) } else { (bi, bv) }
        });
    (best, (first + i) as isize - k as isize)
}

/// What the classification found for one component.
#[derive(Clone, Debug, Serialize)]
pub struct PulseCall {
    pub pulse_like: bool,
    /// The extracted wavelet's pseudo-period (s), pulse-like or not.
    pub period_s: f64,
    /// Shahi & Baker's indicator (pulse-like when > 0, with the other two conditions).
    pub indicator: f64,
    pub pgv_ratio: f64,
    pub energy_ratio: f64,
    /// Whether the pulse arrives early (before the record's 17 % of ∫v²).
    pub early: bool,
}

/// The indicator of Shahi & Baker (2014) from the PGV ratio, the energy ratio and the
/// record's PGV in cm/s (their logistic regression, in standardised variables).
pub fn indicator(pgv_ratio: f64, energy_ratio: f64, pgv_cm_s: f64) -> f64 {
    let pc = 0.63 * pgv_ratio + 0.777 * energy_ratio;
    let p = (pc - 1.208421) / 0.2462717;
    let v = (pgv_cm_s - 11.58861) / 18.88015;
    -7.817 - 0.5679 * p * p - 0.1516 * v * v - 3.0253 * p - 1.7396 * v - 2.7156 * p * v
}

/// The extracted pulse of a velocity history (m/s, at the samples) and its pseudo-period.
pub fn extract(v: &[f64], dt: f64) -> (Vec<f64>, f64) {
    let fc = centre_frequency();
    let longest = MAX_PERIOD
        .min((v.len() - 1) as f64 * dt)
        .max(MIN_PERIOD * 1.5);
    let periods: Vec<f64> = (0..SCALES)
        .map(|i| MIN_PERIOD * (longest / MIN_PERIOD).powf(i as f64 / (SCALES - 1) as f64))
        .collect();
    // The L¹-normalised transform: |C(s, τ)| / √s (module docs, step 1).
    let strength = |period: f64| {
        let scale = period * fc;
        peak_at(v, dt, scale).0 / scale.sqrt()
    };
    let values: Vec<f64> = periods.iter().map(|p| strength(*p)).collect();
    let best = (0..SCALES)
        .max_by(|a, b| values[*a].total_cmp(&values[*b]))
        .unwrap_or(0);
    let (lo, hi) = (
        periods[best.saturating_sub(1)],
        periods[(best + 1).min(SCALES - 1)],
    );
    let period = golden_min(|p| -strength(p), lo, hi, 1e-4 * periods[best]);
    let scale = period * fc;
    let (_, j) = peak_at(v, dt, scale);
    let w = wavelet_samples(v.len(), dt, scale, j);
    let ww: f64 = w.iter().map(|x| x * x).sum();
    let coef = if ww > 0.0 {
        v.iter().zip(&w).map(|(r, x)| r * x).sum::<f64>() / ww
    } else {
        0.0
    };
    let pulse = w.iter().map(|x| coef * x).collect();
    (pulse, period)
}

fn energy(v: &[f64], dt: f64) -> f64 {
    v.windows(2)
        .map(|w| 0.5 * dt * (w[0] * w[0] + w[1] * w[1]))
        .sum()
}

/// Classify one component from its velocity at the samples (m/s).
pub fn classify(rec: &Accelerogram, velocity: &[f64]) -> PulseCall {
    let dt = rec.dt;
    let peak = |x: &[f64]| x.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
    let pgv = peak(velocity);
    if pgv == 0.0 {
        return PulseCall {
            pulse_like: false,
            period_s: 0.0,
            indicator: f64::NEG_INFINITY,
            pgv_ratio: 1.0,
            energy_ratio: 1.0,
            early: false,
        };
    }
    let (pulse, period) = extract(velocity, dt);
    let residual: Vec<f64> = velocity.iter().zip(&pulse).map(|(v, p)| v - p).collect();
    let pgv_ratio = peak(&residual[..]) / pgv;
    let total = energy(velocity, dt);
    let energy_ratio = energy(&residual, dt) / total;
    let pi = indicator(pgv_ratio, energy_ratio, 100.0 * pgv);
    // The record's 17 % of ∫v² (first sample at or past it), and the pulse's share by then.
    let mut cum = 0.0;
    let mut t17 = velocity.len() - 1;
    for (k, w) in velocity.windows(2).enumerate() {
        cum += 0.5 * dt * (w[0] * w[0] + w[1] * w[1]);
        if cum >= 0.17 * total {
            t17 = k + 1;
            break;
        }
    }
    let early = energy(&pulse[..=t17], dt) > 0.05 * energy(&pulse, dt);
    PulseCall {
        pulse_like: pi > 0.0 && early && period >= MIN_TP,
        period_s: period,
        indicator: pi,
        pgv_ratio,
        energy_ratio,
        early,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::excitation::Pulse;
    use crate::excitation::ims::kinematics;

    /// White noise: independent Gaussian samples (Box–Muller on a seeded generator).
    fn noise(n: usize, sigma: f64, seed: u64) -> Vec<f64> {
        let mut rng = fastrand::Rng::with_seed(seed);
        (0..n)
            .map(|_| {
                let (u1, u2) = (1.0 - rng.f64(), rng.f64());
                sigma * (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
            })
            .collect()
    }

    fn call(dt: f64, accel: Vec<f64>) -> PulseCall {
        let rec = Accelerogram::new(dt, accel).unwrap();
        let kin = kinematics(&rec);
        classify(&rec, &kin.velocity)
    }

    /// The mother wavelet: unit norm, zero mean, and the true peak of |ψ̂|, 0.6977 (checked
    /// independently: PyWavelets' `wavefun('db4', level=10)` and a direct Fourier sum on a
    /// 1e-4 grid of frequencies). MATLAB's and PyWavelets' `centfrq` say 0.7143 = 5/7 because
    /// they read the peak off an FFT of the support [0, 7], whose resolution is 1/7; the
    /// FFT's 5/7 is 0.13 % below the true peak's |ψ̂|, so it is not the peak.
    #[test]
    fn daubechies_4_wavelet() {
        let m = mother();
        let dx = 1.0 / (1u32 << LEVELS) as f64;
        let mean: f64 = m.psi.iter().sum::<f64>() * dx;
        let norm: f64 = m.psi.iter().map(|p| p * p).sum::<f64>() * dx;
        assert!(mean.abs() < 1e-6, "{mean}");
        assert!((norm - 1.0).abs() < 1e-12);
        assert!((m.centre - 0.6977).abs() < 2e-4, "{}", m.centre);
        assert!((m.centre - 5.0 / 7.0).abs() > 0.01, "{}", m.centre);
    }

    /// The pseudo-period chosen for a harmonic velocity is its period (the L¹-normalised
    /// transform peaks at s = f_c T), for periods on and between the search grid's scales.
    /// The harmonic is switched on and off over 10 s (cosine tapers): an abrupt switch-on
    /// is broadband and moves the peak by about 1 % at 0.7 s.
    #[test]
    fn a_harmonic_s_pseudo_period_is_its_period() {
        let dt = 0.01;
        let taper = |t: f64| {
            let edge = t.min(60.0 - t).clamp(0.0, 10.0) / 10.0;
            0.5 * (1.0 - (std::f64::consts::PI * edge).cos())
        };
        for period in [0.7, 1.3, 2.0, 3.7] {
            let v: Vec<f64> = (0..6000)
                .map(|k| {
                    let t = k as f64 * dt;
                    taper(t) * (2.0 * std::f64::consts::PI * t / period).sin()
                })
                .collect();
            let (_, tp) = extract(&v, dt);
            assert!((tp - period).abs() < 0.01 * period, "{period}: {tp}");
        }
    }

    /// A Mavroeidis–Papageorgiou pulse (Tp = 1.5 s, PGV 0.8 m/s, γ = 2.5) starting at 5 s in
    /// 30 s of white noise (σ = 0.3 m/s²) is pulse-like, with Tp within 5 %.
    #[test]
    fn mavroeidis_papageorgiou_pulse_in_noise_is_pulse_like() {
        for (tp, gamma) in [(1.5, 2.5), (3.0, 2.0), (0.8, 3.0)] {
            let dt = 0.01;
            let pulse = Pulse::mavroeidis_papageorgiou(tp, 0.8, gamma, 0.0);
            let mut accel = noise(3000, 0.3, 7);
            for (k, a) in accel.iter_mut().enumerate() {
                *a += pulse.accel(k as f64 * dt - 5.0);
            }
            let c = call(dt, accel);
            assert!(c.pulse_like, "Tp {tp}: {c:?}");
            assert!((c.period_s - tp).abs() < 0.05 * tp, "Tp {tp}: {c:?}");
        }
    }

    /// White noise alone (several seeds, σ = 1 m/s², 20 s) is not pulse-like.
    #[test]
    fn white_noise_is_not_pulse_like() {
        for seed in 1..=5 {
            let c = call(0.01, noise(2000, 1.0, seed));
            assert!(!c.pulse_like, "seed {seed}: {c:?}");
        }
    }

    /// The indicator at the centre of Shahi & Baker's standardisation (pc = 1.208421,
    /// PGV = 11.58861 cm/s) is the intercept; a strong clean pulse (ratios near 0, PGV 100
    /// cm/s) scores positive, a record with no pulse (ratios 1) negative.
    #[test]
    fn indicator_signs() {
        let pc_ratio = 1.208421 / (0.63 + 0.777);
        assert!((indicator(pc_ratio, pc_ratio, 11.58861) + 7.817).abs() < 1e-5);
        assert!(indicator(0.2, 0.1, 100.0) > 0.0);
        assert!(indicator(1.0, 1.0, 100.0) < 0.0);
    }
}
