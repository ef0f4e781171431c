//! Sweeps: run a study's scenes in parallel (rayon), in shards, reusing cached results, and
//! stop cleanly on cancel. Results come back in expansion order whatever the thread count, so
//! a sweep is deterministic.

use crate::excitation::Library;
use crate::sim::{self, Quantity, SceneResult};
use crate::study::{ScenePoint, Study, StudyError, StudyKind};
pub mod adaptive;
pub mod design;
pub mod estimate;
mod facade;
pub mod hunt;
pub mod ida;
mod journal;
mod output;
pub mod rounds;
mod store;

pub use facade::{
    DirRun, Finished, SCENE_TIME_LIMIT, SetStatus, Writers, load_fullest, lock_results,
    seconds_per_scene, set_status,
};
pub use output::{OpenOptions, OutputError, OutputLock, default_out_dir, results_name};

use journal::Journal;
use output::Output;
pub use store::{RESULTS_FORMAT, load_results, results_file_json, results_identity};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Progress {
    /// `total` scenes to go through (cached ones included).
    Started {
        total: usize,
    },
    /// Scene `index` (expansion index) finished; `ok` is false for a failed scene; `reused`
    /// is true for a scene taken from the journal or cache instead of computed (progress
    /// rates and ETAs count only computed scenes).
    SceneDone {
        index: usize,
        ok: bool,
        reused: bool,
    },
    Finished {
        cancelled: bool,
    },
}

#[derive(Clone, Debug, Default)]
pub struct SweepOptions {
    /// Worker threads; None uses all cores.
    pub jobs: Option<usize>,
    /// (i, N): run only scenes whose expansion index is i mod N (0-based i).
    pub shard: Option<(usize, usize)>,
    /// A previous results file whose finished scenes are reused (matched by scene key).
    pub cache: Option<PathBuf>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneOutcome {
    pub point: ScenePoint,
    /// The scene's result, or why it failed.
    pub result: Result<SceneResult, String>,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SweepResults {
    pub study_hash: String,
    /// The study the points came from (quantities, axes); None for ad-hoc point lists.
    #[serde(default)]
    pub study: Option<Study>,
    /// Finished scenes in expansion order (cancelled or other shards' scenes are absent).
    pub outcomes: Vec<SceneOutcome>,
    /// Whether the sweep was cancelled before every selected scene ran.
    #[serde(default)]
    pub cancelled: bool,
    /// The shard this result holds, if any.
    #[serde(default)]
    pub shard: Option<(usize, usize)>,
    /// Identifies the program that computed the results ([`build_id`]); a cache is reused only
    /// by the same build, so a rebuilt rocklab never serves results of older physics.
    #[serde(default)]
    pub build: String,
    /// Map cells an adaptive map did not run: their verdict follows from the refinement rule
    /// (every known point around them agrees). Never scenes: spectra and results.csv hold
    /// only `outcomes`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub inferred: Vec<InferredCell>,
}

/// A map cell filled by an adaptive map's refinement rule instead of a run.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct InferredCell {
    /// The scene's expansion index (it was not run).
    pub index: usize,
    pub overturned: bool,
}

/// A hash of the running executable, computed once per process ("unknown" if unreadable).
pub fn build_id() -> &'static str {
    static ID: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    ID.get_or_init(|| {
        use sha2::{Digest, Sha256};
        std::env::current_exe()
            .and_then(std::fs::read)
            .map(|bytes| {
                Sha256::digest(&bytes)[..8]
                    .iter()
                    .map(|b| format!("{b:02x}"))
                    .collect()
            })
            .unwrap_or_else(|_| "unknown".into())
    })
}

/// Whether finished scenes of `previous` may be reused by this program.
pub fn reusable(previous: &SweepResults) -> bool {
    previous.build == build_id() && previous.build != "unknown"
}

