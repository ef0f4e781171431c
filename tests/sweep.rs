//! Sweeps: deterministic whatever the thread count, equal to running scenes one by one,
//! shard + merge equal to one run, cancel keeps what finished, reruns reuse cached scenes,
//! failures are recorded; and the `run`/`merge`/`compare`/`plot` commands end to end.

use crate::util::{rocklab, rocklab_command};
use rocklab::report;
use rocklab::study::Study;
use rocklab::sweep::{self, Progress, SceneOutcome, SweepOptions, SweepResults};
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

const SMALL: &str = r#"(
    version: 1,
    name: "small",
    structure: rigid(p: 2.0, alpha: 0.17453292519943295),
    devices: [
        none,
        sequential(sigma: 0.5),
        mechanistic(sigma: 0.5, k_theta: [1.0, 3.0]),
    ],
    excitation: pulse(
        shape: sine,
        amplitude: alpha_ratio(1.5),
        frequency: ratio([2.5, 4.0, 6.0, 9.0]),
    ),
    quantities: [peak_rotation_ratio, peak_abs_acceleration],
    duration: 8.0,
)"#;

fn small() -> Study {
    Study::from_ron_str(SMALL, "small.ron").unwrap()
}

fn quiet(_: Progress) {}

/// Results without wall-clock times (the only field that legitimately varies between runs).
fn timeless(outcomes: &[SceneOutcome]) -> Vec<SceneOutcome> {
    outcomes
        .iter()
        .cloned()
        .map(|mut o| {
            if let Ok(r) = &mut o.result {
                r.wall_seconds = 0.0;
            }
            o
        })
        .collect()
}

fn run_with(study: &Study, opts: SweepOptions) -> SweepResults {
    sweep::run_study(
        study,
        &opts,
        rocklab::excitation::library::global().unwrap(),
        &AtomicBool::new(false),
        &quiet,
    )
    .unwrap()
}

#[test]
fn one_and_two_threads_agree_with_each_other_and_with_scene_by_scene_runs() {
    let study = small();
    let one = run_with(
        &study,
        SweepOptions {
            jobs: Some(1),
            ..Default::default()
        },
    );
    let two = run_with(
        &study,
        SweepOptions {
            jobs: Some(2),
            ..Default::default()
        },
    );
    assert_eq!(one.outcomes.len(), 16);
    assert!(!one.cancelled);
    assert_eq!(timeless(&one.outcomes), timeless(&two.outcomes));
    assert_eq!(
        report::results_csv(&one).unwrap(),
        report::results_csv(&two).unwrap()
    );
    // A study's scenes compute what its quantities need; alone, the same measures.
    let bounds = rocklab::sim::Bounds {
        measures: rocklab::report::Quantity::measures(&study.quantities),
        ..Default::default()
    };
    for o in &one.outcomes {
        let mut alone = rocklab::sim::run_bounded(
            &o.point.scene,
            rocklab::excitation::library::global().unwrap(),
            bounds,
        )
        .unwrap();
        alone.wall_seconds = 0.0;
        assert_eq!(timeless(std::slice::from_ref(o))[0].result, Ok(alone));
    }
    // Something happens in this sweep: some scenes overturn, some survive with peaks.
    let overturned = one
        .outcomes
        .iter()
        .filter(|o| o.result.as_ref().unwrap().overturned)
        .count();
    assert!(
        overturned > 0 && overturned < one.outcomes.len(),
        "{overturned}"
    );
}

#[test]
fn the_simulate_command_agrees_with_the_sweep() {
    let study = small();
    let results = run_with(&study, SweepOptions::default());
    // Mechanistic kθ = 3, ωg/p = 4.
    let o = results
        .outcomes
        .iter()
        .find(|o| o.point.group == "mechanistic kθ=3" && o.point.coords[0].1 == 4.0)
        .unwrap();
    let out = rocklab_command(&[
        "simulate",
        "--alpha",
        "0.17453292519943295",
        "--p",
        "2",
        "--device",
        "mechanistic",
        "--sigma",
        "0.5",
        "--k-theta",
        "3",
        "--amplitude-alpha",
        "1.5",
        "--frequency-ratio",
        "4",
        "--duration",
        "8",
        "--stop-when-settled",
        "--json",
    ])
    .output()
    .unwrap();
    let json = crate::util::json_of(out);
    let r = o.result.as_ref().unwrap();
    assert_eq!(
        json["peak_rotation_ratio"].as_f64().unwrap(),
        r.peak_rotation_ratio
    );
    assert_eq!(json["impacts"].as_u64().unwrap(), r.counters.impacts);
    assert_eq!(json["end_time"].as_f64().unwrap(), r.end_time);
}

