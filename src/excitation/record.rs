//! Sampled ground motions. Between samples the acceleration is linear (the usual reading of a
//! digitised record), so every quantity here — PGA, PGV, first exceedance, peak — is exact for
//! that piecewise-linear history, not an approximation to it.

use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Uniformly sampled acceleration a_k (m/s²) at t0 + k·dt; zero before t0 and after the last
/// sample.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    t0: f64,
    dt: f64,
    inv_dt: f64,
    accel: Vec<f64>,
    pga: f64,
    pgv: f64,
    /// What turns a sample into m/s² at standard gravity for the intensity measures
    /// ([`Series::standard_samples`]): STANDARD_GRAVITY / G for a file in g, else 1.
    to_standard: f64,
}

impl Series {
    /// Panics if `accel` is empty or dt is not positive: readers check both first.
    pub fn new(t0: f64, dt: f64, accel: Vec<f64>) -> Self {
        assert!(
            !accel.is_empty() && dt > 0.0,
            "a series needs samples and dt > 0"
        );
        let pga = accel.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
        let mut s = Series {
            t0,
            dt,
            inv_dt: 1.0 / dt,
            accel,
            pga,
            pgv: 0.0,
            to_standard: 1.0,
        };
        s.pgv = s.velocity_extremes().1;
        s
    }

    pub fn t0(&self) -> f64 {
        self.t0
    }
    pub fn dt(&self) -> f64 {
        self.dt
    }
    pub fn npts(&self) -> usize {
        self.accel.len()
    }

    /// This series read from a file in `units`: a file in g was turned into m/s² with the
    /// model's [`G`](super::G), and the intensity measures turn it back with standard gravity.
    pub fn read_in(mut self, units: super::reader::Units) -> Self {
        self.to_standard = match units {
            super::reader::Units::G => super::ims::STANDARD_GRAVITY / super::G,
            _ => 1.0,
        };
        self
    }

    /// Samples in m/s² as the intensity measures read them: a record in g converted with
    /// standard gravity (`ims::STANDARD_GRAVITY`), not the model's g; others as stored.
    pub fn standard_samples(&self) -> Vec<f64> {
        if self.to_standard == 1.0 {
            return self.accel.clone();
        }
        self.accel.iter().map(|a| a * self.to_standard).collect()
    }
    /// Samples in m/s².
    /// A hash of the data (t0, dt and every sample, bit for bit): two series with the same
    /// fingerprint drive a structure identically. Caches key results on it, so replacing a
    /// record file (e.g. a stand-in by the real AT2) invalidates them.
    pub fn fingerprint(&self) -> String {
        use sha2::{Digest, Sha256};
        let mut h = Sha256::new();
        h.update(self.t0().to_le_bytes());
        h.update(self.dt().to_le_bytes());
        for a in self.samples() {
            h.update(a.to_le_bytes());
        }
        h.finalize()[..8]
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect()
    }

    pub fn samples(&self) -> &[f64] {
        &self.accel
    }
    /// Time of the last sample.
    pub fn end(&self) -> f64 {
        self.time(self.accel.len() - 1)
    }
    /// Peak |a| (m/s²).
    pub fn pga(&self) -> f64 {
        self.pga
    }
    /// Peak |v| (m/s) of the exact integral of the piecewise-linear acceleration from v(t0) = 0.
    pub fn pgv(&self) -> f64 {
        self.pgv
    }

    #[inline]
    fn time(&self, k: usize) -> f64 {
        self.t0 + k as f64 * self.dt
    }

    /// Linear interpolation between samples, O(1).
    #[inline]
    pub fn accel(&self, t: f64) -> f64 {
        let x = (t - self.t0) * self.inv_dt;
        let last = self.accel.len() - 1;
        // The tolerance keeps t = t0 + k·dt on sample k despite rounding in k·dt.
        if x.is_nan() || x < -1e-9 || x > last as f64 + 1e-9 {
            return 0.0;
        }
        let x = x.max(0.0);
        let i = x as usize;
        if i >= last {
            return self.accel[last];
        }
        let f = x - i as f64;
        self.accel[i] + f * (self.accel[i + 1] - self.accel[i])
    }

    /// Velocity at each sample (trapezoid rule, exact for linear segments) and peak |v|,
    /// including extrema inside segments where a changes sign.
    pub fn velocity_extremes(&self) -> (Vec<f64>, f64) {
        let a = &self.accel;
        let mut v = Vec::with_capacity(a.len());
        v.push(0.0);
        let mut peak = 0.0_f64;
        for k in 0..a.len() - 1 {
            let (a0, a1, v0) = (a[k], a[k + 1], v[k]);
            if a0 * a1 < 0.0 {
                // v is quadratic on the segment; its extremum is where a = 0.
                let tau = self.dt * a0 / (a0 - a1);
                peak = peak.max((v0 + 0.5 * a0 * tau).abs());
            }
            let v1 = v0 + 0.5 * self.dt * (a0 + a1);
            peak = peak.max(v1.abs());
            v.push(v1);
        }
        (v, peak)
    }

