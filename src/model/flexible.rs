//! Flexible rocking structure (MODEL.md "Flexible rocking structure"; paper §6): a lumped mass
//! m on a massless elastic column (height H, k = m ωn², c = 2 ξ ωn m) fixed to a rigid base of
//! half-width B that can uplift about either corner, with an inerter device acting on the
//! mass's horizontal coordinate X.
//!
//! Coordinates (u, θ), MODEL.md's recommended form (equivalent to the paper's R–β, Eqs. 34–52,
//! without the ½ on the inerter term of Eqs. 51–52):
//!   X = sB + (u − sB) cos θ + H sin θ,  Y = (sB − u) sin θ + H cos θ,
//!   ∂X/∂u = cos θ, ∂X/∂θ = Y, ∂Y/∂u = −sin θ, ∂Y/∂θ = Z = (sB − u) cos θ − H sin θ,
//!   Ẋ = u̇ cos θ + Y θ̇,  Ẍ = ü cos θ + Y θ̈ + κ,  κ = Z θ̇² − 2 sin θ u̇ θ̇.
//!
//! State: [u, u̇, θ, θ̇, flywheels (y, ẏ per flywheel), accumulators (input work, device damping,
//! friction, column damping ∫ c u̇² dt)]. In full contact θ ≡ θ̇ ≡ 0.
//!
//! Full contact with no device or a rigidly coupled inerter under a record is a linear SDOF
//! under piecewise-linear forcing: [`FlexibleModel::with_exact_contact`] advances it in closed
//! form ([`super::sdof`]), one record sample at a time, and hands over to the integrator at
//! the located uplift.

use super::device::{ClutchEvent, DeviceModel};
use super::sdof::{Basis, Oscillator, Segment, gauss_legendre_5_nodes};
use super::{
    Action, Counters, EndReason, Energy, Exact, Ledger, Peaks, SimModel, extremum_on_step,
    refined_max, refined_max_of_samples,
};
use crate::excitation::{G, Motion, RecordMotion};
use crate::scene::FlexibleStructure;
use crate::solver::{Dense, Direction, MAX_EVENTS, OdeSystem};

#[derive(Clone, Copy, Debug, PartialEq)]
enum Ev {
    Impact,
    Overturn,
    Uplift(f64),
    Sequential,
    Clutch(ClutchEvent),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    /// Base flat on the ground: θ ≡ 0, the mass vibrates as a fixed-base SDOF.
    Contact,
    Rocking,
}

/// Geometry of the mass at one configuration (u, θ) about pivot s.
#[derive(Clone, Copy, Debug)]
struct Kinematics {
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

pub struct FlexibleModel<'m> {
    m: f64,
    k: f64,
    c: f64,
    b: f64,
    h: f64,
    dev: DeviceModel,
    motion: &'m Motion,
    initial_rotation: f64,
    acc: usize,
    events: [Ev; MAX_EVENTS],
    n_events: usize,
    phase: Phase,
    pivot: f64,
    seq_engaged: bool,
    /// Time of the last uplift, to recognise a grazing lift-off that lands at once.
    last_uplift: f64,
    ledger: Ledger,
    counters: Counters,
    peaks: Peaks,
    /// The full-contact phase as a linear oscillator, when it is advanced in closed form.
    contact: Option<ContactOscillator>,
    /// The closed form's basis at the nodes of the last few interval lengths.
    nodes: [Option<IntervalNodes>; 4],
    nodes_next: usize,
}

/// The closed form's basis (e^{−στ}, cos ωd τ, sin ωd τ) at the interior quarter points, the
/// end and the Gauss–Legendre nodes of an interval of length h.
#[derive(Clone, Copy, Debug)]
struct IntervalNodes {
    h: f64,
    quarters: [Basis; 3],
    end: Basis,
    gauss: [(Basis, f64); 5],
}

impl IntervalNodes {
    fn new(osc: &Oscillator, h: f64) -> Self {
        IntervalNodes {
            h,
            quarters: std::array::from_fn(|k| osc.basis(h * (k + 1) as f64 / 4.0)),
            end: osc.basis(h),
            gauss: gauss_legendre_5_nodes(h).map(|(tau, w)| (osc.basis(tau), w)),
        }
    }
}

/// The closed-form state (u, u̇, ü) at one instant τ of a contact segment.
#[derive(Clone, Copy, Debug)]
struct Sample {
    tau: f64,
    u: f64,
    v: f64,
    a: f64,
}

impl Sample {
    fn new(seg: &Segment, basis: &Basis) -> Self {
        let (u, v) = seg.state_at(basis);
        Sample {
            tau: basis.tau,
            u,
            v,
            a: seg.accel(basis.tau, u, v),
        }
    }
}

/// Full contact with a linear device: (m + mc) ü + c u̇ + k u = −m a_g (Eq. 41 with
/// Fd = −mc ü), i.e. ü + 2ζω u̇ + ω² u = −(m/M) a_g with M = m + mc, ω² = k/M, 2ζω = c/M.
#[derive(Clone, Copy, Debug)]
struct ContactOscillator {
    osc: Oscillator,
    /// m/M: the share of the ground's inertial load per unit moving mass.
    load_ratio: f64,
    /// Longest closed-form interval (ωd h ≤ 0.5 rad), so that samples at quarters resolve
    /// every extremum and the quadrature stays at roundoff.
    max_interval: f64,
}

