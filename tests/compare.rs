//! Comparisons by meaning: exact group identity and labels, pairing (same record, same
//! structure; one side a grid), selectors and their errors, overturning-aware statistics
//! checked against hand-computed values on small synthetic results, record-suite mean and
//! CV, map comparison, and `rocklab compare --json` end to end.

use rocklab::report::compare::{self, MapCell};
use rocklab::report::select::Selector;
use rocklab::report::{self, Group, OverturningMap, PointState, Quantity};
use rocklab::sim::{Peaks, SceneResult};
use rocklab::study::{DeviceKind, Study};
use rocklab::sweep::{SceneOutcome, SweepResults};

/// What a synthetic scene ends with.
#[derive(Clone, Copy)]
enum Fake {
    Peak(f64),
    Overturned,
    Failed,
    NotRun,
}

/// Results of `study` without running it: every scene gets the outcome `fake` says, on a
/// template result of one real (short) scene.
fn synthetic(study: &Study, fake: impl Fn(&rocklab::study::ScenePoint) -> Fake) -> SweepResults {
    let points = study.expand().unwrap();
    let outcomes = points
        .iter()
        .filter_map(|p| {
            let result = match fake(p) {
                Fake::NotRun => return None,
                Fake::Failed => Err("synthetic failure".to_string()),
                Fake::Overturned => Ok(SceneResult::from_peaks(true, 0.3, Peaks::default(), 1.0)),
                Fake::Peak(v) => {
                    let peaks = Peaks {
                        rotation: v * 0.1,
                        ..Peaks::default()
                    };
                    Ok(SceneResult::from_peaks(false, 0.5, peaks, v))
                }
            };
            Some(SceneOutcome {
                point: p.clone(),
                result,
            })
        })
        .collect();
    SweepResults {
        study_hash: study.hash(),
        study: Some(study.clone()),
        outcomes,
        ..Default::default()
    }
}

/// Sequential and a 2-member mechanistic grid on two block slendernesses α, over ωg/p.
const GRID: &str = r#"(
    version: 1,
    name: "grid",
    structure: rigid(p: 2.0, alpha: [0.1, 0.2]),
    devices: [sequential(sigma: 0.5), mechanistic(sigma: 0.5, k_theta: [1.0, 3.0])],
    excitation: pulse(shape: sine, amplitude: alpha_ratio(1.5), frequency: ratio([2.0, 4.0, 6.0])),
    duration: 0.5,
)"#;

fn kind(p: &rocklab::study::ScenePoint) -> (&'static str, f64, f64, f64) {
    use rocklab::scene::{ClutchStiffness, Device, Structure};
    let alpha = match &p.scene.structure {
        Structure::Rigid(b) => b.alpha,
        s => panic!("{s:?}"),
    };
    let x = p.coords[0].1;
    match &p.scene.device {
        Device::Sequential { .. } => ("seq", alpha, 0.0, x),
        Device::Mechanistic(c) => match c.stiffness {
            ClutchStiffness::KTheta(k) => ("mech", alpha, k, x),
            s => panic!("{s:?}"),
        },
        d => panic!("{d:?}"),
    }
}

/// Sequential: 10α + x (α = 0.2 overturns at x = 4). Mechanistic kθ = 1: half of that
/// (overturns at α = 0.1, x = 6; 3.0 at α = 0.2, x = 4; 6.0 at α = 0.2, x = 6). kθ = 3: 0.8
/// of it (fails at α = 0.1, x = 2; overturns at α = 0.2, x = 4; did not run at α = 0.2, x = 6).
fn grid_results() -> SweepResults {
    let study = Study::from_ron_str(GRID, "grid.ron").unwrap();
    synthetic(&study, |p| {
        let (dev, alpha, k, x) = kind(p);
        let seq = 10.0 * alpha + x;
        let a2 = alpha == 0.2;
        match (dev, k, a2, x) {
            ("seq", _, true, 4.0) => Fake::Overturned,
            ("seq", ..) => Fake::Peak(seq),
            ("mech", 1.0, false, 6.0) => Fake::Overturned,
            ("mech", 1.0, true, 4.0) => Fake::Peak(3.0),
            ("mech", 1.0, true, 6.0) => Fake::Peak(6.0),
            ("mech", 1.0, ..) => Fake::Peak(seq / 2.0),
            ("mech", 3.0, false, 2.0) => Fake::Failed,
            ("mech", 3.0, true, 4.0) => Fake::Overturned,
            ("mech", 3.0, true, 6.0) => Fake::NotRun,
            ("mech", 3.0, ..) => Fake::Peak(0.8 * seq),
            other => panic!("{other:?}"),
        }
    })
}

