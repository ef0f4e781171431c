//! The workbench's comparison, driven by keys on small results computed with the real binary
//! (tests/data/tui_clutch_grid*.{ron,json}, tests/data/tui_records*.{ron,json}; how to remake
//! them is in the .ron files): pairing as `rocklab compare` pairs (same record, same
//! structure; one side a grid), the statistics in the readout, the shared y scale, the B/A row
//! around 1.0, the overturning maps' difference, and the spectra filter.

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use rocklab::report::{PointState, compare};
use rocklab::study::{DeviceKind, Part, Study};
use rocklab::sweep::SweepResults;
use rocklab::tui::app::{App, Options, ResultsTab, Screen};
use rocklab::tui::draw::draw;
use rocklab::tui::theme::Theme;
use std::path::PathBuf;

use KeyCode::{Char, Down, Enter, Esc, Left, Right};

fn app_with(results: &str) -> App {
    let results: SweepResults = serde_json::from_str(results).unwrap();
    let mut app = App::new(
        Study::builtin_default(),
        None,
        Options {
            deterministic: true,
            jobs: Some(1),
            out_root: PathBuf::from("target/tui-tests/compare"),
        },
    );
    app.open_results(results, PathBuf::from("tests/data"));
    assert_eq!(app.screen, Screen::Results);
    app
}

fn grid() -> App {
    app_with(include_str!("data/tui_clutch_grid_results.json"))
}

fn records() -> App {
    app_with(include_str!("data/tui_records_results.json"))
}

fn map_app() -> App {
    app_with(include_str!("data/tui_small_map_results.json"))
}

fn keys(app: &mut App, codes: &[KeyCode]) {
    for c in codes {
        app.handle_key(KeyEvent::new(*c, KeyModifiers::NONE));
    }
}

fn screen(app: &App, (w, h): (u16, u16)) -> String {
    let mut terminal = Terminal::new(TestBackend::new(w, h)).unwrap();
    terminal.draw(|f| draw(app, Theme::COLOR, f)).unwrap();
    let buf = terminal.backend().buffer().clone();
    buf.content
        .chunks(w as usize)
        .map(|row| {
            let line: String = row.iter().map(|c| c.symbol()).collect();
            line.trim_end().to_string()
        })
        .collect::<Vec<_>>()
        .join("\n")
}

fn snap(name: &str, value: String) {
    insta::with_settings!({
        snapshot_path => concat!(env!("CARGO_MANIFEST_DIR"), "/snapshots"),
        prepend_module_to_snapshot => false,
        omit_expression => true,
    }, {
        insta::assert_snapshot!(format!("tui_{name}"), value);
    });
}

/// The pairs the comparison shows now (current quantity).
fn pairs(app: &App) -> Vec<compare::SpectrumPair> {
    let data = app.shared.results.as_ref().unwrap();
    let q = app.browser.current_quantity(data).unwrap();
    app.browser.compare.pairs(data, q).unwrap()
}

/// Every structure and excitation setting of A is B's: the same situation.
fn same_structure_and_excitation(p: &compare::SpectrumPair) -> bool {
    p.a_group
        .settings
        .iter()
        .filter(|s| s.part != Part::Device)
        .all(|s| p.b_group.setting(&s.id) == Some(s))
}