impl<'m> FlexibleModel<'m> {
    pub fn new(
        structure: &FlexibleStructure,
        device: DeviceModel,
        motion: &'m Motion,
        initial_rotation: f64,
    ) -> Self {
        let m = structure.mass;
        let (b, h) = (
            structure.r0 * structure.alpha.sin(),
            structure.r0 * structure.alpha.cos(),
        );
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
        if let DeviceModel::Clutch(c) = device {
            for e in c.events() {
                push(Ev::Clutch(*e));
            }
        }
        FlexibleModel {
            m,
            k: m * structure.omega_n.powi(2),
            c: 2.0 * structure.xi * structure.omega_n * m,
            b,
            h,
            dev: device,
            motion,
            initial_rotation,
            acc: 4 + 2 * device.flywheels(),
            events,
            n_events: n,
            phase: Phase::Contact,
            pivot: 1.0,
            seq_engaged: false,
            last_uplift: f64::NEG_INFINITY,
            ledger: Ledger::default(),
            counters: Counters::default(),
            peaks: Peaks::default(),
            contact: None,
            nodes: [None; 4],
            nodes_next: 0,
        }
    }

    /// Advance full contact in closed form where it is exact: a linear device (none, or a
    /// rigidly coupled inerter), a sampled record (linear between samples) and an
    /// underdamped column. Otherwise (or when `enabled` is false) the integrator does it.
    pub fn with_exact_contact(mut self, enabled: bool) -> Self {
        let mc = match self.dev {
            DeviceModel::None => 0.0,
            DeviceModel::Coupled { mr } => mr,
            _ => return self,
        };
        if !enabled || !matches!(self.motion, Motion::Record(_)) {
            return self;
        }
        let total = self.m + mc;
        let omega = (self.k / total).sqrt();
        let zeta = self.c / (2.0 * (self.k * total).sqrt());
        self.contact = Oscillator::new(omega, zeta).map(|osc| ContactOscillator {
            osc,
            load_ratio: self.m / total,
            max_interval: 0.5 / osc.omega_d(),
        });
        self
    }

    /// Whether full contact is advanced in closed form (see [`Self::with_exact_contact`]).
    pub fn exact_contact(&self) -> bool {
        self.contact.is_some()
    }

    /// Number of state components this model needs.
    pub fn state_len(device: &DeviceModel) -> usize {
        4 + 2 * device.flywheels() + 4
    }

    /// Characteristic magnitudes for the error control: of [u, u̇, θ, θ̇, y, ẏ, …], the column
    /// deformation the ground can impose before uplift, reach/ω² with reach =
    /// min(g tan α, peak |a_g|) and ω the faster of ωn and the ground's characteristic
    /// frequency |a_g|max/|v_g|max (a fast pulse barely moves a soft column); rotations ~α;
    /// flywheels like the column (they follow X, which is u until the base lifts, and the
    /// relative part of the tolerance takes over once X grows); and of the energies,
    /// ½ m (ω u)², the energy the column takes on at that deformation.
    pub fn scales(structure: &FlexibleStructure, motion: &Motion, p: f64) -> ([f64; 8], f64) {
        let wn = structure.omega_n;
        let peak = motion.peak_abs(0.0, motion.end());
        let (reach, w) = if peak > 0.0 {
            let w_ground = peak / peak_ground_velocity(motion).max(f64::MIN_POSITIVE);
            ((G * structure.alpha.tan()).min(peak), wn.max(w_ground))
        } else {
            (G * structure.alpha.tan(), wn)
        };
        let u = reach / (w * w);
        let a = structure.alpha;
        let energy = 0.5 * structure.mass * (w * u).powi(2);
        ([u, w * u, a, p * a, u, w * u, u, w * u], energy)
    }

    #[inline]
    fn kinematics(&self, u: f64, theta: f64) -> Kinematics {
        let (sin, cos) = if self.phase == Phase::Rocking {
            theta.sin_cos()
        } else {
            (0.0, 1.0)
        };
        let lever = self.pivot * self.b - u;
        Kinematics {
            sin,
            cos,
            lever,
            x: self.pivot * self.b - lever * cos + self.h * sin,
            y: lever * sin + self.h * cos,
            z: lever * cos - self.h * sin,
        }
    }

    /// Horizontal position and velocity of the mass.
    #[inline]
    fn x_xdot(&self, y: &[f64]) -> (f64, f64) {
        let kin = self.kinematics(y[0], y[2]);
        (kin.x, y[1] * kin.cos + kin.y * y[3])
    }

    /// Horizontal acceleration Ẍ from the state and its derivative.
    #[inline]
    fn xddot(&self, y: &[f64], dy: &[f64]) -> f64 {
        let kin = self.kinematics(y[0], y[2]);
        dy[1] * kin.cos + kin.y * dy[3] + kin.z * y[3] * y[3] - 2.0 * kin.sin * y[1] * y[3]
    }

