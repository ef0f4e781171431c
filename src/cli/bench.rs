//! `rocklab bench`: work-precision tables. For each representative scene and tolerance, the
//! relative error of every peak against a tight reference, with wall time, steps and RHS
//! evaluations. Times are medians over repeats, measured in one run so ratios are meaningful.

use crate::excitation::PulseShape;
use crate::presets::{
    flexible_fig14, flexible_landers, flexible_northridge, flexible_wide_landers, inerter,
    mechanistic, mechanistic_xi_theta, rigid_fig8, rigid_northridge, sequential,
};
use crate::scene::*;
use crate::sim::{self, Quantity, SceneResult};
use clap::Args;
use std::time::Instant;

#[derive(Args, Debug, Clone)]
pub struct BenchArgs {
    /// Tolerances to tabulate.
    #[arg(long, value_delimiter = ',', default_values_t = vec![1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10])]
    pub rtol: Vec<f64>,
    /// Tolerance of the reference solution.
    #[arg(long, default_value_t = 1e-12)]
    pub reference: f64,
    /// Timing repeats per cell (the median is reported).
    #[arg(long, default_value_t = 5)]
    pub repeats: usize,
    /// Only scenes whose name contains this.
    #[arg(long)]
    pub only: Option<String>,
    /// Skip the sweep-throughput table (Fig. 12 and Fig. 24 studies on 1 and 2 threads).
    #[arg(long)]
    pub no_sweeps: bool,
    /// Print only what each optional quantity (drift, accelerations, energy ledger) costs.
    #[arg(long)]
    pub quantity_costs: bool,
    /// Only the method comparison (DP54 against DOP853 on the Fig. 8 scenes).
    #[arg(long)]
    pub methods_only: bool,
    /// Only the record-suite throughput: scenes per second of a fragility study's scenes
    /// (every component of --suite-dir × the far-field stripes × bare, sequential and
    /// mechanistic blocks) on one and two threads.
    #[arg(long)]
    pub record_suite: bool,
    /// The record suite's directory (one file per component).
    #[arg(long, default_value = "records/fema-p695/farfield")]
    pub suite_dir: std::path::PathBuf,
    /// Run only this many components of the suite, spread over it.
    #[arg(long)]
    pub suite_records: Option<usize>,
    /// Only the workbench's latency on this study: keystrokes and edits (median, worst),
    /// driven headlessly on an 80×24 frame (e.g. benches/tui_333k.ron).
    #[arg(long, value_name = "STUDY")]
    pub tui: Option<std::path::PathBuf>,
    /// Only the run-time estimate on this study: sampled, then run to the end; the estimate
    /// before, at 10 % and at 50 % against the real time (e.g. benches/estimate_53k.ron).
    #[arg(long, value_name = "STUDY")]
    pub estimate: Option<std::path::PathBuf>,
    /// With --tui: keystrokes to time.
    #[arg(long, default_value_t = 60)]
    pub keys: usize,
    /// With --tui: edits to time (each changes the scene count).
    #[arg(long, default_value_t = 4)]
    pub edits: usize,
}

/// The studies whose sweep throughput the bench reports, embedded so the bench runs anywhere.
const SWEEP_STUDIES: [(&str, &str); 2] = [
    (
        "studies/fig12_rigid_spectra.ron",
        include_str!("../../studies/fig12_rigid_spectra.ron"),
    ),
    (
        "studies/fig24_records.ron",
        include_str!("../../studies/fig24_records.ron"),
    ),
];

/// Scenes per second of a whole study at its own tolerance, best of `repeats`, with `jobs`
/// worker threads. Returns (scenes, best wall seconds).
pub fn sweep_throughput(
    study: &crate::study::Study,
    jobs: usize,
    repeats: usize,
) -> anyhow::Result<(usize, f64)> {
    let points = study.expand()?;
    let opts = crate::sweep::SweepOptions {
        jobs: Some(jobs),
        shard: None,
        cache: None,
    };
    let library = crate::excitation::library::global()?;
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let mut best = f64::INFINITY;
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        // As `rocklab run` does it: the scenes compute only the study's quantities.
        let results = crate::sweep::run_study(study, &opts, library, &cancel, &|_| {})?;
        best = best.min(start.elapsed().as_secs_f64());
        if let Some(Err(e)) = results
            .outcomes
            .iter()
            .map(|o| &o.result)
            .find(|r| r.is_err())
        {
            anyhow::bail!("a scene failed in the bench sweep: {e}");
        }
    }
    Ok((points.len(), best))
}

