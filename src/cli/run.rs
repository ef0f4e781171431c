//! `rocklab run` and `rocklab merge`: a study from its RON file (or the built-in default) to
//! results files, with a progress bar on a terminal and plain lines in batch jobs.

use super::UsageError;
use crate::report;
use crate::study::{Study, StudyKind};
use crate::sweep::{self, OpenOptions, Progress, SweepResults};
use anyhow::Context;
use clap::Args;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Run a study: expand its grids, run the scenes in parallel, write results.
#[derive(Args, Debug, Clone)]
pub struct RunArgs {
    /// Study file (RON), or `default` for the built-in study.
    pub study: String,
    /// Output directory (default: out/<study name>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Run only slice i of N (0 ≤ i < N): scenes whose index is i mod N. Combine the shard
    /// files with `rocklab merge`.
    #[arg(long, value_parser = parse_shard)]
    pub shard: Option<(usize, usize)>,
    /// Rerun every scene instead of reusing finished ones. The previous results stay in
    /// place until the new run has finished.
    #[arg(long)]
    pub fresh: bool,
    /// No longer needed (kept for old scripts): another study's results in --out (an edited
    /// study's, most often) are set aside and their unchanged scenes reused.
    #[arg(long, hide = true)]
    pub force: bool,
    /// Wall-clock limit of one scene in seconds (0: none); a scene over it is recorded as
    /// failed with the reason.
    #[arg(long, default_value_t = sweep::SCENE_TIME_LIMIT.as_secs_f64(), value_parser = parse_seconds)]
    pub scene_time_limit: f64,
    /// Do not print the summary.
    #[arg(long)]
    pub quiet: bool,
    /// Validate and expand only: print the scene count per group (to size a job array).
    #[arg(long)]
    pub dry_run: bool,
}

/// Combine shard results (`rocklab run --shard i/N`) into one results set.
#[derive(Args, Debug, Clone)]
pub struct MergeArgs {
    /// Shard results files (results.shard-*-of-N.json), their journals, or a directory holding
    /// them. A shard whose final write never happened is read from its journal.
    #[arg(required = true)]
    pub inputs: Vec<PathBuf>,
    /// Merge shards computed by different builds of rocklab (never reused as current).
    #[arg(long)]
    pub force: bool,
    /// Output directory for the merged results.
    #[arg(long)]
    pub out: PathBuf,
    #[arg(long)]
    pub quiet: bool,
}

/// `out/<study name>`, as `run` and `slurm` both place a study's results (see
/// [`sweep::default_out_dir`]); a name that would leave `out/` is a usage error.
pub fn default_out(study_name: &str) -> Result<std::path::PathBuf, UsageError> {
    sweep::default_out_dir(Path::new("out"), study_name).map_err(|e| UsageError::new(e.to_string()))
}

pub(super) fn parse_seconds(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        // Checked here, once: a limit past what a Duration holds (~1.8e19 s) would panic
        // where the sweep converts it, in a worker thread.
        Ok(v) if v.is_finite() && v >= 0.0 && Duration::try_from_secs_f64(v).is_ok() => Ok(v),
        Ok(v) if v.is_finite() && v > 0.0 => Err(format!(
            "invalid time `{s}`: at most {} s (0 for no limit)",
            crate::numfmt::fmt_exact(Duration::MAX.as_secs_f64())
        )),
        _ => Err(format!("invalid time `{s}`: expected seconds ≥ 0")),
    }
}

fn parse_shard(s: &str) -> Result<(usize, usize), String> {
    let bad = || format!("invalid shard `{s}`: expected i/N with 0 ≤ i < N, e.g. 0/4");
    let (i, n) = s.split_once('/').ok_or_else(bad)?;
    let (i, n): (usize, usize) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if n == 0 || i >= n {
        return Err(bad());
    }
    Ok((i, n))
}

/// Set by SIGINT, SIGTERM or SIGHUP: the sweep stops starting scenes, stops the running ones
/// and keeps what finished. A second signal exits at once (finished scenes are journalled).
static CANCEL: AtomicBool = AtomicBool::new(false);

/// The last of those signals received (its number), for the exit status.
static SIGNAL: AtomicUsize = AtomicUsize::new(0);

