//! Housner's rigid block with an inerter device (docs/MODEL.md "Rigid block"; paper §2, §3, §5),
//! as a [`Body`] of the rocking shell.
//!
//! State: [θ, θ̇ | flywheels | accumulators] ([`super::shell::Layout`]); the block's own
//! accumulator is the work of the Dirac impact moment.

use super::column::HistoryColumn;
use super::device::{DeviceModel, Returnable};
use super::shell::{Body, Landing, Mode, OwnLoss, Rocking};
use super::{Ledger, Measures, Peaks, extremum_of_component};
use crate::excitation::Motion;
use crate::scene::{Form, Impact, RigidBlock};
use crate::solver::{Dense, Direction, no_root_inside};
use crate::trig;
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

/// The rigid block in the rocking shell.
pub type RigidModel<'m> = Rocking<'m, RigidBody>;

const THETA: usize = 0;
const THETA_DOT: usize = 1;

/// The equations actually integrated (a scene's `Form::Auto` is resolved before the model is
/// built, by [`Form::resolve`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Equations {
    /// The exact trigonometric equations.
    Trigonometric,
    Slender,
}

pub struct RigidBody {
    r: f64,
    alpha: f64,
    m: f64,
    form: Equations,
    /// p² = 3g/(4R).
    p2: f64,
    /// The constant part of the gravity the block feels ([`Motion::gravity`]); p² and 1/g
    /// are derived from it once, and a vertical motion enters the right-hand side as the
    /// factor g_eff(t)/g of the restoring moment.
    g: f64,
    inv_g: f64,
    i0: f64,
    sin_a: f64,
    cos_a: f64,
    /// tan α (exact) or α (slender): uplift needs |a_g| > g · this.
    uplift_ratio: f64,
    restitution_override: Option<f64>,
    /// Dirac impact: (width n, zone half-width θi).
    dirac: Option<(f64, f64)>,
    /// Kinetic energy at entry into the Dirac zone while the impact moment is active.
    dirac_energy: Option<f64>,
    /// Below this post-impact rate the block is put to rest (its next excursion would be
    /// < 1e-10 α): Zeno-safe chattering.
    rest_rate: f64,
    /// Deflection scale of a device spring, for the error control.
    deflection: f64,
}

impl<'m> RigidModel<'m> {
    pub fn new(
        block: &RigidBlock,
        device: DeviceModel,
        impact: Impact,
        motion: &'m Motion,
        initial_rotation: f64,
    ) -> Self {
        let mut body = RigidBody::new(block, &device, impact, motion.gravity().g());
        // A constant vertical acceleration changes p² to p² g_rest/g for good: so does the
        // rate below which the chattering block is put to rest (exact similarity, MODEL.md).
        let g_rest = motion.gravity().at_rest();
        if g_rest != body.g {
            body.rest_rate =
                REST_EXCURSION.sqrt() * (body.p2 * g_rest / body.g).sqrt() * block.alpha;
        }
        Rocking::with_body(body, device, motion, initial_rotation)
    }
}

impl RigidBody {
    fn new(block: &RigidBlock, device: &DeviceModel, impact: Impact, g: f64) -> Self {
        let r = block.size;
        let p2 = 3.0 * g / (4.0 * r);
        let form = match block.form {
            Form::Slender => Equations::Slender,
            Form::Exact | Form::Auto => Equations::Trigonometric,
        };
        let (restitution_override, dirac) = match impact {
            Impact::Housner { restitution } => (restitution, None),
            Impact::Dirac { width } => (None, Some((width, dirac_zone(width)))),
        };
        // A flywheel position enters the physics only through the spring deflection
        // δ = x − y, whose scale is the deflection that carries the uplift force m g tanα:
        // resolving y to rtol·Rα left clutch forces with ~1e-3 relative error and peaks
        // drifting by 1% at rtol 1e-6.
        let x = r * block.alpha;
        let deflection = match device.spring_stiffness() {
            Some(k) => block.mass * g * block.alpha.tan() / k,
            None => x,
        }
        .min(x);
        RigidBody {
            r,
            alpha: block.alpha,
            m: block.mass,
            form,
            p2,
            g,
            inv_g: 1.0 / g,
            i0: 4.0 / 3.0 * block.mass * r * r,
            // From the same function as `sc`, so that X = 0 at θ = 0 exactly: glibc's and
            // libm's differ by an ulp for ~2 % of α, and an X of 1e-16 at uplift gave a
            // clutch function a spurious sign at its restart (an extra event).
            sin_a: trig::sin(block.alpha),
            cos_a: trig::cos(block.alpha),
            uplift_ratio: match form {
                Equations::Trigonometric => block.alpha.tan(),
                Equations::Slender => block.alpha,
            },
            restitution_override,
            dirac,
            dirac_energy: None,
            rest_rate: REST_EXCURSION.sqrt() * p2.sqrt() * block.alpha,
            deflection,
        }
    }