/// A named scene for benchmarks (scenes from [`crate::presets`]).
pub struct BenchScene {
    pub name: &'static str,
    pub scene: Scene,
}

pub fn scenes() -> Vec<BenchScene> {
    vec![
        BenchScene {
            name: "rigid bare, sine pulse",
            scene: rigid_fig8(Device::None),
        },
        BenchScene {
            name: "rigid sequential, sine pulse",
            scene: rigid_fig8(sequential()),
        },
        BenchScene {
            name: "rigid mechanistic, sine pulse",
            scene: rigid_fig8(mechanistic()),
        },
        BenchScene {
            name: "rigid bare, Northridge record",
            scene: rigid_northridge(Device::None),
        },
        BenchScene {
            name: "rigid mechanistic, Northridge record",
            scene: rigid_northridge(mechanistic()),
        },
        BenchScene {
            name: "flexible sequential, Fig. 14",
            scene: flexible_fig14(sequential()),
        },
        BenchScene {
            name: "flexible mechanistic, Fig. 14",
            scene: flexible_fig14(mechanistic()),
        },
        BenchScene {
            name: "flexible bare, Landers record",
            scene: flexible_landers(Device::None),
        },
        BenchScene {
            name: "flexible inerter, Landers record",
            scene: flexible_landers(inerter()),
        },
        BenchScene {
            name: "flexible bare, Northridge record",
            scene: flexible_northridge(Device::None),
        },
        BenchScene {
            name: "flexible inerter, Northridge record",
            scene: flexible_northridge(inerter()),
        },
        BenchScene {
            name: "flexible bare, wide base, Landers record",
            scene: flexible_wide_landers(Device::None),
        },
        BenchScene {
            name: "flexible sequential, Landers record",
            scene: flexible_landers(sequential()),
        },
        BenchScene {
            name: "flexible mechanistic, Landers record",
            scene: flexible_landers(mechanistic_xi_theta(0.02)),
        },
    ]
}

/// One cell of the table.
pub struct Cell {
    pub rtol: f64,
    pub result: SceneResult,
    pub median_seconds: f64,
    /// Relative peak errors of [`ERROR_PEAKS`].
    pub errors: [f64; 4],
}

/// The peaks whose relative errors the tables give (read through the quantity table).
const ERROR_PEAKS: [Quantity; 4] = [
    Quantity::PeakRotation,
    Quantity::PeakDeformation,
    Quantity::PeakDrift,
    Quantity::PeakAbsAcceleration,
];

/// The peaks of [`ERROR_PEAKS`]; one the run did not measure reads 0, as the result holds it.
fn peaks(r: &SceneResult) -> [f64; 4] {
    ERROR_PEAKS.map(|q| q.peak(r).unwrap_or(0.0))
}

fn relative_error(a: f64, reference: f64) -> f64 {
    if reference == 0.0 {
        a.abs()
    } else {
        (a - reference).abs() / reference.abs()
    }
}

