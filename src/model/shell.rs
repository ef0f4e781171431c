//! The rocking shell: everything a rocking structure with an inerter device does the same way
//! whatever the structure is. The device and its flywheels, the event table (impact,
//! overturning, uplift to either side, the sequential switch, the mechanistic clutch events),
//! the phase (flat on the ground or rocking) and the pivot, the sequential clutch's state, the
//! energy ledger, the peaks, and the [`OdeSystem`] and [`SimModel`] plumbing.
//!
//! A structure family implements [`Body`]: its kinematics (the horizontal coordinate X the
//! device acts on), its accelerations, the uplift and overturning tests, the impact jump and
//! its own energy. [`super::rigid`] and [`super::flexible`] are the two bodies.

// Over 800 lines on purpose: the shell is one state machine (events, phase, pivot, peaks,
// energy ledger) whose parts read and write the same state; split it only along a new seam.

use super::device::{ClutchEvent, DeviceModel, resync_sequential, toggle_sequential};
use super::rigid::below_peak;
use super::{
    Action, ClosedFormEnd, Counters, EndReason, Energy, Ledger, Measures, Peaks, SimModel,
    refine_sampled,
};
use crate::excitation::{G, Motion};
use crate::solver::{Dense, Direction, MAX_EVENTS, OdeSystem};

/// Whether the base is flat on the ground or rocking about a corner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Base flat on the ground: θ ≡ 0.
    Contact,
    Rocking,
}

/// Where each part of the state lives:
/// `[structure coordinates and rates | flywheels (y, ẏ each) | accumulators]`.
/// The four accumulators are named by [`Accumulator`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Number of structure coordinates and rates (the leading components).
    pub coordinates: usize,
    pub flywheels: usize,
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
            flywheels: device.flywheels(),
        }
    }

    /// Number of state components.
    pub fn state_len(&self) -> usize {
        self.coordinates + 2 * self.flywheels + 4
    }

    /// Index of flywheel i's position (its velocity follows it).
    pub fn flywheel(&self, i: usize) -> usize {
        self.coordinates + 2 * i
    }

    /// The flywheel states `[y_a, ẏ_a, y_b, ẏ_b]` (as many as the device has).
    pub fn flywheel_states<'y>(&self, y: &'y [f64]) -> &'y [f64] {
        &y[self.coordinates..self.flywheel(self.flywheels)]
    }

    pub fn flywheel_states_mut<'y>(&self, y: &'y mut [f64]) -> &'y mut [f64] {
        &mut y[self.coordinates..self.flywheel(self.flywheels)]
    }

    pub fn accumulator(&self, which: Accumulator) -> usize {
        self.flywheel(self.flywheels) + which as usize
    }

    /// Velocity of flywheel i, 0 if the device has no such flywheel (for histories).
    fn flywheel_velocity(&self, y: &[f64], i: usize) -> f64 {
        if i < self.flywheels {
            y[self.flywheel(i) + 1]
        } else {
            0.0
        }
    }
}

/// The discrete mode the body's equations depend on, plus what they need of the device and
/// the ground.
pub struct Mode<'m> {
    pub dev: DeviceModel,
    pub motion: &'m Motion,
    pub layout: Layout,
    pub phase: Phase,
    /// s = ±1: the corner the base rocks about (θ > 0 rocks about x = +B).
    pub pivot: f64,
    pub sequential_engaged: bool,
}

impl Mode<'_> {
    pub fn rocking(&self) -> bool {
        self.phase == Phase::Rocking
    }

    /// Apparent mass rigidly attached to X right now.
    pub fn coupled_mass(&self) -> f64 {
        self.dev.coupled_mass(self.sequential_engaged)
    }

    /// Kinetic energy of the coupled mass at Ẋ.
    pub fn coupled_kinetic(&self, xdot: f64) -> f64 {
        0.5 * self.coupled_mass() * xdot * xdot
    }
}

/// What the last accumulator of the state integrates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OwnLoss {
    /// Work of the rigid block's Dirac impact moment (booked with the impacts).
    Impact,
    /// Viscous damping of the flexible column, ∫ c u̇² dt.
    ColumnDamping,
}

/// How an impact ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Landing {
    /// Rocking on about the other corner.
    Rocking,
    /// Base flat on the ground.
    Flat,
}

/// Energy the device can still give back to the structure once the ground has stopped
/// (see [`Rocking::returnable`]), and the springs through which it can push.
#[derive(Clone, Copy, Debug)]
pub struct Returnable {
    pub energy: f64,
    /// Stiffness of the device springs (0 without).
    pub k: f64,
    /// Number of springs that can push on the structure.
    pub springs: f64,
}