    /// S = sin(sα − θ), C = cos(sα − θ) (slender: S = sα − θ, C = 1). The body's sines and
    /// cosines are fdlibm's (musl's algorithms, < 1 ulp like glibc's), inline for |sα − θ| ≤
    /// π/4 ([`trig`]) and the `libm` crate's beyond: glibc's sincos saves and restores the SSE
    /// rounding mode on every call, which perf put at 14 % of a mechanistic scene's time; with
    /// libm the scene ran 10 % faster (the bare block 7 %). (glibc's sin stays on the pulses'
    /// phases, up to 2π, where libm's was slower.)
    #[inline]
    fn sc(&self, pivot: f64, theta: f64) -> (f64, f64) {
        let a = pivot * self.alpha - theta;
        match self.form {
            Equations::Trigonometric => trig::sincos(a),
            Equations::Slender => (a, 1.0),
        }
    }

    fn dirac_moment(&self, m: &Mode, theta: f64, thetadot: f64) -> f64 {
        match (self.dirac_energy, self.dirac) {
            (Some(e_ini), Some((n, _))) => {
                let r = self.restitution(m);
                -thetadot.signum() * 2.0 * e_ini * (1.0 - r) * (-(theta / n).powi(2)).exp()
                    / (n * PI.sqrt())
            }
            _ => 0.0,
        }
    }

    fn restitution(&self, m: &Mode) -> f64 {
        if let Some(r) = self.restitution_override {
            return r;
        }
        let mr = m.coupled_mass();
        if mr > 0.0 {
            inerter_restitution(self.alpha, mr / self.m)
        } else {
            housner_restitution(self.alpha)
        }
    }

    /// Ẍ = R (C θ̈ + S θ̇²) for a given θ̈ (slender: R θ̈), (S, C) = `k`.
    fn xddot_of(&self, k: &(f64, f64), y: &[f64], thetaddot: f64) -> f64 {
        let (s, c) = *k;
        match self.form {
            Equations::Trigonometric => self.r * (c * thetaddot + s * y[THETA_DOT] * y[THETA_DOT]),
            Equations::Slender => self.r * thetaddot,
        }
    }

    fn drift_of(&self, theta: f64) -> f64 {
        let x = match self.form {
            Equations::Trigonometric => self.r * (self.sin_a - trig::sin(self.alpha - theta.abs())),
            Equations::Slender => self.r * theta.abs(),
        };
        x / (self.r * self.cos_a)
    }

    fn potential(&self, s: f64, c: f64) -> f64 {
        match self.form {
            Equations::Trigonometric => self.m * self.g * self.r * (c - self.cos_a),
            Equations::Slender => 0.5 * self.m * self.g * self.r * (self.alpha.powi(2) - s * s),
        }
    }
}

impl Body for RigidBody {
    /// (S, C) of [`RigidBody::sc`].
    type Kin = (f64, f64);
    const COORDINATES: &'static [HistoryColumn] = &[HistoryColumn::Theta, HistoryColumn::ThetaDot];
    const THETA: usize = THETA;
    const THETA_DOT: usize = THETA_DOT;
    const MOVES_IN_CONTACT: bool = false;
    const OWN_LOSS: OwnLoss = OwnLoss::Impact;

