//! Intensity measures of a ground-motion record (docs/MODEL.md "Intensity measures").
//!
//! The record is the piecewise-linear interpolation of its samples, unscaled, starting at
//! rest, with no filtering or baseline correction; a record in g is turned into m/s² with
//! standard gravity [`STANDARD_GRAVITY`] (not the model's `G`, which drives the scenes).
//!
//! - here: PGA, PGV and PGD (exact integration, peaks of the continuous functions), Arias
//!   intensity and CAV (trapezoid rule on the samples), significant durations from the Husid
//!   curve, the mean period Tm, and [`Ims`], everything `rocklab records --ims` lists;
//! - [`spectrum`]: Sa(T, ξ) by the Nigam–Jennings recurrence, Sa_avg and RotD50;
//! - [`pulse`]: pulse classification (Shahi & Baker 2014) with the pulse period Tp.

pub mod pulse;
pub mod spectrum;

use serde::Serialize;

/// Standard gravity (m/s²): every intensity measure turns a record in g into m/s² with it,
/// as eqsig, pyrotd and PEER do. The scenes keep the model's `excitation::G` = 9.81.
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// The damping ratio of Sa when a study or command gives none.
pub const DEFAULT_DAMPING: f64 = 0.05;

/// Why an intensity measure cannot be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ImError {
    #[error(
        "a record needs at least two samples and a time step > 0 (got {npts} samples, dt {dt})"
    )]
    Record { npts: usize, dt: f64 },
    #[error("period {0} s: a spectral period must be finite and > 0")]
    Period(f64),
    #[error("damping ratio {0}: it must be in [0, 1)")]
    Damping(f64),
    #[error("Sa_avg from {from} s to {to} s: the range needs 0 < from < to")]
    Range { from: f64, to: f64 },
    #[error("RotD50 needs two components with the same dt and length ({0})")]
    Pair(String),
}

/// A uniformly sampled acceleration history in m/s², the first sample at t = 0.
#[derive(Clone, Debug)]
pub struct Accelerogram {
    pub dt: f64,
    pub accel: Vec<f64>,
}

impl Accelerogram {
    pub fn new(dt: f64, accel: Vec<f64>) -> Result<Self, ImError> {
        if accel.len() < 2 || dt.is_nan() || dt <= 0.0 || !dt.is_finite() {
            return Err(ImError::Record {
                npts: accel.len(),
                dt,
            });
        }
        Ok(Accelerogram { dt, accel })
    }

    /// A record series as the intensity measures read it (standard gravity for a file in g).
    pub fn from_series(series: &super::Series) -> Result<Self, ImError> {
        Self::new(series.dt(), series.standard_samples())
    }

    pub fn duration(&self) -> f64 {
        (self.accel.len() - 1) as f64 * self.dt
    }
}

/// Ground velocity and displacement at the samples, exact for the piecewise-linear
/// acceleration from rest, and the peaks of the continuous |v(t)| and |d(t)| (interior
/// extrema between samples included: v is quadratic and d cubic on each segment).
#[derive(Clone, Debug)]
pub struct Kinematics {
    pub velocity: Vec<f64>,
    pub displacement: Vec<f64>,
    pub pgv: f64,
    pub pgd: f64,
}

pub fn kinematics(rec: &Accelerogram) -> Kinematics {
    let (a, h) = (&rec.accel, rec.dt);
    let n = a.len();
    let (mut v, mut d) = (vec![0.0; n], vec![0.0; n]);
    let (mut pgv, mut pgd) = (0.0_f64, 0.0_f64);
    for k in 0..n - 1 {
        let (a0, a1, v0, d0) = (a[k], a[k + 1], v[k], d[k]);
        let jerk = (a1 - a0) / h;
        // On the segment, with τ ∈ [0, h]: v = v0 + a0 τ + jerk τ²/2,
        // d = d0 + v0 τ + a0 τ²/2 + jerk τ³/6.
        let vel = |t: f64| v0 + t * (a0 + 0.5 * jerk * t);
        let disp = |t: f64| d0 + t * (v0 + t * (0.5 * a0 + jerk * t / 6.0));
        if a0 * a1 < 0.0 {
            pgv = pgv.max(vel(h * a0 / (a0 - a1)).abs());
        }
        for t in roots_in_segment(0.5 * jerk, a0, v0, h) {
            pgd = pgd.max(disp(t).abs());
        }
        v[k + 1] = v0 + 0.5 * h * (a0 + a1);
        d[k + 1] = d0 + h * v0 + h * h * (2.0 * a0 + a1) / 6.0;
        pgv = pgv.max(v[k + 1].abs());
        pgd = pgd.max(d[k + 1].abs());
    }
    Kinematics {
        velocity: v,
        displacement: d,
        pgv,
        pgd,
    }
}

