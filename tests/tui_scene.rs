//! The Scene screen, headless: a fixed scene, the whole Fig. 8 history, checking a scene, and
//! a scene opened from a map cell. Helpers in tests/tui.rs.

use crate::tui::{
    SMALL, app_for, fixed_results, key, keys, new_app, render, run_to_completion, scratch_dir,
    small_map_study, snap, snap_text, text,
};
use crossterm::event::KeyCode::{self, Enter, Right, Up};
use rocklab::tui::app::{SceneState, Screen};
use rocklab::tui::theme::Theme;
use std::time::Duration;

/// The Scene screen draws a fixed scene: the result of a point of the fixed results and
/// histories from closed forms (a decaying rocking motion, its flywheels, clutch forces and
/// energies), not a rerun, so the snapshot changes only when the drawing does.
#[test]
fn scene_screen_draws_a_fixed_scene() {
    let mut app = new_app();
    small_map_study(&mut app);
    let results = fixed_results();
    let outcome = results
        .outcomes
        .iter()
        .find(|o| {
            o.point.group == "mechanistic"
                && o.point.coord("ωg/p") == Some(4.0)
                && o.point.coord("A/(g·α)") == Some(2.0)
        })
        .expect("the fixed results hold the point");
    let decay = |t: f64| (-0.3 * t).exp();
    let w = std::f64::consts::PI;
    let history = rocklab::sim::History {
        columns: vec![
            rocklab::sim::HistoryColumn::T,
            rocklab::sim::HistoryColumn::Theta,
            rocklab::sim::HistoryColumn::FlywheelAVel,
            rocklab::sim::HistoryColumn::FlywheelBVel,
            rocklab::sim::HistoryColumn::ClutchForceA,
            rocklab::sim::HistoryColumn::ClutchForceB,
            rocklab::sim::HistoryColumn::EInput,
            rocklab::sim::HistoryColumn::EStructure,
            rocklab::sim::HistoryColumn::EDeviceDamping,
        ],
        rows: (0..=800)
            .map(|i| {
                let t = i as f64 * 0.01;
                let theta = 0.09 * decay(t) * (w * t).sin();
                let rate = 0.09 * decay(t) * w * (w * t).cos();
                vec![
                    t,
                    theta,
                    rate.max(0.0) * 1.5,
                    rate.min(0.0) * 1.5,
                    2.0 * rate.max(0.0),
                    -2.0 * rate.min(0.0),
                    0.3 * (1.0 - decay(t)) + 0.5 * rate * rate,
                    0.5 * rate * rate,
                    0.3 * (1.0 - decay(t)),
                ]
            })
            .collect(),
        events: Vec::new(),
    };
    app.scene.show(
        outcome.point.clone(),
        outcome.result.clone().unwrap(),
        history,
    );
    key(&mut app, KeyCode::Char('4'));
    assert_eq!(app.screen, Screen::Scene);
    assert!(app.wait_idle(Duration::from_secs(1)), "nothing runs");
    snap_text(&app, "scene");
}

/// The Fig. 8 scene (bare block, ωg/p = 4, from the Fig. 12 study, whose sweep stops it once
/// settled at 1.2 s) rerun for the Scene screen: the whole 15 s with all its impacts, θ and the
/// energy balance only (no device panels for a bare block), units on every axis.
#[test]
fn scene_screen_shows_the_whole_fig8_history() {
    let (study, point) = crate::util::fig12_study_and_fig8_point();
    let mut app = app_for(study, scratch_dir());
    app.scene.open(point);
    key(&mut app, KeyCode::Char('4'));
    assert_eq!(app.screen, Screen::Scene);
    assert!(app.wait_idle(Duration::from_secs(60)), "the scene reruns");
    let Some(SceneState::Done(result, history)) = app.scene.view.as_ref().map(|v| &v.state) else {
        panic!("the scene finished");
    };
    assert!(result.counters.impacts >= 20, "{}", result.counters.impacts);
    assert_eq!(
        history
            .column(rocklab::sim::HistoryColumn::T)
            .unwrap()
            .last(),
        Some(&15.0)
    );
    let screen = text(&render(&app, Theme::COLOR, SMALL));
    assert!(screen.contains(&format!("0–15 s: impacts {}", result.counters.impacts)));
    for unit in ["rad", "J", "t (s)"] {
        assert!(screen.contains(unit), "{unit}\n{screen}");
    }
    for device in ["flywheel", "clutch", "device"] {
        assert!(!screen.contains(device), "{device}\n{screen}");
    }
    assert!(screen.lines().all(|l| l.chars().count() <= 80));
    snap("scene_fig8_full_80x24", screen);
}