/// `scene` run `repeats` times with the time in the integrator's stages measured
/// (`Stats::stage_nanos`, a clock read before and after each trial step) and `repeats` times
/// without, alternately, so load on the machine moves both alike: the last result, the median
/// stage time (ns) less what the clock itself adds to each interval ([`clock_gap_nanos`]), and
/// the median time of the uninstrumented runs (s), what a user's run takes. (Timing both from
/// the instrumented runs counted two clock reads per trial, ~5 ns per RHS call on the
/// mechanistic block, as work outside the stages.) `measures`: the quantities computed.
pub fn stage_timed(
    scene: &Scene,
    repeats: usize,
    measures: sim::Measures,
) -> Result<(SceneResult, f64, f64), sim::SimError> {
    let library =
        crate::excitation::library::global().map_err(|e| sim::SimError::Invalid(e.to_string()))?;
    let timed_stages = sim::Bounds {
        time_stages: true,
        measures,
        ..Default::default()
    };
    let plain = sim::Bounds {
        time_stages: false,
        ..timed_stages
    };
    let gap = clock_gap_nanos();
    let (mut stages, mut wall, mut last) = (Vec::new(), Vec::new(), None);
    for _ in 0..repeats.max(1) {
        let r = sim::run_bounded(scene, library, timed_stages)?;
        let trials = (r.stats.steps + r.stats.rejected) as f64;
        stages.push((r.stats.stage_nanos as f64 - trials * gap).max(0.0));
        let start = Instant::now();
        let r = sim::run_bounded(scene, library, plain)?;
        wall.push(start.elapsed().as_secs_f64());
        last = Some(r);
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    Ok((
        last.expect("ran once"),
        median(&mut stages),
        median(&mut wall),
    ))
}

/// What a pair of clock reads adds to the interval between them: the median of 10 001
/// back-to-back `Instant` differences (~20 ns here).
fn clock_gap_nanos() -> f64 {
    let mut gaps: Vec<f64> = (0..10_001)
        .map(|_| {
            let start = Instant::now();
            start.elapsed().as_nanos() as f64
        })
        .collect();
    gaps.sort_by(f64::total_cmp);
    gaps[gaps.len() / 2]
}

/// RHS calls made inside the stages (trial steps, and DOP853's dense-output stages): the
/// calls the stage time covers (restarts and step estimates make the rest).
fn stage_calls(method: Method, st: &crate::sim::SceneStats) -> f64 {
    let trials = (st.steps + st.rejected) as f64;
    match method {
        Method::Dop853 => 12.0 * trials + 3.0 * st.steps as f64,
        _ => 6.0 * trials,
    }
    .max(1.0)
}

/// The largest relative error over the four peaks.
fn worst(errors: &[f64; 4]) -> f64 {
    errors.iter().copied().fold(0.0, f64::max)
}

/// Work-precision of both methods on the Fig. 8 bare and mechanistic scenes: peak error
/// against a DOP853 reference, RHS calls, accepted and rejected steps, RHS calls per accepted
/// step, time per RHS call all-in and in the stages alone, event-function calls per step.
fn print_method_tables(args: &BenchArgs) -> anyhow::Result<()> {
    let scenes = [
        ("Fig. 8 rigid bare", rigid_fig8(Device::None)),
        ("Fig. 8 rigid mechanistic", rigid_fig8(mechanistic())),
    ];
    for (name, scene) in scenes {
        if args
            .only
            .as_ref()
            .is_some_and(|o| !name.contains(o.as_str()))
        {
            continue;
        }
        let mut reference = scene.clone();
        reference.method = Method::Dop853;
        let (reference, _) = timed(&reference, args.reference, 1)?;
        let want = peaks(&reference);
        println!(
            "\n## Methods: {name} (errors against DOP853 at rtol {:e}; auto = DOP853 at rtol ≤ {:e})\n",
            args.reference, DOP853_BELOW_RTOL
        );
        println!(
            "| method | rtol | worst peak err | RHS calls | accepted | rejected | RHS/accepted | time (ms) | ns/RHS all-in | ns/RHS stages | all-in / stages | rotation only: all-in / stages | event calls/step | refine calls/event |"
        );
        println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
        for method in [Method::Dp54, Method::Dop853] {
            for &rtol in &args.rtol {
                let mut s = scene.clone();
                s.method = method;
                s.rtol = rtol;
                let (result, stage_nanos, seconds) =
                    stage_timed(&s, args.repeats, sim::Measures::ALL)?;
                // The same scene computing the rotation alone, as a rotation spectrum does.
                let (rot, rot_stage_nanos, rot_seconds) =
                    stage_timed(&s, args.repeats, sim::Measures::ROTATION)?;
                let rot_ratio = rot_seconds * 1e9 / rot_stage_nanos;
                let got = peaks(&result);
                let errors = std::array::from_fn(|i| relative_error(got[i], want[i]));
                let st = result.stats;
                println!(
                    "| {} | {:.0e} | {:.1e} | {} | {} | {} | {:.2} | {:.3} | {:.0} | {:.0} | {:.2} | {:.2} | {:.2} | {:.1} |",
                    method_name(method),
                    rtol,
                    worst(&errors),
                    st.rhs_evals,
                    st.steps,
                    st.rejected,
                    st.rhs_evals as f64 / st.steps.max(1) as f64,
                    seconds * 1e3,
                    seconds * 1e9 / st.rhs_evals.max(1) as f64,
                    stage_nanos / stage_calls(method, &st),
                    seconds * 1e9 / stage_nanos * stage_calls(method, &st)
                        / st.rhs_evals.max(1) as f64,
                    rot_ratio * stage_calls(method, &rot.stats) / rot.stats.rhs_evals.max(1) as f64,
                    st.event_calls as f64 / st.steps.max(1) as f64,
                    st.refine_calls as f64 / st.events.max(1) as f64,
                );
            }
        }
        print_equal_error_rows(&scene, &want, args)?;
    }
    Ok(())
}

/// The worst relative peak errors the equal-error rows aim at.
const TARGET_ERRORS: [f64; 3] = [1e-4, 1e-6, 1e-8];

/// All-in / stages where users meet it: for each target error, the loosest tolerance (half
/// decades, 1e-3 … 1e-11) at which the default method (`auto`) reaches it.
fn print_equal_error_rows(scene: &Scene, want: &[f64; 4], args: &BenchArgs) -> anyhow::Result<()> {
    let library = crate::excitation::library::global()?;
    let mut tried = Vec::new();
    for k in 6..=22 {
        let mut s = scene.clone();
        s.method = Method::Auto;
        s.rtol = 10f64.powf(-0.5 * k as f64);
        let got = peaks(&sim::run(&s, library)?);
        tried.push((
            s,
            worst(&std::array::from_fn(|i| relative_error(got[i], want[i]))),
        ));
    }
    println!(
        "\nAt equal error, method auto (the loosest of the tolerances 1e-3, 3.2e-4, … 1e-11 that meets each target):\n"
    );
    println!(
        "| target err | rtol | method | worst peak err | RHS calls | RHS/accepted | ns/RHS all-in | ns/RHS stages | all-in / stages |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for target in TARGET_ERRORS {
        let Some((s, err)) = tried.iter().find(|(_, e)| *e <= target) else {
            println!("| {target:.0e} | none reaches it | | | | | | | |");
            continue;
        };
        let method = s.method.resolve(s);
        let (result, stage_nanos, seconds) = stage_timed(s, args.repeats, sim::Measures::ALL)?;
        let st = result.stats;
        let rhs = st.rhs_evals.max(1) as f64;
        let stage_ns = stage_nanos / stage_calls(method, &st);
        println!(
            "| {target:.0e} | {:.1e} | {} | {err:.1e} | {} | {:.2} | {:.0} | {stage_ns:.0} | {:.2} |",
            s.rtol,
            method_name(method),
            st.rhs_evals,
            rhs / st.steps.max(1) as f64,
            seconds * 1e9 / rhs,
            seconds * 1e9 / rhs / stage_ns,
        );
    }
    Ok(())
}

fn method_name(method: Method) -> &'static str {
    match method {
        Method::Dop853 => "dop853",
        _ => "dp54",
    }
}

