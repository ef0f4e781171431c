//! Study files: every shipped study round-trips (RON → study → RON), expansion follows the
//! grids, and each kind of bad input gets a message naming file, line, column, field and a
//! hint (snapshots in the top-level `snapshots/` directory).

use rocklab::scene::{ClutchStiffness, Damping, Device, Structure};
use rocklab::study::{Study, StudyError};
use std::path::Path;

fn shipped() -> Vec<(String, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies");
    let mut out: Vec<(String, String)> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().to_string();
            (name, std::fs::read_to_string(&p).unwrap())
        })
        .collect();
    out.sort();
    out
}

#[test]
fn every_shipped_study_round_trips_and_validates() {
    let studies = shipped();
    assert!(studies.len() >= 9, "{} studies", studies.len());
    for (name, text) in studies {
        let study = Study::parse_ron(&text, &name).unwrap_or_else(|e| panic!("{e}"));
        let again = study.to_ron_string();
        let back =
            Study::parse_ron(&again, "round-trip").unwrap_or_else(|e| panic!("{e}\n{again}"));
        assert_eq!(back, study, "{name} does not round-trip:\n{again}");
        assert_eq!(back.hash(), study.hash());
        let valid = Study::from_ron_str(&text, &name).unwrap_or_else(|e| panic!("{e}"));
        assert!(!valid.expand().unwrap().is_empty());
    }
}

#[test]
fn the_builtin_default_is_the_shipped_default() {
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/default.ron"))
            .unwrap();
    assert_eq!(
        Study::builtin_default(),
        Study::from_ron_str(&text, "default.ron").unwrap()
    );
}

#[test]
fn a_clutch_grid_expands_to_the_cartesian_product_with_the_frequency_fastest() {
    let text = r#"(
        version: 1,
        name: "grid",
        structure: rigid(p: 2.5, alpha: [0.15, 0.2]),
        devices: [
            none,
            mechanistic(sigma: 0.5, k_theta: [1.0, 10.0], xi_theta: [0.0, 0.02, 0.2], play: 0.001),
        ],
        excitation: pulse(shape: sine, amplitude: alpha_ratio(1.5),
                          frequency: ratio((from: 2.0, to: 8.0, steps: 4))),
        duration: 5.0,
    )"#;
    let study = Study::from_ron_str(text, "grid.ron").unwrap();
    let points = study.expand().unwrap();
    // bare: 2 α × 4 ωg/p; mechanistic: 2 α × 2 kθ × 3 ξθ × 4 ωg/p.
    assert_eq!(points.len(), 2 * 4 + 2 * 2 * 3 * 4);
    for (i, p) in points.iter().enumerate() {
        assert_eq!(p.index, i);
        assert_eq!(p.coords[0].0, "ωg/p");
        // p given, size derived: the scene's p is the requested one.
        assert!((p.scene.structure.p() - 2.5).abs() < 1e-12);
    }
    assert_eq!(
        points
            .iter()
            .map(|p| p.coords[0].1)
            .take(5)
            .collect::<Vec<_>>(),
        [2.0, 4.0, 6.0, 8.0, 2.0]
    );
    assert_eq!(points[0].group, "bare α=0.15");
    let last = points.last().unwrap();
    assert_eq!(last.group, "mechanistic kθ=10 ξθ=0.2 α=0.2");
    match &last.scene.device {
        Device::Mechanistic(c) => {
            assert_eq!(c.stiffness, ClutchStiffness::KTheta(10.0));
            assert_eq!(c.damping, Damping::XiTheta(0.2));
            assert_eq!(c.play, 0.001);
        }
        d => panic!("{d:?}"),
    }
    match &last.scene.structure {
        Structure::Rigid(b) => assert_eq!(b.alpha, 0.2),
        s => panic!("{s:?}"),
    }
    // Keys identify scenes: all distinct, stable across expansions.
    let keys: std::collections::HashSet<_> = points.iter().map(|p| &p.key).collect();
    assert_eq!(keys.len(), points.len());
    assert_eq!(study.expand().unwrap()[7].key, points[7].key);
}

fn error_of(text: &str) -> StudyError {
    match Study::from_ron_str(text, "bad.ron") {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e,
    }
}

const GOOD: &str = r#"(
    version: 1,
    name: "bad",
    structure: rigid(p: 2.0, alpha: 0.1745),
    devices: [
        none,
        mechanistic(sigma: 0.5, cbar: 1.0),
    ],
    excitation: pulse(
        shape: sine,
        amplitude: alpha_ratio(1.5),
        frequency: ratio((from: 1.0, to: 10.0, steps: 10)),
    ),
    duration: 10.0,
)"#;

