//! The Results screen's design view (`g`): a small design study run here, its answer shown
//! one line per design point, and the readout of the row under the cursor checked against
//! design.csv's row; not-achievable and non-monotone points are shown as such. Snapshot at
//! 80×24.

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use rocklab::numfmt::fmt_num;
use rocklab::report::design::design_csv;
use rocklab::study::Study;
use rocklab::sweep::design::{DesignRow, DesignStatus};
use rocklab::sweep::{self, SweepOptions, SweepResults};
use rocklab::tui::app::{App, Options, ResultsTab, Screen};
use rocklab::tui::draw::draw;
use rocklab::tui::theme::Theme;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

/// One block, the bare block, a sequential and a mechanistic clutch, three pulses, σ up to
/// 1.5: the bare block fails, the mechanistic clutch's answer is found, the sequential one's
/// lies above the bracket (about 1.75 for these pulses).
const STUDY: &str = r#"(
    version: 1,
    name: "design_view",
    structure: rigid(p: 2.0, alpha: deg(8)),
    devices: [none, sequential(sigma: 0.5), mechanistic(sigma: 0.5, cbar: 1.0)],
    excitation: pulse(
        shape: sine,
        amplitude: tan_alpha_ratio(2.0),
        frequency: ratio((from: 3.0, to: 7.0, steps: 3)),
    ),
    quantities: [peak_rotation_ratio],
    spectrum: alpha,
    duration: 8.0,
    design: (
        parameter: sigma,
        bracket: (0.0, 1.5),
        resolution: 0.05,
        target: limit(quantity: peak_rotation_ratio, max: 0.5),
    ),
)"#;

fn study() -> Study {
    Study::from_ron_str(STUDY, "design_view.ron").unwrap_or_else(|e| panic!("{e}"))
}

fn results(study: &Study) -> SweepResults {
    sweep::run_study(
        study,
        &SweepOptions::default(),
        rocklab::excitation::library::global().unwrap(),
        &AtomicBool::new(false),
        &|_| {},
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

fn app_with(results: SweepResults) -> App {
    let dir = PathBuf::from("target/tui-tests/design");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut app = App::new(
        Study::builtin_default(),
        None,
        Options {
            deterministic: true,
            jobs: Some(1),
            out_root: dir.clone(),
        },
    );
    app.open_results(results, dir);
    assert_eq!(app.screen, Screen::Results);
    app
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

/// design.csv's rows as column → text maps.
fn csv_rows(study: &Study, rows: &[DesignRow]) -> Vec<HashMap<String, String>> {
    let bytes = design_csv(study, rows).unwrap();
    let mut reader = csv::Reader::from_reader(bytes.as_slice());
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    reader
        .records()
        .map(|r| {
            let r = r.unwrap();
            header
                .iter()
                .cloned()
                .zip(r.iter().map(String::from))
                .collect()
        })
        .collect()
}

/// The text after `word ` in `line` (as far as the next space, comma or parenthesis).
fn text_after(line: &str, word: &str) -> String {
    let at = line
        .find(word)
        .unwrap_or_else(|| panic!("{word} not in {line}"))
        + word.len();
    line[at..]
        .trim_start()
        .chars()
        .take_while(|c| !matches!(c, ' ' | ',' | ')'))
        .collect()
}

/// A design.csv number as the workbench formats numbers.
fn csv_num(row: &HashMap<String, String>, column: &str) -> String {
    let v: f64 = row[column]
        .parse()
        .unwrap_or_else(|e| panic!("{column} {:?}: {e}", row[column]));
    fmt_num(v)
}

#[test]
fn the_design_view_reads_out_the_row_of_design_csv_under_the_cursor() {
    let study = study();
    let results = results(&study);
    let mut app = app_with(results);
    // A design study's results open on its answer.
    assert_eq!(app.browser.tab, ResultsTab::Design);
    let rows = app.shared.results.as_ref().unwrap().design.clone();
    let csv = csv_rows(&study, &rows);
    let statuses: Vec<DesignStatus> = rows.iter().map(|r| r.status).collect();
    assert_eq!(
        statuses,
        [
            DesignStatus::ReferenceFails,
            DesignStatus::NotAchievable,
            DesignStatus::Found
        ],
        "{rows:?}"
    );
    // The cursor on the mechanistic clutch: the readout's numbers are design.csv's row.
    keys(&mut app, &[KeyCode::Down, KeyCode::Down]);
    let text = screen(&app, (80, 24));
    let line = |needle: &str| {
        text.lines()
            .find(|l| l.contains(needle))
            .unwrap_or_else(|| panic!("{needle} not in\n{text}"))
            .to_string()
    };
    let row = &csv[2];
    assert_eq!(row["status"], "found");
    let answer = line("least σ =");
    assert!(answer.starts_with("mechanistic"), "{answer}");
    for (word, column) in [("σ =", "value"), ("lo", "lo"), ("hi", "hi")] {
        let shown = text_after(&answer, word);
        assert_eq!(shown, csv_num(row, column), "{word} vs {column}: {answer}");
    }
    let probes = line("probes (");
    assert_eq!(text_after(&probes, ""), csv_num(row, "probes"), "{probes}");
    assert_eq!(text_after(&probes, "("), csv_num(row, "scenes"), "{probes}");
    assert!(
        probes.contains(&format!("governing {},", row["governing"])),
        "{probes} vs {}",
        row["governing"]
    );
    assert_eq!(text_after(&probes, "achieved"), csv_num(row, "achieved"));
    let achieved: f64 = row["achieved"].parse().unwrap();
    assert!(achieved <= 0.5, "the answer meets the target: {achieved}");
    assert!(line("found:").contains("least value found"));
    snap("design_80x24", text);
    // The sequential clutch: not achievable, its bar runs off the bracket's top.
    keys(&mut app, &[KeyCode::Up]);
    let text = screen(&app, (80, 24));
    assert!(
        text.contains("not achievable within the bracket: σ = 1.5 fails"),
        "{text}"
    );
    assert!(text.contains("░▶     >1.5 not_achievable"), "{text}");
    let gov = &csv[1]["governing"];
    assert!(text.contains(&format!("governing {gov},")), "{text}");
}

#[test]
fn a_non_monotone_point_is_shown_with_the_values_that_fail_again() {
    let study = study();
    let results = results(&study);
    let mut app = app_with(results);
    let data = app.shared.results.as_mut().unwrap();
    let mut row = data.design[2].clone();
    row.status = DesignStatus::NonMonotone;
    row.fails_above = vec![0.15, 0.6];
    let value = row.value.unwrap();
    data.design.push(row);
    keys(&mut app, &[KeyCode::End]);
    let text = screen(&app, (80, 24));
    assert!(
        text.contains(&format!("{} non_monotone", fmt_num(value))),
        "{text}"
    );
    assert!(
        text.contains("fails again at σ = 0.15, 0.6: no threshold"),
        "{text}"
    );
    assert!(text.contains("non_monotone: a value above the answer fails again"));
}

#[test]
fn results_of_another_study_say_the_design_view_has_nothing() {
    let results: SweepResults =
        serde_json::from_str(include_str!("data/tui_small_map_results.json")).unwrap();
    let mut app = app_with(results);
    assert_ne!(app.browser.tab, ResultsTab::Design);
    keys(&mut app, &[KeyCode::Char('g')]);
    assert_eq!(app.browser.tab, ResultsTab::Design);
    assert!(screen(&app, (80, 24)).contains("not of a design study"));
}