/// Run `scene` at `rtol` `repeats` times; the result of the last run and the median time.
pub fn timed(
    scene: &Scene,
    rtol: f64,
    repeats: usize,
) -> Result<(SceneResult, f64), sim::SimError> {
    let mut s = scene.clone();
    s.rtol = rtol;
    let library =
        crate::excitation::library::global().map_err(|e| sim::SimError::Invalid(e.to_string()))?;
    let mut times = Vec::with_capacity(repeats);
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        let r = sim::run(&s, library)?;
        times.push(start.elapsed().as_secs_f64());
        last = Some(r);
    }
    times.sort_by(f64::total_cmp);
    Ok((last.expect("ran once"), times[times.len() / 2]))
}

pub fn table(
    scene: &Scene,
    rtols: &[f64],
    reference: f64,
    repeats: usize,
) -> Result<Vec<Cell>, sim::SimError> {
    let (reference, _) = timed(scene, reference, 1)?;
    let want = peaks(&reference);
    rtols
        .iter()
        .map(|&rtol| {
            let (result, median_seconds) = timed(scene, rtol, repeats)?;
            let got = peaks(&result);
            let errors = std::array::from_fn(|i| relative_error(got[i], want[i]));
            Ok(Cell {
                rtol,
                result,
                median_seconds,
                errors,
            })
        })
        .collect()
}

