//! Inerter devices acting on one horizontal coordinate x of a structure (MODEL.md "Devices").
//! The structure supplies x and ẋ; the device returns the force Fd it puts on the structure
//! and the accelerations of its flywheels. Shared by the rigid and flexible families.

use super::clutch::{clutch_force, clutch_potential, friction_force};
use crate::excitation::G;
use crate::scene::{ClutchStiffness, Coupling, Damping, Device, ResetRule};

/// A device with its parameters converted to the translational form.
#[derive(Clone, Copy, Debug)]
pub enum DeviceModel {
    None,
    /// mr rigidly joins the x motion.
    Coupled {
        mr: f64,
    },
    /// Sequential twin clutch: mr joins the x motion while |ẋ| grows.
    Sequential {
        mr: f64,
    },
    /// Single flywheel behind a linear spring k, damping c̄.
    Spring {
        mr: f64,
        k: f64,
        cbar: f64,
    },
    /// Twin mechanistic clutches.
    Clutch(ClutchModel),
}

#[derive(Clone, Copy, Debug)]
pub struct ClutchModel {
    pub mr: f64,
    pub k: f64,
    pub eps_hat: f64,
    pub cbar: f64,
    /// Friction force magnitude (N).
    pub friction: f64,
    pub eta: f64,
    pub rho: f64,
    pub play: f64,
    pub reset: ResetRule,
}

fn spring_constant(stiffness: ClutchStiffness, rho: f64, mr: f64, p: f64) -> f64 {
    match stiffness {
        ClutchStiffness::KTheta(k_theta) => k_theta / (rho * rho),
        ClutchStiffness::FrequencyRatio(r) => mr * (r * p).powi(2),
    }
}

fn damping_cbar(damping: Damping, k: f64, mr: f64) -> f64 {
    match damping {
        Damping::CBar(c) => c,
        // ξθ = c/(2√(kθ J)) ⇒ c̄ = c/J = 2 ξθ √(kθ/J) = 2 ξθ √(k/mr).
        Damping::XiTheta(xi) => 2.0 * xi * (k / mr).sqrt(),
    }
}

impl DeviceModel {
    /// Convert scene parameters for a structure of mass `m` and frequency parameter `p`.
    pub fn new(device: &Device, m: f64, p: f64) -> Self {
        match device {
            Device::None => DeviceModel::None,
            Device::Inerter { sigma, coupling } => {
                let mr = sigma * m;
                match coupling {
                    Coupling::Rigid => DeviceModel::Coupled { mr },
                    Coupling::Flywheel {
                        stiffness,
                        rho,
                        damping,
                    } => {
                        let k = spring_constant(*stiffness, *rho, mr, p);
                        DeviceModel::Spring {
                            mr,
                            k,
                            cbar: damping_cbar(*damping, k, mr),
                        }
                    }
                }
            }
            Device::Sequential { sigma } => DeviceModel::Sequential { mr: sigma * m },
            Device::Mechanistic(c) => {
                let mr = c.sigma * m;
                let k = spring_constant(c.stiffness, c.rho, mr, p);
                DeviceModel::Clutch(ClutchModel {
                    mr,
                    k,
                    eps_hat: c.epsilon / c.rho,
                    cbar: damping_cbar(c.damping, k, mr),
                    friction: c.friction * mr * G,
                    eta: c.eta,
                    rho: c.rho,
                    play: c.play,
                    reset: c.reset,
                })
            }
        }
    }

    /// Number of flywheels whose motion is integrated (each adds y, ẏ to the state).
    pub fn flywheels(&self) -> usize {
        match self {
            DeviceModel::Spring { .. } => 1,
            DeviceModel::Clutch(_) => 2,
            _ => 0,
        }
    }

    pub fn mr(&self) -> f64 {
        match *self {
            DeviceModel::None => 0.0,
            DeviceModel::Coupled { mr }
            | DeviceModel::Sequential { mr }
            | DeviceModel::Spring { mr, .. } => mr,
            DeviceModel::Clutch(c) => c.mr,
        }
    }

    /// Apparent mass rigidly attached to x right now.
    pub fn coupled_mass(&self, sequential_engaged: bool) -> f64 {
        match *self {
            DeviceModel::Coupled { mr } => mr,
            DeviceModel::Sequential { mr } if sequential_engaged => mr,
            _ => 0.0,
        }
    }

    /// Spring forces on the flywheels for structure position x and flywheel states
    /// `fly = [y_a, ẏ_a, y_b, ẏ_b]`: returns (f_a, f_b). Fd = −(f_a + f_b).
    #[inline]
    pub fn spring_forces(&self, x: f64, fly: &[f64]) -> (f64, f64) {
        match *self {
            DeviceModel::Spring { k, .. } => (k * (x - fly[0]), 0.0),
            DeviceModel::Clutch(c) => {
                let fa = clutch_force(c.k, c.eps_hat, x - fly[0] - c.play);
                // Mirror of clutch a: f_b(δ) = −f_a(−δ).
                let fb = -clutch_force(c.k, c.eps_hat, -(x - fly[2]) - c.play);
                (fa, fb)
            }
            _ => (0.0, 0.0),
        }
    }

    /// Flywheel acceleration under spring force f at velocity ẏ; also returns the power lost
    /// to viscous damping and to friction.
    #[inline]
    pub fn flywheel_accel(&self, f: f64, ydot: f64) -> (f64, f64, f64) {
        match *self {
            DeviceModel::Spring { mr, cbar, .. } => {
                (f / mr - cbar * ydot, cbar * mr * ydot * ydot, 0.0)
            }
            DeviceModel::Clutch(c) => {
                let fmu = friction_force(c.friction, c.eta, c.rho, ydot);
                (
                    (f - fmu) / c.mr - c.cbar * ydot,
                    c.cbar * c.mr * ydot * ydot,
                    fmu * ydot,
                )
            }
            _ => (0.0, 0.0, 0.0),
        }
    }

    /// Energy stored in flywheels and springs (excluding a coupled mass, which the structure
    /// books with its own kinetic energy).
    pub fn stored_energy(&self, x: f64, fly: &[f64]) -> f64 {
        match *self {
            DeviceModel::Spring { mr, k, .. } => {
                0.5 * mr * fly[1] * fly[1] + 0.5 * k * (x - fly[0]).powi(2)
            }
            DeviceModel::Clutch(c) => {
                0.5 * c.mr * (fly[1] * fly[1] + fly[3] * fly[3])
                    + self.clutch_potential_a(x - fly[0])
                    + self.clutch_potential_b(x - fly[2])
            }
            _ => 0.0,
        }
    }

    pub fn clutch_potential_a(&self, delta_a: f64) -> f64 {
        match *self {
            DeviceModel::Clutch(c) => clutch_potential(c.k, c.eps_hat, delta_a - c.play),
            _ => 0.0,
        }
    }

    pub fn clutch_potential_b(&self, delta_b: f64) -> f64 {
        match *self {
            DeviceModel::Clutch(c) => clutch_potential(c.k, c.eps_hat, -delta_b - c.play),
            _ => 0.0,
        }
    }
}

impl ClutchModel {
    /// Clutch a is disengaged (may be reset on re-engagement) at relative displacement δa.
    pub fn a_resettable(&self, delta_a: f64) -> bool {
        match self.reset {
            ResetRule::Paper => delta_a < self.play,
            ResetRule::Strict => delta_a < 0.0,
        }
    }

    pub fn b_resettable(&self, delta_b: f64) -> bool {
        match self.reset {
            ResetRule::Paper => delta_b > -self.play,
            ResetRule::Strict => delta_b > 0.0,
        }
    }
}
