//! The rocking shell: everything a rocking structure with an inerter device does the same way
//! whatever the structure is. The device's states, the event table (impact, overturning,
//! uplift to either side, the device's switch and its own events), the phase (flat on the
//! ground or rocking) and the pivot, the device switch's state, the
//! energy ledger, the peaks, and the [`OdeSystem`] and [`SimModel`] plumbing.
//!
//! A structure family implements [`Body`]: its kinematics (the horizontal coordinate X the
//! device acts on), its accelerations, the uplift and overturning tests, the impact jump and
//! its own energy. [`super::rigid`] and [`super::flexible`] are the two bodies.

// The shell is one state machine (events, phase, pivot, peaks, energy ledger) whose parts read
// and write the same state; split along its seams: the state layout (`layout`), what a body
// supplies (`body`), and the solver and driver interfaces (`systems`).

mod body;
mod layout;
mod systems;
#[cfg(test)]
mod tests;

pub use body::{Body, Landing, Mode, OwnLoss};
pub use layout::{Accumulator, Layout, Phase};

use super::device::{ClutchEvent, DeviceModel, Returnable};
use super::{Action, Counters, EndReason, Energy, Ledger, Measures, Peaks};
use crate::excitation::Motion;
use crate::solver::MAX_EVENTS;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Ev {
    Impact,
    Overturn,
    Uplift(f64),
    /// The device's switch ([`DeviceModel::has_switch`]).
    Switch,
    Own(usize),
    /// An event of the device's own states ([`DeviceModel::events`]).
    Device(ClutchEvent),
}

/// Largest state a rocking model has (flexible structure with two device degrees of freedom).
const MAX_STATE: usize = 16;

/// A rocking structure `B` with its device: the model the simulation driver runs.
pub struct Rocking<'m, B: Body> {
    pub(super) body: B,
    pub(super) mode: Mode<'m>,
    initial_rotation: f64,
    events: [Ev; MAX_EVENTS],
    n_events: usize,
    /// Whether an event function reads X or Ẋ (the device's switch and events).
    events_read_x: bool,
    measures: Measures,
    /// Time of the last uplift, to recognise a grazing lift-off that lands at once.
    last_uplift: f64,
    pub(super) ledger: Ledger,
    counters: Counters,
    peaks: Peaks,
}

impl<'m, B: Body> Rocking<'m, B> {
    pub fn with_body(
        body: B,
        device: DeviceModel,
        motion: &'m Motion,
        initial_rotation: f64,
    ) -> Self {
        let peaks = Peaks {
            angular_acceleration_p2: body.angular_acceleration_scale().map(|_| 0.0),
            ..Peaks::default()
        };
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
        if device.has_switch() {
            push(Ev::Switch);
        }
        for i in 0..body.own_events() {
            push(Ev::Own(i));
        }
        for e in device.events() {
            push(Ev::Device(*e));
        }
        Rocking {
            body,
            mode: Mode {
                dev: device,
                motion,
                layout: Layout::new(B::COORDINATES.len(), &device),
                phase: Phase::Contact,
                pivot: 1.0,
                switch_engaged: false,
            },
            initial_rotation,
            events,
            n_events: n,
            events_read_x: events[..n]
                .iter()
                .any(|e| matches!(e, Ev::Switch | Ev::Device(_))),
            measures: Measures::ALL,
            last_uplift: f64::NEG_INFINITY,
            ledger: Ledger::default(),
            counters: Counters::default(),
            peaks,
        }
    }

    /// Compute only these measures (default: all); call before the run starts.
    pub fn set_measures(&mut self, measures: Measures) {
        self.measures = measures;
        if !measures.angular_acceleration {
            self.peaks.angular_acceleration_p2 = None;
        }
    }

    /// Integrate the energy accumulators (the default) or not: a run that neither reports the
    /// energy nor records a history leaves them out. They are no part of the error norm, so
    /// the steps, and every other result, are the same either way. Call before the run (and
    /// before anything that reads the layout, as the flexible structure's closed-form
    /// contact).
    pub fn with_ledger(mut self, ledger: bool) -> Self {
        self.mode.layout.ledger = ledger;
        self
    }