/// Roots of c2 τ² + c1 τ + c0 strictly inside (0, h).
fn roots_in_segment(c2: f64, c1: f64, c0: f64, h: f64) -> impl Iterator<Item = f64> {
    let roots: [Option<f64>; 2] = if c2 == 0.0 {
        [(c1 != 0.0).then(|| -c0 / c1), None]
    } else {
        let disc = c1 * c1 - 4.0 * c2 * c0;
        if disc < 0.0 {
            [None, None]
        } else {
            // The numerically stable pair (no cancellation between −c1 and √disc).
            let q = -0.5 * (c1 + disc.sqrt().copysign(c1));
            [Some(q / c2), (q != 0.0).then(|| c0 / q)]
        }
    };
    roots
        .into_iter()
        .flatten()
        .filter(move |t| *t > 0.0 && *t < h)
}

/// Trapezoid-rule integral of f(a_k) over the samples.
fn trapezoid(rec: &Accelerogram, f: impl Fn(f64) -> f64) -> f64 {
    rec.accel
        .windows(2)
        .map(|w| 0.5 * rec.dt * (f(w[0]) + f(w[1])))
        .sum()
}

/// Arias intensity π/(2g) ∫ a² dt (m/s), trapezoid rule on the samples.
pub fn arias(rec: &Accelerogram) -> f64 {
    std::f64::consts::PI / (2.0 * STANDARD_GRAVITY) * trapezoid(rec, |a| a * a)
}

/// Cumulative absolute velocity ∫ |a| dt (m/s), trapezoid rule on the samples.
pub fn cav(rec: &Accelerogram) -> f64 {
    trapezoid(rec, f64::abs)
}

/// Significant duration: the time between the Husid curve (cumulative ∫a² by the trapezoid
/// rule, normalised) reaching `from` and reaching `to` (fractions), each crossing read by
/// linear interpolation between samples. eqsig takes the first sample at or past each level
/// instead, which can differ by up to one dt.
pub fn significant_duration(rec: &Accelerogram, from: f64, to: f64) -> f64 {
    let mut husid = Vec::with_capacity(rec.accel.len());
    let mut sum = 0.0;
    husid.push(0.0);
    for w in rec.accel.windows(2) {
        sum += 0.5 * rec.dt * (w[0] * w[0] + w[1] * w[1]);
        husid.push(sum);
    }
    if sum <= 0.0 {
        return 0.0;
    }
    let crossing = |level: f64| {
        let target = level * sum;
        let k = husid.partition_point(|h| *h < target).max(1);
        if k >= husid.len() {
            return rec.duration();
        }
        let (h0, h1) = (husid[k - 1], husid[k]);
        let f = if h1 > h0 {
            (target - h0) / (h1 - h0)
        } else {
            0.0
        };
        (k - 1) as f64 * rec.dt + f * rec.dt
    };
    crossing(to) - crossing(from)
}

/// Mean period Tm (Rathje, Abrahamson & Bray 1998): Σ C² / f over Σ C², C the Fourier
/// amplitudes of the acceleration (the FFT of the samples, not zero-padded) at the
/// frequencies 0.25 Hz ≤ f ≤ 20 Hz. None if no Fourier frequency falls in the band.
pub fn mean_period(rec: &Accelerogram) -> Option<f64> {
    use rustfft::{FftPlanner, num_complex::Complex};
    let n = rec.accel.len();
    let mut buf: Vec<Complex<f64>> = rec.accel.iter().map(|a| Complex::new(*a, 0.0)).collect();
    FftPlanner::new().plan_fft_forward(n).process(&mut buf);
    let df = 1.0 / (n as f64 * rec.dt);
    let (mut num, mut den) = (0.0, 0.0);
    for (k, c) in buf.iter().enumerate().take(n / 2 + 1).skip(1) {
        let f = k as f64 * df;
        if (0.25..=20.0).contains(&f) {
            num += c.norm_sqr() / f;
            den += c.norm_sqr();
        }
    }
    (den > 0.0).then(|| num / den)
}