#[test]
fn cancel_keeps_the_finished_scenes() {
    let study = small();
    let points = study.expand().unwrap();
    let cancel = AtomicBool::new(false);
    let done = AtomicUsize::new(0);
    let progress = |p: Progress| {
        if let Progress::SceneDone { .. } = p
            && done.fetch_add(1, Ordering::SeqCst) + 1 == 3
        {
            cancel.store(true, Ordering::SeqCst);
        }
    };
    let opts = SweepOptions {
        jobs: Some(1),
        ..Default::default()
    };
    let partial = sweep::run(
        &points,
        &opts,
        rocklab::excitation::library::global().unwrap(),
        &cancel,
        &progress,
    );
    assert!(partial.cancelled);
    assert_eq!(partial.outcomes.len(), 3);
    for o in &partial.outcomes {
        let mut alone = rocklab::sim::run(
            &o.point.scene,
            rocklab::excitation::library::global().unwrap(),
        )
        .unwrap();
        alone.wall_seconds = 0.0;
        assert_eq!(timeless(std::slice::from_ref(o))[0].result, Ok(alone));
    }
    let indices: Vec<usize> = partial.outcomes.iter().map(|o| o.point.index).collect();
    assert!(indices.windows(2).all(|w| w[0] < w[1]), "{indices:?}");
}

#[test]
fn reruns_reuse_finished_scenes_by_key_and_fresh_runs_do_not() {
    let study = small();
    let first = run_with(&study, SweepOptions::default());
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("results.json");
    // Tamper with one cached result: if the rerun reuses it, the sentinel shows.
    let mut tampered = first.clone();
    let r = tampered.outcomes[5].result.as_mut().unwrap();
    r.peak_rotation_ratio = 123.0;
    r.overturned = false;
    // A recorded failure is not reused: the scene runs again.
    tampered.outcomes[6].result = Err("record file missing".into());
    report::save_results(&cache, &tampered).unwrap();
    let reused = run_with(
        &study,
        SweepOptions {
            cache: Some(cache.clone()),
            ..Default::default()
        },
    );
    assert_eq!(
        reused.outcomes[5]
            .result
            .as_ref()
            .unwrap()
            .peak_rotation_ratio,
        123.0
    );
    assert_eq!(
        timeless(&reused.outcomes[..5]),
        timeless(&first.outcomes[..5])
    );
    // Results of another build of rocklab are never reused.
    tampered.build = "another build".into();
    let other = dir.path().join("other.json");
    report::save_results(&other, &tampered).unwrap();
    let rerun = run_with(
        &study,
        SweepOptions {
            cache: Some(other),
            ..Default::default()
        },
    );
    assert_eq!(timeless(&rerun.outcomes), timeless(&first.outcomes));
    let fresh = run_with(&study, SweepOptions::default());
    assert_eq!(timeless(&fresh.outcomes), timeless(&first.outcomes));
    // A changed solver setting changes every key: nothing is reused.
    let mut tighter = study.clone();
    tighter.rtol = 1e-8;
    let rerun = run_with(
        &tighter,
        SweepOptions {
            cache: Some(cache),
            ..Default::default()
        },
    );
    assert!(
        rerun
            .outcomes
            .iter()
            .all(|o| o.result.as_ref().unwrap().peak_rotation_ratio != 123.0)
    );
}

#[test]
fn a_failing_scene_is_recorded_and_the_sweep_goes_on() {
    let mut points = small().expand().unwrap();
    points[1].scene.duration = -1.0;
    let results = sweep::run(
        &points,
        &SweepOptions::default(),
        rocklab::excitation::library::global().unwrap(),
        &AtomicBool::new(false),
        &quiet,
    );
    assert_eq!(results.outcomes.len(), points.len());
    let reason = results.outcomes[1].result.as_ref().unwrap_err();
    assert!(reason.contains("duration"), "{reason}");
    assert!(
        results
            .outcomes
            .iter()
            .enumerate()
            .all(|(i, o)| i == 1 || o.result.is_ok())
    );
    assert!(report::summary(&results).contains("1 failed"));
    let csv = String::from_utf8(report::results_csv(&results).unwrap()).unwrap();
    assert!(csv.contains("failed: invalid scene"), "{csv}");
}

