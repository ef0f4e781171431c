//! Flexible rocking structure (docs/MODEL.md "Flexible rocking structure"; paper §6) as a [`Body`]
//! of the rocking shell: a lumped mass m on a massless elastic column (height H, k = m ωn²,
//! c = 2 ξ ωn m) fixed to a rigid base of half-width B that can uplift about either corner,
//! with an inerter device acting on the mass's horizontal coordinate X.
//!
//! Coordinates (u, θ), docs/MODEL.md's recommended form (equivalent to the paper's R–β, Eqs. 34–52,
//! without the ½ on the inerter term of Eqs. 51–52):
//!   X = sB + (u − sB) cos θ + H sin θ,  Y = (sB − u) sin θ + H cos θ,
//!   ∂X/∂u = cos θ, ∂X/∂θ = Y, ∂Y/∂u = −sin θ, ∂Y/∂θ = Z = (sB − u) cos θ − H sin θ,
//!   Ẋ = u̇ cos θ + Y θ̇,  Ẍ = ü cos θ + Y θ̈ + κ,  κ = Z θ̇² − 2 sin θ u̇ θ̇.
//!
//! State: [u, u̇, θ, θ̇ | flywheels | accumulators] ([`super::shell::Layout`]); the column's
//! own accumulator is its damping work ∫ c u̇² dt. In full contact θ ≡ θ̇ ≡ 0.
//!
//! Full contact with no device or a rigidly coupled inerter under a record is advanced in
//! closed form ([`super::contact`]) when the scene allows it.

use super::column::HistoryColumn;
use super::contact::ClosedFormContact;
use super::device::{DeviceModel, Returnable};
use super::rigid::below_peak;
use super::shell::{Body, Landing, Mode, OwnLoss, Rocking};
use super::{Ledger, Measures, Peaks, extremum_of_component, extremum_on_step};
use crate::excitation::{Horizontal, Motion};
use crate::scene::FlexibleStructure;
use crate::solver::Dense;

pub(super) const U: usize = 0;
pub(super) const U_DOT: usize = 1;
const THETA: usize = 2;
const THETA_DOT: usize = 3;

/// The flexible structure in the rocking shell.
pub type FlexibleModel<'m> = Rocking<'m, FlexibleBody>;

/// The column and base: mass, stiffness, damping, half-width B and height H.
#[derive(Clone, Copy, Debug)]
pub struct Column {
    pub m: f64,
    pub k: f64,
    pub c: f64,
    pub b: f64,
    pub h: f64,
    /// The constant part of the gravity the structure feels ([`Motion::gravity`]).
    pub g: f64,
}

pub struct FlexibleBody {
    col: Column,
    /// Error-control scales: of (u, u̇, θ, θ̇) and of one flywheel.
    scales: ([f64; 4], [f64; 2]),
    /// The full-contact phase as a linear oscillator, when it is advanced in closed form.
    contact: Option<ClosedFormContact>,
}

/// Geometry of the mass at one configuration (u, θ) about pivot s.
#[derive(Clone, Copy, Debug)]
pub struct Kinematics {
    sin: f64,
    cos: f64,
    /// sB − u: horizontal lever of the mass about the pivot, in the base frame.
    lever: f64,
    x: f64,
    /// Y = ∂X/∂θ (height of the mass above the pivot).
    y: f64,
    /// Z = ∂Y/∂θ = −(X − sB).
    z: f64,
}

impl<'m> FlexibleModel<'m> {
    pub fn new(
        structure: &FlexibleStructure,
        device: DeviceModel,
        motion: &'m Motion,
        initial_rotation: f64,
    ) -> Self {
        let g = motion.gravity().g();
        let p = (g / structure.r0).sqrt();
        let body = FlexibleBody {
            col: Column::new(structure, g),
            scales: scales(structure, motion, p),
            contact: None,
        };
        Rocking::with_body(body, device, motion, initial_rotation)
    }