fn sel(text: &str) -> Selector {
    Selector::parse(text).unwrap()
}

fn close(a: Option<f64>, b: f64) -> bool {
    a.is_some_and(|a| (a - b).abs() < 1e-12)
}

#[test]
fn groups_carry_their_parameters_and_outcomes() {
    let results = grid_results();
    let spectra = report::spectra(&results);
    assert_eq!(spectra.len(), 6, "2 α × (sequential + 2 kθ)");
    let s = spectra
        .iter()
        .find(|s| s.label == "mechanistic kθ=3 α=0.2")
        .expect("labels list the varying device parameters first");
    assert_eq!(s.group.device, DeviceKind::Mechanistic);
    assert_eq!(s.group.variant, 1);
    assert_eq!(s.group.setting("k_theta").unwrap().value, 3.0);
    assert_eq!(s.group.setting("alpha").unwrap().value, 0.2);
    assert_eq!(s.group.setting("alpha").unwrap().text, "0.2");
    assert_eq!(s.group.setting("sigma").unwrap().value, 0.5);
    assert!(!s.group.setting("sigma").unwrap().varies);
    assert!(
        s.group.setting("frequency").is_none(),
        "the spectrum axis is free"
    );
    // x = 6 did not run: two points, the overturned one marked as such.
    assert_eq!(s.xs, vec![2.0, 4.0]);
    assert_eq!(s.states, vec![PointState::Survived, PointState::Overturned]);
    for (&i, &x) in s.outcomes.iter().zip(&s.xs) {
        let o = &results.outcomes[i];
        assert_eq!(o.point.coords[0].1, x);
        assert_eq!(o.point.group, "mechanistic kθ=3 α=0.2");
    }
}

#[test]
fn a_grid_side_pairs_each_member_with_the_same_structure_and_hand_computed_statistics() {
    let results = grid_results();
    let spectra = report::spectra(&results);
    let pairs = compare::compare_spectra(
        &spectra,
        Quantity::PeakRotationRatio,
        &sel("sequential"),
        &sel("mechanistic"),
    )
    .unwrap();
    // 2 α × 2 kθ: never sequential at α = 0.1 against mechanistic at α = 0.2.
    assert_eq!(pairs.len(), 4);
    for p in &pairs {
        assert_eq!(
            p.a_group.setting("alpha").unwrap().value,
            p.b_group.setting("alpha").unwrap().value
        );
    }
    let find = |alpha: f64, k: f64| {
        pairs
            .iter()
            .find(|p| {
                p.b_group.setting("alpha").unwrap().value == alpha
                    && p.b_group.setting("k_theta").unwrap().value == k
            })
            .unwrap()
            .stats
            .clone()
    };
    // α = 0.1, kθ = 1: A = 3, 5, 7; B = 1.5, 2.5, overturned.
    let s = find(0.1, 1.0);
    assert_eq!((s.points, s.ratio_points), (3, 2));
    assert!(close(s.mean_ratio, 0.5) && close(s.median_ratio, 0.5));
    assert!(close(s.peak_a, 5.0) && close(s.peak_b, 2.5) && close(s.peak_ratio, 0.5));
    assert_eq!((s.a_overturns_b_survives, s.b_overturns_a_survives), (0, 1));
    // α = 0.1, kθ = 3: B fails at x = 2 (counted apart), else 0.8 of A.
    let s = find(0.1, 3.0);
    assert_eq!((s.ratio_points, s.failed, s.not_run), (2, 1, 0));
    assert!(close(s.mean_ratio, 0.8) && close(s.min_ratio, 0.8) && close(s.max_ratio, 0.8));
    // α = 0.2, kθ = 1: A = 4, overturned, 8; B = 2, 3, 6: ratios 0.5 and 0.75.
    let s = find(0.2, 1.0);
    assert_eq!(s.a_overturns_b_survives, 1);
    assert!(close(s.mean_ratio, 0.625) && close(s.median_ratio, 0.625));
    assert!(close(s.min_ratio, 0.5) && close(s.max_ratio, 0.75));
    assert!(close(s.peak_ratio, 6.0 / 8.0), "{:?}", s.peak_ratio);
    // α = 0.2, kθ = 3: both overturn at x = 4, B did not run at x = 6.
    let s = find(0.2, 3.0);
    assert_eq!((s.both_overturn, s.not_run, s.ratio_points), (1, 1, 1));
    assert!(close(s.mean_ratio, 0.8));
    assert_eq!(compare::median(&[3.0, 1.0, 10.0, 2.0]), Some(2.5));

    // A selector fixes a grid value; the other side stays paired by α.
    let pairs = compare::compare_spectra(
        &spectra,
        Quantity::PeakRotationRatio,
        &sel("sequential(alpha: 0.2)"),
        &sel("mechanistic(k_theta: 3.0)"),
    )
    .unwrap();
    assert_eq!(pairs.len(), 1);
    assert_eq!(pairs[0].b, "mechanistic kθ=3 α=0.2");
    // Two members of one grid against each other: matched on α, kθ left free.
    let pairs = compare::compare_spectra(
        &spectra,
        Quantity::PeakRotationRatio,
        &sel("mechanistic(k_theta: 1)"),
        &sel("mechanistic(k_theta: 3)"),
    )
    .unwrap();
    assert_eq!(pairs.len(), 2);
}

