//! From `simulate` flags to a scene and the measures to take.

use crate::cli::UsageError;
use crate::excitation::{KinkPolicy, PulseShape, library};
use crate::scene::{
    Amplitude, Clutch, ClutchStiffness, Coupling, Damping, Device, Excitation, FlexibleStructure,
    Form, Frequency, Impact, RecordScale, ResetRule, RigidBlock, Scene, Structure, VerticalMotion,
    default_epsilon, default_eta, default_rho,
};

use super::{
    CouplingKind, DeviceKind, FormKind, ImpactKind, KinksKind, PulseKind, ResetKind, SimulateArgs,
    StructureKind,
};
use crate::sim::Measures;
use crate::study::Quantity;

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
            // The flexible structure lands by the VVEL rule (docs/MODEL.md): no restitution to choose.
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
            vertical: self.vertical()?,
            duration: self.duration.unwrap_or(default_duration),
            rtol: self.rtol,
            initial_rotation: self.theta0,
            stop_when_settled: self.stop_when_settled,
            closed_form_contact: !self.integrate_contact,
            method: self.method,
        };
        scene.validate().map_err(|e| match self.p {
            // The size was derived from --p: name the flag the user gave.
            Some(p) if e.field == "size" => UsageError::invalid(
                "--p",
                p,
                &format!("gives a size R = {size:e} m, which {}", e.expected),
            ),
            _ => UsageError::from_invalid(e),
        })?;
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
                crate::cli::existing_records_dir(dir)?;
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

    /// The vertical ground motion the --vertical-* flags describe (clap lets at most one of
    /// record, pulse, constant and ratio through).
    fn vertical(&self) -> Result<Option<VerticalMotion>, UsageError> {
        if let Some(file) = &self.vertical_record {
            library::global()
                .and_then(|lib| lib.load(file, self.baseline))
                .map_err(|e| UsageError::new(format!("--vertical-record {file}: {e}")))?;
            return Ok(Some(VerticalMotion::Record(file.clone())));
        }
        if let Some(c) = self.vertical_constant {
            return Ok(Some(VerticalMotion::Constant(c)));
        }
        if let Some(r) = self.vertical_ratio {
            return Ok(Some(VerticalMotion::Ratio(r)));
        }
        let Some(kind) = self.vertical_pulse else {
            return Ok(None);
        };
        let shape = match kind {
            PulseKind::Sine => PulseShape::Sine,
            PulseKind::Cosine => PulseShape::Cosine,
            PulseKind::Ricker => PulseShape::Ricker,
            PulseKind::AntisymmetricRicker => PulseShape::AntisymmetricRicker,
            PulseKind::Mp => {
                return Err(UsageError::new(
                    "--vertical-pulse mp is not offered (it needs γ and ν): give the vertical \
                     MP pulse in a study file",
                ));
            }
        };
        let amplitude = Amplitude::G(need(
            self.vertical_amplitude_g,
            "--vertical-amplitude-g",
            "with --vertical-pulse (A_v/g)",
        )?);
        let frequency = match (self.vertical_frequency, self.vertical_frequency_ratio) {
            (Some(w), None) => Frequency::RadPerSec(w),
            (None, Some(r)) => Frequency::Ratio(r),
            _ => {
                return Err(UsageError::new(
                    "one of --vertical-frequency or --vertical-frequency-ratio is required \
                     with --vertical-pulse",
                ));
            }
        };
        Ok(Some(VerticalMotion::Pulse {
            shape,
            amplitude,
            frequency,
        }))
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
