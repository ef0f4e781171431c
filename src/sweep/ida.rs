//! Incremental dynamic analysis (a fragility section with `method: ida(resolution: r)`): one
//! [`Hunt`] per record and structure variant over the study's `scale` values (the ladder),
//! run as rounds through the journalled round driver (`rounds.rs`): each round is the next
//! probe of every unfinished hunt, all in parallel. The ladder's scenes are the study's own
//! points; a bisection probe is the same scene at another intensity, numbered after the
//! study's expansion (`Layout::len()` + subject × [`probe_slots`] + its place in the hunt, so
//! a resumed run numbers it the same). Every decision is a function of finished scenes, so a
//! stop loses only the running scenes and a rerun replays the hunts from the journal.

// StudyError is large by design (file, position, field, hint; built once): see study/mod.rs.
#![allow(clippy::result_large_err)]

use super::hunt::{Hunt, Response, StateResult};
use super::rounds::{self, Finished, RoundEnd, Rounds};
use super::{Checkpoint, Progress, SceneOutcome, SweepOptions, SweepResults, build_id};
use crate::excitation::Library;
use crate::scene::{Excitation, RecordScale, Scene};
use crate::sim::{Quantity, SceneResult};
use crate::study::fragility::MAX_BISECTIONS;
use crate::study::{Layout, Param, ScenePoint, Study, StudyError, scene_key};
use std::collections::{HashMap, HashSet};
use std::sync::atomic::AtomicBool;

/// One record × variant of the analysis.
struct Subject {
    /// The ladder's scenes (study points), by increasing intensity.
    ladder: Vec<ScenePoint>,
    hunt: Hunt,
    /// Every probe's scene, in the order probed (the last may still be running).
    probes: Vec<ScenePoint>,
}

/// Where one record × variant's hunt stands.
#[derive(Clone, Debug, PartialEq)]
pub struct IdaRecord {
    /// The subject's first ladder scene (its variant, record and group).
    pub nominal: ScenePoint,
    /// Scenes run (probes with a result).
    pub probes: usize,
    /// A scene failed: the record is left out of the fit.
    pub failed: bool,
    /// The hunt asked for no further probe.
    pub done: bool,
    /// Per damage state (the section's, in order).
    pub states: Vec<(f64, StateResult)>,
    /// The ladder's top.
    pub top: f64,
}

/// The IDA over every record and variant of a study.
pub struct IdaSearch {
    subjects: Vec<Subject>,
    states: Vec<f64>,
    measure: Quantity,
    resolution: f64,
    finished: Finished,
    first_index: usize,
    slots: usize,
}

/// Most probes one hunt can make: the ladder, then per damage state at most
/// [`MAX_BISECTIONS`] bisections (validation bounds the top over the resolution) and one more.
pub fn probe_slots(ladder: usize, states: usize) -> usize {
    ladder + states * (MAX_BISECTIONS as usize + 1)
}

impl IdaSearch {
    pub fn new(study: &Study) -> Result<IdaSearch, StudyError> {
        let f = study.fragility.as_ref();
        let resolution = f.and_then(|f| f.method.ida_resolution()).ok_or_else(|| {
            StudyError::field(
                "fragility.method",
                "the study is no incremental dynamic analysis",
                "fragility: (method: ida(resolution: 0.05), …)",
            )
        })?;
        let f = f.expect("checked");
        let states = f.damage_states.levels();
        let layout = Layout::of(study)?;
        let mut by_key: HashMap<(usize, Vec<usize>), usize> = HashMap::new();
        let mut groups: Vec<Vec<ScenePoint>> = Vec::new();
        for point in study.expand()? {
            let Some((v, mut at)) = layout.locate(point.index) else {
                continue;
            };
            if let Some(s) = layout.variants[v]
                .params
                .iter()
                .position(|p| p.param == Param::Scale)
            {
                at[s] = usize::MAX;
            }
            let next = groups.len();
            let g = *by_key.entry((v, at)).or_insert(next);
            if g == next {
                groups.push(Vec::new());
            }
            groups[g].push(point);
        }
        let mut ladder_len = 0;
        let subjects = groups
            .into_iter()
            .map(|mut ladder| {
                ladder.sort_by(|a, b| intensity(a).total_cmp(&intensity(b)));
                ladder_len = ladder_len.max(ladder.len());
                let ims = ladder.iter().map(intensity).collect();
                Subject {
                    hunt: Hunt::new(ims, states.clone(), resolution),
                    ladder,
                    probes: Vec::new(),
                }
            })
            .collect();
        Ok(IdaSearch {
            subjects,
            slots: probe_slots(ladder_len, states.len()),
            states,
            measure: f.measure,
            resolution,
            finished: Finished::new(),
            first_index: layout.len(),
        })
    }

    /// The scene of subject `s` at intensity `im`: a ladder point, or the nominal scene at
    /// that intensity numbered by its place in the hunt.
    fn point_at(&self, s: usize, im: f64) -> ScenePoint {
        let subject = &self.subjects[s];
        if let Some(p) = subject.ladder.iter().find(|p| intensity(p) == im) {
            return p.clone();
        }
        let nominal = &subject.ladder[0];
        let scene = at_intensity(&nominal.scene, im);
        let mut coords = nominal.coords.clone();
        for (label, v) in &mut coords {
            if label == Param::Scale.label() {
                *v = im;
            }
        }
        ScenePoint {
            index: self.first_index + s * self.slots + subject.probes.len(),
            key: scene_key(&scene),
            scene,
            group: nominal.group.clone(),
            coords,
            // The record's draw: the hunt climbs one drawn structure.
            uncertain: nominal.uncertain.clone(),
        }
    }

