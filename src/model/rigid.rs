//! Housner's rigid block with an inerter device (MODEL.md "Rigid block"; paper §2, §3, §5).
//!
//! State: [θ, θ̇, flywheels (y, ẏ per flywheel), accumulators (input work, device damping,
//! friction, Dirac impact work)]. Only the flywheels the device has are in the state.

use super::device::{ClutchEvent, DeviceModel};
use super::{
    Action, Counters, EndReason, Energy, Ledger, Peaks, SimModel, extremum_on_step, refined_max,
};
use crate::excitation::{G, Motion};
use crate::scene::{Form, Impact, RigidBlock};

/// The equations actually integrated (a scene's `Form::Auto` is resolved before the model is
/// built, by [`Form::resolve`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Equations {
    Exact,
    Slender,
}
use crate::solver::{Dense, Direction, MAX_EVENTS, OdeSystem};
use std::f64::consts::PI;

/// Housner's coefficient of restitution (Eq. 3): r = (1 − 1.5 sin²α)².
pub fn housner_restitution(alpha: f64) -> f64 {
    (1.0 - 1.5 * alpha.sin().powi(2)).powi(2)
}

/// Restitution with an inerter rigidly attached at impact (Eq. 16).
pub fn inerter_restitution(alpha: f64, sigma: f64) -> f64 {
    let q = 0.75 * sigma * alpha.cos().powi(2);
    ((1.0 - 1.5 * alpha.sin().powi(2) + q) / (1.0 + q)).powi(2)
}

/// Half-width θi = 2.576 n/√2 of the Dirac-delta impact zone (§3).
pub fn dirac_zone(width: f64) -> f64 {
    2.576 * width / 2f64.sqrt()
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Ev {
    Impact,
    Overturn,
    Uplift(f64),
    Sequential,
    DiracZone,
    Clutch(ClutchEvent),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    /// Flat on the ground: θ ≡ 0.
    Contact,
    Rocking,
}

pub struct RigidModel<'m> {
    r: f64,
    alpha: f64,
    m: f64,
    form: Equations,
    p2: f64,
    i0: f64,
    sin_a: f64,
    cos_a: f64,
    /// tan α (exact) or α (slender): uplift needs |a_g| > g · this.
    uplift_ratio: f64,
    dev: DeviceModel,
    restitution_override: Option<f64>,
    /// Dirac impact: (width n, zone half-width θi).
    dirac: Option<(f64, f64)>,
    motion: &'m Motion,
    initial_rotation: f64,
    acc: usize,
    events: [Ev; MAX_EVENTS],
    n_events: usize,
    // Discrete mode.
    phase: Phase,
    pivot: f64,
    seq_engaged: bool,
    /// Kinetic energy at entry into the Dirac zone while the impact moment is active.
    dirac_energy: Option<f64>,
    /// Below this post-impact rate the block is put to rest (its next excursion would be
    /// < 1e-10 α): Zeno-safe chattering.
    rest_rate: f64,
    ledger: Ledger,
    counters: Counters,
    peaks: Peaks,
}

impl<'m> RigidModel<'m> {
    pub fn new(
        block: &RigidBlock,
        device: DeviceModel,
        impact: Impact,
        motion: &'m Motion,
        initial_rotation: f64,
    ) -> Self {
        let r = block.size;
        let p2 = 3.0 * G / (4.0 * r);
        let form = match block.form {
            Form::Slender => Equations::Slender,
            Form::Exact | Form::Auto => Equations::Exact,
        };
        let (restitution_override, dirac) = match impact {
            Impact::Housner { restitution } => (restitution, None),
            Impact::Dirac { width } => (None, Some((width, dirac_zone(width)))),
        };
        let acc = 2 + 2 * device.flywheels();
        let mut events = [Ev::Impact; MAX_EVENTS];
        let mut n = 0;
        let mut push = |e| {
            events[n] = e;
            n += 1;
        };
        push(Ev::Impact);
        push(Ev::Overturn);
        push(Ev::Uplift(1.0));
        push(Ev::Uplift(-1.0));
        if matches!(device, DeviceModel::Sequential { .. }) {
            push(Ev::Sequential);
        }
        if dirac.is_some() {
            push(Ev::DiracZone);
        }
        if let DeviceModel::Clutch(c) = device {
            for e in c.events() {
                push(Ev::Clutch(*e));
            }
        }
        RigidModel {
            r,
            alpha: block.alpha,
            m: block.mass,
            form,
            p2,
            i0: 4.0 / 3.0 * block.mass * r * r,
            sin_a: block.alpha.sin(),
            cos_a: block.alpha.cos(),
            uplift_ratio: match form {
                Equations::Exact => block.alpha.tan(),
                Equations::Slender => block.alpha,
            },
            dev: device,
            restitution_override,
            dirac,
            motion,
            initial_rotation,
            acc,
            events,
            n_events: n,
            phase: Phase::Contact,
            pivot: 1.0,
            seq_engaged: false,
            dirac_energy: None,
            rest_rate: (2e-10f64).sqrt() * p2.sqrt() * block.alpha,
            ledger: Ledger::default(),
            counters: Counters::default(),
            peaks: Peaks {
                angular_acceleration_p2: Some(0.0),
                ..Peaks::default()
            },
        }
    }

