//! Inerter devices acting on one horizontal coordinate x of a structure (docs/MODEL.md "Devices").
//! The structure supplies x and ẋ; the device returns the force Fd it puts on the structure
//! and the rates of its own states (its flywheels). Shared by the rigid and flexible
//! families: the rocking shell ([`super::shell`]) calls these methods and never asks which
//! device it holds, so a new device is a variant of [`DeviceModel`] and its arms here.

use super::clutch::{clutch_force, clutch_potential, friction_force};
use super::{Counters, Ledger};
use crate::scene::{ClutchStiffness, Coupling, Damping, Device, ResetRule};
use crate::solver::Direction;

/// A device with its parameters converted to the translational form. Named as the study
/// names devices (none / inerter / sequential / mechanistic), the inerter by its coupling.
#[derive(Clone, Copy, Debug)]
pub enum DeviceModel {
    None,
    /// Single inerter, rigid coupling: mr joins the x motion.
    RigidInerter {
        mr: f64,
    },
    /// Single inerter, flywheel coupling: a flywheel behind a linear spring k, damping c̄.
    FlywheelInerter {
        mr: f64,
        k: f64,
        cbar: f64,
    },
    /// Sequential twin clutch: mr joins the x motion while |ẋ| grows.
    Sequential {
        mr: f64,
    },
    /// Twin mechanistic clutches.
    Mechanistic(ClutchModel),
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
    /// Convert scene parameters for a structure of mass `m` and frequency parameter `p`
    /// under gravity `g` (the friction force is a fraction of mr g: a nominal force of the
    /// mechanism, which a vertical ground motion does not change).
    pub fn new(device: &Device, m: f64, p: f64, g: f64) -> Self {
        match device {
            Device::None => DeviceModel::None,
            Device::Inerter { sigma, coupling } => {
                let mr = sigma * m;
                match coupling {
                    Coupling::Rigid => DeviceModel::RigidInerter { mr },
                    Coupling::Flywheel {
                        stiffness,
                        rho,
                        damping,
                    } => {
                        let k = spring_constant(*stiffness, *rho, mr, p);
                        DeviceModel::FlywheelInerter {
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
                DeviceModel::Mechanistic(ClutchModel {
                    mr,
                    k,
                    eps_hat: c.epsilon / c.rho,
                    cbar: damping_cbar(c.damping, k, mr),
                    friction: c.friction * mr * g,
                    eta: c.eta,
                    rho: c.rho,
                    play: c.play,
                    reset: c.reset,
                })
            }
        }
    }

    /// The device's flywheels, whose motion is integrated: the one place its state size is
    /// decided (each adds y, ẏ to the state, see [`super::shell::Layout`]), so the driver's
    /// dispatch over state sizes (`sim::run_sampled`) is a total match.
    pub fn flywheels(&self) -> Flywheels {
        match self {
            DeviceModel::None
            | DeviceModel::RigidInerter { .. }
            | DeviceModel::Sequential { .. } => Flywheels::Zero,
            DeviceModel::FlywheelInerter { .. } => Flywheels::One,
            DeviceModel::Mechanistic(_) => Flywheels::Two,
        }
    }

    /// Number of the device's degrees of freedom whose motion is integrated.
    pub fn dofs(&self) -> usize {
        self.flywheels() as usize
    }

    pub fn mr(&self) -> f64 {
        match *self {
            DeviceModel::None => 0.0,
            DeviceModel::RigidInerter { mr }
            | DeviceModel::Sequential { mr }
            | DeviceModel::FlywheelInerter { mr, .. } => mr,
            DeviceModel::Mechanistic(c) => c.mr,
        }
    }

    /// Apparent mass rigidly attached to x right now (`engaged`: the switch's state).
    pub fn coupled_mass(&self, engaged: bool) -> f64 {
        match *self {
            DeviceModel::RigidInerter { mr } => mr,
            DeviceModel::Sequential { mr } if engaged => mr,
            DeviceModel::None
            | DeviceModel::Sequential { .. }
            | DeviceModel::FlywheelInerter { .. }
            | DeviceModel::Mechanistic(_) => 0.0,
        }
    }

    /// The device is a constant mass on x with no state of its own (a linear device): that
    /// mass, or None. Full contact of a flexible column then has a closed form.
    pub fn constant_coupled_mass(&self) -> Option<f64> {
        match *self {
            DeviceModel::None => Some(0.0),
            DeviceModel::RigidInerter { mr } => Some(mr),
            DeviceModel::FlywheelInerter { .. }
            | DeviceModel::Sequential { .. }
            | DeviceModel::Mechanistic(_) => None,
        }
    }

    /// Stiffness of the device's springs, None for a device without springs.
    pub fn spring_stiffness(&self) -> Option<f64> {
        match *self {
            DeviceModel::FlywheelInerter { k, .. } => Some(k),
            DeviceModel::Mechanistic(c) => Some(c.k),
            DeviceModel::None
            | DeviceModel::RigidInerter { .. }
            | DeviceModel::Sequential { .. } => None,
        }
    }

    /// Whether the device has a switch deciding on the sign of ẋ·ẍ of the bare structure
    /// (the sequential law); the shell locates it and calls [`Self::toggle_switch`].
    pub fn has_switch(&self) -> bool {
        match self {
            DeviceModel::Sequential { .. } => true,
            DeviceModel::None
            | DeviceModel::RigidInerter { .. }
            | DeviceModel::FlywheelInerter { .. }
            | DeviceModel::Mechanistic(_) => false,
        }
    }

    /// Spring forces on the flywheels for structure position x and device states
    /// `states = [y_a, ẏ_a, y_b, ẏ_b]`: returns (f_a, f_b). Fd = −(f_a + f_b).
    #[inline]
    pub fn spring_forces(&self, x: f64, states: &[f64]) -> (f64, f64) {
        match *self {
            DeviceModel::FlywheelInerter { k, .. } => (k * (x - states[0]), 0.0),
            DeviceModel::Mechanistic(c) => {
                let fa = clutch_force(c.k, c.eps_hat, x - states[0] - c.play);
                // Mirror of clutch a: f_b(δ) = −f_a(−δ).
                let fb = -clutch_force(c.k, c.eps_hat, -(x - states[2]) - c.play);
                (fa, fb)
            }
            DeviceModel::None
            | DeviceModel::RigidInerter { .. }
            | DeviceModel::Sequential { .. } => (0.0, 0.0),
        }
    }

    /// The force Fd the device's springs put on the structure (not counting a coupled mass).
    #[inline]
    pub fn spring_force(&self, x: f64, states: &[f64]) -> f64 {
        let (fa, fb) = self.spring_forces(x, states);
        -(fa + fb)
    }

    /// Flywheel acceleration under spring force f at velocity ẏ; also returns the power lost
    /// to viscous damping and to friction.
    #[inline]
    fn flywheel_accel(&self, f: f64, ydot: f64) -> (f64, f64, f64) {
        match *self {
            DeviceModel::FlywheelInerter { mr, cbar, .. } => {
                (f / mr - cbar * ydot, cbar * mr * ydot * ydot, 0.0)
            }
            DeviceModel::Mechanistic(c) => {
                let fmu = friction_force(c.friction, c.eta, c.rho, ydot);
                (
                    (f - fmu) / c.mr - c.cbar * ydot,
                    c.cbar * c.mr * ydot * ydot,
                    fmu * ydot,
                )
            }
            // No flywheel ([`Self::dofs`] is 0): never called, and nothing moves.
            DeviceModel::None
            | DeviceModel::RigidInerter { .. }
            | DeviceModel::Sequential { .. } => (0.0, 0.0, 0.0),
        }
    }

    /// The device's equations of motion at structure position x: writes the rates of its
    /// `states` (as many as [`Self::dofs`] pairs y, ẏ) into `rates`, returns the force on
    /// the structure and the power it dissipates. (Inlined into the right-hand side, the
    /// bare block's hot path: a device without states costs one test.)
    #[inline(always)]
    pub fn rates(&self, x: f64, states: &[f64], rates: &mut [f64]) -> DeviceRates {
        if states.is_empty() {
            return DeviceRates::STATELESS;
        }
        let (fa, fb) = self.spring_forces(x, states);
        let (mut damping, mut friction) = (0.0, 0.0);
        for (i, f) in [fa, fb].into_iter().take(states.len() / 2).enumerate() {
            let (a, pv, pf) = self.flywheel_accel(f, states[2 * i + 1]);
            rates[2 * i] = states[2 * i + 1];
            rates[2 * i + 1] = a;
            damping += pv;
            friction += pf;
        }
        DeviceRates {
            force: -(fa + fb),
            damping,
            friction,
        }
    }

    /// Energy stored in flywheels and springs (excluding a coupled mass, which the structure
    /// books with its own kinetic energy).
    pub fn stored_energy(&self, x: f64, states: &[f64]) -> f64 {
        match *self {
            DeviceModel::FlywheelInerter { mr, k, .. } => {
                0.5 * mr * states[1] * states[1] + 0.5 * k * (x - states[0]).powi(2)
            }
            DeviceModel::Mechanistic(c) => {
                0.5 * c.mr * (states[1] * states[1] + states[3] * states[3])
                    + c.potential_a(x - states[0])
                    + c.potential_b(x - states[2])
            }
            DeviceModel::None
            | DeviceModel::RigidInerter { .. }
            | DeviceModel::Sequential { .. } => 0.0,
        }
    }

    /// Energy the device can still give back once the ground has stopped. A coupled mass and
    /// a two-way spring give back all they hold. The sequential law gives nothing back (mr's
    /// energy is lost at disengagement). A one-way clutch pushes flywheel a only forward
    /// (f_a ≥ 0, ẏ_a ≥ 0) and b only backward, so flywheel energy never returns: only the
    /// clutch springs' can.
    pub fn returnable(&self, x: f64, xdot: f64, states: &[f64]) -> Returnable {
        let (energy, springs, k) = match *self {
            DeviceModel::None | DeviceModel::Sequential { .. } => (0.0, 0.0, 0.0),
            DeviceModel::RigidInerter { mr } => (0.5 * mr * xdot * xdot, 0.0, 0.0),
            DeviceModel::FlywheelInerter { k, .. } => (self.stored_energy(x, states), 1.0, k),
            DeviceModel::Mechanistic(c) => (
                c.potential_a(x - states[0]).max(0.0) + c.potential_b(x - states[2]).max(0.0),
                2.0,
                c.k,
            ),
        };
        Returnable { energy, k, springs }
    }

    /// The events of the device's own states (located by the shell like its own), in order.
    pub fn events(&self) -> &'static [ClutchEvent] {
        match self {
            DeviceModel::Mechanistic(c) => c.events(),
            DeviceModel::None
            | DeviceModel::RigidInerter { .. }
            | DeviceModel::FlywheelInerter { .. }
            | DeviceModel::Sequential { .. } => &[],
        }
    }

    /// Event `ev`'s function at structure position x and velocity ẋ (see
    /// [`ClutchModel::event_value`]); 1 for a device without it.
    #[inline]
    pub fn event_value(&self, ev: ClutchEvent, x: f64, xdot: f64, states: &[f64]) -> f64 {
        match self {
            DeviceModel::Mechanistic(c) => c.event_value(ev, x, xdot, states),
            DeviceModel::None
            | DeviceModel::RigidInerter { .. }
            | DeviceModel::FlywheelInerter { .. }
            | DeviceModel::Sequential { .. } => 1.0,
        }
    }

    /// Its time derivative along the solution (see [`ClutchModel::event_rate`]).
    #[inline]
    pub fn event_rate(
        &self,
        ev: ClutchEvent,
        x: (f64, f64, f64),
        states: &[f64],
        rates: &[f64],
    ) -> f64 {
        match self {
            DeviceModel::Mechanistic(c) => c.event_rate(ev, x, states, rates),
            DeviceModel::None
            | DeviceModel::RigidInerter { .. }
            | DeviceModel::FlywheelInerter { .. }
            | DeviceModel::Sequential { .. } => 0.0,
        }
    }

    /// The jump of event `ev` at structure position x (see [`ClutchModel::apply`]).
    pub fn apply_event(
        &self,
        ev: ClutchEvent,
        x: f64,
        states: &mut [f64],
        ledger: &mut Ledger,
        counters: &mut Counters,
    ) {
        match self {
            DeviceModel::Mechanistic(c) => c.apply(ev, x, states, ledger, counters),
            DeviceModel::None
            | DeviceModel::RigidInerter { .. }
            | DeviceModel::FlywheelInerter { .. }
            | DeviceModel::Sequential { .. } => {}
        }
    }

    /// The switch at velocity ẋ (see [`toggle_sequential`]).
    pub fn toggle_switch(
        &self,
        xdot: f64,
        engaged: &mut bool,
        ledger: &mut Ledger,
        counters: &mut Counters,
    ) {
        toggle_sequential(self.mr(), xdot, engaged, ledger, counters);
    }

    /// After a jump, put the switch where its law wants it (see [`resync_sequential`]).
    pub fn resync_switch(
        &self,
        xdot: f64,
        bare_xddot: f64,
        engaged: &mut bool,
        ledger: &mut Ledger,
        counters: &mut Counters,
    ) {
        resync_sequential(self.mr(), xdot, bare_xddot, engaged, ledger, counters);
    }
}

/// How many flywheels a device integrates (see [`DeviceModel::flywheels`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flywheels {
    Zero = 0,
    One = 1,
    Two = 2,
}

/// What the device's equations give the structure: the force Fd on it (not counting a
/// coupled mass) and the power the device dissipates.
#[derive(Clone, Copy, Debug)]
pub struct DeviceRates {
    pub force: f64,
    /// Viscous damping of the flywheels.
    pub damping: f64,
    pub friction: f64,
}

impl DeviceRates {
    /// A device without states: what the general case gives without springs, Fd = −(0 + 0)
    /// = −0, nothing dissipated.
    pub const STATELESS: DeviceRates = DeviceRates {
        force: -(0.0 + 0.0),
        damping: 0.0,
        friction: 0.0,
    };
}

/// Energy the device can still give back to the structure once the ground has stopped
/// (see [`DeviceModel::returnable`]), and the springs through which it can push.
#[derive(Clone, Copy, Debug)]
pub struct Returnable {
    pub energy: f64,
    /// Stiffness of the device springs (0 without).
    pub k: f64,
    /// Number of springs that can push on the structure.
    pub springs: f64,
}

/// The sequential law's switch at velocity ẋ. Disengaging loses the flywheel's ½ mr ẋ²;
/// engaging at ẋ ≠ 0 creates it from nothing (the law's known flaw, docs/MODEL.md), booked as
/// negative dissipation so the energy balance closes.
fn toggle_sequential(
    mr: f64,
    xdot: f64,
    engaged: &mut bool,
    ledger: &mut Ledger,
    counters: &mut Counters,
) {
    let e = 0.5 * mr * xdot * xdot;
    if *engaged {
        ledger.disengagement += e;
    } else {
        ledger.disengagement -= e;
        counters.engagements += 1;
    }
    *engaged = !*engaged;
}

/// After a jump, put the sequential clutch where its law wants it: engaged exactly while
/// ẋ·ẍ > 0 (ẍ of the bare structure).
fn resync_sequential(
    mr: f64,
    xdot: f64,
    bare_xddot: f64,
    engaged: &mut bool,
    ledger: &mut Ledger,
    counters: &mut Counters,
) {
    let g = xdot * bare_xddot;
    if (*engaged && g < 0.0) || (!*engaged && g > 0.0) {
        toggle_sequential(mr, xdot, engaged, ledger, counters);
    }
}

/// Events of the mechanistic clutch, the same for every structure: contact and separation at
/// δ = ±up (located, so no step straddles the tanh corner), the re-engagement resets, and the
/// strict rule's guard boundaries at δ = 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClutchEvent {
    ContactA,
    ContactB,
    ResetA,
    ResetB,
    GuardA,
    GuardB,
}