    /// Advance full contact in closed form where it is exact: a linear device (none, or a
    /// rigidly coupled inerter), a sampled record (linear between samples) and an
    /// underdamped column. Otherwise (or when `enabled` is false) the integrator does it.
    pub fn with_closed_form_contact(mut self, enabled: bool) -> Self {
        let Some(mc) = self.mode.dev.constant_coupled_mass() else {
            return self;
        };
        // The closed form is for a constant gravity: a vertical motion is integrated.
        if !enabled
            || !matches!(self.mode.motion.ground(), Horizontal::Record(_))
            || self.mode.motion.gravity().has_vertical()
        {
            return self;
        }
        self.body.contact = ClosedFormContact::new(&self.body.col, mc, self.mode.layout);
        self
    }

    /// Whether full contact is advanced in closed form (see
    /// [`Self::with_closed_form_contact`]).
    pub fn closed_form_contact(&self) -> bool {
        self.body.contact.is_some()
    }
}

/// Characteristic magnitudes for the error control: of [u, u̇, θ, θ̇], the column deformation
/// the ground can impose before uplift, reach/ω² with reach = min(g tan α, peak |a_g|) and ω
/// the faster of ωn and the ground's characteristic frequency |a_g|max/|v_g|max (a fast pulse
/// barely moves a soft column); rotations ~α; flywheels like the column (they follow X, which
/// is u until the base lifts, and the relative part of the tolerance takes over once X
/// grows).
fn scales(structure: &FlexibleStructure, motion: &Motion, p: f64) -> ([f64; 4], [f64; 2]) {
    let wn = structure.omega_n;
    let peak = motion.peak_abs(0.0, motion.end());
    let g = motion.gravity().g();
    let (reach, w) = if peak > 0.0 {
        let w_ground = peak / peak_ground_velocity(motion).max(f64::MIN_POSITIVE);
        ((g * structure.alpha.tan()).min(peak), wn.max(w_ground))
    } else {
        (g * structure.alpha.tan(), wn)
    };
    let u = reach / (w * w);
    let a = structure.alpha;
    ([u, w * u, a, p * a], [u, w * u])
}

/// |v_g|max over the motion, by the trapezoidal rule on 4000 intervals (a scale, not a result).
fn peak_ground_velocity(motion: &Motion) -> f64 {
    const INTERVALS: usize = 4000;
    let dt = motion.end() / INTERVALS as f64;
    let (mut v, mut peak, mut a_prev) = (0.0f64, 0.0f64, motion.accel(0.0));
    for k in 1..=INTERVALS {
        let a = motion.accel(k as f64 * dt);
        v += 0.5 * (a_prev + a) * dt;
        peak = peak.max(v.abs());
        a_prev = a;
    }
    peak
}

impl Column {
    fn new(structure: &FlexibleStructure, g: f64) -> Self {
        let m = structure.mass;
        Column {
            m,
            k: m * structure.omega_n.powi(2),
            c: 2.0 * structure.xi * structure.omega_n * m,
            b: structure.r0 * structure.alpha.sin(),
            h: structure.r0 * structure.alpha.cos(),
            g,
        }
    }

    /// Uplift test toward side s (Eqs. 37–38): s (k u + c u̇) H − m g (B − s u), positive when
    /// the base lifts off. The device force loads the mass, not the base, and cancels out.
    pub fn uplift_margin(&self, side: f64, u: f64, udot: f64) -> f64 {
        self.uplift_margin_at(side, u, udot, self.g)
    }

    /// [`Column::uplift_margin`] under gravity `g_eff` (g + ü_v).
    pub fn uplift_margin_at(&self, side: f64, u: f64, udot: f64, g_eff: f64) -> f64 {
        side * (self.k * u + self.c * udot) * self.h - self.m * g_eff * (self.b - side * u)
    }

