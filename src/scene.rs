//! A scene: everything needed to reproduce one simulation, as plain serde data. Studies expand
//! into scenes; `rocklab simulate` builds one from flags. Names follow the paper (σ, kθ, ρ, ε,
//! c̄, ξθ, fμ, η, up) so study files read like its figure captions.

use crate::excitation::{G, KinkPolicy, PulseShape};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    pub structure: Structure,
    pub device: Device,
    #[serde(default)]
    pub impact: Impact,
    pub excitation: Excitation,
    /// The vertical ground motion (absent: none, gravity constant; docs/MODEL.md "Vertical
    /// ground motion").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertical: Option<VerticalMotion>,
    /// Total simulated time (s); the run stops earlier only at overturning or rest.
    pub duration: f64,
    /// Relative tolerance of the integrator.
    #[serde(default = "default_rtol")]
    pub rtol: f64,
    /// Initial uplift rotation (rad), for free-rocking studies; 0 starts at rest on the ground.
    #[serde(default)]
    pub initial_rotation: f64,
    /// End the run once the ground has stopped and the energy left provably cannot raise any
    /// peak (the free-vibration tail). Peaks are unchanged; end time and final energies differ.
    #[serde(default)]
    pub stop_when_settled: bool,
    /// Advance the full-contact phase of a flexible structure with a linear device (none, or a
    /// rigidly coupled inerter) under a record in closed form instead of with the integrator
    /// (`false` forces the integrator; `stats.closed_form_steps` counts closed-form
    /// intervals). Serialized as `exact_contact` (study and scene files keep their names).
    #[serde(default = "default_closed_form_contact", rename = "exact_contact")]
    pub closed_form_contact: bool,
    /// Runge–Kutta pair of the integrator; `auto` chooses by `rtol` ([`Method::resolve`]).
    #[serde(default, skip_serializing_if = "Method::is_auto")]
    pub method: Method,
}

pub fn default_closed_form_contact() -> bool {
    true
}

/// The default relative tolerance, chosen from `rocklab bench`'s work-precision tables: the
/// cheapest tolerance at which every representative scene's peaks are within 1e-3 of the
/// rtol = 1e-12 reference (worst: the rigid mechanistic scene's acceleration peak, 8.3e-4;
/// at 1e-4 it is 7.5e-3). See BENCHMARKS.md.
pub fn default_rtol() -> f64 {
    1e-5
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Structure {
    Rigid(RigidBlock),
    Flexible(FlexibleStructure),
}

impl Structure {
    pub fn alpha(&self) -> f64 {
        match self {
            Structure::Rigid(b) => b.alpha,
            Structure::Flexible(f) => f.alpha,
        }
    }

    /// Frequency parameter p (rad/s): √(3g/4R) for a rectangular block, √(g/R0) for a point
    /// mass on a rocking base.
    pub fn p(&self) -> f64 {
        match self {
            Structure::Rigid(b) => (3.0 * G / (4.0 * b.size)).sqrt(),
            Structure::Flexible(f) => (G / f.r0).sqrt(),
        }
    }

    pub fn mass(&self) -> f64 {
        match self {
            Structure::Rigid(b) => b.mass,
            Structure::Flexible(f) => f.mass,
        }
    }
}

/// Housner's rectangular block.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigidBlock {
    /// Half-diagonal R (m).
    pub size: f64,
    /// Slenderness α (rad).
    pub alpha: f64,
    #[serde(default = "unit_mass")]
    pub mass: f64,
    #[serde(default)]
    pub form: Form,
}

/// Exact trigonometric equations, the small-α (slender) linearisation, or `auto`: the slender
/// form only where its error against the exact form is below the tolerance. Results record the
/// form actually used (`SceneResult::form_used`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Form {
    #[default]
    Exact,
    Slender,
    Auto,
}

/// The integrator's Runge–Kutta pair. Both locate events and restart identically; they differ
/// in cost per accuracy.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// DOP853 at and below [`DOP853_BELOW_RTOL`] unless a mechanistic clutch makes the scene
    /// event-dense; Dormand–Prince 5(4) otherwise.
    #[default]
    Auto,
    /// Dormand–Prince 5(4): 6 RHS calls per step.
    Dp54,
    /// DOP853 (8th order, 7th-order dense output): 15 RHS calls per step.
    Dop853,
}

