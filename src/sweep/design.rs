//! The design inverse: per design point (a device variant and one value of every varying
//! parameter off the excitation axes), the least value of the sized parameter for which the
//! study's target holds at every excitation point.
//!
//! The search per point: probe both ends of the bracket; if the top fails, the target is not
//! achievable within the bracket; if the bottom passes, the answer is the bottom; otherwise
//! bisect until the bracket [lo, hi] (lo fails, hi passes) is narrower than `resolution` × hi.
//! Every probe is a full evaluation: one scene per excitation point. The response need not be
//! monotone in the parameter (rocking resurrections, clutch resonances), so after converging
//! `verify` values above the answer (denser near it) and the bracket's top are probed too; any
//! that fails marks the point non-monotone instead of presenting a threshold that is not one.
//! A failure between probes can still be missed: the verification samples, it cannot prove.
//!
//! Bisection rather than a secant: an overturning verdict is binary and a peak jumps where
//! the response changes regime (one impact more or less), so a secant model of the response
//! gains little and needs its own safeguards; bisection's probe count is known in advance
//! (log2 of the bracket over the resolution).
//!
//! The search runs through the round driver (`rounds.rs`, as adaptive maps do): each round is
//! every unfinished point's next probe, all in parallel, each scene journalled as it
//! finishes; the next round is a pure function of the finished scenes (matched by scene key),
//! so a resumed run replays the rounds from the journal and runs only what is missing, and
//! the answer can be recomputed from a results file ([`replay`]).

// StudyError is large by design (file, position, field, hint; built once): see study/mod.rs.
#![allow(clippy::result_large_err)]

mod fit;
mod points;

use super::rounds::{self, Finished, Rounds};
use super::{Checkpoint, Progress, SceneOutcome, SweepOptions, SweepResults, build_id};
use crate::excitation::Library;
use crate::study::design::{Design, DesignParameter, DesignTarget};
use crate::study::{Layout, ScenePoint, Study, StudyError, scene_key};
use fit::{FitSummary, FragilityFit};
use points::design_points;
pub use points::with_parameter;
use std::sync::atomic::AtomicBool;

/// Where a design point stands at the end (or the current state of an unfinished search).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DesignStatus {
    /// The least value is `value` (within the resolution); verified above it.
    Found,
    /// The bracket's bottom already meets the target (σ = 0: no device needed).
    MetAtLow,
    /// Even the bracket's top fails the target.
    NotAchievable,
    /// A value above the answer fails the target again: the answer is no threshold.
    NonMonotone,
    /// A variant without the parameter (the bare structure): evaluated once, meets the target.
    ReferenceMet,
    /// A variant without the parameter that fails the target.
    ReferenceFails,
    /// The search was stopped before it finished.
    Incomplete,
}

impl DesignStatus {
    pub const ALL: [DesignStatus; 7] = [
        DesignStatus::Found,
        DesignStatus::MetAtLow,
        DesignStatus::NotAchievable,
        DesignStatus::NonMonotone,
        DesignStatus::ReferenceMet,
        DesignStatus::ReferenceFails,
        DesignStatus::Incomplete,
    ];

    pub fn name(self) -> &'static str {
        match self {
            DesignStatus::Found => "found",
            DesignStatus::MetAtLow => "met_at_low",
            DesignStatus::NotAchievable => "not_achievable",
            DesignStatus::NonMonotone => "non_monotone",
            DesignStatus::ReferenceMet => "reference_met",
            DesignStatus::ReferenceFails => "reference_fails",
            DesignStatus::Incomplete => "incomplete",
        }
    }

    pub fn help(self) -> &'static str {
        match self {
            DesignStatus::Found => "least value found to the resolution, verified above it",
            DesignStatus::MetAtLow => "the bracket's low end already meets the target",
            DesignStatus::NotAchievable => "not achievable within the bracket: its top fails",
            DesignStatus::NonMonotone => "a value above the answer fails again (see fails_above)",
            DesignStatus::ReferenceMet => "variant without the parameter: meets the target",
            DesignStatus::ReferenceFails => "variant without the parameter: fails the target",
            DesignStatus::Incomplete => "the search was stopped before it finished",
        }
    }
}

