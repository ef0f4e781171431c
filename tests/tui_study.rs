//! The Study screen, headless: the tree, editing fields and list elements, refusing bad
//! values, saving, opening, searching, the help overlay. Helpers in tests/tui.rs.

use crate::tui::{
    SMALL, ctrl, key, keys, new_app, render, scene_count, set_field, small_map_study, snap,
    snap_text, text, typed,
};
use crossterm::event::KeyCode::{self, Down, Enter, Esc};
use rocklab::study::Study;
use rocklab::tui::app::Effect;
use rocklab::tui::theme::Theme;

#[test]
fn study_screen_shows_the_default_study_and_its_scene_count() {
    let mut app = new_app();
    let n = scene_count(&app);
    assert!(n > 0);
    let buf = text(&render(&app, Theme::COLOR, SMALL));
    assert!(buf.contains(&format!("{n} scenes")), "{buf}");
    snap_text(&app, "study_start");
    keys(&mut app, &[Down, Down, Down]);
    snap_text(&app, "study_cursor");
}

#[test]
fn editing_a_grid_changes_the_scene_count_and_marks_the_study_unsaved() {
    let mut app = new_app();
    let before = scene_count(&app);
    set_field(&mut app, "frequency", "ratio([2.0, 4.0, 8.0])");
    let after = scene_count(&app);
    assert!(app.shared.dirty);
    assert!(after < before, "{after} ≥ {before}");
    snap_text(&app, "study_edited");
    // The scene count is proportional to the number of points on the grid.
    set_field(
        &mut app,
        "frequency_ratios",
        "ratio([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])",
    );
    assert_eq!(
        scene_count(&app),
        2 * after,
        "{:?} {:?}",
        app.editor.edit_error,
        app.message
    );
}

#[test]
fn a_malformed_value_is_refused_with_the_parser_message_and_the_study_is_kept() {
    let mut app = new_app();
    let before = scene_count(&app);
    key(&mut app, KeyCode::Char('/'));
    typed(&mut app, "frequency");
    key(&mut app, Enter);
    key(&mut app, Enter);
    typed(&mut app, "]]");
    key(&mut app, Enter);
    assert!(
        app.editor.edit.is_some(),
        "the editor stays open on an error"
    );
    assert!(app.editor.edit_error.is_some());
    assert!(!app.shared.dirty);
    snap_text(&app, "study_parse_error");
    key(&mut app, Esc);
    assert!(app.editor.edit.is_none());
    assert_eq!(scene_count(&app), before);
}

#[test]
fn a_physically_invalid_value_is_refused_with_the_field_and_a_hint() {
    let mut app = new_app();
    let before = scene_count(&app);
    set_field(&mut app, "alpha", "-0.1");
    let err = app.editor.edit_error.clone().expect("refused");
    assert!(err.contains("alpha"), "{err}");
    assert!(!app.shared.dirty);
    snap_text(&app, "study_invalid");
    key(&mut app, Esc);
    assert_eq!(scene_count(&app), before);
}

#[test]
fn an_unset_optional_field_can_be_set_and_unset() {
    let mut app = new_app();
    let before = scene_count(&app);
    // The default study has no overturning map: set one over frequency × amplitude.
    set_field(&mut app, "map", "(x: frequency, y: amplitude)");
    assert!(
        app.editor.edit_error.is_none(),
        "{:?}",
        app.editor.edit_error
    );
    set_field(&mut app, "amplitude", "alpha_ratio([1.5, 3.0])");
    assert_eq!(scene_count(&app), 2 * before);
    assert!(app.shared.study.map.is_some());
    key(&mut app, KeyCode::Char('/'));
    typed(&mut app, "map");
    key(&mut app, Enter);
    key(&mut app, KeyCode::Char('d'));
    assert!(app.shared.study.map.is_none());
}

#[test]
fn list_elements_can_be_added_from_a_copy_and_deleted() {
    let mut app = new_app();
    let before = scene_count(&app);
    let variants = app.shared.study.devices.len();
    key(&mut app, KeyCode::Char('/'));
    typed(&mut app, "[1]");
    key(&mut app, Enter);
    // An unchanged copy would be a second variant with the same label: refused, editor open.
    key(&mut app, KeyCode::Char('a'));
    key(&mut app, Enter);
    assert!(app.editor.edit_error.is_some());
    assert_eq!(app.shared.study.devices.len(), variants);
    // Changed and labelled, it goes in after the original, with as many scenes as each other
    // variant.
    ctrl(&mut app, 'u');
    ctrl(&mut app, 'k');
    typed(
        &mut app,
        "sequential(sigma: 1.0, label: \"sequential σ=1\")",
    );
    key(&mut app, Enter);
    assert!(
        app.editor.edit_error.is_none(),
        "{:?}",
        app.editor.edit_error
    );
    assert_eq!(app.shared.study.devices.len(), variants + 1);
    assert_eq!(scene_count(&app), before + before / variants);
    let row = &app.editor.rows[app.editor.cursor];
    assert_eq!(row.label, "[2]", "the cursor is on the new element");
    key(&mut app, KeyCode::Char('d'));
    assert_eq!(scene_count(&app), before);
    assert_eq!(app.shared.study.devices.len(), variants);
}