/// The tolerance at and below which `auto` integrates with DOP853, from `rocklab bench`'s
/// work-precision tables (BENCHMARKS.md): on the Fig. 8 bare block DOP853 needs fewer RHS
/// calls at equal peak error from rtol 1e-4 down (769 against 3115 for errors ~1e-8), on the
/// mechanistic block (a restart every ~2 steps) more at every tolerance (restarts and
/// rejected steps cost it 15 and 12 calls). The threshold is conservative: studies at the
/// default rtol keep Dormand–Prince.
pub const DOP853_BELOW_RTOL: f64 = 1e-6;

impl Method {
    pub fn is_auto(&self) -> bool {
        *self == Method::Auto
    }

    /// The pair to integrate `scene` with (`Auto` resolved).
    pub fn resolve(self, scene: &Scene) -> Method {
        let event_dense = matches!(scene.device, Device::Mechanistic(_));
        match self {
            Method::Auto if scene.rtol <= DOP853_BELOW_RTOL && !event_dense => Method::Dop853,
            Method::Auto => Method::Dp54,
            m => m,
        }
    }
}

/// Relative peak-rotation error of the slender form against the exact one, per α²: measured
/// 1.83 for α from 0.002 to 0.05 (rtol 1e-10, Fig. 8 pulse; `rocklab simulate --form`).
pub const SLENDER_ERROR_PER_ALPHA2: f64 = 1.83;

impl Form {
    /// The form to integrate: `Auto` becomes `Slender` only when its estimated error
    /// (with a safety factor 2) is below `rtol`.
    pub fn resolve(self, alpha: f64, rtol: f64) -> Form {
        match self {
            Form::Auto if 2.0 * SLENDER_ERROR_PER_ALPHA2 * alpha * alpha < rtol => Form::Slender,
            Form::Auto => Form::Exact,
            f => f,
        }
    }
}

/// Lumped mass on an elastic column over an uplifting rigid base (paper §6).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlexibleStructure {
    /// R0 = √(B² + H²) (m).
    pub r0: f64,
    pub alpha: f64,
    #[serde(default = "unit_mass")]
    pub mass: f64,
    /// Column damping ratio ξ.
    pub xi: f64,
    /// Column natural frequency ωn (rad/s).
    pub omega_n: f64,
}

fn unit_mass() -> f64 {
    1.0
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Device {
    None,
    /// Single inerter, no clutch.
    Inerter {
        sigma: f64,
        coupling: Coupling,
    },
    /// Twin clutched inerters, Makris–Kampas sequential law.
    Sequential {
        sigma: f64,
    },
    /// Twin clutched inerters with the mechanistic clutch of the paper.
    Mechanistic(Clutch),
}

impl Device {
    pub fn sigma(&self) -> f64 {
        match self {
            Device::None => 0.0,
            Device::Inerter { sigma, .. } | Device::Sequential { sigma } => *sigma,
            Device::Mechanistic(c) => c.sigma,
        }
    }

    pub fn name(&self) -> &'static str {
        match self {
            Device::None => "none",
            Device::Inerter { .. } => "inerter",
            Device::Sequential { .. } => "sequential",
            Device::Mechanistic(_) => "mechanistic",
        }
    }
}

/// How a single inerter is attached.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Coupling {
    /// mr joins the horizontal motion (infinitely stiff connection).
    Rigid,
    /// Explicit flywheel behind a linear spring, with optional damping.
    Flywheel {
        stiffness: ClutchStiffness,
        #[serde(default = "default_rho")]
        rho: f64,
        damping: Damping,
    },
}

/// Mechanistic clutch parameters (paper names).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Clutch {
    pub sigma: f64,
    #[serde(default)]
    pub stiffness: ClutchStiffness,
    /// Pinion radius ρ (m).
    #[serde(default = "default_rho")]
    pub rho: f64,
    /// tanh smoothing factor ε (per radian of flywheel rotation).
    #[serde(default = "default_epsilon")]
    pub epsilon: f64,
    #[serde(default)]
    pub damping: Damping,
    /// Dry friction force fμ as a fraction of mr·g.
    #[serde(default)]
    pub friction: f64,
    /// Friction transition coefficient η (s/rad).
    #[serde(default = "default_eta")]
    pub eta: f64,
    /// Gear play up (m).
    #[serde(default)]
    pub play: f64,
    #[serde(default)]
    pub reset: ResetRule,
}