/// The answer at one design point.
#[derive(Clone, Debug, PartialEq)]
pub struct DesignRow {
    /// Device variant index and label.
    pub variant: usize,
    pub device: String,
    /// The answer's axes: the varying parameters off the excitation axes (label, value), in
    /// the study's expansion order; a record (if off the excitation axes) by name in `record`.
    pub axes: Vec<(String, f64)>,
    pub record: Option<String>,
    /// The sized parameter; None for a reference variant (no such parameter).
    pub parameter: Option<DesignParameter>,
    /// The least value meeting the target (Found, MetAtLow, NonMonotone).
    pub value: Option<f64>,
    /// The final bracket: `lo` fails (or is the bracket's bottom), `hi` passes.
    pub lo: f64,
    pub hi: f64,
    /// Probes (parameter values) evaluated, and their scenes.
    pub probes: usize,
    pub scenes: usize,
    /// The excitation point of the worst response at the answer (at the bracket's top if not
    /// achievable), as `label=value` pairs, and that response (None: overturned or failed).
    pub governing: String,
    pub achieved: Option<f64>,
    /// Whether the governing scene overturned (or failed) rather than having a response.
    pub achieved_note: Option<&'static str>,
    pub status: DesignStatus,
    /// Values above the answer that fail the target (non-monotone), ascending.
    pub fails_above: Vec<f64>,
    /// Why the answer leans on the study's range: governed at an end of an excitation axis
    /// (the worst case may lie beyond it), or a fragility target whose median interval
    /// straddles the goal.
    pub warning: Option<String>,
}

/// One design point of the study's expansion.
struct Point {
    variant: usize,
    device: String,
    label_axes: Vec<(String, f64)>,
    record: Option<String>,
    sized: bool,
    /// The nominal scenes over the excitation axes, and each one's excitation text.
    nominal: Vec<ScenePoint>,
    excitation: Vec<String>,
    /// Per nominal scene: which end of an ordered excitation axis it sits at, if any.
    edges: Vec<Option<String>>,
}

/// A scene's verdict under the target.
#[derive(Clone, Copy, Debug, PartialEq)]
enum SceneVerdict {
    Response(f64),
    Overturned,
    Failed,
}

impl SceneVerdict {
    /// Larger is worse: failed and overturned above every response.
    fn rank(self) -> (u8, f64) {
        match self {
            SceneVerdict::Response(v) => (0, v),
            SceneVerdict::Overturned => (1, 0.0),
            SceneVerdict::Failed => (2, 0.0),
        }
    }
}

/// A probe's evaluation: whether every scene meets the target and the worst scene (a
/// fragility target: the fitted curve, unless a scene failed).
#[derive(Clone, Copy, Debug)]
struct Evaluation {
    pass: bool,
    worst: usize,
    verdict: SceneVerdict,
    fit: Option<FitSummary>,
}

struct Probe {
    value: f64,
    scenes: Vec<ScenePoint>,
    eval: Option<Evaluation>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    /// Waiting for both ends (or the reference's one probe).
    Ends,
    Bisect,
    Verify,
    Done,
}

struct State {
    phase: Phase,
    lo: f64,
    hi: f64,
    probes: Vec<Probe>,
    /// Probe positions the phase waits for.
    pending: Vec<usize>,
    status: DesignStatus,
}

/// The search over every design point of a study.
pub struct Search {
    design: Design,
    points: Vec<Point>,
    states: Vec<State>,
    next_index: usize,
    finished: Finished,
    /// A fragility target's fit (None: a response target).
    fragility: Option<FragilityFit>,
}

/// The design section of a design study, or an error naming the field.
fn design_of(study: &Study) -> Result<&Design, StudyError> {
    study.design.as_ref().ok_or_else(|| {
        StudyError::field(
            "design",
            "the study has no design section",
            "add design: (parameter: sigma, bracket: (0.0, 3.0), target: no_overturning)",
        )
    })
}

