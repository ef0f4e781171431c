//! Scenes under records and the new pulse families: convergence, serde, validation.

use rocklab::excitation::{KinkPolicy, PulseShape};
use rocklab::scene::{
    Amplitude, Clutch, Device, Excitation, Form, Frequency, Impact, RecordScale, RigidBlock, Scene,
    Structure,
};
use rocklab::sim;
use rocklab::sim::HistoryColumn;

fn scene(excitation: Excitation, device: Device, rtol: f64) -> Scene {
    Scene {
        vertical: None,
        structure: Structure::Rigid(RigidBlock {
            size: 2.0,
            alpha: 0.2,
            mass: 1.0,
            form: Form::Exact,
        }),
        device,
        impact: Impact::default(),
        excitation,
        duration: 8.0,
        rtol,
        initial_rotation: 0.0,
        stop_when_settled: false,
        closed_form_contact: true,
        method: Default::default(),
    }
}

fn northridge(factor: f64) -> Excitation {
    Excitation::Record {
        name: "northridge".into(),
        scale: RecordScale::Factor(factor),
        baseline: false,
        kinks: KinkPolicy::StopAtSamples,
    }
}

#[test]
fn a_record_scene_converges_as_the_tolerance_tightens() {
    let run = |rtol| {
        sim::run(
            &scene(
                northridge(0.6),
                Device::Mechanistic(Clutch::paper_default(0.5)),
                rtol,
            ),
            rocklab::excitation::library::global().unwrap(),
        )
        .unwrap()
    };
    let reference = run(1e-11);
    assert!(!reference.overturned && reference.counters.uplifts >= 1);
    assert!(reference.counters.resets > 0 && reference.counters.impacts > 0);
    let err = |rtol| (run(rtol).peaks.rotation - reference.peaks.rotation).abs();
    let (e5, e7, e9) = (err(1e-5), err(1e-7), err(1e-9));
    assert!(e9 < e7 && e7 < e5, "{e5:e} {e7:e} {e9:e}");
    assert!(e9 < 1e-7 * reference.peaks.rotation, "{e9:e}");
    assert!(
        reference.energy_residual < 1e-8,
        "{}",
        reference.energy_residual
    );
}

#[test]
fn polarity_flip_mirrors_the_response() {
    // docs/MODEL.md: flipping the excitation's sign leaves every peak unchanged.
    let up = sim::run(
        &scene(northridge(0.5), Device::None, 1e-9),
        rocklab::excitation::library::global().unwrap(),
    )
    .unwrap();
    let down = sim::run(
        &scene(northridge(-0.5), Device::None, 1e-9),
        rocklab::excitation::library::global().unwrap(),
    )
    .unwrap();
    assert!(up.peaks.rotation > 0.0);
    assert!((up.peaks.rotation - down.peaks.rotation).abs() < 1e-9 * up.peaks.rotation);
    assert_eq!(up.counters.impacts, down.counters.impacts);
}

#[test]
fn the_uplift_starts_where_the_record_first_exceeds_g_tan_alpha() {
    // Bare block at rest: nothing moves until |a_g| > g tan α, located exactly on the record.
    let s = scene(northridge(0.6), Device::None, 1e-9);
    let (_, history) =
        sim::run_with_history(&s, rocklab::excitation::library::global().unwrap(), true).unwrap();
    let h = history.unwrap();
    let (t, theta) = (
        h.column(HistoryColumn::T).unwrap(),
        h.column(HistoryColumn::Theta).unwrap(),
    );
    let first_move = t[theta.iter().position(|th| *th != 0.0).unwrap()];
    let motion = sim::motion_for(&s, rocklab::excitation::library::global().unwrap()).unwrap();
    let onset = motion
        .first_exceedance(0.0, rocklab::excitation::G * 0.2f64.tan())
        .unwrap();
    assert!(
        first_move >= onset && first_move < onset + 0.01,
        "{onset} {first_move}"
    );
}