#[test]
fn spectra_and_maps_are_the_scene_results_rearranged() {
    let text = r#"(
        version: 1,
        name: "map",
        structure: rigid(p: 2.0, alpha: 0.17453292519943295),
        devices: [none, sequential(sigma: 0.5)],
        excitation: pulse(shape: sine, amplitude: tan_alpha_ratio([1.0, 2.0, 4.0]),
                          frequency: ratio([6.0, 2.0, 4.0])),
        map: (x: frequency, y: amplitude),
        duration: 8.0,
    )"#;
    let study = Study::from_ron_str(text, "map.ron").unwrap();
    let results = run_with(&study, SweepOptions::default());
    let maps = report::maps(&results);
    assert_eq!(maps.len(), 2);
    let spectra = report::spectra(&results);
    // One spectrum per device and amplitude, sorted by ωg/p.
    assert_eq!(spectra.len(), 6);
    for o in &results.outcomes {
        let r = o.result.as_ref().unwrap();
        let (x, y) = (
            o.point.coord("ωg/p").unwrap(),
            o.point.coord("A/(g·tanα)").unwrap(),
        );
        let map = maps.iter().find(|m| m.label == o.point.group).unwrap();
        assert_eq!(map.xs, vec![2.0, 4.0, 6.0]);
        let (ix, iy) = (
            map.xs.iter().position(|v| *v == x).unwrap(),
            map.ys.iter().position(|v| *v == y).unwrap(),
        );
        assert_eq!(map.cells[iy][ix], Some(r.overturned));
        let sp = spectra
            .iter()
            .find(|s| {
                s.label
                    == format!(
                        "{} A/(g·tanα)={}",
                        o.point.group,
                        rocklab::numfmt::fmt_num(y)
                    )
            })
            .unwrap();
        assert_eq!(sp.xs, vec![2.0, 4.0, 6.0]);
        let i = sp.xs.iter().position(|v| *v == x).unwrap();
        assert_eq!(sp.ys[i], (!r.overturned).then_some(r.peak_rotation_ratio));
    }
    // Both maps draw, one panel each.
    let dir = tempfile::tempdir().unwrap();
    let options = report::FigureOptions::new(report::ImageFormat::Svg);
    let choice = report::PlotChoice::default();
    let file = report::plot_maps(dir.path(), &options, &results, &maps, &choice).unwrap();
    let svg = std::fs::read_to_string(file.unwrap()).unwrap();
    assert!(svg.contains("(a) bare") && svg.contains("(b) sequential"));
    // Overturning is monotone in amplitude for the bare block at ωg/p = 2 (the most
    // dangerous frequency here): if it survives a strong pulse it survives a weaker one.
    let bare = &maps[0];
    let column: Vec<bool> = bare.cells.iter().map(|row| row[0].unwrap()).collect();
    assert!(column.windows(2).all(|w| w[0] <= w[1]), "{column:?}");
}

fn write_small(dir: &Path) -> String {
    let path = dir.join("small.ron");
    std::fs::write(&path, SMALL).unwrap();
    path.to_string_lossy().to_string()
}