#[test]
fn selectors_that_match_nothing_say_what_there_is() {
    let results = grid_results();
    let spectra = report::spectra(&results);
    let q = Quantity::PeakRotationRatio;
    let err = |a: &str, b: &str| {
        compare::compare_spectra(&spectra, q, &sel(a), &sel(b))
            .unwrap_err()
            .to_string()
    };
    let e = err("sequential", "mechanistic(k_theta: 5.0)");
    assert!(e.contains("k_theta (kθ): 1, 3"), "{e}");
    assert!(e.contains("alpha (α): 0.1, 0.2"), "{e}");
    assert!(e.lines().count() <= 4, "a few lines, not every group: {e}");
    let e = err("sequential", "mechanistic(plya: 0.005)");
    assert!(
        e.contains("`plya` is not a parameter") && e.contains("play"),
        "{e}"
    );
    // A parameter left at its single default value is listed when named.
    let e = err("sequential", "mechanistic(play: 0.005)");
    assert!(e.contains("play (up): 0"), "{e}");
    let e = err("inerter", "mechanistic");
    assert!(e.contains("sequential, mechanistic"), "{e}");
    assert!(Selector::parse("mechanistic(k_theta: 3").is_err());
}

#[test]
fn labels_tell_near_equal_values_apart() {
    let study = |devices: &str| {
        Study::from_ron_str(
            &GRID.replace(
                "devices: [sequential(sigma: 0.5), mechanistic(sigma: 0.5, k_theta: [1.0, 3.0])]",
                devices,
            ),
            "labels.ron",
        )
        .unwrap()
    };
    let groups = |s: &Study| {
        let mut g: Vec<String> = s.expand().unwrap().into_iter().map(|p| p.group).collect();
        g.dedup();
        g
    };
    let s = study(
        "devices: [mechanistic(sigma: 0.5, play: (from: 0.00001, to: 0.0001, steps: 5, log: true))]",
    );
    let labels: Vec<String> = groups(&s)
        .into_iter()
        .filter(|g| g.ends_with("α=0.1"))
        .collect();
    assert_eq!(
        labels,
        [
            "mechanistic up=1e-5 α=0.1",
            "mechanistic up=1.778e-5 α=0.1",
            "mechanistic up=3.162e-5 α=0.1",
            "mechanistic up=5.623e-5 α=0.1",
            "mechanistic up=1e-4 α=0.1",
        ]
    );
    let results = synthetic(&s, |_| Fake::Peak(1.0));
    let spectra = report::spectra(&results);
    assert_eq!(spectra.len(), 10, "5 plays × 2 α, none merged");
    assert_eq!(spectra[3].group.setting("play").unwrap().text, "5.623e-5");
    assert!(spectra.iter().all(|s| s.xs.len() == 3));
    let s = study("devices: [mechanistic(sigma: 0.5, k_theta: [1.0, 1.00000001])]");
    let labels = groups(&s);
    assert!(
        labels.contains(&"mechanistic kθ=1 α=0.1".to_string()),
        "{labels:?}"
    );
    assert!(
        labels.contains(&"mechanistic kθ=1.00000001 α=0.1".to_string()),
        "{labels:?}"
    );
    // A value listed twice would run the same scenes twice under one label.
    let e = Study::from_ron_str(
        &GRID.replace("k_theta: [1.0, 3.0]", "k_theta: [1.0, 1.0]"),
        "dup.ron",
    )
    .unwrap_err();
    assert!(e.to_string().contains("given twice"), "{e}");
}

