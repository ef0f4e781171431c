//! The workbench on large studies (issue 42 item 2): a study beyond `EXPAND_AT_ONCE` scenes is
//! expanded off the UI thread, so an edit returns control at once (the check is pending, then
//! the new count lands); a superseded expansion never shows; long lists draw only the rows in
//! view; a running sweep leaves keys working. Speeds are in BENCHMARKS.md (`rocklab bench
//! --tui`), not asserted here.

use crate::tui::*;
use crossterm::event::KeyCode::{self, Down, Tab};
use rocklab::study::Study;
use rocklab::tui::app::{App, Check, EXPAND_AT_ONCE, Screen};
use std::time::Duration;

/// A rigid-block map study of `sizes` × 45 amplitudes × `freqs` frequencies × 6 devices.
fn large_study(sizes: usize, freqs: usize) -> Study {
    let text = std::fs::read_to_string("benches/tui_333k.ron").unwrap();
    let text = text
        .replace("steps: 19", &format!("steps: {sizes}"))
        .replace("steps: 65", &format!("steps: {freqs}"));
    Study::parse_ron(&text, "large").unwrap()
}

fn pending(app: &App) -> Option<usize> {
    match app.shared.check {
        Check::Pending { scenes } => Some(scenes),
        _ => None,
    }
}

#[test]
fn an_edit_of_a_large_study_returns_before_its_expansion_lands() {
    let mut app = app_for(large_study(2, 65), scratch_dir());
    let scenes = 2 * 45 * 65 * 6;
    assert!(scenes > EXPAND_AT_ONCE);
    // Opening it does not wait either: the layout's count shows while it expands.
    assert_eq!(pending(&app), Some(scenes));
    assert!(app.wait_idle(Duration::from_secs(120)));
    assert_eq!(scene_count(&app), scenes);
    assert_eq!(app.shared.groups, 2 * 6, "a group per size and device");

    set_field(
        &mut app,
        "frequency",
        "ratio((from: 1.0, to: 12.0, steps: 64))",
    );
    assert!(app.shared.dirty, "the edit was applied");
    assert!(app.editor.edit.is_none(), "the editor closed at once");
    assert_eq!(pending(&app), Some(2 * 45 * 64 * 6));
    snap_text(&app, "scale_expanding");
    // Keys work meanwhile.
    key(&mut app, Tab);
    assert_eq!(app.screen, Screen::Run);
    key(&mut app, KeyCode::Char('1'));
    assert!(app.wait_idle(Duration::from_secs(120)));
    assert_eq!(scene_count(&app), 2 * 45 * 64 * 6);
}

#[test]
fn a_superseded_expansion_never_shows() {
    let mut app = app_for(large_study(2, 65), scratch_dir());
    assert!(app.wait_idle(Duration::from_secs(120)));
    set_field(
        &mut app,
        "frequency",
        "ratio((from: 1.0, to: 12.0, steps: 60))",
    );
    set_field(
        &mut app,
        "frequency",
        "ratio((from: 1.0, to: 12.0, steps: 50))",
    );
    let wanted = 2 * 45 * 50 * 6;
    let stale = 2 * 45 * 60 * 6;
    let mut seen = Vec::new();
    for _ in 0..24_000 {
        app.tick();
        match &app.shared.check {
            Check::Ok(points) => seen.push(points.len()),
            Check::Pending { scenes } => assert_eq!(*scenes, wanted),
            Check::Invalid(msg) => panic!("{msg}"),
        }
        if pending(&app).is_none() {
            break;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!(!seen.contains(&stale));
    assert_eq!(seen, vec![wanted], "only the latest edit's expansion lands");
    // A small study set while a large one expands wins too (its expansion is abandoned).
    set_field(
        &mut app,
        "frequency",
        "ratio((from: 1.0, to: 12.0, steps: 60))",
    );
    set_field(&mut app, "size", "1.0");
    assert_eq!(scene_count(&app), 45 * 60 * 6);
    assert!(app.wait_idle(Duration::from_secs(120)));
    std::thread::sleep(Duration::from_millis(200));
    app.tick();
    assert_eq!(scene_count(&app), 45 * 60 * 6);
}

#[test]
fn the_run_screen_draws_the_groups_in_view_at_its_offset() {
    // 24 groups (12 sizes × 2 devices) of one scene each: more rows than 80×24 shows.
    let mut app = app_for(Study::builtin_default(), scratch_dir());
    set_field(
        &mut app,
        "structure",
        "rigid(size: (from: 0.5, to: 6.0, steps: 12), alpha: 0.2)",
    );
    set_field(&mut app, "devices", "[none, sequential(sigma: 0.5)]");
    set_field(&mut app, "frequency", "ratio(4.0)");
    set_field(&mut app, "amplitude", "alpha_ratio(1.5)");
    assert_eq!(scene_count(&app), 24);
    key(&mut app, KeyCode::Char('r'));
    assert!(app.wait_idle(Duration::from_secs(120)));
    key(&mut app, KeyCode::Char('2'));
    keys(&mut app, &[Down; 3]);
    assert_eq!(app.runs.scroll, 3);
    // Rows 4 to 21 of the 24 groups: the fourth size (R = 2) of the bare block first.
    let frame = text(&render(&app, rocklab::tui::theme::Theme::COLOR, SMALL));
    assert!(frame.contains("rows 4–21 of 24"), "{frame}");
    let first = frame.lines().nth(5).unwrap_or_default();
    assert!(first.starts_with("bare R=2 "), "{frame}");
    snap("scale_run_rows_at_offset_80x24", frame);
}

#[test]
fn a_running_sweep_leaves_keys_working() {
    let mut app = app_for(large_study(2, 30), scratch_dir());
    assert!(app.wait_idle(Duration::from_secs(120)));
    assert_eq!(scene_count(&app), 2 * 45 * 30 * 6);
    key(&mut app, KeyCode::Char('r'));
    assert!(app.is_running(), "{:?}", app.message);
    // Wait for the first finished scene, then move around while progress is drained.
    for _ in 0..12_000 {
        app.tick();
        if app.runs.state.as_ref().is_some_and(|r| r.done > 0) {
            break;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    for (code, screen) in [
        (Tab, Screen::Results),
        (Tab, Screen::Scene),
        (KeyCode::Char('1'), Screen::Study),
        (Down, Screen::Study),
        (KeyCode::Char('2'), Screen::Run),
    ] {
        key(&mut app, code);
        app.tick();
        assert_eq!(app.screen, screen);
    }
    assert!(
        app.runs.state.as_ref().unwrap().done > 0,
        "progress arrived"
    );
    assert!(
        app.is_running(),
        "still running: the keys came during the sweep"
    );
    key(&mut app, KeyCode::Char('c'));
    key(&mut app, KeyCode::Enter);
    assert!(app.wait_idle(Duration::from_secs(60)));
}
