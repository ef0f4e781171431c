//! `rocklab bench --estimate STUDY`: how good the run-time estimate is on a real run. The study
//! is sampled as the workbench samples it (`sweep::estimate::sample_costs`), then run to the
//! end with the estimator fed as the Run screen feeds it (a refresh every 100 ms); printed:
//! the estimate of the whole run before it, at 10 % and at 50 % of its scenes (elapsed +
//! left), against the real time, beside the plain estimate main used (mean seconds of a few
//! scenes × scenes / threads before; elapsed / done × left during).

use crate::study::{Quantity, Study};
use crate::sweep::estimate::{self, RunEstimate};
use crate::sweep::{self, Progress, SweepOptions};
use std::path::Path;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// (fraction reached, elapsed, new estimate of the total, plain estimate of the total).
type Mark = (f64, f64, Option<f64>, Option<f64>);

pub fn run(path: &Path) -> anyhow::Result<()> {
    let study = Study::load(path)?;
    let points = study.expand()?;
    let n = points.len();
    let library = crate::excitation::library::global()?;
    let threads = rayon::current_num_threads();
    let strata = estimate::study_strata(&study, n);
    let measures = Quantity::measures(&study.quantities);
    let cancel = AtomicBool::new(false);
    let sampling = Instant::now();
    let model = estimate::sample_costs(
        &points,
        measures,
        &strata,
        estimate::SAMPLES_PER_STRATUM,
        Duration::from_secs(4),
        library,
        &cancel,
    );
    let sample_seconds = sampling.elapsed().as_secs_f64();
    let before = (model.as_ref()).map(|m| estimate::seconds_before_run(m, &strata, threads));
    let plain_before = sweep::seconds_per_scene(&points, &cancel)
        .map(|per| per * n as f64 / threads.min(n) as f64);

    let estimator = Mutex::new(RunEstimate::new(strata, model, threads));
    let done = AtomicUsize::new(0);
    let progress = |p: Progress| {
        if let Progress::SceneDone { index, reused, .. } = p {
            if let Ok(mut e) = estimator.lock() {
                e.scene_done(index, reused);
            }
            done.fetch_add(1, Ordering::Relaxed);
        }
    };
    let finished = AtomicBool::new(false);
    let started = Instant::now();
    let mut marks: Vec<Mark> = Vec::new();
    let results = std::thread::scope(|scope| {
        let poller = scope.spawn(|| {
            let mut marks = Vec::new();
            let mut next = [0.1, 0.5].into_iter().peekable();
            while !finished.load(Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(100));
                let elapsed = started.elapsed().as_secs_f64();
                let d = done.load(Ordering::Relaxed);
                let left = estimator
                    .lock()
                    .ok()
                    .and_then(|mut e| e.seconds_left(elapsed));
                if let Some(&f) = next.peek()
                    && d as f64 >= f * n as f64
                {
                    let plain = sweep::eta_seconds(elapsed, d, n - d).map(|l| elapsed + l);
                    marks.push((f, elapsed, left.map(|l| elapsed + l), plain));
                    next.next();
                }
            }
            marks
        });
        let opts = SweepOptions::default();
        let results = sweep::run_study(&study, &opts, library, &cancel, &progress)
            .map_err(anyhow::Error::from);
        finished.store(true, Ordering::Relaxed);
        marks = poller.join().unwrap_or_default();
        results
    })?;
    let real = started.elapsed().as_secs_f64();
    let failed = results
        .outcomes
        .iter()
        .filter(|o| o.result.is_err())
        .count();
    let show = |s: Option<f64>| s.map_or("–".to_string(), |s| format!("{s:.1}"));
    let ratio = |s: Option<f64>| s.map_or("–".to_string(), |s| format!("{:.2}×", s / real));
    println!(
        "rocklab bench --estimate {}: {n} scenes ({failed} failed), {threads} threads, sample {sample_seconds:.1} s",
        path.display()
    );
    println!(
        "| when | new estimate of the run (s) | ratio to real | plain estimate (s) | ratio to real |"
    );
    println!("|---|---|---|---|---|");
    println!(
        "| before the run | {} | {} | {} | {} |",
        show(before),
        ratio(before),
        show(plain_before),
        ratio(plain_before)
    );
    for (f, at, new, plain) in marks {
        println!(
            "| at {:.0} % ({at:.1} s in) | {} | {} | {} | {} |",
            f * 100.0,
            show(new),
            ratio(new),
            show(plain),
            ratio(plain)
        );
    }
    println!("| real | {real:.1} | 1.00× | {real:.1} | 1.00× |");
    Ok(())
}