/// The bad-input cases: (snapshot name, replace this, by this).
const CASES: &[(&str, &str, &str)] = &[
    ("unknown_field", "alpha: 0.1745", "alpah: 0.1745"),
    ("unknown_device", "none,", "bogus,"),
    (
        "unknown_clutch_field",
        "cbar: 1.0)",
        "cbar: 1.0, stifness: 3.0)",
    ),
    ("missing_duration", "    duration: 10.0,\n", ""),
    ("bad_range", "steps: 10", "steps: 1"),
    ("huge_range", "steps: 10", "steps: 1000000000000"),
    ("range_typo", "steps: 10", "stesp: 10"),
    ("negative_sigma", "sigma: 0.5", "sigma: [0.5, -0.5]"),
    ("alpha_too_large", "alpha: 0.1745", "alpha: 2.0"),
    ("size_and_p", "rigid(p: 2.0,", "rigid(p: 2.0, size: 1.0,"),
    (
        "cbar_and_xi_theta",
        "cbar: 1.0)",
        "cbar: 1.0, xi_theta: 0.02)",
    ),
    ("negative_play", "cbar: 1.0)", "cbar: 1.0, play: -0.001)"),
    ("zero_frequency", "from: 1.0", "from: 0.0"),
    ("version", "version: 1", "version: 2"),
    (
        "no_devices",
        "none,\n        mechanistic(sigma: 0.5, cbar: 1.0),",
        "",
    ),
    (
        "spectrum_axis_missing",
        "duration: 10.0,",
        "duration: 10.0, spectrum: omega_n,",
    ),
    (
        "map_same_axes",
        "duration: 10.0,",
        "duration: 10.0, map: (x: frequency, y: frequency),",
    ),
    ("rtol", "duration: 10.0,", "duration: 10.0, rtol: 0.5,"),
    ("same_label", "none,", "mechanistic(sigma: 0.2),"),
    ("not_ron", "devices: [", "devices: ["),
];

#[test]
fn bad_inputs_name_file_line_column_field_and_hint() {
    let mut report = String::new();
    for (name, from, to) in CASES {
        assert!(GOOD.contains(from), "{name}");
        let mut text = GOOD.replacen(from, to, 1);
        if *name == "not_ron" {
            text = text.replacen("name: \"bad\"", "name: bad\"", 1);
        }
        let e = error_of(&text);
        assert!(
            e.line.is_some() && e.column.is_some(),
            "{name}: no position in {e}"
        );
        assert!(
            e.field.is_some() || *name == "not_ron",
            "{name}: no field in {e}"
        );
        assert!(e.hint.is_some(), "{name}: no hint in {e}");
        report.push_str(&format!("{name}:\n  {e}\n"));
    }
    insta::with_settings!({snapshot_path => "../snapshots", prepend_module_to_snapshot => false}, {
        insta::assert_snapshot!("study_errors", report);
    });
}

#[test]
fn a_physically_invalid_value_points_at_its_line() {
    let text = GOOD.replacen("sigma: 0.5", "sigma: -0.5", 1);
    let e = error_of(&text);
    assert_eq!(e.field.as_deref(), Some("devices[1].sigma"));
    let line = text.lines().nth(e.line.unwrap() - 1).unwrap();
    assert!(line.contains("sigma: -0.5"), "line {:?}: {line}", e.line);
    assert_eq!(&line[e.column.unwrap() - 1..][..5], "sigma");
}

#[test]
fn unknown_field_position_is_the_field() {
    let text = GOOD.replacen("alpha: 0.1745", "alpah: 0.1745", 1);
    let e = error_of(&text);
    assert_eq!(e.field.as_deref(), Some("alpah"));
    let line = text.lines().nth(e.line.unwrap() - 1).unwrap();
    assert!(line.contains("alpah"), "{line}");
}

#[test]
fn a_missing_file_is_an_error_not_a_panic() {
    let e = Study::load(Path::new("/nonexistent/study.ron")).unwrap_err();
    assert!(e.to_string().starts_with("/nonexistent/study.ron: "), "{e}");
}

