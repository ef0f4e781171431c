//! `rocklab simulate`: one scene from flags, a summary or one JSON object on stdout.

mod flags;

use super::UsageError;
use crate::excitation::library;
use crate::scene::{Excitation, Scene, Structure};

use crate::sim::{self, SceneResult};
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
    /// Vertical ground motion from a record file (any format --record takes), positive up,
    /// aligned in time with the horizontal, multiplied by the horizontal record's scale
    /// factor (1 under a pulse); zero after its end.
    #[arg(long, group = "vertical")]
    pub vertical_record: Option<String>,
    /// Vertical pulse family, with --vertical-amplitude-g and --vertical-frequency or
    /// --vertical-frequency-ratio (the amplitude is absolute: it does not follow the
    /// horizontal's scaling).
    #[arg(long, value_enum, group = "vertical")]
    pub vertical_pulse: Option<PulseKind>,
    /// Vertical pulse amplitude A_v/g (positive: the first lobe is up).
    #[arg(long, requires = "vertical_pulse")]
    pub vertical_amplitude_g: Option<f64>,
    /// Vertical pulse circular frequency (rad/s).
    #[arg(
        long,
        requires = "vertical_pulse",
        conflicts_with = "vertical_frequency_ratio"
    )]
    pub vertical_frequency: Option<f64>,
    /// Vertical pulse frequency over p.
    #[arg(long, requires = "vertical_pulse")]
    pub vertical_frequency_ratio: Option<f64>,
    /// Constant vertical acceleration c·g: gravity becomes (1 + c) g (c ≥ -1).
    #[arg(long, group = "vertical", allow_hyphen_values = true)]
    pub vertical_constant: Option<f64>,
    /// Vertical acceleration r·a_g(t), r times the horizontal (after its scaling; r may be
    /// negative).
    #[arg(long, group = "vertical", allow_hyphen_values = true)]
    pub vertical_ratio: Option<f64>,
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
    /// Most rows --history may hold: a run that would record more stops with an error naming
    /// this cap, before it fills memory (each row is about 100 bytes).
    #[arg(long, default_value_t = sim::DEFAULT_HISTORY_ROWS, requires = "history")]
    pub max_history_rows: usize,
    /// Print exactly one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Also run the scene at a 1000× tighter rtol, and there with its inputs (excitation
    /// amplitude, θ0) scaled by 1 ± 1e-7, and say whether its peaks are converged, not yet
    /// converged (tighten --rtol) or ill-conditioned (a relative change of 1e-7 in the inputs
    /// moves them); about 3–15× the scene's own time.
    #[arg(long)]
    pub check: bool,
    /// Run the scene this many times in-process and report `wall_seconds` as the fastest run,
    /// the median beside it (`wall_seconds_median`): a warm timing, as a compiled peer is
    /// timed. Every run must give the same result (checked).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    pub repeat: u32,
}

/// Wall times of `--repeat` runs of one scene (s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timing {
    pub fastest: f64,
    pub median: f64,
    pub repeats: usize,
}

impl Timing {
    /// From the wall times of the runs (at least one).
    pub fn of(walls: &[f64]) -> Timing {
        let mut sorted = walls.to_vec();
        sorted.sort_by(f64::total_cmp);
        let n = sorted.len();
        let median = if n % 2 == 1 {
            sorted[n / 2]
        } else {
            0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
        };
        Timing {
            fastest: sorted[0],
            median,
            repeats: n,
        }
    }
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

/// The JSON object `simulate --json` prints (keys are a contract other tools rely on).
pub fn result_json(scene: &Scene, r: &SceneResult) -> serde_json::Value {
    let mut json = serde_json::json!({
        "overturned": r.overturned,
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
    });
    // Each peak under its key from the quantity table; null when the run did not measure it.
    for q in crate::sim::Quantity::ALL {
        json[q.info().key] = serde_json::json!(q.peak(r));
    }
    json
}

/// One scene run from `simulate`'s flags: everything its text and `--json` output show.
pub struct Simulated {
    pub scene: Scene,
    pub result: SceneResult,
    /// The sampled history, when asked for (`--history`, or Python's `history=True`).
    pub history: Option<sim::History>,
    pub check: Option<sim::check::Check>,
    pub timing: Timing,
}

/// Run the scene the flags describe (`--repeat` times, with `--check` if asked), recording
/// its history when `record_history`. The one computation behind `rocklab simulate` and
/// Python's `rocklab.simulate`.
pub fn compute(args: &SimulateArgs, record_history: bool) -> anyhow::Result<Simulated> {
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
        history_rows: Some(args.max_history_rows),
        ..Default::default()
    };
    let (result, history, check, timing, differs) = crate::sweep::guarded(|| {
        let sampling = args.dt.clone().unwrap_or(sim::Sampling::Auto);
        let sampling = record_history.then_some(&sampling);
        let (mut result, history) = sim::run_sampled(&scene, library, sampling, bounds)?;
        let mut walls = vec![result.wall_seconds];
        let mut differs = None;
        for run in 2..=args.repeat {
            let (mut again, _) = sim::run_sampled(&scene, library, sampling, bounds)?;
            walls.push(again.wall_seconds);
            again.wall_seconds = result.wall_seconds;
            if again != result {
                differs.get_or_insert(run);
            }
        }
        let timing = Timing::of(&walls);
        result.wall_seconds = timing.fastest;
        let check = args
            .check
            .then(|| sim::check::check(&scene, &result, library, bounds))
            .transpose()?;
        Ok((result, history, check, timing, differs))
    })
    .map_err(|e| match e {
        // A scene the model refuses is bad input: exit 2 like a bad flag.
        crate::sweep::Guarded::Sim(sim::SimError::Invalid(msg)) => {
            anyhow::Error::from(UsageError::new(msg))
        }
        e => e.into(),
    })?;
    if let Some(run) = differs {
        anyhow::bail!(
            "--repeat: run {run} of the scene gave a different result from the first (the \
             solver should be deterministic; please report the command)"
        );
    }
    Ok(Simulated {
        scene,
        result,
        history,
        check,
        timing,
    })
}