#[test]
fn a_clutch_grid_pairs_sequential_with_each_member_sorted_by_mean_ratio() {
    let mut app = grid();
    keys(&mut app, &[Char('c')]);
    assert_eq!(app.browser.tab, ResultsTab::Compare);
    let view = &app.browser.compare;
    assert_eq!(view.a.selector_text(), "sequential");
    assert_eq!(view.b.selector_text(), "mechanistic");
    let p = pairs(&app);
    // One row per grid member (2 ξθ × 2 play), each against the one sequential spectrum.
    assert_eq!(p.len(), 4);
    let mut members: Vec<(f64, f64)> = p
        .iter()
        .map(|p| {
            assert_eq!(p.a_group.device, DeviceKind::Sequential);
            assert_eq!(p.b_group.device, DeviceKind::Mechanistic);
            assert!(same_structure_and_excitation(p), "{p:?}");
            let v = |id: &str| p.b_group.setting(id).unwrap().value;
            (v("xi_theta"), v("play"))
        })
        .collect();
    members.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(
        members,
        [(0.02, 0.0), (0.02, 0.005), (0.2, 0.0), (0.2, 0.005)]
    );
    // Sorted by the mean of B/A, smallest first.
    let means: Vec<f64> = p.iter().map(|p| p.stats.mean_ratio.unwrap()).collect();
    assert!(means.windows(2).all(|w| w[0] <= w[1]), "{means:?}");
    // The statistics are those of the two spectra, point by point: the mean of B/A over the
    // points where both survive, and the overturns one side has and the other not.
    let data = app.shared.results.as_ref().unwrap();
    for pair in &p {
        let of = |g: &rocklab::report::Group| data.spectra.iter().find(|s| s.group == *g).unwrap();
        let (a, b) = (of(&pair.a_group), of(&pair.b_group));
        assert_eq!(a.xs, b.xs);
        let both: Vec<f64> = (0..a.xs.len())
            .filter(|&i| a.states[i] == PointState::Survived && b.states[i] == PointState::Survived)
            .map(|i| b.ys[i].unwrap() / a.ys[i].unwrap())
            .collect();
        let mean = both.iter().sum::<f64>() / both.len() as f64;
        assert!((pair.stats.mean_ratio.unwrap() - mean).abs() < 1e-12);
        let a_only = (0..a.xs.len())
            .filter(|&i| {
                a.states[i] == PointState::Overturned && b.states[i] == PointState::Survived
            })
            .count();
        assert_eq!(pair.stats.a_overturns_b_survives, a_only);
    }
    // The readout says which statistic is which, for the selected pair.
    let s = &p[0].stats;
    let shown = screen(&app, (80, 24));
    assert!(
        shown.contains(&format!("A overturns, B not: {}", s.a_overturns_b_survives)),
        "{shown}"
    );
    assert!(shown.contains("mean ") && shown.contains("median ") && shown.contains("peak ratio"));
    assert!(shown.contains("1.0 ─"), "the 1.0 line is marked:\n{shown}");
    snap("compare_grid_80x24", shown);
    // ↓ selects the next pair, y toggles the scale.
    keys(&mut app, &[Down, Char('y')]);
    assert_eq!(app.browser.compare.pair, 1);
    let shown = screen(&app, (80, 24));
    assert!(shown.contains("each on its own scale"), "{shown}");
    let name: String = format!("B {}", p[1].b).chars().take(18).collect();
    assert!(shown.contains(&name), "{name}\n{shown}");
}

#[test]
fn the_picker_chooses_a_and_b_by_device_and_parameter_value() {
    let mut app = grid();
    keys(&mut app, &[Char('c')]);
    // B: the field below the device is the first parameter that varies (ξθ); → its first
    // value.
    keys(&mut app, &[Char('b'), Down, Right]);
    assert!(app.browser.compare.picking.is_some());
    let shown = screen(&app, (80, 24));
    assert!(shown.contains("pick B"), "{shown}");
    keys(&mut app, &[Enter]);
    assert!(app.browser.compare.picking.is_none());
    assert_eq!(
        app.browser.compare.b.selector_text(),
        "mechanistic(xi_theta: 0.02)"
    );
    let p = pairs(&app);
    assert_eq!(p.len(), 2);
    assert!(
        p.iter()
            .all(|p| p.b_group.setting("xi_theta").unwrap().value == 0.02)
    );
    // Play too: one pair.
    keys(&mut app, &[Char('b'), Down, Down, Right, Right, Enter]);
    assert_eq!(
        app.browser.compare.b.selector_text(),
        "mechanistic(xi_theta: 0.02, play: 0.005)"
    );
    assert_eq!(pairs(&app).len(), 1);
    // Back to "any" for play (value list wraps round through "any").
    keys(&mut app, &[Char('b'), Down, Down, Right, Enter]);
    assert_eq!(
        app.browser.compare.b.selector_text(),
        "mechanistic(xi_theta: 0.02)"
    );
    // x swaps: the mechanistic members become A, the sequential B.
    keys(&mut app, &[Char('x')]);
    assert!(
        pairs(&app)
            .iter()
            .all(|p| p.a_group.device == DeviceKind::Mechanistic)
    );
}