pub fn default_rho() -> f64 {
    0.05
}
pub fn default_epsilon() -> f64 {
    1e6
}
pub fn default_eta() -> f64 {
    100.0
}

impl Clutch {
    pub fn paper_default(sigma: f64) -> Self {
        Clutch {
            sigma,
            stiffness: ClutchStiffness::default(),
            rho: default_rho(),
            epsilon: default_epsilon(),
            damping: Damping::default(),
            friction: 0.0,
            eta: default_eta(),
            play: 0.0,
            reset: ResetRule::Paper,
        }
    }
}

/// Clutch (or inerter spring) stiffness: the paper's kθ, or the clutch spring frequency
/// √(k/mr) = √(kθ/J) as a multiple of the structure's p. The paper gives no kθ but pins the
/// clutch frequency down: it calls the same §6 systems c̄ = 1 s⁻¹ (§6.2) and ξθ = 0.02 (§6.3),
/// and ξθ = c̄ / (2 √(kθ/J)), so √(kθ/J) = 25 rad/s. The default, 25 p, is that for the §6
/// structure (p = √(g/10 m) = 0.990 rad/s: 24.8 rad/s, ξθ = 0.02 ⇔ c̄ = 0.99 s⁻¹); at fixed
/// c̄ a stiffer clutch barely changes peaks (the paper's Fig. 18; docs/MODEL.md "Defaults").
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ClutchStiffness {
    KTheta(f64),
    FrequencyRatio(f64),
}

impl Default for ClutchStiffness {
    fn default() -> Self {
        ClutchStiffness::FrequencyRatio(25.0)
    }
}

/// Flywheel viscous damping: c̄ = c/J (1/s), or the ratio ξθ = c/(2√(kθ J)).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Damping {
    CBar(f64),
    XiTheta(f64),
}

impl Default for Damping {
    fn default() -> Self {
        Damping::CBar(1.0)
    }
}

/// Re-engagement reset with gear play (docs/MODEL.md): the paper's rule resets whenever the clutch
/// is disengaged (δ < up), the strict rule only once the gap has closed the other way (δ < 0).
/// `never` is the paper's counterfactual (§4: "if this is not done, then the clutch will be
/// prevented from re-engaging after the first engagement event"), there to measure that claim.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ResetRule {
    #[default]
    Paper,
    Strict,
    Never,
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Impact {
    /// Instantaneous impact, Housner's r (Eq. 3) or Eq. 16 with a rigidly attached inerter;
    /// `restitution` overrides r (1 makes impacts elastic).
    Housner {
        #[serde(default)]
        restitution: Option<f64>,
    },
    /// Gaussian impact moment of width n (rad) (§3).
    Dirac { width: f64 },
}

impl Default for Impact {
    fn default() -> Self {
        Impact::Housner { restitution: None }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Excitation {
    /// An analytic pulse: `amplitude` is its peak acceleration, `frequency` its ωg.
    Pulse {
        shape: PulseShape,
        amplitude: Amplitude,
        frequency: Frequency,
    },
    /// A Mavroeidis–Papageorgiou pulse given by its period Tp (s) and peak ground velocity
    /// (m/s) instead of peak acceleration and ωg.
    MpPulse {
        tp: f64,
        pgv: f64,
        gamma: f64,
        #[serde(default)]
        nu: f64,
    },
    /// A ground-motion record from the library (name, Table 1 number, or file path).
    Record {
        name: String,
        #[serde(default)]
        scale: RecordScale,
        /// Apply the baseline correction of `Series::baseline_corrected` (off by default).
        #[serde(default)]
        baseline: bool,
        /// How the integrator treats the kinks between samples (a numerical choice).
        #[serde(default)]
        kinks: KinkPolicy,
    },
}

/// A vertical ground acceleration ü_v(t), positive up: gravity becomes g + ü_v(t).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum VerticalMotion {
    /// A vertical record file (any format the record reader takes), aligned in time with the
    /// horizontal (zero after its end) and multiplied by the horizontal record's scale
    /// factor, so a scaled three-component recording keeps its V/H (factor 1 under a pulse).
    Record(String),
    /// An analytic pulse (the horizontal pulses' shapes); its amplitude is absolute: it does
    /// not follow a scaling of the horizontal motion.
    Pulse {
        shape: PulseShape,
        amplitude: Amplitude,
        frequency: Frequency,
    },
    /// ü_v = c·g at every time (a static change of gravity to (1 + c) g).
    Constant(f64),
    /// ü_v(t) = r·a_g(t), the horizontal acceleration after its scaling (r may be negative).
    Ratio(f64),
}

/// How a record is scaled.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RecordScale {
    /// a_g = factor · record (negative flips the polarity).
    Factor(f64),
    /// Scaled to this PGA (g).
    Pga(f64),
    /// Scaled to this PGV (m/s).
    Pgv(f64),
    /// Scaled to this PGA* = PGA/(g·tan α) of the scene's structure.
    PgaStar(f64),
    /// Scaled to this PGV* = PGV·p/(g·tan α) of the scene's structure.
    PgvStar(f64),
}

