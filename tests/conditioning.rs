//! `sim::check` (`simulate --check`): converged, not converged, or ill-conditioned, on cases
//! whose answer is known.

use crate::util::rocklab;
use rocklab::presets::{flexible_fig14, rigid_fig8};
use rocklab::scene::*;
use rocklab::sim::check::{Reproducibility, check};
use rocklab::sim::{self, Bounds};

fn checked(scene: &Scene) -> rocklab::sim::check::Check {
    let library = rocklab::excitation::library::global().unwrap();
    let result = sim::run(scene, library).unwrap();
    check(scene, &result, library, Bounds::default()).unwrap()
}

fn condition(c: &rocklab::sim::check::Check, quantity: &str) -> f64 {
    c.peaks
        .iter()
        .find(|p| p.quantity == quantity)
        .unwrap_or_else(|| panic!("{quantity} not checked: {c:?}"))
        .condition
}

/// Below uplift the flexible structure is a linear oscillator: its peaks are proportional to
/// the amplitude (κ = 1 exactly) and it never rotates (κ = 0).
#[test]
fn a_linear_response_has_condition_one() {
    let mut scene = flexible_fig14(Device::None);
    scene.excitation = scene.excitation.scaled(0.2);
    let c = checked(&scene);
    assert_eq!(c.verdict, Reproducibility::Converged, "{}", c.report());
    assert_eq!(condition(&c, "peak_rotation"), 0.0);
    for q in ["peak_deformation", "peak_drift", "peak_abs_acceleration_g"] {
        let k = condition(&c, q);
        assert!((k - 1.0).abs() < 1e-3, "{q}: κ = {k}");
    }
}

/// The pulse scenes of the paper are well-conditioned and converged at the default rtol.
#[test]
fn the_paper_scenes_are_converged() {
    for scene in [
        rigid_fig8(Device::None),
        rigid_fig8(Device::Mechanistic(Clutch::paper_default(0.5))),
        flexible_fig14(Device::Sequential { sigma: 0.5 }),
    ] {
        let c = checked(&scene);
        assert_eq!(c.verdict, Reproducibility::Converged, "{}", c.report());
        assert!(
            c.peaks
                .iter()
                .all(|p| p.condition < 10.0 && p.change < 1e-3),
            "{}",
            c.report()
        );
    }
}

/// A loose tolerance on a well-conditioned scene: not converged, and the check says to tighten.
#[test]
fn a_loose_tolerance_is_not_converged() {
    let mut scene = rigid_fig8(Device::Mechanistic(Clutch::paper_default(0.5)));
    scene.rtol = 1e-2;
    let c = checked(&scene);
    assert_eq!(c.verdict, Reproducibility::NotConverged, "{}", c.report());
    assert!(c.report().contains("a tighter --rtol fixes it"));
}

/// On the overturning boundary (found by bisection on the amplitude to 1e-9) a change of 1e-7
/// in the amplitude flips the outcome.
#[test]
fn the_overturning_boundary_is_ill_conditioned() {
    let library = rocklab::excitation::library::global().unwrap();
    let at = |ratio: f64| {
        let mut s = rigid_fig8(Device::None);
        s.excitation = Excitation::Pulse {
            shape: rocklab::excitation::PulseShape::Sine,
            amplitude: Amplitude::AlphaRatio(ratio),
            frequency: Frequency::Ratio(2.0),
        };
        s
    };
    // Bisected at the check's reference tolerance, whose runs it compares.
    let overturns = |ratio: f64| {
        let mut s = at(ratio);
        s.rtol = 1e-8;
        sim::run(&s, library).unwrap().overturned
    };
    let (mut low, mut high) = (1.0, 4.0);
    assert!(!overturns(low) && overturns(high));
    while high / low - 1.0 > 1e-9 {
        let mid = 0.5 * (low + high);
        if overturns(mid) {
            high = mid
        } else {
            low = mid
        }
    }
    let c = checked(&at(0.5 * (low + high)));
    assert!(c.overturn_flips, "{}", c.report());
    assert_eq!(c.verdict, Reproducibility::IllConditioned);
    assert!(c.report().contains("overturning boundary"));
}

