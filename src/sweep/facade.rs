//! The one run pipeline, as the CLI (`rocklab run`, `merge`, `status`), the workbench and the
//! Slurm worker use it: open an output directory (lock, resume from its journal), run with
//! every finished scene journalled, save the results file and the tables, drop what was set
//! aside; load the fullest of a results file and its journal; estimate a scene's cost. The
//! journal and the output directory's layout stay private to `sweep`.

use super::journal::{count_journal, results_from_journal};
use super::output::{OpenOptions, Output, OutputLock, journal_path, open_output};
use super::{Progress, SweepOptions, SweepResults, in_shard, load_results, run_into};
use crate::excitation::Library;
use crate::study::{ScenePoint, Study, StudyKind};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

/// The wall time after which a scene fails instead of hanging a run (`rocklab run`'s default
/// `--scene-time-limit`, and the workbench's).
pub const SCENE_TIME_LIMIT: Duration = Duration::from_secs(600);

/// An output directory opened for a run: locked, with what its journal or results hold
/// ready for reuse.
#[derive(Debug)]
pub struct DirRun {
    output: Output,
    dir: PathBuf,
    shard: Option<(usize, usize)>,
}

/// How finished results are written: the results file (with what the report derives from
/// them) and the tables beside it. `sweep` knows no report: callers pass `report::WRITERS`.
#[derive(Clone, Copy)]
pub struct Writers<'a> {
    /// The results file at a path.
    pub results: &'a (dyn Fn(&Path, &SweepResults) -> crate::error::Result<()> + Sync),
    /// The tables in a directory, for a whole study (not a shard).
    pub tables: &'a (dyn Fn(&Path, &Study, &SweepResults) -> crate::error::Result<()> + Sync),
}

impl DirRun {
    /// Prepare `dir` for `study`'s run of `total` scenes (of shard `shard`): create it, check
    /// it is writable and has room, lock the results set, decide what to reuse.
    pub fn open(
        dir: &Path,
        shard: Option<(usize, usize)>,
        study: &Study,
        total: usize,
        opts: OpenOptions,
    ) -> crate::error::Result<DirRun> {
        Ok(DirRun {
            output: open_output(dir, shard, study, total, opts)?,
            dir: dir.to_path_buf(),
            shard,
        })
    }

    /// What opening found and decided, for the user (resumed, discarded, set aside).
    pub fn notes(&self) -> &[String] {
        &self.output.notes
    }

    pub fn results_path(&self) -> &Path {
        &self.output.results_path
    }

    pub fn journal_path(&self) -> &Path {
        self.output.journal.path()
    }

    /// Run `points` of `study` (of this shard), every finished scene journalled, then save the
    /// results file and, for a whole study, the tables (`writers`). An error if the journal
    /// could not be written; otherwise the results, with [`Finished::written`] an error when a
    /// cancelled `--fresh` run left the previous complete results in place or a write failed
    /// (saying that the journal keeps every finished scene).
    #[allow(clippy::too_many_arguments)]
    pub fn run(
        mut self,
        study: &Study,
        points: &[ScenePoint],
        jobs: Option<usize>,
        library: &Library,
        scene_time_limit: Option<Duration>,
        cancel: &AtomicBool,
        progress: &(dyn Fn(Progress) + Sync),
        writers: Writers,
    ) -> crate::error::Result<Finished> {
        let opts = SweepOptions {
            jobs,
            shard: self.shard,
            cache: None,
        };
        let output = &mut self.output;
        let results = run_into(
            output,
            study,
            points,
            &opts,
            library,
            scene_time_limit,
            cancel,
            progress,
        )?;
        let journal = output.journal.path().display().to_string();
        if results.cancelled && output.keep_previous_results {
            let kept = crate::error::error!(
                "cancelled: the previous complete results in {} are kept; this --fresh run's {} \
                 finished scenes are in {journal}: run the same command without --fresh to \
                 continue it",
                output.results_path.display(),
                results.outcomes.len()
            );
            return Ok(Finished {
                results,
                written: Err(kept),
                reused: output.reused,
            });
        }
        let written = (writers.results)(&output.results_path, &results).and_then(|()| {
            if self.shard.is_none() {
                (writers.tables)(&self.dir, study, &results)
            } else {
                Ok(())
            }
        });
        let written = written.map_err(|e| {
            e.context(format!(
                "the journal {journal} keeps all {} finished scenes: fix the cause and run the \
                 same command again to write the results (or `rocklab merge {journal} --out DIR`)",
                results.outcomes.len()
            ))
        });
        if written.is_ok()
            && !results.cancelled
            && let Some(aside) = &output.set_aside
        {
            let _ = std::fs::remove_file(aside);
        }
        let reused = output.reused;
        Ok(Finished {
            results,
            written,
            reused,
        })
    }
}

/// A run's results and whether they were written.
#[derive(Debug)]
pub struct Finished {
    pub results: SweepResults,
    /// Ok once the results file (and tables) are written; otherwise why not, saying where
    /// the finished scenes are kept.
    pub written: crate::error::Result<()>,
    /// Scenes reused (from the journal, or adopted from an edited study's results) instead of
    /// computed.
    pub reused: usize,
}