    fn mass(&self) -> f64 {
        self.m
    }

    #[inline]
    fn kin(&self, m: &Mode, y: &[f64]) -> (f64, f64) {
        self.sc(m.pivot, y[THETA])
    }

    /// Horizontal position and velocity of the centre of mass.
    #[inline]
    fn x_xdot_kin(&self, m: &Mode, k: &(f64, f64), y: &[f64]) -> (f64, f64) {
        if !m.rocking() {
            return (0.0, 0.0);
        }
        let (s, c) = *k;
        let x = match self.form {
            Equations::Trigonometric => self.r * (m.pivot * self.sin_a - s),
            Equations::Slender => self.r * y[THETA],
        };
        (x, self.r * c * y[THETA_DOT])
    }

    fn xddot(&self, m: &Mode, k: &(f64, f64), y: &[f64], dy: &[f64]) -> f64 {
        if !m.rocking() {
            return 0.0;
        }
        self.xddot_of(k, y, dy[THETA_DOT])
    }

    /// Vertical velocity of the centre of mass: Y = R C (slender: R(1 − S²/2)), Ẏ = R S θ̇.
    fn y_dot_kin(&self, m: &Mode, k: &(f64, f64), y: &[f64]) -> f64 {
        if !m.rocking() {
            return 0.0;
        }
        self.r * k.0 * y[THETA_DOT]
    }