/// The one JSON object `simulate --json` prints.
pub fn json_output(run: &Simulated) -> anyhow::Result<serde_json::Value> {
    let mut json = result_json(&run.scene, &run.result);
    json["wall_seconds_median"] = run.timing.median.into();
    json["repeats"] = run.timing.repeats.into();
    if let Excitation::Record { name, .. } = &run.scene.excitation {
        json["record_source"] = library::global()?.load(name, false)?.source.kind().into();
    }
    if let Some(check) = &run.check {
        json["check"] = serde_json::to_value(check)?;
    }
    Ok(json)
}

pub fn run(args: &SimulateArgs) -> anyhow::Result<()> {
    let run = compute(args, args.history.is_some())?;
    if let (Some(path), Some(h)) = (&args.history, &run.history) {
        crate::report::write_history_csv(path, h)?;
    }
    if args.json {
        println!("{}", json_output(&run)?);
    } else {
        let Simulated {
            scene,
            result,
            check,
            timing,
            ..
        } = &run;
        let library = library::global()?;
        if let Excitation::Record { name, baseline, .. } = &scene.excitation {
            let record = library.load(name, *baseline)?;
            let factor = match sim::motion_for(scene, library)?.ground() {
                crate::excitation::Horizontal::Record(m) => m.factor,
                crate::excitation::Horizontal::Pulse(_) => 1.0,
            };
            println!(
                "record {} × {factor:.6}: {}",
                record.name,
                record.source.label()
            );
        }
        print!("{}", summary(scene, result));
        if timing.repeats > 1 {
            println!(
                "  wall time over {} runs: fastest {:.3} ms, median {:.3} ms",
                timing.repeats,
                timing.fastest * 1e3,
                timing.median * 1e3
            );
        }
        if let Some(check) = check {
            print!("{}", check.report());
        }
    }
    Ok(())
}

pub fn summary(scene: &Scene, r: &SceneResult) -> String {
    let e = &r.energy;
    // Every peak the run measured, named and labelled by the quantity table (a rigid block's
    // θ̈ between impacts is the paper's acceleration measure; a flexible structure has none).
    let peaks: String = sim::Quantity::ALL
        .into_iter()
        .filter_map(|q| Some(format!("{:<12} {:.6e}\n", q.label(), q.peak(r)?)))
        .collect();
    format!(
        "structure {}, device {}, end: {} at t = {:.4} s\n\
         {peaks}\
         impacts {}  uplifts {}  engagements {}  resets {}\n\
         energy (J): input {:.6e}  structure {:.6e}  inerter {:.6e}  dissipated {:.6e}  residual {:.2e}\n\
         solver: {} steps ({} rejected), {} rhs evaluations, {} closed-form steps, {:.3} ms\n",
        match scene.structure {
            Structure::Rigid(_) => "rigid",
            Structure::Flexible(_) => "flexible",
        },
        scene.device.name(),
        r.end_reason.name(),
        r.end_time,
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

#[cfg(test)]
mod timing_tests {
    use super::Timing;

    #[test]
    fn fastest_and_median_of_odd_and_even_counts() {
        let odd = Timing::of(&[3.0, 1.0, 2.0]);
        assert_eq!((odd.fastest, odd.median, odd.repeats), (1.0, 2.0, 3));
        let even = Timing::of(&[4.0, 1.0, 3.0, 2.0]);
        assert_eq!((even.fastest, even.median, even.repeats), (1.0, 2.5, 4));
        let one = Timing::of(&[0.5]);
        assert_eq!((one.fastest, one.median), (0.5, 0.5));
    }
}
