//! What a structure family supplies to the rocking shell ([`Body`]) and what it is given.

use super::{Layout, Phase};
use crate::excitation::Motion;
use crate::model::column::HistoryColumn;
use crate::model::device::{DeviceModel, Returnable};
use crate::model::{Ledger, Measures, Peaks};
use crate::solver::{Dense, Direction};

/// The discrete mode the body's equations depend on, plus what they need of the device and
/// the ground.
pub struct Mode<'m> {
    pub dev: DeviceModel,
    pub motion: &'m Motion,
    pub layout: Layout,
    pub phase: Phase,
    /// s = ±1: the corner the base rocks about (θ > 0 rocks about x = +B).
    pub pivot: f64,
    /// The device's switch is engaged ([`DeviceModel::has_switch`]).
    pub switch_engaged: bool,
}

impl Mode<'_> {
    pub fn rocking(&self) -> bool {
        self.phase == Phase::Rocking
    }

    /// Apparent mass rigidly attached to X right now.
    pub fn coupled_mass(&self) -> f64 {
        self.dev.coupled_mass(self.switch_engaged)
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

/// What a structure family supplies to the rocking shell. `m` is the shell's [`Mode`]; `y`
/// the whole state, whose leading [`Body::COORDINATES`] components are the body's.
pub trait Body {
    /// Trigonometry and kinematics of one configuration, computed once per sample and shared
    /// by the right-hand side, the event functions and the peak searches that need them.
    type Kin: Copy;
    /// History names of the body's state components, in state order.
    const COORDINATES: &'static [HistoryColumn];
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
    /// Vertical velocity Ẏ of the mass centre relative to the ground (the vertical ground
    /// motion's work is −m ü_v Ẏ), `k` = kin(y).
    fn y_dot_kin(&self, m: &Mode, k: &Self::Kin, y: &[f64]) -> f64;
    /// Write the body's state derivatives under ground acceleration `ag`, gravity `g_eff`
    /// (g + ü_v at this time, [`crate::excitation::Gravity::at`]), device force `fd` (not
    /// counting a coupled mass) and coupled mass `mc`; return the rate of the
    /// [`Accumulator::Own`] integral.
    #[allow(clippy::too_many_arguments)]
    fn derivatives(
        &self,
        m: &Mode,
        k: &Self::Kin,
        ag: f64,
        g_eff: f64,
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
    /// Whether [`Body::observe_step`] could raise a peak anywhere inside the step from
    /// (t0, y0) to (t1, y1), derivatives f0 and f1 there; true unless the step's ends rule it
    /// out (the step's dense output is then not built).
    fn step_may_raise_peaks(
        &self,
        _m: &Mode,
        _start: (f64, &[f64], &[f64]),
        _end: (f64, &[f64], &[f64]),
        _peaks: &Peaks,
    ) -> bool {
        true
    }
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
    /// Characteristic magnitudes for the error control: of the body's components and of one
    /// device degree of freedom's (y, ẏ).
    fn tolerance_scales(&self, m: &Mode) -> (Vec<f64>, [f64; 2]);

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
