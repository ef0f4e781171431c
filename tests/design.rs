//! The design inverse (study `design:` section, `rocklab design`): every answer checked by
//! rerunning scenes at it and just below it, the search's cost against a grid at the same
//! resolution, resume from finished scenes, and a non-monotone case reported as such.

use rocklab::sim::{self, Bounds};
use rocklab::study::Study;
use rocklab::study::design::{DesignParameter, DesignTarget};
use rocklab::sweep::design::{DesignRow, DesignStatus, replay, with_parameter};
use rocklab::sweep::{self, Progress, SweepOptions, SweepResults};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// A small design study: one block, sequential and mechanistic clutches, five pulses.
const SMALL: &str = r#"(
    version: 1,
    name: "design_small",
    structure: rigid(p: 2.0, alpha: [deg(8), deg(12)]),
    devices: [none, sequential(sigma: 0.5), mechanistic(sigma: 0.5, cbar: 1.0)],
    excitation: pulse(
        shape: sine,
        amplitude: tan_alpha_ratio(2.0),
        frequency: ratio((from: 3.0, to: 7.0, steps: 5)),
    ),
    quantities: [peak_rotation_ratio],
    spectrum: alpha,
    duration: 8.0,
    design: (
        parameter: sigma,
        bracket: (0.0, 3.0),
        resolution: 0.02,
        target: limit(quantity: peak_rotation_ratio, max: 0.5),
    ),
)"#;

fn small() -> Study {
    Study::from_ron_str(SMALL, "design_small.ron").unwrap_or_else(|e| panic!("{e}"))
}