/// Expand and run a whole study.
#[allow(clippy::result_large_err)]
pub fn run_study(
    study: &Study,
    opts: &SweepOptions,
    library: &Library,
    cancel: &AtomicBool,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<SweepResults, StudyError> {
    let points = study.expand()?;
    let checkpoint = Checkpoint {
        reuse: cache(opts),
        measures: crate::study::Quantity::measures(&study.quantities),
        ..Default::default()
    };
    let searched = |field: &str, e: crate::error::Error| {
        StudyError::field(field, e.to_string(), "run it without --shard")
    };
    match study.kind() {
        StudyKind::RefinedMap => {
            adaptive::run_refined(study, &points, opts, library, checkpoint, cancel, progress)
                .map_err(|e| searched("map.refine", e))
        }
        StudyKind::Design => design::run_design(study, opts, library, checkpoint, cancel, progress)
            .map_err(|e| searched("design", e)),
        StudyKind::Ida => ida::run_ida(study, opts, library, checkpoint, cancel, progress)
            .map_err(|e| searched("fragility.method", e)),
        StudyKind::Spectra | StudyKind::Map | StudyKind::Stripes => {
            let mut results =
                run_checkpointed(&points, opts, library, checkpoint, cancel, progress);
            results.study_hash = study.hash();
            results.study = Some(study.clone());
            Ok(results)
        }
    }
}

/// Whether a study is an incremental dynamic analysis (its scenes come from hunts).
pub fn is_ida(study: &Study) -> bool {
    study.kind() == StudyKind::Ida
}

/// Run `points` (or the shard's slice of them). Never panics on a bad scene: failures are
/// recorded with their reason and the sweep goes on. Records are resolved in `library`.
pub fn run(
    points: &[ScenePoint],
    opts: &SweepOptions,
    library: &Library,
    cancel: &AtomicBool,
    progress: &(dyn Fn(Progress) + Sync),
) -> SweepResults {
    let checkpoint = Checkpoint {
        reuse: cache(opts),
        ..Default::default()
    };
    run_checkpointed(points, opts, library, checkpoint, cancel, progress)
}

/// The finished scenes of the options' cache, if it may be reused.
fn cache(opts: &SweepOptions) -> HashMap<String, Result<SceneResult, String>> {
    opts.cache
        .as_ref()
        .and_then(|path| load_results(path).ok())
        .filter(reusable)
        .map(cache_by_key)
        .unwrap_or_default()
}

/// What a sweep keeps across stops: the journal it appends to, the finished scenes it
/// reuses (by scene key), and the wall-clock limit of one scene.
#[derive(Debug, Default)]
pub struct Checkpoint<'a> {
    pub journal: Option<&'a Journal>,
    pub reuse: HashMap<String, Result<SceneResult, String>>,
    /// A scene running longer is stopped and recorded as failed, with the reason.
    pub scene_time_limit: Option<std::time::Duration>,
    /// What each scene computes (the study's quantities); a finished scene is reused only if
    /// it computed all of it.
    pub measures: crate::sim::Measures,
}

/// [`run`] with each finished scene appended to the checkpoint's journal as it completes,
/// reusing its finished scenes. A scene stopped by `cancel` while it runs is not finished: it
/// is neither journalled nor returned. If the journal cannot be written (full disk), no
/// further scene starts; [`Journal::failure`] says why.
pub fn run_checkpointed(
    points: &[ScenePoint],
    opts: &SweepOptions,
    library: &Library,
    checkpoint: Checkpoint,
    cancel: &AtomicBool,
    progress: &(dyn Fn(Progress) + Sync),
) -> SweepResults {
    let Checkpoint {
        journal,
        mut reuse,
        scene_time_limit,
        measures,
    } = checkpoint;
    reuse.retain(|_, r| match r {
        Ok(r) => r.measured.covers(measures),
        Err(_) => true,
    });
    let bounds = sim::Bounds {
        cancel: Some(cancel),
        time_limit: scene_time_limit,
        measures,
        time_stages: false,
        history_rows: None,
    };
    let selected: Vec<&ScenePoint> = points
        .iter()
        .filter(|p| in_shard(p.index, opts.shard))
        .collect();
    progress(Progress::Started {
        total: selected.len(),
    });
    // Hand each reused result to its point (moved, not cloned: a resume should cost what a
    // fresh run costs); a key shared by several points is cloned for all but the last.
    let mut remaining: HashMap<&str, usize> = HashMap::new();
    for p in &selected {
        *remaining.entry(p.key.as_str()).or_default() += 1;
    }
    let work: Vec<(&ScenePoint, Option<Result<SceneResult, String>>)> = selected
        .iter()
        .map(|p| {
            let left = remaining.get_mut(p.key.as_str()).expect("counted");
            *left -= 1;
            let cached = if *left == 0 {
                reuse.remove(&p.key)
            } else {
                reuse.get(&p.key).cloned()
            };
            (*p, cached)
        })
        .collect();
    drop(reuse);
    let journal_broken = AtomicBool::new(false);
    let stopped = || cancel.load(Ordering::Relaxed) || journal_broken.load(Ordering::Relaxed);
    let run_one = |(point, cached): (&ScenePoint, Option<Result<SceneResult, String>>)| {
        let reused = cached.is_some();
        let result = match cached {
            Some(r) => r,
            None if stopped() => return None,
            None => {
                let result = run_guarded(point, library, bounds)?;
                if let Some(journal) = journal
                    && !journal.append(point.index, &point.key, &result)
                {
                    journal_broken.store(true, Ordering::Relaxed);
                }
                result
            }
        };
        progress(Progress::SceneDone {
            index: point.index,
            ok: result.is_ok(),
            reused,
        });
        Some(SceneOutcome {
            point: point.clone(),
            result,
        })
    };
    let finished: Vec<Option<SceneOutcome>> = match rayon::ThreadPoolBuilder::new()
        .num_threads(opts.jobs.unwrap_or(0))
        .build()
    {
        Ok(pool) => pool.install(|| work.into_par_iter().map(run_one).collect()),
        // No pool (e.g. threads unavailable): run on this thread.
        Err(_) => work.into_iter().map(run_one).collect(),
    };
    let cancelled = finished.iter().any(Option::is_none);
    progress(Progress::Finished { cancelled });
    SweepResults {
        study_hash: String::new(),
        study: None,
        outcomes: finished.into_iter().flatten().collect(),
        cancelled,
        shard: opts.shard,
        build: build_id().to_string(),
        inferred: Vec::new(),
    }
}

