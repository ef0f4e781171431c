//! The rigid block against docs/MODEL.md's public cases 1–5 and 7, closed forms, symmetry,
//! convergence and the energy balance.

use rocklab::excitation::{G, PulseShape};
use rocklab::model::EndReason;
use rocklab::model::rigid::{housner_restitution, inerter_restitution};
use rocklab::scene::*;
use rocklab::sim::HistoryColumn;
use rocklab::sim::{self, SceneResult};

const ALPHA_10: f64 = 10.0 * std::f64::consts::PI / 180.0;

/// Size of a block with frequency parameter p.
fn size_for_p(p: f64) -> f64 {
    3.0 * G / (4.0 * p * p)
}

fn pulse(amplitude: Amplitude, ratio: f64) -> Excitation {
    Excitation::Pulse {
        shape: PulseShape::Sine,
        amplitude,
        frequency: Frequency::Ratio(ratio),
    }
}

/// The paper's Fig. 8 scene (α = 10°, p = 2 rad/s, one-sine A/(gα) = 1.5, ωg/p = 4, 10 s)
/// at rtol 1e-8.
fn fig8(device: Device) -> Scene {
    Scene {
        rtol: 1e-8,
        ..rocklab::presets::rigid_fig8(device)
    }
}

fn mechanistic() -> Device {
    Device::Mechanistic(Clutch::paper_default(0.5))
}

fn all_devices() -> Vec<(&'static str, Device)> {
    vec![
        ("none", Device::None),
        (
            "inerter",
            Device::Inerter {
                sigma: 0.5,
                coupling: Coupling::Rigid,
            },
        ),
        (
            "inerter-flywheel",
            Device::Inerter {
                sigma: 0.5,
                coupling: Coupling::Flywheel {
                    stiffness: ClutchStiffness::FrequencyRatio(50.0),
                    rho: 0.05,
                    damping: Damping::CBar(1.0),
                },
            },
        ),
        ("sequential", Device::Sequential { sigma: 0.5 }),
        ("mechanistic", mechanistic()),
    ]
}

