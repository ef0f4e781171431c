//! Adaptive overturning maps (map: (…, refine: (levels: n))): cell for cell the full map on
//! the shipped map study, what the refinement finds and misses on a known island shape, and
//! a stopped adaptive run resumed from its journal.

use crate::util::sweep_in;
use rocklab::report::maps;
use rocklab::study::{Refine, Study};
use rocklab::sweep::adaptive::{CellVerdict, MapGrid, refine};
use rocklab::sweep::{self, SweepOptions};
use std::collections::HashSet;
use std::sync::atomic::AtomicBool;

fn shipped_map() -> Study {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/overturning_map_rigid.ron"
    );
    Study::load(std::path::Path::new(path)).unwrap()
}

fn adaptive(mut study: Study, levels: u32) -> Study {
    study.map.as_mut().unwrap().refine = Some(Refine { levels });
    study
}

fn run(study: &Study) -> sweep::SweepResults {
    sweep::run_study(
        study,
        &SweepOptions::default(),
        rocklab::excitation::library::global().unwrap(),
        &AtomicBool::new(false),
        &|_| {},
    )
    .unwrap()
}

/// The shipped map at its own resolution: the adaptive map's cells (run and inferred) equal
/// the full grid's, its run scenes are the full run's scenes, and it runs under a third of them.
#[test]
fn the_adaptive_shipped_map_equals_the_full_map_cell_for_cell() {
    let full_study = shipped_map();
    let full = run(&full_study);
    let study = adaptive(full_study.clone(), 2);
    let refined = run(&study);
    assert!(!refined.cancelled);
    let (full_maps, refined_maps) = (maps(&full), maps(&refined));
    assert_eq!(full_maps.len(), 2);
    assert_eq!(refined_maps.len(), full_maps.len());
    for (f, r) in full_maps.iter().zip(&refined_maps) {
        assert_eq!(f.label, r.label);
        assert_eq!((&f.xs, &f.ys), (&r.xs, &r.ys));
        for (iy, (frow, rrow)) in f.cells.iter().zip(&r.cells).enumerate() {
            for (ix, (fc, rc)) in frow.iter().zip(rrow).enumerate() {
                assert!(fc.is_some(), "the full map ran every cell");
                assert_eq!(fc, rc, "{} cell ({ix}, {iy}) differs", f.label);
            }
        }
        assert_eq!(f.boundary(), r.boundary());
        // The boundary is not trivial: both verdicts on the map.
        assert!(!f.boundary().is_empty());
    }
    // The workbench shows the inferred cells as verdicts (not as unrun gaps), flagged.
    let shown = rocklab::tui::components::results::Results::new(refined.clone(), false);
    for m in &shown.maps {
        assert!(m.cells.iter().flatten().all(Option::is_some), "{}", m.label);
        let flagged = (0..m.ys.len())
            .flat_map(|iy| (0..m.xs.len()).map(move |ix| (ix, iy)))
            .filter(|(ix, iy)| m.inferred(*ix, *iy))
            .count();
        assert!(flagged > m.xs.len() * m.ys.len() / 2, "{flagged} inferred");
    }
    // Every grid point is run or inferred, never both; run scenes are the full run's.
    let ran: HashSet<usize> = refined.outcomes.iter().map(|o| o.point.index).collect();
    let inferred: HashSet<usize> = refined.inferred.iter().map(|c| c.index).collect();
    assert!(ran.is_disjoint(&inferred));
    assert_eq!(ran.len() + inferred.len(), full.outcomes.len());
    for o in &refined.outcomes {
        let f = &full.outcomes[o.point.index];
        assert_eq!(f.point.key, o.point.key);
        let peaks = |r: &Result<rocklab::sim::SceneResult, String>| {
            r.as_ref()
                .map(|r| (r.overturned, r.peak_rotation_ratio))
                .ok()
        };
        assert_eq!(peaks(&f.result), peaks(&o.result));
    }
    assert!(
        3 * refined.outcomes.len() < full.outcomes.len(),
        "{} of {} scenes ran",
        refined.outcomes.len(),
        full.outcomes.len()
    );
}

/// A fake classifier over one nx × ny grid: overturned where `overturns(ix, iy)`.
fn oracle(
    nx: usize,
    ny: usize,
    levels: u32,
    overturns: impl Fn(usize, usize) -> bool,
) -> (Vec<bool>, usize) {
    let mut runs = 0;
    let grid = MapGrid {
        nx,
        ny,
        nodes: (0..nx * ny).collect(),
    };
    let inferred = refine(vec![grid], levels, |points| {
        runs += points.len();
        points
            .iter()
            .map(|&i| {
                let v = if overturns(i % nx, i / nx) {
                    CellVerdict::Overturned
                } else {
                    CellVerdict::Survived
                };
                (i, Some(v))
            })
            .collect()
    })
    .expect("the oracle answers every point");
    let mut out: Vec<Option<bool>> = vec![None; nx * ny];
    for c in &inferred {
        out[c.index] = Some(c.overturned);
    }
    // Run points carry their true verdict; only the inferred ones can be wrong.
    let result = (0..nx * ny)
        .map(|i| out[i].unwrap_or_else(|| overturns(i % nx, i / nx)))
        .collect();
    (result, runs)
}