#[test]
fn record_pairs_stay_within_a_record_and_suites_have_hand_computed_mean_and_cv() {
    let text = r#"(
        version: 1,
        name: "suite",
        structure: flexible(r0: 10.0, alpha: 0.2, xi: 0.02, omega_n: [4.0, 8.0]),
        devices: [sequential(sigma: 0.5), mechanistic(sigma: 0.5, xi_theta: 0.02)],
        excitation: record(names: ["landers", "northridge"], scale: 0.01),
        spectrum: omega_n,
        duration: 0.2,
    )"#;
    let study = Study::from_ron_str(text, "suite.ron").unwrap();
    // landers: sequential 1, 2 over ωn; northridge: 3, overturned. Mechanistic: 0.9× sequential.
    let results = synthetic(&study, |p| {
        let rocklab::scene::Excitation::Record { name, .. } = &p.scene.excitation else {
            panic!()
        };
        let omega = p.coords[0].1;
        let seq = match (name.as_str(), omega) {
            ("landers", 4.0) => 1.0,
            ("landers", _) => 2.0,
            ("northridge", 4.0) => 3.0,
            _ => return Fake::Overturned,
        };
        match p.scene.device.name() {
            "sequential" => Fake::Peak(seq),
            _ => Fake::Peak(0.9 * seq),
        }
    });
    let spectra = report::spectra(&results);
    let pairs = compare::compare_spectra(
        &spectra,
        Quantity::PeakRotationRatio,
        &sel("sequential"),
        &sel("mechanistic"),
    )
    .unwrap();
    assert_eq!(pairs.len(), 2);
    for p in &pairs {
        assert_eq!(p.a_group.record(), p.b_group.record());
        assert!(close(p.stats.mean_ratio, 0.9));
    }
    assert_eq!(pairs[0].a, "sequential · landers");
    // The workbench's default pair: sequential vs mechanistic of the same record.
    let rows: Vec<&report::Spectrum> = spectra.iter().collect();
    let (a, b) = compare::default_pair(&rows).unwrap();
    assert_eq!(rows[a].group.device, DeviceKind::Sequential);
    assert_eq!(rows[b].group.device, DeviceKind::Mechanistic);
    assert_eq!(rows[a].group.record(), rows[b].group.record());

    let suites = compare::suite_spectra(&results, &spectra);
    let seq = suites.iter().find(|s| s.label == "sequential").unwrap();
    assert_eq!(seq.records, ["landers", "northridge"]);
    assert_eq!(seq.xs, vec![4.0, 8.0]);
    // ωn = 4: records 1 and 3: mean 2, sample std √2, CV √2/2. ωn = 8: only landers (2).
    assert!(close(seq.mean[0], 2.0) && close(seq.cv[0], 2f64.sqrt() / 2.0));
    assert!(close(seq.mean[1], 2.0) && seq.cv[1].is_none());
    assert_eq!(seq.overturned, vec![0, 1]);
    let suite_pairs = compare::compare_suites(
        &suites,
        Quantity::PeakRotationRatio,
        &sel("sequential"),
        &sel("mechanistic"),
    )
    .unwrap();
    assert_eq!(suite_pairs.len(), 1);
    assert!(close(suite_pairs[0].stats.mean_ratio, 0.9));
    assert!(close(suite_pairs[0].mean_cv_a, 2f64.sqrt() / 2.0));
    assert_eq!(
        (suite_pairs[0].overturned_a, suite_pairs[0].overturned_b),
        (1, 1)
    );
    let summary = report::summary(&results);
    assert!(summary.contains("record suite (2 records"), "{summary}");
}