    /// (ü, θ̈) for device force `fd` (not counting a coupled mass) and coupled mass `mc`.
    ///
    /// Rocking phase (MODEL.md), with a = Fd − m a_g:
    ///   m ü + m H θ̈ + m (sB − u) θ̇² − m g sin θ + k u + c u̇ = a cos θ
    ///   m H ü + m ((sB − u)² + H²) θ̈ − 2 m (sB − u) u̇ θ̇ + m g Z = a Y
    /// A rigidly coupled mass mc adds ½ mc Ẋ² to T. Its Lagrange terms are
    /// d/dt(mc Ẋ ∂Ẋ/∂q̇) − mc Ẋ ∂Ẋ/∂q = mc Ẍ ∂X/∂q (because ∂Ẋ/∂q̇ = ∂X/∂q and
    /// d/dt ∂X/∂q = ∂Ẋ/∂q), i.e. exactly the load of Fd = −mc Ẍ. With
    /// Ẍ = J q̈ + κ, J = (cos θ, Y), the mass matrix gains mc JᵀJ and the right-hand side
    /// loses mc κ Jᵀ. Full contact (θ ≡ 0): (m + mc) ü + c u̇ + k u = Fd − m a_g (Eq. 41).
    #[inline]
    fn accelerations(&self, ag: f64, y: &[f64], fd: f64, mc: f64) -> (f64, f64) {
        let (u, udot, thetadot) = (y[0], y[1], y[3]);
        let load = fd - self.m * ag;
        let elastic = self.k * u + self.c * udot;
        if self.phase == Phase::Contact {
            return ((load - elastic) / (self.m + mc), 0.0);
        }
        let kin = self.kinematics(u, y[2]);
        let (m, h) = (self.m, self.h);
        let kappa = kin.z * thetadot * thetadot - 2.0 * kin.sin * udot * thetadot;
        let m11 = m + mc * kin.cos * kin.cos;
        let m12 = m * h + mc * kin.cos * kin.y;
        let m22 = m * (kin.lever * kin.lever + h * h) + mc * kin.y * kin.y;
        let f = load - mc * kappa;
        let r1 = f * kin.cos - m * kin.lever * thetadot * thetadot + m * G * kin.sin - elastic;
        let r2 = f * kin.y + 2.0 * m * kin.lever * udot * thetadot - m * G * kin.z;
        let det = m11 * m22 - m12 * m12;
        ((r1 * m22 - r2 * m12) / det, (m11 * r2 - m12 * r1) / det)
    }

    /// Ẍ of the structure without a coupled mass: the sequential law decides on it (the
    /// coupled Ẍ is Ẍ_bare / (1 + mc J M⁻¹ Jᵀ) by Sherman–Morrison, so it has the same sign).
    fn bare_xddot(&self, t: f64, y: &[f64]) -> f64 {
        let (fa, fb) = self.dev.spring_forces(self.x_xdot(y).0, &y[4..self.acc]);
        let (udd, thdd) = self.accelerations(self.motion.accel(t), y, -(fa + fb), 0.0);
        let mut dy = [0.0; 4];
        dy[1] = udd;
        dy[3] = thdd;
        self.xddot(y, &dy)
    }

    /// Uplift test toward side s (Eqs. 37–38): s (k u + c u̇) H − m g (B − s u), positive when
    /// the base lifts off. The device force loads the mass, not the base, and cancels out.
    fn uplift_margin(&self, side: f64, y: &[f64]) -> f64 {
        side * (self.k * y[0] + self.c * y[1]) * self.h - self.m * G * (self.b - side * y[0])
    }

    fn rhs_slice(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        dy.fill(0.0);
        let ag = self.motion.accel(t);
        let (x, xdot) = self.x_xdot(y);
        let (fa, fb) = self.dev.spring_forces(x, &y[4..self.acc]);
        let (mut visc, mut fric) = (0.0, 0.0);
        for (i, f) in [fa, fb].into_iter().take(self.dev.flywheels()).enumerate() {
            let j = 4 + 2 * i;
            let (a, pv, pf) = self.dev.flywheel_accel(f, y[j + 1]);
            dy[j] = y[j + 1];
            dy[j + 1] = a;
            visc += pv;
            fric += pf;
        }
        let mc = self.dev.coupled_mass(self.seq_engaged);
        let (udd, thdd) = self.accelerations(ag, y, -(fa + fb), mc);
        dy[0] = y[1];
        dy[1] = udd;
        if self.phase == Phase::Rocking {
            dy[2] = y[3];
            dy[3] = thdd;
        }
        dy[self.acc] = -self.m * ag * xdot;
        dy[self.acc + 1] = visc;
        dy[self.acc + 2] = fric;
        dy[self.acc + 3] = self.c * y[1] * y[1];
    }

    fn event_value(&self, ev: Ev, t: f64, y: &[f64]) -> f64 {
        let rocking = self.phase == Phase::Rocking;
        match ev {
            Ev::Impact if rocking => self.pivot * y[2],
            Ev::Impact => 1.0,
            // The mass passes over the pivot: s Z ≤ 0.
            Ev::Overturn if rocking => -self.pivot * self.kinematics(y[0], y[2]).z,
            Ev::Overturn => -1.0,
            Ev::Uplift(_) if rocking => -1.0,
            Ev::Uplift(side) => self.uplift_margin(side, y),
            Ev::Sequential => self.x_xdot(y).1 * self.bare_xddot(t, y),
            Ev::Clutch(e) => {
                let DeviceModel::Clutch(c) = &self.dev else {
                    return 1.0;
                };
                let (x, xdot) = self.x_xdot(y);
                c.event_value(e, x, xdot, &y[4..8])
            }
        }
    }

    fn coupled_kinetic(&self, y: &[f64]) -> f64 {
        let (_, xdot) = self.x_xdot(y);
        0.5 * self.dev.coupled_mass(self.seq_engaged) * xdot * xdot
    }

