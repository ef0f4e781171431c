//! The closed-form full-contact path of the flexible structure (`Scene::exact_contact`):
//! the stepper alone against the analytic ramp response, and whole scenes against the
//! general integrator at tight tolerance, in contact throughout and with uplift.

use rocklab::excitation::KinkPolicy;
use rocklab::model::sdof::Oscillator;
use rocklab::scene::*;
use rocklab::sim::HistoryColumn;
use rocklab::sim::{self, SceneResult};

fn flexible(alpha: f64, device: Device, record: &str, duration: f64) -> Scene {
    Scene {
        vertical: None,
        structure: Structure::Flexible(FlexibleStructure {
            r0: 10.0,
            alpha,
            mass: 1.0,
            xi: 0.02,
            omega_n: 12.0,
        }),
        device,
        impact: Impact::default(),
        excitation: Excitation::Record {
            name: record.into(),
            scale: RecordScale::Factor(1.0),
            baseline: false,
            kinks: KinkPolicy::default(),
        },
        duration,
        rtol: default_rtol(),
        initial_rotation: 0.0,
        stop_when_settled: false,
        closed_form_contact: true,
        method: Default::default(),
    }
}

fn rigid_inerter() -> Device {
    Device::Inerter {
        sigma: 0.5,
        coupling: Coupling::Rigid,
    }
}

