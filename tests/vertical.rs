//! Vertical ground motion (docs/MODEL.md "Vertical ground motion"): gravity becomes
//! g + ü_v(t) wherever the models use it. Checked against an exact similarity, the uplift
//! condition's closed form, an independent scipy integration, the energy ledger, and bit
//! identity with no vertical motion.

use crate::util::rocklab;
use rocklab::excitation::{PulseShape, library};
use rocklab::presets::{flexible_structure, mechanistic, rigid_size_for_p, scene};
use rocklab::scene::{
    Amplitude, Device, Excitation, Form, Frequency, RigidBlock, Scene, Structure, VerticalMotion,
};
use rocklab::sim::{self, History, HistoryColumn, Sampling, SceneResult, SimError};

fn rigid(alpha: f64, p: f64) -> Structure {
    Structure::Rigid(RigidBlock {
        size: rigid_size_for_p(p),
        alpha,
        mass: 1.0,
        form: Form::Exact,
    })
}

fn pulse(shape: PulseShape, amplitude_g: f64, omega: f64) -> Excitation {
    Excitation::Pulse {
        shape,
        amplitude: Amplitude::G(amplitude_g),
        frequency: Frequency::RadPerSec(omega),
    }
}

fn vertical_pulse(shape: PulseShape, amplitude_g: f64, omega: f64) -> VerticalMotion {
    VerticalMotion::Pulse {
        shape,
        amplitude: Amplitude::G(amplitude_g),
        frequency: Frequency::RadPerSec(omega),
    }
}

/// A scene at a tight tolerance, run to its end.
fn tight(structure: Structure, device: Device, excitation: Excitation, duration: f64) -> Scene {
    Scene {
        rtol: 1e-12,
        ..scene(structure, device, excitation, duration)
    }
}

fn with_vertical(scene: &Scene, vertical: Option<VerticalMotion>) -> Scene {
    Scene {
        vertical,
        ..scene.clone()
    }
}

fn run(scene: &Scene) -> SceneResult {
    sim::run(scene, library::global().unwrap()).unwrap_or_else(|e| panic!("{e}"))
}