#[test]
fn shards_merged_equal_one_full_run() {
    let dir = tempfile::tempdir().unwrap();
    let study = write_small(dir.path());
    let full = dir.path().join("full");
    let out = rocklab(&[
        "run",
        &study,
        "--out",
        full.to_str().unwrap(),
        "--jobs",
        "2",
        "--quiet",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let shards = dir.path().join("shards");
    let mut files = Vec::new();
    for i in 0..3 {
        let shard = format!("{i}/3");
        let out = rocklab(&[
            "run",
            &study,
            "--out",
            shards.to_str().unwrap(),
            "--shard",
            &shard,
            "--jobs",
            "1",
            "--quiet",
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        files.push(shards.join(format!("results.shard-{i}-of-3.json")));
    }
    // Merge in a scrambled order: the result is in expansion order all the same.
    let merged = dir.path().join("merged");
    let out = rocklab(&[
        "merge",
        files[2].to_str().unwrap(),
        files[0].to_str().unwrap(),
        files[1].to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let read = |p: &Path| std::fs::read(p).unwrap();
    assert_eq!(
        read(&full.join("results.csv")),
        read(&merged.join("results.csv"))
    );
    assert_eq!(
        read(&full.join("summary.txt")),
        read(&merged.join("summary.txt"))
    );
    let a = report::load_results(&full.join("results.json")).unwrap();
    let b = report::load_results(&merged.join("results.json")).unwrap();
    assert_eq!(timeless(&a.outcomes), timeless(&b.outcomes));
    assert_eq!((a.study_hash, a.study), (b.study_hash, b.study));
    // A missing shard is reported as incomplete, not silently merged.
    let partial = dir.path().join("partial");
    let out = rocklab(&[
        "merge",
        files[0].to_str().unwrap(),
        "--out",
        partial.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("incomplete"));
}

#[test]
fn run_prints_a_summary_and_compare_and_plot_read_the_results() {
    let dir = tempfile::tempdir().unwrap();
    let study = write_small(dir.path());
    let out_dir = dir.path().join("out");
    let out = rocklab(&["run", &study, "--out", out_dir.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // Not a terminal: plain progress lines instead of a bar.
    let log = String::from_utf8(out.stderr).unwrap();
    assert!(log.contains("progress: 0/16 scenes"), "{log}");
    assert!(log.contains("16 scenes (0 reused, 16 new) in"), "{log}");
    let summary = String::from_utf8(out.stdout).unwrap();
    assert!(summary.contains("study small"), "{summary}");
    assert!(summary.contains("mechanistic kθ=3"), "{summary}");
    let out = rocklab(&[
        "compare",
        out_dir.to_str().unwrap(),
        "--a",
        "sequential",
        "--b",
        "bare",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("A = sequential, B = bare") && text.contains("B/A"),
        "{text}"
    );
    let out = rocklab(&[
        "compare",
        out_dir.to_str().unwrap(),
        "--a",
        "inerter",
        "--b",
        "bare",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let svg = dir.path().join("svg");
    let out = rocklab(&[
        "plot",
        out_dir.to_str().unwrap(),
        "--svg",
        svg.to_str().unwrap(),
        "--scene",
        "5",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for name in ["spectra.svg", "scene-5.svg"] {
        let text = std::fs::read_to_string(svg.join(name)).unwrap();
        assert!(text.starts_with("<svg") && text.contains("<text"), "{name}");
    }
    let png = dir.path().join("png");
    let out = rocklab(&[
        "plot",
        out_dir.to_str().unwrap(),
        "--png",
        png.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bytes = std::fs::read(png.join("spectra.png")).unwrap();
    assert_eq!(&bytes[..4], b"\x89PNG");
}

#[test]
fn a_bad_study_file_exits_2_naming_the_place() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.ron");
    std::fs::write(&path, SMALL.replace("sigma: 0.5)", "sigma: 0.5, sigm: 1)")).unwrap();
    let out = rocklab(&[
        "run",
        path.to_str().unwrap(),
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("bad.ron:7:") && err.contains("sigm"), "{err}");
    assert!(!dir.path().join("results.json").exists());
    let out = rocklab(&["run", &write_small(dir.path()), "--dry-run"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("16 scenes in 4 groups") && text.contains("4  mechanistic kθ=3"),
        "{text}"
    );
    assert!(!dir.path().join("out").exists());
    let out = rocklab(&["run", "default", "--shard", "3/3"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn record_studies_run_each_record_at_each_scale() {
    let text = r#"(
        version: 1,
        name: "records",
        structure: rigid(p: [1.5, 3.0], alpha: 0.2),
        devices: [none, mechanistic(sigma: 0.5, xi_theta: 0.02)],
        excitation: record(names: ["northridge", "palm_springs"], scale: [0.0, 1.0]),
        spectrum: p,
        duration: 30.0,
    )"#;
    let study = Study::from_ron_str(text, "records.ron").unwrap();
    let results = run_with(&study, SweepOptions::default());
    assert_eq!(results.outcomes.len(), 2 * 2 * 2 * 2);
    for o in &results.outcomes {
        let r = o.result.as_ref().unwrap();
        let scale = o.point.coord("scale").unwrap();
        assert!(
            o.point.group.ends_with(" · northridge") || o.point.group.ends_with(" · palm_springs")
        );
        if scale == 0.0 {
            // No ground motion: the structure never leaves the ground.
            assert_eq!(
                (r.peaks.rotation, r.overturned),
                (0.0, false),
                "{}",
                o.point.group
            );
        }
    }
    // At full scale, Northridge (PGA 0.87 g) lifts the bare block with p = 1.5 (uplift at
    // g·tan α = 0.2 g).
    let full = results
        .outcomes
        .iter()
        .find(|o| {
            o.point.group == "bare scale=1 · northridge" && o.point.coords[0] == ("p".into(), 1.5)
        })
        .unwrap();
    let r = full.result.as_ref().unwrap();
    assert!(r.overturned || r.peaks.rotation > 0.0, "{r:?}");
    let bad = Study::from_ron_str(&text.replace("palm_springs", "kobe"), "bad.ron").unwrap_err();
    assert_eq!(bad.field.as_deref(), Some("excitation.names[1]"));
    assert!(bad.to_string().contains("rocklab records"), "{bad}");
    assert!(bad.line.is_some(), "{bad}");
}
