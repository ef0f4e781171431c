//! `rocklab run` and `rocklab merge`: a study from its RON file (or the built-in default) to
//! results files, with a progress bar on a terminal and plain lines in batch jobs.

use super::UsageError;
use crate::report;
use crate::study::Study;
use crate::sweep::{self, Progress, SweepOptions, SweepResults};
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
    /// Rerun every scene instead of reusing finished ones from a previous results file.
    #[arg(long)]
    pub fresh: bool,
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
    /// Shard results files (results.shard-*-of-N.json).
    #[arg(required = true)]
    pub inputs: Vec<PathBuf>,
    /// Output directory for the merged results.
    #[arg(long)]
    pub out: PathBuf,
    #[arg(long)]
    pub quiet: bool,
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

/// Set by Ctrl-C; the sweep stops starting scenes and keeps what finished.
static CANCEL: AtomicBool = AtomicBool::new(false);

pub fn load_study(arg: &str) -> anyhow::Result<Study> {
    if arg == "default" && !Path::new(arg).exists() {
        return Ok(Study::builtin_default());
    }
    Study::load(Path::new(arg)).map_err(|e| UsageError::new(e.to_string()).into())
}

pub fn results_name(shard: Option<(usize, usize)>) -> String {
    match shard {
        Some((i, n)) => format!("results.shard-{i}-of-{n}.json"),
        None => "results.json".into(),
    }
}

pub fn run(args: &RunArgs) -> anyhow::Result<()> {
    let study = load_study(&args.study)?;
    if args.jobs == Some(0) {
        return Err(UsageError::new("--jobs must be at least 1").into());
    }
    if args.dry_run {
        let points = study.expand().map_err(|e| UsageError::new(e.to_string()))?;
        let mut groups: Vec<(String, usize)> = Vec::new();
        for p in &points {
            match groups.iter_mut().find(|(g, _)| *g == p.group) {
                Some((_, n)) => *n += 1,
                None => groups.push((p.group.clone(), 1)),
            }
        }
        println!(
            "study {} (hash {}): {} scenes in {} groups",
            study.name,
            study.hash(),
            points.len(),
            groups.len()
        );
        for (g, n) in groups {
            println!("  {n:>7}  {g}");
        }
        return Ok(());
    }
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out").join(&study.name));
    std::fs::create_dir_all(&out)
        .with_context(|| format!("cannot create output directory {}", out.display()))?;
    let results_path = out.join(results_name(args.shard));
    let mut cache = (!args.fresh && results_path.exists()).then(|| results_path.clone());
    if let Some(path) = &cache
        && let Ok(previous) = report::load_results(path)
        && !sweep::reusable(&previous)
    {
        eprintln!(
            "note: {} was written by another build of rocklab; rerunning every scene",
            path.display()
        );
        cache = None;
    }
    let opts = SweepOptions {
        jobs: args.jobs,
        shard: args.shard,
        cache,
    };
    // Only the first handler registration succeeds; later calls (tests) keep it.
    let _ = ctrlc::set_handler(|| CANCEL.store(true, Ordering::SeqCst));
    let reporter = Reporter::new(std::io::stderr().is_terminal());
    let started = Instant::now();
    let results = sweep::run_study(&study, &opts, &CANCEL, &|p| reporter.report(p))
        .map_err(|e| UsageError::new(e.to_string()))?;
    reporter.finish();
    let elapsed = started.elapsed();
    report::save_results(&results_path, &results)?;
    if args.shard.is_none() {
        write_tables(&out, &study, &results)?;
    }
    if !args.quiet {
        print!("{}", report::summary(&results));
    }
    eprintln!(
        "{} scenes in {:.1} s; results in {}",
        results.outcomes.len(),
        elapsed.as_secs_f64(),
        results_path.display()
    );
    if results.cancelled {
        anyhow::bail!(
            "cancelled: kept {} finished scenes in {}; run the same command again to finish",
            results.outcomes.len(),
            results_path.display()
        );
    }
    Ok(())
}

/// CSV, summary and the canonical study next to the results file.
fn write_tables(out: &Path, study: &Study, results: &SweepResults) -> anyhow::Result<()> {
    report::write_atomic(&out.join("results.csv"), &report::results_csv(results)?)?;
    report::write_atomic(
        &out.join("results.columns.csv"),
        &report::results_columns_csv(results)?,
    )?;
    report::write_atomic(
        &out.join("summary.txt"),
        report::summary(results).as_bytes(),
    )?;
    study.save(&out.join("study.ron"))
}

pub fn merge(args: &MergeArgs) -> anyhow::Result<()> {
    let parts = args
        .inputs
        .iter()
        .map(|p| report::load_results(p))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let merged = sweep::merge(parts)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create output directory {}", args.out.display()))?;
    let path = args.out.join("results.json");
    report::save_results(&path, &merged)?;
    if let Some(study) = &merged.study {
        write_tables(&args.out, study, &merged)?;
    }
    if !args.quiet {
        print!("{}", report::summary(&merged));
    }
    if merged.cancelled {
        eprintln!(
            "warning: the merged results are incomplete ({} scenes); missing shards or cancelled runs",
            merged.outcomes.len()
        );
    }
    eprintln!("merged {} files into {}", args.inputs.len(), path.display());
    Ok(())
}

/// Progress: an indicatif bar with ETA on a terminal, a plain line every few seconds otherwise.
struct Reporter {
    bar: Option<indicatif::ProgressBar>,
    total: AtomicUsize,
    done: AtomicUsize,
    failed: AtomicUsize,
    started: Instant,
    last_line: Mutex<Instant>,
}

impl Reporter {
    fn new(terminal: bool) -> Self {
        let bar = terminal.then(|| {
            let bar = indicatif::ProgressBar::new(0);
            bar.set_style(
                indicatif::ProgressStyle::with_template(
                    "{bar:40} {pos}/{len} scenes  {elapsed} elapsed, ETA {eta}  {msg}",
                )
                .expect("valid template"),
            );
            bar
        });
        Reporter {
            bar,
            total: AtomicUsize::new(0),
            done: AtomicUsize::new(0),
            failed: AtomicUsize::new(0),
            started: Instant::now(),
            last_line: Mutex::new(Instant::now()),
        }
    }

    fn report(&self, p: Progress) {
        match p {
            Progress::Started { total } => {
                self.total.store(total, Ordering::Relaxed);
                match &self.bar {
                    Some(bar) => bar.set_length(total as u64),
                    // Batch logs get a first line at once, then one every few seconds.
                    None => self.line(0, 0),
                }
            }
            Progress::SceneDone { ok, .. } => {
                let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
                if !ok {
                    self.failed.fetch_add(1, Ordering::Relaxed);
                }
                let failed = self.failed.load(Ordering::Relaxed);
                if let Some(bar) = &self.bar {
                    bar.inc(1);
                    if failed > 0 {
                        bar.set_message(format!("{failed} failed"));
                    }
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

    fn line(&self, done: usize, failed: usize) {
        let total = self.total.load(Ordering::Relaxed).max(1);
        let elapsed = self.started.elapsed().as_secs_f64();
        let eta = elapsed / done.max(1) as f64 * (total - done.min(total)) as f64;
        eprintln!(
            "progress: {done}/{total} scenes ({:.0}%), {failed} failed, {elapsed:.0} s elapsed, ETA {eta:.0} s",
            100.0 * done as f64 / total as f64
        );
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
