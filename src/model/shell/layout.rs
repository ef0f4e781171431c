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
/// The four accumulators are named by [`Accumulator`]; they are integrated only for a run that
/// keeps the energy ledger (`ledger`), and are never error controlled (quadratures of the
/// dissipated power: the steps are those of the physical state alone, with or without them).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Number of structure coordinates and rates (the leading components).
    pub coordinates: usize,
    /// The device's degrees of freedom ([`DeviceModel::dofs`]: its flywheels).
    pub device_dofs: usize,
    /// Whether the energy accumulators are part of the state.
    pub ledger: bool,
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
            ledger: true,
        }
    }

    /// Number of state components.
    pub fn state_len(&self) -> usize {
        self.physical_len() + if self.ledger { 4 } else { 0 }
    }

    /// Number of physical state components (structure and device: what the error norm
    /// controls and the events read); the accumulators, if any, follow them.
    pub fn physical_len(&self) -> usize {
        self.device_dof(self.device_dofs)
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

    /// Index of an accumulator; None without the ledger.
    pub fn accumulator(&self, which: Accumulator) -> Option<usize> {
        self.ledger.then(|| self.physical_len() + which as usize)
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