/// A study's sweep into an opened output directory, as `rocklab run` and the workbench do it:
/// the scenes the directory's journal (or results) hold are reused, every computed scene is
/// journalled as it finishes. Errors if the journal could not be written (the scenes
/// journalled before stay). The caller writes the results file ([`Output::results_path`]).
// The run's inputs as `rocklab run` names them; a struct of them would only be unpacked here.
#[allow(clippy::too_many_arguments)]
fn run_into(
    output: &mut Output,
    study: &Study,
    points: &[ScenePoint],
    opts: &SweepOptions,
    library: &Library,
    scene_time_limit: Option<std::time::Duration>,
    cancel: &AtomicBool,
    progress: &(dyn Fn(Progress) + Sync),
) -> crate::error::Result<SweepResults> {
    let measures = crate::study::Quantity::measures(&study.quantities);
    // Another study's finished scenes that this one still has (it was edited): into the
    // journal first, which is from now on their record, then reused like the journal's own.
    let mut reuse = std::mem::take(&mut output.reuse);
    let mut adopted = std::mem::take(&mut output.adopted);
    for p in points.iter().filter(|p| in_shard(p.index, opts.shard)) {
        if !reuse.contains_key(&p.key)
            && let Some(r) = adopted.remove(&p.key)
            && r.measured.covers(measures)
        {
            let r = Ok(r);
            output.journal.append(p.index, &p.key, &r);
            reuse.insert(p.key.clone(), r);
        }
    }
    drop(adopted);
    let reused = std::sync::atomic::AtomicUsize::new(0);
    let counting = |p: Progress| {
        if let Progress::SceneDone { reused: true, .. } = p {
            reused.fetch_add(1, Ordering::Relaxed);
        }
        progress(p)
    };
    let progress = &counting;
    let checkpoint = Checkpoint {
        journal: Some(&output.journal),
        reuse,
        scene_time_limit,
        measures,
    };
    let mut results = match study.kind() {
        StudyKind::RefinedMap => {
            adaptive::run_refined(study, points, opts, library, checkpoint, cancel, progress)?
        }
        StudyKind::Design => {
            design::run_design(study, opts, library, checkpoint, cancel, progress)?
        }
        StudyKind::Ida => ida::run_ida(study, opts, library, checkpoint, cancel, progress)?,
        StudyKind::Spectra | StudyKind::Map | StudyKind::Stripes => {
            run_checkpointed(points, opts, library, checkpoint, cancel, progress)
        }
    };
    results.study_hash = study.hash();
    results.study = Some(study.clone());
    output.reused = reused.into_inner();
    let journal = output.journal.path().display().to_string();
    let synced = output.journal.sync();
    if let Some(why) = output.journal.failure() {
        crate::error::bail!(
            "cannot append to the journal {journal}: {why}; the scenes journalled before are \
             kept: free some space and run the same command again"
        );
    }
    synced?;
    Ok(results)
}

/// Seconds left at the pace of the scenes computed so far: reused scenes cost nothing and say
/// nothing about the pace. None before the first computed scene.
pub fn eta_seconds(elapsed: f64, computed: usize, remaining: usize) -> Option<f64> {
    (computed > 0 && elapsed > 0.0).then(|| elapsed / computed as f64 * remaining as f64)
}