/// SIGINT (Ctrl-C), SIGTERM (Slurm's time limit, `kill`) and SIGHUP (a dropped SSH session)
/// all stop a sweep the same way.
fn install_signal_handlers() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    for signal in [SIGINT, SIGTERM, SIGHUP] {
        // The shutdown goes first: it fires only once the flag is set by an earlier signal.
        let _ = signal_hook::flag::register_conditional_shutdown(signal, 128 + signal, &CANCEL);
        let _ = signal_hook::flag::register_usize(signal, &SIGNAL, signal as usize);
        let _ = signal_hook::flag::register(signal, &CANCEL);
    }
}

/// How often a finishing run looks for a signal: well under the second a batch system's
/// `--signal=B:TERM@60` warning is counted in.
const SIGNAL_POLL: Duration = Duration::from_millis(25);

/// From here on the sweep is over and every finished scene is in the journal (appended and
/// synced before the results are written): a signal while the results and tables are written
/// ends the process within [`SIGNAL_POLL`] instead of after the writes (minutes for a very
/// large study), and the same command run again writes them from the journal, computing
/// nothing. A write interrupted this way leaves the previous file in place (writes are
/// atomic renames). A sweep stopped by a signal has none to wait for: its partial results are
/// written, and a second signal ends it at once (the conditional shutdown above).
fn stop_on_signal_while_writing(results: &SweepResults, journal: PathBuf) {
    if results.cancelled {
        return;
    }
    say(&format!(
        "writing the results of {} scenes (a signal now stops at once; the journal keeps them)",
        results.outcomes.len()
    ));
    let scenes = results.outcomes.len();
    std::thread::spawn(move || {
        while !CANCEL.load(Ordering::Relaxed) {
            std::thread::sleep(SIGNAL_POLL);
        }
        let signal = SIGNAL.load(Ordering::Relaxed) as i32;
        say(&format!(
            "stopped by signal {signal} while writing the results: the journal {} keeps all \
             {scenes} finished scenes; run the same command again to write the results (it \
             computes nothing)",
            journal.display()
        ));
        // _exit: the main thread may be mid-write; nothing of ours needs flushing (the
        // journal is synced, results files are renamed into place whole or not at all).
        signal_hook::low_level::exit(128 + signal);
    });
}

/// A line on stderr that never fails the run: after SIGHUP the terminal may be gone.
fn say(msg: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "{msg}");
}

/// A line on stdout; a closed pipe (`| head`) ends the output quietly.
pub fn print_out(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(e.into()),
    }
}

pub fn load_study(arg: &str) -> anyhow::Result<Study> {
    if arg == "default" && !Path::new(arg).exists() {
        return Ok(Study::builtin_default());
    }
    Study::load(Path::new(arg)).map_err(|e| UsageError::new(e.to_string()).into())
}

pub use sweep::results_name;

/// An adaptive map cannot be split into shards (each refinement round needs every verdict of
/// the round before): refused before anything runs.
pub fn refuse_adaptive_shards(study: &Study, what: &str) -> anyhow::Result<()> {
    if study.kind() == StudyKind::RefinedMap {
        return Err(UsageError::new(format!(
            "study {}: its map is adaptive (map: (…, refine: …)) and cannot run as {what}: each \
             refinement round needs every verdict of the round before. Run it unsharded (it runs \
             only the boundary: `rocklab run`), or remove `refine` to shard the full grid",
            study.name
        ))
        .into());
    }
    Ok(())
}

/// A design study's search cannot be split into shards either (each probe needs the verdict
/// of the one before).
pub fn refuse_design_shards(study: &Study, what: &str) -> anyhow::Result<()> {
    if study.kind() == StudyKind::Design {
        return Err(UsageError::new(format!(
            "study {}: it has a design section and cannot run as {what}: each probe of the \
             search needs the verdict of the one before. Run it unsharded (`rocklab design`)",
            study.name
        ))
        .into());
    }
    if study.kind() == StudyKind::Ida {
        return Err(UsageError::new(format!(
            "study {}: it is an incremental dynamic analysis (fragility method ida) and cannot \
             run as {what}: each probe of a record's hunt needs the verdict of the one before. \
             Run it unsharded (`rocklab run`)",
            study.name
        ))
        .into());
    }
    Ok(())
}

