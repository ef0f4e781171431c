//! `rocklab simulate`: one scene from flags, a summary or one JSON object on stdout.

use super::UsageError;
use crate::excitation::{KinkPolicy, PulseShape, library};
use crate::scene::{
    Amplitude, Clutch, ClutchStiffness, Coupling, Damping, Device, Excitation, FlexibleStructure,
    Form, Frequency, Impact, RecordScale, ResetRule, RigidBlock, Scene, Structure, default_epsilon,
    default_eta, default_rho,
};

use crate::sim::{self, Measures, SceneResult};
use crate::study::Quantity;
use clap::{Args, ValueEnum};
use std::path::PathBuf;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum StructureKind {
    Rigid,
    Flexible,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DeviceKind {
    None,
    Inerter,
    Sequential,
    Mechanistic,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ImpactKind {
    Housner,
    Dirac,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum CouplingKind {
    Rigid,
    Flywheel,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FormKind {
    Exact,
    Slender,
    /// Slender only where its error against the exact form is below --rtol.
    Auto,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ResetKind {
    Paper,
    Strict,
}

/// Run one scene and print its peaks.
#[derive(Args, Debug, Clone)]
#[command(allow_negative_numbers = true)]
pub struct SimulateArgs {
    #[arg(long, value_enum, default_value = "rigid")]
    pub structure: StructureKind,
    /// R (rigid block half-diagonal) or R0 (flexible structure), in m.
    #[arg(long, conflicts_with = "p")]
    pub size: Option<f64>,
    /// Frequency parameter p (rad/s) instead of --size.
    #[arg(long)]
    pub p: Option<f64>,
    /// Slenderness α in radians (`0.1745`, `0.1745rad`) or degrees (`10deg`, `10°`); always
    /// recorded in radians.
    #[arg(long, value_parser = parse_angle, allow_hyphen_values = true)]
    pub alpha: Option<f64>,
    #[arg(long, default_value_t = 1.0)]
    pub mass: f64,
    /// Exact equations (default) or the slender (small-α) form. Rigid block only.
    #[arg(long, value_enum, default_value = "exact")]
    pub form: FormKind,
    /// Flexible: column damping ratio ξ.
    #[arg(long, allow_negative_numbers = true)]
    pub xi: Option<f64>,
    /// Flexible: column natural frequency ωn (rad/s).
    #[arg(long, conflicts_with = "omega_ratio", allow_negative_numbers = true)]
    pub omega_n: Option<f64>,
    /// Flexible: ωn/p.
    #[arg(long, allow_negative_numbers = true)]
    pub omega_ratio: Option<f64>,
    #[arg(long, value_enum, default_value = "none")]
    pub device: DeviceKind,
    /// Apparent mass ratio σ = mr/m.
    #[arg(long)]
    pub sigma: Option<f64>,
    /// Single inerter: rigid coupling (default) or explicit flywheel behind a spring.
    #[arg(long, value_enum)]
    pub coupling: Option<CouplingKind>,
    /// Clutch rotational stiffness kθ (N·m/rad). Default: clutch frequency √(kθ/J) = √(k/mr)
    /// = 25 p, the paper's pair ξθ = 0.02 ⇔ c̄ = 1 s⁻¹ on the §6 structure (c̄ = 2 ξθ √(kθ/J)).
    #[arg(long, conflicts_with = "clutch_frequency_ratio")]
    pub k_theta: Option<f64>,
    /// Clutch frequency √(k/mr) as a multiple of p, instead of --k-theta.
    #[arg(long)]
    pub clutch_frequency_ratio: Option<f64>,
    /// Pinion radius ρ (m), default 0.05.
    #[arg(long)]
    pub rho: Option<f64>,
    /// Clutch smoothing ε, default 1e6.
    #[arg(long)]
    pub epsilon: Option<f64>,
    /// Flywheel damping c̄ = c/J (1/s), default 1.
    #[arg(long, conflicts_with = "xi_theta")]
    pub cbar: Option<f64>,
    /// Flywheel damping ratio ξθ instead of --cbar.
    #[arg(long)]
    pub xi_theta: Option<f64>,
    /// Dry friction fμ as a fraction of mr·g.
    #[arg(long)]
    pub friction: Option<f64>,
    /// Friction transition η (s/rad), default 100.
    #[arg(long)]
    pub eta: Option<f64>,
    /// Gear play up (m).
    #[arg(long)]
    pub play: Option<f64>,
    /// Re-engagement reset rule with gear play.
    #[arg(long, value_enum)]
    pub reset: Option<ResetKind>,
    #[arg(long, value_enum, default_value = "housner")]
    pub impact: ImpactKind,
    /// Dirac-delta impact width n (rad).
    #[arg(long)]
    pub width: Option<f64>,
    /// Override the coefficient of restitution r (Housner impact).
    #[arg(long)]
    pub restitution: Option<f64>,
    /// Pulse family (default sine).
    #[arg(long, value_enum)]
    pub pulse: Option<PulseKind>,
    /// Mavroeidis–Papageorgiou γ (> 1, number of cycles).
    #[arg(long)]
    pub gamma: Option<f64>,
    /// Mavroeidis–Papageorgiou phase ν (rad), default 0.
    #[arg(long)]
    pub nu: Option<f64>,
    /// Mavroeidis–Papageorgiou pulse period Tp (s), with --pgv, instead of amplitude and
    /// frequency flags.
    #[arg(long, requires = "pgv")]
    pub tp: Option<f64>,
    /// Mavroeidis–Papageorgiou peak ground velocity (m/s), with --tp.
    #[arg(long, requires = "tp")]
    pub pgv: Option<f64>,
    /// Run under a ground-motion record: a name from `rocklab records`, its Table 1 number,
    /// or a path to an AT2, one-column (with '# dt:') or two-column (t, a) file.
    #[arg(long)]
    pub record: Option<String>,
    /// Scale the record by this factor (default 1).
    #[arg(long, group = "record_scale")]
    pub scale: Option<f64>,
    /// Scale the record to this PGA (g).
    #[arg(long, group = "record_scale")]
    pub scale_pga: Option<f64>,
    /// Scale the record to this PGV (m/s).
    #[arg(long, group = "record_scale")]
    pub scale_pgv: Option<f64>,
    /// Baseline-correct the record (remove the least-squares velocity drift).
    #[arg(long)]
    pub baseline: bool,
    /// How the integrator treats the kinks between record samples.
    #[arg(long, value_enum)]
    pub kinks: Option<KinksKind>,
    /// Records directory (default: $ROCKLAB_RECORDS, else ./records if it holds an index.ron, else the
    /// records embedded in the binary).
    #[arg(long)]
    pub records_dir: Option<PathBuf>,
    /// Pulse amplitude A/g.
    #[arg(long, group = "amp")]
    pub amplitude_g: Option<f64>,
    /// Pulse amplitude A/(g·tanα).
    #[arg(long, group = "amp")]
    pub amplitude_ratio: Option<f64>,
    /// Pulse amplitude A/(g·α) (the paper's rigid-block convention).
    #[arg(long, group = "amp")]
    pub amplitude_alpha: Option<f64>,
    /// Pulse circular frequency ωg (rad/s).
    #[arg(long, conflicts_with = "frequency_ratio")]
    pub frequency: Option<f64>,
    /// ωg/p.
    #[arg(long)]
    pub frequency_ratio: Option<f64>,
    /// Total simulated time (s); stops earlier only at overturning or rest. Default: 10 s for
    /// pulses, the record's length + 10 s for records.
    #[arg(long)]
    pub duration: Option<f64>,
    /// Relative tolerance of the integrator.
    #[arg(long, default_value_t = crate::scene::default_rtol())]
    pub rtol: f64,
    /// Integrator: dop853 at tight tolerance, dp54 otherwise (auto), or either.
    #[arg(long, value_enum, default_value = "auto")]
    pub method: crate::scene::Method,
    /// Initial rotation θ0 (rad) for free rocking.
    #[arg(long, default_value_t = 0.0)]
    pub theta0: f64,
    /// Stop once the ground has stopped and the energy left cannot raise any peak.
    #[arg(long)]
    pub stop_when_settled: bool,
    /// Integrate the full-contact phase of a flexible structure instead of advancing it in
    /// closed form (the default with no device or a rigid inerter under a record).
    #[arg(long)]
    pub integrate_contact: bool,
    /// Compute only these quantities (comma-separated: peak_rotation, peak_rotation_ratio,
    /// peak_deformation, peak_drift, peak_abs_acceleration, peak_angular_acceleration, energy);
    /// the rotation is always computed. Default: all.
    #[arg(long, value_delimiter = ',')]
    pub quantities: Option<Vec<String>>,
    /// Write the time history to this CSV file: rows on a uniform time grid (see --dt) from the
    /// integrator's dense output, plus a row before and after every event (impacts, uplifts,
    /// clutch switches) at its exact instant.
    #[arg(long)]
    pub history: Option<PathBuf>,
    /// Sample step of --history in seconds (`0.001`), or `steps` for one row per solver step.
    /// Default: the duration / 4000 and at most a pulse's length / 200, rounded down to
    /// 1, 2 or 5 × 10ᵏ s.
    #[arg(long, value_parser = parse_sampling, requires = "history")]
    pub dt: Option<sim::Sampling>,
    /// Print exactly one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Also run the scene at a 1000× tighter rtol, and there with its inputs (excitation
    /// amplitude, θ0) scaled by 1 ± 1e-7, and say whether its peaks are converged, not yet
    /// converged (tighten --rtol) or ill-conditioned (a relative change of 1e-7 in the inputs
    /// moves them); about 3–15× the scene's own time.
    #[arg(long)]
    pub check: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PulseKind {
    Sine,
    Cosine,
    /// Symmetric Ricker wavelet.
    Ricker,
    /// Antisymmetric Ricker wavelet.
    AntisymmetricRicker,
    /// Mavroeidis–Papageorgiou (needs --gamma).
    Mp,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum KinksKind {
    /// Stop the integrator at every sample (default).
    StopAtSamples,
    /// Step across samples; the error controller handles the kinks.
    StepOver,
}

fn need(value: Option<f64>, flag: &'static str, why: &'static str) -> Result<f64, UsageError> {
    value.ok_or_else(|| UsageError::new(format!("{flag} is required {why}")))
}

fn only_with(
    value: Option<f64>,
    flag: &'static str,
    allowed: bool,
    context: &'static str,
) -> Result<(), UsageError> {
    if value.is_some() && !allowed {
        return Err(UsageError::new(format!("{flag} only applies {context}")));
    }
    Ok(())
}

impl SimulateArgs {
    /// Turn flags into a scene, rejecting missing and contradictory combinations.
    pub fn scene(&self) -> Result<Scene, UsageError> {
        let alpha = need(self.alpha, "--alpha", "(slenderness in rad, 0 < α < π/2)")?;
        let size = match (self.size, self.p) {
            (Some(s), None) => s,
            (None, Some(p)) => {
                if !(p.is_finite() && p > 0.0) {
                    return Err(UsageError::invalid("--p", p, "must be a finite number > 0"));
                }
                match self.structure {
                    StructureKind::Rigid => 3.0 * crate::excitation::G / (4.0 * p * p),
                    StructureKind::Flexible => crate::excitation::G / (p * p),
                }
            }
            _ => return Err(UsageError::new("one of --size or --p is required")),
        };
        let rigid = self.structure == StructureKind::Rigid;
        let structure = if rigid {
            for (v, f) in [
                (self.xi, "--xi"),
                (self.omega_n, "--omega-n"),
                (self.omega_ratio, "--omega-ratio"),
            ] {
                only_with(v, f, false, "to --structure flexible")?;
            }
            Structure::Rigid(RigidBlock {
                size,
                alpha,
                mass: self.mass,
                form: match self.form {
                    FormKind::Exact => Form::Exact,
                    FormKind::Slender => Form::Slender,
                    FormKind::Auto => Form::Auto,
                },
            })
        } else {
            if self.form != FormKind::Exact {
                return Err(UsageError::new(
                    "--form slender|auto only applies to --structure rigid",
                ));
            }
            // The flexible structure lands by the VVEL rule (MODEL.md): no restitution to choose.
            if self.impact != ImpactKind::Housner || self.restitution.is_some() {
                return Err(UsageError::new(
                    "--impact and --restitution only apply to --structure rigid \
                     (the flexible structure uses the VVEL impact of Chopra and Yim)",
                ));
            }
            let p = (crate::excitation::G / size).sqrt();
            let omega_n = match (self.omega_n, self.omega_ratio) {
                (Some(w), None) => w,
                (None, Some(r)) if r.is_finite() && r > 0.0 => r * p,
                (None, Some(r)) => {
                    return Err(UsageError::invalid(
                        "--omega-ratio",
                        r,
                        "ωn/p must be a finite number > 0",
                    ));
                }
                _ => {
                    return Err(UsageError::new(
                        "one of --omega-n or --omega-ratio is required with --structure flexible",
                    ));
                }
            };
            Structure::Flexible(FlexibleStructure {
                r0: size,
                alpha,
                mass: self.mass,
                xi: need(
                    self.xi,
                    "--xi",
                    "with --structure flexible (column damping ratio)",
                )?,
                omega_n,
            })
        };
        let device = self.device()?;
        let impact = match self.impact {
            ImpactKind::Housner => {
                only_with(self.width, "--width", false, "to --impact dirac")?;
                Impact::Housner {
                    restitution: self.restitution,
                }
            }
            ImpactKind::Dirac => {
                only_with(
                    self.restitution,
                    "--restitution",
                    false,
                    "to --impact housner",
                )?;
                Impact::Dirac {
                    width: need(self.width, "--width", "with --impact dirac (rad)")?,
                }
            }
        };
        let (excitation, default_duration) = self.excitation()?;
        let scene = Scene {
            structure,
            device,
            impact,
            excitation,
            duration: self.duration.unwrap_or(default_duration),
            rtol: self.rtol,
            initial_rotation: self.theta0,
            stop_when_settled: self.stop_when_settled,
            closed_form_contact: !self.integrate_contact,
            method: self.method,
        };
        scene.validate().map_err(UsageError::from_invalid)?;
        Ok(scene)
    }

    /// The excitation the flags describe, and the default duration that goes with it.
    fn excitation(&self) -> Result<(Excitation, f64), UsageError> {
        let record_only = "with --record";
        only_with(self.scale, "--scale", self.record.is_some(), record_only)?;
        only_with(
            self.scale_pga,
            "--scale-pga",
            self.record.is_some(),
            record_only,
        )?;
        only_with(
            self.scale_pgv,
            "--scale-pgv",
            self.record.is_some(),
            record_only,
        )?;
        if self.record.is_none() && (self.baseline || self.kinks.is_some()) {
            return Err(UsageError::new(
                "--baseline and --kinks only apply with --record",
            ));
        }
        if let Some(name) = &self.record {
            let pulse_flags = [
                (self.amplitude_g, "--amplitude-g"),
                (self.amplitude_ratio, "--amplitude-ratio"),
                (self.amplitude_alpha, "--amplitude-alpha"),
                (self.frequency, "--frequency"),
                (self.frequency_ratio, "--frequency-ratio"),
                (self.gamma, "--gamma"),
                (self.nu, "--nu"),
                (self.tp, "--tp"),
                (self.pgv, "--pgv"),
            ];
            for (v, f) in pulse_flags {
                only_with(v, f, false, "to pulses, not with --record")?;
            }
            if self.pulse.is_some() {
                return Err(UsageError::new("--pulse and --record exclude each other"));
            }
            if let Some(dir) = &self.records_dir {
                super::existing_records_dir(dir)?;
            }
            if let Some(dir) = &self.records_dir
                && !library::set_records_dir(dir.clone())
            {
                return Err(UsageError::new(
                    "--records-dir was set after records were loaded",
                ));
            }
            let scale = match (self.scale, self.scale_pga, self.scale_pgv) {
                (_, Some(a), _) => RecordScale::Pga(a),
                (_, _, Some(v)) => RecordScale::Pgv(v),
                (k, _, _) => RecordScale::Factor(k.unwrap_or(1.0)),
            };
            // Load now, so an unknown name or a bad file is a usage error with its message.
            let record = library::global()
                .and_then(|lib| lib.load(name, self.baseline))
                .map_err(|e| UsageError::new(format!("--record {name}: {e}")))?;
            let excitation = Excitation::Record {
                // Store the canonical name ("3" → "imperial_valley") so the scene reads plainly.
                name: if record.meta.is_some() {
                    record.name.clone()
                } else {
                    name.clone()
                },
                scale,
                baseline: self.baseline,
                kinks: match self.kinks {
                    Some(KinksKind::StepOver) => KinkPolicy::StepOver,
                    _ => KinkPolicy::StopAtSamples,
                },
            };
            return Ok((excitation, record.series.end() + 10.0));
        }
        only_with(
            self.records_dir.as_ref().map(|_| 0.0),
            "--records-dir",
            false,
            record_only,
        )?;
        let pulse = self.pulse.unwrap_or(PulseKind::Sine);
        let mp = pulse == PulseKind::Mp;
        only_with(self.gamma, "--gamma", mp, "to --pulse mp")?;
        only_with(self.nu, "--nu", mp, "to --pulse mp")?;
        only_with(self.tp, "--tp", mp, "to --pulse mp")?;
        let shape = match pulse {
            PulseKind::Sine => PulseShape::Sine,
            PulseKind::Cosine => PulseShape::Cosine,
            PulseKind::Ricker => PulseShape::Ricker,
            PulseKind::AntisymmetricRicker => PulseShape::AntisymmetricRicker,
            PulseKind::Mp => PulseShape::MavroeidisPapageorgiou {
                gamma: need(self.gamma, "--gamma", "with --pulse mp (γ > 1)")?,
                nu: self.nu.unwrap_or(0.0),
            },
        };
        if let (PulseShape::MavroeidisPapageorgiou { gamma, nu }, Some(tp), Some(pgv)) =
            (shape, self.tp, self.pgv)
        {
            for (v, f) in [
                (self.amplitude_g, "--amplitude-g"),
                (self.amplitude_ratio, "--amplitude-ratio"),
                (self.amplitude_alpha, "--amplitude-alpha"),
                (self.frequency, "--frequency"),
                (self.frequency_ratio, "--frequency-ratio"),
            ] {
                only_with(v, f, false, "without --tp/--pgv")?;
            }
            return Ok((Excitation::MpPulse { tp, pgv, gamma, nu }, 10.0));
        }
        let amplitude = match (self.amplitude_g, self.amplitude_ratio, self.amplitude_alpha) {
            (Some(a), None, None) => Amplitude::G(a),
            (None, Some(r), None) => Amplitude::TanAlphaRatio(r),
            (None, None, Some(r)) => Amplitude::AlphaRatio(r),
            _ => {
                return Err(UsageError::new(
                    "one of --amplitude-g, --amplitude-ratio or --amplitude-alpha is required (or --record)",
                ));
            }
        };
        let frequency = match (self.frequency, self.frequency_ratio) {
            (Some(w), None) => Frequency::RadPerSec(w),
            (None, Some(r)) => Frequency::Ratio(r),
            _ => {
                return Err(UsageError::new(
                    "one of --frequency or --frequency-ratio is required",
                ));
            }
        };
        let excitation = Excitation::Pulse {
            shape,
            amplitude,
            frequency,
        };
        Ok((excitation, 10.0))
    }

    fn device(&self) -> Result<Device, UsageError> {
        let mech = self.device == DeviceKind::Mechanistic;
        let flywheel =
            self.device == DeviceKind::Inerter && self.coupling == Some(CouplingKind::Flywheel);
        let springy = mech || flywheel;
        let ctx_spring = "to --device mechanistic or --device inerter --coupling flywheel";
        only_with(self.k_theta, "--k-theta", springy, ctx_spring)?;
        only_with(
            self.clutch_frequency_ratio,
            "--clutch-frequency-ratio",
            springy,
            ctx_spring,
        )?;
        only_with(self.rho, "--rho", springy, ctx_spring)?;
        only_with(self.cbar, "--cbar", springy, ctx_spring)?;
        only_with(self.xi_theta, "--xi-theta", springy, ctx_spring)?;
        let ctx_mech = "to --device mechanistic";
        only_with(self.epsilon, "--epsilon", mech, ctx_mech)?;
        only_with(self.friction, "--friction", mech, ctx_mech)?;
        only_with(self.eta, "--eta", mech, ctx_mech)?;
        only_with(self.play, "--play", mech, ctx_mech)?;
        if self.reset.is_some() && !mech {
            return Err(UsageError::new(
                "--reset only applies to --device mechanistic",
            ));
        }
        if self.coupling.is_some() && self.device != DeviceKind::Inerter {
            return Err(UsageError::new(
                "--coupling only applies to --device inerter",
            ));
        }
        if self.device == DeviceKind::None {
            only_with(
                self.sigma,
                "--sigma",
                false,
                "with a device (--device inerter|sequential|mechanistic)",
            )?;
            return Ok(Device::None);
        }
        let sigma = need(
            self.sigma,
            "--sigma",
            "with a device (apparent mass ratio mr/m ≥ 0)",
        )?;
        let stiffness = match (self.k_theta, self.clutch_frequency_ratio) {
            (Some(k), _) => ClutchStiffness::KTheta(k),
            (_, Some(r)) => ClutchStiffness::FrequencyRatio(r),
            _ => ClutchStiffness::default(),
        };
        let damping = match (self.cbar, self.xi_theta) {
            (_, Some(x)) => Damping::XiTheta(x),
            (Some(c), _) => Damping::CBar(c),
            _ => Damping::default(),
        };
        let rho = self.rho.unwrap_or_else(default_rho);
        Ok(match self.device {
            DeviceKind::None => unreachable!(),
            DeviceKind::Inerter => Device::Inerter {
                sigma,
                coupling: if flywheel {
                    Coupling::Flywheel {
                        stiffness,
                        rho,
                        damping,
                    }
                } else {
                    Coupling::Rigid
                },
            },
            DeviceKind::Sequential => Device::Sequential { sigma },
            DeviceKind::Mechanistic => Device::Mechanistic(Clutch {
                sigma,
                stiffness,
                rho,
                epsilon: self.epsilon.unwrap_or_else(default_epsilon),
                damping,
                friction: self.friction.unwrap_or(0.0),
                eta: self.eta.unwrap_or_else(default_eta),
                play: self.play.unwrap_or(0.0),
                reset: match self.reset {
                    Some(ResetKind::Strict) => ResetRule::Strict,
                    _ => ResetRule::Paper,
                },
            }),
        })
    }
}

/// The JSON object `simulate --json` prints (keys are a contract other tools rely on).
pub fn result_json(scene: &Scene, r: &SceneResult) -> serde_json::Value {
    serde_json::json!({
        "overturned": r.overturned,
        "peak_rotation": r.peaks.rotation,
        "peak_rotation_ratio": r.peak_rotation_ratio,
        "peak_deformation": r.measured.deformation.then_some(r.peaks.deformation),
        "peak_drift": r.measured.drift.then_some(r.peaks.drift),
        "peak_abs_acceleration_g": r.measured.abs_acceleration.then_some(r.peaks.abs_acceleration_g),
        "peak_angular_acceleration_p2": r.peaks.angular_acceleration_p2,
        "impacts": r.counters.impacts,
        "uplifts": r.counters.uplifts,
        "engagements": r.counters.engagements,
        "resets": r.counters.resets,
        "energy_residual": r.measured.energy.then_some(r.energy_residual),
        "energy": r.measured.energy.then_some(r.energy),
        "end_reason": r.end_reason,
        "end_time": r.end_time,
        "steps": r.stats.steps,
        "rejected_steps": r.stats.rejected,
        "rhs_evals": r.stats.rhs_evals,
        "exact_steps": r.stats.closed_form_steps,
        "wall_seconds": r.wall_seconds,
        "form_used": r.form_used,
        "scene": scene,
    })
}

impl SimulateArgs {
    /// The measures `--quantities` asks for (all without it).
    pub fn measures(&self) -> Result<Measures, UsageError> {
        let Some(names) = &self.quantities else {
            return Ok(Measures::ALL);
        };
        let mut quantities = Vec::new();
        let mut energy = false;
        for name in names.iter().map(|n| n.trim()) {
            match Quantity::from_name(name) {
                Some(q) => quantities.push(q),
                None if name == "energy" => energy = true,
                None => {
                    let known: Vec<&str> = Quantity::ALL.iter().map(|q| q.name()).collect();
                    return Err(UsageError::new(format!(
                        "--quantities: unknown quantity `{name}`; known: {}, energy",
                        known.join(", ")
                    )));
                }
            }
        }
        Ok(Measures {
            energy,
            ..Quantity::measures(&quantities)
        })
    }
}

pub fn run(args: &SimulateArgs) -> anyhow::Result<()> {
    let measures = args.measures()?;
    let scene = args.scene()?;
    if args.check {
        // Before the run: a check that cannot be made should not cost the scene first.
        sim::check::reference_rtol(scene.rtol)
            .map_err(|e| UsageError::new(format!("--check: {e}")))?;
    }
    let library = library::global()?;
    let bounds = sim::Bounds {
        measures,
        ..Default::default()
    };
    let (result, history, check) = crate::sweep::guarded(|| {
        let sampling = args.dt.clone().unwrap_or(sim::Sampling::Auto);
        let sampling = args.history.is_some().then_some(&sampling);
        let (result, history) = sim::run_sampled(&scene, library, sampling, bounds)?;
        let check = args
            .check
            .then(|| sim::check::check(&scene, &result, library, bounds))
            .transpose()?;
        Ok((result, history, check))
    })
    .map_err(|e| match e {
        // A scene the model refuses is bad input: exit 2 like a bad flag.
        crate::sweep::Guarded::Sim(sim::SimError::Invalid(msg)) => {
            anyhow::Error::from(UsageError::new(msg))
        }
        e => e.into(),
    })?;
    if let (Some(path), Some(h)) = (&args.history, &history) {
        crate::report::write_history_csv(path, h)?;
    }
    if args.json {
        let mut json = result_json(&scene, &result);
        if let Some(check) = &check {
            json["check"] = serde_json::to_value(check)?;
        }
        println!("{json}");
    } else {
        if let Excitation::Record { name, baseline, .. } = &scene.excitation {
            let record = library.load(name, *baseline)?;
            let factor = match sim::motion_for(&scene, library)? {
                crate::excitation::Motion::Record(m) => m.factor,
                crate::excitation::Motion::Pulse(_) => 1.0,
            };
            println!(
                "record {} × {factor:.6}: {}",
                record.name,
                record.source.label()
            );
        }
        print!("{}", summary(&scene, &result));
        if let Some(check) = &check {
            print!("{}", check.report());
        }
    }
    Ok(())
}

pub fn summary(scene: &Scene, r: &SceneResult) -> String {
    let e = &r.energy;
    // Rigid block: the paper's acceleration measure, θ̈ between impacts.
    let angular = r
        .peaks
        .angular_acceleration_p2
        .map(|a| format!("peak |θ̈| between impacts {a:.6} p²\n"))
        .unwrap_or_default();
    format!(
        "structure {:?}, device {}, end: {:?} at t = {:.4} s\n\
         peak rotation      {:.6e} rad  ({:.4} α)\n\
         peak deformation   {:.6e} m\n\
         peak drift         {:.6e}\n\
         peak |abs. accel.| {:.6} g\n\
         {angular}\
         impacts {}  uplifts {}  engagements {}  resets {}\n\
         energy (J): input {:.6e}  structure {:.6e}  inerter {:.6e}  dissipated {:.6e}  residual {:.2e}\n\
         solver: {} steps ({} rejected), {} rhs evaluations, {} closed-form steps, {:.3} ms\n",
        match scene.structure {
            Structure::Rigid(_) => "rigid",
            Structure::Flexible(_) => "flexible",
        },
        scene.device.name(),
        r.end_reason,
        r.end_time,
        r.peaks.rotation,
        r.peak_rotation_ratio,
        r.peaks.deformation,
        r.peaks.drift,
        r.peaks.abs_acceleration_g,
        r.counters.impacts,
        r.counters.uplifts,
        r.counters.engagements,
        r.counters.resets,
        e.input,
        e.structure,
        e.inerter,
        e.dissipated(),
        r.energy_residual,
        r.stats.steps,
        r.stats.rejected,
        r.stats.rhs_evals,
        r.stats.closed_form_steps,
        r.wall_seconds * 1e3,
    )
}

pub use crate::study::parse_angle;

/// A --dt value: a positive step in seconds, or `steps`.
pub fn parse_sampling(text: &str) -> Result<sim::Sampling, String> {
    let t = text.trim();
    if t == "steps" {
        return Ok(sim::Sampling::Steps);
    }
    t.strip_suffix('s')
        .unwrap_or(t)
        .trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite() && *v > 0.0)
        .map(sim::Sampling::Uniform)
        .ok_or_else(|| format!("`{text}` is not a sample step: give seconds (0.001) or `steps`"))
}

#[cfg(test)]
mod angle_tests {
    use super::parse_angle;

    #[test]
    fn angles_in_degrees_become_radians() {
        let ten = 10f64.to_radians();
        for text in [
            "10deg",
            "10 deg",
            "10°",
            "0.17453292519943295",
            "0.17453292519943295rad",
        ] {
            assert!((parse_angle(text).unwrap() - ten).abs() < 1e-15, "{text}");
        }
        for bad in ["deg", "10 degrees", "ten", "NaNdeg", ""] {
            assert!(parse_angle(bad).is_err(), "{bad}");
        }
    }
}