/// Overturning below a rising boundary, with a rectangular survival island inside the
/// overturned region (the non-monotone spectra of sine pulses): any island at least one coarse
/// cell (2^levels grid steps) wide and tall is found exactly, wherever it sits; an island
/// narrower than a coarse cell that touches no lattice point is missed (inferred overturned).
#[test]
fn islands_of_a_coarse_cell_are_found_and_smaller_ones_between_lattice_points_are_missed() {
    let (nx, ny, levels) = (49, 41, 3);
    let step = 1 << levels;
    // Overturned left of x = 30 + y/2 (a boundary that runs through the whole map).
    let mainland = |x: usize, y: usize| 2 * x < 60 + y;
    let island = |x0: usize, y0: usize, w: usize, h: usize| {
        move |x: usize, y: usize| {
            let inside = (x0..=x0 + w).contains(&x) && (y0..=y0 + h).contains(&y);
            mainland(x, y) && !inside
        }
    };
    let mut checked = 0;
    for (w, h) in [(step, step), (step + 3, step), (step, step + 5)] {
        for x0 in 0..=(30 - w - 1) {
            for y0 in (0..ny - h).step_by(3) {
                let truth = island(x0, y0, w, h);
                let (map, runs) = oracle(nx, ny, levels, truth);
                for y in 0..ny {
                    for x in 0..nx {
                        assert_eq!(
                            map[y * nx + x],
                            truth(x, y),
                            "island {w}×{h} at ({x0}, {y0}): cell ({x}, {y})"
                        );
                    }
                }
                assert!(runs < nx * ny, "{runs} runs");
                checked += 1;
            }
        }
    }
    assert!(checked > 100);
    // Smaller than a coarse cell and strictly between lattice lines: missed entirely.
    let small = island(step + 2, step + 2, step - 4, step - 4);
    let (map, _) = oracle(nx, ny, levels, small);
    assert!(!small(step + 3, step + 3), "the island is there");
    assert!(
        map[(step + 3) * nx + step + 3],
        "and the refinement misses it"
    );
    // The same island with one more level of refinement's worth of lattice (levels 2) is found.
    let (map, _) = oracle(nx, ny, 2, small);
    assert!((0..nx * ny).all(|i| map[i] == small(i % nx, i / nx)));
}

/// A small adaptive map stopped after a few scenes, then resumed: the scenes of the first run
/// are reused from the journal (not recomputed) and the result is the uninterrupted one.
#[test]
fn a_stopped_adaptive_map_resumes_from_its_journal() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/overturning_map_rigid.ron"
    ))
    .unwrap()
    .replace("steps: 29", "steps: 15")
    .replace("steps: 45", "steps: 23")
    .replace(
        "map: (x: frequency, y: amplitude)",
        "map: (x: frequency, y: amplitude, refine: (levels: 2))",
    );
    let study = Study::from_ron_str(&text, "small adaptive map").unwrap();
    let uninterrupted = run(&study);
    assert!(!uninterrupted.cancelled && !uninterrupted.inferred.is_empty());

    let dir = tempfile::tempdir().unwrap();
    let points = study.expand().unwrap();
    // First run: stopped after 20 scenes (in the coarse round: there is more to do).
    let first = sweep_in(dir.path(), &study, &points, Some(20));
    let (stopped, results_file, journal) = (first.results, first.results_file, first.journal);
    assert!(stopped.cancelled);
    assert!(
        stopped.inferred.is_empty(),
        "no cell inferred from a stopped run"
    );
    let first = stopped.outcomes.len();
    assert!(first >= 20 && first < uninterrupted.outcomes.len());
    // The journal alone (as a run killed before writing its results file leaves it).
    let partial_file = std::fs::read(&results_file).unwrap();
    std::fs::remove_file(&results_file).unwrap();
    let (from_journal, _) = sweep::load_fullest(&journal).unwrap().unwrap();
    std::fs::write(&results_file, partial_file).unwrap();
    assert!(
        from_journal.cancelled,
        "a stopped adaptive journal is incomplete"
    );

    // Resumed: the first run's scenes come from the journal.
    let again = sweep_in(dir.path(), &study, &points, None);
    let resumed = again.results;
    assert!(!resumed.cancelled);
    assert_eq!(again.reused, first);
    assert_eq!(again.computed, uninterrupted.outcomes.len() - first);
    assert_eq!(resumed.inferred, uninterrupted.inferred);
    assert_eq!(maps(&resumed), maps(&uninterrupted));
    // The finished journal alone replays to the same inferred cells (`rocklab merge JOURNAL`).
    std::fs::remove_file(&results_file).unwrap();
    let (replayed, _) = sweep::load_fullest(&journal).unwrap().unwrap();
    assert!(!replayed.cancelled);
    assert_eq!(replayed.inferred, uninterrupted.inferred);
}

/// Sharding an adaptive map is refused with the reason, before any scene runs.
#[test]
fn sharding_an_adaptive_map_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let study = adaptive(shipped_map(), 2);
    let path = dir.path().join("adaptive.ron");
    study.save(&path).unwrap();
    let out = dir.path().join("out");
    let output = crate::util::rocklab(&[
        "run",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--shard",
        "0/2",
    ]);
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("adaptive") && stderr.contains("shard 0/2"),
        "{stderr}"
    );
    assert!(!out.join("results.shard-0-of-2.journal").exists());
}