/// `rocklab design STUDY`: `rocklab run` on a study with a design section.
pub fn design(args: &RunArgs) -> anyhow::Result<()> {
    let study = load_study(&args.study)?;
    if study.design.is_none() {
        return Err(UsageError::new(format!(
            "{}: study {} has no design section: add one, e.g. design: (parameter: sigma, \
             bracket: (0.0, 3.0), target: limit(quantity: peak_rotation_ratio, max: 0.5)) \
             (README \"Design: the least device\")",
            args.study, study.name
        ))
        .into());
    }
    run(args)
}

/// Worker threads: at least 1; more than a few per core only adds memory and contention.
fn checked_jobs(jobs: Option<usize>) -> anyhow::Result<Option<usize>> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    match jobs {
        Some(0) => Err(UsageError::new("--jobs must be at least 1").into()),
        Some(j) if j > 4 * cores => {
            say(&format!(
                "warning: --jobs {j} is more than 4 × the {cores} cores here; using {}",
                4 * cores
            ));
            Ok(Some(4 * cores))
        }
        j => Ok(j),
    }
}

pub fn run(args: &RunArgs) -> anyhow::Result<()> {
    let study = load_study(&args.study)?;
    let jobs = checked_jobs(args.jobs)?;
    let points = study.expand().map_err(|e| UsageError::new(e.to_string()))?;
    if let Some((i, n)) = args.shard {
        refuse_adaptive_shards(&study, &format!("shard {i}/{n}"))?;
        refuse_design_shards(&study, &format!("shard {i}/{n}"))?;
        if n > points.len() {
            return Err(UsageError::new(format!(
                "--shard {i}/{n}: the study has {} scenes, so at most {} shards (a shard of \
                 no scene would write an empty results file)",
                points.len(),
                points.len()
            ))
            .into());
        }
    }
    if args.dry_run {
        // Groups in order of first appearance, found by name (a study may have as many
        // groups as scenes: a scan per scene would be quadratic).
        let mut groups: Vec<(&str, usize)> = Vec::new();
        let mut at: std::collections::HashMap<&str, usize> = Default::default();
        for p in &points {
            let i = *at.entry(p.group.as_str()).or_insert_with(|| {
                groups.push((p.group.as_str(), 0));
                groups.len() - 1
            });
            groups[i].1 += 1;
        }
        let mut text = format!(
            "study {} (hash {}): {} scenes in {} groups\n",
            study.name,
            study.hash(),
            points.len(),
            groups.len()
        );
        for (g, n) in groups {
            text.push_str(&format!("  {n:>7}  {g}\n"));
        }
        if let Some(levels) = study.map.and_then(|m| m.refine_levels()) {
            let grids =
                sweep::adaptive::map_grids(&study).map_err(|e| UsageError::new(e.to_string()))?;
            let coarse = sweep::adaptive::Refinement::new(grids, levels)
                .first_points()
                .len();
            text.push_str(&format!(
                "adaptive map (levels {levels}): {coarse} scenes in the coarse lattice, then only \
                 cells along the boundary (not shardable)\n"
            ));
        }
        return print_out(&text);
    }
    let out = match &args.out {
        Some(out) => out.clone(),
        None => default_out(&study.name)?,
    };
    let reporter = Reporter::new(std::io::stderr().is_terminal());
    let started = Instant::now();
    let plan = RunPlan {
        study: &study,
        points: &points,
        out: &out,
        shard: args.shard,
        open: OpenOptions { fresh: args.fresh },
        jobs,
        scene_time_limit: (args.scene_time_limit > 0.0)
            .then(|| Duration::from_secs_f64(args.scene_time_limit)),
    };
    let on_open = |output: &sweep::DirRun| {
        for note in output.notes() {
            say(&format!("note: {note}"));
        }
        install_signal_handlers();
    };
    let before_writing = |results: &SweepResults, journal: &Path| {
        reporter.finish();
        stop_on_signal_while_writing(results, journal.to_path_buf());
    };
    let ran = run_into_dir(
        &plan,
        &CANCEL,
        &|p| reporter.report(p),
        &on_open,
        &before_writing,
    );
    reporter.finish();
    let DirOutcome {
        finished,
        results_path,
    } = ran?;
    finished.written?;
    let results = finished.results;
    let reused = finished.reused;
    drop(points);
    let elapsed = started.elapsed();
    if !args.quiet {
        print_out(&report::study_summary(&study, &results)?)?;
    }
    say(&format!(
        "{} scenes ({} reused, {} new) in {:.1} s; results in {}",
        results.outcomes.len(),
        reused,
        results.outcomes.len() - reused,
        elapsed.as_secs_f64(),
        results_path.display()
    ));
    if results.cancelled {
        anyhow::bail!(
            "cancelled: kept {} finished scenes in {}; run the same command again to finish",
            results.outcomes.len(),
            results_path.display()
        );
    }
    Ok(())
}

