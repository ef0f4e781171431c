//! The Run screen, headless: a run by keys to its results, stopping (keeping what finished),
//! quitting mid-sweep and resuming, scrolling, and every screen at every size. Helpers in
//! tests/tui.rs.

use crate::tui::{
    SMALL, app_for, ctrl, key, keys, new_app, new_app_in, render, run_to_completion, scene_count,
    scratch_dir, set_field, small_map_study, snap, snap_text, text, typed,
};
use crossterm::event::KeyCode::{self, Backspace, Down, Enter, Esc, Left, Right, Up};
use rocklab::study::Study;
use rocklab::tui::app::{App, Effect, Options, ResultsTab, SceneState, Screen};
use rocklab::tui::theme::Theme;
use std::time::Duration;

/// The key-sequence test: edit a grid, run the small study to completion, land on the
/// results, move through spectra, maps and the comparison, open a scene.
#[test]
fn edit_run_and_read_results_by_keys() {
    let mut app = new_app();
    small_map_study(&mut app);
    let total = scene_count(&app);
    assert_eq!(total, 36);
    snap_text(&app, "run_before");
    run_to_completion(&mut app);
    assert_eq!(app.screen, Screen::Results, "{:?}", app.message);
    let run = app.runs.state.as_ref().unwrap();
    assert_eq!(run.done, total);
    assert_eq!(run.finished, Some(false));
    let data = app.shared.results.as_ref().unwrap();
    assert_eq!(data.results.outcomes.len(), total);
    assert!(!data.spectra.is_empty());

    // The results screens' drawing is snapshotted from fixed results (results_screens_draw_fixed_results); the same
    // keys move the cursors here for the scene opened at the end.
    keys(&mut app, &[Right, Right, Down, KeyCode::Char(']')]);
    key(&mut app, KeyCode::Char('m'));
    assert_eq!(app.browser.tab, ResultsTab::Maps);
    keys(&mut app, &[Right, Up, KeyCode::Char('c')]);

    key(&mut app, KeyCode::Char('2'));
    snap_text(&app, "run_finished");

    // Write the results file and read it back: the same outcomes.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sub").join("results.json");
    keys(&mut app, &[KeyCode::Char('3'), KeyCode::Char('w')]);
    ctrl(&mut app, 'u');
    ctrl(&mut app, 'k');
    typed(&mut app, path.to_str().unwrap());
    key(&mut app, Enter);
    let back = rocklab::report::load_results(&path).unwrap();
    assert_eq!(
        back.outcomes,
        app.shared.results.as_ref().unwrap().results.outcomes
    );

    // Open the scene under the comparison cursor (variant B, the mechanistic model): its rerun
    // with histories must reproduce the spectrum value at that point.
    keys(&mut app, &[KeyCode::Char('3'), KeyCode::Char('c'), Left]);
    let (expected, x) = {
        let data = app.shared.results.as_ref().unwrap();
        let q = app.browser.current_quantity(data).unwrap();
        let pairs = app.browser.compare.pairs(data, q).unwrap();
        let pair = &pairs[app.browser.compare.pair];
        let x = app.browser.spectra.x;
        assert!(pair.b.contains("mechanistic"), "{}", pair.b);
        (pair.points[x].b, pair.points[x].x)
    };
    let expected = expected.expect("B survives at the cursor");
    key(&mut app, Enter);
    assert_eq!(app.screen, Screen::Scene, "{:?}", app.message);
    assert!(app.wait_idle(Duration::from_secs(60)));
    let scene = app.scene.view.as_ref().unwrap();
    assert_eq!(scene.point.coords[0].1, x);
    match &scene.state {
        SceneState::Done(result, history) => {
            assert!((result.peak_rotation_ratio - expected).abs() <= 1e-12 * expected);
            assert!(history.rows.len() > 10);
        }
        _ => panic!("the scene did not finish"),
    }
    key(&mut app, Esc);
    assert_eq!(app.screen, Screen::Results);
    // Editing the study afterwards marks the results as stale.
    let fresh = text(&render(&app, Theme::COLOR, SMALL));
    assert!(!fresh.contains("edited since"), "{fresh}");
    keys(&mut app, &[KeyCode::Char('1')]);
    set_field(&mut app, "duration", "10.0");
    key(&mut app, KeyCode::Char('3'));
    let stale = text(&render(&app, Theme::COLOR, SMALL));
    assert!(stale.contains("study edited since this run"), "{stale}");
    key(&mut app, Backspace);
}