/// `simulate --check --json` carries the check; the text form prints the verdict.
#[test]
fn simulate_prints_the_check() {
    // The Fig. 8 mechanistic scene (cli_simulate's base scene).
    let args = crate::cli_simulate::with(&["--device", "mechanistic", "--sigma", "0.5", "--check"]);
    let out = rocklab(&[&args[..], &["--json"]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["check"]["verdict"], "converged");
    assert_eq!(v["check"]["reference_rtol"].as_f64(), Some(1e-8));
    let rotation = &v["check"]["peaks"][0];
    assert_eq!(rotation["quantity"], "peak_rotation");
    assert_eq!(rotation["value"], v["peak_rotation"]);
    let out = rocklab(&args);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("verdict: converged"), "{text}");
}

/// `rocklab check` over a results file: the hard case's 50 p clutch is ill-conditioned, the
/// default 25 p clutch converged, one CSV row per scene and quantity.
#[test]
fn check_flags_the_ill_conditioned_scenes_of_a_results_file() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("hard.ron");
    std::fs::write(
        &study,
        r#"(
    version: 1,
    name: "hard",
    description: "tests/hard_cases.rs::long_record_chattering_to_rest, 25 p and 50 p",
    structure: rigid(size: [3.0], alpha: 0.25),
    devices: [mechanistic(sigma: 0.5, clutch_frequency_ratio: [25.0, 50.0], cbar: 1.0)],
    excitation: record(names: ["landers"], scale: 1.0),
    quantities: [peak_rotation_ratio, peak_abs_acceleration],
    spectrum: size,
    duration: 10.5,
)"#,
    )
    .unwrap();
    let out = dir.path().join("out");
    let o = crate::util::run_into(study.to_str().unwrap(), &out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = rocklab(&["check", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("2 scenes checked: 1 converged, 0 not converged")
            && text.contains("1 ill-conditioned"),
        "{text}"
    );
    let csv = std::fs::read_to_string(out.join("check.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 4, "{csv}");
    let row = |scene: &str, q: &str| {
        rows.iter()
            .find(|r| r[0] == scene && r[4] == q)
            .unwrap_or_else(|| panic!("{scene} {q}: {csv}"))
    };
    assert_eq!(row("0", "peak_rotation")[1], "converged");
    let stiff = row("1", "peak_rotation");
    assert_eq!(stiff[1], "ill_conditioned");
    assert!(stiff[8].parse::<f64>().unwrap() > 1e4, "{csv}");
    // Selecting scenes, and a selection that matches none.
    let o = rocklab(&["check", out.to_str().unwrap(), "--scenes", "0"]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("1 scene checked: 1 converged"));
    let o = rocklab(&["check", out.to_str().unwrap(), "--scenes", "7-9"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no finished scene matches --scenes"));
}

/// Scaling an excitation scales its ground acceleration at every instant, whatever its form.
#[test]
fn scaled_excitations_scale_the_ground_acceleration() {
    let library = rocklab::excitation::library::global().unwrap();
    let record = |scale| Excitation::Record {
        name: "landers".into(),
        scale,
        baseline: false,
        kinks: Default::default(),
    };
    let pulse = |amplitude| Excitation::Pulse {
        shape: rocklab::excitation::PulseShape::Sine,
        amplitude,
        frequency: Frequency::Ratio(3.0),
    };
    for excitation in [
        pulse(Amplitude::G(0.3)),
        pulse(Amplitude::AlphaRatio(1.5)),
        pulse(Amplitude::TanAlphaRatio(1.5)),
        Excitation::MpPulse {
            tp: 1.0,
            pgv: 0.5,
            gamma: 2.0,
            nu: 0.3,
        },
        record(RecordScale::Factor(-1.5)),
        record(RecordScale::Pga(0.4)),
        record(RecordScale::Pgv(0.6)),
    ] {
        let mut scene = rigid_fig8(Device::None);
        scene.excitation = excitation.clone();
        let base = sim::motion_for(&scene, library).unwrap();
        scene.excitation = excitation.scaled(1.25);
        let scaled = sim::motion_for(&scene, library).unwrap();
        let times = [0.1, 0.37, 0.55, 0.8];
        assert!(
            times.iter().any(|&t| base.accel(t) != 0.0),
            "{excitation:?}"
        );
        for t in times {
            let (a, b) = (base.accel(t), scaled.accel(t));
            assert!(
                (b - 1.25 * a).abs() <= 1e-14 * a.abs(),
                "{excitation:?} t={t}: {a} {b}"
            );
        }
    }
}

/// Just below the uplift threshold (A = g tan α) the block does not rock, and 1e-7 more
/// amplitude makes it: the rotation appears (κ infinite, null in JSON) but stays far below
/// 1e-3 α, so it is negligible and the verdict rests on the other peaks.
#[test]
fn a_peak_that_appears_has_infinite_condition() {
    let mut scene = rigid_fig8(Device::None);
    scene.excitation = Excitation::Pulse {
        shape: rocklab::excitation::PulseShape::Sine,
        amplitude: Amplitude::TanAlphaRatio(1.0 - 5e-8),
        frequency: Frequency::Ratio(5.0),
    };
    let c = checked(&scene);
    let rotation = &c.peaks[0];
    assert_eq!(rotation.reference, 0.0);
    assert_eq!(rotation.condition, f64::INFINITY);
    assert!(rotation.negligible, "{}", c.report());
    // The acceleration follows the ground's: linear.
    assert!((condition(&c, "peak_abs_acceleration_g") - 1.0).abs() < 1e-3);
    assert_eq!(c.verdict, Reproducibility::Converged, "{}", c.report());
    assert!(c.report().contains("negligible (< 1e-3 α), not judged"));
    let json = serde_json::to_value(&c).unwrap();
    assert_eq!(json["peaks"][0]["condition"], serde_json::Value::Null);
    assert_eq!(json["peaks"][0]["negligible"], true);
    // Were that peak not negligible, no tolerance would settle it.
    let mut not_negligible = c.clone();
    not_negligible.peaks[0].negligible = false;
    not_negligible.verdict = Reproducibility::IllConditioned;
    assert_eq!(not_negligible.suggested_rtol(), None);
    assert!(not_negligible.report().contains("appears or vanishes"));
}

/// A flexible Fig. 14 structure that barely lifts off (ωg/p = 14.5: θ = 2e-6 rad, 1e-5 α):
/// its rotation moves by ~50 % with the tolerance, by 1e-6 rad, and is negligible; the
/// deformation, converged, decides.
#[test]
fn a_barely_rocking_peak_is_negligible() {
    let mut scene = flexible_fig14(Device::Mechanistic(Clutch::paper_default(0.5)));
    scene.excitation = Excitation::Pulse {
        shape: rocklab::excitation::PulseShape::Sine,
        amplitude: Amplitude::TanAlphaRatio(1.5),
        frequency: Frequency::Ratio(14.5),
    };
    let c = checked(&scene);
    let rotation = &c.peaks[0];
    assert!(
        rotation.negligible && rotation.change > 0.1,
        "{}",
        c.report()
    );
    assert!(rotation.reference < 1e-5 * 0.2 * 10.0, "{}", c.report());
    assert!(
        !c.peaks
            .iter()
            .find(|p| p.quantity == "peak_deformation")
            .unwrap()
            .negligible
    );
    assert_eq!(c.verdict, Reproducibility::Converged, "{}", c.report());
}

/// `simulate --check` of a small bare block (R = 1 m, α = 0.2, one-sine at 5 rad/s) with
/// `extra` flags.
fn small_block_check(extra: &[&str]) -> std::process::Output {
    let base = [
        "simulate",
        "--size",
        "1",
        "--alpha",
        "0.2",
        "--frequency",
        "5",
        "--check",
    ];
    rocklab(&[&base[..], extra].concat())
}

/// A check that cannot be made is refused before the scene runs; scene ranges are checked.
#[test]
fn impossible_checks_are_refused_up_front() {
    let o = small_block_check(&["--amplitude-ratio", "1.5", "--rtol", "1e-12"]);
    assert_eq!(o.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("--check: rtol 1e-12 leaves no tighter reference"),
        "{stderr}"
    );
    assert!(o.stdout.is_empty(), "nothing ran");
    let o = rocklab(&["check", "out/none", "--scenes", "5-2"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("a range runs from low to high, e.g. 2-5"));
}

/// Rotation alone, and no uplift: every peak is negligible, and the check says so.
#[test]
fn a_check_of_negligible_peaks_only_says_so() {
    let o = small_block_check(&["--amplitude-ratio", "0.5", "--quantities", "peak_rotation"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("verdict: converged: every peak is negligible"),
        "{text}"
    );
}
