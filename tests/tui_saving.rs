//! The workbench's questions before it throws work away or overwrites it: discarding a
//! running sweep, overwriting results (of this study or another), saving a study without
//! comments it cannot keep; and the spectra of a many-row study at 80×24. Key-driven, on
//! ratatui's TestBackend (helpers from tests/tui.rs).

use crate::tui::{
    SMALL, app_for, ctrl, fixed_results, key, new_app_in, render, scratch_dir, set_field,
    small_map_study, snap, text, typed,
};
use crossterm::event::KeyCode::{self, Enter, Esc};
use rocklab::study::Study;
use rocklab::tui::app::{App, Effect, Options, Prompt, Screen, load_results_at};
use rocklab::tui::theme::Theme;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Tick until the running sweep has finished `n` scenes.
fn wait_for_scenes(app: &mut App, n: usize) {
    let until = Instant::now() + Duration::from_secs(60);
    while app.runs.state.as_ref().unwrap().done < n && Instant::now() < until {
        app.tick();
        std::thread::sleep(Duration::from_millis(2));
    }
    assert!(app.runs.state.as_ref().unwrap().done >= n);
}

fn frame(app: &App) -> String {
    text(&render(app, Theme::COLOR, SMALL))
}

/// `d` in the quit question quits at once, without the unsaved-changes question; the scenes
/// finished so far stay in the journal, where a rerun finds them.
#[test]
fn discard_quits_without_the_unsaved_question_and_keeps_the_journal() {
    let root = scratch_dir();
    let mut app = new_app_in(root.clone());
    small_map_study(&mut app);
    assert!(app.shared.dirty);
    key(&mut app, KeyCode::Char('r'));
    assert_eq!(key(&mut app, KeyCode::Char('q')), Effect::None);
    let shown = frame(&app);
    assert!(
        shown.contains("discard: quit, drop unsaved study edits"),
        "{shown}"
    );
    assert!(shown.contains("keep finished scenes and quit"), "{shown}");
    wait_for_scenes(&mut app, 2);
    assert_eq!(key(&mut app, KeyCode::Char('d')), Effect::Quit);
    assert!(app.wait_idle(Duration::from_secs(60)));
    let done = app.runs.state.as_ref().unwrap().done;
    let (on_disk, _) = load_results_at(&root.join("default")).unwrap();
    assert_eq!(on_disk.outcomes.len(), done, "finished scenes stay on disk");
}

/// The built-in default with 100 times the frequencies (3600 scenes): a sweep that is still
/// running when a test answers the stop question (the 36 scenes of the default can all finish
/// between two ticks of a loaded machine, and then there is nothing left to stop).
fn long_default(root: PathBuf) -> App {
    let text = include_str!("../studies/default.ron").replace("steps: 12", "steps: 1200");
    app_for(Study::from_ron_str(&text, "long.ron").unwrap(), root)
}

/// `d` in the cancel question stops the sweep and shows none of its results; `n`/`Esc`
/// keep it running; its finished scenes stay in the journal.
#[test]
fn discard_cancels_without_showing_the_partial_results() {
    let root = scratch_dir();
    let mut app = long_default(root.clone());
    key(&mut app, KeyCode::Char('r'));
    key(&mut app, Esc);
    assert!(matches!(app.prompt, Some(Prompt::StopSweep(_))));
    snap("confirm_cancel_80x24", frame(&app));
    key(&mut app, KeyCode::Char('n'));
    assert!(
        app.prompt.is_none() && app.is_running(),
        "n keeps it running"
    );
    wait_for_scenes(&mut app, 2);
    key(&mut app, Esc);
    assert_eq!(key(&mut app, KeyCode::Char('d')), Effect::None);
    assert!(app.wait_idle(Duration::from_secs(60)));
    assert!(
        app.shared.results.is_none(),
        "discarded results are not shown"
    );
    let said = app.message.clone().unwrap().0;
    assert!(said.contains("discarded"), "{said}");
    let done = app.runs.state.as_ref().unwrap().done;
    let (on_disk, _) = load_results_at(&root.join("default")).unwrap();
    assert_eq!(on_disk.outcomes.len(), done);
}

