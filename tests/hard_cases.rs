//! Stability on hard cases (issue 7): stiff clutches, sharp clutch corners, large gear play,
//! strong friction, slender and stocky blocks, fast pulses, the overturning boundary. Each must
//! finish without NaN inside the step budget, close its energy balance, and converge as the
//! tolerance tightens.

use rocklab::excitation::PulseShape;
use rocklab::presets::{flexible_fig14, rigid_fig8};
use rocklab::scene::*;
use rocklab::sim::{self, SceneResult};

fn run_at(scene: &Scene, rtol: f64) -> SceneResult {
    let mut s = scene.clone();
    s.rtol = rtol;
    let r = sim::run(&s, rocklab::excitation::library::global().unwrap())
        .unwrap_or_else(|e| panic!("scene failed at rtol {rtol}: {e}"));
    let p = r.peaks;
    assert!(
        [p.rotation, p.drift, p.abs_acceleration_g, r.energy_residual]
            .iter()
            .all(|v| v.is_finite()),
        "non-finite result: {r:?}"
    );
    r
}

/// Converged: the peak rotation moves by less than `tol` relative between rtol 1e-6 and 1e-9,
/// and the energy balance closes at both.
fn assert_stable(name: &str, scene: &Scene, tol: f64) -> SceneResult {
    let coarse = run_at(scene, 1e-6);
    let fine = run_at(scene, 1e-9);
    let change = (coarse.peaks.rotation - fine.peaks.rotation).abs() / fine.peaks.rotation;
    println!(
        "{name}: θmax/α = {:.5}, change 1e-6→1e-9 {change:.1e}, residual {:.1e}/{:.1e}, steps {}/{}",
        fine.peak_rotation_ratio,
        coarse.energy_residual,
        fine.energy_residual,
        coarse.stats.steps,
        fine.stats.steps
    );
    assert!(change < tol, "{name}: peak moved by {change:e}");
    // Bounded, and shrinking with the tolerance (friction with a sharp atan transition is
    // the worst case measured: 1.4e-4 at 1e-6).
    assert!(
        coarse.energy_residual < 1e-3,
        "{name}: residual {}",
        coarse.energy_residual
    );
    assert!(
        fine.energy_residual < 1e-6,
        "{name}: residual {}",
        fine.energy_residual
    );
    fine
}

fn clutch(f: impl FnOnce(&mut Clutch)) -> Device {
    let mut c = Clutch::paper_default(0.5);
    f(&mut c);
    Device::Mechanistic(c)
}

#[test]
fn very_stiff_clutch() {
    for ratio in [1e3, 1e4] {
        let scene = rigid_fig8(clutch(|c| {
            c.stiffness = ClutchStiffness::FrequencyRatio(ratio)
        }));
        assert_stable(&format!("clutch frequency {ratio:e} p"), &scene, 1e-3);
    }
}

#[test]
fn sharp_clutch_corner() {
    for eps in [1e7, 1e8] {
        let scene = rigid_fig8(clutch(|c| c.epsilon = eps));
        assert_stable(&format!("epsilon {eps:e}"), &scene, 1e-3);
    }
}

#[test]
fn large_gear_play_with_both_reset_rules() {
    let paper = assert_stable(
        "play 1 cm, paper rule",
        &rigid_fig8(clutch(|c| c.play = 0.01)),
        1e-3,
    );
    let strict = assert_stable(
        "play 1 cm, strict rule",
        &rigid_fig8(clutch(|c| {
            c.play = 0.01;
            c.reset = ResetRule::Strict
        })),
        1e-3,
    );
    // The two rules are different models: both run, and the choice is visible in the peaks.
    assert!(paper.counters.resets > 0 && strict.counters.resets > 0);
}

