//! Analytic acceleration pulses. Each family is a unit-peak shape f(s) of the phase s = ω t,
//! scaled to a_g = A f(ω t): `amplitude` A is the peak |a_g| and `omega` ω the pulse's
//! circular frequency, so A/(g tan α) and ω/p mean the same thing for every family.

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PulseShape {
    /// a_g = A sin(ω t) for 0 ≤ t ≤ 2π/ω.
    Sine,
    /// a_g = A cos(ω t) for 0 ≤ t ≤ 2π/ω (jumps at both ends).
    Cosine,
    /// Symmetric Ricker wavelet (Mexican hat, second derivative of a Gaussian):
    /// a_g = A (1 − x²) e^{−x²/2}, x = (t − tc)/σ, σ = √2/ω, so that ω is where its Fourier
    /// amplitude peaks (Tp = 2π/ω is the Mexican hat's (1 − 2π²t²/Tp²) e^{−π²t²/Tp²}).
    /// Truncated at |x| = 8 (tail below 1e-12 A), centre tc = 8σ.
    Ricker,
    /// Antisymmetric Ricker wavelet (third derivative of a Gaussian):
    /// a_g ∝ (x³ − 3x) e^{−x²/2}, x = (t − tc)/σ, σ = √3/ω (Fourier peak at ω), scaled to
    /// peak |a_g| = A (reached at x = ±√(3 − √6)). Truncated at |x| = 8, tc = 8σ.
    AntisymmetricRicker,
    /// Mavroeidis & Papageorgiou (2003) velocity pulse, fp = ω/2π = 1/Tp:
    /// v ∝ ½ [1 + cos(2π fp τ/γ)] cos(2π fp τ + ν) for |τ| ≤ γ/(2 fp), τ = t − γ/(2 fp);
    /// a_g = dv/dt scaled to peak |a_g| = A. γ > 1 sets the number of cycles, ν the phase.
    MavroeidisPapageorgiou { gamma: f64, nu: f64 },
}

/// Truncation of the Ricker wavelets, in Gaussian standard deviations.
const RICKER_HALF_WIDTH: f64 = 8.0;

/// A pulse with peak acceleration A (m/s², signed) and circular frequency ω (rad/s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pulse {
    pub shape: PulseShape,
    /// Private: `gain` is derived from it.
    amplitude: f64,
    pub omega: f64,
    /// max |unit shape| before normalisation (1 for sine, cosine and the symmetric Ricker).
    norm: f64,
    /// An upper bound of |d(unit shape)/d(phase)| before normalisation ([`Pulse::accel_bound`]).
    slope: f64,
    /// amplitude / norm: a_g is one product, not a product and a division, on every
    /// right-hand side.
    gain: f64,
}

impl Pulse {
    pub fn new(shape: PulseShape, amplitude: f64, omega: f64) -> Self {
        let norm = match shape {
            PulseShape::Sine | PulseShape::Cosine | PulseShape::Ricker => 1.0,
            PulseShape::AntisymmetricRicker => {
                let x = (3.0 - 6f64.sqrt()).sqrt();
                (x * (x * x - 3.0)).abs() * (-0.5 * x * x).exp()
            }
            PulseShape::MavroeidisPapageorgiou { gamma, nu } => {
                max_abs(|s| mp_accel_shape(s, gamma, nu), -gamma * PI, gamma * PI)
            }
        };
        // Maxima of |f'(phase)|, from f'' = 0: Ricker f = (1 − c²/2)e^(−c²/4),
        // f' = c(c²/4 − 3/2)e^(−c²/4), largest at c² = 6 − √24 (0.9760); antisymmetric
        // Ricker f = g(c/√3), g' = (6x² − x⁴ − 3)e^(−x²/2), largest at x = 0 (3/√3 = √3);
        // MP: the phase-scan of its f' (the scan that finds `norm`; 1e-9 for its roundoff).
        let slope = match shape {
            PulseShape::Sine | PulseShape::Cosine => 1.0,
            PulseShape::Ricker => 0.977,
            PulseShape::AntisymmetricRicker => 3f64.sqrt(),
            PulseShape::MavroeidisPapageorgiou { gamma, nu } => {
                (1.0 + 1e-9) * max_abs(|s| mp_accel_slope(s, gamma, nu), -gamma * PI, gamma * PI)
            }
        };
        Pulse {
            shape,
            amplitude,
            omega,
            norm,
            slope,
            gain: amplitude / norm,
        }
    }

