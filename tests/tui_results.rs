//! The Results screen, headless: spectra, maps and comparison of fixed results, partial
//! results, opening results from disk, and a `check.csv` beside them. Helpers in tests/tui.rs.

use crate::tui::{
    LARGE, SMALL, fixed_results, key, keys, new_app, render, scene_count, small_map_study, snap,
    snap_text_and_styles, styles, text, typed,
};
use crossterm::event::KeyCode::{self, Down, Enter, Right, Up};
use rocklab::study::Study;
use rocklab::sweep::SweepResults;
use rocklab::tui::app::{ResultsTab, Screen};
use rocklab::tui::theme::Theme;

/// The fixture's study is the one `small_map_study` makes by keys (else every results
/// screen would say "study edited since this run").
#[test]
fn the_fixed_results_are_of_the_small_map_study() {
    let mut app = new_app();
    small_map_study(&mut app);
    let file = Study::load(std::path::Path::new("tests/data/tui_small_map.ron")).unwrap();
    assert_eq!(file, app.shared.study);
    assert_eq!(fixed_results().study.as_ref(), Some(&app.shared.study));
}

/// The spectra, maps and comparison of fixed results, by keys.
#[test]
fn results_screens_draw_fixed_results() {
    let mut app = new_app();
    small_map_study(&mut app);
    app.show_results(fixed_results(), false);
    key(&mut app, KeyCode::Char('3'));
    assert_eq!(app.screen, Screen::Results);
    let data = app.shared.results.as_ref().unwrap();
    assert_eq!(data.results.outcomes.len(), scene_count(&app));
    assert!(!data.spectra.is_empty());

    snap_text_and_styles(&app, "results_spectra");
    keys(&mut app, &[Right, Right, Down]);
    snap_text_and_styles(&app, "results_spectra_cursor");
    key(&mut app, KeyCode::Char(']'));
    snap_text_and_styles(&app, "results_spectra_next_quantity");

    key(&mut app, KeyCode::Char('m'));
    assert_eq!(app.browser.tab, ResultsTab::Maps);
    keys(&mut app, &[Right, Up]);
    snap_text_and_styles(&app, "results_map");
    let mono = render(&app, Theme::MONO, SMALL);
    snap(
        "results_map_mono_80x24",
        format!(
            "{}\n--- foreground colours ---\n{}",
            text(&mono),
            styles(&mono)
        ),
    );

    key(&mut app, KeyCode::Char('c'));
    snap_text_and_styles(&app, "results_compare");
}

/// Results of [`small_map_study`] as a stopped sweep leaves them: every third scene never ran,
/// one failed.
fn partial_results() -> SweepResults {
    let mut results = fixed_results();
    results.outcomes.retain(|o| o.point.index % 3 != 1);
    results.outcomes[4].result = Err("the solver gave up (test)".into());
    results.cancelled = true;
    results
}

/// A stopped sweep's results: unrun points blank, failed (`?`) and overturned (`×`/`█`)
/// distinct in glyphs and readouts; the axes keep the study's full range.
#[test]
fn partial_results_are_honest() {
    use rocklab::tui::components::results::Mark;
    let mut app = new_app();
    small_map_study(&mut app);
    let full = {
        app.show_results(fixed_results(), false);
        let data = app.shared.results.as_ref().unwrap();
        (
            data.spectra[0].xs.clone(),
            data.maps[0].xs.clone(),
            data.maps[0].ys.clone(),
        )
    };
    app.show_results(partial_results(), true);
    key(&mut app, KeyCode::Char('3'));
    let data = app.shared.results.as_ref().unwrap();
    assert_eq!(
        data.results.outcomes.len(),
        24,
        "placeholders are never results"
    );
    assert_eq!(
        data.spectra[0].xs, full.0,
        "spectrum axis keeps the full range"
    );
    assert_eq!(
        (data.maps[0].xs.clone(), data.maps[0].ys.clone()),
        (full.1, full.2)
    );
    let count = |m: Mark| {
        data.map_marks
            .iter()
            .flatten()
            .flatten()
            .filter(|x| **x == m)
            .count()
    };
    assert_eq!(
        count(Mark::NotRun),
        12,
        "every third of 36 scenes never ran"
    );
    assert_eq!(count(Mark::Failed), 1);
    // The spectra (and so the comparison made of them) hold the unrun points as not run, not
    // as failed: one spectrum per scene and quantity.
    let states = |state: rocklab::report::PointState| {
        (data.spectra.iter())
            .filter(|s| s.quantity == data.spectra[0].quantity)
            .flat_map(|s| &s.states)
            .filter(|x| **x == state)
            .count()
    };
    assert_eq!(states(rocklab::report::PointState::NotRun), 12);
    assert_eq!(states(rocklab::report::PointState::Failed), 1);
    snap_text_and_styles(&app, "results_partial_spectra");
    // The cursor on an unrun point reads "not run", never "overturned".
    let unrun_x = data.spectrum_marks[0]
        .iter()
        .position(|m| *m == Mark::NotRun)
        .expect("an unrun point on the first spectrum");
    for _ in 0..unrun_x {
        key(&mut app, Right);
    }
    let screen = text(&render(&app, Theme::COLOR, SMALL));
    assert!(screen.contains("not run"), "{screen}");
    key(&mut app, KeyCode::Char('m'));
    snap_text_and_styles(&app, "results_partial_map");
}