    /// Re-decide the sequential clutch after a jump or a phase change (Ẋ is continuous across
    /// both, Ẍ is not), booking the energy the law creates or destroys.
    fn resync_sequential(&mut self, t: f64, y: &[f64]) {
        if !matches!(self.dev, DeviceModel::Sequential { .. }) {
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

    fn uplift(&mut self, side: f64, t: f64, y: &mut [f64]) -> Action {
        self.phase = Phase::Rocking;
        self.pivot = side;
        y[2] = 0.0;
        y[3] = 0.0;
        self.last_uplift = t;
        self.counters.uplifts += 1;
        self.resync_sequential(t, y);
        Action::Continue
    }

    /// VVEL impact (Chopra–Yim, Eqs. 39–40): the mass keeps its horizontal velocity and loses
    /// the vertical one, u̇⁺ = u̇⁻ + H θ̇⁻, θ̇⁺ = 0. At θ = 0, Ẋ = u̇ + H θ̇ is unchanged, so a
    /// coupled inerter keeps its energy and flywheels keep their velocities; the loss is
    /// ½ m (sB − u)² θ̇⁻².
    fn impact(&mut self, t: f64, y: &mut [f64]) -> Action {
        self.counters.impacts += 1;
        let lever = self.pivot * self.b - y[0];
        self.ledger.impact += 0.5 * self.m * (lever * y[3]).powi(2);
        y[1] += self.h * y[3];
        y[2] = 0.0;
        y[3] = 0.0;
        self.phase = Phase::Contact;
        // A lift-off that landed within roundoff of its start (the margin was positive but
        // already falling) would lift and land again forever at the same instant: stay down,
        // the margin is on its way below zero.
        let grazing = t - self.last_uplift <= 1e-12 * t.abs().max(1.0);
        for side in [1.0, -1.0] {
            if !grazing && self.uplift_margin(side, y) > 0.0 {
                return self.uplift(side, t, y);
            }
        }
        self.resync_sequential(t, y);
        Action::Continue
    }

    /// The jump of event `index` at t.
    fn apply_event(&mut self, index: usize, t: f64, y: &mut [f64]) -> Action {
        match self.events[index] {
            Ev::Impact => self.impact(t, y),
            Ev::Overturn => Action::Stop(EndReason::Overturned),
            Ev::Uplift(side) => self.uplift(side, t, y),
            Ev::Sequential => {
                self.toggle_sequential(y);
                Action::Continue
            }
            Ev::Clutch(e) => {
                if let DeviceModel::Clutch(c) = self.dev {
                    let (x, _) = self.x_xdot(y);
                    c.apply(e, x, &mut y[4..8], &mut self.ledger, &mut self.counters);
                }
                Action::Continue
            }
        }
    }

    /// Two events can fall within the location tolerance of each other (the sequential clutch
    /// switches where Ẍ = 0, which is exactly where the mass passes over the pivot). The
    /// located one is returned on its post-crossing side, possibly past the other's root, and
    /// a function already past its root at a restart never reports the crossing: catch up
    /// with overturning and landing here.
    fn settle(&mut self, action: Action, t: f64, y: &mut [f64]) -> Action {
        if action != Action::Continue || self.phase != Phase::Rocking {
            return action;
        }
        if self.event_value(Ev::Overturn, t, y) >= 0.0 {
            return Action::Stop(EndReason::Overturned);
        }
        if self.pivot * y[2] < 0.0 {
            return self.impact(t, y);
        }
        action
    }

    /// One closed-form interval of full contact (see [`ContactOscillator`]): from t to the next
    /// record sample (or t_stop, or the longest interval), stopping early at an uplift.
    fn advance_contact(&mut self, t: f64, t_stop: f64, y: &mut [f64]) -> Option<(f64, Exact)> {
        let contact = self.contact.filter(|_| self.phase == Phase::Contact)?;
        let Motion::Record(record) = self.motion else {
            return None;
        };
        let (t1, a0, a1) = record_interval(record, t, t_stop, contact.max_interval);
        let h = t1 - t;
        if h <= 0.0 {
            return None;
        }
        let slope = (a1 - a0) / h;
        let ground = |tau: f64| a0 + slope * tau;
        let osc = contact.osc;
        let seg = osc.segment(
            y[0],
            y[1],
            -contact.load_ratio * a0,
            -contact.load_ratio * slope,
        );
        let nodes = self.interval_nodes(&osc, h);
        let at = |basis: &Basis| Sample::new(&seg, basis);
        let mut samples = [
            Sample::new(&seg, &osc.basis(0.0)),
            at(&nodes.quarters[0]),
            at(&nodes.quarters[1]),
            at(&nodes.quarters[2]),
            at(&nodes.end),
        ];
        let (tau_end, outcome, gauss) = match self.first_uplift(&seg, &samples) {
            Some((tau, side)) => {
                let index = self.events[..self.n_events]
                    .iter()
                    .position(|e| *e == Ev::Uplift(side))
                    .expect("uplift events exist in both directions");
                samples = std::array::from_fn(|k| at(&osc.basis(tau * k as f64 / 4.0)));
                let gauss = gauss_legendre_5_nodes(tau).map(|(x, w)| (osc.basis(x), w));
                (tau, Exact::Event(index), gauss)
            }
            None => {
                let stretch = h / nodes.h;
                (
                    h,
                    Exact::Reached,
                    nodes.gauss.map(|(b, w)| (b, w * stretch)),
                )
            }
        };
        self.observe_segment(&seg, &samples, &ground);
        for (basis, w) in gauss {
            let (_, v) = seg.state_at(&basis);
            y[self.acc] -= w * self.m * ground(basis.tau) * v;
            y[self.acc + 3] += w * self.c * v * v;
        }
        (y[0], y[1]) = (samples[4].u, samples[4].v);
        let t_end = if tau_end == h { t1 } else { t + tau_end };
        Some((t_end, outcome))
    }

    /// The bases at the nodes of an interval of length h, from a small cache keyed by h's bits:
    /// a record's intervals t0 + k dt take only a few distinct lengths (dt to roundoff), so
    /// an interval rarely costs a transcendental function.
    fn interval_nodes(&mut self, osc: &Oscillator, h: f64) -> IntervalNodes {
        if let Some(n) = self.nodes.iter().flatten().find(|n| n.h == h) {
            return *n;
        }
        let slot = self.nodes_next % self.nodes.len();
        self.nodes_next += 1;
        *self.nodes[slot].insert(IntervalNodes::new(osc, h))
    }

    /// The earliest uplift (Eqs. 37–38, either side) on a contact segment: the margin rising
    /// through zero between two samples, or peaking above zero between samples where it is
    /// negative (its rate turns from + to − and the end tangents allow it to reach zero).
    /// The margin is linear in (u, u̇), so its second derivative is a damped free vibration
    /// with zeros π/ωd apart: samples ≤ ωd h/4 ≤ 0.125 rad apart hold at most one inflection,
    /// the peak lies on a concave stretch, below the tangent at one end (the factor 2 is
    /// margin). Not seen: a rate turning −, +, − within one piece, which can only graze zero by
    /// a third-order amount. Located by bisection to roundoff; the returned τ is on the lifted
    /// side (margin ≥ 0).
    fn first_uplift(&self, seg: &Segment, samples: &[Sample; 5]) -> Option<(f64, f64)> {
        let margin = |side: f64, s: &Sample| self.uplift_margin(side, &[s.u, s.v]);
        // d/dt of the margin: s (k u̇ + c ü) H + m g s u̇.
        let rate = |side: f64, s: &Sample| {
            side * ((self.k * s.v + self.c * s.a) * self.h + self.m * G * s.v)
        };
        let fresh = |tau: f64| Sample::new(seg, &seg.basis(tau));
        for pair in samples.windows(2) {
            let (lo, hi) = (&pair[0], &pair[1]);
            let width = hi.tau - lo.tau;
            let mut found: Option<(f64, f64)> = None;
            for side in [1.0, -1.0] {
                let (g_lo, g_hi) = (margin(side, lo), margin(side, hi));
                if g_lo >= 0.0 {
                    // Already on the lifted side at the start (a grazing landing): not a rise.
                    continue;
                }
                let (r_lo, r_hi) = (rate(side, lo), rate(side, hi));
                let crossing_end = if g_hi >= 0.0 {
                    Some(hi.tau)
                } else if r_lo > 0.0
                    && r_hi < 0.0
                    && (g_lo + 2.0 * r_lo * width >= 0.0 || g_hi - 2.0 * r_hi * width >= 0.0)
                {
                    let top = bisect(lo.tau, hi.tau, 60, |tau| rate(side, &fresh(tau)) > 0.0).0;
                    (margin(side, &fresh(top)) >= 0.0).then_some(top)
                } else {
                    None
                };
                if let Some(end) = crossing_end {
                    let tau = bisect(lo.tau, end, 200, |tau| margin(side, &fresh(tau)) < 0.0).1;
                    if found.is_none_or(|(t0, _)| tau < t0) {
                        found = Some((tau, side));
                    }
                }
            }
            if found.is_some() {
                return found;
            }
        }
        None
    }

    /// Peaks over a contact segment from its samples, where X = u (θ = 0): |u| at the samples
    /// and at interior zeros of u̇, and the absolute acceleration ü + a_g refined like
    /// [`refined_max`] does on an integrator step.
    fn observe_segment(
        &mut self,
        seg: &Segment,
        samples: &[Sample; 5],
        ground: &impl Fn(f64) -> f64,
    ) {
        let mut deformation = samples.iter().fold(0.0f64, |m, s| m.max(s.u.abs()));
        for pair in samples.windows(2) {
            if pair[0].v * pair[1].v < 0.0 {
                // |u| is flat at its extremum: a bracket of 2⁻³⁰ of the sample spacing leaves
                // a relative error ~ (ω δτ)² far below roundoff.
                let rising = pair[0].v > 0.0;
                let (a, b) = bisect(pair[0].tau, pair[1].tau, 30, |tau| {
                    (seg.state(tau).1 > 0.0) == rising
                });
                deformation = deformation.max(seg.state(0.5 * (a + b)).0.abs());
            }
        }
        self.peaks.deformation = self.peaks.deformation.max(deformation);
        self.peaks.drift = self.peaks.drift.max(deformation / self.h);
        let accel_g = |tau: f64| {
            let (u, v) = seg.state(tau);
            (seg.accel(tau, u, v) + ground(tau)).abs() / G
        };
        let sampled = samples.map(|s| (s.tau, (s.a + ground(s.tau)).abs() / G));
        let floor = self.peaks.abs_acceleration_g;
        let peak = refined_max_of_samples(accel_g, &sampled, floor);
        self.peaks.abs_acceleration_g = floor.max(peak);
    }

    fn absolute_acceleration(&self, t: f64, y: &[f64], dy: &[f64]) -> f64 {
        self.xddot(y, dy) + self.motion.accel(t)
    }

    fn device_force(&self, t: f64, y: &[f64]) -> (f64, f64, f64) {
        let (x, _) = self.x_xdot(y);
        let (fa, fb) = self.dev.spring_forces(x, &y[4..self.acc]);
        let mc = self.dev.coupled_mass(self.seq_engaged);
        if mc > 0.0 {
            let mut dy = vec![0.0; y.len()];
            self.rhs_slice(t, y, &mut dy);
            return (0.0, 0.0, -mc * self.xddot(y, &dy));
        }
        (fa, fb, -(fa + fb))
    }

    /// Energy the device can still give back to the structure, and a bound on the force it
    /// can exert when E is in play. A coupled mass and a two-way spring give back all they
    /// hold. The sequential law gives nothing back (mr's energy is lost at disengagement).
    /// A one-way clutch pushes flywheel a only forward (f_a ≥ 0, ẏ_a ≥ 0) and b only
    /// backward, so flywheel energy never returns: only the clutch springs' can. A spring of
    /// stiffness k holding at most E pushes with at most √(2kE) (the tanh corner adds a
    /// relative ~1/(ε̂δ)², covered by the margin).
    fn returnable_energy(&self, y: &[f64]) -> (f64, impl Fn(f64) -> f64) {
        let (x, _) = self.x_xdot(y);
        let fly = &y[4..self.acc];
        let (energy, springs, k) = match self.dev {
            DeviceModel::None | DeviceModel::Sequential { .. } => (0.0, 0.0, 0.0),
            DeviceModel::Coupled { .. } => (self.coupled_kinetic(y), 0.0, 0.0),
            DeviceModel::Spring { k, .. } => (self.dev.stored_energy(x, fly), 1.0, k),
            DeviceModel::Clutch(c) => (
                self.dev.clutch_potential_a(x - fly[0]).max(0.0)
                    + self.dev.clutch_potential_b(x - fly[2]).max(0.0),
                2.0,
                c.k,
            ),
        };
        (energy, move |e: f64| {
            springs * (2.0 * k * e).sqrt() * (1.0 + 1e-6)
        })
    }

    fn energy_parts(&self, y: &[f64]) -> Energy {
        let acc = self.acc;
        let (u, udot, thetadot) = (y[0], y[1], y[3]);
        let kin = self.kinematics(u, y[2]);
        let kinetic = 0.5
            * self.m
            * (udot * udot
                + 2.0 * self.h * udot * thetadot
                + (kin.lever * kin.lever + self.h * self.h) * thetadot * thetadot);
        // V = m g Y + ½ k u², relative to the base flat on the ground (Y = H).
        let potential = self.m * G * (kin.y - self.h) + 0.5 * self.k * u * u;
        let (x, _) = self.x_xdot(y);
        Energy {
            input: y[acc],
            structure: kinetic + potential,
            inerter: self.coupled_kinetic(y) + self.dev.stored_energy(x, &y[4..acc]),
            column_damping: y[acc + 3],
            device_damping: y[acc + 1],
            friction: y[acc + 2],
            impact: self.ledger.impact,
            disengagement: self.ledger.disengagement,
            reset: self.ledger.reset,
        }
    }
}

/// The closed-form interval from t: up to the next sample of the record (a_g linear on it),
/// t_stop or t + `longest`, with a_g at its ends taken from inside it (a record that starts
/// or ends on a nonzero sample jumps there; a_g = 0 outside it).
fn record_interval(record: &RecordMotion, t: f64, t_stop: f64, longest: f64) -> (f64, f64, f64) {
    let s = &*record.series;
    let cap = t_stop.min(t + longest);
    if t < s.t0() {
        return (cap.min(s.t0()), 0.0, 0.0);
    }
    if t >= s.end() {
        return (cap, 0.0, 0.0);
    }
    // The first sample strictly after t, computed as the integrator's breakpoints are.
    let time = |k: usize| s.t0() + k as f64 * s.dt();
    let mut k = ((t - s.t0()) / s.dt()).floor() as usize + 1;
    if time(k) <= t + 1e-9 * s.dt() {
        k += 1;
    }
    let t1 = cap.min(time(k.min(s.npts() - 1)));
    (t1, record.accel(t), record.accel(t1))
}

/// Bisection of [a, b] where `left(a)` holds and `left(b)` does not, for at most `iterations`
/// halvings or down to adjacent floating-point numbers: the final bracket (a, b).
fn bisect(mut a: f64, mut b: f64, iterations: usize, left: impl Fn(f64) -> bool) -> (f64, f64) {
    for _ in 0..iterations {
        let mid = 0.5 * (a + b);
        if mid <= a || mid >= b {
            break;
        }
        if left(mid) { a = mid } else { b = mid }
    }
    (a, b)
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

/// Largest |f(y)| over a step whose rate is g(y): samples plus interior zeros of the rate.
fn extremum_of<const N: usize>(
    dense: &Dense<N>,
    t_end: f64,
    value: impl Fn(&[f64; N]) -> f64,
    rate: impl Fn(&[f64; N]) -> f64,
) -> f64 {
    const SAMPLES: usize = 4;
    let t0 = dense.t0;
    let mut t_prev = t0;
    let mut r_prev = rate(&dense.state(t0));
    let mut best = value(&dense.state(t0)).abs();
    for k in 1..=SAMPLES {
        let t = t0 + (t_end - t0) * k as f64 / SAMPLES as f64;
        let y = dense.state(t);
        let r = rate(&y);
        best = best.max(value(&y).abs());
        if r_prev * r < 0.0 {
            let (mut a, mut b) = (t_prev, t);
            for _ in 0..60 {
                let mid = 0.5 * (a + b);
                if rate(&dense.state(mid)) * r_prev > 0.0 {
                    a = mid
                } else {
                    b = mid
                }
                if b - a < 1e-15 * t.abs().max(1.0) {
                    break;
                }
            }
            best = best.max(value(&dense.state(0.5 * (a + b))).abs());
        }
        t_prev = t;
        r_prev = r;
    }
    best
}

impl<const N: usize> OdeSystem<N> for FlexibleModel<'_> {
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
        }
    }