#[test]
fn strong_friction_with_a_sharp_transition() {
    let scene = |eta: f64| {
        rigid_fig8(clutch(|c| {
            c.friction = 0.2;
            c.eta = eta;
        }))
    };
    let r = assert_stable("friction 0.2 mr g, eta 1e3", &scene(1e3), 1e-3);
    assert!(r.energy.friction > 0.0);
    // η = 1e5 makes the friction law stiff (slope ~2.5e6 1/s on the flywheel): the explicit
    // integrator is stability limited, the peak is still right at 1e-6, but the friction work
    // converges only below ~1e-8 (measured residuals 5.6e-3, 9.5e-7, 7.9e-11 at 1e-6/8/10).
    let sharp = scene(1e5);
    let (coarse, fine) = (run_at(&sharp, 1e-6), run_at(&sharp, 1e-10));
    let change = (coarse.peaks.rotation - fine.peaks.rotation).abs() / fine.peaks.rotation;
    assert!(change < 2e-3, "peak moved by {change:e}");
    assert!(
        coarse.energy_residual < 2e-2,
        "residual {}",
        coarse.energy_residual
    );
    assert!(
        fine.energy_residual < 1e-8,
        "residual {}",
        fine.energy_residual
    );
}

#[test]
fn slender_and_stocky_blocks() {
    for alpha in [0.02, 0.6] {
        for device in [
            Device::None,
            Device::Mechanistic(Clutch::paper_default(0.5)),
        ] {
            let mut scene = rigid_fig8(device);
            if let Structure::Rigid(b) = &mut scene.structure {
                b.alpha = alpha;
            }
            scene.excitation = Excitation::Pulse {
                shape: PulseShape::Sine,
                amplitude: Amplitude::TanAlphaRatio(1.5),
                frequency: Frequency::Ratio(6.0),
            };
            assert_stable(&format!("alpha {alpha}"), &scene, 1e-3);
        }
    }
}

#[test]
fn fast_pulse() {
    for device in [
        Device::None,
        Device::Sequential { sigma: 0.5 },
        Device::Mechanistic(Clutch::paper_default(0.5)),
    ] {
        let mut scene = rigid_fig8(device);
        scene.excitation = Excitation::Pulse {
            shape: PulseShape::Sine,
            amplitude: Amplitude::TanAlphaRatio(3.0),
            frequency: Frequency::Ratio(20.0),
        };
        assert_stable("omega_g/p = 20", &scene, 1e-3);
    }
}

/// The overturning boundary in ωg/p, found by bisection, is stable under tolerance changes, and
/// a scene within 1e-4 of it is decided consistently.
#[test]
fn overturning_boundary_is_stable_under_tolerance() {
    let boundary = |rtol: f64| {
        let overturns = |ratio: f64| {
            let mut s = rigid_fig8(Device::None);
            s.excitation = Excitation::Pulse {
                shape: PulseShape::Sine,
                amplitude: Amplitude::AlphaRatio(1.5),
                frequency: Frequency::Ratio(ratio),
            };
            run_at(&s, rtol).overturned
        };
        let (mut lo, mut hi) = (2.0, 4.0);
        assert!(overturns(lo) && !overturns(hi));
        for _ in 0..40 {
            let mid = 0.5 * (lo + hi);
            if overturns(mid) { lo = mid } else { hi = mid }
        }
        lo
    };
    let (b6, b9) = (boundary(1e-6), boundary(1e-9));
    println!("boundary ωg/p: rtol 1e-6 {b6:.8}, rtol 1e-9 {b9:.8}");
    assert!((b6 - b9).abs() / b9 < 1e-4, "{b6} vs {b9}");
}

#[test]
fn step_budget_is_a_clear_error_not_a_hang() {
    // An absurdly stiff clutch under a tight tolerance exhausts the budget quickly.
    let scene = rigid_fig8(clutch(|c| {
        c.stiffness = ClutchStiffness::FrequencyRatio(1e9)
    }));
    let mut s = scene;
    s.rtol = 1e-12;
    s.duration = 1e4;
    match sim::run(&s, rocklab::excitation::library::global().unwrap()) {
        Err(e) => {
            let msg = e.to_string();
            assert!(msg.contains("step") || msg.contains("stiff"), "{msg}");
        }
        Ok(r) => panic!("expected a budget error, got {r:?}"),
    }
}