    /// Number of state components this model needs.
    pub fn state_len(&self) -> usize {
        self.mode.layout.state_len()
    }

    fn x_xdot(&self, y: &[f64]) -> (f64, f64) {
        self.body.x_xdot(&self.mode, y)
    }

    fn rhs_slice(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let k = self.body.kin(&self.mode, y);
        self.rhs_kin(t, y, &k, dy)
    }

    /// The right-hand side at (t, y) whose kinematics `k` are already known.
    #[inline]
    fn rhs_kin(&self, t: f64, y: &[f64], k: &B::Kin, dy: &mut [f64]) {
        dy.fill(0.0);
        let m = &self.mode;
        let layout = m.layout;
        let ag = m.motion.accel(t);
        let gravity = m.motion.gravity();
        let g_eff = gravity.at(t);
        let (x, xdot) = self.body.x_xdot_kin(m, k, y);
        let device = m
            .dev
            .rates(x, layout.device_states(y), layout.device_states_mut(dy));
        let own = self
            .body
            .derivatives(m, k, ag, g_eff, y, device.force, m.coupled_mass(), dy);
        if layout.ledger {
            let a = layout.physical_len();
            // The ground's work in its own frame: −m a_g Ẋ, and −m ü_v Ẏ with a vertical
            // motion (the structure's potential energy is booked with the constant g).
            let mut input = -self.body.mass() * ag * xdot;
            if g_eff != gravity.g() {
                let uv = g_eff - gravity.g();
                input -= self.body.mass() * uv * self.body.y_dot_kin(m, k, y);
            }
            let acc = &mut dy[a..a + 4];
            acc[Accumulator::Input as usize] = input;
            acc[Accumulator::DeviceDamping as usize] = device.damping;
            acc[Accumulator::Friction as usize] = device.friction;
            acc[Accumulator::Own as usize] = own;
        }
    }

    /// Event `ev`'s value at (t, y); `kx` = (kin(y), (X, Ẋ)) when the caller has them.
    #[inline(always)]
    fn event_value(&self, ev: Ev, t: f64, y: &[f64], kx: Option<&(B::Kin, (f64, f64))>) -> f64 {
        let m = &self.mode;
        let rocking = m.rocking();
        let kx = || match kx {
            Some(v) => *v,
            None => {
                let k = self.body.kin(m, y);
                (k, self.body.x_xdot_kin(m, &k, y))
            }
        };
        match ev {
            Ev::Impact if rocking => m.pivot * y[B::THETA],
            Ev::Impact => 1.0,
            Ev::Overturn if rocking => self.body.overturn_margin(m, y),
            Ev::Overturn => -1.0,
            Ev::Uplift(_) if rocking => -1.0,
            Ev::Uplift(side) => self.body.uplift_margin(m, side, t, y),
            Ev::Switch if rocking || B::MOVES_IN_CONTACT => {
                let (k, (_, xdot)) = kx();
                xdot * self.body.bare_xddot(m, &k, t, y)
            }
            // X ≡ 0 while flat: the switch keeps its side until the base lifts.
            Ev::Switch if m.switch_engaged => 1.0,
            Ev::Switch => -1.0,
            Ev::Own(i) => self.body.own_event_value(m, i, y),
            Ev::Device(e) => {
                let (_, (x, xdot)) = kx();
                m.dev.event_value(e, x, xdot, m.layout.device_states(y))
            }
        }
    }

    /// Re-decide the device's switch after a jump or a phase change (Ẋ is continuous across
    /// both, Ẍ is not), booking the energy the law creates or destroys.
    fn resync_switch(&mut self, t: f64, y: &[f64]) {
        if !self.mode.dev.has_switch() {
            return;
        }
        let k = self.body.kin(&self.mode, y);
        let xdot = self.body.x_xdot_kin(&self.mode, &k, y).1;
        let bare = self.body.bare_xddot(&self.mode, &k, t, y);
        self.mode.dev.resync_switch(
            xdot,
            bare,
            &mut self.mode.switch_engaged,
            &mut self.ledger,
            &mut self.counters,
        );
    }

