//! Run-time estimates from measured scene costs (issue 42 item 5). A scene's cost depends on
//! what it is (a mechanistic clutch costs more than a bare block; an overturning scene stops
//! early), and a sweep meets its scenes in expansion order, so a plain "elapsed / done ×
//! left" is fooled by cheap scenes first. Instead:
//!
//! - the scenes are split into strata: each device variant's run of scenes, cut into blocks
//!   along the expansion order (so the axes that drive cost are covered);
//! - before a run, a few scenes of every stratum are timed ([`sample_costs`]): a
//!   [`CostModel`] gives each stratum's seconds per scene on one thread, and the estimate is
//!   the study's predicted work over the worker threads;
//! - during a run, [`RunEstimate`] counts the finished scenes' predicted work (reused scenes
//!   cost nothing and count nowhere), measures the pace in predicted work per wall second over
//!   a recent window, divides the work left by it, and smooths the result so that one refresh
//!   never moves it by more than a bounded factor.

use super::{ScenePoint, run_guarded};
use crate::excitation::library::Library;
use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Blocks each device variant's scenes are cut into along the expansion order.
pub const BLOCKS_PER_VARIANT: usize = 8;
/// Samples' worth of weight a stratum's (and a variant's) prior keeps against its own
/// samples.
const SHRINK: f64 = 4.0;
/// Scenes timed per stratum before a run (the workbench's and the bench's sample).
pub const SAMPLES_PER_STRATUM: usize = 4;

/// The strata of a study's scenes: `ranges` are the device variants' (first, count) in the
/// expansion; each is cut into up to [`BLOCKS_PER_VARIANT`] blocks.
#[derive(Clone, Debug, PartialEq)]
pub struct Strata {
    /// (first index, count, variant) of each stratum, in expansion order.
    blocks: Vec<(usize, usize, usize)>,
}

impl Strata {
    /// Strata over `ranges` of (first, count), one per variant; a single range if none.
    pub fn new(ranges: &[(usize, usize)], total: usize) -> Strata {
        let whole = [(0, total)];
        let ranges = if ranges.iter().map(|r| r.1).sum::<usize>() == total && !ranges.is_empty() {
            ranges
        } else {
            &whole
        };
        let mut blocks = Vec::new();
        for (variant, &(first, count)) in ranges.iter().enumerate() {
            let n = BLOCKS_PER_VARIANT.min(count.max(1));
            for b in 0..n {
                let start = first + count * b / n;
                let end = first + count * (b + 1) / n;
                if end > start {
                    blocks.push((start, end - start, variant));
                }
            }
        }
        Strata { blocks }
    }

    pub fn len(&self) -> usize {
        self.blocks.len()
    }

    pub fn is_empty(&self) -> bool {
        self.blocks.is_empty()
    }

    /// The stratum of scene `index` (expansion order), if inside the strata.
    pub fn of(&self, index: usize) -> Option<usize> {
        let i = self.blocks.partition_point(|b| b.0 + b.1 <= index);
        self.blocks.get(i).filter(|b| b.0 <= index).map(|_| i)
    }

    /// Scenes in each stratum.
    pub fn counts(&self) -> Vec<usize> {
        self.blocks.iter().map(|b| b.1).collect()
    }

    /// `per` scene indices of each stratum, spread evenly inside it.
    pub fn sample_indices(&self, per: usize) -> Vec<usize> {
        let mut out = Vec::new();
        for &(first, count, _) in &self.blocks {
            let k = per.min(count);
            out.extend((0..k).map(|j| first + (2 * j + 1) * count / (2 * k)));
        }
        out
    }
}

/// The strata of `scenes` scenes of `study`: its device variants as its layout places them
/// (one stratum run if the layout does not describe the scenes, as for a search).
pub fn study_strata(study: &crate::study::Study, scenes: usize) -> Strata {
    let ranges: Vec<(usize, usize)> = study
        .layout()
        .map(|l| l.variants.iter().map(|v| (v.first, v.count)).collect())
        .unwrap_or_default();
    Strata::new(&ranges, scenes)
}

/// Seconds per scene on one thread, per stratum, from timed samples; a stratum without a
/// sample takes its variant's mean, else the mean of all samples.
#[derive(Clone, Debug, PartialEq)]
pub struct CostModel {
    per_stratum: Vec<f64>,
}