/// Modelling only what the scene needs: the same scene with and without an optimisation, at
/// the default tolerance. Returns (without, with) results and median times.
pub fn compare_option(
    scene: &Scene,
    enable: impl Fn(&mut Scene),
    repeats: usize,
) -> Result<[(SceneResult, f64); 2], sim::SimError> {
    let mut on = scene.clone();
    enable(&mut on);
    Ok([
        timed(scene, scene.rtol, repeats)?,
        timed(&on, on.rtol, repeats)?,
    ])
}

fn print_option_table(
    title: &str,
    enable: impl Fn(&mut Scene) + Copy,
    args: &BenchArgs,
) -> anyhow::Result<()> {
    println!("\n## {title} (rtol {:e})\n", default_rtol());
    println!(
        "| scene | RHS evals off → on | time (ms) off → on | speed-up | θmax change | accel change |"
    );
    println!("|---|---|---|---|---|---|");
    for bench in scenes() {
        if args
            .only
            .as_ref()
            .is_some_and(|o| !bench.name.contains(o.as_str()))
        {
            continue;
        }
        let [(off, t_off), (on, t_on)] = compare_option(&bench.scene, enable, args.repeats)?;
        println!(
            "| {} | {} → {} | {:.3} → {:.3} | {:.2}× | {:.1e} | {:.1e} |",
            bench.name,
            off.stats.rhs_evals,
            on.stats.rhs_evals,
            t_off * 1e3,
            t_on * 1e3,
            t_off / t_on,
            relative_error(on.peaks.rotation, off.peaks.rotation),
            relative_error(on.peaks.abs_acceleration_g, off.peaks.abs_acceleration_g),
        );
    }
    Ok(())
}