    /// From rest |Ẋ| can only grow: the device's switch engages (at Ẋ = 0, no energy).
    fn engage_switch_from_rest(&mut self) {
        if self.mode.dev.has_switch() {
            self.mode.switch_engaged = true;
            self.counters.engagements += 1;
        }
    }

    fn uplift(&mut self, side: f64, t: f64, y: &mut [f64]) -> Action {
        self.mode.phase = Phase::Rocking;
        self.mode.pivot = side;
        y[B::THETA] = 0.0;
        y[B::THETA_DOT] = 0.0;
        self.last_uplift = t;
        self.counters.uplifts += 1;
        if !self.mode.switch_engaged && self.x_xdot(y).1 == 0.0 {
            self.engage_switch_from_rest();
        } else {
            self.resync_switch(t, y);
        }
        Action::Continue
    }

    /// The base comes down flat at t: it lifts again at once if the ground asks for it,
    /// otherwise it stays in full contact (idle, if nothing moves).
    fn land(&mut self, t: f64, y: &mut [f64]) -> Action {
        self.mode.phase = Phase::Contact;
        // A lift-off that landed within roundoff of its start (the margin was positive but
        // already falling) would lift and land again forever at the same instant: stay down,
        // the margin is on its way below zero.
        let grazing = t - self.last_uplift <= 1e-12 * t.abs().max(1.0);
        for side in [1.0, -1.0] {
            if !grazing && self.body.uplift_margin(&self.mode, side, t, y) > 0.0 {
                return self.uplift(side, t, y);
            }
        }
        self.resync_switch(t, y);
        match self.body.idle_until(&self.mode, t) {
            Some(until) if self.device_at_rest(t, y) => Action::Idle { until },
            _ => Action::Continue,
        }
    }

    /// Whether the device holds still and unloaded (flywheels at rest, springs slack: every
    /// flywheel derivative exactly zero). Only then may a body that does not move in contact
    /// idle to the ground's exceedance instead of integrating the resting phase (stepping over
    /// a record's samples, that integration stepped over the uplift).
    fn device_at_rest(&self, t: f64, y: &[f64]) -> bool {
        let layout = self.mode.layout;
        if layout.device_dofs == 0 {
            return true;
        }
        let mut dy = [0.0; MAX_STATE];
        let dy = &mut dy[..y.len()];
        self.rhs_slice(t, y, dy);
        layout.device_states(dy).iter().all(|d| *d == 0.0)
    }

    fn impact(&mut self, t: f64, y: &mut [f64]) -> Action {
        self.counters.impacts += 1;
        match self.body.impact(&mut self.mode, &mut self.ledger, y) {
            Landing::Rocking => {
                self.resync_switch(t, y);
                Action::Continue
            }
            Landing::Flat => self.land(t, y),
        }
    }

    /// The jump of event `index` at t.
    fn apply_event(&mut self, index: usize, t: f64, y: &mut [f64]) -> Action {
        match self.events[index] {
            Ev::Impact => self.impact(t, y),
            Ev::Overturn => Action::Stop(EndReason::Overturned),
            Ev::Uplift(side) => self.uplift(side, t, y),
            Ev::Switch => {
                let xdot = self.x_xdot(y).1;
                self.mode.dev.toggle_switch(
                    xdot,
                    &mut self.mode.switch_engaged,
                    &mut self.ledger,
                    &mut self.counters,
                );
                Action::Continue
            }
            Ev::Own(i) => {
                self.body.apply_own_event(i, y);
                Action::Continue
            }
            Ev::Device(e) => {
                let (x, _) = self.x_xdot(y);
                let states = self.mode.layout.device_states_mut(y);
                let dev = self.mode.dev;
                dev.apply_event(e, x, states, &mut self.ledger, &mut self.counters);
                Action::Continue
            }
        }
    }