#[test]
fn scenes_with_new_excitations_round_trip_through_ron() {
    let excitations = [
        Excitation::Record {
            name: "landers".into(),
            scale: RecordScale::Pgv(0.8),
            baseline: true,
            kinks: KinkPolicy::StepOver,
        },
        Excitation::MpPulse {
            tp: 1.2,
            pgv: 0.5,
            gamma: 2.2,
            nu: 0.3,
        },
        Excitation::Pulse {
            shape: PulseShape::MavroeidisPapageorgiou {
                gamma: 2.0,
                nu: 0.0,
            },
            amplitude: Amplitude::TanAlphaRatio(1.5),
            frequency: Frequency::Ratio(4.0),
        },
    ];
    for e in excitations {
        let s = scene(e, Device::None, 1e-6);
        let text = ron::to_string(&s).unwrap();
        assert_eq!(ron::from_str::<Scene>(&text).unwrap(), s);
    }
    // Defaults and strictness.
    let short: Excitation = ron::from_str(r#"record(name: "1")"#).unwrap();
    assert_eq!(
        short,
        Excitation::Record {
            name: "1".into(),
            scale: RecordScale::Factor(1.0),
            baseline: false,
            kinks: KinkPolicy::StopAtSamples
        }
    );
    assert!(ron::from_str::<Excitation>(r#"record(name: "1", scal: factor(2.0))"#).is_err());
}

#[test]
fn invalid_record_and_pulse_values_name_their_field() {
    let bad = [
        (northridge(f64::NAN), "scale"),
        (
            Excitation::Record {
                name: " ".into(),
                scale: RecordScale::Factor(1.0),
                baseline: false,
                kinks: KinkPolicy::default(),
            },
            "record",
        ),
        (
            Excitation::Record {
                name: "landers".into(),
                scale: RecordScale::Pga(0.0),
                baseline: false,
                kinks: KinkPolicy::default(),
            },
            "scale_pga",
        ),
        (
            Excitation::MpPulse {
                tp: 1.0,
                pgv: 0.5,
                gamma: 1.0,
                nu: 0.0,
            },
            "gamma",
        ),
        (
            Excitation::MpPulse {
                tp: -1.0,
                pgv: 0.5,
                gamma: 2.0,
                nu: 0.0,
            },
            "tp",
        ),
    ];
    for (e, field) in bad {
        let err = scene(e, Device::None, 1e-6).validate().unwrap_err();
        assert_eq!(err.field, field);
    }
    let unknown = sim::run(
        &scene(
            Excitation::Record {
                name: "no_such_record".into(),
                scale: RecordScale::Factor(1.0),
                baseline: false,
                kinks: KinkPolicy::default(),
            },
            Device::None,
            1e-6,
        ),
        rocklab::excitation::library::global().unwrap(),
    )
    .unwrap_err()
    .to_string();
    assert!(unknown.contains("unknown record 'no_such_record'") && unknown.contains("landers"));
}

#[test]
fn scaling_to_pga_reaches_the_target_on_the_ground() {
    let s = scene(
        Excitation::Record {
            name: "superstition_hills".into(),
            scale: RecordScale::Pga(0.3),
            baseline: false,
            kinks: KinkPolicy::default(),
        },
        Device::None,
        1e-6,
    );
    let m = sim::motion_for(&s, rocklab::excitation::library::global().unwrap()).unwrap();
    assert!((m.peak_abs(0.0, m.end()) / rocklab::excitation::G - 0.3).abs() < 1e-12);
}

#[test]
fn a_record_below_the_uplift_threshold_leaves_the_block_at_rest() {
    // The imperial_valley stand-in peaks at 0.059 g < tan 0.2: the block rides the ground and
    // its absolute acceleration is the record's PGA.
    let s = scene(
        Excitation::Record {
            name: "imperial_valley".into(),
            scale: RecordScale::Factor(1.0),
            baseline: false,
            kinks: KinkPolicy::default(),
        },
        Device::None,
        1e-6,
    );
    let r = sim::run(&s, rocklab::excitation::library::global().unwrap()).unwrap();
    let m = sim::motion_for(&s, rocklab::excitation::library::global().unwrap()).unwrap();
    let pga_g = m.peak_abs(0.0, m.end()) / rocklab::excitation::G;
    assert!(pga_g > 0.05 && pga_g < 0.2f64.tan());
    assert_eq!((r.counters.uplifts, r.peaks.rotation), (0, 0.0));
    assert!((r.peaks.abs_acceleration_g - pga_g).abs() < 1e-12);
}

/// Steps of a history that straddle a record sample (dt = 0.01 s) while the block rocks.
fn straddling_steps(kinks: KinkPolicy) -> (usize, f64) {
    let s = scene(
        Excitation::Record {
            name: "northridge".into(),
            scale: RecordScale::Factor(0.5),
            baseline: false,
            kinks,
        },
        Device::None,
        1e-10,
    );
    let (result, history) =
        sim::run_with_history(&s, rocklab::excitation::library::global().unwrap(), true).unwrap();
    let h = history.unwrap();
    let (t, th, om) = (
        h.column(HistoryColumn::T).unwrap(),
        h.column(HistoryColumn::Theta).unwrap(),
        h.column(HistoryColumn::ThetaDot).unwrap(),
    );
    let dt = 0.01;
    let end = sim::motion_for(&s, rocklab::excitation::library::global().unwrap())
        .unwrap()
        .end();
    // Integrator steps only: a row at rest on the ground starts an idle gap (the history has
    // no row where the block wakes up).
    let moving = |i: usize| th[i] != 0.0 || om[i] != 0.0;
    let straddles = (0..t.len() - 1)
        .filter(|&i| t[i + 1] <= end && t[i + 1] > t[i] && moving(i))
        .filter(|&i| {
            let next_sample = ((t[i] / dt + 1e-6).floor() + 1.0) * dt;
            next_sample < t[i + 1] - 1e-9
        })
        .count();
    (straddles, result.peaks.rotation)
}

#[test]
fn stop_at_samples_never_steps_across_a_sample_and_agrees_with_step_over() {
    let (stop, peak_stop) = straddling_steps(KinkPolicy::StopAtSamples);
    let (over, peak_over) = straddling_steps(KinkPolicy::StepOver);
    assert_eq!(stop, 0);
    assert!(over > 100, "{over}");
    // Bare block (contact is skipped exactly, nothing to miss): both policies converge to the
    // same peak (BENCHMARKS.md, "Records: kinks between samples").
    assert!(
        (peak_stop - peak_over).abs() < 1e-6 * peak_stop,
        "{peak_stop} {peak_over}"
    );
}