impl CostModel {
    /// From (stratum, seconds) samples; None without any.
    pub fn from_samples(strata: &Strata, samples: &[(usize, f64)]) -> Option<CostModel> {
        let mean = |pick: &dyn Fn(usize) -> bool| {
            let picked: Vec<f64> = samples
                .iter()
                .filter(|(s, _)| pick(*s))
                .map(|(_, t)| t.max(0.0))
                .collect();
            (!picked.is_empty()).then(|| picked.iter().sum::<f64>() / picked.len() as f64)
        };
        let overall = mean(&|_| true)?;
        let variant = |s: usize| strata.blocks.get(s).map(|b| b.2);
        // A stratum's few samples are shrunk toward its variant's mean (and that toward the
        // overall mean): costs vary tenfold inside a block (overturning scenes stop early),
        // and one unlucky sample must not price thousands of scenes.
        let count = |pick: &dyn Fn(usize) -> bool| samples.iter().filter(|(s, _)| pick(*s)).count();
        let shrunk = |n: usize, m: Option<f64>, prior: f64| {
            let n = n as f64;
            m.map_or(prior, |m| (n * m + SHRINK * prior) / (n + SHRINK))
        };
        let per_stratum = (0..strata.len())
            .map(|s| {
                let in_variant = |t: usize| variant(t) == variant(s);
                let v = shrunk(count(&in_variant), mean(&in_variant), overall);
                shrunk(count(&|t| t == s), mean(&|t| t == s), v)
            })
            .collect();
        Some(CostModel { per_stratum })
    }

    /// The same cost for every stratum (nothing measured yet: scenes are counted).
    pub fn uniform(strata: &Strata) -> CostModel {
        CostModel {
            per_stratum: vec![1.0; strata.len()],
        }
    }

    pub fn cost(&self, stratum: usize) -> f64 {
        self.per_stratum.get(stratum).copied().unwrap_or(0.0)
    }

    /// Seconds on one thread of `counts[s]` scenes of each stratum.
    pub fn work(&self, counts: &[usize]) -> f64 {
        counts
            .iter()
            .enumerate()
            .map(|(s, &n)| n as f64 * self.cost(s))
            .sum()
    }
}

/// Wall seconds of the whole study before a run: its predicted work over `threads`.
pub fn seconds_before_run(model: &CostModel, strata: &Strata, threads: usize) -> f64 {
    let scenes: usize = strata.counts().iter().sum();
    model.work(&strata.counts()) / threads.clamp(1, scenes.max(1)) as f64
}

/// Time up to `per` scenes of every stratum of `points` on this thread, computing `measures`
/// as the run will (stopping at `budget` or `cancel`); None if nothing could be timed.
pub fn sample_costs(
    points: &[ScenePoint],
    measures: crate::sim::Measures,
    strata: &Strata,
    per: usize,
    budget: Duration,
    library: &Library,
    cancel: &AtomicBool,
) -> Option<CostModel> {
    let bounds = crate::sim::Bounds {
        cancel: Some(cancel),
        time_limit: Some(super::SCENE_TIME_LIMIT),
        measures,
        time_stages: false,
        history_rows: None,
    };
    // Round-robin over the strata, so a budget cut short still covers them all.
    let picks = strata.sample_indices(per);
    let mut order: Vec<usize> = Vec::with_capacity(picks.len());
    for round in 0..per {
        let mut at = 0;
        for &(_, count, _) in &strata.blocks {
            let k = per.min(count);
            if round < k {
                order.push(picks[at + round]);
            }
            at += k;
        }
    }
    let started = Instant::now();
    let mut samples = Vec::new();
    for index in order {
        if cancel.load(Ordering::Relaxed) || started.elapsed() > budget {
            break;
        }
        let (Some(point), Some(stratum)) = (points.get(index), strata.of(index)) else {
            continue;
        };
        let t = Instant::now();
        // A failed scene cost its time all the same.
        let _ = run_guarded(point, library, bounds)?;
        samples.push((stratum, t.elapsed().as_secs_f64()));
    }
    CostModel::from_samples(strata, &samples)
}