fn map(device: DeviceKind, cells: Vec<Vec<Option<bool>>>) -> OverturningMap {
    OverturningMap {
        label: device.name().into(),
        group: Group {
            device,
            variant: 0,
            device_label: device.name().into(),
            settings: vec![],
        },
        x_axis: "ωg/p".into(),
        y_axis: "A/g".into(),
        xs: vec![1.0, 2.0, 3.0],
        ys: vec![0.5, 1.0],
        outcomes: vec![vec![None; 3]; 2],
        cells,
    }
}

#[test]
fn maps_side_by_side_mark_where_only_one_variant_survives() {
    let a = map(
        DeviceKind::None,
        vec![
            vec![Some(false), Some(true), Some(false)],
            vec![Some(true), Some(true), None],
        ],
    );
    let b = map(
        DeviceKind::Mechanistic,
        vec![
            vec![Some(false), Some(false), Some(true)],
            vec![Some(true), Some(false), Some(false)],
        ],
    );
    let m = compare::compare_map_pair(&a, &b);
    use MapCell::*;
    assert_eq!(
        m.cells,
        vec![
            vec![BothSurvive, OnlyBSurvives, OnlyASurvives],
            vec![BothOverturn, OnlyBSurvives, Missing],
        ]
    );
    assert_eq!(m.count(OnlyBSurvives), 2);
    let text = compare::map_text(&m);
    // Largest y on top.
    let rows: Vec<&str> = text
        .lines()
        .filter(|l| l.contains('█') || l.contains('·'))
        .collect();
    assert!(
        rows[1].ends_with("█B?") && rows[2].ends_with("·BA"),
        "{text}"
    );
}

#[test]
fn compare_json_reports_the_pairs_of_a_results_file() {
    let dir = tempfile::tempdir().unwrap();
    report::save_results(&dir.path().join("results.json"), &grid_results()).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rocklab"))
        .args(["compare", dir.path().to_str().unwrap()])
        .args([
            "--a",
            "sequential",
            "--b",
            "mechanistic(k_theta: 1.0)",
            "--json",
        ])
        .output()
        .unwrap();
    let json = crate::util::json_of(out);
    let pairs = json["pairs"].as_array().unwrap();
    assert_eq!(pairs.len(), 2);
    // One side a grid is not the case here: study order (α = 0.1 first).
    assert_eq!(pairs[0]["b"], "mechanistic kθ=1 α=0.1");
    assert_eq!(pairs[0]["stats"]["b_overturns_a_survives"], 1);
    assert_eq!(pairs[1]["stats"]["a_overturns_b_survives"], 1);
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rocklab"))
        .args(["compare", dir.path().to_str().unwrap()])
        .args(["--a", "sequential", "--b", "mechanistic(k_theta: 2.0)"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("k_theta (kθ): 1, 3"), "{err}");
    // plot --select refuses the same selector with a non-zero exit (issue 42, item 3), and
    // draws nothing rather than a figure short of what was asked.
    let figs = dir.path().join("figs");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rocklab"))
        .args(["plot", dir.path().to_str().unwrap(), "--svg"])
        .arg(&figs)
        .args(["--select", "mechanistic(k_theta: 2.0)"])
        .output()
        .unwrap();
    assert!(!out.status.success(), "plot --select exited 0");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("k_theta (kθ): 1, 3"), "{err}");
}