/// What a structure family supplies to the rocking shell. `m` is the shell's [`Mode`]; `y`
/// the whole state, whose leading [`Body::COORDINATES`] components are the body's.
pub trait Body {
    /// Trigonometry and kinematics of one configuration, computed once per sample and shared
    /// by the right-hand side, the event functions and the peak searches that need them.
    type Kin: Copy;
    /// History names of the body's state components, in state order.
    const COORDINATES: &'static [&'static str];
    /// Indices of θ and θ̇ in the state.
    const THETA: usize;
    const THETA_DOT: usize;
    /// Whether X moves while the base is flat (a flexible column vibrates; a rigid block rides
    /// the ground, so X ≡ 0 and nothing moves until it lifts).
    const MOVES_IN_CONTACT: bool;
    const OWN_LOSS: OwnLoss;

    /// The mass the ground's inertial load acts on.
    fn mass(&self) -> f64;
    /// The shared kinematics of state y.
    fn kin(&self, m: &Mode, y: &[f64]) -> Self::Kin;
    /// Horizontal position X and velocity Ẋ of the point the device acts on, `k` = kin(y).
    fn x_xdot_kin(&self, m: &Mode, k: &Self::Kin, y: &[f64]) -> (f64, f64);
    /// [`Body::x_xdot_kin`] computing the kinematics.
    fn x_xdot(&self, m: &Mode, y: &[f64]) -> (f64, f64) {
        self.x_xdot_kin(m, &self.kin(m, y), y)
    }
    /// Ẍ from the state and its time derivative.
    fn xddot(&self, m: &Mode, k: &Self::Kin, y: &[f64], dy: &[f64]) -> f64;
    /// Write the body's state derivatives under ground acceleration `ag`, device force `fd`
    /// (not counting a coupled mass) and coupled mass `mc`; return the rate of the
    /// [`Accumulator::Own`] integral.
    #[allow(clippy::too_many_arguments)]
    fn derivatives(
        &self,
        m: &Mode,
        k: &Self::Kin,
        ag: f64,
        y: &[f64],
        fd: f64,
        mc: f64,
        dy: &mut [f64],
    ) -> f64;
    /// Ẍ of the structure without a coupled mass: the sequential law decides on it.
    fn bare_xddot(&self, m: &Mode, k: &Self::Kin, t: f64, y: &[f64]) -> f64;
    /// Uplift test toward side s while flat: positive when the base lifts off.
    fn uplift_margin(&self, m: &Mode, side: f64, t: f64, y: &[f64]) -> f64;
    /// Rocking: non-negative once the structure has passed over its pivot.
    fn overturn_margin(&self, m: &Mode, y: &[f64]) -> f64;
    /// Its time derivative along the solution (dy = dy/dt), where it has a closed form.
    fn overturn_margin_rate(&self, _m: &Mode, _y: &[f64], _dy: &[f64]) -> Option<f64> {
        None
    }
    /// The impact jump at θ = 0 (after the shell counted it): velocities, pivot, energy lost.
    fn impact(&mut self, m: &mut Mode, ledger: &mut Ledger, y: &mut [f64]) -> Landing;
    /// Kinetic plus potential (plus strain) energy of the structure.
    fn energy(&self, m: &Mode, y: &[f64]) -> f64;
    /// The ground has stopped: can the energy left (the body's plus what the device can give
    /// back) no longer raise any peak?
    fn settled(&self, m: &Mode, y: &[f64], device: Returnable, peaks: &Peaks) -> bool;
    /// Rotation, deformation and drift peaks (those `measures` asks for) over an accepted
    /// step.
    fn observe_step<const N: usize>(
        &self,
        m: &Mode,
        measures: Measures,
        dense: &Dense<N>,
        t_end: f64,
        peaks: &mut Peaks,
    );
    /// Rotation, deformation and drift peaks at one point.
    fn observe_point(&self, m: &Mode, measures: Measures, y: &[f64], peaks: &mut Peaks);
    /// Upper bounds of |absolute acceleration|/g and of |θ̈|/p² (as the peak searches read
    /// them, from the interpolant) over a step, given bounds of |y_i| (`value`) and of the
    /// interpolant's |ẏ_i| (`rate`) over the step and of |a_g| (`ground`); None where the
    /// body has no cheap bound (the peak is then searched).
    fn acceleration_bounds(
        &self,
        _m: &Mode,
        _value: impl Fn(usize) -> f64,
        _rate: impl Fn(usize) -> f64,
        _ground: f64,
    ) -> (Option<f64>, Option<f64>) {
        (None, None)
    }
    /// Characteristic magnitudes for the error control: of the body's components, of one
    /// flywheel's (y, ẏ), and of the energies.
    fn tolerance_scales(&self, m: &Mode) -> (Vec<f64>, [f64; 2], f64);

    /// Flat on the ground at t with the device at rest: skip to this time (see
    /// [`Action::Idle`]).
    fn idle_until(&self, _m: &Mode, _t: f64) -> Option<f64> {
        None
    }
    /// The longest integration step the body allows until the next restart (the rigid
    /// block's Dirac impact window; see [`OdeSystem::max_step`]).
    fn max_step(&self, _m: &Mode) -> f64 {
        f64::INFINITY
    }
    /// p² for a body that reports its peak angular acceleration between impacts as
    /// |θ̈|max/p² (the rigid block); None for one that does not.
    fn angular_acceleration_scale(&self) -> Option<f64> {
        None
    }
    /// End of an idle period: the side the base lifts toward, or None (at rest for good).
    fn wake_side(&self, _m: &Mode, _t: f64) -> Option<f64> {
        None
    }
    /// Advance full contact in closed form from t to at most `t_stop` (see
    /// [`SimModel::advance_closed_form`]); `Some(side)` in the result: it ends at an uplift.
    fn advance_closed_form(
        &mut self,
        _m: &Mode,
        _peaks: &mut Peaks,
        _t: f64,
        _t_stop: f64,
        _y: &mut [f64],
    ) -> Option<(f64, Option<f64>)> {
        None
    }

    /// Events of the body's own beyond the shell's (the rigid block's Dirac zone).
    fn own_events(&self) -> usize {
        0
    }
    fn own_event_value(&self, _m: &Mode, _index: usize, _y: &[f64]) -> f64 {
        1.0
    }
    fn own_event_direction(&self, _index: usize) -> Direction {
        Direction::Either
    }
    fn own_event_name(&self, _index: usize) -> &'static str {
        "own"
    }
    fn apply_own_event(&mut self, _index: usize, _y: &mut [f64]) {}
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Ev {
    Impact,
    Overturn,
    Uplift(f64),
    Sequential,
    Own(usize),
    Clutch(ClutchEvent),
}