    /// Two events can fall within the location tolerance of each other (the sequential clutch
    /// switches where Ẍ = 0, which is exactly where a flexible structure's mass passes over
    /// the pivot). The located one is returned on its post-crossing side, possibly past the
    /// other's root, and a function already past its root at a restart never reports the
    /// crossing: catch up with overturning and landing here.
    fn catch_up(&mut self, action: Action, t: f64, y: &mut [f64]) -> Action {
        if action != Action::Continue || !self.mode.rocking() {
            return action;
        }
        if self.body.overturn_margin(&self.mode, y) >= 0.0 {
            return Action::Stop(EndReason::Overturned);
        }
        if self.mode.pivot * y[B::THETA] < 0.0 {
            return self.impact(t, y);
        }
        action
    }

    /// Energy the device can still give back once the ground has stopped
    /// ([`DeviceModel::returnable`]).
    fn returnable(&self, y: &[f64]) -> Returnable {
        let (x, xdot) = self.x_xdot(y);
        let m = &self.mode;
        m.dev.returnable(x, xdot, m.layout.device_states(y))
    }

    fn absolute_acceleration(&self, t: f64, k: &B::Kin, y: &[f64], dy: &[f64]) -> f64 {
        self.body.xddot(&self.mode, k, y, dy) + self.mode.motion.accel(t)
    }

    /// |absolute acceleration|/g (`dy` the interpolant's rates) and |θ̈|/p² (from the
    /// right-hand side, 0 while flat) at (t, y), sharing the kinematics; each only if asked.
    fn accelerations_at<const N: usize>(
        &self,
        t: f64,
        y: &[f64; N],
        dy: Option<&[f64; N]>,
        angular: bool,
    ) -> (f64, f64) {
        let k = self.body.kin(&self.mode, y);
        let abs_g = dy.map_or(0.0, |dy| {
            self.absolute_acceleration(t, &k, y, dy).abs() / self.mode.motion.gravity().g()
        });
        let theta_dd = match self.body.angular_acceleration_scale() {
            Some(p2) if angular && self.mode.rocking() => {
                let mut d = [0.0; N];
                self.rhs_kin(t, y, &k, &mut d);
                d[B::THETA_DOT].abs() / p2
            }
            _ => 0.0,
        };
        (abs_g, theta_dd)
    }

    /// Clutch forces (f_a, f_b) and the device force Fd; a coupled mass pushes with −mc Ẍ.
    fn device_force(&self, t: f64, y: &[f64]) -> (f64, f64, f64) {
        let (x, _) = self.x_xdot(y);
        let (fa, fb) = self
            .mode
            .dev
            .spring_forces(x, self.mode.layout.device_states(y));
        let mc = self.mode.coupled_mass();
        if mc > 0.0 {
            let mut dy = vec![0.0; y.len()];
            let k = self.body.kin(&self.mode, y);
            self.rhs_kin(t, y, &k, &mut dy);
            return (0.0, 0.0, -mc * self.body.xddot(&self.mode, &k, y, &dy));
        }
        (fa, fb, -(fa + fb))
    }

    fn energy_of(&self, y: &[f64]) -> Energy {
        let m = &self.mode;
        let layout = m.layout;
        let (x, xdot) = self.x_xdot(y);
        // Without the ledger only the stored energies are known (what a run that does not
        // report the energy reads: the initial stored energy).
        let acc = |which| layout.accumulator(which).map_or(0.0, |i| y[i]);
        let own = acc(Accumulator::Own);
        let (column_damping, impact) = match B::OWN_LOSS {
            OwnLoss::Impact => (0.0, self.ledger.impact + own),
            OwnLoss::ColumnDamping => (own, self.ledger.impact),
        };
        Energy {
            input: acc(Accumulator::Input),
            structure: self.body.energy(m, y),
            inerter: m.coupled_kinetic(xdot) + m.dev.stored_energy(x, layout.device_states(y)),
            column_damping,
            device_damping: acc(Accumulator::DeviceDamping),
            friction: acc(Accumulator::Friction),
            impact,
            disengagement: self.ledger.disengagement,
            reset: self.ledger.reset,
        }
    }
}
