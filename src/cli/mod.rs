//! Command-line interface: clap commands at the edge, library errors turned into messages.

pub mod bench;
mod bench_estimate;
mod bench_quantities;
mod bench_suite;
mod bench_tui;
pub mod check;
pub mod compare;
pub mod ims;
pub mod paper;
pub mod plot;
pub mod records;
mod records_ims;
mod records_suite;
pub mod risk;
pub mod run;
pub mod simulate;
pub mod slurm;
pub mod status;
pub mod table;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "rocklab",
    version,
    about = "Seismic studies of rocking structures protected by clutched inerters"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Without a command: open the workbench in monochrome (also: NO_COLOR).
    #[arg(long)]
    pub mono: bool,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Run one scene and print its peaks.
    Simulate(Box<simulate::SimulateArgs>),
    /// List the ground-motion records (npts, dt, PGA, PGV, source).
    Records(records::RecordsArgs),
    /// Work-precision tables: peak errors, steps, RHS evaluations and time per tolerance.
    Bench(bench::BenchArgs),
    /// Run a study (RON file or `default`): parallel sweep, spectra, maps, CSV/JSON results.
    Run(run::RunArgs),
    /// The least device parameter meeting a study's design target, as a design chart: runs
    /// the study's design search (as `run` does on such a study) and prints the answer.
    Design(run::RunArgs),
    /// Combine the results of `run --shard i/N` into one.
    Merge(run::MergeArgs),
    /// Write (and with --submit submit) a Slurm job array and its merge job for a study.
    Slurm(slurm::SlurmArgs),
    /// Scenes done, failed, missing and running per shard of an output directory.
    Status(status::StatusArgs),
    /// Side-by-side spectra of two device variants and their ratio per point.
    Compare(compare::CompareArgs),
    /// Which scenes of a results file are converged, not converged, or ill-conditioned.
    Check(check::CheckArgs),
    /// The paper's results-section claims rerun against rocklab: the PAPER.md table.
    Paper(paper::PaperArgs),
    /// Which intensity measure predicts each damage state best: β of ln IDA capacity per
    /// IM, variant and damage state, with bootstrap intervals and magnitude sufficiency.
    Ims(ims::ImsArgs),

    /// Seismic risk at a site: the mean annual frequency of reaching each damage state from a
    /// fragility study's results and a hazard curve, bare against protected, with intervals;
    /// FEMA P695 collapse margins with --mce.
    Risk(risk::RiskArgs),
    /// Figures from a results file: spectra, overturning maps, a scene's histories.
    Plot(plot::PlotArgs),
    /// The results as CSV, long (tidy) or wide, with ASCII column names.
    Table(table::TableArgs),
    /// Open the terminal workbench on a saved study (default: the built-in study).
    Tui(TuiArgs),
}

#[derive(clap::Args, Debug)]
pub struct TuiArgs {
    /// Study file (RON) to open, `default` for the built-in study (the default), or results
    /// to browse: a results directory (out/<study>), a results.json or its journal.
    pub study: Option<std::path::PathBuf>,
    /// No colours: glyphs and reverse video only (also: NO_COLOR).
    #[arg(long)]
    pub mono: bool,
}

/// Open the workbench on a study file, or on the built-in default study.
fn tui(args: &TuiArgs) -> anyhow::Result<()> {
    // `default` names the built-in study, as in `rocklab run default`.
    let path = args.study.clone().filter(|p| p.as_os_str() != "default");
    let results = path
        .as_deref()
        .filter(|p| crate::tui::app::is_results_path(p));
    if let Some(p) = &path
        && !p.exists()
    {
        return Err(UsageError::new(format!(
            "{}: no such file or directory (hint: `rocklab tui` opens the built-in default \
             study, `rocklab tui out/<study>` the results of a run)",
            p.display()
        ))
        .into());
    }
    let (study, invalid) = match &path {
        _ if results.is_some() => (crate::study::Study::builtin_default(), None),
        Some(path) => crate::tui::open_study(path).map_err(UsageError::new)?,
        None => (crate::study::Study::builtin_default(), None),
    };
    // A `$ROCKLAB_RECORDS` that names no directory is refused, as by every other command,
    // before the terminal is asked for: the workbench must not fall back silently.
    crate::excitation::Library::checked_default_dir()?;
    use std::io::IsTerminal;
    if !std::io::stdout().is_terminal() || !std::io::stdin().is_terminal() {
        return Err(UsageError::new(
            "the workbench needs a terminal; for batch runs use `rocklab run <study.ron>`",
        )
        .into());
    }
    match results {
        Some(results) => crate::tui::run_results(results, args.mono),
        None => crate::tui::run(study, path, invalid, args.mono),
    }
}