    fn response(&self, result: &Result<SceneResult, String>) -> Response {
        match result {
            Err(_) => Response::Failed,
            Ok(r) if r.overturned => Response::Overturned,
            Ok(r) => match self.measure.of(r) {
                Some(v) if v.is_finite() => Response::Peak(v),
                _ => Response::Failed,
            },
        }
    }

    /// Every finished probe scene, by index.
    pub fn outcomes(&self) -> Vec<SceneOutcome> {
        rounds::finished_outcomes(self.subjects.iter().flat_map(|s| &s.probes), &self.finished)
    }

    /// Every hunt as it stands.
    pub fn records(&self) -> Vec<IdaRecord> {
        self.subjects
            .iter()
            .map(|s| IdaRecord {
                nominal: s.ladder[0].clone(),
                probes: s.hunt.probes().len(),
                failed: s.hunt.failed(),
                done: s.hunt.done(),
                states: self.states.iter().map(|&d| (d, s.hunt.result(d))).collect(),
                top: s.hunt.top(),
            })
            .collect()
    }

    pub fn complete(&self) -> bool {
        self.subjects.iter().all(|s| s.hunt.done())
    }

    /// Scenes the same ladder would take as stripes (every record × variant × level).
    pub fn stripe_scenes(&self) -> usize {
        self.subjects.iter().map(|s| s.ladder.len()).sum()
    }

    /// Scenes of stripes as fine as the resolution: from the ladder's bottom to its top in
    /// steps of the resolution, every record × variant.
    pub fn fine_stripe_scenes(&self) -> usize {
        self.subjects
            .iter()
            .map(|s| {
                let (bottom, top) = (intensity(&s.ladder[0]), s.hunt.top());
                ((top - bottom) / self.resolution).ceil() as usize + 1
            })
            .sum()
    }
}

impl Rounds for IdaSearch {
    /// Advance every hunt through its finished probes; the next round is each unfinished
    /// hunt's next unfinished probe.
    fn next_round(&mut self) -> Vec<ScenePoint> {
        let mut round = Vec::new();
        let mut seen = HashSet::new();
        for s in 0..self.subjects.len() {
            while let Some(im) = self.subjects[s].hunt.next() {
                let point = self.point_at(s, im);
                let Some(result) = self.finished.get(&point.key) else {
                    if seen.insert(point.key.clone()) {
                        round.push(point);
                    }
                    break;
                };
                let response = self.response(result);
                let subject = &mut self.subjects[s];
                subject.hunt.record(im, response);
                subject.probes.push(point);
            }
        }
        round
    }

    fn record(&mut self, outcomes: &[SceneOutcome]) {
        for o in outcomes {
            self.finished.insert(o.point.key.clone(), o.result.clone());
        }
    }
}

/// The intensity of a study point (its record's `scale` value).
fn intensity(p: &ScenePoint) -> f64 {
    match &p.scene.excitation {
        Excitation::Record { scale, .. } => scale.value(),
        _ => f64::NAN,
    }
}

/// The scene with its record scaled to `im` of the same intensity measure.
fn at_intensity(scene: &Scene, im: f64) -> Scene {
    let mut scene = scene.clone();
    if let Excitation::Record { scale, .. } = &mut scene.excitation {
        *scale = match *scale {
            RecordScale::Factor(_) => RecordScale::Factor(im),
            RecordScale::Pga(_) => RecordScale::Pga(im),
            RecordScale::Pgv(_) => RecordScale::Pgv(im),
            RecordScale::PgaStar(_) => RecordScale::PgaStar(im),
            RecordScale::PgvStar(_) => RecordScale::PgvStar(im),
        };
    }
    scene
}

/// The IDA recomputed from finished scenes (a results file): the hunts replayed on them,
/// unfinished where a scene they need is missing.
pub fn replay(study: &Study, outcomes: &[SceneOutcome]) -> Result<IdaSearch, StudyError> {
    let by_key = rounds::by_key(outcomes);
    let mut search = IdaSearch::new(study)?;
    rounds::drive(&mut search, |round| {
        let outcomes: Vec<SceneOutcome> = round
            .into_iter()
            .filter_map(|point| {
                let result = by_key.get(&point.key)?.clone();
                Some(SceneOutcome { point, result })
            })
            .collect();
        // A round with a missing scene cannot finish: stop after recording the rest.
        let go_on = !outcomes.is_empty();
        RoundEnd { outcomes, go_on }
    });
    Ok(search)
}

/// An IDA study's sweep: the hunts' rounds through the journal. The results hold every probe
/// scene. Sharding is refused: each probe needs the one before.
pub fn run_ida(
    study: &Study,
    opts: &SweepOptions,
    library: &Library,
    checkpoint: Checkpoint,
    cancel: &AtomicBool,
    progress: &(dyn Fn(Progress) + Sync),
) -> crate::error::Result<SweepResults> {
    rounds::refuse_shards(
        study,
        opts,
        "an incremental dynamic analysis",
        "each probe of a record's hunt needs the verdict of the one before; run it unsharded",
    )?;
    let mut search = IdaSearch::new(study).map_err(|e| crate::error::error!("{e}"))?;
    let run = rounds::run_journalled(&mut search, opts, library, checkpoint, cancel, progress);
    Ok(SweepResults {
        study_hash: study.hash(),
        study: Some(study.clone()),
        outcomes: search.outcomes(),
        cancelled: !run.complete,
        shard: None,
        build: build_id().to_string(),
        inferred: Vec::new(),
    })
}