fn run(scene: &Scene) -> SceneResult {
    sim::run(scene, rocklab::excitation::library::global().unwrap()).expect("scene runs")
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

// Case 1.
#[test]
fn eq16_reduces_to_housner_and_grows_with_sigma() {
    for alpha_deg in [5.0f64, 10.0, 20.0, 30.0] {
        let a = alpha_deg.to_radians();
        assert!((inerter_restitution(a, 0.0) - housner_restitution(a)).abs() < 1e-15);
        let mut last = housner_restitution(a);
        for sigma in [0.1, 0.5, 1.0, 2.0, 5.0] {
            let r = inerter_restitution(a, sigma);
            assert!(r > last && r < 1.0, "α={alpha_deg}° σ={sigma}: r={r}");
            last = r;
        }
    }
    // Housner's value for α = 10°: (1 − 1.5 sin²10°)² = 0.911598…
    assert!((housner_restitution(ALPHA_10) - 0.911_584_7).abs() < 1e-6);
    // The inerter matters more for stocky blocks (Fig. 3).
    let gain = |deg: f64| {
        inerter_restitution(deg.to_radians(), 1.0) / housner_restitution(deg.to_radians())
    };
    assert!(gain(30.0) > gain(10.0));
}

// Case 2: free rocking of a slender bare block, θ = α − (α − θ0) cosh(pt) between impacts.
#[test]
fn slender_free_rocking_matches_closed_form() {
    let (alpha, p, theta0) = (0.2, 2.0, 0.15);
    let scene = Scene {
        vertical: None,
        structure: Structure::Rigid(RigidBlock {
            size: size_for_p(p),
            alpha,
            mass: 1.0,
            form: Form::Slender,
        }),
        device: Device::None,
        impact: Impact::default(),
        excitation: pulse(Amplitude::G(0.0), 1.0),
        duration: 6.0,
        rtol: 1e-11,
        initial_rotation: theta0,
        stop_when_settled: false,
        closed_form_contact: true,
        method: Default::default(),
    };
    let (result, history) = sim::run_with_history(
        &scene,
        rocklab::excitation::library::global().unwrap(),
        true,
    )
    .unwrap();
    let history = history.unwrap();
    let r = housner_restitution(alpha);
    // Closed form, half-cycle by half-cycle: starting at rest from amplitude a, the block
    // reaches θ = 0 after acosh(α/(α − a))/p; the next half-cycle starts at θ = 0 with
    // θ̇² = r p² (α² − (α − a)²) and returns to θ = 0 after twice the time to its peak.
    let impact_times: Vec<f64> = history
        .events
        .iter()
        .filter(|(_, k)| *k == "impact")
        .map(|(t, _)| *t)
        .collect();
    assert!(impact_times.len() >= 5, "{impact_times:?}");
    let mut t = (alpha / (alpha - theta0)).acosh() / p;
    let mut amplitude = theta0;
    for (n, &measured) in impact_times.iter().take(8).enumerate() {
        assert!(
            rel(measured, t) < 1e-6,
            "impact {n}: t = {measured}, closed form {t}"
        );
        // Amplitude after this impact, from energy: (α − a')² = α² − r (α² − (α − a)²).
        amplitude =
            alpha - (alpha * alpha - r * (alpha * alpha - (alpha - amplitude).powi(2))).sqrt();
        t += 2.0 * (alpha / (alpha - amplitude)).acosh() / p;
    }
    // The peak rotation is θ0 itself, and the run conserves energy through the ledger.
    assert!(rel(result.peaks.rotation, theta0) < 1e-12);
    assert!(
        result.energy_residual < 1e-8,
        "residual {}",
        result.energy_residual
    );
    // Between impacts the history follows α − (α − θ0) cosh(pt) exactly.
    let t_first = impact_times[0];
    let (ts, thetas) = (
        history.column(HistoryColumn::T).unwrap(),
        history.column(HistoryColumn::Theta).unwrap(),
    );
    for (t, theta) in ts.iter().zip(&thetas).filter(|(t, _)| **t < t_first) {
        let exact = alpha - (alpha - theta0) * (p * t).cosh();
        assert!(
            (theta - exact).abs() < 1e-8 * alpha,
            "t={t}: {theta} vs {exact}"
        );
    }
}

// Case 3: no damping, elastic impacts (r = 1), no friction: energy is conserved over many
// clutch engagement cycles.
#[test]
fn mechanistic_clutch_conserves_energy_without_dissipation() {
    let mut clutch = Clutch::paper_default(0.5);
    clutch.damping = Damping::CBar(0.0);
    // A stiff clutch (√(k/mr) = 50 p) engages and resets often enough in 20 s for the test to
    // cover many cycles (at the default 25 p: 5 engagements, 4 resets).
    clutch.stiffness = ClutchStiffness::FrequencyRatio(50.0);
    let mut scene = fig8(Device::Mechanistic(clutch));
    scene.impact = Impact::Housner {
        restitution: Some(1.0),
    };
    scene.duration = 20.0;
    scene.rtol = 1e-10;
    let r = run(&scene);
    assert!(
        r.counters.engagements >= 2 && r.counters.resets >= 5,
        "{:?}",
        r.counters
    );
    assert!(r.counters.impacts >= 10);
    let e = r.energy;
    assert_eq!(e.impact, 0.0);
    assert_eq!(e.device_damping, 0.0);
    // Everything the ground put in is still stored (resets move ~1e-11 J of spring energy).
    assert!(r.energy_residual < 1e-7, "residual {}", r.energy_residual);
    assert!(e.reset.abs() < 1e-8 * e.input, "reset losses {}", e.reset);
    assert!(rel(e.structure + e.inerter, e.input) < 1e-6);
}

// Case 4 (Fig. 8): bare > single inerter > sequential ≳ mechanistic.
#[test]
fn fig8_ordering_of_peak_rotations() {
    let bare = run(&fig8(Device::None));
    let inerter = run(&fig8(Device::Inerter {
        sigma: 0.5,
        coupling: Coupling::Rigid,
    }));
    let sequential = run(&fig8(Device::Sequential { sigma: 0.5 }));
    let mech = run(&fig8(mechanistic()));
    let (b, i, s, m) = (
        bare.peaks.rotation,
        inerter.peaks.rotation,
        sequential.peaks.rotation,
        mech.peaks.rotation,
    );
    println!(
        "peak θ/α: bare {:.4}, inerter {:.4}, sequential {:.4}, mechanistic {:.4}",
        b / ALPHA_10,
        i / ALPHA_10,
        s / ALPHA_10,
        m / ALPHA_10
    );
    assert!(b > i && i > s && s >= m, "{b} {i} {s} {m}");
    // The protected ones lie within ~30% of each other.
    assert!(i / m < 1.3, "inerter/mechanistic = {}", i / m);
    // Sequential decays faster: it comes to rest before the mechanistic model does.
    assert_eq!(sequential.end_reason, EndReason::Rest);
    let mech_rest = if mech.end_reason == EndReason::Rest {
        mech.end_time
    } else {
        f64::INFINITY
    };
    assert!(sequential.end_time < mech_rest);
    // The mechanistic clutch engages and resets repeatedly.
    assert!(
        mech.counters.engagements >= 10 && mech.counters.resets >= 10,
        "{:?}",
        mech.counters
    );
    // A rigidly attached inerter never engages anything; the sequential law engages on every
    // growing half-cycle.
    assert_eq!(inerter.counters.engagements, 0);
    assert!(sequential.counters.engagements >= sequential.counters.impacts);
}

// Case 5 (Fig. 12): the bare block α = 10°, A/(gα) = 1.5 overturns below ωg/p ≈ 3.
#[test]
fn overturning_boundary_of_the_bare_block_is_near_three() {
    let overturns = |ratio: f64| {
        let mut s = fig8(Device::None);
        s.excitation = pulse(Amplitude::AlphaRatio(1.5), ratio);
        s.rtol = 1e-9;
        run(&s).overturned
    };
    assert!(overturns(2.0));
    assert!(!overturns(4.0));
    let (mut lo, mut hi) = (2.0, 4.0);
    for _ in 0..30 {
        let mid = 0.5 * (lo + hi);
        if overturns(mid) { lo = mid } else { hi = mid }
    }
    println!("overturning boundary ωg/p = {lo:.6}");
    assert!((2.6..3.4).contains(&lo), "boundary at {lo}");
}

// Case 7 (Fig. 5): the Dirac-delta impact converges, linearly in n, to Housner with the
// effective restitution of the 99% zone, r_eff = 1 − erf(1.8215)(1 − r), which is itself within
// 0.1% of Housner's rotation for α = 10°.
#[test]
fn dirac_impact_converges_to_housner() {
    let with = |impact: Impact| {
        let mut s = fig8(Device::None);
        s.impact = impact;
        s.rtol = 1e-9;
        run(&s)
    };
    let housner = with(Impact::default());
    let r_eff = 1.0 - libm_erf(1.8215) * (1.0 - housner_restitution(ALPHA_10));
    let effective = with(Impact::Housner {
        restitution: Some(r_eff),
    });
    assert!(rel(effective.peaks.rotation, housner.peaks.rotation) < 1e-3);
    let errors: Vec<f64> = [1e-3, 1e-4, 1e-5]
        .iter()
        .map(|&n| {
            rel(
                with(Impact::Dirac { width: n }).peaks.rotation,
                effective.peaks.rotation,
            )
        })
        .collect();
    println!("Dirac peak error against r_eff at n = 1e-3, 1e-4, 1e-5: {errors:?}");
    // Linear convergence: each tenfold narrower zone cuts the error about tenfold.
    assert!(
        errors[1] < errors[0] / 5.0 && errors[2] < errors[1] / 5.0,
        "{errors:?}"
    );
    assert!(errors[2] < 5e-4);
    let fine = with(Impact::Dirac { width: 1e-4 });
    assert!(rel(fine.peaks.rotation, housner.peaks.rotation) < 5e-3);
    assert_eq!(fine.counters.impacts, housner.counters.impacts);
    // The energy the Gaussian moment removes is booked as impact loss and closes the balance.
    assert!(fine.energy.impact > 0.0);
    assert!(
        fine.energy_residual < 1e-6,
        "residual {}",
        fine.energy_residual
    );
}

/// erf by its series (|x| ≤ 2 is all this test needs).
fn libm_erf(x: f64) -> f64 {
    let mut term = x;
    let mut sum = x;
    for n in 1..60 {
        term *= -x * x / n as f64;
        sum += term / (2 * n + 1) as f64;
    }
    2.0 / std::f64::consts::PI.sqrt() * sum
}

#[test]
fn flipping_the_excitation_mirrors_the_response() {
    for (name, device) in all_devices() {
        let up = fig8(device.clone());
        let mut down = up.clone();
        down.excitation = pulse(Amplitude::AlphaRatio(-1.5), 4.0);
        let (a, b) = (run(&up), run(&down));
        assert!(
            rel(a.peaks.rotation, b.peaks.rotation) < 1e-9,
            "{name}: {} vs {}",
            a.peaks.rotation,
            b.peaks.rotation
        );
        assert!(
            rel(a.peaks.abs_acceleration_g, b.peaks.abs_acceleration_g) < 1e-9,
            "{name}"
        );
        assert_eq!(a.counters, b.counters, "{name}");
    }
}

#[test]
fn peaks_converge_as_the_tolerance_tightens() {
    for (name, device) in all_devices() {
        let at = |rtol: f64| {
            let mut s = fig8(device.clone());
            s.rtol = rtol;
            run(&s).peaks.rotation
        };
        let reference = at(1e-12);
        let errors: Vec<f64> = [1e-5, 1e-7, 1e-9]
            .iter()
            .map(|&t| rel(at(t), reference))
            .collect();
        println!("{name}: peak rotation errors at rtol 1e-5/1e-7/1e-9: {errors:?}");
        assert!(errors[0] < 1e-3, "{name}: {errors:?}");
        assert!(errors[2] < 1e-6, "{name}: {errors:?}");
        assert!(errors[2] < errors[0], "{name}: {errors:?}");
    }
}

#[test]
fn energy_balance_closes_for_every_device() {
    for (name, device) in all_devices() {
        for rtol in [1e-6, 1e-9] {
            let mut s = fig8(device.clone());
            s.rtol = rtol;
            let r = run(&s);
            println!("{name} rtol {rtol:e}: residual {:.2e}", r.energy_residual);
            assert!(
                r.energy_residual < 100.0 * rtol,
                "{name} at {rtol}: residual {}",
                r.energy_residual
            );
        }
    }
    // Friction and play too, with the strict reset rule.
    let mut c = Clutch::paper_default(0.5);
    c.friction = 0.1;
    c.play = 0.005;
    c.reset = ResetRule::Strict;
    let mut s = fig8(Device::Mechanistic(c));
    s.rtol = 1e-9;
    let r = run(&s);
    assert!(r.energy.friction > 0.0);
    assert!(r.energy_residual < 1e-7, "residual {}", r.energy_residual);
}

#[test]
fn sequential_books_the_energy_its_law_creates() {
    let r = run(&fig8(Device::Sequential { sigma: 0.5 }));
    // Disengagements lose energy; engagements at nonzero velocity create some back.
    assert!(r.energy.disengagement > 0.0);
    assert!(r.energy_residual < 1e-6);
}

#[test]
fn uplift_needs_ground_acceleration_above_g_tan_alpha() {
    let mut below = fig8(Device::None);
    below.excitation = pulse(Amplitude::TanAlphaRatio(0.999), 4.0);
    let r = run(&below);
    assert_eq!(r.counters.uplifts, 0);
    assert_eq!(r.peaks.rotation, 0.0);
    assert_eq!(
        r.stats.steps, 0,
        "a block that never uplifts is not integrated"
    );
    // It moves with the ground: its peak absolute acceleration is the pulse's.
    assert!(rel(r.peaks.abs_acceleration_g, 0.999 * ALPHA_10.tan()) < 1e-6);
    let mut above = below.clone();
    above.excitation = pulse(Amplitude::TanAlphaRatio(1.001), 4.0);
    // Both lobes of the one-sine pulse exceed the threshold: one uplift in each.
    assert_eq!(run(&above).counters.uplifts, 2);
    // The slender form has its own threshold, g·α < g·tan α.
    let mut slender = below.clone();
    if let Structure::Rigid(b) = &mut slender.structure {
        b.form = Form::Slender;
    }
    assert!(run(&slender).counters.uplifts >= 1);
}

#[test]
fn slender_form_approaches_exact_for_small_alpha() {
    let diff = |alpha: f64| {
        let mut exact = fig8(Device::None);
        if let Structure::Rigid(b) = &mut exact.structure {
            b.alpha = alpha;
        }
        exact.excitation = pulse(Amplitude::TanAlphaRatio(1.5), 4.0);
        let mut slender = exact.clone();
        if let Structure::Rigid(b) = &mut slender.structure {
            b.form = Form::Slender;
        }
        rel(run(&slender).peaks.rotation, run(&exact).peaks.rotation)
    };
    let (d_small, d_large) = (diff(0.05), diff(0.3));
    println!("slender vs exact peak difference: α=0.05 {d_small:.2e}, α=0.3 {d_large:.2e}");
    assert!(d_small < d_large && d_small < 0.02);
}

/// Cutting the free-vibration tail once no peak can change leaves every peak identical, over a
/// spread of pulses and devices (a bound that was not a bound would show here).
#[test]
fn settled_tail_cut_leaves_peaks_unchanged() {
    let mut cut_some = 0;
    for (name, device) in all_devices() {
        for ratio in [3.5, 5.0, 8.0, 12.0] {
            let mut full = fig8(device.clone());
            full.excitation = pulse(Amplitude::AlphaRatio(2.0), ratio);
            full.rtol = 1e-7;
            let mut cut = full.clone();
            cut.stop_when_settled = true;
            let (a, b) = (run(&full), run(&cut));
            assert_eq!(a.peaks, b.peaks, "{name} at ωg/p = {ratio}");
            assert!(b.stats.rhs_evals <= a.stats.rhs_evals);
            if b.end_reason == EndReason::Settled {
                cut_some += 1;
                assert!(b.end_time < a.end_time);
            }
        }
    }
    assert!(
        cut_some >= 10,
        "the cut applied in only {cut_some} of 20 scenes"
    );
}

/// Free rocking from θ0 with flywheel devices: the flywheels start where the block is
/// (unloaded springs), so the peak is θ0 and nothing is thrown over.
#[test]
fn free_rocking_with_flywheels_starts_with_unloaded_springs() {
    for (name, device) in all_devices() {
        let mut s = fig8(device);
        s.excitation = pulse(Amplitude::G(0.0), 1.0);
        s.initial_rotation = 0.5 * ALPHA_10;
        let r = run(&s);
        assert!(!r.overturned, "{name}");
        assert!(
            rel(r.peaks.rotation, 0.5 * ALPHA_10) < 1e-12,
            "{name}: {}",
            r.peaks.rotation
        );
        assert!(r.energy_residual < 1e-6, "{name}: {}", r.energy_residual);
    }
}

/// `form: auto` integrates the slender equations only where their error against the exact
/// ones is below the tolerance, and says which it used.
#[test]
fn auto_form_uses_slender_only_below_the_tolerance() {
    for (alpha, rtol) in [(5e-4, 1e-6), (0.05, 1e-6), (0.05, 1e-2)] {
        let mut exact = fig8(Device::None);
        exact.excitation = pulse(Amplitude::TanAlphaRatio(1.5), 4.0);
        exact.rtol = rtol;
        if let Structure::Rigid(b) = &mut exact.structure {
            b.alpha = alpha;
        }
        let mut auto = exact.clone();
        if let Structure::Rigid(b) = &mut auto.structure {
            b.form = Form::Auto;
        }
        let (e, a) = (run(&exact), run(&auto));
        assert_eq!(e.form_used, Some(Form::Exact));
        let expected = Form::Auto.resolve(alpha, rtol);
        assert_eq!(a.form_used, Some(expected), "α = {alpha}, rtol = {rtol}");
        assert_eq!(expected == Form::Slender, alpha < 0.01 || rtol > 1e-3);
        // Whatever it picks, the peak stays within the tolerance of the exact equations'.
        assert!(rel(a.peaks.rotation, e.peaks.rotation) < rtol.max(1e-6));
    }
}

/// A flywheel-coupled inerter with σ = 0 (a flywheel without inertia, whose equation divides
/// by σm) is refused by name before it runs, for either damping form, instead of running on
/// NaN (ξθ gave c̄ = 2ξθ√(0/0)).
#[test]
fn a_flywheel_coupling_without_inertia_is_refused_by_name() {
    for damping in [Damping::XiTheta(0.02), Damping::CBar(1.0)] {
        let scene = fig8(Device::Inerter {
            sigma: 0.0,
            coupling: Coupling::Flywheel {
                stiffness: ClutchStiffness::FrequencyRatio(50.0),
                rho: 0.05,
                damping,
            },
        });
        let err = scene.validate().unwrap_err();
        assert_eq!(err.field, "sigma");
        assert!(err.expected.contains("device None"), "{}", err.expected);
        let library = rocklab::excitation::library::global().unwrap();
        assert!(sim::run(&scene, library).is_err(), "{damping:?}");
    }
    // The rigid coupling and the sequential law stay valid at σ = 0 (Housner's block).
    for device in [
        Device::Inerter {
            sigma: 0.0,
            coupling: Coupling::Rigid,
        },
        Device::Sequential { sigma: 0.0 },
    ] {
        let r = run(&fig8(device));
        let bare = run(&fig8(Device::None));
        assert!(rel(r.peaks.rotation, bare.peaks.rotation) < 1e-6);
    }
}

/// Every device runs on both structures: the integrator has an instance for every state size a
/// model has (2 or 4 structure components, 0–2 flywheels, 4 accumulators), and each run
/// integrates (the dispatch refuses a size it has no instance for instead of running another).
#[test]
fn every_device_runs_on_both_structures_with_its_own_state_size() {
    use rocklab::presets::{
        flexible_fig14, inerter, inerter_with_dissipation, mechanistic, rigid_fig8, sequential,
    };
    let library = rocklab::excitation::library::global().unwrap();
    for device in [
        Device::None,
        inerter(),
        inerter_with_dissipation(),
        sequential(),
        mechanistic(),
    ] {
        for mut scene in [rigid_fig8(device.clone()), flexible_fig14(device.clone())] {
            scene.duration = 1.0;
            let r = sim::run(&scene, library)
                .unwrap_or_else(|e| panic!("{:?} on {:?}: {e}", scene.device, scene.structure));
            assert!(
                r.stats.rhs_evals > 0,
                "{:?} integrated nothing",
                scene.device
            );
        }
    }
}