#[test]
fn cancel_keeps_what_finished() {
    // The default study at a tight tolerance: its sweep must outlast the few frames between
    // starting and confirming the stop (at the default tolerance it can finish first).
    let mut study = Study::builtin_default();
    study.rtol = 1e-12;
    let mut app = app_for(study, scratch_dir());
    key(&mut app, KeyCode::Char('r'));
    // Before the first tick nothing has been reported: a reproducible frame of a running sweep.
    assert!(app.is_running());
    snap_text(&app, "run_started");
    key(&mut app, KeyCode::Char('c'));
    assert!(app.prompt.is_some(), "stopping a sweep asks first");
    key(&mut app, Enter);
    snap(
        "run_cancelling_80x24",
        text(&render(&app, Theme::COLOR, SMALL)),
    );
    assert!(app.wait_idle(Duration::from_secs(120)));
    let run = app.runs.state.as_ref().unwrap();
    assert_eq!(run.finished, Some(true));
    let kept = app.shared.results.as_ref().unwrap().results.outcomes.len();
    assert_eq!(kept, run.done, "every finished scene is kept");
    assert!(kept < run.total, "cancelled at once, yet all {kept} ran");
    assert_eq!(
        app.screen,
        Screen::Run,
        "a cancelled run stays on the Run screen"
    );
}

/// Every screen and results tab, with data, draws at any size without panicking; from 40×10
/// up the tab bar is there (the help overlay covers it).
#[test]
fn every_screen_draws_at_any_size() {
    let mut app = new_app();
    small_map_study(&mut app);
    run_to_completion(&mut app);
    keys(&mut app, &[KeyCode::Char('c'), Enter]);
    assert!(app.wait_idle(Duration::from_secs(60)));
    let sizes = [
        (1, 1),
        (20, 5),
        (39, 9),
        (40, 10),
        (57, 13),
        (80, 24),
        (133, 41),
        (240, 70),
    ];
    let views: [&[KeyCode]; 8] = [
        &[KeyCode::Char('1')],
        &[KeyCode::Char('2')],
        &[KeyCode::Char('3'), KeyCode::Char('s')],
        &[KeyCode::Char('m')],
        &[KeyCode::Char('c')],
        &[KeyCode::Char('4')],
        &[KeyCode::Char('?')],
        &[Esc, KeyCode::Char('1'), Enter],
    ];
    for view in views {
        keys(&mut app, view);
        for (w, h) in sizes {
            for theme in [Theme::COLOR, Theme::MONO] {
                let buf = text(&render(&app, theme, (w, h)));
                if w >= 40 && h >= 10 && !app.help.visible {
                    assert!(buf.contains("rocklab"), "{w}×{h} after {view:?}:\n{buf}");
                }
            }
        }
    }
}