    /// Number of state components this model needs.
    pub fn state_len(device: &DeviceModel) -> usize {
        2 + 2 * device.flywheels() + 4
    }

    /// S = sin(sα − θ), C = cos(sα − θ) (slender: S = sα − θ, C = 1).
    #[inline]
    fn sc(&self, theta: f64) -> (f64, f64) {
        let a = self.pivot * self.alpha - theta;
        match self.form {
            Equations::Exact => a.sin_cos(),
            Equations::Slender => (a, 1.0),
        }
    }

    /// Horizontal position and velocity of the centre of mass.
    #[inline]
    fn x_xdot(&self, y: &[f64]) -> (f64, f64) {
        if self.phase == Phase::Contact {
            return (0.0, 0.0);
        }
        let (s, c) = self.sc(y[0]);
        let x = match self.form {
            Equations::Exact => self.r * (self.pivot * self.sin_a - s),
            Equations::Slender => self.r * y[0],
        };
        (x, self.r * c * y[1])
    }

    fn dirac_moment(&self, theta: f64, thetadot: f64) -> f64 {
        match (self.dirac_energy, self.dirac) {
            (Some(e_ini), Some((n, _))) => {
                let r = self.restitution();
                -thetadot.signum() * 2.0 * e_ini * (1.0 - r) * (-(theta / n).powi(2)).exp()
                    / (n * PI.sqrt())
            }
            _ => 0.0,
        }
    }

    fn restitution(&self) -> f64 {
        if let Some(r) = self.restitution_override {
            return r;
        }
        let mr = self.dev.coupled_mass(self.seq_engaged);
        if mr > 0.0 {
            inerter_restitution(self.alpha, mr / self.m)
        } else {
            housner_restitution(self.alpha)
        }
    }

    /// θ̈ of the bare block (no device), used by the sequential engagement test.
    fn bare_xddot(&self, t: f64, y: &[f64]) -> f64 {
        let (s, c) = self.sc(y[0]);
        let ag = self.motion.accel(t);
        let thdd = -self.p2 * (s + ag / G * c) + self.dirac_moment(y[0], y[1]) / self.i0;
        match self.form {
            Equations::Exact => self.r * (c * thdd + s * y[1] * y[1]),
            Equations::Slender => self.r * thdd,
        }
    }

    /// Uplift test toward side s while in contact: positive when the block lifts off.
    fn uplift_margin(&self, side: f64, t: f64, y: &[f64]) -> f64 {
        let (fa, fb) = self.dev.spring_forces(0.0, &y[2..self.acc]);
        let fd = -(fa + fb);
        side * (fd - self.m * self.motion.accel(t)) - self.m * G * self.uplift_ratio
    }

