//! Scene histories (issue 15 part 5): a scene run for its history covers the whole duration the
//! study asks for (the settled-tail cut is for sweeps), on a uniform grid resampled from the
//! integrator's dense output, with every event instant kept as a pair of rows (before and after
//! its jump).

use crate::util::{fig12_study_and_fig8_point, rocklab, rocklab_json};
use rocklab::excitation::library;
use rocklab::presets::{self, mechanistic, rigid_fig8};
use rocklab::scene::*;
use rocklab::sim::HistoryColumn;
use rocklab::sim::{self, History, Sampling};

/// The Fig. 8 scene as the Fig. 12 study sweeps it: bare block, ωg/p = 4, 15 s, stopping once
/// settled.
fn fig8_study_scene() -> Scene {
    let (_, point) = fig12_study_and_fig8_point();
    assert!(point.scene.stop_when_settled, "studies stop settled scenes");
    assert_eq!(point.scene.duration, 15.0);
    point.scene
}

fn column(h: &History, name: HistoryColumn) -> Vec<f64> {
    h.column(name).unwrap_or_else(|| panic!("no column {name}"))
}

/// Times of the rows that are not at an event instant.
fn grid_times(h: &History) -> Vec<f64> {
    column(h, HistoryColumn::T)
        .into_iter()
        .filter(|t| !h.events.iter().any(|(te, _)| te == t))
        .collect()
}

#[test]
fn the_fig8_scene_history_covers_15_s_and_every_impact() {
    let scene = fig8_study_scene();
    let lib = library::global().unwrap();
    // The sweep stops at the first settle: about 1.2 s and a handful of impacts.
    let swept = sim::run(&scene, lib).unwrap();
    assert!(swept.end_time < 2.0, "{}", swept.end_time);
    assert!(swept.counters.impacts < 5, "{}", swept.counters.impacts);

    let (result, history) =
        sim::run_history(&sim::history_scene(&scene), lib, &Sampling::Auto).unwrap();
    let t = column(&history, HistoryColumn::T);
    assert_eq!(t[0], 0.0);
    assert_eq!(*t.last().unwrap(), 15.0);
    assert!(result.counters.impacts >= 20, "{}", result.counters.impacts);
    let impacts = history.events.iter().filter(|e| e.1 == "impact").count();
    assert_eq!(impacts as u64, result.counters.impacts);
    // Peaks do not depend on the settled-tail cut.
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    assert!(rel(result.peaks.rotation, swept.peaks.rotation) < 1e-12);

    // Uniform spacing apart from event instants, at the automatic step (15 s / 4000, rounded
    // down to 2 ms), and sorted.
    let dt = 0.002;
    let grid = grid_times(&history);
    assert_eq!(grid.len(), 7501);
    for (k, g) in grid.iter().enumerate() {
        assert!((g - k as f64 * dt).abs() < 1e-9 * dt, "row {k} at {g}");
    }
    assert!(t.windows(2).all(|w| w[0] <= w[1]), "times are sorted");
    // Every event instant is a pair of rows: before and after the jump. An impact keeps θ and
    // jumps θ̇ (Housner: the pivot switches, θ̇ × r), so the curve shows a jump, not a slope.
    let theta = column(&history, HistoryColumn::Theta);
    let rate = column(&history, HistoryColumn::ThetaDot);
    for (te, name) in &history.events {
        let rows: Vec<usize> = (0..t.len()).filter(|&i| t[i] == *te).collect();
        // An uplift ends an idle period: no jump, one row.
        assert_eq!(
            rows.len(),
            if *name == "uplift" { 1 } else { 2 },
            "{name} at {te}"
        );
        if *name == "impact" {
            let (a, b) = (rows[0], rows[1]);
            assert!((theta[a] - theta[b]).abs() < 1e-12, "{te}");
            let ratio = rate[b] / rate[a];
            assert!(
                ratio > 0.5 && ratio < 1.0,
                "θ̇ × {ratio} at the impact at {te}"
            );
        }
    }
}

/// Rows sampled at the solver's step ends from the dense output reproduce the solver's own
/// states there (the interpolant of the right step is used, events are not interpolated
/// across), for a block with impacts, one with a mechanistic clutch, and a flexible column.
#[test]
fn resampled_rows_match_the_solver_states_at_step_ends() {
    let lib = library::global().unwrap();
    let mut flexible = presets::flexible_fig14(mechanistic());
    flexible.duration = 12.0;
    for scene in [
        sim::history_scene(&fig8_study_scene()),
        rigid_fig8(mechanistic()),
        flexible,
    ] {
        let (_, steps) = sim::run_history(&scene, lib, &Sampling::Steps).unwrap();
        let mut times = column(&steps, HistoryColumn::T);
        times.dedup();
        let (_, resampled) = sim::run_history(&scene, lib, &Sampling::At(times)).unwrap();
        assert!(steps.rows.len() > 100);
        assert_eq!(resampled.events, steps.events);
        assert!(resampled.rows.len() >= steps.rows.len());
        for (c, name) in steps.columns.iter().enumerate() {
            let scale = steps.rows.iter().map(|r| r[c].abs()).fold(1e-300, f64::max);
            for (a, b) in steps.rows.iter().zip(&resampled.rows) {
                assert_eq!(a[0], b[0]);
                assert!(
                    (a[c] - b[c]).abs() <= 1e-12 * scale,
                    "{name} at t = {}: {} vs {}",
                    a[0],
                    a[c],
                    b[c]
                );
            }
        }
    }
}