/// The same scene advanced in closed form (at the default tolerance, which only the rocking
/// phases use) and by the integrator throughout at `rtol`.
fn both(scene: &Scene, rtol: f64) -> (SceneResult, SceneResult) {
    let exact = sim::run(scene, rocklab::excitation::library::global().unwrap()).unwrap();
    let mut integrated = scene.clone();
    integrated.closed_form_contact = false;
    integrated.rtol = rtol;
    (
        exact,
        sim::run(&integrated, rocklab::excitation::library::global().unwrap()).unwrap(),
    )
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

/// Ramp f = b t from rest (Chopra §4.3): u = (b/ω²) (t − 2ζ/ω + e^{−ζωt} (2ζ/ω cos ωd t −
/// (1 − 2ζ²)/ωd sin ωd t)). Chained closed-form intervals reproduce it at roundoff, for
/// undamped and damped oscillators and intervals up to a quarter period.
#[test]
fn chained_intervals_reproduce_the_analytic_ramp_response() {
    let (omega, b) = (12.0, 3.0);
    for zeta in [0.0, 0.02, 0.3] {
        let wd = omega * (1.0f64 - zeta * zeta).sqrt();
        let exact = |t: f64| {
            let e = (-zeta * omega * t).exp();
            b / (omega * omega)
                * (t - 2.0 * zeta / omega
                    + e * (2.0 * zeta / omega * (wd * t).cos()
                        - (1.0 - 2.0 * zeta * zeta) / wd * (wd * t).sin()))
        };
        let osc = Oscillator::new(omega, zeta).unwrap();
        for steps in [1usize, 7, 400] {
            let t_end = 2.0;
            let h = t_end / steps as f64;
            let (mut u, mut v) = (0.0, 0.0);
            for i in 0..steps {
                let f0 = b * i as f64 * h;
                (u, v) = osc.segment(u, v, f0, b).state(h);
            }
            let want = exact(t_end);
            // Velocity by a central difference of the analytic displacement.
            let d = 1e-6;
            let want_v = (exact(t_end + d) - exact(t_end - d)) / (2.0 * d);
            assert!(
                (u - want).abs() < 1e-13 * want.abs(),
                "ζ {zeta}, {steps} steps: u {u} vs {want}"
            );
            assert!(
                (v - want_v).abs() < 1e-8 * want_v.abs(),
                "ζ {zeta}, {steps} steps: v {v} vs {want_v}"
            );
        }
    }
}

/// A wide base never lifts under Northridge: the whole run is the fixed-base SDOF, advanced
/// in closed form, and the integrator at rtol 1e-13 agrees on every peak and on the final
/// state and energies to ~1e-9, bare and with a rigid inerter. (At rtol 1e-12 the
/// integrator's acceleration peak of the bare column is 1e-6 low: `refined_max` refines a step
/// only when a sample beats the running peak, and a maximum just past one step's end leaves the
/// next step's first sample only tying it; at 1e-8, 1e-10 and 1e-13 it agrees with the closed
/// form to 2e-8, 1e-9, 5e-12.)
#[test]
fn in_full_contact_the_closed_form_matches_the_tight_integrator() {
    for device in [Device::None, rigid_inerter()] {
        let scene = flexible(1.3, device.clone(), "northridge", 25.0);
        let (exact, integrated) = both(&scene, 1e-13);
        assert_eq!(
            exact.counters.uplifts, 0,
            "{device:?}: the base must stay down"
        );
        assert_eq!(integrated.counters.uplifts, 0);
        assert!(exact.stats.closed_form_steps > 2000, "{:?}", exact.stats);
        assert_eq!((exact.stats.steps, exact.stats.rhs_evals), (0, 0));
        assert_eq!(integrated.stats.closed_form_steps, 0);
        let pairs = [
            (exact.peaks.deformation, integrated.peaks.deformation),
            (exact.peaks.drift, integrated.peaks.drift),
            (
                exact.peaks.abs_acceleration_g,
                integrated.peaks.abs_acceleration_g,
            ),
            (exact.energy.input, integrated.energy.input),
            (exact.energy.structure, integrated.energy.structure),
            (exact.energy.inerter, integrated.energy.inerter),
            (
                exact.energy.column_damping,
                integrated.energy.column_damping,
            ),
        ];
        for (i, (a, b)) in pairs.into_iter().enumerate() {
            if b != 0.0 {
                assert!(relative(a, b) < 1e-9, "{device:?} #{i}: {a} vs {b}");
            } else {
                assert_eq!(a, 0.0, "{device:?} #{i}");
            }
        }
        assert_eq!(exact.end_time, integrated.end_time);
        assert!(
            exact.energy_residual < 1e-12,
            "{device:?}: {}",
            exact.energy_residual
        );
    }
}

/// The Fig. 24 structure (R0 = 10 m, α = 0.2, ξ = 0.02, ωn = 12 rad/s) lifts off many times
/// under Landers and Northridge: the closed-form contact phases hand over to the integrator at
/// the located uplift, and peaks, counts and energy agree with the integrator throughout to
/// its own accuracy at rtol 1e-10.
#[test]
fn with_uplift_the_hand_over_keeps_the_integrator_peaks() {
    for (record, device) in [
        ("landers", Device::None),
        ("landers", rigid_inerter()),
        ("northridge", Device::None),
        ("northridge", rigid_inerter()),
    ] {
        let duration = if record == "landers" { 58.0 } else { 30.0 };
        let mut scene = flexible(0.2, device.clone(), record, duration);
        scene.rtol = 1e-10;
        let (exact, integrated) = both(&scene, 1e-10);
        let tag = format!("{record} {device:?}");
        assert!(exact.counters.uplifts > 5, "{tag}: {:?}", exact.counters);
        assert_eq!(exact.counters, integrated.counters, "{tag}");
        assert!(
            exact.stats.closed_form_steps > 0 && exact.stats.steps > 0,
            "{tag}"
        );
        let pairs = [
            (exact.peaks.rotation, integrated.peaks.rotation),
            (exact.peaks.deformation, integrated.peaks.deformation),
            (exact.peaks.drift, integrated.peaks.drift),
            (
                exact.peaks.abs_acceleration_g,
                integrated.peaks.abs_acceleration_g,
            ),
        ];
        for (i, (a, b)) in pairs.into_iter().enumerate() {
            assert!(relative(a, b) < 1e-7, "{tag} peak #{i}: {a} vs {b}");
        }
        assert!(
            exact.energy_residual < 1e-8,
            "{tag}: {}",
            exact.energy_residual
        );
        assert!(
            exact.energy_residual <= 10.0 * integrated.energy_residual.max(1e-11),
            "{tag}: {} vs {}",
            exact.energy_residual,
            integrated.energy_residual
        );
    }
}

/// The uplift is located on the closed form: the first lift-off of the Fig. 24 structure under
/// Landers is where the integrator (rtol 1e-10) locates it, and the history has a row at every
/// record sample of the contact phase before it.
#[test]
fn uplift_is_located_where_the_integrator_finds_it_and_history_keeps_every_sample() {
    let mut scene = flexible(0.2, Device::None, "landers", 58.0);
    scene.rtol = 1e-10;
    let first_uplift = |s: &Scene| {
        let (_, h) =
            sim::run_with_history(s, rocklab::excitation::library::global().unwrap(), true)
                .unwrap();
        let h = h.unwrap();
        let t = h
            .events
            .iter()
            .find(|(_, name)| *name == "uplift")
            .expect("the base lifts")
            .0;
        let times = h.column(HistoryColumn::T).unwrap();
        (
            t,
            times.into_iter().filter(|&ti| ti < t).collect::<Vec<_>>(),
        )
    };
    let (t_exact, rows) = first_uplift(&scene);
    let mut integrated = scene.clone();
    integrated.closed_form_contact = false;
    let (t_integrated, _) = first_uplift(&integrated);
    assert!(
        (t_exact - t_integrated).abs() < 1e-9,
        "{t_exact} vs {t_integrated}"
    );
    // Landers is sampled at 0.005 s from t = 0.
    let samples_before = (t_exact / 0.005).ceil() as usize;
    assert!(rows.len() >= samples_before, "{} rows", rows.len());
    for k in (0..samples_before).step_by(97) {
        let tk = k as f64 * 0.005;
        assert!(
            rows.iter().any(|&t| (t - tk).abs() < 1e-9),
            "no row at sample {k}"
        );
    }
}

/// Where the contact phase is not a linear oscillator under piecewise-linear forcing (a
/// switching or clutched device, an analytic pulse) or the scene asks for the integrator,
/// nothing is advanced in closed form; a scene file without the option gets the default.
#[test]
fn closed_form_only_where_it_is_exact() {
    let counts = |s: &Scene| {
        sim::run(s, rocklab::excitation::library::global().unwrap())
            .unwrap()
            .stats
            .closed_form_steps
    };
    let short = |device| flexible(0.2, device, "northridge", 3.0);
    assert!(counts(&short(Device::None)) > 0);
    assert!(counts(&short(rigid_inerter())) > 0);
    assert_eq!(counts(&short(Device::Sequential { sigma: 0.5 })), 0);
    assert_eq!(
        counts(&short(Device::Mechanistic(Clutch::paper_default(0.5)))),
        0
    );
    let mut forced = short(Device::None);
    forced.closed_form_contact = false;
    assert_eq!(counts(&forced), 0);
    let mut pulse = short(Device::None);
    pulse.excitation = Excitation::Pulse {
        shape: rocklab::excitation::PulseShape::Sine,
        amplitude: Amplitude::TanAlphaRatio(0.8),
        frequency: Frequency::RadPerSec(8.0),
    };
    assert_eq!(counts(&pulse), 0);
    // A critically damped or overdamped column has no oscillatory closed form here.
    let mut overdamped = short(Device::None);
    if let Structure::Flexible(f) = &mut overdamped.structure {
        f.xi = 1.2;
    }
    assert_eq!(counts(&overdamped), 0);

    let text = ron::to_string(&short(Device::None)).unwrap();
    let without = text.replace(",exact_contact:true", "");
    assert_ne!(text, without, "the option is serialised: {text}");
    let parsed: Scene = ron::from_str(&without).unwrap();
    assert!(parsed.closed_form_contact);
}

/// The settled-tail cut works on the closed-form path as on the integrator's: same peaks, an
/// earlier end, and the energy still balances.
#[test]
fn settled_tail_cut_on_the_closed_form_keeps_the_peaks() {
    let full = flexible(1.3, Device::None, "northridge", 40.0);
    let mut cut = full.clone();
    cut.stop_when_settled = true;
    let (a, b) = (
        sim::run(&full, rocklab::excitation::library::global().unwrap()).unwrap(),
        sim::run(&cut, rocklab::excitation::library::global().unwrap()).unwrap(),
    );
    assert_eq!(b.end_reason, rocklab::model::EndReason::Settled);
    assert!(
        b.end_time < 0.9 * a.end_time,
        "{} vs {}",
        b.end_time,
        a.end_time
    );
    assert_eq!(a.peaks, b.peaks);
    assert!(b.energy_residual < 1e-12, "{}", b.energy_residual);
}

/// A maximum just past an interval's first sample, which equals the running peak (it was the
/// previous interval's end), is still found between the samples.
#[test]
fn sampled_maximum_is_refined_when_the_first_sample_ties_the_running_peak() {
    let f = |t: f64| 1.0 - (t - 0.1).powi(2);
    let samples: Vec<(f64, f64)> = (0..=4)
        .map(|k| (k as f64 / 4.0, f(k as f64 / 4.0)))
        .collect();
    // The running peak, from the previous interval's end, a roundoff above this first sample.
    let floor = samples[0].1 + 1e-15;
    let peak = rocklab::model::refined_max_of_samples(f, &samples, floor);
    assert!((peak - 1.0).abs() < 1e-12, "{peak}");
}