/// The results at `path` — a results file, its journal, or a directory holding
/// `results.json` — from whichever of the results file and its journal holds more (a run
/// stopped by SIGKILL after an earlier partial write has more in its journal). None when
/// there is neither; the results file's path with them.
pub fn load_fullest(path: &Path) -> crate::error::Result<Option<(SweepResults, PathBuf)>> {
    let (results_path, journal) = if path.is_dir() {
        let file = path.join(super::results_name(None));
        let journal = journal_path(&file);
        (file, journal)
    } else if path.extension().is_some_and(|e| e == "journal") {
        (path.with_extension("json"), path.to_path_buf())
    } else {
        (path.to_path_buf(), journal_path(path))
    };
    let from_file = results_path.exists().then(|| load_results(&results_path));
    let from_journal = journal.exists().then(|| results_from_journal(&journal));
    let results = match (from_file, from_journal) {
        (Some(Ok(a)), Some(Ok(b))) if b.outcomes.len() > a.outcomes.len() => b,
        (Some(Ok(a)), _) => a,
        (_, Some(Ok(b))) => b,
        (Some(Err(e)), _) | (None, Some(Err(e))) => return Err(e),
        (None, None) => return Ok(None),
    };
    Ok(Some((results, results_path)))
}

/// Lock the results set at `path` (a results file) for writing, as a run does; the lock is
/// held until the guard is dropped.
pub fn lock_results(path: &Path) -> crate::error::Result<OutputLock> {
    OutputLock::acquire(path)
}

/// Mean wall seconds per scene of `points`, timed on at most 12 scenes spread through them
/// (one thread, about 5 s of work at most, each scene guarded like a sweep's so a panic is a
/// failed scene, not a crash). None if nothing was timed (cancelled, or no record library).
pub fn seconds_per_scene(points: &[ScenePoint], cancel: &AtomicBool) -> Option<f64> {
    const SAMPLES: usize = 12;
    const BUDGET: Duration = Duration::from_secs(5);
    let opts = SweepOptions {
        jobs: Some(1),
        ..Default::default()
    };
    let library = crate::excitation::library::global().ok()?;
    let step = (points.len() / SAMPLES).max(1);
    let started = Instant::now();
    let mut timed = 0;
    for point in points.iter().step_by(step) {
        if cancel.load(std::sync::atomic::Ordering::Relaxed) {
            break;
        }
        super::run(std::slice::from_ref(point), &opts, library, cancel, &|_| {});
        timed += 1;
        if started.elapsed() > BUDGET {
            break;
        }
    }
    (timed > 0).then(|| started.elapsed().as_secs_f64() / timed as f64)
}

/// What is known of one results set (one per shard of a job array).
#[derive(Clone, Debug, PartialEq)]
pub struct SetStatus {
    pub shard: Option<(usize, usize)>,
    pub ok: usize,
    pub failed: usize,
    /// Scenes the set has to go through; None if nothing says (no journal, unreadable file).
    pub total: Option<usize>,
    /// The pid of the process writing this set now.
    pub running: Option<String>,
    pub study_hash: Option<String>,
    /// A search in rounds (design) not finished: it needs at most this many more scenes
    /// (`total` is None: how many exactly is known only at its end).
    pub remaining_at_most: Option<usize>,
    /// What the search has answered so far, for `rocklab status` to print.
    pub note: Option<String>,
}

impl SetStatus {
    pub fn missing(&self) -> Option<usize> {
        self.total.map(|t| t.saturating_sub(self.ok + self.failed))
    }
}

/// How far the results set at `results_path` (of shard `shard`) got, from its journal (its
/// results file when it has none), and whether a process is writing it now.
pub fn set_status(results_path: &Path, shard: Option<(usize, usize)>) -> SetStatus {
    let journal = journal_path(results_path);
    let running = OutputLock::holder(results_path);
    let mut status = SetStatus {
        shard,
        ok: 0,
        failed: 0,
        total: None,
        running,
        study_hash: None,
        remaining_at_most: None,
        note: None,
    };
    if let Ok((header, counts)) = count_journal(&journal) {
        status.ok = counts.ok;
        status.failed = counts.failed;
        status.total = Some(header.total);
        status.study_hash = Some(header.study_hash);
        // An adaptive map runs only part of its grid: it is complete when its refinement is
        // (replayed from the journal), and what is missing is unknown until then.
        if header
            .study
            .is_some_and(|s| s.kind() == StudyKind::RefinedMap)
        {
            let complete = results_from_journal(&journal).is_ok_and(|r| !r.cancelled);
            status.total = complete.then_some(status.ok + status.failed);
        }
    } else if let Ok(results) = load_results(results_path) {
        status.failed = results
            .outcomes
            .iter()
            .filter(|o| o.result.is_err())
            .count();
        status.ok = results.outcomes.len() - status.failed;
        status.total = results
            .study
            .as_ref()
            .and_then(|s| s.expand().ok())
            .map(|p| p.iter().filter(|p| in_shard(p.index, shard)).count());
        if results
            .study
            .as_ref()
            .is_some_and(|s| s.kind() == StudyKind::RefinedMap)
        {
            status.total = (!results.cancelled).then_some(status.ok + status.failed);
        }
        status.study_hash = Some(results.study_hash);
    }
    design_status(&mut status, results_path);
    status
}

/// A design study's set: its search replayed on the finished scenes (journal or results,
/// whichever holds more) says whether it is complete and bounds what is left; the nominal
/// grid's size, which the journal's header holds, means nothing for it.
fn design_status(status: &mut SetStatus, results_path: &Path) {
    let Ok(Some((results, _))) = load_fullest(results_path) else {
        return;
    };
    let Some(study) = results
        .study
        .as_ref()
        .filter(|s| s.kind() == StudyKind::Design)
    else {
        return;
    };
    let finished = (results.outcomes.iter())
        .map(|o| (o.point.key.clone(), o.result.clone()))
        .collect();
    let Ok(progress) = super::design::progress(study, &finished) else {
        return;
    };
    let done = status.ok + status.failed;
    status.total = progress.complete.then_some(done);
    status.remaining_at_most = (!progress.complete).then_some(progress.remaining_at_most);
    status.note = Some(progress.describe());
}