/// `rocklab tui out/x` and `o` open results (a directory or its results.json) for browsing,
/// with the study they came from.
#[test]
fn results_open_from_a_directory_or_file() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("x");
    std::fs::create_dir_all(&dir).unwrap();
    rocklab::report::save_results(&dir.join("results.json"), &partial_results()).unwrap();
    for path in [dir.clone(), dir.join("results.json")] {
        let mut app = new_app();
        key(&mut app, KeyCode::Char('o'));
        typed(&mut app, path.to_str().unwrap());
        key(&mut app, Enter);
        assert_eq!(app.screen, Screen::Results, "{:?}", app.message);
        let data = app.shared.results.as_ref().unwrap();
        assert_eq!(data.results.outcomes.len(), 24);
        assert!(data.cancelled);
        assert_eq!(Some(&app.shared.study), data.results.study.as_ref());
        assert_eq!(scene_count(&app), 36, "the study they came from");
        assert_eq!(
            app.shared.output_dir().unwrap(),
            dir,
            "a rerun resumes there"
        );
    }
    let (results, at) = rocklab::tui::app::load_results_at(&dir).unwrap();
    assert_eq!((results.outcomes.len(), at), (24, dir));
}

/// A `check.csv` beside opened results (`rocklab check`) puts each point's verdict and κ in
/// the spectra's cursor readout; negligible rows do not count toward κ.
#[test]
fn results_show_their_check_at_the_cursor() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("x");
    std::fs::create_dir_all(&dir).unwrap();
    let results = partial_results();
    rocklab::report::save_results(&dir.join("results.json"), &results).unwrap();
    let mut csv = String::from(
        "scene,verdict,rtol,reference_rtol,quantity,value,reference,change,condition,negligible,overturn_flips\n",
    );
    for o in &results.outcomes {
        let i = o.point.index;
        csv += &format!("{i},ill_conditioned,1e-5,1e-8,peak_rotation,1,1,0,3.2e6,false,false\n");
        csv += &format!("{i},ill_conditioned,1e-5,1e-8,peak_drift,1,1,0,9.9e9,true,false\n");
    }
    std::fs::write(dir.join("check.csv"), csv).unwrap();
    let mut app = new_app();
    key(&mut app, KeyCode::Char('o'));
    typed(&mut app, dir.to_str().unwrap());
    key(&mut app, Enter);
    assert_eq!(app.screen, Screen::Results, "{:?}", app.message);
    let message = format!("{:?}", app.message);
    assert!(
        message.contains("check.csv: 24 scenes checked"),
        "{message}"
    );
    let screen = text(&render(&app, Theme::COLOR, LARGE));
    assert!(
        screen.contains("check: ill-conditioned (κ 3.2e6)"),
        "{screen}"
    );
    assert!(!screen.contains("9.9e9"), "{screen}");
    // A malformed file is said, not silently dropped.
    std::fs::write(dir.join("check.csv"), "scene,verdict\nx,y\n").unwrap();
    key(&mut app, KeyCode::Char('1'));
    key(&mut app, KeyCode::Char('o'));
    typed(&mut app, dir.to_str().unwrap());
    key(&mut app, Enter);
    assert!(
        format!("{:?}", app.message).contains("not read"),
        "{:?}",
        app.message
    );
}
