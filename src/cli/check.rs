//! `rocklab check`: which scenes of a results file are converged, not converged at their
//! tolerance, or ill-conditioned ([`crate::sim::check`] on each, in parallel), so a jagged
//! spectrum can be told apart from an under-resolved one.

use super::UsageError;
use crate::report;
use crate::sim::check::{Check, CheckCsvRow, Reproducibility, check};
use crate::sweep::SceneOutcome;
use rayon::prelude::*;
use std::io::IsTerminal;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct CheckArgs {
    /// Results file (results.json) or the directory holding it.
    pub results: PathBuf,
    /// Only these scenes: indices and ranges, `3,7,10-20` (default: every finished scene).
    #[arg(long, value_delimiter = ',', value_parser = parse_range)]
    pub scenes: Option<Vec<(usize, usize)>>,
    /// Write one row per scene and quantity here (default: check.csv beside the results):
    /// scene, verdict, rtol, reference_rtol, quantity, value, reference, change, condition (κ),
    /// negligible, overturn_flips.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// At most this many of the scenes that are not converged or ill-conditioned are listed
    /// in the summary, the largest κ first.
    #[arg(long, default_value_t = 10)]
    pub worst: usize,
    /// Wall-clock limit of each of a scene's check runs in seconds (0: none), as for `run`: at
    /// a 1000× tighter rtol a scene takes longer than it did in the sweep.
    #[arg(long, default_value_t = 600.0, value_parser = super::run::parse_seconds)]
    pub scene_time_limit: f64,
}

/// `7` or `10-20` (inclusive).
fn parse_range(text: &str) -> Result<(usize, usize), String> {
    let t = text.trim();
    if t.is_empty() {
        return Err("an empty entry: give scene indices and ranges, e.g. 3,7,10-20".into());
    }
    let bad = || format!("`{t}`: give scene indices and ranges, e.g. 3,7,10-20");
    let (a, b) = t.split_once('-').unwrap_or((t, t));
    let (a, b): (usize, usize) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    if a > b {
        return Err(format!(
            "`{t}`: a range runs from low to high, e.g. {b}-{a}"
        ));
    }
    Ok((a, b))
}

pub fn run(args: &CheckArgs) -> anyhow::Result<()> {
    let path = super::compare::resolve_results(&args.results);
    let results = report::load_results(&path)?;
    let chosen = |i: usize| {
        args.scenes
            .as_ref()
            .is_none_or(|r| r.iter().any(|&(a, b)| (a..=b).contains(&i)))
    };
    let (outcomes, failed_in_run): (Vec<&SceneOutcome>, Vec<&SceneOutcome>) = results
        .outcomes
        .iter()
        .filter(|o| chosen(o.point.index))
        .partition(|o| o.result.is_ok());
    // Scenes that failed in the run have no result to check; say so rather than skip them.
    let failed_note = match failed_in_run.len() {
        0 => String::new(),
        n => {
            let mut shown: Vec<String> = failed_in_run
                .iter()
                .take(10)
                .map(|o| o.point.index.to_string())
                .collect();
            if n > 10 {
                shown.push("…".into());
            }
            format!(
                "{n} selected scene{} failed in the run and cannot be checked: {}",
                if n == 1 { "" } else { "s" },
                shown.join(", ")
            )
        }
    };
    let indices = match (results.outcomes.first(), results.outcomes.last()) {
        (Some(a), Some(b)) => format!("indices {}…{}", a.point.index, b.point.index),
        _ => "none".to_string(),
    };
    if outcomes.is_empty() {
        return Err(UsageError::new(format!(
            "{}: no finished scene {}{}",
            path.display(),
            if args.scenes.is_some() {
                format!("matches --scenes (scenes in the file: {indices})")
            } else {
                "to check".to_string()
            },
            if failed_note.is_empty() {
                String::new()
            } else {
                format!(" ({failed_note})")
            }
        ))
        .into());
    }
    if let (Some(ranges), Some(last)) = (&args.scenes, results.outcomes.last()) {
        let last = last.point.index;
        if ranges.iter().any(|&(_, b)| b > last) {
            eprintln!("note: --scenes reaches past the last scene in the file ({indices})");
        }
    }
    let csv_path = args
        .csv
        .clone()
        .unwrap_or_else(|| path.with_file_name("check.csv"));
    // Opened before the work, so a bad path costs nothing.
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_path(&csv_path)
        .map_err(|e| UsageError::new(format!("--csv {}: {e}", csv_path.display())))?;
    let library = crate::excitation::library::global()?;
    let bar = std::io::stderr().is_terminal().then(|| {
        let bar = indicatif::ProgressBar::new(outcomes.len() as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} scenes checked")
                .expect("valid template"),
        );
        bar
    });
    let checks: Vec<(&SceneOutcome, Result<Check, String>)> = outcomes
        .par_iter()
        .map(|o| {
            let result = o.result.as_ref().expect("finished scenes only");
            let bounds = crate::sim::Bounds {
                measures: result.measured,
                time_limit: (args.scene_time_limit > 0.0)
                    .then(|| std::time::Duration::from_secs_f64(args.scene_time_limit)),
                ..Default::default()
            };
            let c = crate::sweep::guarded(|| check(&o.point.scene, result, library, bounds))
                .map_err(|e| e.to_string());
            if let Some(bar) = &bar {
                bar.inc(1);
            }
            (*o, c)
        })
        .collect();
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    w.write_record(CheckCsvRow::HEADER)?;
    let (mut counts, mut failed) = ([0usize; 3], Vec::new());
    for (o, c) in &checks {
        let c = match c {
            Ok(c) => c,
            Err(e) => {
                failed.push(format!("scene {}: {e}", o.point.index));
                continue;
            }
        };
        counts[c.verdict as usize] += 1;
        for row in CheckCsvRow::rows(o.point.index, c) {
            w.serialize(row)?;
        }
    }
    w.flush()?;
    println!(
        "{} scene{} checked: {} converged, {} not converged at their rtol (tighten it), {} \
         ill-conditioned (a change of {:e} in the inputs moves a peak by > 1e-3){}",
        checks.len(),
        if checks.len() == 1 { "" } else { "s" },
        counts[Reproducibility::Converged as usize],
        counts[Reproducibility::NotConverged as usize],
        counts[Reproducibility::IllConditioned as usize],
        crate::sim::check::INPUT_CHANGE,
        if failed.is_empty() {
            String::new()
        } else {
            format!(", {} checks failed", failed.len())
        }
    );
    let mut worst: Vec<(&SceneOutcome, &Check)> = checks
        .iter()
        .filter_map(|(o, c)| c.as_ref().ok().map(|c| (*o, c)))
        .filter(|(_, c)| c.verdict != Reproducibility::Converged)
        .collect();
    let condition = |c: &Check| c.worst_condition();
    worst.sort_by(|a, b| condition(b.1).total_cmp(&condition(a.1)));
    for (o, c) in worst.iter().take(args.worst) {
        let change = c.worst_change().map_or(0.0, |p| p.change);
        println!(
            "  {}: {}, κ {}, off by {change:.1e} at rtol {:e}{}",
            report::scene_title(&o.point),
            c.verdict.label(),
            crate::numfmt::fmt_condition(condition(c)),
            c.rtol,
            if c.overturn_flips {
                ", on the overturning boundary"
            } else {
                ""
            }
        );
    }
    for f in &failed {
        eprintln!("  {f}");
    }
    if !failed_note.is_empty() {
        println!("{failed_note}");
    }
    println!("per scene and quantity: {}", csv_path.display());
    Ok(())
}
