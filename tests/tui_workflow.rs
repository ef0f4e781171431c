//! The workbench on a user's own study (issue 28): an edit keeps the finished scenes, the
//! output folder chosen with `d` belongs to the study it was chosen for, an invalid study
//! opens in the editor with its error, and `o` opens from every screen.

use crate::tui::{
    SMALL, ctrl, key, new_app, render, run_to_completion, scene_count, set_field, small_map_study,
    text, typed,
};
use crossterm::event::KeyCode::{self, Enter};
use rocklab::tui::app::{App, Check, Options, Screen};
use rocklab::tui::theme::Theme;

/// Every finished scene whose scene is unchanged is reused after an edit of the study (a
/// grid widened), and the Run screen says "N reused, M new"; the results equal a fresh run's.
#[test]
fn an_edit_reuses_the_finished_scenes() {
    let mut app = new_app();
    small_map_study(&mut app);
    run_to_completion(&mut app);
    let first = scene_count(&app);
    key(&mut app, KeyCode::Char('1'));
    set_field(&mut app, "amplitude", "alpha_ratio([1.0, 2.0, 4.0, 6.0])");
    let total = scene_count(&app);
    assert_eq!(total, first / 3 * 4);
    run_to_completion(&mut app);
    let run = app.runs.state.as_ref().unwrap();
    assert_eq!(run.finished, Some(false), "{:?}", app.message);
    assert_eq!((run.done, run.reused), (total, first));
    key(&mut app, KeyCode::Char('2'));
    let shown = text(&render(&app, Theme::COLOR, SMALL));
    assert!(
        shown.contains(&format!("{first} reused, {} new", total - first)),
        "{shown}"
    );
    assert!(!shown.contains("another study"), "{shown}");
    // The same as a run from scratch (wall times aside).
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let fresh = rocklab::sweep::run_study(
        &app.shared.study,
        &Default::default(),
        rocklab::excitation::library::global().unwrap(),
        &cancel,
        &|_| {},
    )
    .unwrap();
    let timeless = |r: &rocklab::sweep::SweepResults| -> Vec<_> {
        r.outcomes
            .iter()
            .map(|o| {
                let mut o = o.clone();
                if let Ok(r) = &mut o.result {
                    r.wall_seconds = 0.0;
                }
                o
            })
            .collect()
    };
    let data = app.shared.results.as_ref().unwrap();
    assert_eq!(timeless(&data.results), timeless(&fresh));
}

fn save_default_as(dir: &std::path::Path, name: &str) -> std::path::PathBuf {
    let path = dir.join(format!("{name}.ron"));
    let mut study = rocklab::study::Study::builtin_default();
    study.name = name.into();
    std::fs::write(&path, study.to_ron_keeping(None).text).unwrap();
    path
}

/// `d` on the Run screen sends the next run elsewhere; opening another study (or Ctrl-N)
/// forgets it, saying so, so the next run does not collide with the old one's folder.
#[test]
fn the_d_folder_belongs_to_the_study_it_was_chosen_for() {
    let dir = tempfile::tempdir().unwrap();
    let other = save_default_as(dir.path(), "other");
    let mut app = new_app();
    let elsewhere = dir.path().join("elsewhere");
    let choose = |app: &mut App| {
        key(app, KeyCode::Char('2'));
        key(app, KeyCode::Char('d'));
        ctrl(app, 'u');
        ctrl(app, 'k');
        typed(app, elsewhere.to_str().unwrap());
        key(app, Enter);
        assert_eq!(app.shared.output_dir().unwrap(), elsewhere);
    };
    choose(&mut app);
    // `o` from the Run screen opens too.
    key(&mut app, KeyCode::Char('o'));
    typed(&mut app, other.to_str().unwrap());
    key(&mut app, Enter);
    assert_eq!(app.shared.path.as_deref(), Some(other.as_path()));
    assert_eq!(
        app.shared.output_dir().unwrap(),
        app.shared.options.out_root.join("other")
    );
    let (msg, _) = app.message.clone().unwrap();
    assert!(msg.contains("again") && msg.contains("elsewhere"), "{msg}");
    choose(&mut app);
    key(&mut app, KeyCode::Char('1'));
    ctrl(&mut app, 'n');
    assert_ne!(app.shared.output_dir().unwrap(), elsewhere);
    // Ctrl-N starts clean: no description, no header comment of the default's file.
    assert!(app.shared.study.description.is_empty());
    assert!(app.shared.original.is_none());
}

