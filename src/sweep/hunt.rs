//! The hunt and fill of an incremental dynamic analysis for one record and structure
//! variant, as a pure state machine: no scenes, only intensities in and responses out. The
//! IDA search (`sweep/ida.rs`) asks each record's [`Hunt`] for its next intensity, runs that
//! scene and records its response, round after round.
//!
//! Hunt: climb the study's IM ladder (its `scale` values, lowest first) until the highest
//! damage state is reached or the ladder ends (then every state not reached is censored at
//! the top). Fill: for each damage state, lowest first, bisect between the highest intensity
//! that held below the state's first exceedance and that first exceedance, until the bracket
//! is no wider than the resolution (IM units). Intensity 0 holds by definition (no ground
//! motion, no response), so a state reached at the bottom of the ladder is bisected down
//! from there.
//!
//! Every decision is a function of the probes so far (no order, clock or randomness), so a
//! hunt replayed from the same responses asks for the same intensities: what makes a stopped
//! IDA resume from its journal. Rocking is not monotone in the intensity: a level that holds
//! above one that reached the state is a resurrection, and every one met on the way is
//! reported ([`StateResult::resurrections`]); the capacity is the *first* exceedance.

/// What one scene of the hunt answered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Response {
    /// The damage measure (e.g. θmax/α).
    Peak(f64),
    /// Overturned: beyond every damage state.
    Overturned,
    /// The scene failed (no verdict): the hunt stops and the record is left out of the fit.
    Failed,
}

impl Response {
    /// Whether the response reached damage state `threshold` (None: no verdict).
    fn reaches(self, threshold: f64) -> Option<bool> {
        match self {
            Response::Peak(v) => Some(v >= threshold),
            Response::Overturned => Some(true),
            Response::Failed => None,
        }
    }
}

/// One damage state's outcome of a hunt.
#[derive(Clone, Debug, PartialEq)]
pub struct StateResult {
    /// The first intensity that reached the state (the bracket's top); None: censored.
    pub capacity: Option<f64>,
    /// The highest intensity that held below the capacity (0: none probed), or for a censored
    /// state the top of the ladder.
    pub lo: f64,
    /// The capacity, or for a censored state the top of the ladder.
    pub hi: f64,
    /// Reached nowhere up to the top of the ladder.
    pub censored: bool,
    /// (held, reached_below): every probe that held above an intensity that reached the
    /// state, with the highest such intensity below it.
    pub resurrections: Vec<(f64, f64)>,
}

/// The hunt and fill for one record and variant.
#[derive(Clone, Debug)]
pub struct Hunt {
    ladder: Vec<f64>,
    states: Vec<f64>,
    resolution: f64,
    /// (intensity, response) in the order probed.
    probes: Vec<(f64, Response)>,
}

impl Hunt {
    /// `ladder`: the hunt's intensities, increasing and positive; `states`: the damage-state
    /// thresholds, increasing; `resolution`: the widest final bracket, in IM units (> 0).
    pub fn new(ladder: Vec<f64>, states: Vec<f64>, resolution: f64) -> Hunt {
        debug_assert!(ladder.windows(2).all(|w| w[0] < w[1]) && ladder[0] > 0.0);
        debug_assert!(resolution > 0.0);
        Hunt {
            ladder,
            states,
            resolution,
            probes: Vec::new(),
        }
    }

    /// The intensity to probe next; None when the hunt is done (or a scene failed).
    pub fn next(&self) -> Option<f64> {
        if self.failed() {
            return None;
        }
        let top_state = *self.states.last()?;
        if self.first_reaching(top_state).is_none() {
            let climbed = self.probes.iter().map(|p| p.0).fold(0.0, f64::max);
            if let Some(&next) = self.ladder.iter().find(|&&x| x > climbed) {
                return Some(next);
            }
        }
        self.states.iter().find_map(|&ds| {
            let hi = self.first_reaching(ds)?;
            let lo = self.held_below(hi);
            (hi - lo > self.resolution).then_some(0.5 * (lo + hi))
        })
    }

    /// Record the response at `im` (the intensity [`Hunt::next`] asked for).
    pub fn record(&mut self, im: f64, response: Response) {
        self.probes.push((im, response));
    }

    /// Whether a scene of the hunt failed.
    pub fn failed(&self) -> bool {
        self.probes.iter().any(|p| p.1 == Response::Failed)
    }