/// `c` on the Scene screen checks the scene: the Fig. 8 bare block converged; the same point
/// with the hard case's scene (50 p clutch under Landers) ill-conditioned.
#[test]
fn scene_screen_checks_the_scene() {
    let (study, point) = crate::util::fig12_study_and_fig8_point();
    let mut app = app_for(study, scratch_dir());
    app.scene.open(point.clone());
    key(&mut app, KeyCode::Char('4'));
    key(&mut app, KeyCode::Char('c'));
    assert!(app.wait_idle(Duration::from_secs(60)), "the check runs");
    let screen = text(&render(&app, Theme::COLOR, SMALL));
    assert!(
        screen.contains("check: converged · worst rel. change"),
        "{screen}"
    );
    assert!(screen.contains("rtol 1e-5 vs 1e-8"), "{screen}");
    assert!(screen.lines().all(|l| l.chars().count() <= 80));

    let mut hard = point;
    let mut clutch = rocklab::scene::Clutch::paper_default(0.5);
    clutch.stiffness = rocklab::scene::ClutchStiffness::FrequencyRatio(50.0);
    hard.scene.device = rocklab::scene::Device::Mechanistic(clutch);
    hard.scene.structure = rocklab::scene::Structure::Rigid(rocklab::scene::RigidBlock {
        size: 3.0,
        alpha: 0.25,
        mass: 1.0,
        form: rocklab::scene::Form::Exact,
    });
    hard.scene.excitation = rocklab::presets::record("landers");
    hard.scene.duration = 10.5;
    app.scene.open(hard);
    key(&mut app, KeyCode::Char('c'));
    assert!(app.wait_idle(Duration::from_secs(60)), "the check runs");
    let screen = text(&render(&app, Theme::COLOR, SMALL));
    assert!(screen.contains("check: ill-conditioned"), "{screen}");
    assert!(
        screen.contains("a 1e-7 change of the inputs moves it"),
        "{screen}"
    );
}

/// Enter on a map cell reruns exactly that scene: its axes values and its overturning verdict
/// match the cell.
#[test]
fn a_scene_opened_from_a_map_cell_is_that_cell() {
    let mut app = new_app();
    small_map_study(&mut app);
    run_to_completion(&mut app);
    keys(
        &mut app,
        &[KeyCode::Char('m'), Right, Right, Up, KeyCode::Char(']')],
    );
    let (x_axis, y_axis, x, y, cell) = {
        let data = app.shared.results.as_ref().unwrap();
        let map = &data.maps[app.browser.maps.map];
        let (cx, cy) = app.browser.maps.cell;
        (
            map.x_axis.clone(),
            map.y_axis.clone(),
            map.xs[cx],
            map.ys[cy],
            map.cells[cy][cx],
        )
    };
    key(&mut app, Enter);
    assert_eq!(app.screen, Screen::Scene, "{:?}", app.message);
    assert!(app.wait_idle(Duration::from_secs(60)));
    let scene = app.scene.view.as_ref().unwrap();
    assert_eq!(scene.point.coord(&x_axis), Some(x));
    assert_eq!(scene.point.coord(&y_axis), Some(y));
    match &scene.state {
        SceneState::Done(result, _) => assert_eq!(Some(result.overturned), cell),
        _ => panic!("the scene did not finish"),
    }
}