#[test]
fn flexible_omega_ratio_becomes_omega_n_and_records_become_scenes() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/fig19_damping.ron"),
    )
    .unwrap();
    let points = Study::from_ron_str(&text, "fig19_damping.ron")
        .unwrap()
        .expand()
        .unwrap();
    assert_eq!(points.len(), 3 * 37);
    for p in &points {
        match &p.scene.structure {
            // ωn/p = 8 with p = √(g/R0).
            Structure::Flexible(f) => {
                assert!((f.omega_n - 8.0 * (9.81f64 / 10.0).sqrt()).abs() < 1e-12);
                assert!((p.scene.structure.p() * 8.0 - f.omega_n).abs() < 1e-12);
            }
            s => panic!("{s:?}"),
        }
    }
    assert_eq!(points[0].group, "mechanistic ξθ=0");
    assert_eq!(points[37].group, "mechanistic ξθ=0.02");

    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/fig24_records.ron"),
    )
    .unwrap();
    let points = Study::from_ron_str(&text, "fig24_records.ron")
        .unwrap()
        .expand()
        .unwrap();
    // 3 devices × 40 ωn × 5 records; ωn is the spectrum axis.
    assert_eq!(points.len(), 600);
    assert!(points.iter().all(|p| p.coords[0].0 == "ωn"));
    assert_eq!(points[0].group, "bare · landers");
    assert_eq!(points[0].coords[0].1, 2.0);
    assert!((points[39 * 5].coords[0].1 - 29.3).abs() < 1e-12);
    match &points[1].scene.excitation {
        rocklab::scene::Excitation::Record { name, .. } => assert_eq!(name, "northridge"),
        e => panic!("{e:?}"),
    }
}

/// Issue 29: a name in front of a value is accepted only where the schema has that name
/// (closed per field), a key is never given twice (a range's included), and a raw string
/// holding a quote does not blind the reading. Each was read as the plain value before.
#[test]
fn a_wrapper_or_key_that_means_nothing_is_refused_where_it_is_written() {
    let mech = "mechanistic(sigma: 0.5, cbar: 1.0)";
    for (from, to, line, name) in [
        (mech, "mechanistic(sigma: xi(0.5), cbar: 1.0)", 7, "xi"),
        ("alpha_ratio(1.5)", "alpha_ratio(g(1.5))", 11, "g"),
        (
            mech,
            "mechanistic(sigma: 0.5, cbar: 1.0, play: sine(0.001))",
            7,
            "sine",
        ),
        ("alpha: 0.1745", "alpha: p(0.2)", 4, "p"),
        (
            "ratio((from: 1.0, to: 10.0, steps: 10))",
            "ratio(ratio(4.0))",
            12,
            "ratio",
        ),
        (
            "ratio((from: 1.0, to: 10.0, steps: 10))",
            "ratio((from: 1.0, steps: 3, to: 12.0, from: 2.0))",
            12,
            "from",
        ),
    ] {
        assert!(GOOD.contains(from), "{from}");
        let e = error_of(&GOOD.replacen(from, to, 1));
        assert_eq!(e.line, Some(line), "{to}: {e}");
        let text = e.to_string();
        assert!(text.contains(&format!("`{name}")), "{to}: {text}");
        assert!(e.hint.is_some() && e.field.is_some(), "{to}: {text}");
        let column = e.column.unwrap();
        let written = GOOD.replacen(from, to, 1);
        let at_line = written.lines().nth(line - 1).unwrap();
        assert!(
            at_line[column - 1..].starts_with(name),
            "{to}: column {column} of `{at_line}`"
        );
    }
    // A raw string with a quote in it, then a wrong name: still found.
    let text = GOOD.replacen(
        "name: \"bad\",",
        "name: \"bad\", description: r#\"tricky \" quote\"#,",
        1,
    );
    assert!(Study::from_ron_str(&text, "ok.ron").is_ok());
    let e = error_of(&text.replacen("alpha_ratio(1.5)", "alpha_ratio(foo(1.5))", 1));
    assert!(e.to_string().contains("`foo("), "{e}");
    // The names that do mean something, and `Some`, stay accepted.
    for ok in [
        GOOD.replacen("alpha: 0.1745", "alpha: deg(10)", 1),
        GOOD.replacen("cbar: 1.0", "cbar: Some(1.0)", 1),
        GOOD.replacen("cbar: 1.0)", "cbar: 1.0, label: Some(\"m\"))", 1),
    ] {
        Study::from_ron_str(&ok, "ok.ron").unwrap_or_else(|e| panic!("{e}\n{ok}"));
    }
}

/// Issue 42, item 10: the bare structure is `none` in a study and `bare` in results, labels
/// and selectors; a study takes either name for it.
#[test]
fn a_study_takes_bare_for_the_bare_structure_as_results_name_it() {
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/default.ron"))
            .unwrap();
    assert!(
        text.contains("none"),
        "default.ron names the bare structure `none`"
    );
    let bare = text.replacen("none", "bare", 1);
    let (a, b) = (
        Study::from_ron_str(&text, "default.ron").unwrap(),
        Study::from_ron_str(&bare, "bare.ron").unwrap(),
    );
    assert_eq!(a.devices, b.devices);
}