/// A long record leaves the block chattering: hundreds of impacts of shrinking amplitude, which
/// would never end without Zeno-safe rest detection. Every device must reach rest and close its
/// energy balance; bare and sequential peaks converge under tightening tolerance.
///
/// The mechanistic clutch, measured on Landers (R = 3 m, α = 0.25; `rocklab simulate
/// --structure rigid --size 3 --alpha 0.25 --device mechanistic --sigma 0.5 --record landers
/// --duration 10.5 --rtol R [--clutch-frequency-ratio 50]`), peak θ/α:
///
/// | rtol | default clutch, 25 p | 50 p |
/// |---|---|---|
/// | 1e-5 (default) | 1.811401e-2 | 1.44456e-2 (−1.9 %; −17 % before the flywheel velocity scale) |
/// | 1e-7 | 1.811097e-2 | 1.46550e-2 (−0.5 %) |
/// | 1e-9 | 1.811092e-2 | 1.47298e-2 (+6e-5) |
/// | 1e-11 | 1.811092e-2 | 1.47290e-2 |
/// | 1e-12 | 1.811092e-2 | 1.47290e-2 |
///
/// With the default clutch the peaks converge at the default tolerance (over 10.5 s and over
/// the whole record). With the stiffer clutch the rocking is tiny (θ ~ 0.015 α) and the peak
/// converges from rtol 1e-9, 1.9 % off at the default (resolving the free flywheels'
/// velocities at the clutch-deflection scale, `RigidBody::tolerance_scales`, took that from
/// 17 %). The rest is not the integrator, nor the reset at grazing crossings of δ̇: the exact
/// peak moves by 1.2 % when the record is scaled by 1 + 1e-7 (κ ~ 1e5; BENCHMARKS.md,
/// issue 17 session 8), so `sim::check` must call it ill-conditioned and the default clutch
/// converged. All three behaviours are asserted so a change to any shows.
#[test]
fn long_record_chattering_to_rest() {
    let scene = |device: Device, duration: f64| {
        let mut scene = rigid_fig8(device);
        scene.structure = Structure::Rigid(RigidBlock {
            size: 3.0,
            alpha: 0.25,
            mass: 1.0,
            form: Form::Exact,
        });
        scene.excitation = Excitation::Record {
            name: "landers".into(),
            scale: RecordScale::Factor(1.0),
            baseline: false,
            kinks: Default::default(),
        };
        scene.duration = duration;
        scene
    };
    let mechanistic = Device::Mechanistic(Clutch::paper_default(0.5));
    let stiff = clutch(|c| c.stiffness = ClutchStiffness::FrequencyRatio(50.0));
    for device in [Device::None, Device::Sequential { sigma: 0.5 }] {
        let r = assert_stable("Landers, R = 3 m, α = 0.25", &scene(device, 80.0), 1e-3);
        assert!(r.counters.impacts > 100, "{:?}", r.counters);
        assert_eq!(r.end_reason, rocklab::model::EndReason::Rest);
    }
    // The default clutch: converged at the default tolerance, over the strong motion and over
    // the whole record, and closer at each tighter tolerance.
    for duration in [10.5, 80.0] {
        let s = scene(mechanistic.clone(), duration);
        let reference = run_at(&s, 1e-11).peaks;
        let error = |rtol: f64| {
            let p = run_at(&s, rtol).peaks;
            let rel = |a: f64, b: f64| (a - b).abs() / b;
            rel(p.rotation, reference.rotation)
                .max(rel(p.abs_acceleration_g, reference.abs_acceleration_g))
        };
        let errors = [
            error(rocklab::scene::default_rtol()),
            error(1e-8),
            error(1e-10),
        ];
        println!("default clutch, {duration} s: peak errors at rtol 1e-5/1e-8/1e-10 {errors:?}");
        assert!(errors[0] < 1e-3, "{duration} s: {errors:?}");
        assert!(
            errors[1] < errors[0] && errors[2] < errors[1],
            "{duration} s: {errors:?}"
        );
    }
    // The stiff clutch: converged only at the tightest tolerances, far off at the default.
    let early = scene(stiff.clone(), 10.5);
    let (tight, tighter) = (run_at(&early, 1e-11), run_at(&early, 1e-12));
    let change = (tight.peaks.rotation - tighter.peaks.rotation).abs() / tighter.peaks.rotation;
    assert!(
        change < 1e-3,
        "mechanistic peak moved by {change:e} from 1e-11 to 1e-12"
    );
    let off = |rtol: f64| {
        let p = run_at(&early, rtol).peaks.rotation;
        (p - tighter.peaks.rotation).abs() / tighter.peaks.rotation
    };
    let (at_default, at_1e9) = (off(rocklab::scene::default_rtol()), off(1e-9));
    println!(
        "50 p clutch, 10.5 s: peak off by {at_default:.2e} at the default rtol, {at_1e9:.1e} at 1e-9"
    );
    assert!(
        at_1e9 < 1e-3 && at_default < 0.03,
        "{at_default:e} {at_1e9:e}"
    );
    // Converging as the tolerance tightens, by more than a decade per two decades of rtol.
    let errors = [1e-7, 1e-9, 1e-11].map(off);
    println!("50 p clutch, 10.5 s: peak off at rtol 1e-7/1e-9/1e-11 {errors:?}");
    assert!(
        errors[0] > 10.0 * errors[1] && errors[1] > 10.0 * errors[2],
        "{errors:?}"
    );
    // Why: the problem, not the integrator. Before the main pulse the block rocks at θ ~ 1e-4
    // rad with impacts every 5–10 ms, and there perturbations grow by ~1e5: at the reference
    // tolerance a change of 1e-7 in the record's amplitude moves this peak by ~1 %, so no
    // formulation converges it at rtol 1e-5 without changing the answer. (A reset hysteresis
    // of the corner's width, 5e-8 m, or 2e-7 m leaves κ as large; 1e-5 m cures it but moves
    // the peak by 8 %.) The same scene with the default clutch, the sequential law or no
    // device is well-conditioned, and `sim::check` tells the cases apart.
    let library = rocklab::excitation::library::global().unwrap();
    let checked = |s: &Scene| {
        let r = run_at(s, rocklab::scene::default_rtol());
        let c = rocklab::sim::check::check(s, &r, library, Default::default()).unwrap();
        println!("{}", c.report());
        c
    };
    let rotation_condition = |c: &rocklab::sim::check::Check| c.peaks[0].condition;
    let c = checked(&early);
    assert_eq!(
        c.verdict,
        rocklab::sim::check::Reproducibility::IllConditioned
    );
    assert!(rotation_condition(&c) > 1e4, "{}", c.report());
    assert!(off(c.suggested_rtol().unwrap()) < 1e-3, "{}", c.report());
    for device in [
        Device::None,
        Device::Sequential { sigma: 0.5 },
        Device::Mechanistic(Clutch::paper_default(0.5)),
    ] {
        let c = checked(&scene(device, 10.5));
        assert_eq!(c.verdict, rocklab::sim::check::Reproducibility::Converged);
        assert!(rotation_condition(&c) < 100.0, "{}", c.report());
    }
    for device in [mechanistic, stiff] {
        for rtol in [1e-6, 1e-9] {
            let r = run_at(&scene(device.clone(), 80.0), rtol);
            assert_eq!(r.end_reason, rocklab::model::EndReason::Rest);
            assert!(r.end_time < 60.0 && r.counters.impacts > 100, "{r:?}");
            assert!(
                r.energy_residual < 1e3 * rtol,
                "residual {}",
                r.energy_residual
            );
        }
    }
}