/// The stop question counts the scenes as they finish (it froze at the count it opened
/// with), and goes away once the sweep has returned: a `d` pressed after that discards
/// nothing, neither this sweep's results nor, later, another one's (a discard that stayed
/// armed once hid the next run's results, leaving an older run's on the Results screen).
#[test]
fn the_stop_question_counts_live_and_ends_with_the_sweep() {
    let root = scratch_dir();
    let mut app = new_app_in(root.clone());
    key(&mut app, KeyCode::Char('r'));
    key(&mut app, Esc);
    let mut seen = Vec::new();
    let until = Instant::now() + Duration::from_secs(60);
    while let Some(Prompt::StopSweep(stop)) = &app.prompt {
        assert!(Instant::now() < until, "the sweep did not return");
        let run = app.runs.state.as_ref().unwrap();
        assert_eq!(
            (stop.done, stop.total),
            (run.done, run.total),
            "the count is live"
        );
        let shown = frame(&app);
        assert!(
            shown.contains(&format!("{}/{} scenes done", run.done, run.total)),
            "{shown}"
        );
        seen.push(run.done);
        app.tick();
        std::thread::sleep(Duration::from_millis(2));
    }
    assert!(!app.is_running(), "the question stays while the sweep runs");
    assert_eq!(app.runs.state.as_ref().unwrap().done, 36);
    let said = app.message.clone().unwrap().0;
    assert!(said.contains("finished before an answer"), "{said}");
    // The sweep's own results are shown, and a late `d` is no discard.
    assert_eq!(
        app.shared.results.as_ref().unwrap().results.outcomes.len(),
        36
    );
    key(&mut app, KeyCode::Char('d'));
    key(&mut app, Esc);
    assert!(!app.runs.state.as_ref().unwrap().discard);
    app.shared.results = None;
    key(&mut app, KeyCode::Char('1'));
    key(&mut app, KeyCode::Char('r'));
    assert!(app.wait_idle(Duration::from_secs(60)));
    assert_eq!(
        app.shared
            .results
            .as_ref()
            .map(|r| r.results.outcomes.len()),
        Some(36),
        "the next run's results are shown: {:?} (seen {seen:?})",
        app.message
    );
}

/// Type `path` into the `w` prompt.
fn write_results_to(app: &mut App, path: &Path) {
    key(app, KeyCode::Char('w'));
    assert!(matches!(app.prompt, Some(Prompt::SaveResults(_))));
    ctrl(app, 'u');
    ctrl(app, 'k');
    typed(app, path.to_str().unwrap());
    key(app, Enter);
}

fn hash_at(path: &Path) -> String {
    rocklab::sweep::results_identity(path).unwrap().0
}

/// `w` writes a new file at once, asks before overwriting results of this study, and asks
/// (saying so) before overwriting results of another study; `n` leaves the file as it was.
#[test]
fn w_asks_before_overwriting_results() {
    let dir = scratch_dir();
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("results.json");
    let mut app = new_app_in(dir.clone());
    small_map_study(&mut app);
    let ours = fixed_results();
    app.show_results(ours.clone(), false);
    key(&mut app, KeyCode::Char('3'));
    write_results_to(&mut app, &path);
    assert!(app.prompt.is_none(), "a new file is written at once");
    assert_eq!(hash_at(&path), ours.study_hash);

    write_results_to(&mut app, &path);
    let Some(Prompt::OverwriteResults(over)) = &app.prompt else {
        panic!("overwriting asks: {:?}", app.message);
    };
    assert_eq!((over.scenes, over.other_study.clone()), (Some(36), None));
    snap("confirm_overwrite_80x24", frame(&app));
    key(&mut app, KeyCode::Char('n'));
    assert!(app.prompt.is_none());

    // The file now holds another study's results.
    let mut theirs = fixed_results();
    let mut other = theirs.study.clone().unwrap();
    other.name = "other_study".into();
    theirs.study_hash = other.hash();
    theirs.study = Some(other);
    rocklab::report::save_results(&path, &theirs).unwrap();
    write_results_to(&mut app, &path);
    let Some(Prompt::OverwriteResults(over)) = &app.prompt else {
        panic!("overwriting asks");
    };
    assert_eq!(over.other_study.as_deref(), Some("other_study"));
    snap("confirm_overwrite_other_80x24", frame(&app));
    key(&mut app, Esc);
    assert_eq!(hash_at(&path), theirs.study_hash, "n/Esc leaves the file");
    write_results_to(&mut app, &path);
    key(&mut app, KeyCode::Char('y'));
    assert_eq!(hash_at(&path), ours.study_hash, "y overwrites");
}