impl Search {
    pub fn new(study: &Study) -> Result<Search, StudyError> {
        let design = design_of(study)?.clone();
        let points = design_points(study, &design)?;
        let mut search = Search {
            states: Vec::new(),
            next_index: Layout::of(study)?.len(),
            finished: Finished::new(),
            fragility: FragilityFit::of(study)?,
            design,
            points,
        };
        for p in 0..search.points.len() {
            let (lo, hi) = search.design.bracket;
            let mut state = State {
                phase: Phase::Ends,
                lo,
                hi,
                probes: Vec::new(),
                pending: Vec::new(),
                status: DesignStatus::Incomplete,
            };
            let values = if search.points[p].sized {
                vec![lo, hi]
            } else {
                vec![f64::NAN]
            };
            for v in values {
                let at = search.add_probe(p, &mut state, v);
                state.pending.push(at);
            }
            search.states.push(state);
        }
        Ok(search)
    }

    fn add_probe(&mut self, p: usize, state: &mut State, value: f64) -> usize {
        if let Some(i) = state
            .probes
            .iter()
            .position(|q| q.value.to_bits() == value.to_bits())
        {
            return i;
        }
        let point = &self.points[p];
        let scenes = point
            .nominal
            .iter()
            .map(|n| {
                let scene = if point.sized {
                    with_parameter(&n.scene, self.design.parameter, value)
                } else {
                    n.scene.clone()
                };
                let mut coords = n.coords.clone();
                if point.sized {
                    coords.push((self.design.parameter.label().to_string(), value));
                }
                self.next_index += 1;
                ScenePoint {
                    index: self.next_index - 1,
                    key: scene_key(&scene),
                    scene,
                    group: n.group.clone(),
                    coords,
                    // Validation refuses uncertain parameters in a design.
                    uncertain: None,
                }
            })
            .collect();
        state.probes.push(Probe {
            value,
            scenes,
            eval: None,
        });
        state.probes.len() - 1
    }

    /// Whether every point's search has finished.
    pub fn complete(&self) -> bool {
        self.states.iter().all(|s| s.phase == Phase::Done)
    }

    /// Evaluate the pending probes of point `p` whose scenes have all finished; true if none
    /// is left pending unevaluated.
    fn evaluate_pending(&mut self, p: usize) -> bool {
        let target = self.design.target;
        let state = &mut self.states[p];
        let mut all = true;
        for &i in &state.pending {
            let probe = &mut state.probes[i];
            if probe.eval.is_some() {
                continue;
            }
            let eval = match &self.fragility {
                Some(fit) => evaluate_fit(fit, &probe.scenes, &self.finished),
                None => evaluate(target, &probe.scenes, &self.finished),
            };
            match eval {
                Some(e) => probe.eval = Some(e),
                None => all = false,
            }
        }
        all
    }