pub(crate) fn run_with(study: &Study, opts: &SweepOptions, computed: &AtomicUsize) -> SweepResults {
    sweep::run_study(
        study,
        opts,
        rocklab::excitation::library::global().unwrap(),
        &AtomicBool::new(false),
        &|p| {
            if let Progress::SceneDone { reused: false, .. } = p {
                computed.fetch_add(1, Ordering::Relaxed);
            }
        },
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

pub(crate) fn run(study: &Study) -> SweepResults {
    run_with(study, &SweepOptions::default(), &AtomicUsize::new(0))
}

/// The peak rotation ratio (None: overturned) of every nominal scene of a design point with
/// σ set to `value`, in the order of its excitation points.
fn responses(study: &Study, row: &DesignRow, value: f64) -> Vec<(String, Option<f64>)> {
    let layout = study.layout().unwrap();
    let library = rocklab::excitation::library::global().unwrap();
    study
        .expand()
        .unwrap()
        .into_iter()
        .filter(|p| layout.locate(p.index).unwrap().0 == row.variant)
        .filter(|p| row.axes.iter().all(|(label, v)| p.coord(label) == Some(*v)))
        .map(|p| {
            let scene = with_parameter(&p.scene, DesignParameter::Sigma, value);
            let bounds = Bounds {
                measures: rocklab::study::Quantity::measures(&study.quantities),
                ..Bounds::default()
            };
            let r = sim::run_bounded(&scene, library, bounds).unwrap();
            let ratio = (!r.overturned).then_some(r.peak_rotation_ratio);
            (format!("ωg/p={}", p.coord("ωg/p").unwrap()), ratio)
        })
        .collect()
}

fn passes(r: Option<f64>, max: f64) -> bool {
    r.is_some_and(|v| v <= max)
}

/// Checks every answer of `rows` by rerunning scenes: at the reported value the target holds
/// at every excitation point (and the governing one is the worst there), at the value less
/// the resolution it fails at the governing point, and the final bracket is within the
/// resolution. Returns the number of answers found (references are only counted out).
fn check_answers(study: &Study, rows: &[DesignRow]) -> usize {
    let design = study.design.clone().unwrap();
    let DesignTarget::Limit { max, .. } = design.target else {
        panic!("a limit target")
    };
    let mut found = 0;
    for row in rows {
        match row.status {
            DesignStatus::ReferenceMet | DesignStatus::ReferenceFails => {
                assert_eq!(row.device, "bare");
                assert_eq!(row.probes, 1);
                continue;
            }
            DesignStatus::Found => found += 1,
            other => panic!("{row:?}: {other:?}"),
        }
        let value = row.value.unwrap();
        assert_eq!(value, row.hi);
        assert!(row.hi - row.lo <= design.resolution * row.hi, "{row:?}");
        let at = responses(study, row, value);
        for (point, r) in &at {
            assert!(
                passes(*r, max),
                "{row:?}: {point} gives {r:?} at σ = {value}"
            );
        }
        let worst = at
            .iter()
            .max_by(|a, b| a.1.unwrap().total_cmp(&b.1.unwrap()))
            .unwrap();
        assert_eq!(worst.0, row.governing, "{row:?}");
        assert_eq!(worst.1, row.achieved, "{row:?}");
        let below = value * (1.0 - design.resolution);
        let governing = responses(study, row, below)
            .into_iter()
            .find(|(p, _)| *p == row.governing)
            .unwrap();
        assert!(
            !passes(governing.1, max),
            "{row:?}: at σ = {below} the governing point gives {:?}",
            governing.1
        );
    }
    found
}

/// Every answer of the small study is right (see [`check_answers`]).
#[test]
fn every_design_point_meets_the_target_at_its_value_and_fails_just_below() {
    let study = small();
    let results = run(&study);
    assert!(!results.cancelled);
    let rows = replay(&study, &results.outcomes).unwrap();
    assert_eq!(rows.len(), 3 * 2, "three devices × two α");
    assert_eq!(check_answers(&study, &rows), 4, "{rows:?}");
    // An answer governed at an end of the frequency axis (ωg/p = 3 or 7) says the worst case
    // may lie beyond it; one governed inside says nothing. The warning reaches design.csv.
    let csv =
        String::from_utf8(rocklab::report::design::design_csv(&study, &rows).unwrap()).unwrap();
    for row in rows.iter().filter(|r| r.status == DesignStatus::Found) {
        let at: f64 = row.governing.rsplit('=').next().unwrap().parse().unwrap();
        let at_end = at == 3.0 || at == 7.0;
        assert_eq!(row.warning.is_some(), at_end, "{row:?}");
        if let Some(w) = &row.warning {
            let end = if at == 3.0 { "lowest" } else { "highest" };
            assert!(w.contains(&format!("governed at the {end} ωg/p")), "{w}");
            assert!(csv.contains(w.as_str()), "{csv}");
        }
    }
    // The bare block fails at α = 8° and the clutches need a σ > 0 there.
    assert!(
        rows.iter()
            .any(|r| r.status == DesignStatus::ReferenceFails)
    );
}

/// Every answer of the shipped design study is right, checked the same way.
#[test]
fn every_answer_of_the_shipped_design_study_is_right() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/design_sigma_rigid.ron"
    );
    let study = Study::load(std::path::Path::new(path)).unwrap_or_else(|e| panic!("{e}"));
    let rows = replay(&study, &run(&study).outcomes).unwrap();
    assert_eq!(rows.len(), 2 * 5, "two clutches × five α");
    assert_eq!(check_answers(&study, &rows), 10, "{rows:?}");
}

