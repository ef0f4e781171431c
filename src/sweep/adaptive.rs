//! Adaptive overturning maps: the map's grid computed by boundary refinement instead of cell by
//! cell. A coarse lattice (every 2^levels-th value of both map axes, the last value always
//! included) runs first; then every leaf cell of the lattice whose known points disagree
//! (overturned vs survived, or a failed scene among them) is split at its midpoints and the new
//! corners run, round after round, down to neighbouring grid values. A leaf whose known points
//! all agree fills its unrun grid points with that verdict ([`InferredCell`]).
//!
//! No monotonicity is assumed: a survival island or an overturning tongue is found wherever it
//! covers a point that runs (a coarse lattice point, or a point of a split cell). What can be
//! missed is a feature that fits between the known points of an agreeing leaf: narrower than a
//! coarse cell (2^levels grid steps) and touching none of its corners. Refinement checks every
//! known point on a leaf's closed boundary, so a leaf whose neighbour found a disagreeing
//! point on their shared edge splits too.
//!
//! The rounds are plain sweeps over points of the full expansion (same indices, same keys),
//! run by the round driver (`rounds.rs`), so the journal, resume and the scene time limit
//! work as for a full map: a resumed run replays the rounds from the journalled scenes (the
//! refinement is a pure function of the verdicts) and runs only what is missing.

use super::rounds::{self, Rounds};
use super::{
    Checkpoint, InferredCell, Progress, SceneOutcome, SweepOptions, SweepResults, build_id,
};
use crate::excitation::Library;
use crate::study::{Axis, ScenePoint, Study, StudyError};
use std::collections::HashMap;
use std::sync::atomic::AtomicBool;

/// What a run point says about its cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CellVerdict {
    Overturned,
    Survived,
    /// The scene failed: no verdict, its neighbourhood is refined.
    Failed,
}

impl CellVerdict {
    pub fn of(outcome: &SceneOutcome) -> CellVerdict {
        match &outcome.result {
            Ok(r) if r.overturned => CellVerdict::Overturned,
            Ok(_) => CellVerdict::Survived,
            Err(_) => CellVerdict::Failed,
        }
    }
}

/// One map's grid: the expansion index of every (ix, iy) node, axes sorted ascending.
#[derive(Clone, Debug, PartialEq)]
pub struct MapGrid {
    pub nx: usize,
    pub ny: usize,
    /// `nodes[iy * nx + ix]`: expansion index.
    pub nodes: Vec<usize>,
}

/// The grids of a study's maps: one per group (device variant and every parameter off the
/// map's axes), in expansion order. Empty if the study has no map.
// StudyError is large by design (file, position, field, hint; built once): see study/mod.rs.
#[allow(clippy::result_large_err)]
pub fn map_grids(study: &Study) -> Result<Vec<MapGrid>, StudyError> {
    let Some(axes) = study.map else {
        return Ok(vec![]);
    };
    let layout = study.layout()?;
    let mut grids = Vec::new();
    for variant in &layout.variants {
        let position = |axis: Axis| variant.params.iter().position(|p| p.axis == Some(axis));
        let (Some(px), Some(py)) = (position(axes.x), position(axes.y)) else {
            continue;
        };
        // Rank of each value position along its axis (the map's axes are sorted ascending).
        let ranks = |p: usize| -> Vec<usize> {
            let values = &variant.params[p].values;
            let mut order: Vec<usize> = (0..values.len()).collect();
            order.sort_by(|a, b| values[*a].total_cmp(&values[*b]));
            let mut rank = vec![0; values.len()];
            for (r, i) in order.into_iter().enumerate() {
                rank[i] = r;
            }
            rank
        };
        let (rx, ry) = (ranks(px), ranks(py));
        let (nx, ny) = (rx.len(), ry.len());
        let mut by_group: HashMap<Vec<usize>, usize> = HashMap::new();
        let first_grid = grids.len();
        for index in variant.first..variant.first + variant.count {
            let Some((_, mut at)) = layout.locate(index) else {
                continue;
            };
            let (ix, iy) = (rx[at[px]], ry[at[py]]);
            at[px] = usize::MAX;
            at[py] = usize::MAX;
            let g = *by_group.entry(at).or_insert_with(|| {
                grids.push(MapGrid {
                    nx,
                    ny,
                    nodes: vec![usize::MAX; nx * ny],
                });
                grids.len() - 1
            });
            grids[g].nodes[iy * nx + ix] = index;
        }
        debug_assert!(
            grids[first_grid..]
                .iter()
                .all(|g| !g.nodes.contains(&usize::MAX))
        );
    }
    Ok(grids)
}