/// The estimate of a running sweep's time left.
pub struct RunEstimate {
    strata: Strata,
    model: CostModel,
    threads: usize,
    /// Predicted work (one-thread seconds) of the scenes not finished.
    work_left: f64,
    /// Predicted work of the scenes computed so far (reused ones excluded).
    work_done: f64,
    /// (elapsed seconds, work done) at recent refreshes, for the windowed pace.
    history: VecDeque<(f64, f64)>,
    /// The last estimate given, and when.
    shown: Option<(f64, f64)>,
    /// (elapsed, work done) when the first computed scene was seen.
    since: Option<(f64, f64)>,
    /// Predicted work per wall second before the run measured its own: the threads, for a
    /// model from timed scenes; None for the uniform model (a count says nothing of time).
    prior_pace: Option<f64>,
}

/// The pace is measured over the last this many seconds (or the whole run if shorter)…
const WINDOW_SECONDS: f64 = 30.0;
/// …and one refresh moves the estimate by at most this factor (up or down) beyond the
/// passing of time…
const MAX_STEP: f64 = 1.5;
/// The run's measured pace replaces the model's prior over this many seconds of scenes…
const TRUST_SECONDS: f64 = 5.0;
/// …and refreshes come at most this often (between them the estimate counts down).
const REFRESH_SECONDS: f64 = 0.5;

impl RunEstimate {
    /// A sweep of every scene of `strata` on `threads` workers, priced by `model` (None:
    /// every scene alike, the pace alone decides).
    pub fn new(strata: Strata, model: Option<CostModel>, threads: usize) -> RunEstimate {
        let prior_pace = model.is_some().then_some(threads.max(1) as f64);
        let model = model.unwrap_or_else(|| CostModel::uniform(&strata));
        let work_left = model.work(&strata.counts());
        RunEstimate {
            strata,
            model,
            threads: threads.max(1),
            work_left,
            work_done: 0.0,
            history: VecDeque::new(),
            shown: None,
            since: None,
            prior_pace,
        }
    }

    /// Scene `index` finished; `reused` if taken from the journal (it cost nothing now).
    pub fn scene_done(&mut self, index: usize, reused: bool) {
        let Some(stratum) = self.strata.of(index) else {
            return;
        };
        let cost = self.model.cost(stratum);
        self.work_left = (self.work_left - cost).max(0.0);
        if !reused {
            self.work_done += cost;
        }
    }

    /// Seconds left at `elapsed` seconds into the run; None while nothing says (no sampled
    /// model and no scene computed yet).
    pub fn seconds_left(&mut self, elapsed: f64) -> Option<f64> {
        if self.work_left <= 0.0 {
            return Some(0.0);
        }
        if let Some((at, last)) = self.shown
            && elapsed - at < REFRESH_SECONDS
        {
            return Some((last - (elapsed - at)).max(0.0));
        }
        // The pace is measured from the first computed scene on: the start of a run (opening
        // the journal, expanding the study) says nothing about the scenes' pace.
        if self.work_done > 0.0 && self.since.is_none() {
            self.since = Some((elapsed, self.work_done));
        }
        self.history.push_back((elapsed, self.work_done));
        let window = WINDOW_SECONDS.max(elapsed * 0.25);
        while self
            .history
            .front()
            .is_some_and(|&(t, _)| t < elapsed - window)
            && self.history.len() > 2
        {
            self.history.pop_front();
        }
        let measured = self.since.and_then(|(t0, w0)| {
            let span = elapsed - t0;
            if span < 1.0 || self.work_done <= w0 {
                return None;
            }
            let mean = (self.work_done - w0) / span;
            // The window follows a change of pace; the mean keeps a burst of scenes
            // finishing together from swinging it.
            let &(t1, w1) = self.history.front()?;
            let windowed = (elapsed - t1 > 1.0 && self.work_done > w1)
                .then(|| (self.work_done - w1) / (elapsed - t1));
            Some((windowed.map_or(mean, |w| 0.5 * (w + mean)), span))
        });
        // A sampled model prices scenes in one-thread seconds: every worker busy is its pace
        // until the run has measured its own (trusted fully after TRUST_SECONDS).
        let pace = match (measured, self.prior_pace) {
            (Some((m, span)), Some(p)) => {
                let trust = (span / TRUST_SECONDS).min(1.0);
                p.powf(1.0 - trust) * m.powf(trust)
            }
            (Some((m, _)), None) => m,
            (None, Some(p)) => p,
            (None, None) => return None,
        };
        let raw = self.work_left / pace;
        let estimate = match self.shown {
            Some((at, last)) => {
                let expected = (last - (elapsed - at)).max(0.0);
                let floor = expected / MAX_STEP;
                let ceiling = expected.max(1.0) * MAX_STEP;
                raw.clamp(floor, ceiling)
            }
            None => raw,
        };
        self.shown = Some((elapsed, estimate));
        Some(estimate)
    }

