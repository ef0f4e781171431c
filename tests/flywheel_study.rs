//! A single inerter behind a flywheel, written in a study (the paper's Fig. 14 "inerter
//! c̄ = 1"): it reads strictly, labels its groups, and runs exactly the scene `rocklab
//! simulate --device inerter --coupling flywheel` runs.

use crate::cli_simulate::with_value;
use crate::util::{rocklab_json, run_into};
use rocklab::study::Study;

const STUDY: &str = r#"// Fig. 14's pair: an inerter attached rigidly, and one behind a flywheel (c̄ = 1).
(
    version: 1,
    name: "flywheel",
    structure: rigid(p: 2.0, alpha: 0.17453292519943295),
    devices: [
        inerter(sigma: 0.5),
        inerter(sigma: 0.5, coupling: flywheel(cbar: 1.0)),
    ],
    excitation: pulse(shape: sine, amplitude: alpha_ratio(1.5), frequency: ratio([2.0, 4.0, 8.0])),
    quantities: [peak_rotation_ratio, peak_abs_acceleration],
    duration: 10.0,
)
"#;

#[test]
fn a_flywheel_inerter_study_runs_the_scenes_simulate_runs() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("flywheel.ron");
    std::fs::write(&path, STUDY).unwrap();
    let out = dir.path().join("out");
    let o = run_into(path.to_str().unwrap(), &out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let results = rocklab::report::load_results(&out.join("results.json")).unwrap();
    let flywheel: Vec<_> = results
        .outcomes
        .iter()
        .filter(|o| o.point.group == "flywheel inerter")
        .collect();
    assert_eq!(
        flywheel.len(),
        3,
        "one group per coupling, the flywheel's labelled"
    );
    for o in flywheel {
        // The paper's "inerter with dissipation": the clutch's spring, c̄ = 1 s⁻¹.
        assert_eq!(
            o.point.scene.device,
            rocklab::presets::inerter_with_dissipation()
        );
        let ratio = o.point.coord("ωg/p").unwrap().to_string();
        let sim = rocklab_json(&with_value(
            "--frequency-ratio",
            &ratio,
            &[
                "--device",
                "inerter",
                "--coupling",
                "flywheel",
                "--sigma",
                "0.5",
                "--cbar",
                "1",
                "--stop-when-settled",
                "--json",
            ],
        ));
        let r = o.result.as_ref().unwrap();
        // To the last bit: the same scene, integrated the same way.
        assert_eq!(
            sim["peak_rotation_ratio"].as_f64(),
            Some(r.peak_rotation_ratio)
        );
        assert_eq!(sim["peak_rotation"].as_f64(), Some(r.peaks.rotation));
        assert_eq!(
            sim["peak_abs_acceleration_g"].as_f64(),
            Some(r.peaks.abs_acceleration_g)
        );
        assert_eq!(sim["impacts"].as_u64(), Some(r.counters.impacts));
        assert_eq!(sim["end_time"].as_f64(), Some(r.end_time));
        assert_eq!(sim["steps"].as_u64(), Some(r.stats.steps));
    }
    // The flywheel changes the response (else the comparison above proves little).
    let peak = |group: &str| {
        let o = results
            .outcomes
            .iter()
            .find(|o| o.point.group == group && o.point.coord("ωg/p") == Some(4.0));
        o.unwrap().result.as_ref().unwrap().peak_rotation_ratio
    };
    assert_ne!(peak("inerter"), peak("flywheel inerter"));
    // The study kept beside the results reads back to the same study.
    let kept = Study::load(&out.join("study.ron")).unwrap();
    assert_eq!(kept, Study::from_ron_str(STUDY, "flywheel.ron").unwrap());
}

#[test]
fn a_flywheel_grid_names_its_parameters_in_the_labels() {
    let text = STUDY.replace(
        "flywheel(cbar: 1.0)",
        "flywheel(k_theta: 100.0, cbar: [0.5, 1.0])",
    );
    let points = Study::from_ron_str(&text, "grid.ron")
        .unwrap()
        .expand()
        .unwrap();
    let groups: Vec<&str> = points.iter().map(|p| p.group.as_str()).collect();
    assert_eq!(groups.len(), 3 + 2 * 3);
    assert!(groups.contains(&"flywheel inerter c̄=0.5"), "{groups:?}");
    assert!(groups.contains(&"flywheel inerter c̄=1"), "{groups:?}");
    let stiffness = |p: &rocklab::study::ScenePoint| match &p.scene.device {
        rocklab::scene::Device::Inerter {
            coupling: rocklab::scene::Coupling::Flywheel { stiffness, .. },
            ..
        } => Some(*stiffness),
        _ => None,
    };
    assert!(
        points
            .iter()
            .filter_map(stiffness)
            .all(|s| s == rocklab::scene::ClutchStiffness::KTheta(100.0))
    );
}

#[test]
fn a_bad_flywheel_field_is_refused_where_it_is_written() {
    // (replacement of `cbar: 1.0` in the flywheel, the field and words of the error)
    let cases = [
        ("stifness: 3.0", None, "stifness"),
        (
            "cbar: 1.0, xi_theta: 0.02",
            Some("devices[1].coupling.cbar"),
            "at most one",
        ),
        (
            "k_theta: 1.0, clutch_frequency_ratio: 3.0",
            Some("devices[1].coupling.k_theta"),
            "at most one",
        ),
        ("cbar: -1.0", Some("devices[1].coupling.cbar"), "-1"),
        ("rho: [0.05, 0.0]", Some("devices[1].coupling.rho"), "0"),
        ("cbar: foo(1.0)", None, "foo"),
    ];
    let line = STUDY.lines().position(|l| l.contains("flywheel(")).unwrap() + 1;
    for (set, field, words) in cases {
        let text = STUDY.replace("flywheel(cbar: 1.0)", &format!("flywheel({set})"));
        let e = Study::from_ron_str(&text, "bad.ron").expect_err(set);
        assert_eq!(e.line, Some(line), "{set}: {e}");
        if let Some(field) = field {
            assert_eq!(e.field.as_deref(), Some(field), "{set}: {e}");
        }
        assert!(e.to_string().contains(words), "{set}: {e}");
        assert!(
            e.to_string().contains("bad.ron") && e.hint.is_some(),
            "{set}: {e}"
        );
    }
    // The clutch's fields belong in the coupling, not in the inerter.
    let text = STUDY.replace("coupling: flywheel(cbar: 1.0)", "cbar: 1.0");
    let e = Study::from_ron_str(&text, "bad.ron").unwrap_err();
    assert!(e.to_string().contains("cbar"), "{e}");
}