    fn rhs_slice(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        dy.fill(0.0);
        let ag = self.motion.accel(t);
        let (x, xdot) = self.x_xdot(y);
        let (fa, fb) = self.dev.spring_forces(x, &y[2..self.acc]);
        let (mut visc, mut fric) = (0.0, 0.0);
        for (i, f) in [fa, fb].into_iter().take(self.dev.flywheels()).enumerate() {
            let j = 2 + 2 * i;
            let (a, pv, pf) = self.dev.flywheel_accel(f, y[j + 1]);
            dy[j] = y[j + 1];
            dy[j + 1] = a;
            visc += pv;
            fric += pf;
        }
        if self.phase == Phase::Rocking {
            let (theta, thetadot) = (y[0], y[1]);
            let (s, c) = self.sc(theta);
            let fd = -(fa + fb);
            let moment = self.dirac_moment(theta, thetadot);
            // (1 + ¾σC²) θ̈ = −p²(S + (a_g/g) C) − ¾σ C S θ̇² + (Fd R C + M)/I0
            let sigma = self.dev.coupled_mass(self.seq_engaged) / self.m;
            let mut num = -self.p2 * (s + ag / G * c) + (fd * self.r * c + moment) / self.i0;
            let mut den = 1.0;
            if sigma > 0.0 {
                den += 0.75 * sigma * c * c;
                if self.form == Equations::Exact {
                    num -= 0.75 * sigma * c * s * thetadot * thetadot;
                }
            }
            dy[0] = thetadot;
            dy[1] = num / den;
            dy[self.acc + 3] = -moment * thetadot;
        }
        dy[self.acc] = -self.m * ag * xdot;
        dy[self.acc + 1] = visc;
        dy[self.acc + 2] = fric;
    }

    fn event_value(&self, ev: Ev, t: f64, y: &[f64]) -> f64 {
        let rocking = self.phase == Phase::Rocking;
        match ev {
            Ev::Impact => {
                if rocking {
                    self.pivot * y[0]
                } else {
                    1.0
                }
            }
            Ev::Overturn => {
                if rocking {
                    self.pivot * y[0] - self.alpha
                } else {
                    -1.0
                }
            }
            Ev::Uplift(side) => {
                if rocking {
                    -1.0
                } else {
                    self.uplift_margin(side, t, y)
                }
            }
            Ev::Sequential => {
                if rocking {
                    self.x_xdot(y).1 * self.bare_xddot(t, y)
                } else if self.seq_engaged {
                    1.0
                } else {
                    -1.0
                }
            }
            Ev::DiracZone => match (rocking, self.dirac_energy) {
                (false, _) => 1.0,
                // Active: stop when the block turns back (sθ̇ becomes positive).
                (true, Some(_)) => self.pivot * y[1],
                (true, None) => self.pivot * y[0] - self.dirac.map_or(0.0, |d| d.1),
            },
            Ev::Clutch(e) => {
                let DeviceModel::Clutch(c) = &self.dev else {
                    return 1.0;
                };
                let (x, xdot) = self.x_xdot(y);
                c.event_value(e, x, xdot, &y[2..6])
            }
        }
    }

    fn coupled_kinetic(&self, y: &[f64]) -> f64 {
        let (_, xdot) = self.x_xdot(y);
        0.5 * self.dev.coupled_mass(self.seq_engaged) * xdot * xdot
    }

    /// Re-decide the sequential clutch after a jump, booking the energy the law creates or
    /// destroys.
    fn resync_sequential(&mut self, t: f64, y: &[f64]) {
        if !matches!(self.dev, DeviceModel::Sequential { .. }) || self.phase != Phase::Rocking {
            return;
        }
        let xdot = self.x_xdot(y).1;
        let bare = self.bare_xddot(t, y);
        super::device::resync_sequential(
            self.dev.mr(),
            xdot,
            bare,
            &mut self.seq_engaged,
            &mut self.ledger,
            &mut self.counters,
        );
    }

    fn toggle_sequential(&mut self, y: &[f64]) {
        let xdot = self.x_xdot(y).1;
        super::device::toggle_sequential(
            self.dev.mr(),
            xdot,
            &mut self.seq_engaged,
            &mut self.ledger,
            &mut self.counters,
        );
    }

    fn uplift(&mut self, side: f64, y: &mut [f64]) -> Action {
        self.phase = Phase::Rocking;
        self.pivot = side;
        y[0] = 0.0;
        y[1] = 0.0;
        self.counters.uplifts += 1;
        // Starting from rest, |ẋ| grows: the sequential clutch engages (at ẋ = 0, no energy).
        if matches!(self.dev, DeviceModel::Sequential { .. }) {
            self.seq_engaged = true;
            self.counters.engagements += 1;
        }
        Action::Continue
    }