impl Default for RecordScale {
    fn default() -> Self {
        RecordScale::Factor(1.0)
    }
}

impl RecordScale {
    /// The factor that applies this scaling to a record with the given PGA (m/s²) and PGV
    /// (m/s), for a structure of slenderness `alpha` and frequency parameter `p` (the
    /// dimensionless PGA* and PGV* depend on them, so one value means the same for every
    /// structure of a family).
    pub fn factor(&self, pga: f64, pgv: f64, alpha: f64, p: f64) -> f64 {
        match *self {
            RecordScale::Factor(k) => k,
            RecordScale::Pga(target) => target * G / pga,
            RecordScale::Pgv(target) => target / pgv,
            RecordScale::PgaStar(target) => target * G * alpha.tan() / pga,
            RecordScale::PgvStar(target) => target * G * alpha.tan() / (p * pgv),
        }
    }

    /// The target value (or the factor), whatever it means.
    pub fn value(&self) -> f64 {
        match *self {
            RecordScale::Factor(v)
            | RecordScale::Pga(v)
            | RecordScale::Pgv(v)
            | RecordScale::PgaStar(v)
            | RecordScale::PgvStar(v) => v,
        }
    }
}

/// Pulse amplitude: absolute (A/g) or relative to the uplift threshold.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Amplitude {
    /// A/g.
    G(f64),
    /// A/(g·tan α) (the flexible-structure convention of the paper).
    TanAlphaRatio(f64),
    /// A/(g·α) (the rigid-block convention of the paper's Figs. 5, 8, 11, 12).
    AlphaRatio(f64),
}

impl Excitation {
    /// The same ground motion with every acceleration multiplied by `factor`: a pulse's peak,
    /// an MP pulse's PGV, a record's scale (or its target PGA / PGV).
    pub fn scaled(&self, factor: f64) -> Excitation {
        let mut e = self.clone();
        match &mut e {
            Excitation::Pulse { amplitude, .. } => {
                *amplitude = match *amplitude {
                    Amplitude::G(a) => Amplitude::G(a * factor),
                    Amplitude::TanAlphaRatio(r) => Amplitude::TanAlphaRatio(r * factor),
                    Amplitude::AlphaRatio(r) => Amplitude::AlphaRatio(r * factor),
                }
            }
            Excitation::MpPulse { pgv, .. } => *pgv *= factor,
            Excitation::Record { scale, .. } => {
                *scale = match *scale {
                    RecordScale::Factor(k) => RecordScale::Factor(k * factor),
                    RecordScale::Pga(target) => RecordScale::Pga(target * factor),
                    RecordScale::Pgv(target) => RecordScale::Pgv(target * factor),
                    RecordScale::PgaStar(target) => RecordScale::PgaStar(target * factor),
                    RecordScale::PgvStar(target) => RecordScale::PgvStar(target * factor),
                }
            }
        }
        e
    }
}

impl VerticalMotion {
    /// Reject meaningless vertical values (a free flight below −g is refused when the motion
    /// is compiled, where the signal is known).
    pub fn validate(&self, p: f64) -> Result<(), Invalid> {
        match self {
            VerticalMotion::Record(name) if name.trim().is_empty() => Err(Invalid {
                field: "vertical_record",
                value: f64::NAN,
                expected: "record(\"FILE\") needs a record file",
            }),
            VerticalMotion::Record(_) => Ok(()),
            VerticalMotion::Pulse {
                shape,
                amplitude,
                frequency,
            } => check_pulse(
                ("vertical_amplitude_g", "vertical_frequency"),
                shape,
                *amplitude,
                *frequency,
                p,
            ),
            VerticalMotion::Constant(c) => check(
                "vertical_constant",
                *c,
                *c >= -1.0,
                "must be a finite number ≥ -1 (ü_v = c·g below -g is free flight)",
            ),
            VerticalMotion::Ratio(r) => {
                check("vertical_ratio", *r, true, "must be a finite number")
            }
        }
    }
}