/// Saving keeps the file's comments and spelling; a save that would drop a comment (its
/// device deleted) asks, and on `y` keeps the file as it was in `<file>.bak`.
#[test]
fn saving_keeps_comments_or_asks_and_keeps_a_backup() {
    let dir = scratch_dir();
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("mine.ron");
    let original = std::fs::read_to_string("studies/default.ron")
        .unwrap()
        .replace(
            "        sequential(sigma: 0.5),\n",
            "        // Makris–Kampas\n        sequential(sigma: 0.5),\n",
        )
        .replace("alpha: 0.17453292519943295", "alpha: deg(10)");
    std::fs::write(&path, &original).unwrap();
    let study = Study::load(&path).unwrap();
    let options = Options {
        deterministic: true,
        jobs: Some(2),
        out_root: dir.clone(),
    };
    let mut app = App::new(study, Some(path.clone()), options);
    set_field(&mut app, "duration", "20.0");
    assert!(app.shared.dirty, "{:?}", app.editor.edit_error);
    key(&mut app, KeyCode::Char('s'));
    assert!(!app.shared.dirty, "{:?}", app.message);
    let saved = std::fs::read_to_string(&path).unwrap();
    assert_eq!(
        saved,
        original.replace("duration: 15.0", "duration: 20.0"),
        "only the edited value changes"
    );

    // Delete the commented device: saving asks.
    key(&mut app, KeyCode::Char('/'));
    typed(&mut app, "[1]");
    key(&mut app, Enter);
    key(&mut app, KeyCode::Char('d'));
    assert_eq!(app.shared.study.devices.len(), 2);
    key(&mut app, KeyCode::Char('s'));
    assert!(matches!(app.prompt, Some(Prompt::DropComments(_))));
    snap("confirm_drop_comments_80x24", frame(&app));
    key(&mut app, KeyCode::Char('n'));
    assert!(app.shared.dirty);
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        saved,
        "n: not saved"
    );
    key(&mut app, KeyCode::Char('s'));
    key(&mut app, KeyCode::Char('y'));
    assert!(!app.shared.dirty, "{:?}", app.message);
    let backup = PathBuf::from(format!("{}.bak", path.display()));
    assert_eq!(std::fs::read_to_string(&backup).unwrap(), saved);
    let now = std::fs::read_to_string(&path).unwrap();
    assert!(!now.contains("Makris"), "{now}");
    assert!(now.starts_with("// The built-in default study"), "{now}");
    assert!(now.contains("alpha: deg(10)"), "{now}");
    assert_eq!(Study::load(&path).unwrap(), app.shared.study);
}

/// Fig. 24's 15 spectra (3 devices × 5 records) at 80×24: the rows that do not fit are
/// scrolled, and no line is left blank while they are hidden.
#[test]
fn many_spectra_fill_the_screen() {
    let study = Study::load(Path::new("studies/fig24_records.ron")).unwrap();
    let template = fixed_results().outcomes[0].result.clone().unwrap();
    let outcomes = study
        .expand()
        .unwrap()
        .into_iter()
        .map(|point| {
            let mut result = template.clone();
            // A smooth made-up spectrum per group: the drawing, not the physics, is tested.
            let x = point.coords[0].1;
            result.peak_rotation_ratio =
                0.1 + 0.05 * (x / 3.0).sin().abs() * (1.0 + (point.index / 40) as f64 / 15.0);
            result.overturned = false;
            rocklab::sweep::SceneOutcome {
                point,
                result: Ok(result),
            }
        })
        .collect();
    let results = rocklab::sweep::SweepResults {
        study_hash: study.hash(),
        study: Some(study.clone()),
        outcomes,
        ..Default::default()
    };
    let mut app = new_app_in(scratch_dir());
    app.open_results(results, PathBuf::from("out/fig24_records"));
    assert_eq!(app.screen, Screen::Results);
    assert_eq!(app.shared.results.as_ref().unwrap().spectra.len() % 15, 0);
    let shown = frame(&app);
    snap("results_fig24_spectra_80x24", shown.clone());
    let rows = |shown: &str| shown.lines().filter(|l| l.contains(" max ")).count();
    assert_eq!(rows(&shown), 15, "all 15 rows fit at 80×24:\n{shown}");
    // Shorter terminals hide rows: then every line shows one (the one blank line is the
    // spacer above the readout).
    for height in [14, 17, 20] {
        let shown = text(&render(&app, Theme::COLOR, (80, height)));
        assert!(rows(&shown) < 15, "{shown}");
        let blank = shown.lines().filter(|l| l.trim().is_empty()).count();
        assert!(blank <= 1, "blank lines while rows are hidden:\n{shown}");
    }
}

/// An angle typed in degrees in the editor is taken in radians.
#[test]
fn the_editor_takes_degrees() {
    let mut app = new_app_in(scratch_dir());
    set_field(&mut app, "alpha", "deg(5)");
    assert!(
        app.editor.edit_error.is_none(),
        "{:?}",
        app.editor.edit_error
    );
    let rigid = format!("{:?}", app.shared.study.structure);
    assert!(
        rigid.contains(&format!("{:?}", 5f64.to_radians())),
        "{rigid}"
    );
    set_field(&mut app, "alpha", "deg(five)");
    let error = app.editor.edit_error.clone().unwrap_or_default();
    assert!(
        error.contains("alpha") && error.contains("not a number"),
        "{error}"
    );
}