/// A block that comes to rest before the end stays at rest until then on the grid; the rows
/// between solver steps follow the dense output (a sine pulse is a curve, not 8 segments).
#[test]
fn a_history_at_rest_reaches_the_duration_and_pulses_are_drawn_finely() {
    let lib = library::global().unwrap();
    let mut scene = rigid_fig8(Device::None);
    scene.duration = 30.0;
    let (result, history) = sim::run_history(&scene, lib, &Sampling::Uniform(0.01)).unwrap();
    assert_eq!(result.end_reason, rocklab::model::EndReason::Rest);
    assert!(result.end_time < 29.0);
    let t = column(&history, HistoryColumn::T);
    assert_eq!(*t.last().unwrap(), 30.0);
    assert_eq!(grid_times(&history).len(), 3001);
    let theta = column(&history, HistoryColumn::Theta);
    for (ti, th) in t.iter().zip(&theta) {
        if *ti > result.end_time {
            assert_eq!(*th, 0.0, "at rest at {ti}");
        }
    }
    // The ground acceleration column is the pulse itself at every grid time.
    let ag = column(&history, HistoryColumn::GroundAccel);
    let motion = sim::motion_for(&scene, lib).unwrap();
    for (ti, a) in t.iter().zip(&ag) {
        assert!((a - motion.accel(*ti)).abs() < 1e-12, "{ti}");
    }
    // Over the pulse the solver takes a few dozen steps; the grid has a row every 10 ms.
    let (_, steps) = sim::run_history(&scene, lib, &Sampling::Steps).unwrap();
    let in_pulse = |h: &History| {
        column(h, HistoryColumn::T)
            .iter()
            .filter(|t| **t < motion.end())
            .count()
    };
    assert!(in_pulse(&history) > 3 * in_pulse(&steps));
}

/// Closed-form contact intervals (a flexible column under a record) end at the grid's times
/// too, so the grid stays uniform and the response there is the exact one.
#[test]
fn closed_form_contact_histories_are_on_the_grid() {
    let lib = library::global().unwrap();
    let scene = Scene {
        vertical: None,
        structure: presets::flexible_structure(12.0),
        device: Device::None,
        impact: Impact::default(),
        excitation: presets::record("northridge"),
        duration: 6.0,
        rtol: default_rtol(),
        initial_rotation: 0.0,
        stop_when_settled: false,
        closed_form_contact: true,
        method: Default::default(),
    };
    // Rocking phases, if any, integrated as tightly as the reference.
    let scene = Scene {
        rtol: 1e-10,
        ..scene
    };
    let (exact, history) = sim::run_history(&scene, lib, &Sampling::Uniform(0.005)).unwrap();
    assert!(exact.stats.closed_form_steps > 0);
    let grid = grid_times(&history);
    assert_eq!(grid.len(), 1201);
    for (k, g) in grid.iter().enumerate() {
        assert!((g - k as f64 * 0.005).abs() < 1e-11, "row {k} at {g}");
    }
    // Against the integrator throughout at a tight tolerance, on the same grid.
    let integrated = Scene {
        closed_form_contact: false,
        ..scene.clone()
    };
    let (_, reference) = sim::run_history(&integrated, lib, &Sampling::Uniform(0.005)).unwrap();
    let (u, u_ref) = (
        column(&history, HistoryColumn::U),
        column(&reference, HistoryColumn::U),
    );
    let scale = u_ref.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert_eq!(u.len(), u_ref.len());
    let worst = u
        .iter()
        .zip(&u_ref)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(worst < 1e-7 * scale, "{worst} of {scale}");
}

#[test]
fn simulate_history_takes_a_sample_step() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("h.csv");
    let pulse = [
        "simulate",
        "--p",
        "2",
        "--alpha",
        "10deg",
        "--pulse",
        "sine",
        "--amplitude-alpha",
        "1.5",
        "--frequency-ratio",
        "4",
        "--duration",
        "15",
        "--json",
        "--history",
    ];
    let mut args = pulse.to_vec();
    args.extend([csv.to_str().unwrap(), "--dt", "0.01"]);
    let json = rocklab_json(&args);
    let impacts = json["impacts"].as_u64().unwrap();
    assert!(impacts >= 20, "{impacts}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let times: Vec<f64> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    // 1501 grid rows, two rows at each impact (before and after its jump) and one at the
    // uplift.
    let uplifts = json["uplifts"].as_u64().unwrap();
    assert_eq!(times.len() as u64, 1501 + 2 * impacts + uplifts);
    assert_eq!(*times.last().unwrap(), 15.0);

    for bad in ["0", "-1", "fast"] {
        let mut args = pulse.to_vec();
        args.extend([csv.to_str().unwrap(), "--dt", bad]);
        let out = rocklab(&args);
        assert_eq!(out.status.code(), Some(2), "--dt {bad}");
        assert!(String::from_utf8_lossy(&out.stderr).contains("sample step"));
    }
    let mut args = pulse.to_vec();
    args.extend([csv.to_str().unwrap(), "--dt", "1e-9"]);
    let out = rocklab(&args);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("sample step"));
}