/// The search runs at most a quarter of the scenes a grid of σ at the same resolution would
/// (a step of resolution × the answer over the bracket, every step a pass over the pulses),
/// and a second run reuses every probe.
#[test]
fn the_search_costs_a_fraction_of_a_grid_and_a_rerun_reuses_every_probe() {
    let study = small();
    let dir = tempfile::tempdir().unwrap();
    let computed = AtomicUsize::new(0);
    let results = run_with(&study, &SweepOptions::default(), &computed);
    let rows = replay(&study, &results.outcomes).unwrap();
    let grid = rocklab::report::design::grid_scenes(&study, &rows);
    let ran = computed.load(Ordering::Relaxed);
    assert!(ran * 4 <= grid, "search {ran} scenes, grid {grid}");
    // Distinct scenes only: σ = 0 of both clutches is the bare block, run once.
    let keys: std::collections::HashSet<&str> = results
        .outcomes
        .iter()
        .map(|o| o.point.key.as_str())
        .collect();
    assert_eq!(keys.len(), ran);
    let path = dir.path().join("results.json");
    rocklab::report::save_results(&path, &results).unwrap();
    let again = AtomicUsize::new(0);
    let opts = SweepOptions {
        cache: Some(path),
        ..Default::default()
    };
    let rerun = run_with(&study, &opts, &again);
    assert_eq!(again.load(Ordering::Relaxed), 0, "every probe reused");
    assert_eq!(replay(&study, &rerun.outcomes).unwrap(), rows);
}

/// A stopped search resumes: with only the first rounds' scenes finished, the rerun computes
/// only the rest and reaches the same answer; the unfinished replay says Incomplete.
#[test]
fn a_stopped_search_resumes_from_its_finished_scenes() {
    let study = small();
    let full = run(&study);
    let rows = replay(&study, &full.outcomes).unwrap();
    let half: Vec<_> = full.outcomes[..full.outcomes.len() / 2].to_vec();
    let partial = replay(&study, &half).unwrap();
    assert!(partial.iter().any(|r| r.status == DesignStatus::Incomplete));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("results.json");
    let stopped = SweepResults {
        outcomes: half.clone(),
        cancelled: true,
        ..full.clone()
    };
    rocklab::report::save_results(&path, &stopped).unwrap();
    let computed = AtomicUsize::new(0);
    let opts = SweepOptions {
        cache: Some(path),
        ..Default::default()
    };
    let resumed = run_with(&study, &opts, &computed);
    let keys = |o: &[sweep::SceneOutcome]| -> std::collections::HashSet<String> {
        o.iter().map(|o| o.point.key.clone()).collect()
    };
    assert_eq!(
        computed.load(Ordering::Relaxed),
        keys(&full.outcomes).len() - keys(&half).len()
    );
    assert_eq!(replay(&study, &resumed.outcomes).unwrap(), rows);
}

/// Not achievable within the bracket is an answer: a bracket whose top is too small.
#[test]
fn a_bracket_too_small_is_reported_not_achievable() {
    let mut study = small();
    study.devices.truncate(2);
    study.design.as_mut().unwrap().bracket = (0.0, 0.02);
    if let rocklab::study::StructureFamily::Rigid { alpha, .. } = &mut study.structure {
        *alpha = rocklab::study::Values::One(8f64.to_radians());
    }
    let rows = replay(&study, &run(&study).outcomes).unwrap();
    let seq = rows.iter().find(|r| r.device == "sequential").unwrap();
    assert_eq!(seq.status, DesignStatus::NotAchievable, "{seq:?}");
    assert_eq!(seq.value, None);
    assert_eq!(seq.probes, 2);
    assert!(!seq.governing.is_empty());
}

/// Bad design sections are refused with the field and a hint.
#[test]
fn bad_design_sections_name_the_field() {
    let cases = [
        (
            "bracket: (0.0, 3.0)",
            "bracket: (3.0, 1.0)",
            "design.bracket",
        ),
        ("resolution: 0.02", "resolution: 0.0", "design.resolution"),
        ("max: 0.5", "max: -1.0", "design.target.max"),
        (
            "quantity: peak_rotation_ratio, max",
            "quantity: peak_abs_acceleration, max",
            "design.target.quantity",
        ),
        (
            "sequential(sigma: 0.5)",
            "sequential(sigma: [0.5, 1.0])",
            "devices[1].sigma",
        ),
        (
            "parameter: sigma",
            "parameter: friction,\n over: [record]",
            "design.over",
        ),
    ];
    for (from, to, field) in cases {
        let text = SMALL.replace(from, to);
        assert_ne!(text, SMALL, "{from}");
        let err = Study::from_ron_str(&text, "bad.ron").unwrap_err();
        assert_eq!(err.field.as_deref(), Some(field), "{to}: {err}");
        assert!(
            err.hint.as_ref().is_some_and(|h| !h.is_empty()),
            "{to}: {err}"
        );
    }
}

