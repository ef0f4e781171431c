//! `rocklab.run`: a study through the same journalled, resumable sweep as `rocklab run`, with
//! the GIL released while it runs and Ctrl-C turned into the sweep's cancellation.

use pyo3::prelude::*;
use rocklab::cli::run::{DirOutcome, RunPlan, default_out, run_into_dir};
use rocklab::sweep::{OpenOptions, Progress, SCENE_TIME_LIMIT};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Duration;

/// How often the waiting thread looks for a signal and reports progress.
const POLL: Duration = Duration::from_millis(100);

/// Scenes finished (computed or reused) and the total, as the sweep reports them.
#[derive(Default)]
struct Counts {
    total: AtomicUsize,
    done: AtomicUsize,
    reused: AtomicUsize,
}

impl Counts {
    fn record(&self, p: Progress) {
        match p {
            Progress::Started { total } => self.total.store(total, Ordering::Relaxed),
            Progress::SceneDone { reused, .. } => {
                self.done.fetch_add(1, Ordering::Relaxed);
                if reused {
                    self.reused.fetch_add(1, Ordering::Relaxed);
                }
            }
            Progress::Finished { .. } => {}
        }
    }

    fn snapshot(&self) -> (usize, usize) {
        (
            self.done.load(Ordering::Relaxed),
            self.total.load(Ordering::Relaxed),
        )
    }
}

/// Run a study (a path, `default`, or RON text with `is_text`) into `out` (default
/// `out/<study name>`, as `rocklab run`). `progress(done, total)` is called from this thread
/// when the count changes. Returns (results directory, results file, scenes, reused, notes).
/// Ctrl-C (or any Python signal handler that raises) cancels the sweep: the finished scenes
/// stay in the journal, the partial results are written, and the exception is raised.
#[pyfunction]
#[pyo3(signature = (study, is_text=false, out=None, jobs=None, fresh=false, progress=None))]
pub fn run(
    py: Python<'_>,
    study: &str,
    is_text: bool,
    out: Option<PathBuf>,
    jobs: Option<usize>,
    fresh: bool,
    progress: Option<PyObject>,
) -> PyResult<(PathBuf, PathBuf, usize, usize, Vec<String>)> {
    let (study, _) = crate::load_study(study, is_text).map_err(crate::to_py)?;
    if jobs == Some(0) {
        return Err(crate::StudyError::new_err("jobs must be at least 1"));
    }
    let points = study
        .expand()
        .map_err(|e| crate::StudyError::new_err(e.to_string()))?;
    let out = match out {
        Some(out) => out,
        None => default_out(&study.name).map_err(|e| crate::StudyError::new_err(e.to_string()))?,
    };
    let plan = RunPlan {
        study: &study,
        points: &points,
        out: &out,
        shard: None,
        open: OpenOptions { fresh },
        jobs,
        scene_time_limit: Some(SCENE_TIME_LIMIT),
    };
    let cancel = AtomicBool::new(false);
    let counts = Counts::default();
    let notes = std::sync::Mutex::new(Vec::new());
    let mut interrupted: Option<PyErr> = None;
    let mut reported = (usize::MAX, 0);
    let ran = std::thread::scope(|scope| {
        let sweep = scope.spawn(|| {
            let on_open = |dir: &rocklab::sweep::DirRun| {
                notes
                    .lock()
                    .expect("notes")
                    .extend(dir.notes().iter().cloned());
            };
            run_into_dir(&plan, &cancel, &|p| counts.record(p), &on_open, &|_, _| {})
        });
        // This thread waits without the GIL, and takes it back every POLL to report
        // progress and to let Python's signal handlers run.
        while !sweep.is_finished() {
            py.allow_threads(|| std::thread::sleep(POLL));
            if interrupted.is_none()
                && let Err(e) = py.check_signals()
            {
                cancel.store(true, Ordering::Relaxed);
                interrupted = Some(e);
            }
            let now = counts.snapshot();
            if let Some(callback) = &progress
                && now != reported
                && now.1 > 0
            {
                reported = now;
                if let Err(e) = callback.call1(py, now) {
                    cancel.store(true, Ordering::Relaxed);
                    interrupted.get_or_insert(e);
                }
            }
        }
        sweep.join()
    });
    let ran = ran.map_err(|_| pyo3::exceptions::PyRuntimeError::new_err("the sweep panicked"))?;
    if let Some(callback) = &progress {
        let now = counts.snapshot();
        if now != reported && now.1 > 0 {
            callback.call1(py, now)?;
        }
    }
    if let Some(e) = interrupted {
        return Err(e);
    }
    let DirOutcome {
        finished,
        results_path,
    } = ran.map_err(crate::to_py)?;
    finished
        .written
        .map_err(|e| crate::to_py(anyhow::Error::from(e)))?;
    let results = finished.results;
    if results.cancelled {
        return Err(pyo3::exceptions::PyRuntimeError::new_err(format!(
            "cancelled: kept {} finished scenes in {}; run it again to finish",
            results.outcomes.len(),
            results_path.display()
        )));
    }
    let notes = notes.into_inner().expect("notes");
    Ok((
        out,
        results_path,
        results.outcomes.len(),
        finished.reused,
        notes,
    ))
}