    #[inline]
    fn kinematics(&self, m: &Mode, u: f64, theta: f64) -> Kinematics {
        let (sin, cos) = if m.rocking() {
            libm::sincos(theta) // not glibc's: see RigidBody::sc
        } else {
            (0.0, 1.0)
        };
        let lever = m.pivot * self.b - u;
        Kinematics {
            sin,
            cos,
            lever,
            x: m.pivot * self.b - lever * cos + self.h * sin,
            y: lever * sin + self.h * cos,
            z: lever * cos - self.h * sin,
        }
    }

    /// [`Column::accelerations_kin`] computing the kinematics (for tests).
    #[cfg(test)]
    fn accelerations(&self, m: &Mode, ag: f64, y: &[f64], fd: f64, mc: f64) -> (f64, f64) {
        let kin = self.kinematics(m, y[U], y[THETA]);
        self.accelerations_kin(m, &kin, ag, self.g, y, fd, mc)
    }

    /// (ü, θ̈) for device force `fd` (not counting a coupled mass) and coupled mass `mc`.
    ///
    /// Rocking phase (docs/MODEL.md), with a = Fd − m a_g:
    ///   m ü + m H θ̈ + m (sB − u) θ̇² − m g sin θ + k u + c u̇ = a cos θ
    ///   m H ü + m ((sB − u)² + H²) θ̈ − 2 m (sB − u) u̇ θ̇ + m g Z = a Y
    /// A rigidly coupled mass mc adds ½ mc Ẋ² to T. Its Lagrange terms are
    /// d/dt(mc Ẋ ∂Ẋ/∂q̇) − mc Ẋ ∂Ẋ/∂q = mc Ẍ ∂X/∂q (because ∂Ẋ/∂q̇ = ∂X/∂q and
    /// d/dt ∂X/∂q = ∂Ẋ/∂q), i.e. exactly the load of Fd = −mc Ẍ. With
    /// Ẍ = J q̈ + κ, J = (cos θ, Y), the mass matrix gains mc JᵀJ and the right-hand side
    /// loses mc κ Jᵀ. Full contact (θ ≡ 0): (m + mc) ü + c u̇ + k u = Fd − m a_g (Eq. 41).
    /// The 2×2 system is solved by Cramer's rule (a linear-algebra crate would round
    /// differently and buys nothing at this size).
    /// `kin` are the configuration's kinematics; g is `g_eff` = g + ü_v (a vertical ground
    /// motion replaces g in the gravity terms).
    #[inline]
    #[allow(clippy::too_many_arguments)]
    fn accelerations_kin(
        &self,
        m: &Mode,
        kin: &Kinematics,
        ag: f64,
        g_eff: f64,
        y: &[f64],
        fd: f64,
        mc: f64,
    ) -> (f64, f64) {
        let (u, udot, thetadot) = (y[U], y[U_DOT], y[THETA_DOT]);
        let load = fd - self.m * ag;
        let elastic = self.k * u + self.c * udot;
        if !m.rocking() {
            return ((load - elastic) / (self.m + mc), 0.0);
        }
        let (mass, h, g) = (self.m, self.h, g_eff);
        let kappa = kin.z * thetadot * thetadot - 2.0 * kin.sin * udot * thetadot;
        let m11 = mass + mc * kin.cos * kin.cos;
        let m12 = mass * h + mc * kin.cos * kin.y;
        let m22 = mass * (kin.lever * kin.lever + h * h) + mc * kin.y * kin.y;
        let f = load - mc * kappa;
        let r1 =
            f * kin.cos - mass * kin.lever * thetadot * thetadot + mass * g * kin.sin - elastic;
        let r2 = f * kin.y + 2.0 * mass * kin.lever * udot * thetadot - mass * g * kin.z;
        let det = m11 * m22 - m12 * m12;
        ((r1 * m22 - r2 * m12) / det, (m11 * r2 - m12 * r1) / det)
    }

    /// Ẍ from the state and (ü, θ̈).
    #[inline]
    #[cfg(test)]
    fn xddot(&self, m: &Mode, y: &[f64], udd: f64, thdd: f64) -> f64 {
        self.xddot_kin(&self.kinematics(m, y[U], y[THETA]), y, udd, thdd)
    }

