//! The response quantities: one table of their names, keys, labels and units (part of the study
//! schema, since a study file names them; here beside the result they are read from),
//! evaluated on a scene's result.

use super::{Measures, SceneResult};
use serde::{Deserialize, Serialize};

/// What the program says about a quantity (one row of [`Quantity::info`]).
#[derive(Debug, PartialEq, Eq)]
pub struct QuantityInfo {
    /// snake_case name in study files, results.csv and `--quantity`.
    pub name: &'static str,
    /// The key of its value in `simulate --json` and check.csv (the peak as the run holds it).
    pub key: &'static str,
    /// Label for summaries and tables, e.g. `|ẍ|max/g`.
    pub label: &'static str,
    /// Figure axis label with its unit, e.g. `ẍmax [g]`.
    pub axis: &'static str,
    /// Unit (empty for a ratio).
    pub unit: &'static str,
    /// A word for people in the check's report, e.g. `abs. accel.`.
    pub short: &'static str,
    /// One line on what it is, for help texts.
    pub help: &'static str,
}

all_variants! {
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
}

impl Quantity {
    /// Everything the program says about this quantity: its row of [`Quantity::info`]'s
    /// table, the one place these names, keys, labels and units are written.
    pub fn info(self) -> &'static QuantityInfo {
        match self {
            Quantity::PeakRotation => &QuantityInfo {
                name: "peak_rotation",
                key: "peak_rotation",
                label: "|θ|max (rad)",
                axis: "θmax [rad]",
                unit: "rad",
                short: "rotation",
                help: "peak rotation |θ|max",
            },
            Quantity::PeakRotationRatio => &QuantityInfo {
                name: "peak_rotation_ratio",
                key: "peak_rotation_ratio",
                label: "|θ|max/α",
                axis: "θmax/α",
                unit: "",
                short: "rotation/α",
                help: "peak rotation over the slenderness angle α (overturning at 1 for a rigid block)",
            },
            Quantity::PeakDeformation => &QuantityInfo {
                name: "peak_deformation",
                key: "peak_deformation",
                label: "|u|max (m)",
                axis: "umax [m]",
                unit: "m",
                short: "deformation",
                help: "peak column deformation |u|max (flexible structures)",
            },
            Quantity::PeakDrift => &QuantityInfo {
                name: "peak_drift",
                key: "peak_drift",
                label: "peak drift",
                axis: "drift |X|max/H",
                unit: "",
                short: "drift",
                help: "peak drift |X|max/H (flexible structures)",
            },
            Quantity::PeakAbsAcceleration => &QuantityInfo {
                name: "peak_abs_acceleration",
                key: "peak_abs_acceleration_g",
                label: "|ẍ|max/g",
                axis: "ẍmax [g]",
                unit: "g",
                short: "abs. accel.",
                help: "peak absolute horizontal acceleration / g, impact jumps excluded",
            },
            Quantity::PeakAngularAcceleration => &QuantityInfo {
                name: "peak_angular_acceleration",
                key: "peak_angular_acceleration_p2",
                label: "|θ̈|max/p²",
                axis: "θ̈max/p²",
                // θ̈max/p² is dimensionless, like θmax/α.
                unit: "",
                short: "θ̈",
                help: "rigid blocks: peak angular acceleration between impacts / p²",
            },
        }
    }

    /// The snake_case name used in study files and CSV.
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// Label for summaries and tables.
    pub fn label(self) -> &'static str {
        self.info().label
    }

    pub fn from_name(name: &str) -> Option<Quantity> {
        Quantity::ALL.into_iter().find(|q| q.name() == name)
    }

    /// A quantity by its key in `simulate --json` and check.csv.
    pub fn from_key(key: &str) -> Option<Quantity> {
        Quantity::ALL.into_iter().find(|q| q.info().key == key)
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
        if r.overturned {
            return None;
        }
        self.peak(r)
    }

    /// The peak in a result whether or not the structure overturned; None if the run did not
    /// measure it or the structure has no such measure (θ̈ of a flexible structure).
    pub fn peak(self, r: &SceneResult) -> Option<f64> {
        if !self.measured_in(r.measured) {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_keys_are_distinct_and_read_back() {
        for (i, q) in Quantity::ALL.iter().enumerate() {
            let info = q.info();
            assert_eq!(Quantity::from_name(info.name), Some(*q));
            assert_eq!(Quantity::from_key(info.key), Some(*q));
            // The study name is serde's spelling of the variant.
            assert_eq!(ron::to_string(q).unwrap(), info.name);
            for other in &Quantity::ALL[i + 1..] {
                assert_ne!(info.name, other.info().name);
                assert_ne!(info.key, other.info().key);
                assert_ne!(info.axis, other.info().axis);
            }
            // An axis label carries the unit when there is one.
            assert!(
                info.unit.is_empty() || info.axis.contains(info.unit),
                "{info:?}"
            );
        }
    }
}