/// A leaf cell of the refinement: grid positions [x0, x1] × [y0, y1], corners included.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Cell {
    x0: usize,
    x1: usize,
    y0: usize,
    y1: usize,
}

impl Cell {
    fn corners(&self) -> [(usize, usize); 4] {
        [
            (self.x0, self.y0),
            (self.x1, self.y0),
            (self.x0, self.y1),
            (self.x1, self.y1),
        ]
    }

    fn nodes(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        (self.y0..=self.y1).flat_map(move |y| (self.x0..=self.x1).map(move |x| (x, y)))
    }

    fn splittable(&self) -> bool {
        self.x1 - self.x0 > 1 || self.y1 - self.y0 > 1
    }

    /// The four (or two) halves at the midpoints of the sides longer than one step.
    fn split(&self) -> Vec<Cell> {
        let cuts = |a: usize, b: usize| {
            if b - a > 1 {
                vec![(a, (a + b) / 2), ((a + b) / 2, b)]
            } else {
                vec![(a, b)]
            }
        };
        let mut out = Vec::new();
        for (y0, y1) in cuts(self.y0, self.y1) {
            for (x0, x1) in cuts(self.x0, self.x1) {
                out.push(Cell { x0, x1, y0, y1 });
            }
        }
        out
    }
}

/// Lattice positions 0, step, 2·step, …, and the last position.
fn lattice(n: usize, step: usize) -> Vec<usize> {
    let mut at: Vec<usize> = (0..n).step_by(step).collect();
    if at.last() != Some(&(n - 1)) {
        at.push(n - 1);
    }
    at
}

struct GridState {
    grid: MapGrid,
    known: Vec<Option<CellVerdict>>,
    leaves: Vec<Cell>,
}

impl GridState {
    fn at(&self, (x, y): (usize, usize)) -> Option<CellVerdict> {
        self.known[y * self.grid.nx + x]
    }

    /// The verdict every known point of the leaf agrees on, if its corners are known, none
    /// failed and all agree.
    fn agreed(&self, cell: &Cell) -> Option<CellVerdict> {
        let first = self.at((cell.x0, cell.y0))?;
        if first == CellVerdict::Failed || cell.corners().iter().any(|c| self.at(*c).is_none()) {
            return None;
        }
        cell.nodes()
            .all(|n| self.at(n).is_none_or(|v| v == first))
            .then_some(first)
    }
}

/// The state of an adaptive map computation over all of a study's maps.
pub struct Refinement {
    grids: Vec<GridState>,
    /// Expansion index → (grid, node).
    where_is: HashMap<usize, (usize, usize)>,
}

impl Refinement {
    /// Coarse leaves every `2^levels` grid steps on each of `grids`.
    pub fn new(grids: Vec<MapGrid>, levels: u32) -> Refinement {
        let step = 1usize << levels.min(16);
        let mut where_is = HashMap::new();
        let grids = grids
            .into_iter()
            .enumerate()
            .map(|(g, grid)| {
                for (node, index) in grid.nodes.iter().enumerate() {
                    where_is.insert(*index, (g, node));
                }
                let (xs, ys) = (lattice(grid.nx, step), lattice(grid.ny, step));
                let pairs = |v: &[usize]| -> Vec<(usize, usize)> {
                    if v.len() == 1 {
                        vec![(v[0], v[0])]
                    } else {
                        v.windows(2).map(|w| (w[0], w[1])).collect()
                    }
                };
                let mut leaves = Vec::new();
                for (y0, y1) in pairs(&ys) {
                    for (x0, x1) in pairs(&xs) {
                        leaves.push(Cell { x0, x1, y0, y1 });
                    }
                }
                GridState {
                    known: vec![None; grid.nodes.len()],
                    grid,
                    leaves,
                }
            })
            .collect();
        Refinement { grids, where_is }
    }