    /// (1 + ¾σC²) θ̈ = −p²((g_eff/g) S + (a_g/g) C) − ¾σ C S θ̇² + (Fd R C + M)/I0, M the
    /// Dirac moment, g_eff = g + ü_v.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    fn derivatives(
        &self,
        m: &Mode,
        k: &(f64, f64),
        ag: f64,
        g_eff: f64,
        y: &[f64],
        fd: f64,
        mc: f64,
        dy: &mut [f64],
    ) -> f64 {
        if !m.rocking() {
            return 0.0;
        }
        let (theta, thetadot) = (y[THETA], y[THETA_DOT]);
        let (s, c) = *k;
        let moment = self.dirac_moment(m, theta, thetadot);
        let sigma = mc / self.m;
        // Without a vertical motion g_eff is g itself: the constant-gravity form, bit for bit.
        let mut num = if g_eff == self.g {
            -self.p2 * (s + ag * self.inv_g * c)
        } else {
            -self.p2 * (g_eff * self.inv_g * s + ag * self.inv_g * c)
        };
        // Without a device force, a Dirac moment or a coupled mass the two divisions add
        // nothing but ~25 cycles of latency to every stage (the bare block: θ̈ waits on them).
        if fd != 0.0 || moment != 0.0 {
            num += (fd * self.r * c + moment) / self.i0;
        }
        dy[THETA] = thetadot;
        dy[THETA_DOT] = if sigma > 0.0 {
            let den = 1.0 + 0.75 * sigma * c * c;
            if self.form == Equations::Trigonometric {
                num -= 0.75 * sigma * c * s * thetadot * thetadot;
            }
            num / den
        } else {
            num
        };
        -moment * thetadot
    }

    /// Ẍ of the bare block (no device force, no coupled mass).
    fn bare_xddot(&self, m: &Mode, k: &(f64, f64), t: f64, y: &[f64]) -> f64 {
        let (s, c) = *k;
        let ag = m.motion.accel(t);
        let g_eff = m.motion.gravity().at(t);
        let restoring = if g_eff == self.g {
            s
        } else {
            g_eff * self.inv_g * s
        };
        let thdd = -self.p2 * (restoring + ag * self.inv_g * c)
            + self.dirac_moment(m, y[THETA], y[THETA_DOT]) / self.i0;
        self.xddot_of(k, y, thdd)
    }

    /// s (Fd − m a_g) − m g tan α (slender: α): the ground (and a device spring) must beat
    /// the block's weight moment.
    fn uplift_margin(&self, m: &Mode, side: f64, t: f64, y: &[f64]) -> f64 {
        let fd = m.dev.spring_force(0.0, m.layout.device_states(y));
        side * (fd - self.m * m.motion.accel(t))
            - self.m * m.motion.gravity().at(t) * self.uplift_ratio
    }

    /// The centre of mass passes over the pivot: |θ| ≥ α.
    fn overturn_margin(&self, m: &Mode, y: &[f64]) -> f64 {
        m.pivot * y[THETA] - self.alpha
    }

    fn overturn_margin_rate(&self, m: &Mode, _y: &[f64], dy: &[f64]) -> Option<f64> {
        Some(m.pivot * dy[THETA])
    }

    /// Housner's impact: θ̇⁺ = √r θ̇⁻ about the other corner (r by Eq. 16 with a coupled
    /// inerter); the Dirac model's moment has already taken the energy. Below the rest rate the
    /// block is put flat, its remaining kinetic energy booked as a reset.
    fn impact(&mut self, m: &mut Mode, ledger: &mut Ledger, y: &mut [f64]) -> Landing {
        if self.dirac.is_some() {
            self.dirac_energy = None;
        } else {
            let r = self.restitution(m);
            let ke = 0.5 * self.i0 * y[THETA_DOT] * y[THETA_DOT]
                + m.coupled_kinetic(self.x_xdot(m, y).1);
            ledger.impact += (1.0 - r) * ke;
            y[THETA_DOT] *= r.sqrt();
        }
        y[THETA] = 0.0;
        m.pivot = -m.pivot;
        if y[THETA_DOT].abs() < self.rest_rate {
            let ke = 0.5 * self.i0 * y[THETA_DOT] * y[THETA_DOT]
                + m.coupled_kinetic(self.x_xdot(m, y).1);
            ledger.reset += ke;
            m.switch_engaged = false;
            self.dirac_energy = None;
            y[THETA_DOT] = 0.0;
            return Landing::Flat;
        }
        Landing::Rocking
    }

    fn energy(&self, m: &Mode, y: &[f64]) -> f64 {
        if !m.rocking() {
            return 0.0;
        }
        let (s, c) = self.sc(m.pivot, y[THETA]);
        0.5 * self.i0 * y[THETA_DOT] * y[THETA_DOT] + self.potential(s, c)
    }

    /// After the ground stops, the block can only draw on its own energy plus what the device
    /// can give back (a coupled or spring-mounted inerter returns its kinetic energy, a
    /// one-way clutch only its spring energy, the sequential law none). From that energy E:
    /// reachable |θ| from PE(θ) ≤ E, and |ẍ| ≤ R(p² s_max + |Fd|max R/I0 + (1 + ¾σ) s_max θ̇²max)
    /// with θ̇²max = 2E/I0 and |Fd|max = 2√(2kE). The Dirac model is excluded (its impact
    /// moment is the acceleration being studied).
    fn settled(&self, m: &Mode, y: &[f64], device: Returnable, peaks: &Peaks) -> bool {
        // A constant vertical acceleration outlives the ground: the reach below is for g.
        if self.dirac.is_some() || !m.rocking() || m.motion.gravity().at_rest() != self.g {
            return false;
        }
        let e = self.energy(m, y) + device.energy;
        let mgr = self.m * self.g * self.r;
        let reach = match self.form {
            Equations::Trigonometric => {
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
            Equations::Trigonometric => self.sin_a,
            Equations::Slender => self.alpha,
        };
        let sigma = m.dev.mr() / self.m;
        let rate2 = 2.0 * e / self.i0;
        let force = 2.0 * (2.0 * device.k * e).sqrt();
        let accel = self.r
            * (self.p2 * s_max + force * self.r / self.i0 + (1.0 + 0.75 * sigma) * s_max * rate2)
            / self.g;
        // |θ̈| ≤ p² s_max + |Fd|max R/I0 + ¾σ s_max θ̇²max with the ground at rest.
        let angular = s_max + (force * self.r / self.i0 + 0.75 * sigma * s_max * rate2) / self.p2;
        reach < peaks.rotation
            && accel < peaks.abs_acceleration_g
            && angular < peaks.angular_acceleration_p2.unwrap_or(0.0)
    }

    /// The drift is a monotone function of |θ| (the same for the step's extremum and the
    /// running peak), so it is read off the rotation's extremum at no cost.
    fn observe_step<const N: usize>(
        &self,
        m: &Mode,
        _measures: Measures,
        dense: &Dense<N>,
        t_end: f64,
        peaks: &mut Peaks,
    ) {
        // No |θ| on the step's interpolant exceeds its bound: a step whose bound is below the
        // running peak cannot raise it (nor the drift), and skipping it changes nothing.
        if m.rocking() && !below_peak(dense.bound(THETA), peaks.rotation) {
            let rot = extremum_of_component(dense, t_end, THETA, THETA_DOT);
            peaks.rotation = peaks.rotation.max(rot);
            peaks.drift = peaks.drift.max(self.drift_of(rot));
        }
    }

    /// |Ẍ + a_g| ≤ R(|θ̈| + S_max θ̇²) + |a_g|max with θ̈ the interpolant's rate of θ̇ (what
    /// the absolute acceleration's search reads) and S_max = sin(α + |θ|max) (slender:
    /// α + |θ|max).
    ///
    /// |θ̈|/p²: the search reads θ̈ from the right-hand side at the interpolated state (the
    /// interpolant's own rate is an order less accurate: 7.6e-6 off for free rocking with
    /// DOP853 at rtol 1e-6, against 2e-15). The two differ by the interpolant's derivative
    /// error, for which there is no cheap bound, so the interpolant's rate bound is enlarged
    /// by [`ANGULAR_BOUND_MARGIN`]. Not a proof; measured (16 right-hand-side samples per
    /// step, every step of the Fig. 8 scenes with each device law at rtol 1e-4 … 1e-10 with
    /// both methods, and of the shipped rigid studies): the samples never exceeded 0.99999
    /// of the unenlarged bound. With the ground at rest, a device without springs and no
    /// Dirac moment, the rigorous (1 + ¾σC²)|θ̈| = |p²S + ¾σCSθ̇²| ≤ p²S_max + ¾σS_max θ̇²
    /// is used where it is smaller.
    fn acceleration_bounds(
        &self,
        m: &Mode,
        value: impl Fn(usize) -> f64,
        rate: impl Fn(usize) -> f64,
        ground: f64,
    ) -> (Option<f64>, Option<f64>) {
        if !m.rocking() {
            return (Some(ground / self.g), Some(0.0));
        }
        let (theta, w, wdot) = (value(THETA), value(THETA_DOT), rate(THETA_DOT));
        let s_max = match self.form {
            Equations::Trigonometric if self.alpha + theta < 0.5 * PI => {
                libm::sin(self.alpha + theta)
            }
            Equations::Trigonometric => 1.0,
            Equations::Slender => self.alpha + theta,
        };
        let abs_g = (self.r * (wdot + s_max * w * w) + ground) / self.g;
        let mut angular = wdot / self.p2 * (1.0 + ANGULAR_BOUND_MARGIN);
        let springless = m.dev.spring_stiffness().is_none();
        // A vertical motion: only a constant one, whose g_eff scales the restoring moment.
        let gravity = m.motion.gravity();
        if ground == 0.0 && springless && self.dirac.is_none() && gravity.is_constant() {
            let sigma = m.coupled_mass() / self.m;
            let weight = s_max * (gravity.at_rest() / self.g);
            angular = angular.min(weight + 0.75 * sigma * s_max * w * w / self.p2);
        }
        (Some(abs_g), Some(angular))
    }

    /// Flat, nothing is observed. Rocking, where θ̇ keeps its sign over the step, |θ| is
    /// monotone and its largest value on the step is at an end: if that lies below the running
    /// peak by more than [`REACH_MARGIN`]·α (far above the interpolant's distance from the
    /// solution, a step's error), [`Body::observe_step`] would skip the step, having built the
    /// dense output only to read its bound. θ̇ is taken to keep its sign where the event
    /// screen's test ([`no_root_inside`]) clears it from θ̇ and θ̈ at the ends: the assumption
    /// (the solution resolved on the step's scale) under which the integrator already skips
    /// the event sub-samples of such a step. Where θ̇ may cross zero (a turning point inside)
    /// but θ̈ has one sign at both ends, θ̇ is taken to be monotone under the same assumption:
    /// the turning point then lies within |θ̇0|·τ of θ0 and |θ̇1|·(h − τ) of θ1 for its time
    /// τ, so |θ| stays below the larger end plus h·|θ̇0||θ̇1|/(|θ̇0| + |θ̇1|), and the step is
    /// skipped where that lies below the peak by the same margin (the observation would find
    /// nothing there: a run that reads every step's interior reports the same peaks). On the
    /// Fig. 8 bare block the later, smaller rocking cycles no longer build the dense output.
    fn step_may_raise_peaks(
        &self,
        m: &Mode,
        (t0, y0, f0): (f64, &[f64], &[f64]),
        (t1, y1, f1): (f64, &[f64], &[f64]),
        peaks: &Peaks,
    ) -> bool {
        if !m.rocking() {
            return false;
        }
        let h = t1 - t0;
        let (w0, w1) = (y0[THETA_DOT], y1[THETA_DOT]);
        let (a0, a1) = (f0[THETA_DOT], f1[THETA_DOT]);
        let ends = y0[THETA].abs().max(y1[THETA].abs());
        let reach = if no_root_inside((w0, w0), h * a0, w1, h * a1) {
            ends
        } else if a0 * a1 > 0.0 && w0 != w1 {
            // (False for a NaN θ̈: such a step is searched.)
            let (v0, v1) = (w0.abs(), w1.abs());
            ends + h.abs() * v0 * v1 / (v0 + v1)
        } else {
            return true;
        };
        reach + REACH_MARGIN * self.alpha >= peaks.rotation
    }

    fn observe_point(&self, _m: &Mode, _measures: Measures, y: &[f64], peaks: &mut Peaks) {
        peaks.rotation = peaks.rotation.max(y[THETA].abs());
        peaks.drift = peaks.drift.max(self.drift_of(y[THETA]));
    }

    /// Rotations ~α, rates ~pα; a flywheel's position and velocity ~ the spring deflection and
    /// p times it (a free flywheel's velocity error integrates into its position, so resolving
    /// the velocity only to the block's speed p R α, as this did, undid the position's scale:
    /// on Landers with a 50 p clutch the peak was 17 % off at the default rtol, 1.9 % now, for
    /// 14 % more RHS calls).
    fn tolerance_scales(&self, _m: &Mode) -> (Vec<f64>, [f64; 2]) {
        let (a, p) = (self.alpha, self.p2.sqrt());
        (vec![a, p * a], [self.deflection, p * self.deflection])
    }

    /// Flat on the ground with the device at rest (the shell checks), nothing moves until the
    /// ground acceleration exceeds g·tanα: do not integrate. Idle to the end of the motion if
    /// it never does (the block still rides the ground).
    /// With a vertical motion the level is g_eff·tanα for a constant g_eff, otherwise a
    /// lower bound of it ([`crate::excitation::Gravity::uplift_level`]), from which the
    /// shell's wake integrates if the ground does not lift the block yet.
    fn idle_until(&self, m: &Mode, t: f64) -> Option<f64> {
        let level = m.motion.gravity().uplift_level(self.uplift_ratio);
        Some(
            m.motion
                .first_exceedance(t, level)
                .unwrap_or_else(|| m.motion.end().max(t)),
        )
    }

    /// Inside an active Dirac zone: a step may rotate the block by at most n/2 at its entry
    /// rate (the zone's θi = 1.82 n takes ≥ 4 steps; the rate only falls inside it). Without
    /// this a step sized before the zone, whose stages land past the Gaussian, crossed θ = 0
    /// with the moment unseen by its error estimate and the impact's energy loss went missing
    /// at rtol ≥ 1e-5 (θmax/α 0.505 instead of 0.470 in the paper's Fig. 5 scene).
    ///
    /// Flat under a varying g_eff, nothing moves and the uplift events read the ground alone:
    /// steps at most a pulse's sampling step, so no lobe of the margin lies inside one.
    fn max_step(&self, m: &Mode) -> f64 {
        match (self.dirac_energy, self.dirac) {
            (Some(e_ini), Some((n, _))) if e_ini > 0.0 => 0.5 * n / (2.0 * e_ini / self.i0).sqrt(),
            _ if !m.rocking() => m.motion.gravity().sampling_step().unwrap_or(f64::INFINITY),
            _ => f64::INFINITY,
        }
    }

    fn angular_acceleration_scale(&self) -> Option<f64> {
        Some(self.p2)
    }

    fn wake_side(&self, m: &Mode, t: f64) -> Option<f64> {
        let ag = m.motion.accel(t);
        (ag.abs() > m.motion.gravity().at(t) * self.uplift_ratio).then(|| -ag.signum())
    }

    fn own_events(&self) -> usize {
        usize::from(self.dirac.is_some())
    }

    /// The Dirac zone: entered when |θ| falls below θi, left when the block turns back.
    fn own_event_value(&self, m: &Mode, _index: usize, y: &[f64]) -> f64 {
        match (m.rocking(), self.dirac_energy) {
            (false, _) => 1.0,
            // Active: stop when the block turns back (sθ̇ becomes positive).
            (true, Some(_)) => m.pivot * y[THETA_DOT],
            (true, None) => m.pivot * y[THETA] - self.dirac.map_or(0.0, |d| d.1),
        }
    }

    fn own_event_direction(&self, _index: usize) -> Direction {
        if self.dirac_energy.is_some() {
            Direction::Rising
        } else {
            Direction::Falling
        }
    }

    fn own_event_name(&self, _index: usize) -> &'static str {
        "dirac_zone"
    }

    fn apply_own_event(&mut self, _index: usize, y: &mut [f64]) {
        self.dirac_energy = match self.dirac_energy {
            Some(_) => None,
            None => Some(0.5 * self.i0 * y[THETA_DOT] * y[THETA_DOT]),
        };
    }
}