/// Closed-form full contact against the integrator throughout: both at the default tolerance,
/// each with its peak errors against the integrator at the reference tolerance, for the scenes
/// where the closed form applies (a flexible structure, no device or a rigid inerter, a record).
fn print_exact_contact_table(args: &BenchArgs) -> anyhow::Result<()> {
    println!(
        "\n## Full contact in closed form (rtol {:e}; errors against the integrator at {:e})\n",
        default_rtol(),
        args.reference
    );
    println!(
        "| scene | RHS evals off → on | exact steps | time (ms) off → on | speed-up | err θmax off / on | err umax off / on | err accel off / on | energy residual off / on |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    let integrate = |s: &mut Scene| s.closed_form_contact = false;
    for bench in scenes() {
        let applies = matches!(bench.scene.structure, Structure::Flexible(_))
            && matches!(bench.scene.excitation, Excitation::Record { .. })
            && matches!(
                bench.scene.device,
                Device::None
                    | Device::Inerter {
                        coupling: Coupling::Rigid,
                        ..
                    }
            );
        if !applies
            || args
                .only
                .as_ref()
                .is_some_and(|o| !bench.name.contains(o.as_str()))
        {
            continue;
        }
        let mut off = bench.scene.clone();
        integrate(&mut off);
        let (reference, _) = timed(&off, args.reference, 1)?;
        let want = peaks(&reference);
        let [(off, t_off), (on, t_on)] =
            compare_option(&off, |s| s.closed_form_contact = true, args.repeats)?;
        let err = |r: &SceneResult, i: usize| relative_error(peaks(r)[i], want[i]);
        println!(
            "| {} | {} → {} | {} | {:.3} → {:.3} | {:.2}× | {:.1e} / {:.1e} | {:.1e} / {:.1e} | {:.1e} / {:.1e} | {:.1e} / {:.1e} |",
            bench.name,
            off.stats.rhs_evals,
            on.stats.rhs_evals,
            on.stats.closed_form_steps,
            t_off * 1e3,
            t_on * 1e3,
            t_off / t_on,
            err(&off, 0),
            err(&on, 0),
            err(&off, 1),
            err(&on, 1),
            err(&off, 3),
            err(&on, 3),
            off.energy_residual,
            on.energy_residual,
        );
    }
    Ok(())
}

pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    if let Some(study) = &args.estimate {
        return super::bench_estimate::run(study);
    }
    if let Some(study) = &args.tui {
        return super::bench_tui::run(study, args.keys, args.edits);
    }
    if args.quantity_costs {
        return super::bench_quantities::print(args);
    }
    if args.methods_only {
        return print_method_tables(args);
    }
    if args.record_suite {
        return super::bench_suite::print(args);
    }
    println!(
        "rocklab bench: relative peak errors against rtol = {:e}; time = median of {} runs",
        args.reference, args.repeats
    );
    for bench in scenes() {
        if args
            .only
            .as_ref()
            .is_some_and(|o| !bench.name.contains(o.as_str()))
        {
            continue;
        }
        println!("\n## {}\n", bench.name);
        println!(
            "| rtol | err θmax | err umax | err drift | err accel | steps | rejected | RHS evals | time (ms) |"
        );
        println!("|---|---|---|---|---|---|---|---|---|");
        for c in table(&bench.scene, &args.rtol, args.reference, args.repeats)? {
            println!(
                "| {:.0e} | {:.1e} | {:.1e} | {:.1e} | {:.1e} | {} | {} | {} | {:.3} |",
                c.rtol,
                c.errors[0],
                c.errors[1],
                c.errors[2],
                c.errors[3],
                c.result.stats.steps,
                c.result.stats.rejected,
                c.result.stats.rhs_evals,
                c.median_seconds * 1e3
            );
        }
    }
    print_option_table(
        "Free-vibration tail cut once no peak can change",
        |s| s.stop_when_settled = true,
        args,
    )?;
    if !args.no_sweeps {
        println!(
            "\n## Sweep throughput (best of {} runs)\n",
            args.repeats.clamp(1, 3)
        );
        println!("| study | scenes | threads | wall time (s) | scenes/s |");
        println!("|---|---|---|---|---|");
        for (origin, text) in SWEEP_STUDIES {
            let study = crate::study::Study::from_ron_str(text, origin)?;
            for jobs in [1, 2] {
                let (n, secs) = sweep_throughput(&study, jobs, args.repeats.clamp(1, 3))?;
                println!(
                    "| {origin} | {n} | {jobs} | {secs:.2} | {:.0} |",
                    n as f64 / secs
                );
            }
        }
    }
    println!("\n## Slender equations where their error is below the tolerance (form: auto)\n");
    println!("| α | form used | time (ms) exact → auto | speed-up | θmax change | rtol |");
    println!("|---|---|---|---|---|---|");
    for alpha in [2e-4, 5e-4, 0.01] {
        let mut exact = rigid_fig8(Device::None);
        exact.excitation = Excitation::Pulse {
            shape: PulseShape::Sine,
            amplitude: Amplitude::TanAlphaRatio(1.5),
            frequency: Frequency::Ratio(4.0),
        };
        if let Structure::Rigid(b) = &mut exact.structure {
            b.alpha = alpha;
        }
        let [(off, t_off), (on, t_on)] = compare_option(
            &exact,
            |s| {
                if let Structure::Rigid(b) = &mut s.structure {
                    b.form = Form::Auto;
                }
            },
            args.repeats,
        )?;
        println!(
            "| {alpha:e} | {:?} | {:.3} → {:.3} | {:.2}× | {:.1e} | {:e} |",
            on.form_used.unwrap_or(Form::Exact),
            t_off * 1e3,
            t_on * 1e3,
            t_off / t_on,
            relative_error(on.peaks.rotation, off.peaks.rotation),
            exact.rtol
        );
    }
    print_exact_contact_table(args)?;
    print_method_tables(args)?;
    Ok(())
}
