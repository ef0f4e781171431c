//! Where each part of a rocking model's state lives, and the phase of its base.

use crate::model::device::DeviceModel;

/// Whether the base is flat on the ground or rocking about a corner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Base flat on the ground: θ ≡ 0.
    Contact,
    Rocking,
}

/// Where each part of the state lives:
/// `[structure coordinates and rates | device states (y, ẏ per degree of freedom) | accumulators]`.
/// The four accumulators are named by [`Accumulator`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Number of structure coordinates and rates (the leading components).
    pub coordinates: usize,
    /// The device's degrees of freedom ([`DeviceModel::dofs`]: its flywheels).
    pub device_dofs: usize,
}

/// The time integrals at the end of the state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Accumulator {
    /// Work of the ground motion, ∫ −m a_g Ẋ dt.
    Input = 0,
    DeviceDamping = 1,
    Friction = 2,
    /// What the structure dissipates continuously ([`Body::OWN_LOSS`]).
    Own = 3,
}

impl Layout {
    pub fn new(coordinates: usize, device: &DeviceModel) -> Self {
        Layout {
            coordinates,
            device_dofs: device.dofs(),
        }
    }

    /// Number of state components.
    pub fn state_len(&self) -> usize {
        self.coordinates + 2 * self.device_dofs + 4
    }

    /// Index of the device's degree of freedom i's position (its velocity follows it).
    pub fn device_dof(&self, i: usize) -> usize {
        self.coordinates + 2 * i
    }

    /// The device states `[y_a, ẏ_a, y_b, ẏ_b]` (as many as the device has).
    pub fn device_states<'y>(&self, y: &'y [f64]) -> &'y [f64] {
        &y[self.coordinates..self.device_dof(self.device_dofs)]
    }

    pub fn device_states_mut<'y>(&self, y: &'y mut [f64]) -> &'y mut [f64] {
        &mut y[self.coordinates..self.device_dof(self.device_dofs)]
    }

    pub fn accumulator(&self, which: Accumulator) -> usize {
        self.device_dof(self.device_dofs) + which as usize
    }

    /// Velocity of the device's degree of freedom i, 0 if it has no such one (for histories).
    pub(super) fn device_velocity(&self, y: &[f64], i: usize) -> f64 {
        if i < self.device_dofs {
            y[self.device_dof(i) + 1]
        } else {
            0.0
        }
    }
}