    fn events(&self, t: f64, y: &[f64; N], g: &mut [f64]) {
        for (i, gi) in g.iter_mut().enumerate() {
            *gi = self.event_value(self.events[i], t, y);
        }
    }

    fn sign_after_zero(&self, index: usize, _t: f64, y: &[f64; N]) -> f64 {
        match self.events[index] {
            // At uplift (θ = θ̇ = 0, sθ̈ > 0) the base moves onto its pivot's side. Knowing
            // this matters: after an impact the uplift margin can already be falling, so the
            // base lands again within the first step, a crossing an undetermined start misses.
            Ev::Impact if y[3] == 0.0 => 1.0,
            Ev::Impact => (self.pivot * y[3]).signum(),
            // From rest (Ẋ = 0) |Ẋ| grows.
            Ev::Sequential if self.x_xdot(y).1 == 0.0 => 1.0,
            _ => 0.0,
        }
    }
}

impl<const N: usize> SimModel<N> for FlexibleModel<'_> {
    fn start(&mut self, y: &mut [f64; N]) -> Action {
        if self.initial_rotation != 0.0 {
            self.phase = Phase::Rocking;
            self.pivot = self.initial_rotation.signum();
            y[2] = self.initial_rotation;
            // Released from rest with the device relaxed: flywheels sit where the mass is.
            let (x, _) = self.x_xdot(y);
            for i in 0..self.dev.flywheels() {
                y[4 + 2 * i] = x;
            }
        }
        if matches!(self.dev, DeviceModel::Sequential { .. }) {
            // From rest |Ẋ| can only grow: engaged from the start (at Ẋ = 0, no energy).
            self.seq_engaged = true;
            self.counters.engagements += 1;
        }
        Action::Continue
    }

    fn on_event(&mut self, index: usize, t: f64, y: &mut [f64; N]) -> Action {
        let action = self.apply_event(index, t, y);
        self.settle(action, t, y)
    }

    fn wake(&mut self, _t: f64, _y: &mut [f64; N]) -> Action {
        // The mass moves with any ground motion: this model never idles.
        Action::Continue
    }

    /// A column vibrating in full contact decays but never stops: the flexible structure is
    /// never at rest in the driver's sense (see [`SimModel::settled`] for the early stop).
    fn at_rest(&self, _t: f64, _y: &[f64; N]) -> bool {
        false
    }

    /// In full contact after the ground stopped, the energy E the structure can still draw on
    /// (its own, plus what the device can give back) can only decrease. The run may stop when
    /// E can neither lift the base (|u| ≤ √(2E/k), |u̇| ≤ √(2E/m) bound the uplift test) nor
    /// beat the deformation, drift and acceleration peaks already recorded.
    fn settled(&self, y: &[f64; N]) -> bool {
        if self.phase != Phase::Contact {
            return false;
        }
        let (returnable, device_force) = self.returnable_energy(y);
        let e = (self.energy_parts(y).structure + returnable).max(0.0);
        let u_max = (2.0 * e / self.k).sqrt();
        let v_max = (2.0 * e / self.m).sqrt();
        let column = self.k * u_max + self.c * v_max;
        let can_uplift = column * self.h + self.m * G * u_max >= self.m * G * self.b;
        // m ü = −(k u + c u̇) + Fd; a coupled mass only lowers |ü|.
        let accel_g = (column + device_force(e)) / (self.m * G);
        !can_uplift
            && u_max <= self.peaks.deformation
            && u_max / self.h <= self.peaks.drift
            && accel_g <= self.peaks.abs_acceleration_g
    }

    fn advance_exact(&mut self, t: f64, t_stop: f64, y: &mut [f64; N]) -> Option<(f64, Exact)> {
        self.advance_contact(t, t_stop, y)
    }

    fn observe_step(&mut self, dense: &Dense<N>, t_end: f64) {
        let deformation = extremum_on_step(dense, t_end, 0, 1);
        self.peaks.deformation = self.peaks.deformation.max(deformation);
        if self.phase == Phase::Rocking {
            let rot = extremum_on_step(dense, t_end, 2, 3);
            self.peaks.rotation = self.peaks.rotation.max(rot);
        }
        let drift = extremum_of(dense, t_end, |y| self.x_xdot(y).0, |y| self.x_xdot(y).1);
        self.peaks.drift = self.peaks.drift.max(drift / self.h);
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
        self.peaks.rotation = self.peaks.rotation.max(y[2].abs());
        self.peaks.deformation = self.peaks.deformation.max(y[0].abs());
        self.peaks.drift = self.peaks.drift.max(self.x_xdot(y).0.abs() / self.h);
        let a = self.absolute_acceleration(t, y, &dy);
        self.peaks.abs_acceleration_g = self.peaks.abs_acceleration_g.max(a.abs() / G);
    }

    fn observe_idle(&mut self, t0: f64, t1: f64) {
        let a = self.motion.peak_abs(t0, t1);
        self.peaks.abs_acceleration_g = self.peaks.abs_acceleration_g.max(a / G);
    }

    fn energy(&self, y: &[f64; N]) -> Energy {
        self.energy_parts(y)
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
            Ev::Clutch(e) => e.name(),
        }
    }

    fn history_columns(&self) -> Vec<&'static str> {
        vec![
            "t",
            "u",
            "u_dot",
            "theta",
            "theta_dot",
            "ground_accel",
            "x",
            "x_dot",
            "flywheel_a_vel",
            "flywheel_b_vel",
            "clutch_force_a",
            "clutch_force_b",
            "device_force",
        ]
        .into_iter()
        .chain(Energy::COLUMNS)
        .collect()
    }

    fn history_row(&self, t: f64, y: &[f64; N]) -> Vec<f64> {
        let (x, xdot) = self.x_xdot(y);
        let nf = self.dev.flywheels();
        let va = if nf >= 1 { y[5] } else { 0.0 };
        let vb = if nf >= 2 { y[7] } else { 0.0 };
        let (fa, fb, fd) = self.device_force(t, y);
        let e = self.energy_parts(y);
        vec![
            t,
            y[0],
            y[1],
            y[2],
            y[3],
            self.motion.accel(t),
            x,
            xdot,
            va,
            vb,
            fa,
            fb,
            fd,
        ]
        .into_iter()
        .chain(e.terms())
        .collect()
    }
}