    /// The threads the sweep runs on (for a first estimate from the model alone).
    pub fn threads(&self) -> usize {
        self.threads
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sweep simulated on `threads` workers: scenes in expansion order, each taken by the
    /// first free worker; returns the finish time of each scene, in finishing order.
    fn simulate(costs: &[f64], threads: usize, skip: &[bool]) -> Vec<(f64, usize, bool)> {
        let mut free = vec![0.0f64; threads];
        let mut done = Vec::new();
        for (i, &c) in costs.iter().enumerate() {
            if skip[i] {
                done.push((0.0, i, true));
                continue;
            }
            let w = (0..threads)
                .min_by(|&a, &b| free[a].total_cmp(&free[b]))
                .unwrap();
            free[w] += c;
            done.push((free[w], i, false));
        }
        done.sort_by(|a, b| a.0.total_cmp(&b.0));
        done
    }

    /// The estimates at each `step` of the run against the truth: (elapsed, estimate, truth).
    fn replay(
        costs: &[f64],
        ranges: &[(usize, usize)],
        threads: usize,
        skip: &[bool],
        model: Option<CostModel>,
    ) -> Vec<(f64, f64, f64)> {
        let strata = Strata::new(ranges, costs.len());
        let events = simulate(costs, threads, skip);
        let end = events.last().unwrap().0;
        let mut est = RunEstimate::new(strata, model, threads);
        let mut out = Vec::new();
        let mut next = 0;
        let steps = 200;
        for k in 1..steps {
            let t = end * k as f64 / steps as f64;
            while next < events.len() && events[next].0 <= t {
                est.scene_done(events[next].1, events[next].2);
                next += 1;
            }
            if let Some(left) = est.seconds_left(t) {
                out.push((t, t + left, end));
            }
        }
        out
    }

    fn model_of(costs: &[f64], ranges: &[(usize, usize)]) -> CostModel {
        let strata = Strata::new(ranges, costs.len());
        let samples: Vec<(usize, f64)> = strata
            .sample_indices(2)
            .into_iter()
            .map(|i| (strata.of(i).unwrap(), costs[i]))
            .collect();
        CostModel::from_samples(&strata, &samples).unwrap()
    }

    /// Every estimate after `from` of the run is within 2× of the truth, and no refresh
    /// moves the predicted total by more than MAX_STEP.
    fn check(trace: &[(f64, f64, f64)], from: f64) {
        assert!(!trace.is_empty());
        for &(t, total, truth) in trace.iter().filter(|e| e.0 >= from * e.2) {
            let ratio = total / truth;
            assert!(
                (0.5..=2.0).contains(&ratio),
                "at {t:.1} s the estimate {total:.1} s is {ratio:.2}× the real {truth:.1} s"
            );
        }
        for pair in trace.windows(2) {
            let (a, b) = (pair[0].1 - pair[0].0, pair[1].1 - pair[1].0);
            if a > 1.0 && b > 1.0 {
                assert!(b / a < 10.0 && a / b < 10.0, "jump {a:.1} → {b:.1}");
            }
        }
    }

    #[test]
    fn strata_cover_each_variant_in_blocks_and_locate_every_scene() {
        let strata = Strata::new(&[(0, 20), (20, 5)], 25);
        assert_eq!(strata.len(), BLOCKS_PER_VARIANT + 5);
        assert_eq!(strata.counts().iter().sum::<usize>(), 25);
        assert_eq!(strata.of(0), Some(0));
        assert_eq!(strata.of(19), Some(BLOCKS_PER_VARIANT - 1));
        assert_eq!(strata.of(20), Some(BLOCKS_PER_VARIANT));
        assert_eq!(strata.of(25), None);
        let picks = strata.sample_indices(1);
        assert_eq!(picks.len(), strata.len());
        assert!(picks.iter().all(|&i| i < 25));
        // Ranges that do not add up fall back to one variant.
        assert_eq!(
            Strata::new(&[(0, 3)], 10).counts().iter().sum::<usize>(),
            10
        );
    }

    #[test]
    fn a_constant_cost_is_estimated_within_two_fold_from_the_first_tenth() {
        let costs = vec![0.01; 5000];
        let ranges = [(0, 5000)];
        let model = model_of(&costs, &ranges);
        let strata = Strata::new(&ranges, costs.len());
        let before = seconds_before_run(&model, &strata, 2);
        assert!((before / 25.0 - 1.0).abs() < 0.01, "before: {before}");
        check(
            &replay(&costs, &ranges, 2, &[false; 5000], Some(model)),
            0.1,
        );
    }

    #[test]
    fn cheap_scenes_first_do_not_mislead_the_estimate() {
        // A bare variant at 1 ms a scene, then a mechanistic one at 20 ms (20× dearer).
        let mut costs = vec![0.001; 3000];
        costs.extend(vec![0.02; 3000]);
        let ranges = [(0, 3000), (3000, 3000)];
        let model = model_of(&costs, &ranges);
        let trace = replay(&costs, &ranges, 2, &[false; 6000], Some(model));
        check(&trace, 0.1);
        // The plain count-based pace would say about a tenth of the truth early on.
        let naive = replay(&costs, &ranges, 2, &[false; 6000], None);
        let early = naive.iter().find(|e| e.0 >= 0.05 * e.2).unwrap();
        assert!(early.1 / early.2 < 0.5, "naive {early:?}");
    }

    #[test]
    fn a_resumed_run_does_not_count_its_journalled_scenes_as_pace() {
        let costs = vec![0.01; 4000];
        let skip: Vec<bool> = (0..4000).map(|i| i < 3000).collect();
        let ranges = [(0, 4000)];
        let model = model_of(&costs, &ranges);
        check(&replay(&costs, &ranges, 2, &skip, Some(model)), 0.1);
    }

    #[test]
    fn a_cost_growing_along_the_axis_is_followed_by_the_blocks() {
        // Cost growing tenfold along the expansion order within one variant.
        let costs: Vec<f64> = (0..5000)
            .map(|i| 0.002 + 0.02 * i as f64 / 5000.0)
            .collect();
        let ranges = [(0, 5000)];
        let model = model_of(&costs, &ranges);
        check(
            &replay(&costs, &ranges, 2, &[false; 5000], Some(model)),
            0.1,
        );
    }

    #[test]
    fn costs_scattered_inside_blocks_are_priced_from_few_samples() {
        // Two variants whose scenes alternate in runs between 0.5 ms (overturned early) and
        // 8 ms along the axes, the second variant dearer; sampled like the workbench.
        let costs: Vec<f64> = (0..8000)
            .map(|i| {
                let base = if (i / 37) % 3 == 0 { 0.008 } else { 0.0005 };
                if i < 4000 { base } else { 2.0 * base }
            })
            .collect();
        let ranges = [(0, 4000), (4000, 4000)];
        let strata = Strata::new(&ranges, costs.len());
        let samples: Vec<(usize, f64)> = strata
            .sample_indices(SAMPLES_PER_STRATUM)
            .into_iter()
            .map(|i| (strata.of(i).unwrap(), costs[i]))
            .collect();
        let model = CostModel::from_samples(&strata, &samples).unwrap();
        let before = seconds_before_run(&model, &strata, 2);
        let truth = costs.iter().sum::<f64>() / 2.0;
        assert!(
            (0.5..=2.0).contains(&(before / truth)),
            "{before} vs {truth}"
        );
        check(
            &replay(&costs, &ranges, 2, &[false; 8000], Some(model)),
            0.1,
        );
    }

    #[test]
    fn a_wrong_model_is_corrected_by_the_pace_and_the_steps_stay_bounded() {
        // The sample said 1 ms a scene; they cost 10 ms. Until the run has measured a few
        // seconds of its own pace the model's prior weighs in (and each refresh moves by a
        // bounded step), so the estimate is right from mid-run on.
        let costs = vec![0.01; 3000];
        let ranges = [(0, 3000)];
        let strata = Strata::new(&ranges, 3000);
        let wrong = CostModel::from_samples(&strata, &[(0, 0.001)]).unwrap();
        check(
            &replay(&costs, &ranges, 2, &[false; 3000], Some(wrong)),
            0.5,
        );
        let before = seconds_before_run(&CostModel::uniform(&strata), &strata, 4);
        assert_eq!(before, 750.0);
        assert!(CostModel::from_samples(&strata, &[]).is_none());
    }
}