/// θ at each of `times` (the rows of the history at exactly those times).
fn theta_at(scene: &Scene, times: &[f64]) -> (SceneResult, Vec<f64>) {
    let (result, history) = sim::run_history(
        scene,
        library::global().unwrap(),
        &Sampling::At(times.to_vec()),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let t = history.column(HistoryColumn::T).unwrap();
    let theta = history.column(HistoryColumn::Theta).unwrap();
    let picked = times
        .iter()
        .map(|time| match t.iter().position(|x| x == time) {
            Some(i) => theta[i],
            // No row: idle flat on the ground or at rest after the run stopped (θ = 0 in the
            // last row before), or after overturning (NaN: not compared).
            None => match t.iter().rposition(|x| x < time) {
                Some(i) if theta[i] == 0.0 => 0.0,
                _ => f64::NAN,
            },
        })
        .collect();
    (result, picked)
}

fn grid(duration: f64, dt: f64) -> Vec<f64> {
    let n = (duration / dt).round() as usize;
    (0..=n).map(|k| k as f64 * dt).collect()
}

fn steps_history(scene: &Scene) -> (SceneResult, History) {
    sim::run_history(scene, library::global().unwrap(), &Sampling::Steps)
        .unwrap_or_else(|e| panic!("{e}"))
}

/// A constant vertical acceleration c·g on a bare block is the same block with
/// p' = p√(1 + c) under the horizontal pulse scaled by 1/(1 + c) at the same absolute
/// frequency: θ̈ = −p²[(1 + c) S + (a/g) C] = −p'²[S + (a/((1 + c) g)) C], the uplift
/// condition |a| > (1 + c) g tan α is |a/(1 + c)| > g tan α, and Housner's r depends on α
/// alone. Exact, so the histories agree to the integrators' accuracy.
#[test]
fn constant_vertical_is_a_block_with_scaled_p_and_pulse() {
    let (alpha, p, duration) = (0.2, 2.0, 6.0);
    let times = grid(duration, 0.01);
    let mut worst = 0.0f64;
    for c in [-0.45, -0.2, 0.3, 1.0] {
        for (shape, a, omega) in [
            (PulseShape::Sine, 0.33, 5.0),
            (PulseShape::Ricker, 0.45, 7.0),
            (PulseShape::AntisymmetricRicker, 0.3, 4.0),
            (PulseShape::Cosine, 0.25, 3.0),
        ] {
            let shaken = with_vertical(
                &tight(
                    rigid(alpha, p),
                    Device::None,
                    pulse(shape, a * (1.0 + c), omega),
                    duration,
                ),
                Some(VerticalMotion::Constant(c)),
            );
            let similar = tight(
                rigid(alpha, p * (1.0 + c).sqrt()),
                Device::None,
                pulse(shape, a, omega),
                duration,
            );
            let (rv, tv) = theta_at(&shaken, &times);
            let (rs, ts) = theta_at(&similar, &times);
            assert_eq!(rv.overturned, rs.overturned, "c {c} {shape:?}");
            assert_eq!(rv.counters.uplifts, rs.counters.uplifts, "c {c} {shape:?}");
            assert!(rv.counters.impacts > 0, "c {c} {shape:?}: no rocking");
            let peak_gap = (rv.peaks.rotation - rs.peaks.rotation).abs();
            assert!(
                peak_gap < 1e-9,
                "c {c} {shape:?}: peaks differ by {peak_gap:e}"
            );
            for (k, (x, y)) in tv.iter().zip(&ts).enumerate() {
                if x.is_nan() || y.is_nan() {
                    assert_eq!(x.is_nan(), y.is_nan(), "c {c} {shape:?} t {}", times[k]);
                    continue;
                }
                worst = worst.max((x - y).abs());
                assert!(
                    (x - y).abs() < 1e-8,
                    "c {c} {shape:?} t {}: θ {x} vs {y}",
                    times[k]
                );
            }
        }
    }
    println!("largest θ difference {worst:e} rad");
}

/// With constant c the block lifts exactly where a_g first reaches (1 + c) g tan α: for a
/// sine pulse A sin ωt at t* = asin((1 + c) g tan α / A)/ω; just below that amplitude it
/// never lifts, just above it does. With ratio(r) the ground lifts it where
/// a_g = g tan α / (1 − r tan α) (toward the side a_g pushes, a_g > 0), found by the
/// integrated uplift events rather than the idle scan.
#[test]
fn uplift_begins_where_the_ground_beats_the_effective_weight() {
    let (alpha, p, omega): (f64, f64, f64) = (0.2, 2.0, 5.0);
    let first_uplift = |scene: &Scene| -> Option<f64> {
        let (_, h) = steps_history(scene);
        h.events
            .iter()
            .find(|(_, name)| *name == "uplift")
            .map(|(t, _)| *t)
    };
    for c in [-0.3, 0.0, 0.5] {
        let level = (1.0 + c) * alpha.tan();
        let at = |a: f64| {
            with_vertical(
                &tight(
                    rigid(alpha, p),
                    Device::None,
                    pulse(PulseShape::Sine, a, omega),
                    2.0,
                ),
                Some(VerticalMotion::Constant(c)),
            )
        };
        let t = first_uplift(&at(2.0 * level)).expect("lifts");
        let expected = (0.5f64).asin() / omega;
        assert!((t - expected).abs() < 1e-12, "c {c}: {t} vs {expected}");
        assert_eq!(first_uplift(&at(level * (1.0 - 1e-9))), None, "c {c}");
        assert!(first_uplift(&at(level * (1.0 + 1e-9))).is_some(), "c {c}");
    }
    for r in [0.5, -0.7] {
        let a = 0.5;
        let level = alpha.tan() / (1.0 - r * alpha.tan());
        let scene = with_vertical(
            &tight(
                rigid(alpha, p),
                Device::None,
                pulse(PulseShape::Sine, a, omega),
                2.0,
            ),
            Some(VerticalMotion::Ratio(r)),
        );
        let t = first_uplift(&scene).expect("lifts");
        let expected = (level / a).asin() / omega;
        assert!((t - expected).abs() < 1e-9, "r {r}: {t} vs {expected}");
    }
}

/// A vertical acceleration below −g anywhere in the scene is refused before anything is
/// integrated, naming the time and the value.
#[test]
fn free_flight_is_refused_with_its_time_and_value() {
    let base = tight(
        rigid(0.2, 2.0),
        Device::None,
        pulse(PulseShape::Sine, 0.6, 4.0),
        3.0,
    );
    let refused = |vertical: VerticalMotion| -> String {
        match sim::run(
            &with_vertical(&base, Some(vertical)),
            library::global().unwrap(),
        ) {
            Err(SimError::Invalid(message)) => message,
            other => panic!("not refused: {other:?}"),
        }
    };
    // ratio 2 of a 0.6 g sine: −1.2 g at ωt = 3π/2.
    let message = refused(VerticalMotion::Ratio(2.0));
    let t = 1.5 * std::f64::consts::PI / 4.0;
    assert!(message.contains("-1.2000 g"), "{message}");
    assert!(message.contains(&format!("t = {t:.4} s")), "{message}");
    assert!(message.contains("free flight"), "{message}");
    // A vertical pulse whose downward lobe passes −g.
    let message = refused(vertical_pulse(PulseShape::Sine, 1.1, 6.0));
    assert!(message.contains("-1.1000 g"), "{message}");
    // A constant below −1 is refused by the scene's validation.
    let message = refused(VerticalMotion::Constant(-1.2));
    assert!(message.contains("vertical_constant"), "{message}");
    // Just above −g is fine.
    assert!(
        sim::run(
            &with_vertical(&base, Some(VerticalMotion::Ratio(1.6))),
            library::global().unwrap()
        )
        .is_ok()
    );
    // The CLI says the same.
    let out = rocklab(&[
        "simulate",
        "--alpha",
        "0.2",
        "--p",
        "2",
        "--amplitude-g",
        "0.6",
        "--frequency",
        "4",
        "--vertical-ratio",
        "2",
    ]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("free flight"), "{stderr}");
}

/// The ground's vertical work −m ü_v Ẏ is booked with the input: the ledger closes with a
/// vertical pulse on a clutched block and with ratio(0.67) on a flexible structure with a
/// clutch under a record; and the vertical work is not negligible there (without booking it
/// the balance would be off by it).
#[test]
fn energy_ledger_closes_with_vertical_input() {
    let block = Scene {
        rtol: 1e-10,
        ..with_vertical(
            &scene(
                rigid(0.2, 2.0),
                mechanistic(),
                pulse(PulseShape::Sine, 0.25, 5.0),
                8.0,
            ),
            Some(vertical_pulse(PulseShape::Ricker, 0.5, 9.0)),
        )
    };
    let flexible = Scene {
        rtol: 1e-9,
        ..with_vertical(
            &rocklab::presets::flexible_landers(rocklab::presets::mechanistic_xi_theta(0.02)),
            Some(VerticalMotion::Ratio(0.67)),
        )
    };
    for (name, scene) in [("rigid", block), ("flexible", flexible)] {
        let shaken = run(&scene);
        let plain = run(&with_vertical(&scene, None));
        println!(
            "{name}: residual {:.2e}, input {:.4} J (without vertical {:.4} J)",
            shaken.energy_residual, shaken.energy.input, plain.energy.input
        );
        assert!(
            shaken.energy_residual < 1e-6,
            "{name}: residual {:e}",
            shaken.energy_residual
        );
        assert!(shaken.counters.uplifts > 0, "{name}: never rocked");
        assert!(!shaken.overturned, "{name}");
        assert!(
            (shaken.peaks.rotation - plain.peaks.rotation).abs() > 1e-4 * plain.peaks.rotation,
            "{name}: the vertical motion changed nothing"
        );
    }
}

/// No vertical motion, constant(0) and ratio(0) give the same history bit for bit, for the
/// bare block and for a flexible structure with a clutch under a record (closed-form
/// contact and all).
#[test]
fn zero_vertical_is_no_vertical_bit_for_bit() {
    let block = scene(
        rigid(0.2, 2.0),
        Device::None,
        pulse(PulseShape::Sine, 0.4, 5.0),
        6.0,
    );
    let flexible = rocklab::presets::flexible_landers(rocklab::presets::mechanistic_xi_theta(0.02));
    let flexible_inerter = rocklab::presets::flexible_landers(rocklab::presets::inerter());
    for scene in [block, flexible, flexible_inerter] {
        let (r0, h0) = steps_history(&scene);
        assert!(r0.counters.uplifts > 0);
        for vertical in [VerticalMotion::Constant(0.0), VerticalMotion::Ratio(0.0)] {
            let (r, h) = steps_history(&with_vertical(&scene, Some(vertical.clone())));
            assert_eq!(h.rows, h0.rows, "{vertical:?}");
            assert_eq!(h.events, h0.events, "{vertical:?}");
            assert_eq!(r.peaks, r0.peaks, "{vertical:?}");
            assert_eq!(r.energy, r0.energy, "{vertical:?}");
        }
    }
}

/// A flexible structure with a clutch and with a rigidly coupled inerter runs under a
/// vertical record: a vertical record file holding c·g for the whole horizontal record acts
/// as constant(c) while it lasts.
#[test]
fn a_vertical_record_file_is_read_and_aligned_with_the_horizontal() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("vertical.txt");
    let c = -0.25;
    let (dt, n) = (0.01, 501);
    let mut text = String::from("# units: g\n");
    for k in 0..n {
        text.push_str(&format!("{} {c}\n", k as f64 * dt));
    }
    std::fs::write(&file, text).unwrap();
    let block = tight(
        rigid(0.2, 2.0),
        Device::None,
        pulse(PulseShape::Sine, 0.2, 5.0),
        4.0,
    );
    let times = grid(4.0, 0.01);
    let (rf, from_file) = theta_at(
        &with_vertical(
            &block,
            Some(VerticalMotion::Record(file.to_str().unwrap().into())),
        ),
        &times,
    );
    let (rc, constant) = theta_at(
        &with_vertical(&block, Some(VerticalMotion::Constant(c))),
        &times,
    );
    assert!(rf.counters.impacts > 0 && !rf.overturned);
    assert_eq!(rf.counters.uplifts, rc.counters.uplifts);
    for (k, (a, b)) in from_file.iter().zip(&constant).enumerate() {
        assert!((a - b).abs() < 1e-8, "t {}: {a} vs {b}", times[k]);
    }
    // Flexible structure, clutch and rigid inerter: runs, and the ledger closes.
    for device in [
        rocklab::presets::mechanistic_xi_theta(0.02),
        rocklab::presets::inerter(),
    ] {
        let flexible = Scene {
            rtol: 1e-9,
            ..with_vertical(
                &scene(
                    flexible_structure(12.0),
                    device,
                    pulse(PulseShape::Sine, 0.5, 3.0),
                    5.0,
                ),
                Some(VerticalMotion::Record(file.to_str().unwrap().into())),
            )
        };
        let r = run(&flexible);
        assert!(r.counters.uplifts > 0 && r.energy_residual < 1e-6, "{r:?}");
    }
}

