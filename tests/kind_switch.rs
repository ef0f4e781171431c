//! Switching the excitation kind in one edit (issue 42, item 6a): pulse → record with the
//! spectrum and map still on the pulse's axes is accepted, the dependent fields follow by the
//! library's rule (`Study::follow_excitation`), and the status line says what changed at 80×24.

use crate::tui::{SMALL, key, new_app, render, set_field, small_map_study, snap, text};
use crossterm::event::KeyCode;
use rocklab::study::{Axis, ExcitationFamily};
use rocklab::tui::theme::Theme;

#[test]
fn pulse_to_record_is_one_edit_with_a_note() {
    let mut app = new_app();
    small_map_study(&mut app);
    assert!(app.shared.study.map.is_some());
    set_field(
        &mut app,
        "excitation",
        "record(names: [\"landers\"], scale: [0.5, 1.0])",
    );
    assert!(
        app.editor.edit_error.is_none(),
        "{:?}",
        app.editor.edit_error
    );
    let study = &app.shared.study;
    assert!(matches!(study.excitation, ExcitationFamily::Record { .. }));
    assert_eq!(study.spectrum, Axis::Scale);
    assert!(study.map.is_none());
    let screen = text(&render(&app, Theme::COLOR, SMALL));
    let note = "spectrum frequency → scale, map dropped (its axes are gone)";
    assert!(screen.contains(note), "{screen}");
    snap("kind_switch_80x24", screen);
    // And back: one edit again, the frequency axis returns.
    key(&mut app, KeyCode::Esc);
    set_field(
        &mut app,
        "excitation",
        "pulse(shape: sine, amplitude: alpha_ratio(1.5), frequency: ratio([2.0, 4.0]))",
    );
    assert!(
        app.editor.edit_error.is_none(),
        "{:?}",
        app.editor.edit_error
    );
    assert_eq!(app.shared.study.spectrum, Axis::Frequency);
}
