//! A scene computes only the quantities asked for (issue 17.5), and what it computes is the
//! same as in a run that computes everything; the interpolant bounds the peak searches skip
//! steps by (issue 17.1) really bound it.

use rocklab::presets::{
    flexible_fig14, mechanistic, rigid_fig8, rigid_northridge, rigid_size_for_p, sequential,
};
use rocklab::report::Quantity;
use rocklab::scene::*;
use rocklab::sim::{self, Bounds, Measures, SceneResult};
use rocklab::solver::{Integrator, OdeSystem, Options};

fn run(scene: &Scene, measures: Measures) -> SceneResult {
    let bounds = Bounds {
        measures,
        ..Default::default()
    };
    sim::run_bounded(
        scene,
        rocklab::excitation::library::global().unwrap(),
        bounds,
    )
    .unwrap_or_else(|e| panic!("{e} for {scene:?}"))
}

/// Scenes with every device law, both structures, a pulse and a record; a rigid block with
/// a Dirac impact and one with free rocking (the ground at rest throughout, where the
/// acceleration bounds skip steps).
fn scenes() -> Vec<Scene> {
    let mut dirac = rigid_fig8(Device::None);
    dirac.impact = Impact::Dirac { width: 0.01 };
    let mut free = rigid_fig8(Device::Inerter {
        sigma: 0.5,
        coupling: Coupling::Rigid,
    });
    free.excitation = Excitation::Pulse {
        shape: rocklab::excitation::PulseShape::Sine,
        amplitude: Amplitude::G(0.0),
        frequency: Frequency::Ratio(4.0),
    };
    free.initial_rotation = 0.1;
    vec![
        rigid_fig8(Device::None),
        rigid_fig8(sequential()),
        rigid_fig8(mechanistic()),
        dirac,
        free,
        flexible_fig14(Device::None),
        flexible_fig14(mechanistic()),
        rigid_northridge(sequential()),
    ]
}

#[test]
fn each_quantity_alone_equals_it_in_the_full_set() {
    for scene in scenes() {
        let full = run(&scene, Measures::ALL);
        for q in Quantity::ALL {
            let alone = run(&scene, Quantity::measures(&[q]));
            // Same steps: the asked quantity is computed on the same dense outputs.
            assert_eq!(alone.stats, full.stats, "{q:?} in {scene:?}");
            assert_eq!(q.of(&alone), q.of(&full), "{q:?} in {scene:?}");
            assert_eq!(alone.end_time, full.end_time);
            // What was not asked is not reported (the rotation always is).
            for other in Quantity::ALL {
                if !other.measured_in(Quantity::measures(&[q])) {
                    assert_eq!(other.of(&alone), None, "{other:?} with only {q:?}");
                }
            }
        }
        let ledger = run(
            &scene,
            Measures {
                energy: true,
                ..Measures::ROTATION
            },
        );
        assert_eq!(ledger.energy, full.energy, "{scene:?}");
        assert_eq!(ledger.energy_residual, full.energy_residual, "{scene:?}");
        let rotation = run(&scene, Measures::ROTATION);
        assert_eq!(rotation.energy, Default::default());
    }
}

/// With `stop_when_settled` a run stops once no reachable motion can raise a peak it reports:
/// a rotation-only run may stop earlier than one that also waits on the accelerations, with
/// the same rotation.
#[test]
fn settling_waits_only_on_the_asked_peaks() {
    let mut scene = rigid_fig8(sequential());
    scene.stop_when_settled = true;
    scene.duration = 30.0;
    let full = run(&scene, Measures::ALL);
    let rotation = run(&scene, Measures::ROTATION);
    assert_eq!(rotation.peaks.rotation, full.peaks.rotation);
    assert!(rotation.end_time <= full.end_time);
}

/// A damped oscillator under a smooth force, stepped coarsely: its interpolant over each step
/// never leaves `Dense::bound`, nor its rate `Dense::rate_bound`.
#[test]
fn dense_output_bounds_hold_over_every_step() {
    struct Forced;
    impl OdeSystem<3> for Forced {
        fn rhs(&self, t: f64, y: &[f64; 3], d: &mut [f64; 3]) {
            d[0] = y[1];
            d[1] = -4.0 * y[0] - 0.3 * y[1] + (3.0 * t).sin();
            d[2] = y[0] * y[0];
        }
    }
    let mut integ = Integrator::new(Options {
        max_steps: 100_000,
        ..Options::new(1e-3, [1e-3; 3])
    });
    integ.restart(&Forced, 0.0, [1.0, -2.0, 0.0]);
    let mut steps = 0;
    while integ.t() < 20.0 {
        integ.step(&Forced, 20.0).unwrap();
        let dense = *integ.dense().unwrap();
        for i in 0..3 {
            let (bound, rate) = (dense.bound(i), dense.rate_bound(i));
            for k in 0..=400 {
                let t = dense.t0 + dense.h * k as f64 / 400.0;
                assert!(
                    dense.state(t)[i].abs() <= bound * (1.0 + 1e-12),
                    "y{i} at {t}"
                );
                assert!(
                    dense.derivative(t)[i].abs() <= rate * (1.0 + 1e-12),
                    "ẏ{i} at {t}"
                );
            }
        }
        steps += 1;
    }
    assert!(steps > 10);
}

/// `simulate --quantities` computes the named ones and reports the others as null.
#[test]
fn simulate_reports_only_the_asked_quantities() {
    let p = rigid_size_for_p(2.0).to_string();
    let json = crate::util::rocklab_json(&[
        "simulate",
        "--size",
        &p,
        "--alpha",
        "10deg",
        "--amplitude-alpha",
        "1.5",
        "--frequency-ratio",
        "4",
        "--quantities",
        "peak_rotation_ratio,peak_abs_acceleration",
        "--json",
    ]);
    assert!(json["peak_rotation_ratio"].as_f64().unwrap() > 0.1);
    assert!(json["peak_abs_acceleration_g"].as_f64().unwrap() > 0.1);
    assert!(json["peak_angular_acceleration_p2"].is_null());
    assert!(json["peak_drift"].is_null());
    assert!(json["energy"].is_null());
    let bad = crate::util::rocklab(&[
        "simulate",
        "--p",
        "2",
        "--alpha",
        "0.2",
        "--quantities",
        "speed",
    ]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("unknown quantity `speed`"));
}