impl Amplitude {
    /// A in m/s².
    pub fn absolute(&self, alpha: f64) -> f64 {
        match *self {
            Amplitude::G(a) => a * G,
            Amplitude::TanAlphaRatio(r) => r * G * alpha.tan(),
            Amplitude::AlphaRatio(r) => r * G * alpha,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Frequency {
    /// ωg in rad/s.
    RadPerSec(f64),
    /// ωg/p.
    Ratio(f64),
}

impl Frequency {
    pub fn absolute(&self, p: f64) -> f64 {
        match *self {
            Frequency::RadPerSec(w) => w,
            Frequency::Ratio(r) => r * p,
        }
    }
}

/// A physically invalid scene value. `field` uses the CLI flag spelling without dashes
/// (`k_theta` ↔ `--k-theta`), so both the CLI and study files can point at it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{field} = {}: {expected}", crate::numfmt::fmt_exact(*.value))]
pub struct Invalid {
    pub field: &'static str,
    pub value: f64,
    pub expected: &'static str,
}

fn check(field: &'static str, value: f64, ok: bool, expected: &'static str) -> Result<(), Invalid> {
    if value.is_finite() && ok {
        Ok(())
    } else {
        Err(Invalid {
            field,
            value,
            expected,
        })
    }
}

fn positive(field: &'static str, v: f64) -> Result<(), Invalid> {
    check(field, v, v > 0.0, "must be a finite number > 0")
}

fn at_least(field: &'static str, v: f64, min: f64, expected: &'static str) -> Result<(), Invalid> {
    check(field, v, v >= min, expected)
}

fn non_negative(field: &'static str, v: f64) -> Result<(), Invalid> {
    check(field, v, v >= 0.0, "must be a finite number ≥ 0")
}

impl Scene {
    /// Reject physically meaningless values before anything runs.
    pub fn validate(&self) -> Result<(), Invalid> {
        let alpha = self.structure.alpha();
        check(
            "alpha",
            alpha,
            alpha > 0.0 && alpha < std::f64::consts::FRAC_PI_2,
            "slenderness must be in (0, π/2) rad",
        )?;
        positive("mass", self.structure.mass())?;
        match &self.structure {
            Structure::Rigid(b) => at_least("size", b.size, MIN_SIZE, "must be ≥ 1 mm (0.001 m)")?,
            Structure::Flexible(f) => {
                at_least("size", f.r0, MIN_SIZE, "must be ≥ 1 mm (0.001 m)")?;
                non_negative("xi", f.xi)?;
                positive("omega_n", f.omega_n)?;
            }
        }
        match &self.device {
            Device::None => {}
            Device::Inerter { sigma, coupling } => {
                non_negative("sigma", *sigma)?;
                if let Coupling::Flywheel {
                    stiffness,
                    rho,
                    damping,
                } = coupling
                {
                    // A flywheel without inertia has no dynamics (its equation divides by
                    // mr = σm): the spring-coupled inerter needs σ > 0.
                    check(
                        "sigma",
                        *sigma,
                        *sigma > 0.0,
                        "must be > 0 for a flywheel coupling (σ = 0 is no inerter: device None)",
                    )?;
                    positive("rho", *rho)?;
                    check_stiffness(*stiffness)?;
                    check_damping(*damping)?;
                }
            }
            Device::Sequential { sigma } => non_negative("sigma", *sigma)?,
            Device::Mechanistic(c) => {
                positive("sigma", c.sigma)?;
                check_stiffness(c.stiffness)?;
                positive("rho", c.rho)?;
                positive("epsilon", c.epsilon)?;
                check_damping(c.damping)?;
                non_negative("friction", c.friction)?;
                positive("eta", c.eta)?;
                non_negative("play", c.play)?;
            }
        }
        match self.impact {
            Impact::Housner {
                restitution: Some(r),
            } => check(
                "restitution",
                r,
                (0.0..=1.0).contains(&r),
                "coefficient of restitution must be in [0, 1]",
            )?,
            Impact::Housner { restitution: None } => {}
            Impact::Dirac { width } => positive("width", width)?,
        }
        match &self.excitation {
            Excitation::Pulse {
                shape,
                amplitude,
                frequency,
            } => check_pulse(
                ("amplitude", "frequency"),
                shape,
                *amplitude,
                *frequency,
                self.structure.p(),
            )?,
            Excitation::MpPulse { tp, pgv, gamma, nu } => {
                at_least("tp", *tp, MIN_PULSE_PERIOD, "pulse period must be ≥ 1 ms")?;
                check("pgv", *pgv, true, "must be a finite number")?;
                check_mp(*gamma, *nu)?;
            }
            Excitation::Record { name, scale, .. } => {
                if name.trim().is_empty() {
                    return Err(Invalid {
                        field: "record",
                        value: f64::NAN,
                        expected: "a record name or path is required",
                    });
                }
                match *scale {
                    RecordScale::Factor(k) => check("scale", k, true, "must be a finite number")?,
                    RecordScale::Pga(a) => positive("scale_pga", a)?,
                    RecordScale::Pgv(v) => positive("scale_pgv", v)?,
                    RecordScale::PgaStar(v) => positive("scale_pga_star", v)?,
                    RecordScale::PgvStar(v) => positive("scale_pgv_star", v)?,
                }
            }
        }
        if let Some(v) = &self.vertical {
            v.validate(self.structure.p())?;
        }
        positive("duration", self.duration)?;
        check(
            "rtol",
            self.rtol,
            self.rtol >= 1e-14 && self.rtol <= 0.1,
            "relative tolerance must be in [1e-14, 0.1]",
        )?;
        check(
            "initial_rotation",
            self.initial_rotation,
            self.initial_rotation.abs() < alpha,
            "initial rotation must be smaller than α in magnitude",
        )
    }
}

/// Bounds of what a scene can resolve: below these sizes and pulse periods the time scales
/// fall under what a step can resolve in f64 over a run, and a pulse of γ half-cycles beyond
/// `MAX_MP_GAMMA` is no longer pulse-like (fitted records have γ of a few).
pub const MIN_SIZE: f64 = 1e-3;
pub const MIN_PULSE_PERIOD: f64 = 1e-3;
pub const MAX_MP_GAMMA: f64 = 20.0;

fn check_mp(gamma: f64, nu: f64) -> Result<(), Invalid> {
    check(
        "gamma",
        gamma,
        gamma > 1.0 && gamma <= MAX_MP_GAMMA,
        "Mavroeidis–Papageorgiou γ must be in (1, 20]",
    )?;
    check("nu", nu, true, "must be a finite phase (rad)")
}

fn check_stiffness(s: ClutchStiffness) -> Result<(), Invalid> {
    match s {
        ClutchStiffness::KTheta(k) => positive("k_theta", k),
        ClutchStiffness::FrequencyRatio(r) => positive("clutch_frequency_ratio", r),
    }
}

fn check_damping(d: Damping) -> Result<(), Invalid> {
    match d {
        Damping::CBar(c) => non_negative("cbar", c),
        Damping::XiTheta(x) => non_negative("xi_theta", x),
    }
}

/// A pulse's amplitude is finite, its frequency positive with a period of at least
/// [`MIN_PULSE_PERIOD`], and a Mavroeidis–Papageorgiou shape's γ and ν in range; `fields` names
/// the amplitude and frequency as the user wrote them (horizontal or vertical).
fn check_pulse(
    fields: (&'static str, &'static str),
    shape: &PulseShape,
    amplitude: Amplitude,
    frequency: Frequency,
    p: f64,
) -> Result<(), Invalid> {
    let (amplitude_field, frequency_field) = fields;
    let a = match amplitude {
        Amplitude::G(a) | Amplitude::TanAlphaRatio(a) | Amplitude::AlphaRatio(a) => a,
    };
    check(amplitude_field, a, true, "must be a finite number")?;
    let w = match frequency {
        Frequency::RadPerSec(w) | Frequency::Ratio(w) => w,
    };
    positive(frequency_field, w)?;
    check(
        frequency_field,
        w,
        2.0 * std::f64::consts::PI / frequency.absolute(p) >= MIN_PULSE_PERIOD,
        "the pulse period 2π/ω must be ≥ 1 ms",
    )?;
    if let PulseShape::MavroeidisPapageorgiou { gamma, nu } = shape {
        check_mp(*gamma, *nu)?;
    }
    Ok(())
}