pub fn in_shard(index: usize, shard: Option<(usize, usize)>) -> bool {
    shard.is_none_or(|(i, n)| index % n == i)
}

/// One scene, with a panic in the core recorded as a failure instead of ending the sweep.
/// None if it was cancelled before it finished.
fn run_guarded(
    point: &ScenePoint,
    library: &Library,
    bounds: sim::Bounds,
) -> Option<Result<SceneResult, String>> {
    let result = match guarded(|| sim::run_bounded(&point.scene, library, bounds)) {
        Err(Guarded::Sim(sim::SimError::Cancelled)) => return None,
        other => other.map_err(|e| e.to_string()),
    };
    Some(result.and_then(|r| {
        if all_finite(&r) {
            Ok(r)
        } else {
            Err("the result holds a non-finite number (NaN or ∞)".into())
        }
    }))
}

/// Why a guarded run failed.
#[derive(Debug, thiserror::Error)]
pub enum Guarded {
    #[error(transparent)]
    Sim(#[from] sim::SimError),
    #[error("internal error (panic): {0}")]
    Panic(String),
}

/// Run `f`, with a panic turned into an error: a failure of one scene, never of the caller.
pub fn guarded<T>(f: impl FnOnce() -> Result<T, sim::SimError>) -> Result<T, Guarded> {
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).map_err(|panic| {
        let msg = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        Guarded::Panic(msg)
    })?;
    Ok(outcome?)
}

/// Whether the numbers of a result are finite (JSON cannot carry NaN or ∞, and a peak that is
/// not finite is not a response).
fn all_finite(r: &SceneResult) -> bool {
    [r.end_time, r.energy_residual]
        .into_iter()
        .chain(Quantity::ALL.into_iter().filter_map(|q| q.peak(r)))
        .chain(r.energy.terms())
        .all(f64::is_finite)
}

/// Finished scenes of a previous run by key. Failures are not reused: they may come from the
/// environment (a missing record file) and rerunning them is cheap.
fn cache_by_key(results: SweepResults) -> HashMap<String, Result<SceneResult, String>> {
    results
        .outcomes
        .into_iter()
        .filter(|o| o.result.is_ok())
        .map(|o| (o.point.key, o.result))
        .collect()
}

/// Combine shard results of one study into one, in expansion order. Errors if the shards
/// come from different studies or builds (unless `force`: the merged results then carry no
/// build and are never reused as current), or overlap inconsistently.
pub fn merge(parts: Vec<SweepResults>, force: bool) -> crate::error::Result<SweepResults> {
    let Some(first) = parts.first() else {
        crate::error::bail!("nothing to merge");
    };
    let hash = first.study_hash.clone();
    let study = first.study.clone();
    let mut build = first.build.clone();
    let mut by_index: std::collections::BTreeMap<usize, SceneOutcome> = Default::default();
    let mut cancelled = false;
    for part in parts {
        if part.study_hash != hash {
            crate::error::bail!(
                "results of different studies (hash {} and {}) cannot be merged",
                hash,
                part.study_hash
            );
        }
        if part.build != build {
            if !force {
                crate::error::bail!(
                    "shards computed by different builds of rocklab ({} and {}) are not merged: \
                     rerun the stale shards, or pass --force to merge them anyway (the merged \
                     results are then never reused as current)",
                    build,
                    part.build
                );
            }
            build = "mixed".into();
        }
        cancelled |= part.cancelled;
        for o in part.outcomes {
            if let Some(prev) = by_index.get(&o.point.index)
                && prev.point.key != o.point.key
            {
                crate::error::bail!("two results for scene {} disagree", o.point.index);
            }
            by_index.insert(o.point.index, o);
        }
    }
    let total = match &study {
        Some(s) => s.expand().map(|p| p.len()).unwrap_or(by_index.len()),
        None => by_index.len(),
    };
    let outcomes: Vec<SceneOutcome> = by_index.into_values().collect();
    // An adaptive map is complete when its refinement is, not when every cell ran.
    let inferred = study.as_ref().and_then(|s| adaptive::replay(s, &outcomes));
    let complete = match (&study, &inferred) {
        (Some(s), _) if s.kind() == StudyKind::RefinedMap => inferred.is_some(),
        _ => outcomes.len() >= total,
    };
    Ok(SweepResults {
        study_hash: hash,
        study,
        cancelled: cancelled || !complete,
        outcomes,
        shard: None,
        build,
        inferred: inferred.unwrap_or_default(),
    })
}