    /// Expansion indices of the unknown corners of the current leaves (sorted).
    fn unknown_corners(&self) -> Vec<usize> {
        let mut out: Vec<usize> = self
            .grids
            .iter()
            .flat_map(|g| {
                g.leaves
                    .iter()
                    .flat_map(|c| c.corners())
                    .filter(|n| g.at(*n).is_none())
                    .map(|(x, y)| g.grid.nodes[y * g.grid.nx + x])
            })
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// The points to run first: the coarse lattice.
    pub fn first_points(&self) -> Vec<usize> {
        self.unknown_corners()
    }

    /// Record the verdict of a run point (points of no map are ignored).
    pub fn record(&mut self, index: usize, verdict: CellVerdict) {
        if let Some(&(g, node)) = self.where_is.get(&index) {
            self.grids[g].known[node] = Some(verdict);
        }
    }

    /// Split every leaf whose known points disagree and return the points to run next;
    /// empty when the refinement is complete (every leaf agrees or spans one grid step).
    pub fn next_points(&mut self) -> Vec<usize> {
        loop {
            let mut split_any = false;
            for g in &mut self.grids {
                let leaves = std::mem::take(&mut g.leaves);
                for cell in leaves {
                    if cell.splittable() && g.agreed(&cell).is_none() {
                        g.leaves.extend(cell.split());
                        split_any = true;
                    } else {
                        g.leaves.push(cell);
                    }
                }
            }
            let next = self.unknown_corners();
            // Splits whose new corners are all known already may make new leaves disagree.
            if !next.is_empty() || !split_any {
                return next;
            }
        }
    }

    /// The unrun grid points of agreeing leaves, with the leaf's verdict (sorted by index).
    pub fn inferred(&self) -> Vec<InferredCell> {
        let mut out = Vec::new();
        for g in &self.grids {
            let mut seen = vec![false; g.known.len()];
            for cell in &g.leaves {
                let Some(verdict) = g.agreed(cell) else {
                    continue;
                };
                for (x, y) in cell.nodes() {
                    let node = y * g.grid.nx + x;
                    if g.known[node].is_none() && !seen[node] {
                        seen[node] = true;
                        out.push(InferredCell {
                            index: g.grid.nodes[node],
                            overturned: verdict == CellVerdict::Overturned,
                        });
                    }
                }
            }
        }
        out.sort_by_key(|c| c.index);
        out
    }
}

/// Run the refinement to the end with `classify` giving the verdicts of each round's points
/// (None for a point it could not run: the refinement then stops, incomplete). Returns the
/// inferred cells, or None if it stopped early.
pub fn refine(
    grids: Vec<MapGrid>,
    levels: u32,
    mut classify: impl FnMut(&[usize]) -> Vec<(usize, Option<CellVerdict>)>,
) -> Option<Vec<InferredCell>> {
    let mut refinement = Refinement::new(grids, levels);
    let mut points = refinement.first_points();
    while !points.is_empty() {
        let mut complete = true;
        for (index, verdict) in classify(&points) {
            match verdict {
                Some(v) => refinement.record(index, v),
                None => complete = false,
            }
        }
        if !complete {
            return None;
        }
        points = refinement.next_points();
    }
    Some(refinement.inferred())
}

/// An adaptive map's sweep: the refinement's rounds through the journal
/// ([`rounds::run_journalled`]: journalled as they finish, reused from `checkpoint`). The
/// results hold the scenes that ran, in expansion order, and, once the refinement is
/// complete, the inferred cells. Sharding is refused: a round needs every verdict of the one
/// before it, so shards cannot run apart.
pub fn run_refined(
    study: &Study,
    points: &[ScenePoint],
    opts: &SweepOptions,
    library: &Library,
    checkpoint: Checkpoint,
    cancel: &AtomicBool,
    progress: &(dyn Fn(Progress) + Sync),
) -> crate::error::Result<SweepResults> {
    rounds::refuse_shards(
        study,
        opts,
        "an adaptive map (map: (…, refine: …))",
        "each refinement round needs every verdict of the round before; run it unsharded (it runs only the boundary), or remove `refine` to shard the full grid",
    )?;
    let Some(levels) = study.map.and_then(|m| m.refine_levels()) else {
        crate::error::bail!("study {}: its map is not adaptive", study.name);
    };
    let mut rounds = MapRounds {
        refinement: Refinement::new(map_grids(study)?, levels),
        by_index: points.iter().map(|p| (p.index, p)).collect(),
        started: false,
    };
    let run = rounds::run_journalled(&mut rounds, opts, library, checkpoint, cancel, progress);
    let mut outcomes = run.outcomes;
    outcomes.sort_by_key(|o| o.point.index);
    Ok(SweepResults {
        study_hash: study.hash(),
        study: Some(study.clone()),
        outcomes,
        cancelled: !run.complete,
        shard: None,
        build: build_id().to_string(),
        inferred: if run.complete {
            rounds.refinement.inferred()
        } else {
            Vec::new()
        },
    })
}

/// The refinement as a round search over the expansion's points: the coarse lattice first,
/// then each round's split corners.
struct MapRounds<'a> {
    refinement: Refinement,
    by_index: HashMap<usize, &'a ScenePoint>,
    started: bool,
}