    /// Move point `p` on once its pending probes are evaluated.
    fn advance(&mut self, p: usize) {
        let state = &mut self.states[p];
        let pending = std::mem::take(&mut state.pending);
        let pass = |s: &State, i: usize| s.probes[i].eval.is_some_and(|e| e.pass);
        let bottom = self.design.bracket.0;
        let top = self.design.bracket.1;
        let mut next: Vec<f64> = Vec::new();
        match state.phase {
            Phase::Ends if !self.points[p].sized => {
                state.status = if pass(state, pending[0]) {
                    DesignStatus::ReferenceMet
                } else {
                    DesignStatus::ReferenceFails
                };
                state.phase = Phase::Done;
            }
            Phase::Ends => {
                let (at_lo, at_hi) = (pass(state, pending[0]), pass(state, pending[1]));
                if !at_hi {
                    state.status = DesignStatus::NotAchievable;
                    state.phase = Phase::Done;
                } else if at_lo {
                    state.hi = bottom;
                    state.phase = Phase::Verify;
                    next = verify_values(&self.design, bottom);
                } else {
                    state.phase = Phase::Bisect;
                }
            }
            Phase::Bisect => {
                let v = state.probes[pending[0]].value;
                if pass(state, pending[0]) {
                    state.hi = v;
                } else {
                    state.lo = v;
                }
            }
            Phase::Verify => {
                let fails: Vec<f64> = pending
                    .iter()
                    .filter(|&&i| !pass(state, i))
                    .map(|&i| state.probes[i].value)
                    .collect();
                state.status = match (fails.is_empty(), state.hi == bottom) {
                    (false, _) => DesignStatus::NonMonotone,
                    (true, true) => DesignStatus::MetAtLow,
                    (true, false) => DesignStatus::Found,
                };
                state.phase = Phase::Done;
            }
            Phase::Done => {}
        }
        if state.phase == Phase::Bisect {
            let (lo, hi) = (state.lo, state.hi);
            // A floor for an answer at (or next to) zero: 1e-3 of the resolution of the
            // bracket's width, so the search always ends.
            let floor = self.design.resolution * 1e-3 * (top - bottom);
            let mid = 0.5 * (lo + hi);
            // A midpoint that is an end (no f64 between them) would probe it again, and the
            // search would loop on a bracket that never narrows: there hi is the answer to
            // f64's resolution (validation keeps `resolution` above that, this is the proof).
            let unsplittable = !(lo < mid && mid < hi);
            if hi - lo <= (self.design.resolution * hi).max(floor) || unsplittable {
                state.phase = Phase::Verify;
                next = verify_values(&self.design, hi);
            } else {
                next = vec![mid];
            }
        }
        let mut state = std::mem::replace(
            &mut self.states[p],
            State {
                phase: Phase::Done,
                lo: 0.0,
                hi: 0.0,
                probes: Vec::new(),
                pending: Vec::new(),
                status: DesignStatus::Incomplete,
            },
        );
        for v in next {
            let at = self.add_probe(p, &mut state, v);
            state.pending.push(at);
        }
        self.states[p] = state;
    }

    /// An upper bound on the scenes still to run: per unfinished point, the probes it may
    /// still evaluate (both ends, every bisection down to the floor of the resolution, the
    /// verification values) less those evaluated, times its scenes per probe.
    pub fn remaining_at_most(&self) -> usize {
        let (bottom, top) = self.design.bracket;
        let floor = self.design.resolution * 1e-3 * (top - bottom);
        let bisections = ((top - bottom) / floor).log2().ceil().max(0.0) as usize;
        self.points
            .iter()
            .zip(&self.states)
            .filter(|(_, s)| s.phase != Phase::Done)
            .map(|(point, state)| {
                let most = match point.sized {
                    true => 2 + bisections + self.design.verify,
                    false => 1,
                };
                let evaluated = state.probes.iter().filter(|p| p.eval.is_some()).count();
                most.saturating_sub(evaluated) * point.nominal.len()
            })
            .sum()
    }

    /// Every scene the search has asked for that has finished, as outcomes (in index order).
    pub fn outcomes(&self) -> Vec<SceneOutcome> {
        let scenes = (self.states.iter()).flat_map(|s| s.probes.iter().flat_map(|p| &p.scenes));
        rounds::finished_outcomes(scenes, &self.finished)
    }

    /// The answer at every design point (Incomplete where the search has not finished).
    pub fn rows(&self) -> Vec<DesignRow> {
        self.points
            .iter()
            .zip(&self.states)
            .map(|(point, state)| self.row(point, state))
            .collect()
    }