    #[inline]
    fn xddot_kin(&self, kin: &Kinematics, y: &[f64], udd: f64, thdd: f64) -> f64 {
        let (udot, thetadot) = (y[U_DOT], y[THETA_DOT]);
        udd * kin.cos + kin.y * thdd + kin.z * thetadot * thetadot - 2.0 * kin.sin * udot * thetadot
    }
}

impl Body for FlexibleBody {
    type Kin = Kinematics;
    const COORDINATES: &'static [HistoryColumn] = &[
        HistoryColumn::U,
        HistoryColumn::UDot,
        HistoryColumn::Theta,
        HistoryColumn::ThetaDot,
    ];
    const THETA: usize = THETA;
    const THETA_DOT: usize = THETA_DOT;
    const MOVES_IN_CONTACT: bool = true;
    const OWN_LOSS: OwnLoss = OwnLoss::ColumnDamping;

    fn mass(&self) -> f64 {
        self.col.m
    }

    #[inline]
    fn kin(&self, m: &Mode, y: &[f64]) -> Kinematics {
        self.col.kinematics(m, y[U], y[THETA])
    }

    /// Horizontal position and velocity of the mass.
    #[inline]
    fn x_xdot_kin(&self, _m: &Mode, kin: &Kinematics, y: &[f64]) -> (f64, f64) {
        (kin.x, y[U_DOT] * kin.cos + kin.y * y[THETA_DOT])
    }

    fn xddot(&self, _m: &Mode, kin: &Kinematics, y: &[f64], dy: &[f64]) -> f64 {
        self.col.xddot_kin(kin, y, dy[U_DOT], dy[THETA_DOT])
    }

    /// Vertical velocity of the mass: Ẏ = −sin θ u̇ + Z θ̇ (0 in full contact).
    fn y_dot_kin(&self, _m: &Mode, kin: &Kinematics, y: &[f64]) -> f64 {
        -kin.sin * y[U_DOT] + kin.z * y[THETA_DOT]
    }

    #[allow(clippy::too_many_arguments)]
    fn derivatives(
        &self,
        m: &Mode,
        kin: &Kinematics,
        ag: f64,
        g_eff: f64,
        y: &[f64],
        fd: f64,
        mc: f64,
        dy: &mut [f64],
    ) -> f64 {
        let (udd, thdd) = self.col.accelerations_kin(m, kin, ag, g_eff, y, fd, mc);
        dy[U] = y[U_DOT];
        dy[U_DOT] = udd;
        if m.rocking() {
            dy[THETA] = y[THETA_DOT];
            dy[THETA_DOT] = thdd;
        }
        self.col.c * y[U_DOT] * y[U_DOT]
    }

    /// Ẍ with the device's spring forces but without a coupled mass (the coupled Ẍ is
    /// Ẍ_bare / (1 + mc J M⁻¹ Jᵀ) by Sherman–Morrison, so it has the same sign).
    fn bare_xddot(&self, m: &Mode, kin: &Kinematics, t: f64, y: &[f64]) -> f64 {
        let x = kin.x;
        let fd = m.dev.spring_force(x, m.layout.device_states(y));
        let (udd, thdd) = self.col.accelerations_kin(
            m,
            kin,
            m.motion.accel(t),
            m.motion.gravity().at(t),
            y,
            fd,
            0.0,
        );
        self.col.xddot_kin(kin, y, udd, thdd)
    }

    fn uplift_margin(&self, m: &Mode, side: f64, t: f64, y: &[f64]) -> f64 {
        let g_eff = m.motion.gravity().at(t);
        self.col.uplift_margin_at(side, y[U], y[U_DOT], g_eff)
    }

    /// The mass passes over the pivot: s Z ≤ 0.
    fn overturn_margin(&self, m: &Mode, y: &[f64]) -> f64 {
        -m.pivot * self.col.kinematics(m, y[U], y[THETA]).z
    }

    /// VVEL impact (Chopra–Yim, Eqs. 39–40): the mass keeps its horizontal velocity and loses
    /// the vertical one, u̇⁺ = u̇⁻ + H θ̇⁻, θ̇⁺ = 0, back to full contact. At θ = 0,
    /// Ẋ = u̇ + H θ̇ is unchanged, so a coupled inerter keeps its energy and flywheels keep
    /// their velocities; the loss is ½ m (sB − u)² θ̇⁻².
    fn impact(&mut self, m: &mut Mode, ledger: &mut Ledger, y: &mut [f64]) -> Landing {
        let lever = m.pivot * self.col.b - y[U];
        ledger.impact += 0.5 * self.col.m * (lever * y[THETA_DOT]).powi(2);
        y[U_DOT] += self.col.h * y[THETA_DOT];
        y[THETA] = 0.0;
        y[THETA_DOT] = 0.0;
        Landing::Flat
    }

    fn energy(&self, m: &Mode, y: &[f64]) -> f64 {
        let col = &self.col;
        let (u, udot, thetadot) = (y[U], y[U_DOT], y[THETA_DOT]);
        let kin = col.kinematics(m, u, y[THETA]);
        let kinetic = 0.5
            * col.m
            * (udot * udot
                + 2.0 * col.h * udot * thetadot
                + (kin.lever * kin.lever + col.h * col.h) * thetadot * thetadot);
        // V = m g Y + ½ k u², relative to the base flat on the ground (Y = H).
        let potential = col.m * col.g * (kin.y - col.h) + 0.5 * col.k * u * u;
        kinetic + potential
    }

    /// In full contact after the ground stopped, the energy E the structure can still draw on
    /// (its own, plus what the device can give back) can only decrease. The run may stop when
    /// E can neither lift the base (|u| ≤ √(2E/k), |u̇| ≤ √(2E/m) bound the uplift test) nor
    /// beat the deformation, drift and acceleration peaks already recorded. A device spring of
    /// stiffness k holding at most E pushes with at most √(2kE) (the tanh corner adds a
    /// relative ~1/(ε̂δ)², covered by the margin).
    fn settled(&self, m: &Mode, y: &[f64], device: Returnable, peaks: &Peaks) -> bool {
        // A constant vertical acceleration outlives the ground: the bounds below are for g.
        if m.rocking() || m.motion.gravity().at_rest() != self.col.g {
            return false;
        }
        let col = &self.col;
        let e = (self.energy(m, y) + device.energy).max(0.0);
        let u_max = (2.0 * e / col.k).sqrt();
        let v_max = (2.0 * e / col.m).sqrt();
        let column = col.k * u_max + col.c * v_max;
        let g = col.g;
        let can_uplift = column * col.h + col.m * g * u_max >= col.m * g * col.b;
        let device_force = device.springs * (2.0 * device.k * e).sqrt() * (1.0 + 1e-6);
        // m ü = −(k u + c u̇) + Fd; a coupled mass only lowers |ü|.
        let accel_g = (column + device_force) / (col.m * g);
        !can_uplift
            && u_max <= peaks.deformation
            && u_max / col.h <= peaks.drift
            && accel_g <= peaks.abs_acceleration_g
    }

    /// Steps whose interpolant bound of |u| (|θ|) lies below the running peak cannot raise it
    /// and are skipped (see [`below_peak`]); the drift, a nonlinear function of (u, θ), is
    /// searched on every step it is asked for.
    fn observe_step<const N: usize>(
        &self,
        m: &Mode,
        measures: Measures,
        dense: &Dense<N>,
        t_end: f64,
        peaks: &mut Peaks,
    ) {
        if measures.deformation && !below_peak(dense.bound(U), peaks.deformation) {
            let deformation = extremum_of_component(dense, t_end, U, U_DOT);
            peaks.deformation = peaks.deformation.max(deformation);
        }
        if m.rocking() && !below_peak(dense.bound(THETA), peaks.rotation) {
            let rot = extremum_of_component(dense, t_end, THETA, THETA_DOT);
            peaks.rotation = peaks.rotation.max(rot);
        }
        if measures.drift {
            let drift = extremum_on_step(
                dense,
                t_end,
                |y| self.x_xdot(m, y).0,
                |y| self.x_xdot(m, y).1,
            );
            peaks.drift = peaks.drift.max(drift / self.col.h);
        }
    }

    fn observe_point(&self, m: &Mode, measures: Measures, y: &[f64], peaks: &mut Peaks) {
        peaks.rotation = peaks.rotation.max(y[THETA].abs());
        if measures.deformation {
            peaks.deformation = peaks.deformation.max(y[U].abs());
        }
        if measures.drift {
            peaks.drift = peaks.drift.max(self.x_xdot(m, y).0.abs() / self.col.h);
        }
    }

    fn tolerance_scales(&self, _m: &Mode) -> (Vec<f64>, [f64; 2]) {
        let (state, flywheel) = self.scales;
        (state.to_vec(), flywheel)
    }

    fn advance_closed_form(
        &mut self,
        m: &Mode,
        peaks: &mut Peaks,
        t: f64,
        t_stop: f64,
        y: &mut [f64],
    ) -> Option<(f64, Option<f64>)> {
        let contact = self.contact.as_mut().filter(|_| !m.rocking())?;
        let Horizontal::Record(record) = m.motion.ground() else {
            return None;
        };
        contact.advance(&self.col, record, peaks, t, t_stop, y)
    }
}