#[cfg(test)]
mod tests {
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
        Motion::Pulse(Pulse::new(PulseShape::Sine, 3.0, 6.0))
    }

    /// The closed-form 2×2 solve satisfies the two rocking equations as written in MODEL.md,
    /// and a coupled mass enters exactly as the load Fd = −mc Ẍ.
    #[test]
    fn rocking_accelerations_satisfy_the_lagrange_equations() {
        let s = structure();
        let mo = motion();
        let mr = 0.7;
        for (pivot, y) in [
            (1.0, [0.03, -0.4, 0.05, 0.3]),
            (-1.0, [-0.02, 0.5, -0.08, 0.2]),
        ] {
            for mc in [0.0, mr] {
                let mut model = FlexibleModel::new(&s, DeviceModel::Coupled { mr }, &mo, 0.0);
                model.phase = Phase::Rocking;
                model.pivot = pivot;
                let (fd_ext, ag) = (0.3, 1.7);
                let (udd, thdd) = model.accelerations(ag, &y, fd_ext, mc);
                let kin = model.kinematics(y[0], y[2]);
                let xdd = model.xddot(&y, &[y[1], udd, y[3], thdd]);
                let fd = fd_ext - mc * xdd;
                let (m, k, c, h, l) = (model.m, model.k, model.c, model.h, kin.lever);
                let (u, ud, thd) = (y[0], y[1], y[3]);
                let e1 =
                    m * udd + m * h * thdd + m * l * thd * thd - m * G * kin.sin + k * u + c * ud
                        - (fd - m * ag) * kin.cos;
                let e2 = m * h * udd + m * (l * l + h * h) * thdd - 2.0 * m * l * ud * thd
                    + m * G * kin.z
                    - (fd - m * ag) * kin.y;
                assert!(e1.abs() < 1e-12 && e2.abs() < 1e-12, "{e1} {e2}");
            }
        }
    }

    /// A coupled mass scales Ẍ by a factor in (0, 1]: the sequential law may decide on the
    /// bare Ẍ whether or not mr is engaged.
    #[test]
    fn coupled_mass_keeps_the_sign_of_the_horizontal_acceleration() {
        let s = structure();
        let mo = motion();
        let mut model = FlexibleModel::new(&s, DeviceModel::Coupled { mr: 1.0 }, &mo, 0.0);
        model.phase = Phase::Rocking;
        for (pivot, y) in [
            (1.0, [0.03, -0.4, 0.05, 0.3]),
            (-1.0, [-0.02, 0.5, -0.08, 0.2]),
        ] {
            model.pivot = pivot;
            for ag in [-3.0, -0.5, 0.0, 0.5, 3.0] {
                let xdd = |mc: f64| {
                    let (udd, thdd) = model.accelerations(ag, &y, 0.0, mc);
                    model.xddot(&y, &[y[1], udd, y[3], thdd])
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
        let s = structure();
        let mo = motion();
        let dev = DeviceModel::new(&Device::Sequential { sigma: 0.5 }, s.mass, 1.0);
        for pivot in [1.0, -1.0] {
            let mut model = FlexibleModel::new(&s, dev, &mo, 0.0);
            model.phase = Phase::Rocking;
            model.pivot = pivot;
            model.seq_engaged = true;
            let mut y = [0.0; 8];
            y[0] = 0.01 * pivot;
            y[1] = -0.2 * pivot;
            y[3] = -0.05 * pivot;
            let before = SimModel::<8>::energy(&model, &y);
            let xdot = model.x_xdot(&y).1;
            model.impact(10.0, &mut y);
            let after = SimModel::<8>::energy(&model, &y);
            assert_eq!(model.phase, Phase::Contact);
            assert!((model.x_xdot(&y).1 - xdot).abs() < 1e-15);
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
        let s = structure();
        let mo = motion();
        let dev = DeviceModel::new(&Device::Sequential { sigma: 0.5 }, s.mass, 1.0);
        let mut model = FlexibleModel::new(&s, dev, &mo, 0.0);
        model.phase = Phase::Rocking;
        for side in [1.0, -1.0] {
            model.pivot = side;
            for (u, ud) in [(0.02, 0.0), (0.03, 0.1), (-0.03, 0.2), (0.05, -0.3)] {
                let y = [u, ud, 0.0, 0.0];
                for (fd, mc) in [(0.0, 0.0), (5.0, 0.0), (0.0, 1.0)] {
                    let thdd = model.accelerations(2.0, &y, fd, mc).1;
                    let margin = model.uplift_margin(side, &y);
                    assert_eq!((side * thdd > 0.0), (margin > 0.0), "{side} {u} {ud}");
                }
            }
        }
    }
}
