//! The one journalled round driver: a search that decides its next scenes from the results of
//! the ones before (an adaptive map's refinement, a design's bisection, an IDA's hunt and
//! fill) runs as rounds of plain sweeps through [`super::run_checkpointed`]. Each round's
//! scenes are journalled as they finish and reused from the checkpoint when present, so a
//! stop loses nothing and a rerun replays the rounds from the journal (the next round must be
//! a pure function of the finished scenes) and runs only what is missing.
//!
//! A search implements [`Rounds`]: `next_round` (the scenes to run next, from what it has
//! recorded; empty when it is done) and `record` (a round's finished scenes). [`drive`] runs
//! one to its end with any way of finishing a round; [`replay`] finishes rounds from finished
//! scenes (a journal, a results file); [`run_journalled`] finishes each round through the
//! journal.

use super::{Checkpoint, Progress, SceneOutcome, SweepOptions, run_checkpointed};
use crate::excitation::Library;
use crate::sim::SceneResult;
use crate::study::ScenePoint;
use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Finished scenes by scene key: a search's record of what ran, or a journal's or a results
/// file's scenes to replay it on.
pub type Finished = HashMap<String, Result<SceneResult, String>>;

/// Outcomes by scene key (the last one of a key wins; a key's result is the same in each).
pub fn by_key(outcomes: &[SceneOutcome]) -> Finished {
    outcomes
        .iter()
        .map(|o| (o.point.key.clone(), o.result.clone()))
        .collect()
}

/// The scenes of `points` that have finished, as outcomes in index order: what a search's
/// results hold (every probe scene it asked for, once per probe that asked).
pub fn finished_outcomes<'a>(
    points: impl Iterator<Item = &'a ScenePoint>,
    finished: &Finished,
) -> Vec<SceneOutcome> {
    let mut out: Vec<SceneOutcome> = points
        .filter_map(|p| {
            Some(SceneOutcome {
                point: p.clone(),
                result: finished.get(&p.key)?.clone(),
            })
        })
        .collect();
    out.sort_by_key(|o| o.point.index);
    out
}

/// A search that runs in rounds of scenes.
pub trait Rounds {
    /// The scenes to run next, decided from everything recorded so far; empty when the
    /// search is complete. Called once before the first round, then once after each
    /// [`Rounds::record`].
    fn next_round(&mut self) -> Vec<ScenePoint>;
    /// A round's finished scenes (a stopped round's may be fewer than it asked for).
    fn record(&mut self, outcomes: &[SceneOutcome]);
}

/// How a round ended: the scenes it finished, and whether the search may go on.
pub struct RoundEnd {
    pub outcomes: Vec<SceneOutcome>,
    /// False: stop after recording `outcomes` (cancelled, the journal failed, a scene is
    /// missing from a replay).
    pub go_on: bool,
}

/// Replay a search on finished scenes (by scene key: a journal's or a results file's): rounds
/// are finished from `finished` until one asks for a scene it lacks, which stops the replay
/// after recording what that round found. The outcomes are every scene found.
pub fn replay(rounds: &mut impl Rounds, finished: &Finished) -> RoundsRun {
    drive(rounds, |round| {
        let asked = round.len();
        let outcomes: Vec<SceneOutcome> = round
            .into_iter()
            .filter_map(|point| {
                let result = finished.get(&point.key)?.clone();
                Some(SceneOutcome { point, result })
            })
            .collect();
        RoundEnd {
            go_on: outcomes.len() == asked,
            outcomes,
        }
    })
}

/// What a driven search ran: every finished scene of every round, in the order the rounds
/// returned them, and whether the search completed (asked for no further round).
pub struct RoundsRun {
    pub outcomes: Vec<SceneOutcome>,
    pub complete: bool,
}

/// Drive `rounds` with `run_round` finishing each round's scenes, until the search asks for
/// no further round or `run_round` stops it.
pub fn drive(
    rounds: &mut impl Rounds,
    mut run_round: impl FnMut(Vec<ScenePoint>) -> RoundEnd,
) -> RoundsRun {
    let mut outcomes = Vec::new();
    loop {
        let round = rounds.next_round();
        if round.is_empty() {
            return RoundsRun {
                outcomes,
                complete: true,
            };
        }
        let end = run_round(round);
        rounds.record(&end.outcomes);
        outcomes.extend(end.outcomes);
        if !end.go_on {
            return RoundsRun {
                outcomes,
                complete: false,
            };
        }
    }
}

/// Refuses a sharded run of a round search: a round needs every verdict of the one before,
/// so shards cannot run apart. `what` names the study's kind, `why` says what to do instead.
pub fn refuse_shards(
    study: &crate::study::Study,
    opts: &SweepOptions,
    what: &str,
    why: &str,
) -> crate::error::Result<()> {
    match opts.shard {
        Some((i, n)) => crate::error::bail!(
            "study {}: {what} cannot run as shard {i}/{n}: {why}",
            study.name
        ),
        None => Ok(()),
    }
}

/// Drive `rounds` to its end, each round a [`run_checkpointed`] over its scenes: journalled
/// as they finish (`checkpoint.journal`), taken from `checkpoint.reuse` when present (each
/// reused result is handed to the first round that asks for its key). Progress reports a
/// total that grows round by round (the scenes so far plus this round's) and one `Finished`
/// at the end. Stops at the end of a round that was cancelled or whose journal failed (the
/// run is then incomplete even if that round was the last).
pub fn run_journalled(
    rounds: &mut impl Rounds,
    opts: &SweepOptions,
    library: &Library,
    checkpoint: Checkpoint,
    cancel: &AtomicBool,
    progress: &(dyn Fn(Progress) + Sync),
) -> RoundsRun {
    let Checkpoint {
        journal,
        mut reuse,
        scene_time_limit,
        measures,
    } = checkpoint;
    let done = AtomicUsize::new(0);
    let mut stopped = false;
    let mut run = drive(rounds, |round| {
        let round_reuse = round
            .iter()
            .filter_map(|p| Some((p.key.clone(), reuse.remove(&p.key)?)))
            .collect();
        let before = done.load(Ordering::Relaxed);
        let round_progress = |p: Progress| match p {
            Progress::Started { total } => progress(Progress::Started {
                total: before + total,
            }),
            Progress::SceneDone { .. } => {
                done.fetch_add(1, Ordering::Relaxed);
                progress(p)
            }
            Progress::Finished { .. } => {}
        };
        let part = run_checkpointed(
            &round,
            opts,
            library,
            Checkpoint {
                journal,
                reuse: round_reuse,
                scene_time_limit,
                measures,
            },
            cancel,
            &round_progress,
        );
        // A stop asked for while a round had nothing left to run (every scene reused) is
        // honoured here too: no round is ever started after it.
        stopped = part.cancelled
            || cancel.load(Ordering::Relaxed)
            || journal.is_some_and(|j| j.failure().is_some());
        RoundEnd {
            outcomes: part.outcomes,
            go_on: !stopped,
        }
    });
    run.complete &= !stopped;
    progress(Progress::Finished {
        cancelled: !run.complete,
    });
    run
}