#[test]
fn quitting_with_unsaved_changes_asks_first() {
    let mut app = new_app();
    set_field(&mut app, "frequency", "ratio(2.0)");
    assert_eq!(key(&mut app, KeyCode::Char('q')), Effect::None);
    snap_text(&app, "study_quit_guard");
    assert_eq!(key(&mut app, KeyCode::Char('n')), Effect::None);
    assert_eq!(key(&mut app, KeyCode::Char('q')), Effect::None);
    assert_eq!(key(&mut app, KeyCode::Char('y')), Effect::Quit);
    // Ctrl-C also asks once, then quits.
    let mut app = new_app();
    set_field(&mut app, "frequency", "ratio(2.0)");
    assert_eq!(ctrl(&mut app, 'c'), Effect::None);
    assert_eq!(ctrl(&mut app, 'c'), Effect::Quit);
    // Without changes, q quits at once.
    let mut app = new_app();
    assert_eq!(key(&mut app, KeyCode::Char('q')), Effect::Quit);
}

#[test]
fn save_as_writes_a_study_that_opens_again() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("shrunk.ron");
    let mut app = new_app();
    set_field(&mut app, "frequency", "ratio([2.0, 4.0])");
    let count = scene_count(&app);
    key(&mut app, KeyCode::Char('S'));
    ctrl(&mut app, 'u');
    ctrl(&mut app, 'k');
    typed(&mut app, path.to_str().unwrap());
    key(&mut app, Enter);
    assert!(!app.shared.dirty, "{:?}", app.message);
    let saved = Study::load(&path).unwrap();
    assert_eq!(saved.expand().unwrap().len(), count);
    // Open it in a fresh workbench through the prompt.
    let mut fresh = new_app();
    key(&mut fresh, KeyCode::Char('o'));
    typed(&mut fresh, path.to_str().unwrap());
    key(&mut fresh, Enter);
    assert_eq!(scene_count(&fresh), count);
    assert_eq!(fresh.shared.path.as_deref(), Some(path.as_path()));
}

#[test]
fn help_overlay_and_small_terminals() {
    let mut app = new_app();
    key(&mut app, KeyCode::Char('?'));
    assert!(app.help.visible);
    snap_text(&app, "help");
    key(&mut app, Esc);
    assert!(!app.help.visible);
    snap("too_small_30x8", text(&render(&app, Theme::COLOR, (30, 8))));
    // Between 40×10 and 80×24 (README: "smaller terminals get a notice"): a line above the
    // key hints gives the size, the remedy and what is cut; none from 80×24.
    for (size, cut) in [
        ((60, 20), "(labels cut, fewer rows)"),
        ((79, 23), "(labels cut, fewer rows)"),
        ((79, 24), "(long labels cut at the right)"),
        ((80, 23), "(fewer rows and smaller charts)"),
    ] {
        let buf = text(&render(&app, Theme::COLOR, size));
        let lines: Vec<&str> = buf.lines().collect();
        let notice = lines[lines.len() - 2];
        let want = format!("{}×{} < 80×24: enlarge the terminal {cut}", size.0, size.1);
        assert_eq!(notice.trim_end(), want, "{buf}");
        assert!(lines[lines.len() - 1].starts_with("? help"), "{buf}");
        if size == (60, 20) || size == (79, 23) {
            snap(&format!("study_cut_{}x{}", size.0, size.1), buf);
        }
    }
    for size in [(80, 24), (160, 48)] {
        let buf = text(&render(&app, Theme::COLOR, size));
        assert!(!buf.contains("enlarge the terminal"), "{buf}");
    }
    // Just above the minimum, every screen still draws.
    for s in ['1', '2', '3', '4'] {
        key(&mut app, KeyCode::Char(s));
        let buf = text(&render(&app, Theme::COLOR, (40, 10)));
        assert!(buf.contains("rocklab"), "{buf}");
    }
}

/// `n` / `N` after `/` find the next / previous match and keep the study.
#[test]
fn n_repeats_the_search_and_never_replaces_the_study() {
    let mut app = new_app();
    small_map_study(&mut app);
    let before = app.shared.study.clone();
    key(&mut app, KeyCode::Char('/'));
    typed(&mut app, "name");
    key(&mut app, Enter);
    let first = app.editor.cursor;
    key(&mut app, KeyCode::Char('n'));
    let second = app.editor.cursor;
    assert!(
        app.editor.rows[second]
            .label
            .to_lowercase()
            .contains("name")
    );
    assert_eq!(app.shared.study, before, "n keeps the study");
    key(&mut app, KeyCode::Char('N'));
    assert_eq!(app.editor.cursor, first);
    // The key hints fit 80 columns whole: the status line is the list cut between hints.
    let all = "? help  q quit  ↑↓ move  Enter edit  r run  s save  / find  o open  a add  \
               d del/unset  S save as  n/N next/prev  ^N new";
    let status = text(&render(&app, Theme::COLOR, SMALL));
    let shown = status.lines().last().unwrap();
    assert!(all.starts_with(shown), "{shown}");
    assert!(
        all[shown.len()..].starts_with("  "),
        "cut mid-hint: {shown}"
    );
    assert!(
        shown.contains("r run") && shown.contains("s save"),
        "{shown}"
    );
}