#[test]
fn a_record_suite_pairs_each_record_with_the_same_record() {
    let mut app = records();
    keys(&mut app, &[Char('c')]);
    assert_eq!(app.browser.compare.a.selector_text(), "sequential");
    assert_eq!(app.browser.compare.b.selector_text(), "mechanistic");
    let check = |app: &App, a: DeviceKind| {
        let p = pairs(app);
        assert_eq!(p.len(), 2, "one pair per record");
        let mut recs: Vec<&str> = p
            .iter()
            .map(|p| {
                assert_eq!(p.a_group.device, a);
                assert_eq!(p.a_group.record(), p.b_group.record(), "{p:?}");
                assert!(same_structure_and_excitation(p));
                p.b_group.record().unwrap()
            })
            .collect();
        recs.sort();
        assert_eq!(recs, ["landers", "northridge"]);
    };
    check(&app, DeviceKind::Sequential);
    // A: the device before sequential is bare.
    keys(&mut app, &[Char('a'), Left, Enter]);
    assert_eq!(app.browser.compare.a.selector_text(), "bare");
    check(&app, DeviceKind::None);
    // A single record on the A side still pairs only with that record.
    keys(&mut app, &[Char('a'), Down, Right, Enter]);
    assert_eq!(
        app.browser.compare.a.selector_text(),
        "bare(record: landers)"
    );
    let p = pairs(&app);
    assert_eq!(p.len(), 1);
    assert_eq!(p[0].b_group.record(), Some("landers"));
}

#[test]
fn the_overturning_maps_difference_is_drawn_with_a_legend() {
    let mut app = map_app();
    keys(&mut app, &[Char('c'), Char('d')]);
    let data = app.shared.results.as_ref().unwrap();
    let maps = app.browser.compare.map_pairs(data).unwrap();
    assert_eq!(maps.len(), 1);
    let m = &maps[0];
    assert_eq!(m.a_group.device, DeviceKind::Sequential);
    assert_eq!(m.b_group.device, DeviceKind::Mechanistic);
    // Cell by cell, from the two maps.
    let of = |g: &rocklab::report::Group| data.maps.iter().find(|x| x.group == *g).unwrap();
    let (a, b) = (of(&m.a_group), of(&m.b_group));
    for (iy, row) in m.cells.iter().enumerate() {
        for (ix, c) in row.iter().enumerate() {
            let want = match (a.cells[iy][ix], b.cells[iy][ix]) {
                (Some(true), Some(false)) => compare::MapCell::OnlyBSurvives,
                (Some(false), Some(true)) => compare::MapCell::OnlyASurvives,
                (Some(true), Some(true)) => compare::MapCell::BothOverturn,
                (Some(false), Some(false)) => compare::MapCell::BothSurvive,
                _ => compare::MapCell::Missing,
            };
            assert_eq!(*c, want);
        }
    }
    let shown = screen(&app, (80, 24));
    for c in compare::MapCell::ALL {
        assert!(
            shown.contains(&format!("{} {} {}", c.glyph(), c.meaning(), m.count(c))),
            "{c:?}:\n{shown}"
        );
    }
    snap("compare_map_80x24", shown);
    // And the spectra comparison of the same results, on the shared scale.
    keys(&mut app, &[Char('d')]);
    let shown = screen(&app, (80, 24));
    assert!(shown.contains("y: A and B on one scale, 0–"), "{shown}");
    snap("compare_spectra_80x24", shown);
}

#[test]
fn the_spectra_filter_picks_rows_by_parameter_and_esc_clears_it() {
    let mut app = grid();
    let rows = |app: &App| app.browser.rows(app.shared.results.as_ref().unwrap()).len();
    assert_eq!(rows(&app), 5);
    keys(&mut app, &[Char('f')]);
    app.type_text("mechanistic(play: 0.005)");
    keys(&mut app, &[Enter]);
    assert_eq!(rows(&app), 2);
    let shown = screen(&app, (80, 24));
    assert!(
        shown.contains("filter mechanistic(play: 0.005): 2 of 5 rows"),
        "{shown}"
    );
    // Rows are named by what varies among them: ξθ, the shared words said once.
    assert!(shown.contains("all rows: mechanistic"), "{shown}");
    // The cursor stays on the filtered rows.
    keys(&mut app, &[Down, Down, Down]);
    assert_eq!(app.browser.spectra.row, 1);
    // A filter that matches nothing is refused with the values there are; the line stays.
    keys(&mut app, &[Char('f')]);
    app.handle_key(KeyEvent::new(Char('u'), KeyModifiers::CONTROL));
    app.type_text("mechanistic(play: 0.7)");
    keys(&mut app, &[Enter]);
    assert!(app.browser.spectra.filter_edit.is_some());
    let shown = screen(&app, (80, 24));
    assert!(shown.contains("matches nothing"), "{shown}");
    // Esc clears: every row again, and q is a key for the app again.
    keys(&mut app, &[Esc]);
    assert_eq!(rows(&app), 5);
    assert!(app.browser.spectra.filter.is_none());
}
