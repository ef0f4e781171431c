//! The response quantities a study reports: part of the study schema (a study file names them),
//! evaluated on a scene's result.

use crate::sim::{Measures, SceneResult};
use serde::{Deserialize, Serialize};

/// A response quantity reported per scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// |θ|max (rad).
    PeakRotation,
    /// |θ|max / α.
    PeakRotationRatio,
    /// Peak column deformation |u|max (m), flexible structures.
    PeakDeformation,
    /// Peak drift (flexible structures).
    PeakDrift,
    /// Peak absolute horizontal acceleration / g.
    PeakAbsAcceleration,
    /// Rigid block: peak angular acceleration between impacts / p² (the paper's rigid-block
    /// acceleration, §3 and Figs. 5, 8, 12).
    PeakAngularAcceleration,
}

impl Quantity {
    pub const ALL: [Quantity; 6] = [
        Quantity::PeakRotation,
        Quantity::PeakRotationRatio,
        Quantity::PeakDeformation,
        Quantity::PeakDrift,
        Quantity::PeakAbsAcceleration,
        Quantity::PeakAngularAcceleration,
    ];

    /// The snake_case name used in study files and CSV.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::PeakRotation => "peak_rotation",
            Quantity::PeakRotationRatio => "peak_rotation_ratio",
            Quantity::PeakDeformation => "peak_deformation",
            Quantity::PeakDrift => "peak_drift",
            Quantity::PeakAbsAcceleration => "peak_abs_acceleration",
            Quantity::PeakAngularAcceleration => "peak_angular_acceleration",
        }
    }

    /// Axis label for plots and summaries.
    pub fn label(self) -> &'static str {
        match self {
            Quantity::PeakRotation => "|θ|max (rad)",
            Quantity::PeakRotationRatio => "|θ|max/α",
            Quantity::PeakDeformation => "|u|max (m)",
            Quantity::PeakDrift => "peak drift",
            Quantity::PeakAbsAcceleration => "|ẍ|max/g",
            Quantity::PeakAngularAcceleration => "|θ̈|max/p²",
        }
    }

    pub fn from_name(name: &str) -> Option<Quantity> {
        Quantity::ALL.into_iter().find(|q| q.name() == name)
    }

    /// What a run must compute to report `quantities` (the rotation is always computed).
    pub fn measures(quantities: &[Quantity]) -> Measures {
        let mut m = Measures::ROTATION;
        for q in quantities {
            match q {
                Quantity::PeakRotation | Quantity::PeakRotationRatio => {}
                Quantity::PeakDeformation => m.deformation = true,
                Quantity::PeakDrift => m.drift = true,
                Quantity::PeakAbsAcceleration => m.abs_acceleration = true,
                Quantity::PeakAngularAcceleration => m.angular_acceleration = true,
            }
        }
        m
    }

    /// Whether a run that computed `measured` reports this quantity.
    pub fn measured_in(self, measured: Measures) -> bool {
        match self {
            Quantity::PeakRotation | Quantity::PeakRotationRatio => true,
            Quantity::PeakDeformation => measured.deformation,
            Quantity::PeakDrift => measured.drift,
            Quantity::PeakAbsAcceleration => measured.abs_acceleration,
            Quantity::PeakAngularAcceleration => measured.angular_acceleration,
        }
    }

    /// The value of this quantity in a result; None if the structure overturned (peaks of an
    /// overturned structure are not a response) or has no such measure.
    pub fn of(self, r: &SceneResult) -> Option<f64> {
        if r.overturned || !self.measured_in(r.measured) {
            return None;
        }
        match self {
            Quantity::PeakRotation => Some(r.peaks.rotation),
            Quantity::PeakRotationRatio => Some(r.peak_rotation_ratio),
            Quantity::PeakDeformation => Some(r.peaks.deformation),
            Quantity::PeakDrift => Some(r.peaks.drift),
            Quantity::PeakAbsAcceleration => Some(r.peaks.abs_acceleration_g),
            Quantity::PeakAngularAcceleration => r.peaks.angular_acceleration_p2,
        }
    }
}