/// Largest state a rocking model has (flexible structure with two flywheels).
const MAX_STATE: usize = 16;

/// A rocking structure `B` with its device: the model the simulation driver runs.
pub struct Rocking<'m, B: Body> {
    pub(super) body: B,
    pub(super) mode: Mode<'m>,
    initial_rotation: f64,
    events: [Ev; MAX_EVENTS],
    n_events: usize,
    /// Whether an event function reads X or Ẋ (the sequential switch, the clutch events).
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
        if matches!(device, DeviceModel::Sequential { .. }) {
            push(Ev::Sequential);
        }
        for i in 0..body.own_events() {
            push(Ev::Own(i));
        }
        if let DeviceModel::Mechanistic(c) = device {
            for e in c.events() {
                push(Ev::Clutch(*e));
            }
        }
        Rocking {
            body,
            mode: Mode {
                dev: device,
                motion,
                layout: Layout::new(B::COORDINATES.len(), &device),
                phase: Phase::Contact,
                pivot: 1.0,
                sequential_engaged: false,
            },
            initial_rotation,
            events,
            n_events: n,
            events_read_x: events[..n]
                .iter()
                .any(|e| matches!(e, Ev::Sequential | Ev::Clutch(_))),
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
        let (x, xdot) = self.body.x_xdot_kin(m, k, y);
        let (fa, fb) = m.dev.spring_forces(x, layout.flywheel_states(y));
        let (mut visc, mut fric) = (0.0, 0.0);
        for (i, f) in [fa, fb].into_iter().take(layout.flywheels).enumerate() {
            let j = layout.flywheel(i);
            let (a, pv, pf) = m.dev.flywheel_accel(f, y[j + 1]);
            dy[j] = y[j + 1];
            dy[j + 1] = a;
            visc += pv;
            fric += pf;
        }
        let own = self
            .body
            .derivatives(m, k, ag, y, -(fa + fb), m.coupled_mass(), dy);
        dy[layout.accumulator(Accumulator::Input)] = -self.body.mass() * ag * xdot;
        dy[layout.accumulator(Accumulator::DeviceDamping)] = visc;
        dy[layout.accumulator(Accumulator::Friction)] = fric;
        dy[layout.accumulator(Accumulator::Own)] = own;
    }

    /// Event `ev`'s value at (t, y); `kx` = (kin(y), (X, Ẋ)) when the caller has them.
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
            Ev::Sequential if rocking || B::MOVES_IN_CONTACT => {
                let (k, (_, xdot)) = kx();
                xdot * self.body.bare_xddot(m, &k, t, y)
            }
            // X ≡ 0 while flat: the switch keeps its side until the base lifts.
            Ev::Sequential if m.sequential_engaged => 1.0,
            Ev::Sequential => -1.0,
            Ev::Own(i) => self.body.own_event_value(m, i, y),
            Ev::Clutch(e) => {
                let DeviceModel::Mechanistic(c) = &m.dev else {
                    return 1.0;
                };
                let (_, (x, xdot)) = kx();
                c.event_value(e, x, xdot, m.layout.flywheel_states(y))
            }
        }
    }

    /// Re-decide the sequential clutch after a jump or a phase change (Ẋ is continuous across
    /// both, Ẍ is not), booking the energy the law creates or destroys.
    fn resync_sequential(&mut self, t: f64, y: &[f64]) {
        if !matches!(self.mode.dev, DeviceModel::Sequential { .. }) {
            return;
        }
        let k = self.body.kin(&self.mode, y);
        let xdot = self.body.x_xdot_kin(&self.mode, &k, y).1;
        let bare = self.body.bare_xddot(&self.mode, &k, t, y);
        resync_sequential(
            self.mode.dev.mr(),
            xdot,
            bare,
            &mut self.mode.sequential_engaged,
            &mut self.ledger,
            &mut self.counters,
        );
    }

    /// From rest |Ẋ| can only grow: the sequential clutch engages (at Ẋ = 0, no energy).
    fn engage_sequential_from_rest(&mut self) {
        if matches!(self.mode.dev, DeviceModel::Sequential { .. }) {
            self.mode.sequential_engaged = true;
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
        if !self.mode.sequential_engaged && self.x_xdot(y).1 == 0.0 {
            self.engage_sequential_from_rest();
        } else {
            self.resync_sequential(t, y);
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
        self.resync_sequential(t, y);
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
        if layout.flywheels == 0 {
            return true;
        }
        let mut dy = [0.0; MAX_STATE];
        let dy = &mut dy[..y.len()];
        self.rhs_slice(t, y, dy);
        dy[layout.flywheel(0)..layout.flywheel(layout.flywheels)]
            .iter()
            .all(|d| *d == 0.0)
    }

    fn impact(&mut self, t: f64, y: &mut [f64]) -> Action {
        self.counters.impacts += 1;
        match self.body.impact(&mut self.mode, &mut self.ledger, y) {
            Landing::Rocking => {
                self.resync_sequential(t, y);
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
            Ev::Sequential => {
                let xdot = self.x_xdot(y).1;
                toggle_sequential(
                    self.mode.dev.mr(),
                    xdot,
                    &mut self.mode.sequential_engaged,
                    &mut self.ledger,
                    &mut self.counters,
                );
                Action::Continue
            }
            Ev::Own(i) => {
                self.body.apply_own_event(i, y);
                Action::Continue
            }
            Ev::Clutch(e) => {
                if let DeviceModel::Mechanistic(c) = self.mode.dev {
                    let (x, _) = self.x_xdot(y);
                    let fly = self.mode.layout.flywheel_states_mut(y);
                    c.apply(e, x, fly, &mut self.ledger, &mut self.counters);
                }
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

    /// Energy the device can still give back once the ground has stopped. A coupled mass and
    /// a two-way spring give back all they hold. The sequential law gives nothing back (mr's
    /// energy is lost at disengagement). A one-way clutch pushes flywheel a only forward
    /// (f_a ≥ 0, ẏ_a ≥ 0) and b only backward, so flywheel energy never returns: only the
    /// clutch springs' can.
    fn returnable(&self, y: &[f64]) -> Returnable {
        let m = &self.mode;
        let (x, xdot) = self.x_xdot(y);
        let fly = m.layout.flywheel_states(y);
        let (energy, springs, k) = match m.dev {
            DeviceModel::None | DeviceModel::Sequential { .. } => (0.0, 0.0, 0.0),
            DeviceModel::RigidInerter { .. } => (m.coupled_kinetic(xdot), 0.0, 0.0),
            DeviceModel::FlywheelInerter { k, .. } => (m.dev.stored_energy(x, fly), 1.0, k),
            DeviceModel::Mechanistic(c) => (
                c.potential_a(x - fly[0]).max(0.0) + c.potential_b(x - fly[2]).max(0.0),
                2.0,
                c.k,
            ),
        };
        Returnable { energy, k, springs }
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
        let abs_g = dy.map_or(0.0, |dy| self.absolute_acceleration(t, &k, y, dy).abs() / G);
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
            .spring_forces(x, self.mode.layout.flywheel_states(y));
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
        let own = y[layout.accumulator(Accumulator::Own)];
        let (column_damping, impact) = match B::OWN_LOSS {
            OwnLoss::Impact => (0.0, self.ledger.impact + own),
            OwnLoss::ColumnDamping => (own, self.ledger.impact),
        };
        Energy {
            input: y[layout.accumulator(Accumulator::Input)],
            structure: self.body.energy(m, y),
            inerter: m.coupled_kinetic(xdot) + m.dev.stored_energy(x, layout.flywheel_states(y)),
            column_damping,
            device_damping: y[layout.accumulator(Accumulator::DeviceDamping)],
            friction: y[layout.accumulator(Accumulator::Friction)],
            impact,
            disengagement: self.ledger.disengagement,
            reset: self.ledger.reset,
        }
    }
}

impl<const N: usize, B: Body> OdeSystem<N> for Rocking<'_, B> {
    #[inline]
    fn rhs(&self, t: f64, y: &[f64; N], dydt: &mut [f64; N]) {
        self.rhs_slice(t, y, dydt)
    }

    fn event_count(&self) -> usize {
        self.n_events
    }

    /// Body and flywheel states; the energy accumulators after them are no event's input.
    fn event_inputs(&self) -> usize {
        self.mode.layout.accumulator(Accumulator::Input)
    }

    fn event_direction(&self, index: usize) -> Direction {
        match self.events[index] {
            Ev::Impact => Direction::Falling,
            Ev::Overturn | Ev::Uplift(_) => Direction::Rising,
            Ev::Clutch(e) => e.direction(),
            Ev::Sequential if self.mode.sequential_engaged => Direction::Falling,
            Ev::Sequential => Direction::Rising,
            Ev::Own(i) => self.body.own_event_direction(i),
        }
    }

    /// The kinematics (one sin/cos for the rigid block) are computed once per sample and
    /// shared by every event function that reads X or Ẋ.
    fn events(&self, t: f64, y: &[f64; N], g: &mut [f64]) {
        let kx = self.events_read_x.then(|| {
            let k = self.body.kin(&self.mode, y);
            (k, self.body.x_xdot_kin(&self.mode, &k, y))
        });
        for (i, gi) in g.iter_mut().enumerate() {
            *gi = self.event_value(self.events[i], t, y, kx.as_ref());
        }
    }

    /// While rocking, every function has its rate in closed form: the impact margin's is
    /// pivot·θ̇, the overturn margin's the body's, a clutch's from Ẋ, Ẍ and the flywheels'
    /// rates, and the others are constants of the phase. One call of the kinematics then
    /// gives the screen what two calls of [`OdeSystem::events`] gave by differencing. In
    /// contact (an uplift margin reads a_g(t)) and with the sequential law (its switch reads
    /// Ẍ) the integrator differences.
    fn events_with_rates(
        &self,
        t: f64,
        y: &[f64; N],
        dydt: &[f64; N],
        g: &mut [f64],
        rates: &mut [f64],
    ) -> bool {
        let m = &self.mode;
        let closed_form = |ev: &Ev| match ev {
            Ev::Impact | Ev::Uplift(_) | Ev::Clutch(_) => true,
            Ev::Overturn => self.body.overturn_margin_rate(m, y, dydt).is_some(),
            Ev::Sequential | Ev::Own(_) => false,
        };
        if !m.rocking() || !self.events[..self.n_events].iter().all(closed_form) {
            return false;
        }
        // The kinematics only where a function reads X (a bare block's read θ alone).
        let kx = self.events_read_x.then(|| {
            let k = self.body.kin(m, y);
            let (x, xdot) = self.body.x_xdot_kin(m, &k, y);
            (k, (x, xdot), self.body.xddot(m, &k, y, dydt))
        });
        let kin_x = kx.map(|(k, v, _)| (k, v));
        let (fly, fly_dot) = (m.layout.flywheel_states(y), m.layout.flywheel_states(dydt));
        for (i, ev) in self.events[..self.n_events].iter().enumerate() {
            g[i] = self.event_value(*ev, t, y, kin_x.as_ref());
            rates[i] = match (ev, &m.dev, &kx) {
                (Ev::Impact, ..) => m.pivot * dydt[B::THETA],
                (Ev::Overturn, ..) => self.body.overturn_margin_rate(m, y, dydt).unwrap_or(0.0),
                (Ev::Clutch(e), DeviceModel::Mechanistic(c), Some((_, (x, xdot), xddot))) => {
                    c.event_rate(*e, (*x, *xdot, *xddot), fly, fly_dot)
                }
                _ => 0.0,
            };
        }
        true
    }

    /// While rocking: the impact margin (pivot·θ) and a mechanistic clutch's functions, the
    /// ones refined by the hundred (chattering impacts, clutch contacts and resets).
    /// (The impact margin reads θ alone.)
    fn event_rate_inputs(&self, index: usize) -> usize {
        match (self.events[index], &self.mode.dev) {
            _ if !self.mode.rocking() => 0,
            (Ev::Impact, _) => B::THETA + 1,
            (Ev::Clutch(_), DeviceModel::Mechanistic(_)) => {
                self.mode.layout.accumulator(Accumulator::Input)
            }
            _ => 0,
        }
    }

    fn event_with_rate(
        &self,
        index: usize,
        _t: f64,
        y: &[f64; N],
        dydt: &[f64; N],
    ) -> Option<(f64, f64)> {
        let m = &self.mode;
        match (self.events[index], &m.dev) {
            _ if !m.rocking() => None,
            (Ev::Impact, _) => Some((m.pivot * y[B::THETA], m.pivot * dydt[B::THETA])),
            (Ev::Clutch(e), DeviceModel::Mechanistic(c)) => {
                let k = self.body.kin(m, y);
                let (x, xdot) = self.body.x_xdot_kin(m, &k, y);
                let xddot = self.body.xddot(m, &k, y, dydt);
                let (fly, fly_dot) = (m.layout.flywheel_states(y), m.layout.flywheel_states(dydt));
                Some((
                    c.event_value(e, x, xdot, fly),
                    c.event_rate(e, (x, xdot, xddot), fly, fly_dot),
                ))
            }
            _ => None,
        }
    }

    /// One function alone: an impact or overturn margin reads θ only, without the
    /// kinematics every function that reads X needs.
    fn event(&self, index: usize, t: f64, y: &[f64; N]) -> f64 {
        self.event_value(self.events[index], t, y, None)
    }

    fn max_step(&self) -> f64 {
        self.body.max_step(&self.mode)
    }

    fn sign_after_zero(&self, index: usize, _t: f64, y: &[f64; N]) -> f64 {
        match self.events[index] {
            // At uplift (θ = θ̇ = 0, sθ̈ > 0) the base moves onto its pivot's side. Knowing
            // this matters: after an impact the uplift margin can already be falling, so the
            // base lands again within the first step, a crossing an undetermined start misses.
            Ev::Impact if y[B::THETA_DOT] == 0.0 => 1.0,
            Ev::Impact => (self.mode.pivot * y[B::THETA_DOT]).signum(),
            // From rest (Ẋ = 0) |Ẋ| grows.
            Ev::Sequential if self.x_xdot(y).1 == 0.0 => 1.0,
            _ => 0.0,
        }
    }
}

impl<const N: usize, B: Body> SimModel<N> for Rocking<'_, B> {
    fn start(&mut self, y: &mut [f64; N]) -> Action {
        let action = if self.initial_rotation != 0.0 {
            self.mode.phase = Phase::Rocking;
            self.mode.pivot = self.initial_rotation.signum();
            y[B::THETA] = self.initial_rotation;
            // Released from rest with the device relaxed: flywheels sit where X is.
            let (x, _) = self.x_xdot(y);
            for i in 0..self.mode.layout.flywheels {
                y[self.mode.layout.flywheel(i)] = x;
            }
            Action::Continue
        } else {
            self.land(0.0, y)
        };
        if B::MOVES_IN_CONTACT {
            self.engage_sequential_from_rest();
        }
        action
    }

    fn on_event(&mut self, index: usize, t: f64, y: &mut [f64; N]) -> Action {
        let action = self.apply_event(index, t, y);
        self.catch_up(action, t, y)
    }

    fn wake(&mut self, t: f64, y: &mut [f64; N]) -> Action {
        match self.body.wake_side(&self.mode, t) {
            Some(side) => self.uplift(side, t, y),
            None => Action::Stop(EndReason::Rest),
        }
    }

    fn wake_name(&self) -> &'static str {
        "uplift"
    }

    /// A body that does not move in contact is lifted by the ground itself: while it is flat
    /// its uplift test reads a_g directly.
    fn events_read_ground(&self) -> bool {
        !B::MOVES_IN_CONTACT && !self.mode.rocking()
    }

    /// Flat after the ground stopped, a body that cannot move in contact stays put: a
    /// flywheel can only spin down and drift away from engagement (its velocity never changes
    /// sign), so nothing can lift it. A flexible column decays but never stops (see
    /// [`SimModel::settled`] for its early stop).
    fn at_rest(&self, _t: f64, _y: &[f64; N]) -> bool {
        !B::MOVES_IN_CONTACT && self.mode.phase == Phase::Contact
    }

    /// A measure not asked for cannot hold the run: its peak counts as out of reach.
    fn settled(&self, y: &[f64; N]) -> bool {
        let mut peaks = self.peaks;
        let unasked = |asked: bool, peak: &mut f64| {
            if !asked {
                *peak = f64::INFINITY
            }
        };
        unasked(self.measures.deformation, &mut peaks.deformation);
        unasked(self.measures.drift, &mut peaks.drift);
        unasked(
            self.measures.abs_acceleration,
            &mut peaks.abs_acceleration_g,
        );
        if !self.measures.angular_acceleration {
            peaks.angular_acceleration_p2 = Some(f64::INFINITY);
        }
        self.body.settled(&self.mode, y, self.returnable(y), &peaks)
    }

    fn advance_closed_form(
        &mut self,
        t: f64,
        t_stop: f64,
        y: &mut [f64; N],
    ) -> Option<(f64, ClosedFormEnd)> {
        let (t1, uplift) =
            self.body
                .advance_closed_form(&self.mode, &mut self.peaks, t, t_stop, y)?;
        let end = match uplift {
            None => ClosedFormEnd::Reached,
            Some(side) => ClosedFormEnd::Event(
                self.events[..self.n_events]
                    .iter()
                    .position(|e| *e == Ev::Uplift(side))
                    .expect("uplift events exist in both directions"),
            ),
        };
        Some((t1, end))
    }

    /// The acceleration peaks are the largest of 4 + 1 samples per step, refined around the
    /// best one when it reaches the running peak ([`refine_sampled`]). The samples of both
    /// share one state, one set of kinematics and one right-hand side. A step whose bound
    /// ([`Body::acceleration_bounds`], from bounds of the interpolant over the whole step and,
    /// while the ground moves, of |a_g|: [`Motion::accel_bound`]) lies below the level at
    /// which the search could change the peak is skipped: every sample, and every point the
    /// refinement visits, lies below it too, so the result is the same as searching (for
    /// |θ̈| up to the margin the rigid block's bound documents).
    fn observe_step(&mut self, dense: &Dense<N>, t_end: f64) {
        self.body
            .observe_step(&self.mode, self.measures, dense, t_end, &mut self.peaks);
        let mut angular_floor = self
            .peaks
            .angular_acceleration_p2
            .filter(|_| self.mode.rocking());
        let mut abs_floor = self
            .measures
            .abs_acceleration
            .then_some(self.peaks.abs_acceleration_g);
        // refine_sampled leaves the peak unchanged when every sample is below this.
        let unreachable = |bound: Option<f64>, floor: f64| {
            bound.is_some_and(|b| below_peak(b, floor * (1.0 - 1e-9)))
        };
        let bounds = |ground: f64| {
            self.body.acceleration_bounds(
                &self.mode,
                |i| dense.bound(i),
                |i| dense.rate_bound(i),
                ground,
            )
        };
        // The bounds are lowest with the ground at rest; where even those reach a running peak
        // (while it grows), the bound of |a_g|, which costs evaluations of a_g, is not needed.
        let (abs_low, angular_low) = bounds(0.0);
        let may_skip = angular_floor.is_some_and(|f| unreachable(angular_low, f))
            || abs_floor.is_some_and(|f| unreachable(abs_low, f));
        if may_skip {
            let (abs_bound, angular_bound) = bounds(self.mode.motion.accel_bound(dense.t0, t_end));
            if angular_floor.is_some_and(|f| unreachable(angular_bound, f)) {
                angular_floor = None;
            }
            if abs_floor.is_some_and(|f| unreachable(abs_bound, f)) {
                abs_floor = None;
            }
        }
        if angular_floor.is_none() && abs_floor.is_none() {
            return;
        }
        const SAMPLES: usize = 4;
        let (t0, mut abs_values, mut angular_values) =
            (dense.t0, [0.0; SAMPLES + 1], [0.0; SAMPLES + 1]);
        for k in 0..=SAMPLES {
            let t = t0 + (t_end - t0) * k as f64 / SAMPLES as f64;
            let dy = abs_floor.map(|_| dense.derivative(t));
            let (a, w) =
                self.accelerations_at(t, &dense.state(t), dy.as_ref(), angular_floor.is_some());
            abs_values[k] = a;
            angular_values[k] = w;
        }
        if let Some(floor) = angular_floor {
            let theta_dd = |t: f64| self.accelerations_at(t, &dense.state(t), None, true).1;
            let peak = refine_sampled(theta_dd, t0, t_end, &angular_values, floor);
            self.peaks.angular_acceleration_p2 = Some(floor.max(peak));
        }
        if let Some(floor) = abs_floor {
            let accel_g = |t: f64| {
                let dy = dense.derivative(t);
                self.accelerations_at(t, &dense.state(t), Some(&dy), false)
                    .0
            };
            let peak = refine_sampled(accel_g, t0, t_end, &abs_values, floor);
            self.peaks.abs_acceleration_g = self.peaks.abs_acceleration_g.max(peak);
        }
    }

    fn observe_point(&mut self, t: f64, y: &[f64; N]) {
        self.body
            .observe_point(&self.mode, self.measures, y, &mut self.peaks);
        if !self.measures.abs_acceleration && self.peaks.angular_acceleration_p2.is_none() {
            return;
        }
        let k = self.body.kin(&self.mode, y);
        let mut dy = [0.0; N];
        self.rhs_kin(t, y, &k, &mut dy);
        if self.measures.abs_acceleration {
            let a = self.absolute_acceleration(t, &k, y, &dy);
            self.peaks.abs_acceleration_g = self.peaks.abs_acceleration_g.max(a.abs() / G);
        }
        // After a jump this is the one-sided value just past it (the jump itself excluded).
        if let Some(peak) = self.peaks.angular_acceleration_p2
            && let Some(p2) = self.body.angular_acceleration_scale()
            && self.mode.rocking()
        {
            self.peaks.angular_acceleration_p2 = Some(peak.max(dy[B::THETA_DOT].abs() / p2));
        }
    }

    fn observe_idle(&mut self, t0: f64, t1: f64) {
        if !self.measures.abs_acceleration {
            return;
        }
        let a = self.mode.motion.peak_abs(t0, t1);
        self.peaks.abs_acceleration_g = self.peaks.abs_acceleration_g.max(a / G);
    }

    fn energy(&self, y: &[f64; N]) -> Energy {
        self.energy_of(y)
    }

    fn peaks(&self) -> Peaks {
        self.peaks
    }

    fn counters(&self) -> Counters {
        self.counters
    }

    fn tolerance_scales(&self) -> (Vec<f64>, f64) {
        let (mut state, flywheel, energy) = self.body.tolerance_scales(&self.mode);
        for _ in 0..self.mode.layout.flywheels {
            state.extend(flywheel);
        }
        (state, energy)
    }

    fn event_name(&self, index: usize) -> &'static str {
        match self.events[index] {
            Ev::Impact => "impact",
            Ev::Overturn => "overturn",
            Ev::Uplift(_) => "uplift",
            Ev::Sequential => "sequential_switch",
            Ev::Own(i) => self.body.own_event_name(i),
            Ev::Clutch(e) => e.name(),
        }
    }

    fn history_columns(&self) -> Vec<&'static str> {
        let device = [
            "ground_accel",
            "x",
            "x_dot",
            "flywheel_a_vel",
            "flywheel_b_vel",
            "clutch_force_a",
            "clutch_force_b",
            "device_force",
        ];
        std::iter::once("t")
            .chain(B::COORDINATES.iter().copied())
            .chain(device)
            .chain(Energy::COLUMNS)
            .collect()
    }

    fn history_row(&self, t: f64, y: &[f64; N]) -> Vec<f64> {
        let layout = self.mode.layout;
        let (x, xdot) = self.x_xdot(y);
        let (fa, fb, fd) = self.device_force(t, y);
        let device = [
            self.mode.motion.accel(t),
            x,
            xdot,
            layout.flywheel_velocity(y, 0),
            layout.flywheel_velocity(y, 1),
            fa,
            fb,
            fd,
        ];
        std::iter::once(t)
            .chain(y[..layout.coordinates].iter().copied())
            .chain(device)
            .chain(self.energy_of(y).terms())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::rigid::RigidModel;
    use crate::presets::{mechanistic, rigid_fig8};
    use crate::scene::Structure;

    /// The closed-form event rates are the event functions' derivatives along the solution:
    /// central differences along the tangent agree, for a clutch engaged on one side, play
    /// taken up on the other, resettable and not, about either pivot.
    #[test]
    fn closed_form_event_rates_match_differences_along_the_solution() {
        let scene = rigid_fig8(mechanistic());
        let Structure::Rigid(block) = &scene.structure else {
            unreachable!()
        };
        // Fig. 8's sine pulse, A = 1.5 g tan α at ω = 4p (the model reads a_g only).
        let motion = Motion::Pulse(crate::excitation::Pulse::new(
            crate::excitation::PulseShape::Sine,
            1.5 * G * block.alpha.tan(),
            4.0 * scene.structure.p(),
        ));
        let device = DeviceModel::new(&scene.device, block.mass, scene.structure.p());
        for (rotation, fly) in [
            (0.3 * block.alpha, [0.004, 0.02, -0.003, -0.05]),
            (-0.2 * block.alpha, [-0.001, -0.3, 0.002, 0.1]),
            (0.5 * block.alpha, [0.05, 0.4, 0.06, 0.2]),
        ] {
            let mut model = RigidModel::new(block, device, scene.impact, &motion, rotation);
            let mut y = [0.0; 10];
            model.start(&mut y);
            y[1] = 0.7 * rotation.signum();
            y[2..6].copy_from_slice(&fly);
            let t = 0.1;
            let mut f = [0.0; 10];
            model.rhs(t, &y, &mut f);
            let m = OdeSystem::<10>::event_count(&model);
            let (mut g, mut rates) = ([0.0; MAX_EVENTS], [0.0; MAX_EVENTS]);
            assert!(model.events_with_rates(t, &y, &f, &mut g[..m], &mut rates[..m]));
            let at = |eps: f64| {
                let mut ge = [0.0; MAX_EVENTS];
                let ye: [f64; 10] = std::array::from_fn(|i| y[i] + eps * f[i]);
                model.events(t + eps, &ye, &mut ge[..m]);
                ge
            };
            let mut direct = [0.0; MAX_EVENTS];
            model.events(t, &y, &mut direct[..m]);
            let eps = 1e-6;
            let (ahead, behind) = (at(eps), at(-eps));
            for i in 0..m {
                assert_eq!(
                    g[i],
                    direct[i],
                    "value of {}",
                    SimModel::<10>::event_name(&model, i)
                );
                let difference = (ahead[i] - behind[i]) / (2.0 * eps);
                assert!(
                    (rates[i] - difference).abs() <= 1e-6 * (1.0 + difference.abs()),
                    "{}: closed form {} vs difference {difference}",
                    SimModel::<10>::event_name(&model, i),
                    rates[i]
                );
            }
        }
    }
}