    fn enter_contact(&mut self, t: f64, y: &mut [f64]) -> Action {
        let ke = 0.5 * self.i0 * y[1] * y[1] + self.coupled_kinetic(y);
        self.ledger.reset += ke;
        if self.seq_engaged {
            self.seq_engaged = false;
        }
        self.phase = Phase::Contact;
        self.dirac_energy = None;
        y[0] = 0.0;
        y[1] = 0.0;
        for side in [1.0, -1.0] {
            if self.uplift_margin(side, t, y) > 0.0 {
                return self.uplift(side, y);
            }
        }
        if !self.device_at_rest(t, y) {
            return Action::Continue;
        }
        // Nothing moves until the ground acceleration exceeds g·tanα: do not integrate (an
        // integrator stepping over the record's samples could step over the crossing). Idle to
        // the end of the motion if it never does (the block still rides the ground).
        let until = self
            .motion
            .first_exceedance(t, G * self.uplift_ratio)
            .unwrap_or_else(|| self.motion.end().max(t));
        Action::Idle { until }
    }

    /// On the ground, whether the device holds still and unloaded (flywheels at rest, springs
    /// slack: every flywheel derivative exactly zero), so nothing moves until the ground
    /// lifts the block.
    fn device_at_rest(&self, t: f64, y: &[f64]) -> bool {
        let mut dy = [0.0; 16];
        let dy = &mut dy[..y.len()];
        self.rhs_slice(t, y, dy);
        dy[2..self.acc].iter().all(|d| *d == 0.0)
    }

    /// Apply the jump of one event.
    fn apply_event(&mut self, index: usize, t: f64, y: &mut [f64]) -> Action {
        match self.events[index] {
            // A crossing of θ = 0 while the block moves onto its pivot's side is no impact.
            // Right after an uplift from rest (θ = θ̇ = 0, θ̈ ≈ 0 at the threshold) the
            // interpolant of a long step can sit at roundoff level (|θ| ~ 1e-30) on the wrong
            // side; booking that as an impact put the block back to rest and the next step
            // found the same crossing again, forever. Snap onto the pivot's side instead.
            Ev::Impact if self.pivot * y[1] > 0.0 => {
                y[0] = 0.0;
                Action::Continue
            }
            Ev::Impact => {
                self.counters.impacts += 1;
                if self.dirac.is_some() {
                    // The Gaussian moment already took the energy: switch pivots only.
                    self.dirac_energy = None;
                } else {
                    let r = self.restitution();
                    let ke = 0.5 * self.i0 * y[1] * y[1] + self.coupled_kinetic(y);
                    self.ledger.impact += (1.0 - r) * ke;
                    y[1] *= r.sqrt();
                }
                y[0] = 0.0;
                self.pivot = -self.pivot;
                if y[1].abs() < self.rest_rate {
                    return self.enter_contact(t, y);
                }
                self.resync_sequential(t, y);
                Action::Continue
            }
            Ev::Overturn => Action::Stop(EndReason::Overturned),
            Ev::Uplift(side) => self.uplift(side, y),
            Ev::Sequential => {
                self.toggle_sequential(y);
                Action::Continue
            }
            Ev::DiracZone => {
                self.dirac_energy = match self.dirac_energy {
                    Some(_) => None,
                    None => Some(0.5 * self.i0 * y[1] * y[1]),
                };
                Action::Continue
            }
            Ev::Clutch(e) => {
                if let DeviceModel::Clutch(c) = self.dev {
                    let (x, _) = self.x_xdot(y);
                    c.apply(e, x, &mut y[2..6], &mut self.ledger, &mut self.counters);
                }
                Action::Continue
            }
        }
    }

    fn absolute_acceleration(&self, t: f64, y: &[f64], dy: &[f64]) -> f64 {
        let ag = self.motion.accel(t);
        if self.phase == Phase::Contact {
            return ag;
        }
        let (s, c) = self.sc(y[0]);
        let xddot = match self.form {
            Equations::Exact => self.r * (c * dy[1] + s * y[1] * y[1]),
            Equations::Slender => self.r * dy[1],
        };
        xddot + ag
    }

    /// |θ̈| / p² from the equations of motion at (t, y): zero on the ground; the Dirac impact
    /// moment included.
    fn angular_acceleration_p2(&self, t: f64, y: &[f64]) -> f64 {
        if self.phase != Phase::Rocking {
            return 0.0;
        }
        let mut dy = [0.0; 16];
        let dy = &mut dy[..y.len()];
        self.rhs_slice(t, y, dy);
        dy[1].abs() / self.p2
    }

    fn peak_angular_acceleration_p2(&self) -> f64 {
        self.peaks.angular_acceleration_p2.unwrap_or(0.0)
    }

    fn drift_of(&self, theta: f64) -> f64 {
        let x = match self.form {
            Equations::Exact => self.r * (self.sin_a - (self.alpha - theta.abs()).sin()),
            Equations::Slender => self.r * theta.abs(),
        };
        x / (self.r * self.cos_a)
    }