/// An explicit `--records-dir` must exist: falling back to the embedded records would run a
/// silently different study.
pub fn existing_records_dir(dir: &std::path::Path) -> Result<(), UsageError> {
    if dir.is_dir() {
        Ok(())
    } else {
        Err(UsageError::new(format!(
            "--records-dir {}: no such directory",
            dir.display()
        )))
    }
}

/// Bad flags or values: reported in one line, exit code 2.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct UsageError(pub String);

impl UsageError {
    pub fn new(msg: impl Into<String>) -> Self {
        UsageError(msg.into())
    }

    pub fn invalid(flag: &str, value: f64, expected: &str) -> Self {
        // 1e-300 as 1e-300, not as 300 digits.
        let shown = crate::numfmt::fmt_exact(value);
        UsageError(format!("invalid value {shown} for {flag}: {expected}"))
    }

    /// Name the CLI flag behind a scene field.
    pub fn from_invalid(e: crate::scene::Invalid) -> Self {
        let flag = match e.field {
            "amplitude" => "--amplitude-g/--amplitude-ratio/--amplitude-alpha".to_string(),
            "frequency" => "--frequency/--frequency-ratio".to_string(),
            "initial_rotation" => "--theta0".to_string(),
            f => format!("--{}", f.replace('_', "-")),
        };
        Self::invalid(&flag, e.value, e.expected)
    }
}

/// Commands that only print (`compare … | head`) end quietly when the reader goes away, as
/// Unix tools do: the default SIGPIPE action instead of Rust's ignore-and-panic. Not for
/// `run` (a closed stderr pipe must not kill a sweep; it writes through `print_out`) nor the
/// workbench.
fn quiet_on_broken_pipe() {
    #[cfg(unix)]
    // SAFETY: setting a signal disposition to its default, before any thread is started.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

pub fn main() -> ExitCode {
    let cli = Cli::parse();
    if matches!(
        cli.command,
        Some(
            Command::Simulate(_)
                | Command::Records(_)
                | Command::Bench(_)
                | Command::Compare(_)
                | Command::Plot(_)
                | Command::Risk(_)
                | Command::Status(_)
                | Command::Table(_)
                | Command::Ims(_)
        )
    ) {
        quiet_on_broken_pipe();
    }
    let outcome = match cli.command {
        Some(Command::Simulate(args)) => simulate::run(&args),
        Some(Command::Records(args)) => records::run(&args),
        Some(Command::Bench(args)) => bench::run(&args),
        Some(Command::Run(args)) => run::run(&args),
        Some(Command::Design(args)) => run::design(&args),
        Some(Command::Merge(args)) => run::merge(&args),
        Some(Command::Slurm(args)) => slurm::run(&args),
        Some(Command::Status(args)) => status::run(&args),
        Some(Command::Compare(args)) => compare::run(&args),
        Some(Command::Check(args)) => check::run(&args),
        Some(Command::Plot(args)) => plot::run(&args),
        Some(Command::Risk(args)) => risk::run(&args),
        Some(Command::Paper(args)) => paper::run(&args),
        Some(Command::Ims(args)) => ims::run(&args),
        Some(Command::Table(args)) => table::run(&args),
        Some(Command::Tui(args)) => tui(&args),
        None => tui(&TuiArgs {
            study: None,
            mono: cli.mono,
        }),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let usage = e.downcast_ref::<UsageError>().is_some();
            eprintln!("error: {e:#}");
            ExitCode::from(if usage { 2 } else { 1 })
        }
    }
}