    fn row(&self, point: &Point, state: &State) -> DesignRow {
        let status = state.status;
        let at_value = |v: f64| {
            state
                .probes
                .iter()
                .find(|p| p.value.to_bits() == v.to_bits())
                .and_then(|p| p.eval)
        };
        let (value, shown) = match status {
            DesignStatus::Found | DesignStatus::MetAtLow | DesignStatus::NonMonotone => {
                (Some(state.hi), at_value(state.hi))
            }
            DesignStatus::NotAchievable => (None, at_value(self.design.bracket.1)),
            DesignStatus::ReferenceMet | DesignStatus::ReferenceFails => {
                (None, state.probes.first().and_then(|p| p.eval))
            }
            DesignStatus::Incomplete => (None, None),
        };
        let fails_above = if status == DesignStatus::NonMonotone {
            let mut v: Vec<f64> = state
                .probes
                .iter()
                .filter(|p| p.value > state.hi && p.eval.is_some_and(|e| !e.pass))
                .map(|p| p.value)
                .collect();
            v.sort_by(f64::total_cmp);
            v
        } else {
            Vec::new()
        };
        let evaluated: Vec<&Probe> = state.probes.iter().filter(|p| p.eval.is_some()).collect();
        DesignRow {
            variant: point.variant,
            device: point.device.clone(),
            axes: point.label_axes.clone(),
            record: point.record.clone(),
            parameter: point.sized.then_some(self.design.parameter),
            value,
            lo: state.lo,
            hi: state.hi,
            probes: evaluated.len(),
            scenes: evaluated.iter().map(|p| p.scenes.len()).sum(),
            governing: shown.map_or(String::new(), |e| match (&self.fragility, &e.fit) {
                (Some(fit), Some(s)) => fit.governing(s),
                _ => point.excitation[e.worst].clone(),
            }),
            achieved: shown.and_then(|e| match (&self.fragility, &e.fit, e.verdict) {
                (Some(fit), Some(s), _) => fit.achieved(s),
                (_, _, SceneVerdict::Response(v)) => Some(v),
                _ => None,
            }),
            achieved_note: shown.and_then(|e| match (e.fit, e.verdict) {
                (Some(s), _) if self.fragility.as_ref()?.achieved(&s).is_none() => {
                    Some(s.status.name())
                }
                (Some(_), _) | (None, SceneVerdict::Response(_)) => None,
                (None, SceneVerdict::Overturned) => Some("overturned"),
                (None, SceneVerdict::Failed) => Some("failed"),
            }),
            status,
            fails_above,
            warning: shown.and_then(|e| match (&self.fragility, &e.fit) {
                (Some(fit), Some(s)) => fit.warning(s),
                _ => point.edges[e.worst].clone(),
            }),
        }
    }
}

impl Rounds for Search {
    /// Advance every point as far as the finished scenes allow and return the scenes of the
    /// next round (one per key, not finished yet); empty when the search is complete.
    fn next_round(&mut self) -> Vec<ScenePoint> {
        loop {
            let mut advanced = false;
            for p in 0..self.points.len() {
                while self.states[p].phase != Phase::Done && self.evaluate_pending(p) {
                    self.advance(p);
                    advanced = true;
                }
            }
            let mut seen = std::collections::HashSet::new();
            let round: Vec<ScenePoint> = self
                .states
                .iter()
                .flat_map(|s| s.pending.iter().flat_map(|&i| &s.probes[i].scenes))
                .filter(|sc| !self.finished.contains_key(&sc.key) && seen.insert(sc.key.clone()))
                .cloned()
                .collect();
            if !round.is_empty() || !advanced {
                return round;
            }
        }
    }

    /// Record finished scenes (by key).
    fn record(&mut self, outcomes: &[SceneOutcome]) {
        for o in outcomes {
            self.finished.insert(o.point.key.clone(), o.result.clone());
        }
    }
}

/// The values checked above an answer: `verify` values between it and the bracket's top,
/// closer together near the answer (at fractions (k/(n+1))² of the way: a failure again is
/// likeliest just above a threshold), and the top (already probed, so free).
fn verify_values(design: &Design, answer: f64) -> Vec<f64> {
    let top = design.bracket.1;
    let n = design.verify;
    let mut values: Vec<f64> = (1..=n)
        .map(|k| answer + (top - answer) * (k as f64 / (n + 1) as f64).powi(2))
        .collect();
    values.push(top);
    values
}

/// A probe's evaluation, once all its scenes have finished. A failed scene fails the target
/// (no verdict is no proof).
fn evaluate(target: DesignTarget, scenes: &[ScenePoint], done: &Finished) -> Option<Evaluation> {
    let quantity = target.quantity()?;
    let mut worst: Option<(usize, SceneVerdict)> = None;
    let mut pass = true;
    for (i, sc) in scenes.iter().enumerate() {
        let verdict = match done.get(&sc.key)? {
            Err(_) => SceneVerdict::Failed,
            Ok(r) if r.overturned => SceneVerdict::Overturned,
            Ok(r) => match quantity.of(r) {
                Some(v) => SceneVerdict::Response(v),
                None => SceneVerdict::Failed,
            },
        };
        pass &= match (verdict, target) {
            (SceneVerdict::Response(v), DesignTarget::Limit { max, .. }) => v <= max,
            (SceneVerdict::Response(_), DesignTarget::NoOverturning) => true,
            _ => false,
        };
        let worse = worst.is_none_or(|(_, w)| {
            verdict.rank().0 > w.rank().0
                || (verdict.rank().0 == w.rank().0 && verdict.rank().1 > w.rank().1)
        });
        if worse {
            worst = Some((i, verdict));
        }
    }
    let (worst, verdict) = worst?;
    Some(Evaluation {
        pass,
        worst,
        verdict,
        fit: None,
    })
}