/// The scipy reference (scripts/vertical-reference.py, tests/data/vertical_reference.csv):
/// a bare block under horizontal and vertical sine pulses that lifts, rocks through ~80
/// impacts and comes to rest. θ(t) agrees within 1e-9 rad (the block's θ ~ 0.1 rad; measured
/// 3e-11) and the peak within 1e-10 rad (measured 7e-12).
#[test]
fn vertical_pulse_matches_the_scipy_reference() {
    let text = include_str!("data/vertical_reference.csv");
    // (α, p, A_h/g, ω_h, A_v/g, ω_v), the (t, θ) samples, the peak |θ|.
    type Case = (Vec<f64>, Vec<(f64, f64)>, f64);
    let mut cases: Vec<Case> = Vec::new();
    let mut keys: Vec<String> = Vec::new();
    for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let key = f[..7].join(",");
        if keys.last() != Some(&key) {
            keys.push(key);
            let params = f[1..7].iter().map(|v| v.parse().unwrap()).collect();
            cases.push((params, Vec::new(), f64::NAN));
        }
        let case = cases.last_mut().unwrap();
        let theta: f64 = f[8].parse().unwrap();
        if f[7] == "peak" {
            case.2 = theta;
        } else {
            case.1.push((f[7].parse().unwrap(), theta));
        }
    }
    assert_eq!(cases.len(), 2);
    for (params, samples, peak) in cases {
        let [alpha, p, ha, hw, va, vw] = params[..] else {
            unreachable!()
        };
        let duration = samples.last().unwrap().0;
        let scene = Scene {
            rtol: 1e-11,
            ..with_vertical(
                &scene(
                    rigid(alpha, p),
                    Device::None,
                    pulse(PulseShape::Sine, ha, hw),
                    duration,
                ),
                Some(vertical_pulse(PulseShape::Sine, va, vw)),
            )
        };
        let times: Vec<f64> = samples.iter().map(|s| s.0).collect();
        let (result, theta) = theta_at(&scene, &times);
        assert!(result.counters.impacts > 50 && !result.overturned);
        assert_eq!(result.end_reason, rocklab::model::EndReason::Rest);
        let mut worst = 0.0f64;
        for ((t, expected), got) in samples.iter().zip(&theta) {
            let got = *got;
            worst = worst.max((got - expected).abs());
            assert!(
                (got - expected).abs() < 1e-9,
                "{params:?} t {t}: {got} vs {expected}"
            );
        }
        let gap = (result.peaks.rotation - peak).abs();
        println!(
            "{params:?}: peak {} vs {peak} ({gap:.1e}), θ within {worst:.1e}",
            result.peaks.rotation
        );
        assert!(
            gap < 1e-10,
            "{params:?}: peak {} vs {peak}",
            result.peaks.rotation
        );
    }
}