    /// An upper bound of |a_g| on [t0, t1], from the end values and the largest slope L:
    /// |a(t)| ≤ min(|a(t0)| + L(t − t0), |a(t1)| + L(t1 − t)) ≤ (|a(t0)| + |a(t1)| + L h)/2,
    /// and never above the peak A. Two evaluations of a_g, against a scan's dozens.
    pub fn accel_bound(&self, t0: f64, t1: f64) -> f64 {
        let peak = self.amplitude.abs();
        if t1 < 0.0 || t0 > self.end() {
            return 0.0;
        }
        // The cosine jumps at both ends (and `accel` may read 0 or A at `end` by rounding of
        // the phase): no Lipschitz bound across them.
        if self.shape == PulseShape::Cosine && (t0 <= 0.0 || t1 >= self.end()) {
            return peak;
        }
        let slope = peak * self.omega * self.slope / self.norm;
        let lipschitz = 0.5 * (self.accel(t0).abs() + self.accel(t1).abs() + slope * (t1 - t0));
        lipschitz.min(peak)
    }

    /// Mavroeidis–Papageorgiou pulse with prevailing period Tp (s) and peak ground velocity
    /// PGV (m/s, signed: the sign of the velocity peak).
    pub fn mavroeidis_papageorgiou(tp: f64, pgv: f64, gamma: f64, nu: f64) -> Self {
        let omega = 2.0 * PI / tp;
        let shape = PulseShape::MavroeidisPapageorgiou { gamma, nu };
        let unit = Pulse::new(shape, 1.0, omega);
        // With a_g = A g(s)/gmax, s = ω τ: v = A/(ω gmax) · v(s), so PGV = A vmax/(ω gmax).
        let vmax = max_abs(|s| mp_velocity_shape(s, gamma, nu), -gamma * PI, gamma * PI);
        Pulse::new(shape, pgv * omega * unit.norm / vmax, omega)
    }

    pub fn period(&self) -> f64 {
        2.0 * PI / self.omega
    }

    /// Duration of the pulse in units of phase (rad).
    fn phase_span(&self) -> f64 {
        match self.shape {
            PulseShape::Sine | PulseShape::Cosine => 2.0 * PI,
            PulseShape::Ricker => 2.0 * RICKER_HALF_WIDTH * 2f64.sqrt(),
            PulseShape::AntisymmetricRicker => 2.0 * RICKER_HALF_WIDTH * 3f64.sqrt(),
            PulseShape::MavroeidisPapageorgiou { gamma, .. } => 2.0 * gamma * PI,
        }
    }

    pub fn end(&self) -> f64 {
        self.phase_span() / self.omega
    }

    #[inline]
    pub fn accel(&self, t: f64) -> f64 {
        let span = self.phase_span();
        let phase = self.omega * t;
        if !(0.0..=span).contains(&phase) {
            return 0.0;
        }
        let centred = phase - 0.5 * span;
        let unit = match self.shape {
            PulseShape::Sine => phase.sin(),
            PulseShape::Cosine => phase.cos(),
            PulseShape::Ricker => {
                let x2 = centred * centred / 2.0;
                (1.0 - x2) * (-0.5 * x2).exp()
            }
            PulseShape::AntisymmetricRicker => {
                let x = centred / 3f64.sqrt();
                (x * x * x - 3.0 * x) * (-0.5 * x * x).exp()
            }
            PulseShape::MavroeidisPapageorgiou { gamma, nu } => mp_accel_shape(centred, gamma, nu),
        };
        self.gain * unit
    }