/// Twice the largest excursion, in units of α², of a block put to rest after an impact
/// (θ̇ below √(2e-10)·p·α: its next excursion would be below 1e-10 α).
const REST_EXCURSION: f64 = 2e-10;

/// Margin, as a fraction of α, between the bound of |θ| on a step and the running peak
/// rotation below which the step is not searched
/// ([`RigidBody::step_may_raise_peaks`]): the interpolant's distance from the solution (a
/// step's error, ~rtol·α) is far below it.
const REACH_MARGIN: f64 = 0.01;

/// Relative enlargement of the interpolant's rate bound of θ̇ before it stands for a bound
/// of the right-hand side's θ̈ ([`RigidBody::acceleration_bounds`]).
const ANGULAR_BOUND_MARGIN: f64 = 1e-3;

/// Whether a bound of a step's values lies safely below the running peak (a margin for the
/// rounding of the bound and of the values it bounds).
pub(super) fn below_peak(bound: f64, peak: f64) -> bool {
    bound * (1.0 + 1e-12) < peak
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The centre of mass sits over the pivot line at θ = 0 exactly (X = 0, drift 0) for
    /// every α, on either pivot: a clutch function reading X is exactly 0 at uplift.
    #[test]
    fn kinematics_vanish_exactly_at_zero_rotation() {
        for k in 1..=90 {
            let block = RigidBlock {
                size: 1.5,
                alpha: (0.5 * k as f64).to_radians(),
                mass: 1.0,
                form: Form::Exact,
            };
            let body = RigidBody::new(
                &block,
                &DeviceModel::None,
                Impact::default(),
                crate::excitation::G,
            );
            for pivot in [1.0, -1.0] {
                let (s, c) = body.sc(pivot, 0.0);
                assert_eq!(
                    (s, c),
                    (pivot * body.sin_a, body.cos_a),
                    "α {}°",
                    0.5 * k as f64
                );
            }
            assert_eq!(body.drift_of(0.0), 0.0);
        }
    }
}
