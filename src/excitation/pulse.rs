//! Analytic acceleration pulses.

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PulseShape {
    /// a_g = A sin(ω t) for 0 ≤ t ≤ 2π/ω.
    Sine,
    /// a_g = A cos(ω t) for 0 ≤ t ≤ 2π/ω (jumps at both ends).
    Cosine,
}

/// A pulse with absolute amplitude A (m/s², signed) and circular frequency ω (rad/s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pulse {
    pub shape: PulseShape,
    pub amplitude: f64,
    pub omega: f64,
}

impl Pulse {
    pub fn period(&self) -> f64 {
        2.0 * PI / self.omega
    }

    pub fn end(&self) -> f64 {
        self.period()
    }

    #[inline]
    pub fn accel(&self, t: f64) -> f64 {
        if !(0.0..=self.end()).contains(&t) {
            return 0.0;
        }
        let phase = self.omega * t;
        self.amplitude
            * match self.shape {
                PulseShape::Sine => phase.sin(),
                PulseShape::Cosine => phase.cos(),
            }
    }

    pub fn next_breakpoint(&self, t: f64) -> Option<f64> {
        (t < self.end()).then(|| self.end())
    }

    pub fn jumps_at(&self, t: f64) -> bool {
        self.shape == PulseShape::Cosine && (t == self.end() || t == 0.0)
    }
}