/// Every intensity measure of one component, as `rocklab records --ims` lists them.
#[derive(Clone, Debug, Serialize)]
pub struct Ims {
    pub pga_g: f64,
    pub pgv_m_s: f64,
    pub pgd_m: f64,
    pub arias_m_s: f64,
    pub cav_m_s: f64,
    pub d5_75_s: f64,
    pub d5_95_s: f64,
    pub periods_s: Vec<f64>,
    pub damping: f64,
    /// Sa(T, ξ) in g, aligned with `periods_s`.
    pub sa_g: Vec<f64>,
    pub tm_s: Option<f64>,
    pub pulse_like: bool,
    /// The pulse period (s) of a pulse-like component; None otherwise.
    pub tp_s: Option<f64>,
    /// The classification's details (indicator, ratios, the extracted wavelet's period).
    pub pulse_classification: pulse::PulseCall,
}

impl Ims {
    pub fn of(rec: &Accelerogram, periods: &[f64], damping: f64) -> Result<Ims, ImError> {
        let kin = kinematics(rec);
        let sa = spectrum::sa(rec, periods, damping)?;
        let call = pulse::classify(rec, &kin.velocity);
        let pga = rec.accel.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
        Ok(Ims {
            pga_g: pga / STANDARD_GRAVITY,
            pgv_m_s: kin.pgv,
            pgd_m: kin.pgd,
            arias_m_s: arias(rec),
            cav_m_s: cav(rec),
            d5_75_s: significant_duration(rec, 0.05, 0.75),
            d5_95_s: significant_duration(rec, 0.05, 0.95),
            periods_s: periods.to_vec(),
            damping,
            sa_g: sa.iter().map(|s| s / STANDARD_GRAVITY).collect(),
            tm_s: mean_period(rec),
            pulse_like: call.pulse_like,
            tp_s: call.pulse_like.then_some(call.period_s),
            pulse_classification: call,
        })
    }
}

/// The periods `rocklab records --ims` uses without `--periods`: 0.1, 0.2, 0.3, 0.5, 0.75, 1,
/// 1.5, 2, 3, 4 and 5 s.
pub const DEFAULT_PERIODS: [f64; 11] = [0.1, 0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0];

#[cfg(test)]
mod tests {
    use super::*;

    fn record(dt: f64, f: impl Fn(f64) -> f64, n: usize) -> Accelerogram {
        Accelerogram::new(dt, (0..n).map(|k| f(k as f64 * dt)).collect()).unwrap()
    }

    /// A constant a0 over [0, T]: Arias π a0² T / (2g), CAV a0 T; v = a0 t, d = a0 t²/2.
    #[test]
    fn constant_record_in_closed_form() {
        let (a0, dt, n) = (1.7, 0.01, 1001);
        let rec = record(dt, |_| a0, n);
        let t = 10.0;
        let ia = std::f64::consts::PI * a0 * a0 * t / (2.0 * STANDARD_GRAVITY);
        assert!((arias(&rec) - ia).abs() < 1e-12 * ia);
        assert!((cav(&rec) - a0 * t).abs() < 1e-12 * a0 * t);
        let kin = kinematics(&rec);
        assert!((kin.pgv - a0 * t).abs() < 1e-10);
        assert!((kin.pgd - 0.5 * a0 * t * t).abs() < 1e-9);
        // Husid grows linearly: D5-95 = 0.9 T, D5-75 = 0.7 T.
        assert!((significant_duration(&rec, 0.05, 0.95) - 0.9 * t).abs() < 1e-9);
        assert!((significant_duration(&rec, 0.05, 0.75) - 0.7 * t).abs() < 1e-9);
    }