/// `rocklab tui bad.ron` with one invalid value opens it in the editor with the parser's
/// message (file, line, field, hint) on screen; runs are refused until it is fixed; a
/// malformed file and a missing path are refused with a message (the latter naming `tui`).
#[test]
fn an_invalid_study_opens_in_the_editor_with_its_error() {
    let dir = tempfile::tempdir().unwrap();
    let good = save_default_as(dir.path(), "bad");
    let text = std::fs::read_to_string(&good).unwrap();
    let at = text.find("duration: ").expect("a duration");
    let end = at + text[at..].find(',').unwrap();
    std::fs::write(
        &good,
        format!("{}duration: -5.0{}", &text[..at], &text[end..]),
    )
    .unwrap();
    let (study, why) = rocklab::tui::open_study(&good).unwrap();
    let why = why.expect("invalid");
    assert!(
        why.contains("bad.ron:") && why.contains("duration"),
        "{why}"
    );
    let mut app = App::new(study, Some(good.clone()), Options::default());
    app.show_invalid(why.clone());
    assert!(matches!(app.shared.check, Check::Invalid(_)));
    let shown = text_of(&app);
    assert!(shown.contains("duration"), "{shown}");
    key(&mut app, KeyCode::Char('r'));
    assert!(app.message.as_ref().unwrap().0.contains("cannot run"));
    // Fixed in the editor, it runs.
    set_field(&mut app, "duration", "8.0");
    assert!(
        matches!(app.shared.check, Check::Ok(_)),
        "{:?} {:?}",
        app.message,
        app.editor.edit_error,
    );
    assert_eq!(app.screen, Screen::Study);

    std::fs::write(&good, "(version: 1, name: ").unwrap();
    assert!(rocklab::tui::open_study(&good).is_err());
    let missing = dir.path().join("missing.ron");
    let o = crate::util::rocklab(&["tui", missing.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("no such file") && err.contains("rocklab tui"),
        "{err}"
    );
    assert!(!err.contains("rocklab run"), "{err}");
}

fn text_of(app: &App) -> String {
    text(&render(app, Theme::COLOR, SMALL))
}

/// Degrees typed in the editor stay degrees: in the tree, in the saved file (with the file's
/// field order and comments), and in the study read back; the cursor stays on the edited
/// field. `size` set on a block with `p` takes its place in one edit, said in 80 columns.
#[test]
fn degrees_round_trip_through_an_edit_and_a_save() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mine.ron");
    let written = "// my study\n(\n    version: 1,\n    name: \"mine\",\n    \
        structure: rigid(p: 2.0, alpha: deg(10)), // the block\n    \
        devices: [none, sequential(sigma: 0.5)],\n    \
        excitation: pulse(shape: sine, amplitude: alpha_ratio(1.5), frequency: ratio([2.0, 4.0])),\n    \
        rtol: 1e-6,\n    duration: 2.0,\n)\n";
    std::fs::write(&path, written).unwrap();
    let mut app = new_app();
    key(&mut app, KeyCode::Char('o'));
    typed(&mut app, path.to_str().unwrap());
    key(&mut app, Enter);
    let row = |app: &App, label: &str| {
        let row = app.editor.rows.iter().find(|r| r.label == label);
        row.unwrap().text.clone()
    };
    assert_eq!(row(&app, "alpha"), "deg(10)");
    set_field(&mut app, "alpha", "deg([8, 12])");
    assert!(
        app.editor.edit_error.is_none(),
        "{:?}",
        app.editor.edit_error
    );
    assert_eq!(app.editor.rows[app.editor.cursor].label, "alpha");
    assert_eq!(row(&app, "alpha"), "deg([8, 12])");
    assert_eq!(
        scene_count(&app),
        2 * 2 * 2,
        "2 angles × 2 devices × 2 frequencies"
    );
    key(&mut app, KeyCode::Char('s'));
    assert!(!app.shared.dirty, "{:?}", app.message);
    let saved = std::fs::read_to_string(&path).unwrap();
    assert_eq!(saved, written.replace("deg(10)", "deg([8, 12])"));
    let back = rocklab::study::Study::load(&path).unwrap();
    assert_eq!(back, app.shared.study);

    // `size` where `p` is set: one edit, the field in p's place.
    set_field(&mut app, "size", "1.5");
    assert!(
        app.editor.edit_error.is_none(),
        "{:?}",
        app.editor.edit_error
    );
    assert_eq!(app.editor.rows[app.editor.cursor].label, "size");
    let screen = text(&render(&app, Theme::COLOR, SMALL));
    assert!(screen.contains("size set in place of p"), "{screen}");
    assert!(screen.lines().all(|l| l.chars().count() <= 80));
    assert!(
        app.editor
            .tree
            .text()
            .contains("rigid(size: 1.5, alpha: deg([8, 12]))"),
        "{}",
        app.editor.tree.text()
    );
}