#[cfg(test)]
mod tests {
    use super::super::SimModel;
    use super::super::shell::Phase;
    use super::*;
    use crate::excitation::{Pulse, PulseShape};
    use crate::scene::Device;

    fn structure() -> FlexibleStructure {
        FlexibleStructure {
            r0: 10.0,
            alpha: 0.2,
            mass: 2.0,
            xi: 0.05,
            omega_n: 8.0,
        }
    }

    fn motion() -> Motion {
        Motion::pulse(Pulse::new(PulseShape::Sine, 3.0, 6.0))
    }

    fn rocking_model<'m>(dev: DeviceModel, mo: &'m Motion, pivot: f64) -> FlexibleModel<'m> {
        let mut model = FlexibleModel::new(&structure(), dev, mo, 0.0);
        model.mode.phase = Phase::Rocking;
        model.mode.pivot = pivot;
        model
    }

    /// The closed-form 2×2 solve satisfies the two rocking equations as written in docs/MODEL.md,
    /// and a coupled mass enters exactly as the load Fd = −mc Ẍ.
    #[test]
    fn rocking_accelerations_satisfy_the_lagrange_equations() {
        let mo = motion();
        let mr = 0.7;
        for (pivot, y) in [
            (1.0, [0.03, -0.4, 0.05, 0.3]),
            (-1.0, [-0.02, 0.5, -0.08, 0.2]),
        ] {
            for mc in [0.0, mr] {
                let model = rocking_model(DeviceModel::RigidInerter { mr }, &mo, pivot);
                let (col, mode) = (&model.body.col, &model.mode);
                let (fd_ext, ag) = (0.3, 1.7);
                let (udd, thdd) = col.accelerations(mode, ag, &y, fd_ext, mc);
                let kin = col.kinematics(mode, y[0], y[2]);
                let xdd = col.xddot(mode, &y, udd, thdd);
                let fd = fd_ext - mc * xdd;
                let (m, k, c, h, l) = (col.m, col.k, col.c, col.h, kin.lever);
                let (u, ud, thd) = (y[0], y[1], y[3]);
                let e1 = m * udd + m * h * thdd + m * l * thd * thd - m * col.g * kin.sin
                    + k * u
                    + c * ud
                    - (fd - m * ag) * kin.cos;
                let e2 = m * h * udd + m * (l * l + h * h) * thdd - 2.0 * m * l * ud * thd
                    + m * col.g * kin.z
                    - (fd - m * ag) * kin.y;
                assert!(e1.abs() < 1e-12 && e2.abs() < 1e-12, "{e1} {e2}");
            }
        }
    }

    /// A coupled mass scales Ẍ by a factor in (0, 1]: the sequential law may decide on the
    /// bare Ẍ whether or not mr is engaged.
    #[test]
    fn coupled_mass_keeps_the_sign_of_the_horizontal_acceleration() {
        let mo = motion();
        for (pivot, y) in [
            (1.0, [0.03, -0.4, 0.05, 0.3]),
            (-1.0, [-0.02, 0.5, -0.08, 0.2]),
        ] {
            let model = rocking_model(DeviceModel::RigidInerter { mr: 1.0 }, &mo, pivot);
            let (col, mode) = (&model.body.col, &model.mode);
            for ag in [-3.0, -0.5, 0.0, 0.5, 3.0] {
                let xdd = |mc: f64| {
                    let (udd, thdd) = col.accelerations(mode, ag, &y, 0.0, mc);
                    col.xddot(mode, &y, udd, thdd)
                };
                let ratio = xdd(1.0) / xdd(0.0);
                assert!(ratio > 0.0 && ratio <= 1.0, "{ratio}");
            }
        }
    }

    /// VVEL (Eqs. 39–40): at θ = 0 the horizontal velocity of the mass survives the impact,
    /// so a coupled inerter keeps its energy, and the structure loses exactly what the ledger
    /// books.
    #[test]
    fn vvel_impact_keeps_the_horizontal_velocity_and_books_the_loss() {
        let mo = motion();
        let dev = DeviceModel::new(
            &Device::Sequential { sigma: 0.5 },
            structure().mass,
            1.0,
            crate::excitation::G,
        );
        for pivot in [1.0, -1.0] {
            let mut model = rocking_model(dev, &mo, pivot);
            model.mode.switch_engaged = true;
            let mut y = [0.0; 8];
            y[0] = 0.01 * pivot;
            y[1] = -0.2 * pivot;
            y[3] = -0.05 * pivot;
            let before = SimModel::<8>::energy(&model, &y);
            let xdot = model.body.x_xdot(&model.mode, &y).1;
            let landing = model
                .body
                .impact(&mut model.mode, &mut model.ledger, &mut y);
            model.mode.phase = Phase::Contact;
            let after = SimModel::<8>::energy(&model, &y);
            assert_eq!(landing, Landing::Flat);
            assert!((model.body.x_xdot(&model.mode, &y).1 - xdot).abs() < 1e-15);
            assert_eq!((y[2], y[3]), (0.0, 0.0));
            let lost = before.structure + before.inerter - after.structure - after.inerter;
            assert!(after.impact > 0.0);
            assert!(
                (lost - after.impact).abs() < 1e-15,
                "{lost} vs {}",
                after.impact
            );
            assert!((before.inerter - after.inerter).abs() < 1e-15);
        }
    }

    /// The uplift test is the sign of θ̈ at θ = θ̇ = 0 (Eqs. 37–38 follow from the rocking
    /// equations), whatever the device load.
    #[test]
    fn uplift_margin_is_the_sign_of_the_rocking_acceleration() {
        let mo = motion();
        let dev = DeviceModel::new(
            &Device::Sequential { sigma: 0.5 },
            structure().mass,
            1.0,
            crate::excitation::G,
        );
        for side in [1.0, -1.0] {
            let model = rocking_model(dev, &mo, side);
            let (col, mode) = (&model.body.col, &model.mode);
            for (u, ud) in [(0.02, 0.0), (0.03, 0.1), (-0.03, 0.2), (0.05, -0.3)] {
                let y = [u, ud, 0.0, 0.0];
                for (fd, mc) in [(0.0, 0.0), (5.0, 0.0), (0.0, 1.0)] {
                    let thdd = col.accelerations(mode, 2.0, &y, fd, mc).1;
                    let margin = col.uplift_margin(side, u, ud);
                    assert_eq!((side * thdd > 0.0), (margin > 0.0), "{side} {u} {ud}");
                }
            }
        }
    }
}