/// `compare` without `--a/--b` pairs as the workbench does (sequential vs mechanistic here)
/// and starts with what it compares, no empty line; A and B the same grid compare its first
/// member with each other one in every situation, with the hand-computed ratios.
#[test]
fn compare_defaults_as_the_workbench_and_a_grid_against_its_first_member() {
    let dir = tempfile::tempdir().unwrap();
    report::save_results(&dir.path().join("results.json"), &grid_results()).unwrap();
    let compare = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_rocklab"))
            .args(["compare", dir.path().to_str().unwrap()])
            .args(args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr).to_string();
        assert!(out.status.success(), "{err}");
        String::from_utf8(out.stdout).unwrap()
    };
    let text = compare(&[]);
    assert!(
        text.starts_with("A = sequential, B = mechanistic\n"),
        "{text}"
    );
    assert_eq!(text, compare(&["--a", "sequential", "--b", "mechanistic"]));

    let results = grid_results();
    let spectra = report::spectra(&results);
    let pairs = compare::compare_spectra(
        &spectra,
        Quantity::PeakRotationRatio,
        &sel("mechanistic"),
        &sel("mechanistic"),
    )
    .unwrap();
    // Per α, kθ = 1 (the first) against kθ = 3: 0.8 / 0.5 where both survive.
    let names: Vec<(&str, &str)> = pairs.iter().map(|p| (p.a.as_str(), p.b.as_str())).collect();
    assert_eq!(
        names,
        [
            ("mechanistic kθ=1 α=0.1", "mechanistic kθ=3 α=0.1"),
            ("mechanistic kθ=1 α=0.2", "mechanistic kθ=3 α=0.2"),
        ]
    );
    assert!(
        close(pairs[0].stats.median_ratio, 1.6),
        "{:?}",
        pairs[0].stats
    );
    let named = rocklab::report::naming::pair_names(&names);
    assert_eq!(named.shared, "A kθ=1 · B kθ=3 · mechanistic");
    assert_eq!(named.names, ["α=0.1", "α=0.2"]);
    // A single variant against itself says so.
    let one = GRID.replace("k_theta: [1.0, 3.0]", "k_theta: 1.0");
    {
        let study = Study::from_ron_str(&one, "one.ron").unwrap();
        let results = synthetic(&study, |_| Fake::Peak(1.0));
        let spectra = report::spectra(&results);
        let err = compare::compare_spectra(
            &spectra,
            Quantity::PeakRotationRatio,
            &sel("mechanistic"),
            &sel("mechanistic"),
        )
        .unwrap_err();
        assert!(err.0.contains("same single variant"), "{}", err.0);
    }
}

/// Issue 42, item 3: a selector may name a map's own axes (`amplitude`, `frequency`), which
/// pick its rows and columns; a value not on the axis is refused with the axis's values.
#[test]
fn map_selectors_pick_rows_and_columns_of_the_maps_axes() {
    let a = map(
        DeviceKind::None,
        vec![
            vec![Some(false), Some(true), Some(false)],
            vec![Some(true), Some(true), None],
        ],
    );
    let b = map(
        DeviceKind::Mechanistic,
        vec![
            vec![Some(false), Some(false), Some(true)],
            vec![Some(true), Some(false), Some(false)],
        ],
    );
    let maps = [a, b];
    let sel = |t: &str| Selector::parse(t).unwrap();
    let m =
        compare::compare_maps(&maps, &sel("bare"), &sel("mechanistic(amplitude: 1.0)")).unwrap();
    assert_eq!(m.len(), 1);
    assert_eq!(m[0].ys, vec![1.0]);
    use MapCell::*;
    assert_eq!(m[0].cells, vec![vec![BothOverturn, OnlyBSurvives, Missing]]);
    let m = compare::compare_maps(
        &maps,
        &sel("bare(frequency: [1.0, 3.0])"),
        &sel("mechanistic"),
    )
    .unwrap();
    assert_eq!(m[0].xs, vec![1.0, 3.0]);
    assert_eq!(m[0].ys, vec![0.5, 1.0]);
    assert_eq!(m[0].cells[0], vec![BothSurvive, OnlyASurvives]);
    let e = compare::compare_maps(&maps, &sel("bare"), &sel("mechanistic(amplitude: 0.7)"))
        .unwrap_err();
    assert!(e.0.contains("amplitude") && e.0.contains("0.5, 1"), "{e}");
    // A parameter that is neither a setting nor an axis is still refused.
    assert!(compare::compare_maps(&maps, &sel("bare"), &sel("mechanistic(k_theta: 1)")).is_err());
}