/// The Scene screen names its scene by the index `rocklab plot --scene N` takes, and each
/// parameter once: a user's rigid family (R and α varying, not axes) put R and α in the group
/// and again in the coordinates ("… R=1 α=0.1745 ωg/p=4 R=1 α=0.1745").
#[test]
fn scene_header_names_the_index_and_each_parameter_once() {
    let study = rocklab::study::Study::from_ron_str(
        "(version: 1, name: \"family\", structure: rigid(size: [1.0, 3.0], alpha: deg([6, 10, 14])),
          devices: [none],
          excitation: pulse(shape: sine, amplitude: alpha_ratio(2.5), frequency: ratio([2.0, 4.0])),
          duration: 4.0)",
        "family.ron",
    )
    .unwrap();
    let point = study
        .expand()
        .unwrap()
        .into_iter()
        .find(|p| {
            p.coord("R") == Some(3.0)
                && p.coord("ωg/p") == Some(4.0)
                && p.coord("α")
                    .is_some_and(|a| (a - 10f64.to_radians()).abs() < 1e-12)
        })
        .expect("the family holds R = 3, α = 10°, ωg/p = 4");
    assert_ne!(point.index, 0);
    let mut app = app_for(study, scratch_dir());
    app.scene.open(point.clone());
    key(&mut app, KeyCode::Char('4'));
    assert!(app.wait_idle(Duration::from_secs(60)), "the scene reruns");
    let screen = text(&render(&app, Theme::COLOR, SMALL));
    let header = screen.lines().nth(1).unwrap();
    assert!(
        header.starts_with(&format!("scene {}  bare R=3 α=", point.index)),
        "{screen}"
    );
    for name in ["R=", "α=", "ωg/p"] {
        assert_eq!(header.matches(name).count(), 1, "{name}: {header}");
    }
    assert!(header.ends_with(", ωg/p = 4"), "{header}");
    let verdict = screen.lines().nth(2).unwrap();
    // A rigid block overturns at θ = α: its measure reads 1.
    assert!(verdict.starts_with("OVERTURNED  θmax/α 1  0–"), "{verdict}");
    assert!(
        !screen.contains("drift"),
        "a rigid block's measure is θmax/α"
    );
    snap("scene_rigid_family_80x24", screen);
}

/// A flexible structure overturns when its mass passes over the pivot, which is when the drift
/// |X|/H reaches B/H = tan α, with θ still below α: the Scene screen says so (it read
/// "OVERTURNED θmax/α 0.9852", a contradiction for a reader who knows the rigid block's
/// θ = α). Fig. 16's bare structure at ωg/p = 2.5: the drift at the end is tan 0.2.
#[test]
fn a_flexible_overturn_reads_as_the_mass_over_the_pivot() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/fig16_flexible_spectra.ron"
    );
    let study = rocklab::study::Study::load(std::path::Path::new(path)).unwrap();
    let point = study
        .expand()
        .unwrap()
        .into_iter()
        .find(|p| p.scene.device == rocklab::scene::Device::None && p.coord("ωg/p") == Some(2.5))
        .expect("Fig. 16 holds the bare structure at ωg/p = 2.5");
    let mut app = app_for(study, scratch_dir());
    app.scene.open(point.clone());
    key(&mut app, KeyCode::Char('4'));
    assert!(app.wait_idle(Duration::from_secs(60)), "the scene reruns");
    let Some(SceneState::Done(result, _)) = app.scene.view.as_ref().map(|v| &v.state) else {
        panic!("the scene finished");
    };
    assert!(result.overturned);
    // The criterion in numbers: drift tan α at the end, θ short of α.
    assert!(
        (result.peaks.drift - 0.2f64.tan()).abs() < 1e-9,
        "{}",
        result.peaks.drift
    );
    assert!(
        result.peak_rotation_ratio < 0.99,
        "{}",
        result.peak_rotation_ratio
    );
    let screen = text(&render(&app, Theme::COLOR, SMALL));
    let header = screen.lines().nth(1).unwrap();
    assert!(
        header.starts_with(&format!("scene {}  bare, ωg/p = 2.5", point.index)),
        "{screen}"
    );
    assert!(
        screen.contains("OVERTURNED  drift |X|max/H 0.2027 (= tan α: mass over the pivot)"),
        "{screen}"
    );
    assert!(screen.contains("θmax/α 0.98"), "{screen}");
    assert!(screen.lines().all(|l| l.chars().count() <= 80));
    snap("scene_flexible_overturned_80x24", screen);
}