    /// Baseline correction: subtract from a the derivative of the least-squares fit
    /// v ≈ c1 τ + c2 τ² (τ = t − t0, through the origin so the ground still starts at rest),
    /// which removes the linear drift of velocity (and quadratic drift of displacement) that
    /// digitisation offsets produce. Opt-in: it changes the record.
    pub fn baseline_corrected(&self) -> Series {
        let (v, _) = self.velocity_extremes();
        let (mut s22, mut s23, mut s33, mut b2, mut b3) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for (k, vk) in v.iter().enumerate() {
            let tau = k as f64 * self.dt;
            let (p, q) = (tau, tau * tau);
            s22 += p * p;
            s23 += p * q;
            s33 += q * q;
            b2 += p * vk;
            b3 += q * vk;
        }
        let det = s22 * s33 - s23 * s23;
        if det.abs() < f64::MIN_POSITIVE || !det.is_finite() {
            return self.clone();
        }
        let c1 = (b2 * s33 - b3 * s23) / det;
        let c2 = (s22 * b3 - s23 * b2) / det;
        let corrected = self
            .accel
            .iter()
            .enumerate()
            .map(|(k, a)| a - (c1 + 2.0 * c2 * k as f64 * self.dt))
            .collect();
        Series {
            to_standard: self.to_standard,
            ..Series::new(self.t0, self.dt, corrected)
        }
    }

    /// Index of the first sample strictly after t.
    fn first_sample_after(&self, t: f64) -> usize {
        if t < self.t0 {
            return 0;
        }
        let k = ((t - self.t0) * self.inv_dt).floor() as usize + 1;
        // Guard against rounding in k·dt: the sample must lie strictly (and visibly) after t.
        if self.time(k) <= t + 1e-9 * self.dt {
            k + 1
        } else {
            k
        }
    }
}

/// How the integrator treats the kinks of a sampled record (a_g is continuous but its slope
/// jumps at every sample). See BENCHMARKS.md, "Records: kinks between samples".
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum KinkPolicy {
    /// Stop at every sample, so no step straddles a kink (default).
    #[default]
    StopAtSamples,
    /// Step across samples and leave the kinks to the error controller.
    StepOver,
}

/// A record scaled by a factor: a_g(t) = factor · a(t). Cheap to clone (shares the samples).
#[derive(Clone, Debug)]
pub struct RecordMotion {
    pub series: Arc<Series>,
    pub factor: f64,
    pub kinks: KinkPolicy,
}

impl RecordMotion {
    #[inline]
    pub fn accel(&self, t: f64) -> f64 {
        self.factor * self.series.accel(t)
    }

    pub fn end(&self) -> f64 {
        self.series.end()
    }

    pub fn next_breakpoint(&self, t: f64) -> Option<f64> {
        match self.kinks {
            KinkPolicy::StopAtSamples => self.next_kink(t),
            KinkPolicy::StepOver => {
                let s = &*self.series;
                if t < s.t0 {
                    Some(s.t0)
                } else {
                    (t < s.end()).then(|| s.end())
                }
            }
        }
    }

    /// The next sample strictly after `t` (the record's start and end included), whatever the
    /// kink policy.
    pub fn next_kink(&self, t: f64) -> Option<f64> {
        let s = &*self.series;
        if t < s.t0 {
            return Some(s.t0);
        }
        if t >= s.end() {
            return None;
        }
        Some(s.time(s.first_sample_after(t).min(s.npts() - 1)))
    }

    /// a_g jumps only where the record starts or ends on a nonzero sample.
    pub fn jumps_at(&self, t: f64) -> bool {
        let s = &*self.series;
        let near = |u: f64| (t - u).abs() <= 1e-9 * s.dt;
        (near(s.t0) && s.accel[0] != 0.0) || (near(s.end()) && s.accel[s.npts() - 1] != 0.0)
    }

    /// First time ≥ t0 at which |a_g| exceeds `level`: the exact crossing of the linear
    /// segment that carries |a_g| past it (nudged by ulps to where the excess is strict).
    pub fn first_exceedance(&self, t0: f64, level: f64) -> Option<f64> {
        let s = &*self.series;
        if self.factor == 0.0 || t0 > s.end() {
            return None;
        }
        let lev = level / self.factor.abs();
        let (mut ta, mut a) = if t0 < s.t0 {
            (s.t0, s.accel[0])
        } else {
            (t0, s.accel(t0))
        };
        if a.abs() > lev {
            return Some(ta);
        }
        for k in s.first_sample_after(ta)..s.npts() {
            let (tb, b) = (s.time(k), s.accel[k]);
            if b.abs() > lev {
                let u = (lev.copysign(b) - a) / (b - a);
                let crossing = (ta + u * (tb - ta)).clamp(ta, tb);
                return Some(self.strictly_past(crossing, tb, level));
            }
            (ta, a) = (tb, b);
        }
        None
    }

    /// The first time from `t` on (to within a few ulps) where |a_g| > level strictly, so a
    /// caller that tests |a_g| > level at the returned time sees it exceeded; |a_g(tb)| > level.
    fn strictly_past(&self, t: f64, tb: f64, level: f64) -> f64 {
        let mut nudge = f64::EPSILON * t.abs().max(self.series.dt);
        let mut u = t;
        while u < tb && self.accel(u).abs() <= level {
            u = (t + nudge).min(tb);
            nudge *= 2.0;
        }
        u
    }

    /// Peak |a_g| over [t0, t1]: the ends and the samples between them.
    pub fn peak_abs(&self, t0: f64, t1: f64) -> f64 {
        let s = &*self.series;
        if t1 < t0 {
            return 0.0;
        }
        let mut peak = s.accel(t0).abs().max(s.accel(t1).abs());
        let first = s.first_sample_after(t0);
        for k in first..s.npts() {
            if s.time(k) > t1 {
                break;
            }
            peak = peak.max(s.accel[k].abs());
        }
        peak * self.factor.abs()
    }
}