/// A fragility probe's evaluation (`fit.rs`): the fitted curve's verdict, or the first scene
/// that failed.
fn evaluate_fit(fit: &FragilityFit, scenes: &[ScenePoint], done: &Finished) -> Option<Evaluation> {
    Some(match fit.evaluate(scenes, done)? {
        Ok(s) => Evaluation {
            pass: s.pass,
            worst: 0,
            verdict: SceneVerdict::Failed,
            fit: Some(s),
        },
        Err(worst) => Evaluation {
            pass: false,
            worst,
            verdict: SceneVerdict::Failed,
            fit: None,
        },
    })
}

/// The design answer recomputed from finished scenes (a results file or journal): the
/// search replayed on them. Rows are Incomplete where a scene it needs is missing.
pub fn replay(study: &Study, outcomes: &[SceneOutcome]) -> Result<Vec<DesignRow>, StudyError> {
    Ok(progress(study, &rounds::by_key(outcomes))?.rows)
}

/// How far a design search got on finished scenes (by key: a journal's or a results file's).
pub struct DesignProgress {
    /// The answer per design point (Incomplete where the search has not finished).
    pub rows: Vec<DesignRow>,
    /// Every probe scene the replayed search asked for that has finished.
    pub outcomes: Vec<SceneOutcome>,
    pub complete: bool,
    /// At most this many further scenes finish the search (each unfinished point's probes
    /// left at most, times its scenes per probe; shared scenes make it fewer).
    pub remaining_at_most: usize,
}

impl DesignProgress {
    /// `rocklab status`'s line: design points answered, probes, what is left at most.
    pub fn describe(&self) -> String {
        let answered = (self.rows.iter())
            .filter(|r| r.status != DesignStatus::Incomplete)
            .count();
        let probes: usize = self.rows.iter().map(|r| r.probes).sum();
        let mut text = format!(
            "design search: {answered} of {} design points answered, {probes} probes",
            self.rows.len()
        );
        if !self.complete {
            text.push_str(&format!(
                "; at most {} more scenes (a bisection ends when its bracket is within the \
                 resolution: how many probes that takes is known only then)",
                self.remaining_at_most
            ));
        }
        text
    }
}

/// The search replayed on `finished`: its rows, the scenes it used and what is left.
pub fn progress(study: &Study, finished: &Finished) -> Result<DesignProgress, StudyError> {
    let mut search = Search::new(study)?;
    let run = rounds::replay(&mut search, finished);
    Ok(DesignProgress {
        rows: search.rows(),
        outcomes: search.outcomes(),
        complete: run.complete && search.complete(),
        remaining_at_most: search.remaining_at_most(),
    })
}

/// A design study's sweep: the search's rounds through the journal
/// ([`rounds::run_journalled`]). The results hold every probe scene. Sharding is refused: a
/// round needs every verdict of the one before it.
pub fn run_design(
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
        "a design study",
        "each probe of its search needs the verdict of the one before; run it unsharded",
    )?;
    let mut search = Search::new(study).map_err(|e| crate::error::error!("{e}"))?;
    let run = rounds::run_journalled(&mut search, opts, library, checkpoint, cancel, progress);
    Ok(SweepResults {
        study_hash: study.hash(),
        study: Some(study.clone()),
        // The search's own list: a scene key shared by probes of several points (one run)
        // appears under each of them.
        outcomes: search.outcomes(),
        cancelled: !run.complete || !search.complete(),
        shard: None,
        build: build_id().to_string(),
        inferred: Vec::new(),
    })
}

#[cfg(test)]
mod tests;