    /// For the sine and cosine pulses, the first time ≥ t0 at which |a_g| exceeds `level`,
    /// in closed form (`Some(None)`: never); `None` for the other shapes, which are scanned.
    /// |sin φ| > L on φ mod π ∈ (asin L, π − asin L), |cos φ| > L off [acos L, π − acos L]:
    /// the answer is t0 itself or the first start of such an arc, moved up by ulps until
    /// |a_g| > level there in floating point (a wake must find the ground past its level).
    pub fn first_exceedance_closed(&self, t0: f64, level: f64) -> Option<Option<f64>> {
        let first_arc = match self.shape {
            PulseShape::Sine => (level / self.amplitude.abs()).asin(),
            PulseShape::Cosine => PI - (level / self.amplitude.abs()).acos(),
            _ => return None,
        };
        let (end, exceeds) = (self.end(), |t: f64| self.accel(t).abs() > level);
        if t0 >= end || level >= self.amplitude.abs() {
            return Some(None);
        }
        if exceeds(t0.max(0.0)) {
            return Some(Some(t0.max(0.0)));
        }
        let phase0 = self.omega * t0.max(0.0);
        // The arcs start at first_arc + kπ; the first at or after phase0.
        // (1e-9 back: t0 a few ulps into an arc whose start rounds past |a_g| ≤ level must
        // not skip to the next arc.)
        let k = ((phase0 - first_arc) / PI - 1e-9).ceil().max(0.0);
        let mut t = ((first_arc + k * PI) / self.omega).max(t0);
        for _ in 0..64 {
            if t > end {
                return Some(None);
            }
            if exceeds(t) && t >= t0 {
                return Some(Some(t));
            }
            t = t.next_up();
        }
        // Rounding of the arc's start beyond 64 ulps: not expected; the scan decides.
        None
    }

    /// For the sine and cosine pulses, max |a_g| on [t0, t1] in closed form: the ends, or A
    /// where a crest (sine: φ = π/2 + kπ, cosine: φ = kπ) lies inside; `None` for the others.
    pub fn peak_abs_closed(&self, t0: f64, t1: f64) -> Option<f64> {
        let crest0 = match self.shape {
            PulseShape::Sine => 0.5 * PI,
            PulseShape::Cosine => 0.0,
            _ => return None,
        };
        let (t0, t1) = (t0.max(0.0), t1.min(self.end()));
        if t1 <= t0 {
            return Some(0.0); // as the scans: an empty interval has no peak
        }
        let ends = self.accel(t0).abs().max(self.accel(t1).abs());
        let k = ((self.omega * t0 - crest0) / PI).ceil();
        let crest = (crest0 + k * PI) / self.omega;
        Some(if crest <= t1 {
            ends.max(self.amplitude.abs())
        } else {
            ends
        })
    }

    pub fn next_breakpoint(&self, t: f64) -> Option<f64> {
        (t < self.end()).then(|| self.end())
    }

    pub fn jumps_at(&self, t: f64) -> bool {
        self.shape == PulseShape::Cosine && (t == self.end() || t == 0.0)
    }
}

/// MP velocity shape v(s) = ½ (1 + cos(s/γ)) cos(s + ν), |s| ≤ γπ.
fn mp_velocity_shape(s: f64, gamma: f64, nu: f64) -> f64 {
    0.5 * (1.0 + (s / gamma).cos()) * (s + nu).cos()
}

/// dv/ds of [`mp_velocity_shape`].
fn mp_accel_shape(s: f64, gamma: f64, nu: f64) -> f64 {
    -0.5 * ((s / gamma).sin() / gamma * (s + nu).cos() + (1.0 + (s / gamma).cos()) * (s + nu).sin())
}

/// d/ds of [`mp_accel_shape`].
fn mp_accel_slope(s: f64, gamma: f64, nu: f64) -> f64 {
    let (sg, cg) = (s / gamma).sin_cos();
    let (sn, cn) = (s + nu).sin_cos();
    -0.5 * ((1.0 + cg * (1.0 + 1.0 / (gamma * gamma))) * cn - 2.0 / gamma * sg * sn)
}

/// max |f| on [a, b] for a shape of the phase s (period 2π): the pulses' own scan.
fn max_abs(f: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    super::scan_peak(f, a, b, 2.0 * PI)
}