/// A non-monotone case, found by a σ grid (0.05 steps) of a sequential clutch on a rigid block
/// (R = 3 m, α = 8°) under Northridge: the bare block survives, yet with σ = 0.10 … 0.15 (and
/// 0.40) it overturns, and survives again from 0.45 on. The bracket's bottom (σ = 0, the bare
/// block) meets the target, so bisection alone would answer "no device needed"; the
/// verification above it finds the overturning, and the row says non_monotone with the
/// values that fail. The bracket's top, 3.75, puts the first verification value at
/// 3.75 × (1/5)² = 0.15 (the verification samples, it cannot prove: 0.12, the first value of
/// a bracket up to 3, happens to survive).
#[test]
fn a_device_that_overturns_a_surviving_block_is_reported_non_monotone() {
    let text = r#"(
        version: 1,
        name: "design_non_monotone",
        structure: rigid(size: 3.0, alpha: deg(8)),
        devices: [sequential(sigma: 0.5)],
        excitation: record(names: ["northridge"]),
        quantities: [peak_rotation_ratio],
        spectrum: size,
        duration: 30.0,
        design: (parameter: sigma, bracket: (0.0, 3.75), target: no_overturning),
    )"#;
    let study =
        Study::from_ron_str(text, "design_non_monotone.ron").unwrap_or_else(|e| panic!("{e}"));
    let rows = replay(&study, &run(&study).outcomes).unwrap();
    let [row] = rows.as_slice() else {
        panic!("{rows:?}")
    };
    assert_eq!(row.status, DesignStatus::NonMonotone, "{row:?}");
    assert_eq!(row.value, Some(0.0));
    assert!(!row.fails_above.is_empty());
    let library = rocklab::excitation::library::global().unwrap();
    let scene = &study.expand().unwrap()[0].scene;
    let overturns = |sigma: f64| {
        let s = with_parameter(scene, DesignParameter::Sigma, sigma);
        sim::run_bounded(&s, library, Bounds::default())
            .unwrap()
            .overturned
    };
    // The reported value survives, and every value said to fail above it overturns.
    assert!(!overturns(0.0));
    for v in &row.fails_above {
        assert!(*v > 0.0 && overturns(*v), "σ = {v}");
    }
    // The summary and design.csv say so.
    let csv =
        String::from_utf8(rocklab::report::design::design_csv(&study, &rows).unwrap()).unwrap();
    assert!(
        csv.lines().nth(1).unwrap().contains("non_monotone"),
        "{csv}"
    );
}

/// The answer reaches the user: design.csv beside the results and `rocklab plot`'s chart.
#[test]
fn design_csv_and_the_design_chart_show_the_answer() {
    let study = small();
    let results = run(&study);
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("x");
    std::fs::create_dir_all(&dir).unwrap();
    rocklab::report::save_results(&dir.join("results.json"), &results).unwrap();
    rocklab::report::write_tables(&dir, &study, &results).unwrap();
    let csv = std::fs::read_to_string(dir.join("design.csv")).unwrap();
    assert!(
        csv.starts_with("device,alpha,parameter,value,lo,hi,probes"),
        "{csv}"
    );
    let options = rocklab::report::FigureOptions::new(rocklab::report::ImageFormat::Svg);
    let svg = rocklab::report::plot_design(&dir, &options, &results)
        .unwrap()
        .unwrap();
    let svg = std::fs::read_to_string(svg).unwrap();
    assert!(svg.contains("least σ"), "the y axis names the parameter");
    assert!(svg.contains("sequential") && svg.contains("mechanistic"));
}