    pub fn done(&self) -> bool {
        self.next().is_none()
    }

    /// The probes so far, in the order they ran.
    pub fn probes(&self) -> &[(f64, Response)] {
        &self.probes
    }

    pub fn top(&self) -> f64 {
        *self.ladder.last().expect("a ladder")
    }

    /// The lowest probed intensity that reached the state.
    fn first_reaching(&self, ds: f64) -> Option<f64> {
        self.probes
            .iter()
            .filter(|p| p.1.reaches(ds) == Some(true))
            .map(|p| p.0)
            .min_by(f64::total_cmp)
    }

    /// The highest probed intensity below `hi` (all of them held: `hi` is the first that
    /// reached), or 0.
    fn held_below(&self, hi: f64) -> f64 {
        self.probes
            .iter()
            .map(|p| p.0)
            .filter(|&x| x < hi)
            .fold(0.0, f64::max)
    }

    /// The outcome for damage state `ds` (one of the hunt's states) as the probes stand.
    pub fn result(&self, ds: f64) -> StateResult {
        let top = self.top();
        let Some(hi) = self.first_reaching(ds) else {
            return StateResult {
                capacity: None,
                lo: top,
                hi: top,
                censored: true,
                resurrections: Vec::new(),
            };
        };
        let mut resurrections: Vec<(f64, f64)> = self
            .probes
            .iter()
            .filter(|p| p.0 > hi && p.1.reaches(ds) == Some(false))
            .map(|&(held, _)| {
                let below = self
                    .probes
                    .iter()
                    .filter(|p| p.0 < held && p.1.reaches(ds) == Some(true))
                    .map(|p| p.0)
                    .fold(hi, f64::max);
                (held, below)
            })
            .collect();
        resurrections.sort_by(|a, b| a.0.total_cmp(&b.0));
        StateResult {
            capacity: Some(hi),
            lo: self.held_below(hi),
            hi,
            censored: false,
            resurrections,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Run a hunt to its end against a response function; returns it and its probe count.
    fn run(mut hunt: Hunt, response: impl Fn(f64) -> Response) -> Hunt {
        let mut guard = 0;
        while let Some(im) = hunt.next() {
            hunt.record(im, response(im));
            guard += 1;
            assert!(guard < 200, "the hunt does not end");
        }
        hunt
    }

    /// θmax/α = IM / capacity, overturning at 1.
    fn monotone(capacity: f64) -> impl Fn(f64) -> Response {
        move |im| {
            let r = im / capacity;
            if r >= 1.0 {
                Response::Overturned
            } else {
                Response::Peak(r)
            }
        }
    }

    /// The first intensity of a ladder of step `step` from `step` that reaches `ds`.
    fn brute_force(response: &impl Fn(f64) -> Response, ds: f64, step: f64, top: f64) -> f64 {
        (1..)
            .map(|k| k as f64 * step)
            .take_while(|&x| x <= top + 1e-12)
            .find(|&x| response(x).reaches(ds) == Some(true))
            .expect("reached below the top")
    }

    const LADDER: [f64; 6] = [1.0, 1.5, 2.25, 3.375, 5.0625, 7.59375];

    #[test]
    fn monotone_capacities_are_within_the_resolution_of_a_fine_ladder() {
        let states = vec![0.2, 0.5, 1.0];
        for capacity in [1.3, 2.0, 3.7, 6.1, 7.5] {
            let response = monotone(capacity);
            let hunt = run(Hunt::new(LADDER.to_vec(), states.clone(), 0.05), &response);
            for &ds in &states {
                let r = hunt.result(ds);
                let fine = brute_force(&response, ds, 0.001, 8.0);
                let cap = r.capacity.unwrap();
                assert!(
                    (cap - fine).abs() <= 0.05,
                    "{capacity} {ds}: {cap} vs {fine}"
                );
                // The bracket holds the true capacity ds·capacity and is no wider than asked.
                assert!(r.lo < ds * capacity && ds * capacity <= r.hi, "{r:?}");
                assert!(r.hi - r.lo <= 0.05, "{r:?}");
                assert!(r.resurrections.is_empty() && !r.censored);
            }
            // Hunt levels up to the first overturning, then bisections: far fewer than the
            // 8000 levels of the fine ladder.
            assert!(hunt.probes().len() < 30, "{}", hunt.probes().len());
        }
    }

    #[test]
    fn the_hunt_stops_climbing_at_the_first_overturning() {
        let hunt = run(Hunt::new(LADDER.to_vec(), vec![1.0], 0.1), monotone(2.0));
        let ladder: Vec<f64> = hunt.probes().iter().map(|p| p.0).take(3).collect();
        assert_eq!(ladder, [1.0, 1.5, 2.25]);
        assert!(hunt.probes().iter().all(|p| p.0 <= 2.25));
        // Bisection between 1.5 and 2.25 down to 0.1: 2.25−1.5 = 0.75 → 0.375 → 0.1875 →
        // 0.09375, three midpoints.
        assert_eq!(hunt.probes().len(), 6);
        let r = hunt.result(1.0);
        assert_eq!((r.lo, r.hi, r.capacity), (1.96875, 2.0625, Some(2.0625)));
    }

    #[test]
    fn a_state_reached_at_the_first_level_is_bisected_down_from_zero() {
        let hunt = run(
            Hunt::new(LADDER.to_vec(), vec![0.5, 1.0], 0.05),
            monotone(0.6),
        );
        let r = hunt.result(0.5);
        assert!(r.lo < 0.3 && 0.3 <= r.hi && r.hi - r.lo <= 0.05, "{r:?}");
        let r = hunt.result(1.0);
        assert!(r.lo < 0.6 && 0.6 <= r.hi && r.hi - r.lo <= 0.05, "{r:?}");
    }

    #[test]
    fn records_that_never_reach_a_state_are_censored_at_the_top() {
        let hunt = run(
            Hunt::new(LADDER.to_vec(), vec![0.5, 1.0], 0.05),
            monotone(12.0),
        );
        // Climbed the whole ladder: 0.5 reached at 6 (bisected), 1 never.
        assert!(hunt.probes().iter().any(|p| p.0 == 7.59375));
        let r = hunt.result(1.0);
        assert_eq!(
            (r.capacity, r.censored, r.lo, r.hi),
            (None, true, 7.59375, 7.59375)
        );
        let r = hunt.result(0.5);
        assert!(
            !r.censored && (r.capacity.unwrap() - 6.0).abs() <= 0.05,
            "{r:?}"
        );
    }

    #[test]
    fn resurrections_met_on_the_way_are_reported_and_the_first_exceedance_is_the_capacity() {
        // Reaches 0.5 on [1.4, 2.5), falls back below it up to 6.25, overturns from 7.
        let response = |im: f64| {
            if im >= 7.0 {
                Response::Overturned
            } else if (1.4..2.5).contains(&im) {
                Response::Peak(0.6)
            } else {
                Response::Peak(0.08 * im)
            }
        };
        let hunt = run(Hunt::new(LADDER.to_vec(), vec![0.5, 1.0], 0.05), response);
        let r = hunt.result(0.5);
        // First reached at 1.5 on the ladder, bisected towards 1.4 from 1.0.
        assert!(r.lo < 1.4 && 1.4 <= r.hi && r.hi - r.lo <= 0.05, "{r:?}");
        // 3.375 and 5.0625 held above 2.25, which reached it.
        let held: Vec<f64> = r.resurrections.iter().map(|p| p.0).collect();
        assert_eq!(held, [3.375, 5.0625], "{r:?}");
        assert!(r.resurrections.iter().all(|p| p.1 == 2.25), "{r:?}");
        let r = hunt.result(1.0);
        assert!(
            r.lo < 7.0 && 7.0 <= r.hi && r.resurrections.is_empty(),
            "{r:?}"
        );
    }

    #[test]
    fn a_failed_scene_ends_the_hunt() {
        let hunt = run(Hunt::new(LADDER.to_vec(), vec![1.0], 0.05), |im| {
            if im > 2.0 {
                Response::Failed
            } else {
                Response::Peak(0.1)
            }
        });
        assert!(hunt.failed() && hunt.done());
        assert_eq!(hunt.probes().len(), 3);
    }

    #[test]
    fn replaying_the_same_responses_asks_for_the_same_intensities() {
        let a = run(
            Hunt::new(LADDER.to_vec(), vec![0.2, 1.0], 0.02),
            monotone(3.3),
        );
        let mut b = Hunt::new(LADDER.to_vec(), vec![0.2, 1.0], 0.02);
        for &(im, r) in a.probes() {
            assert_eq!(b.next(), Some(im));
            b.record(im, r);
        }
        assert!(b.done());
    }
}