    fn device_force(&self, t: f64, y: &[f64]) -> (f64, f64, f64) {
        let (x, _) = self.x_xdot(y);
        let (fa, fb) = self.dev.spring_forces(x, &y[2..self.acc]);
        let mr = self.dev.coupled_mass(self.seq_engaged);
        if mr > 0.0 && self.phase == Phase::Rocking {
            let mut dy = vec![0.0; y.len()];
            self.rhs_slice(t, y, &mut dy);
            let (s, c) = self.sc(y[0]);
            let xddot = match self.form {
                Equations::Exact => self.r * (c * dy[1] + s * y[1] * y[1]),
                Equations::Slender => self.r * dy[1],
            };
            return (0.0, 0.0, -mr * xddot);
        }
        (fa, fb, -(fa + fb))
    }
}

impl<const N: usize> OdeSystem<N> for RigidModel<'_> {
    #[inline]
    fn rhs(&self, t: f64, y: &[f64; N], dydt: &mut [f64; N]) {
        self.rhs_slice(t, y, dydt)
    }

    fn event_count(&self) -> usize {
        self.n_events
    }

    fn event_direction(&self, index: usize) -> Direction {
        match self.events[index] {
            Ev::Impact => Direction::Falling,
            Ev::Overturn | Ev::Uplift(_) => Direction::Rising,
            Ev::Clutch(e) => e.direction(),
            Ev::Sequential if self.seq_engaged => Direction::Falling,
            Ev::Sequential => Direction::Rising,
            Ev::DiracZone if self.dirac_energy.is_some() => Direction::Rising,
            Ev::DiracZone => Direction::Falling,
        }
    }

    fn events(&self, t: f64, y: &[f64; N], g: &mut [f64]) {
        for (i, gi) in g.iter_mut().enumerate() {
            *gi = self.event_value(self.events[i], t, y);
        }
    }

    /// Inside an active Dirac zone: a step may rotate the block by at most n/2 at its entry
    /// rate (the zone's θi = 1.82 n takes ≥ 4 steps; the rate only falls inside it). Without
    /// this a step sized before the zone, whose stages land past the Gaussian, crossed θ = 0
    /// with the moment unseen by its error estimate and the impact's energy loss went missing
    /// at rtol ≥ 1e-5 (θmax/α 0.505 instead of 0.470 in the paper's Fig. 5 scene).
    fn max_step(&self) -> f64 {
        match (self.dirac_energy, self.dirac) {
            (Some(e_ini), Some((n, _))) if e_ini > 0.0 => 0.5 * n / (2.0 * e_ini / self.i0).sqrt(),
            _ => f64::INFINITY,
        }
    }

    fn sign_after_zero(&self, index: usize, _t: f64, y: &[f64; N]) -> f64 {
        match self.events[index] {
            // At uplift from rest (θ = θ̇ = 0) θ̈ is zero at the threshold, up to roundoff, so
            // the first stretch of the first step may sit at |θ| ~ 1e-30 on either side:
            // undetermined (the first sub-sample's sign is adopted), or that roundoff is taken
            // for an impact at the uplift instant, again and again.
            Ev::Impact if y[1] == 0.0 => 0.0,
            // Just after an impact the block moves onto its pivot's side.
            Ev::Impact => (self.pivot * y[1]).signum(),
            _ => 0.0,
        }
    }
}