impl ClutchEvent {
    pub fn name(self) -> &'static str {
        match self {
            ClutchEvent::ContactA => "contact_a",
            ClutchEvent::ContactB => "contact_b",
            ClutchEvent::ResetA => "reset_a",
            ClutchEvent::ResetB => "reset_b",
            ClutchEvent::GuardA => "guard_a",
            ClutchEvent::GuardB => "guard_b",
        }
    }

    pub fn direction(self) -> Direction {
        match self {
            ClutchEvent::ResetA => Direction::Rising,
            ClutchEvent::ResetB => Direction::Falling,
            ClutchEvent::ContactA
            | ClutchEvent::ContactB
            | ClutchEvent::GuardA
            | ClutchEvent::GuardB => Direction::Either,
        }
    }
}

impl ClutchModel {
    pub fn potential_a(&self, delta_a: f64) -> f64 {
        clutch_potential(self.k, self.eps_hat, delta_a - self.play)
    }

    pub fn potential_b(&self, delta_b: f64) -> f64 {
        clutch_potential(self.k, self.eps_hat, -delta_b - self.play)
    }

    /// The clutch events this clutch needs (guards only for the strict rule with play).
    pub fn events(&self) -> &'static [ClutchEvent] {
        use ClutchEvent::*;
        if self.play > 0.0 && self.reset == ResetRule::Strict {
            &[ContactA, ContactB, ResetA, ResetB, GuardA, GuardB]
        } else {
            &[ContactA, ContactB, ResetA, ResetB]
        }
    }

    /// Event function for structure position x and velocity ẋ, flywheels
    /// `fly = [y_a, ẏ_a, y_b, ẏ_b]`. A reset function is a constant of the non-triggering sign
    /// while its clutch is engaged; it can only jump in the non-triggering direction.
    pub fn event_value(&self, ev: ClutchEvent, x: f64, xdot: f64, fly: &[f64]) -> f64 {
        let (da, db) = (x - fly[0], x - fly[2]);
        match ev {
            ClutchEvent::ContactA => da - self.play,
            ClutchEvent::ContactB => db + self.play,
            ClutchEvent::ResetA if self.a_resettable(da) => xdot - fly[1],
            ClutchEvent::ResetA => 1.0,
            ClutchEvent::ResetB if self.b_resettable(db) => xdot - fly[3],
            ClutchEvent::ResetB => -1.0,
            ClutchEvent::GuardA => da,
            ClutchEvent::GuardB => db,
        }
    }

    /// [`Self::event_value`]'s time derivative along the solution, from the structure's
    /// (X, Ẋ, Ẍ) and the flywheel states `fly` with their rates `fly_dot`. A reset function
    /// that is a constant (the clutch engaged) has rate 0.
    pub fn event_rate(
        &self,
        ev: ClutchEvent,
        (x, xdot, xddot): (f64, f64, f64),
        fly: &[f64],
        fly_dot: &[f64],
    ) -> f64 {
        let (da, db) = (x - fly[0], x - fly[2]);
        let (da_dot, db_dot) = (xdot - fly_dot[0], xdot - fly_dot[2]);
        match ev {
            ClutchEvent::ContactA | ClutchEvent::GuardA => da_dot,
            ClutchEvent::ContactB | ClutchEvent::GuardB => db_dot,
            ClutchEvent::ResetA if self.a_resettable(da) => xddot - fly_dot[1],
            ClutchEvent::ResetB if self.b_resettable(db) => xddot - fly_dot[3],
            ClutchEvent::ResetA | ClutchEvent::ResetB => 0.0,
        }
    }

    /// The jump of a clutch event at structure position x: a reset puts the flywheel at x
    /// (velocity unchanged) and books the spring energy it releases; a contact crossing into
    /// engagement is counted.
    pub fn apply(
        &self,
        ev: ClutchEvent,
        x: f64,
        fly: &mut [f64],
        ledger: &mut Ledger,
        counters: &mut Counters,
    ) {
        match ev {
            ClutchEvent::ContactA | ClutchEvent::ContactB => {
                // Just past the crossing: engaged when δa − up > 0, or δb + up < 0.
                let value = self.event_value(ev, x, 0.0, fly);
                let sign = if ev == ClutchEvent::ContactA {
                    1.0
                } else {
                    -1.0
                };
                if value * sign > 0.0 {
                    counters.engagements += 1;
                }
            }
            ClutchEvent::ResetA | ClutchEvent::ResetB => {
                let (j, before, after) = if ev == ClutchEvent::ResetA {
                    (0, self.potential_a(x - fly[0]), self.potential_a(0.0))
                } else {
                    (2, self.potential_b(x - fly[2]), self.potential_b(0.0))
                };
                fly[j] = x;
                ledger.reset += before - after;
                counters.resets += 1;
                // Without play the reset lands on the clutch corner and engages at once.
                if self.play == 0.0 {
                    counters.engagements += 1;
                }
            }
            ClutchEvent::GuardA | ClutchEvent::GuardB => {}
        }
    }

    /// Clutch a is disengaged (may be reset on re-engagement) at relative displacement δa.
    pub fn a_resettable(&self, delta_a: f64) -> bool {
        match self.reset {
            ResetRule::Paper => delta_a < self.play,
            ResetRule::Strict => delta_a < 0.0,
            ResetRule::Never => false,
        }
    }

    pub fn b_resettable(&self, delta_b: f64) -> bool {
        match self.reset {
            ResetRule::Paper => delta_b > -self.play,
            ResetRule::Strict => delta_b > 0.0,
            ResetRule::Never => false,
        }
    }
}