/// q and Ctrl-C during a sweep ask first (keep finished scenes is the default, n keeps it
/// running); after a confirmed quit, the finished scenes are on disk, and a restarted
/// workbench's `r` reuses them instead of computing them again.
#[test]
fn quitting_mid_sweep_asks_and_a_restart_reuses_the_finished_scenes() {
    let root = scratch_dir();
    let mut app = new_app_in(root.clone());
    // Enough scenes that the sweep cannot finish before the questions below are answered
    // (the stop question closes itself once the sweep has returned).
    let bigger = |app: &mut rocklab::tui::app::App| {
        small_map_study(app);
        set_field(app, "frequency", "ratio((from: 2.0, to: 8.0, steps: 60))");
    };
    bigger(&mut app);
    let total = scene_count(&app);
    key(&mut app, KeyCode::Char('r'));
    assert_eq!(key(&mut app, KeyCode::Char('q')), Effect::None, "q asks");
    assert!(matches!(
        app.prompt,
        Some(rocklab::tui::app::Prompt::StopSweep(_))
    ));
    snap(
        "confirm_quit_80x24",
        text(&render(&app, Theme::COLOR, SMALL)),
    );
    // n: the sweep goes on; Ctrl-C asks the same question.
    key(&mut app, KeyCode::Char('n'));
    assert!(app.prompt.is_none() && app.is_running());
    assert_eq!(ctrl(&mut app, 'c'), Effect::None, "Ctrl-C asks");
    assert!(matches!(
        app.prompt,
        Some(rocklab::tui::app::Prompt::StopSweep(_))
    ));
    key(&mut app, Esc);
    // Esc on the Run screen (cancel) asks too, on every screen the dialog draws.
    key(&mut app, Esc);
    assert!(app.prompt.is_some(), "cancel asks");
    key(&mut app, KeyCode::Char('n'));
    key(&mut app, KeyCode::Char('1'));
    key(&mut app, KeyCode::Char('q'));
    let frame = text(&render(&app, Theme::COLOR, SMALL));
    assert!(frame.contains("keep finished scenes"), "{frame}");
    // Let a few scenes finish, then quit keeping them (Enter: the default answer).
    let until = std::time::Instant::now() + Duration::from_secs(60);
    while app.runs.state.as_ref().unwrap().done < 2 && std::time::Instant::now() < until {
        app.tick();
        std::thread::sleep(Duration::from_millis(2));
    }
    key(&mut app, Enter);
    // The edited study is unsaved: that question comes next.
    assert_eq!(key(&mut app, KeyCode::Char('y')), Effect::Quit);
    assert!(app.wait_idle(Duration::from_secs(60)));
    let kept = app.runs.state.as_ref().unwrap().done;
    assert!(kept >= 2, "{kept}");
    let dir = root.join("default");
    let on_disk = rocklab::report::load_results(&dir.join("results.json")).unwrap();
    assert_eq!(
        on_disk.outcomes.len(),
        kept,
        "every finished scene is on disk"
    );
    drop(app);

    let mut again = new_app_in(root.clone());
    bigger(&mut again);
    run_to_completion(&mut again);
    let run = again.runs.state.as_ref().unwrap();
    assert_eq!(run.finished, Some(false), "{:?}", again.message);
    assert_eq!(run.done, total);
    assert_eq!(
        run.reused, kept,
        "the finished scenes are reused, not recomputed"
    );
    key(&mut again, KeyCode::Char('2'));
    let shown = text(&render(&again, Theme::COLOR, SMALL));
    assert!(
        shown.contains(&format!("{kept} reused, {} new", total - kept)),
        "{shown}"
    );
    let resumed = again.shared.results.as_ref().unwrap();
    for o in &on_disk.outcomes {
        let same = resumed
            .results
            .outcomes
            .iter()
            .find(|r| r.point.index == o.point.index)
            .unwrap();
        assert_eq!(same.result, o.result);
    }
}

/// The Run screen of a study with more variants than rows scrolls: g/G, PgUp/PgDn, ↑↓.
#[test]
fn the_run_screen_scrolls() {
    // Fig. 24 with four clutch strengths: 6 devices × 5 records = 30 variants to list.
    let text_of = std::fs::read_to_string("studies/fig24_records.ron").unwrap();
    let many = text_of
        .replace(
            "sequential(sigma: 0.5)",
            "sequential(sigma: [0.3, 0.5, 0.7, 0.9])",
        )
        .replace("duration: 60.0", "duration: 2.0");
    let file = tempfile::NamedTempFile::new().unwrap();
    std::fs::write(file.path(), many).unwrap();
    let study = Study::load(file.path()).unwrap();
    let mut app = App::new(
        study,
        None,
        Options {
            deterministic: true,
            jobs: Some(1),
            out_root: scratch_dir(),
        },
    );
    key(&mut app, KeyCode::Char('r'));
    let groups = app.runs.state.as_ref().unwrap().groups.len();
    assert!(groups > 20, "{groups}");
    let top = text(&render(&app, Theme::COLOR, SMALL));
    assert!(top.contains("rows 1–"), "{top}");
    key(&mut app, KeyCode::Char('G'));
    snap(
        "run_scrolled_80x24",
        text(&render(&app, Theme::COLOR, SMALL)),
    );
    let bottom = text(&render(&app, Theme::COLOR, SMALL));
    let last = &app.runs.state.as_ref().unwrap().groups[groups - 1].name;
    assert!(bottom.contains(last.as_str()), "{bottom}");
    assert!(!top.contains(last.as_str()), "{top}");
    key(&mut app, KeyCode::PageUp);
    key(&mut app, KeyCode::Char('g'));
    assert_eq!(text(&render(&app, Theme::COLOR, SMALL)), top);
    key(&mut app, KeyCode::Char('c'));
    key(&mut app, Enter);
    assert!(app.wait_idle(Duration::from_secs(120)));
}