/// One run of a study into an output directory, as `rocklab run` makes it.
pub struct RunPlan<'a> {
    pub study: &'a Study,
    pub points: &'a [crate::study::ScenePoint],
    pub out: &'a Path,
    pub shard: Option<(usize, usize)>,
    pub open: OpenOptions,
    pub jobs: Option<usize>,
    pub scene_time_limit: Option<Duration>,
}

/// A run's results and where its results file is.
pub struct DirOutcome {
    pub finished: sweep::Finished,
    pub results_path: PathBuf,
}

/// Open the plan's directory through the sweep's façade (lock, resume from the journal) and
/// run the study into it, every finished scene journalled: the one path behind `rocklab run`
/// and Python's `rocklab.run`. `on_open` sees what opening decided before any scene runs;
/// `before_writing` gets the results and the journal's path just before the results file is
/// written.
pub fn run_into_dir(
    plan: &RunPlan,
    cancel: &AtomicBool,
    progress: &(dyn Fn(Progress) + Sync),
    on_open: &dyn Fn(&sweep::DirRun),
    before_writing: &(dyn Fn(&SweepResults, &Path) + Sync),
) -> anyhow::Result<DirOutcome> {
    let total = plan
        .points
        .iter()
        .filter(|p| sweep::in_shard(p.index, plan.shard))
        .count();
    let output = sweep::DirRun::open(plan.out, plan.shard, plan.study, total, plan.open)?;
    on_open(&output);
    let results_path = output.results_path().to_path_buf();
    let library = crate::excitation::library::global()?;
    let journal = output.journal_path().to_path_buf();
    let results_writer = |path: &Path, results: &SweepResults| {
        before_writing(results, &journal);
        (report::WRITERS.results)(path, results)
    };
    let writers = sweep::Writers {
        results: &results_writer,
        ..report::WRITERS
    };
    let finished = output.run(
        plan.study,
        plan.points,
        plan.jobs,
        library,
        plan.scene_time_limit,
        cancel,
        progress,
        writers,
    )?;
    Ok(DirOutcome {
        finished,
        results_path,
    })
}

/// The results of one merge input: a results file, a journal, or both (the fuller wins).
fn load_part(path: &Path) -> anyhow::Result<SweepResults> {
    match sweep::load_fullest(path)? {
        Some((results, _)) => Ok(results),
        None => Err(UsageError::new(format!(
            "{}: no results file or journal there",
            path.display()
        ))
        .into()),
    }
}

/// Merge inputs: files as given; a directory stands for every results set in it.
fn merge_inputs(inputs: &[PathBuf]) -> anyhow::Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for input in inputs {
        if input.is_dir() {
            let sets = super::status::result_sets(input)?;
            if sets.is_empty() {
                anyhow::bail!("{}: no shard results or journals there", input.display());
            }
            files.extend(sets.into_iter().map(|s| s.results_path));
        } else {
            files.push(input.clone());
        }
    }
    Ok(files)
}

pub fn merge(args: &MergeArgs) -> anyhow::Result<()> {
    let inputs = merge_inputs(&args.inputs)?;
    let parts = inputs
        .iter()
        .map(|p| load_part(p))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let merged = sweep::merge(parts, args.force)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create output directory {}", args.out.display()))?;
    let path = args.out.join("results.json");
    let _lock = sweep::lock_results(&path)?;
    report::save_results(&path, &merged)?;
    if let Some(study) = &merged.study {
        report::write_tables(&args.out, study, &merged)?;
    }
    if !args.quiet {
        let text = match &merged.study {
            Some(study) => report::study_summary(study, &merged)?,
            None => report::summary(&merged),
        };
        print_out(&text)?;
    }
    if merged.cancelled {
        say(&format!(
            "warning: the merged results are incomplete ({} scenes); missing shards or cancelled runs (`rocklab status` lists them)",
            merged.outcomes.len()
        ));
    }
    say(&format!(
        "merged {} files into {}",
        inputs.len(),
        path.display()
    ));
    Ok(())
}