    /// A triangle 0 → A → 0 over [0, 2T] sampled at its kinks: the trapezoid rule on a² is
    /// not exact (∫a² = 2A²T/3) but on |a| it is (A T); both checked against their closed forms,
    /// the first at the rule's known error A²T dt²/(3T²)·… bounded by O(dt²).
    #[test]
    fn triangle_record_arias_and_cav() {
        let (amp, t, dt): (f64, f64, f64) = (2.0, 5.0, 0.001);
        let n = (2.0 * t / dt).round() as usize + 1;
        let rec = record(dt, |x| amp * (1.0 - (x - t).abs() / t), n);
        assert!((cav(&rec) - amp * t).abs() < 1e-9);
        let exact = std::f64::consts::PI / (2.0 * STANDARD_GRAVITY) * 2.0 * amp * amp * t / 3.0;
        // Trapezoid on a² = A² (t/T)²: error (2T) · h² · (2A²/T²) / 12 over both ramps.
        let rule_error =
            std::f64::consts::PI / (2.0 * STANDARD_GRAVITY) * 2.0 * t * dt * dt * 2.0 * amp * amp
                / (t * t)
                / 12.0;
        assert!((arias(&rec) - exact - rule_error).abs() < 1e-9 * exact);
        // v peaks at the end (the triangle never changes sign): A T; d(2T) = A T · T.
        let kin = kinematics(&rec);
        assert!((kin.pgv - amp * t).abs() < 1e-9);
        assert!((kin.pgd - amp * t * t).abs() < 1e-7);
    }

    /// Husid durations of a record whose energy is known piecewise: amplitude 1 for 4 s, then
    /// 3 for 2 s (energy 4 then 18 per unit, 22 in all), then 1 for 4 s (4 more, 26).
    /// The 5 % level (1.3) falls at t = 1.3, 75 % (19.5) at 4 + 15.5/9, 95 % (24.7) at
    /// 6 + 2.7 = 8.7.
    #[test]
    fn husid_durations_of_piecewise_energy() {
        let dt = 0.001;
        let n = 10_001;
        // Square the amplitude changes at exact samples: the trapezoid smears each step over
        // one dt, so the expected crossings carry an O(dt) term; tolerance 2 dt.
        let rec = record(
            dt,
            |x| {
                if (4.0..6.0).contains(&(x + 1e-9)) {
                    3.0
                } else {
                    1.0
                }
            },
            n,
        );
        let d595 = significant_duration(&rec, 0.05, 0.95);
        let d575 = significant_duration(&rec, 0.05, 0.75);
        assert!((d595 - (8.7 - 1.3)).abs() < 2.0 * dt, "{d595}");
        assert!((d575 - (4.0 + 15.5 / 9.0 - 1.3)).abs() < 2.0 * dt, "{d575}");
    }

    /// PGV counts the interior extremum: a = +1 then −1 at two samples of dt = 1 gives
    /// v(τ) = τ − τ², peak ¼ at τ = ½, while both samples have v = 0.
    #[test]
    fn pgv_and_pgd_between_samples() {
        let rec = Accelerogram::new(1.0, vec![1.0, -1.0]).unwrap();
        let kin = kinematics(&rec);
        assert!((kin.pgv - 0.25).abs() < 1e-15);
        // d(1) = ½ − ⅓ = 1/6 (v ≥ 0 throughout, so the end is the peak).
        assert!((kin.pgd - 1.0 / 6.0).abs() < 1e-15);
        // A velocity that returns through zero mid-segment: a = 1, then −3: v = τ − 2τ²
        // crosses zero at τ = ½ and reaches −1 at τ = 1; d = τ²/2 − 2τ³/3 peaks at
        // τ = ½ (1/24) and ends at −1/6.
        let rec = Accelerogram::new(1.0, vec![1.0, -3.0]).unwrap();
        let kin = kinematics(&rec);
        assert!((kin.pgd - 1.0 / 6.0).abs() < 1e-15);
        let rec = Accelerogram::new(1.0, vec![1.0, -1.2]).unwrap();
        // v = τ − 1.1 τ², zero at τ = 1/1.1; d = τ²/2 − 1.1 τ³/3 peaks there: 1/(6·1.21).
        let kin = kinematics(&rec);
        assert!((kin.pgd - 1.0 / (6.0 * 1.21)).abs() < 1e-15);
    }

    /// Tm of a pure sine of frequency f (an integer number of cycles, so one Fourier line) is
    /// 1/f.
    #[test]
    fn mean_period_of_a_sine() {
        let (f, dt, n) = (2.0, 0.01, 1000);
        let rec = record(dt, |t| (2.0 * std::f64::consts::PI * f * t).sin(), n);
        let tm = mean_period(&rec).unwrap();
        assert!((tm - 1.0 / f).abs() < 1e-9, "{tm}");
    }

    #[test]
    fn bad_records_are_refused() {
        assert!(Accelerogram::new(0.0, vec![1.0, 2.0]).is_err());
        assert!(Accelerogram::new(0.01, vec![1.0]).is_err());
    }
}