/// The flexible structure of Fig. 14 on the same hard cases: stiff clutch, 1 cm of play under
/// both reset rules, strong friction, a fast pulse.
#[test]
fn flexible_hard_cases() {
    let cases: Vec<(&str, Scene)> = vec![
        (
            "flexible, clutch frequency 1e3 p",
            flexible_fig14(clutch(|c| {
                c.stiffness = ClutchStiffness::FrequencyRatio(1e3)
            })),
        ),
        (
            "flexible, play 1 cm, paper rule",
            flexible_fig14(clutch(|c| c.play = 0.01)),
        ),
        (
            "flexible, play 1 cm, strict rule",
            flexible_fig14(clutch(|c| {
                c.play = 0.01;
                c.reset = ResetRule::Strict
            })),
        ),
        (
            "flexible, friction 0.2 mr g, eta 1e3",
            flexible_fig14(clutch(|c| {
                c.friction = 0.2;
                c.eta = 1e3;
            })),
        ),
        ("flexible, omega_g/p = 20", {
            let mut s = flexible_fig14(Device::Mechanistic(Clutch::paper_default(0.5)));
            s.excitation = Excitation::Pulse {
                shape: PulseShape::Sine,
                amplitude: Amplitude::TanAlphaRatio(3.0),
                frequency: Frequency::Ratio(20.0),
            };
            s
        }),
    ];
    for (name, scene) in cases {
        let r = assert_stable(name, &scene, 1e-3);
        assert!(r.peaks.deformation > 0.0 && r.peaks.deformation.is_finite());
    }
}