impl<const N: usize> SimModel<N> for RigidModel<'_> {
    fn start(&mut self, y: &mut [f64; N]) -> Action {
        if self.initial_rotation != 0.0 {
            self.phase = Phase::Rocking;
            self.pivot = self.initial_rotation.signum();
            y[0] = self.initial_rotation;
            // Flywheels start at rest where the block is: unloaded springs.
            let (x, _) = self.x_xdot(y);
            for j in (2..self.acc).step_by(2) {
                y[j] = x;
            }
            return Action::Continue;
        }
        self.enter_contact(0.0, y)
    }

    fn on_event(&mut self, index: usize, t: f64, y: &mut [f64; N]) -> Action {
        let action = self.apply_event(index, t, y);
        // Two events can fall within the root finder's last bracket (~1e-15 s); the one not
        // reported then already sits on its post-crossing side. Catch overturning and landing.
        if action == Action::Continue && self.phase == Phase::Rocking {
            if self.pivot * y[0] >= self.alpha {
                return Action::Stop(EndReason::Overturned);
            }
            if self.pivot * y[0] < 0.0 {
                let impact = self.events[..self.n_events]
                    .iter()
                    .position(|e| *e == Ev::Impact);
                return self.apply_event(impact.expect("impact is always an event"), t, y);
            }
        }
        action
    }

    fn wake(&mut self, t: f64, y: &mut [f64; N]) -> Action {
        let ag = self.motion.accel(t);
        if ag.abs() <= G * self.uplift_ratio {
            return Action::Stop(EndReason::Rest);
        }
        self.uplift(-ag.signum(), y)
    }

    fn events_read_ground(&self) -> bool {
        // The uplift margins compare a_g with g·tanα.
        self.phase == Phase::Contact
    }

    fn wake_name(&self) -> &'static str {
        "uplift"
    }

    fn at_rest(&self, _t: f64, _y: &[f64; N]) -> bool {
        // In contact after the ground stopped, a flywheel can only spin down and drift away
        // from engagement (its velocity never changes sign), so nothing can move the block.
        self.phase == Phase::Contact
    }

    /// After the ground stops, the block can only draw on its own energy plus what the device
    /// can give back: a coupled or spring-mounted inerter returns its kinetic energy, a
    /// one-way clutch only its spring energy (its flywheel can only brake the block), and the
    /// sequential law none (its mass's energy is lost at every disengagement). From that energy
    /// E: reachable |θ| from PE(θ) ≤ E, and |ẍ| ≤ R(p² s_max + |Fd|max R/I0 + (1 + ¾σ) s_max θ̇²max)
    /// with θ̇²max = 2E/I0 and |Fd|max = 2√(2kE). The Dirac model is excluded (its impact moment
    /// is the acceleration being studied).
    fn settled(&self, y: &[f64; N]) -> bool {
        if self.dirac.is_some() || self.phase != Phase::Rocking {
            return false;
        }
        let (s, c) = self.sc(y[0]);
        let pe = match self.form {
            Equations::Exact => self.m * G * self.r * (c - self.cos_a),
            Equations::Slender => 0.5 * self.m * G * self.r * (self.alpha.powi(2) - s * s),
        };
        let block = 0.5 * self.i0 * y[1] * y[1] + pe;
        let (x, _) = self.x_xdot(y);
        let fly = &y[2..self.acc];
        let (returnable, k) = match self.dev {
            DeviceModel::None | DeviceModel::Sequential { .. } => (0.0, 0.0),
            DeviceModel::Coupled { .. } => (self.coupled_kinetic(y), 0.0),
            DeviceModel::Spring { k, .. } => (self.dev.stored_energy(x, fly), k),
            DeviceModel::Clutch(c) => (
                self.dev.clutch_potential_a(x - fly[0]).max(0.0)
                    + self.dev.clutch_potential_b(x - fly[2]).max(0.0),
                c.k,
            ),
        };
        let e = block + returnable;
        let mgr = self.m * G * self.r;
        let reach = match self.form {
            Equations::Exact => {
                let c_min = self.cos_a + e / mgr;
                if c_min >= 1.0 {
                    return false;
                }
                self.alpha - c_min.acos()
            }
            Equations::Slender => {
                let d = self.alpha.powi(2) - 2.0 * e / mgr;
                if d <= 0.0 {
                    return false;
                }
                self.alpha - d.sqrt()
            }
        };
        let s_max = match self.form {
            Equations::Exact => self.sin_a,
            Equations::Slender => self.alpha,
        };
        let sigma = self.dev.mr() / self.m;
        let rate2 = 2.0 * e / self.i0;
        let force = 2.0 * (2.0 * k * e).sqrt();
        let accel = self.r
            * (self.p2 * s_max + force * self.r / self.i0 + (1.0 + 0.75 * sigma) * s_max * rate2)
            / G;
        // |θ̈| ≤ p² s_max + |Fd|max R/I0 + ¾σ s_max θ̇²max with the ground at rest.
        let angular = s_max + (force * self.r / self.i0 + 0.75 * sigma * s_max * rate2) / self.p2;
        reach < self.peaks.rotation
            && accel < self.peaks.abs_acceleration_g
            && angular < self.peak_angular_acceleration_p2()
    }

    fn observe_step(&mut self, dense: &Dense<N>, t_end: f64) {
        if self.phase == Phase::Rocking {
            let rot = extremum_on_step(dense, t_end, 0, 1);
            self.peaks.rotation = self.peaks.rotation.max(rot);
            self.peaks.drift = self.peaks.drift.max(self.drift_of(rot));
            let floor = self.peak_angular_acceleration_p2();
            let theta_dd = |t: f64| self.angular_acceleration_p2(t, &dense.state(t));
            let peak = refined_max(theta_dd, dense.t0, t_end, 4, floor);
            self.peaks.angular_acceleration_p2 = Some(floor.max(peak));
        }
        let accel_g = |t: f64| {
            self.absolute_acceleration(t, &dense.state(t), &dense.derivative(t))
                .abs()
                / G
        };
        let peak = refined_max(accel_g, dense.t0, t_end, 4, self.peaks.abs_acceleration_g);
        self.peaks.abs_acceleration_g = self.peaks.abs_acceleration_g.max(peak);
    }

    fn observe_point(&mut self, t: f64, y: &[f64; N]) {
        let mut dy = [0.0; N];
        self.rhs_slice(t, y, &mut dy);
        self.peaks.rotation = self.peaks.rotation.max(y[0].abs());
        self.peaks.drift = self.peaks.drift.max(self.drift_of(y[0]));
        let a = self.absolute_acceleration(t, y, &dy);
        self.peaks.abs_acceleration_g = self.peaks.abs_acceleration_g.max(a.abs() / G);
        // After a jump this is the one-sided value just past it (the jump itself excluded).
        let theta_dd = self.angular_acceleration_p2(t, y);
        self.peaks.angular_acceleration_p2 =
            Some(self.peak_angular_acceleration_p2().max(theta_dd));
    }

    fn observe_idle(&mut self, t0: f64, t1: f64) {
        let a = self.motion.peak_abs(t0, t1);
        self.peaks.abs_acceleration_g = self.peaks.abs_acceleration_g.max(a / G);
    }

    fn energy(&self, y: &[f64; N]) -> Energy {
        let acc = self.acc;
        let structure = if self.phase == Phase::Rocking {
            let (s, c) = self.sc(y[0]);
            let pe = match self.form {
                Equations::Exact => self.m * G * self.r * (c - self.cos_a),
                Equations::Slender => 0.5 * self.m * G * self.r * (self.alpha.powi(2) - s * s),
            };
            0.5 * self.i0 * y[1] * y[1] + pe
        } else {
            0.0
        };
        let (x, _) = self.x_xdot(y);
        Energy {
            input: y[acc],
            structure,
            inerter: self.coupled_kinetic(y) + self.dev.stored_energy(x, &y[2..acc]),
            column_damping: 0.0,
            device_damping: y[acc + 1],
            friction: y[acc + 2],
            impact: self.ledger.impact + y[acc + 3],
            disengagement: self.ledger.disengagement,
            reset: self.ledger.reset,
        }
    }

    fn peaks(&self) -> Peaks {
        self.peaks
    }

    fn counters(&self) -> Counters {
        self.counters
    }

    fn event_name(&self, index: usize) -> &'static str {
        match self.events[index] {
            Ev::Impact => "impact",
            Ev::Overturn => "overturn",
            Ev::Uplift(_) => "uplift",
            Ev::Sequential => "sequential_switch",
            Ev::DiracZone => "dirac_zone",
            Ev::Clutch(e) => e.name(),
        }
    }

    fn history_columns(&self) -> Vec<&'static str> {
        vec![
            "t",
            "theta",
            "theta_dot",
            "ground_accel",
            "x",
            "flywheel_a_vel",
            "flywheel_b_vel",
            "clutch_force_a",
            "clutch_force_b",
            "device_force",
            "e_input",
            "e_structure",
            "e_inerter",
            "e_dissipated",
        ]
    }

    fn history_row(&self, t: f64, y: &[f64; N]) -> Vec<f64> {
        let (x, _) = self.x_xdot(y);
        let nf = self.dev.flywheels();
        let va = if nf >= 1 { y[3] } else { 0.0 };
        let vb = if nf >= 2 { y[5] } else { 0.0 };
        let (fa, fb, fd) = self.device_force(t, y);
        let e = SimModel::<N>::energy(self, y);
        vec![
            t,
            y[0],
            y[1],
            self.motion.accel(t),
            x,
            va,
            vb,
            fa,
            fb,
            fd,
            e.input,
            e.structure,
            e.inerter,
            e.dissipated(),
        ]
    }
}