impl Rounds for MapRounds<'_> {
    fn next_round(&mut self) -> Vec<ScenePoint> {
        let indices = if self.started {
            self.refinement.next_points()
        } else {
            self.started = true;
            self.refinement.first_points()
        };
        indices
            .iter()
            .filter_map(|i| self.by_index.get(i).map(|p| (*p).clone()))
            .collect()
    }

    fn record(&mut self, outcomes: &[SceneOutcome]) {
        for o in outcomes {
            self.refinement.record(o.point.index, CellVerdict::of(o));
        }
    }
}

/// The inferred cells of an adaptive study's finished scenes (from a journal or merged
/// results), by replaying the refinement on them; None if a point it needs is missing (the
/// run was stopped) or the study is no adaptive map.
pub fn replay(study: &Study, outcomes: &[SceneOutcome]) -> Option<Vec<InferredCell>> {
    let levels = study.map?.refine_levels()?;
    let verdicts: HashMap<usize, CellVerdict> = outcomes
        .iter()
        .map(|o| (o.point.index, CellVerdict::of(o)))
        .collect();
    refine(map_grids(study).ok()?, levels, |points| {
        points
            .iter()
            .map(|i| (*i, verdicts.get(i).copied()))
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(nx: usize, ny: usize) -> MapGrid {
        MapGrid {
            nx,
            ny,
            nodes: (0..nx * ny).collect(),
        }
    }

    #[test]
    fn lattice_keeps_both_ends() {
        assert_eq!(lattice(9, 4), vec![0, 4, 8]);
        assert_eq!(lattice(10, 4), vec![0, 4, 8, 9]);
        assert_eq!(lattice(1, 4), vec![0]);
    }

    #[test]
    fn a_straight_boundary_runs_only_the_coarse_lattice_and_its_column() {
        // Overturned left of x = 10.5 on a 33 × 17 grid, levels 3 (step 8).
        let (nx, ny) = (33, 17);
        let mut runs = 0;
        let inferred = refine(vec![grid(nx, ny)], 3, |points| {
            runs += points.len();
            points
                .iter()
                .map(|&i| {
                    let v = if i % nx <= 10 {
                        CellVerdict::Overturned
                    } else {
                        CellVerdict::Survived
                    };
                    (i, Some(v))
                })
                .collect()
        })
        .unwrap();
        assert_eq!(runs + inferred.len(), nx * ny);
        for c in &inferred {
            assert_eq!(c.overturned, c.index % nx <= 10, "{c:?}");
        }
        // The column pair x = 10, 11 runs in full; the rest is the 5 × 3 coarse lattice and
        // the split leaves' corners: far fewer than the grid.
        assert!(runs < nx * ny / 3, "{runs} runs");
    }
}