/// Progress: an indicatif bar with ETA on a terminal, a plain line every few seconds otherwise.
struct Reporter {
    bar: Option<indicatif::ProgressBar>,
    total: AtomicUsize,
    done: AtomicUsize,
    /// Scenes reused from the journal or cache (not computed: they do not set the pace).
    reused: AtomicUsize,
    failed: AtomicUsize,
    started: Instant,
    last_line: Mutex<Instant>,
    /// Time left from the pace of computed scenes, windowed and smoothed (`sweep::estimate`).
    estimate: Mutex<Option<sweep::estimate::RunEstimate>>,
}

impl Reporter {
    fn new(terminal: bool) -> Self {
        let bar = terminal.then(|| {
            let bar = indicatif::ProgressBar::new(0);
            bar.set_style(
                indicatif::ProgressStyle::with_template(
                    "{bar:40} {pos}/{len} scenes  {elapsed} elapsed{msg}",
                )
                .expect("valid template"),
            );
            bar
        });
        Reporter {
            bar,
            total: AtomicUsize::new(0),
            done: AtomicUsize::new(0),
            reused: AtomicUsize::new(0),
            failed: AtomicUsize::new(0),
            started: Instant::now(),
            last_line: Mutex::new(Instant::now()),
            estimate: Mutex::new(None),
        }
    }

    fn report(&self, p: Progress) {
        match p {
            Progress::Started { total } => {
                self.total.store(total, Ordering::Relaxed);
                if let Ok(mut estimate) = self.estimate.lock() {
                    let strata = sweep::estimate::Strata::new(&[], total);
                    let threads = rayon::current_num_threads();
                    *estimate = Some(sweep::estimate::RunEstimate::new(strata, None, threads));
                }
                match &self.bar {
                    Some(bar) => bar.set_length(total as u64),
                    // Batch logs get a first line at once, then one every few seconds.
                    None => self.line(0, 0),
                }
            }
            Progress::SceneDone { index, ok, reused } => {
                if let Ok(mut estimate) = self.estimate.lock()
                    && let Some(estimate) = estimate.as_mut()
                {
                    estimate.scene_done(index, reused);
                }
                let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
                if !ok {
                    self.failed.fetch_add(1, Ordering::Relaxed);
                }
                if reused {
                    self.reused.fetch_add(1, Ordering::Relaxed);
                }
                let failed = self.failed.load(Ordering::Relaxed);
                if let Some(bar) = &self.bar {
                    bar.inc(1);
                    bar.set_message(self.tail(done, failed));
                } else if let Ok(mut last) = self.last_line.lock()
                    && last.elapsed() >= Duration::from_secs(5)
                {
                    *last = Instant::now();
                    self.line(done, failed);
                }
            }
            Progress::Finished { .. } => {}
        }
    }

    /// ETA (from computed scenes only), reused and failed counts, as the bar's message.
    fn tail(&self, done: usize, failed: usize) -> String {
        let total = self.total.load(Ordering::Relaxed);
        let reused = self.reused.load(Ordering::Relaxed);
        let elapsed = self.started.elapsed().as_secs_f64();
        let smoothed = (self.estimate.lock().ok())
            .and_then(|mut e| e.as_mut().and_then(|e| e.seconds_left(elapsed)));
        let plain = || sweep::eta_seconds(elapsed, done - reused, total.saturating_sub(done));
        let mut tail = match smoothed.or_else(plain) {
            Some(eta) => format!(", ETA {eta:.0} s"),
            None => ", ETA unknown".to_string(),
        };
        if reused > 0 {
            tail.push_str(&format!(", {reused} reused from cache"));
        }
        if failed > 0 {
            tail.push_str(&format!(", {failed} failed"));
        }
        tail
    }

    fn line(&self, done: usize, failed: usize) {
        let total = self.total.load(Ordering::Relaxed).max(1);
        let elapsed = self.started.elapsed().as_secs_f64();
        say(&format!(
            "progress: {done}/{total} scenes ({:.0}%), {elapsed:.0} s elapsed{}",
            100.0 * done as f64 / total as f64,
            self.tail(done, failed)
        ));
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
