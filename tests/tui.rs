//! The workbench, headless: the app state machine driven by key sequences, rendered with
//! ratatui's TestBackend, snapshotted by insta into the top-level `snapshots/` directory.
//! Frames are deterministic (`Options::deterministic` hides rates, ETAs and estimates).

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::buffer::Buffer;
use ratatui::style::{Color, Modifier};
use rocklab::study::Study;
use rocklab::sweep::SweepResults;
use rocklab::tui::app::{App, Check, Effect, Options, ResultsTab, SceneState, Screen};
use rocklab::tui::draw::draw;
use rocklab::tui::theme::Theme;
use std::path::PathBuf;
use std::time::Duration;

use KeyCode::{Backspace, Down, Enter, Esc, Left, Right, Up};

pub(crate) const SMALL: (u16, u16) = (80, 24);
const LARGE: (u16, u16) = (160, 48);

pub(crate) fn new_app() -> App {
    new_app_in(scratch_dir())
}

/// Where this test's runs write (never into out/): target/tui-tests/<test name>, emptied
/// first: a fixed path, so frames that show it are reproducible, and fresh, so no journal of
/// an earlier test run is resumed.
pub(crate) fn scratch_dir() -> PathBuf {
    let name = std::thread::current()
        .name()
        .unwrap_or("main")
        .replace("::", "-");
    let dir = PathBuf::from("target/tui-tests").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// An app whose runs write under `out_root` (as `out/` for the real workbench).
pub(crate) fn new_app_in(out_root: PathBuf) -> App {
    app_for(Study::builtin_default(), out_root)
}

/// A deterministic app on `study` running two jobs, its runs under `out_root`.
fn app_for(study: Study, out_root: PathBuf) -> App {
    App::new(
        study,
        None,
        Options {
            deterministic: true,
            jobs: Some(2),
            out_root,
        },
    )
}

pub(crate) fn render(app: &App, theme: Theme, (w, h): (u16, u16)) -> Buffer {
    let mut terminal = Terminal::new(TestBackend::new(w, h)).unwrap();
    terminal.draw(|f| draw(app, theme, f)).unwrap();
    terminal.backend().buffer().clone()
}

pub(crate) fn text(buf: &Buffer) -> String {
    let w = buf.area.width as usize;
    buf.content
        .chunks(w)
        .map(|row| {
            let line: String = row.iter().map(|c| c.symbol()).collect();
            line.trim_end().to_string()
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// One letter per cell for its foreground colour (`.` default), upper case when reversed:
/// the colours of map cells and spectrum bars, readable in a diff.
fn styles(buf: &Buffer) -> String {
    let w = buf.area.width as usize;
    buf.content
        .chunks(w)
        .map(|row| {
            let line: String = row
                .iter()
                .map(|c| {
                    let ch = match c.fg {
                        Color::Red => 'r',
                        Color::Green => 'g',
                        Color::Yellow => 'y',
                        Color::Magenta => 'm',
                        Color::Cyan => 'c',
                        Color::Blue => 'b',
                        Color::White => 'w',
                        Color::DarkGray => 'd',
                        Color::LightBlue => 'l',
                        Color::LightRed => 'p',
                        _ => '.',
                    };
                    if c.modifier.contains(Modifier::REVERSED) || c.bg == Color::Blue {
                        if ch == '.' {
                            '#'
                        } else {
                            ch.to_ascii_uppercase()
                        }
                    } else {
                        ch
                    }
                })
                .collect();
            line.trim_end_matches('.').to_string()
        })
        .collect::<Vec<_>>()
        .join("\n")
}

pub(crate) fn snap(name: &str, value: String) {
    insta::with_settings!({
        snapshot_path => concat!(env!("CARGO_MANIFEST_DIR"), "/snapshots"),
        prepend_module_to_snapshot => false,
        omit_expression => true,
    }, {
        insta::assert_snapshot!(format!("tui_{name}"), value);
    });
}

pub(crate) fn snap_text(app: &App, name: &str) {
    for (size, tag) in [(SMALL, "80x24"), (LARGE, "160x48")] {
        snap(
            &format!("{name}_{tag}"),
            text(&render(app, Theme::COLOR, size)),
        );
    }
}

fn snap_text_and_styles(app: &App, name: &str) {
    for (size, tag) in [(SMALL, "80x24"), (LARGE, "160x48")] {
        let buf = render(app, Theme::COLOR, size);
        snap(
            &format!("{name}_{tag}"),
            format!(
                "{}\n--- foreground colours ---\n{}",
                text(&buf),
                styles(&buf)
            ),
        );
    }
}

pub(crate) fn key(app: &mut App, code: KeyCode) -> Effect {
    app.handle_key(KeyEvent::new(code, KeyModifiers::NONE))
}

pub(crate) fn keys(app: &mut App, codes: &[KeyCode]) {
    for c in codes {
        key(app, *c);
    }
}

pub(crate) fn typed(app: &mut App, text: &str) {
    app.type_text(text);
}

pub(crate) fn ctrl(app: &mut App, c: char) -> Effect {
    app.handle_key(KeyEvent::new(KeyCode::Char(c), KeyModifiers::CONTROL))
}

/// Jump to a field with `/`, open its editor, replace the value, apply.
pub(crate) fn set_field(app: &mut App, field: &str, value: &str) {
    key(app, KeyCode::Char('/'));
    typed(app, field);
    key(app, Enter);
    key(app, Enter);
    ctrl(app, 'u');
    ctrl(app, 'k');
    typed(app, value);
    key(app, Enter);
}

pub(crate) fn scene_count(app: &App) -> usize {
    match &app.shared.check {
        Check::Ok(points) => points.len(),
        Check::Invalid(msg) => panic!("study invalid: {msg}"),
    }
}

/// Shrink the default study to a few quick scenes, by keys.
/// Shrink the default study's frequency grid and add an overturning map over frequency ×
/// amplitude, by keys: 3 variants × 4 frequencies × 3 amplitudes.
pub(crate) fn small_map_study(app: &mut App) {
    set_field(app, "frequency", "ratio([2.0, 4.0, 6.0, 8.0])");
    set_field(app, "amplitude", "alpha_ratio([1.0, 2.0, 4.0])");
    set_field(app, "map", "(x: frequency, y: amplitude)");
    assert!(
        app.editor.edit_error.is_none(),
        "{:?}",
        app.editor.edit_error
    );
}

pub(crate) fn run_to_completion(app: &mut App) {
    key(app, KeyCode::Char('r'));
    assert_eq!(app.screen, Screen::Run);
    assert!(
        app.wait_idle(Duration::from_secs(120)),
        "sweep did not finish"
    );
}

/// Results of [`small_map_study`] computed once and kept (tests/data), so that the results
/// screens' snapshots test the drawing, not the physics: they do not change when the solver
/// or a model does. tests/data/tui_small_map.ron says how to regenerate them (after a
/// deliberate change of the default study, the solver or the results format).
pub(crate) fn fixed_results() -> SweepResults {
    rocklab::report::load_results(std::path::Path::new(
        "tests/data/tui_small_map_results.json",
    ))
    .unwrap()
}

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
            "t",
            "theta",
            "flywheel_a_vel",
            "flywheel_b_vel",
            "clutch_force_a",
            "clutch_force_b",
            "e_input",
            "e_structure",
            "e_device_damping",
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
    assert_eq!(history.column("t").unwrap().last(), Some(&15.0));
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
    // Just above the minimum, every screen still draws.
    for s in ['1', '2', '3', '4'] {
        key(&mut app, KeyCode::Char(s));
        let buf = text(&render(&app, Theme::COLOR, (40, 10)));
        assert!(buf.contains("rocklab"), "{buf}");
    }
}

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

/// q and Ctrl-C during a sweep ask first (keep finished scenes is the default, n keeps it
/// running); after a confirmed quit, the finished scenes are on disk, and a restarted
/// workbench's `r` reuses them instead of computing them again.
#[test]
fn quitting_mid_sweep_asks_and_a_restart_reuses_the_finished_scenes() {
    let root = scratch_dir();
    let mut app = new_app_in(root.clone());
    small_map_study(&mut app);
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
    small_map_study(&mut again);
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
        assert_eq!(app.shared.output_dir(), dir, "a rerun resumes there");
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
