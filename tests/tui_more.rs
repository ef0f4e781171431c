//! Views cut to fit say so (issue 42, item 7): a spectra list, a map's rows and a comparison's
//! pairs cut at 80×24 carry the one "more" marker (`▴ N more  ▾ N more`), a strip's window
//! says which points it shows, comparison labels use the width they have, and the help
//! overlay never cuts a word.

use crate::tui::{SMALL, app_for, key, keys, render, scratch_dir, snap, text};
use crossterm::event::KeyCode::{self, Down, Up};
use rocklab::study::{Axis, MapAxes, Study};
use rocklab::sweep::{SceneOutcome, SweepResults};
use rocklab::tui::theme::Theme;

/// The default study with 45 amplitudes × 65 frequencies, bare only, and a map over them.
fn big_study() -> Study {
    let text = include_str!("../studies/default.ron")
        .replace(
            "amplitude: alpha_ratio(1.5)",
            "amplitude: alpha_ratio((from: 1.0, to: 5.4, steps: 45))",
        )
        .replace(
            "ratio((from: 1.0, to: 12.0, steps: 12))",
            "ratio((from: 1.0, to: 13.8, steps: 65))",
        );
    let mut study = Study::from_ron_str(&text, "big").unwrap();
    study.devices.truncate(1);
    study.map = Some(MapAxes {
        x: Axis::Frequency,
        y: Axis::Amplitude,
        refine: None,
    });
    study
}

/// Made-up results for every scene: a peak that grows with the index, every 7th overturned.
fn synthetic(study: &Study) -> SweepResults {
    let outcomes = study
        .expand()
        .unwrap()
        .into_iter()
        .map(|point| {
            let f = 0.1 + 0.5 * ((point.index as f64) * 0.13).sin().abs();
            let peaks = rocklab::sim::Peaks {
                rotation: f * 0.17,
                deformation: 0.0,
                drift: 0.0,
                abs_acceleration_g: f,
                angular_acceleration_p2: None,
            };
            let r = rocklab::sim::SceneResult::from_peaks(point.index % 7 == 0, 10.0, peaks, f);
            SceneOutcome {
                point,
                result: Ok(r),
            }
        })
        .collect();
    SweepResults {
        study_hash: study.hash(),
        study: Some(study.clone()),
        outcomes,
        ..Default::default()
    }
}

fn screen(app: &rocklab::tui::app::App) -> String {
    text(&render(app, Theme::COLOR, SMALL))
}

#[test]
fn cut_spectra_and_maps_say_how_much_is_hidden() {
    let study = big_study();
    let mut app = app_for(study.clone(), scratch_dir());
    app.show_results(synthetic(&study), false);
    key(&mut app, KeyCode::Char('3'));
    let spectra = screen(&app);
    // 45 rows in 24 lines: the rest are counted below them; 65 points: the window says which.
    let more = spectra
        .lines()
        .find(|l| l.contains("more rows"))
        .unwrap_or_else(|| panic!("no marker in\n{spectra}"));
    let hidden: usize = more
        .split_whitespace()
        .nth(1)
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{more}"));
    let shown = spectra.lines().filter(|l| l.contains(" max ")).count();
    assert_eq!(shown + hidden, 45, "{spectra}");
    assert!(more.starts_with("▾ "), "{more}");
    assert!(spectra.contains(" of 65]"), "{spectra}");
    snap("more_spectra_80x24", spectra);
    // Scrolled into the middle: hidden rows on both sides, and the counts still add up.
    for _ in 0..20 {
        key(&mut app, Down);
    }
    let middle = screen(&app);
    let line = middle.lines().find(|l| l.contains("more rows")).unwrap();
    assert!(line.starts_with("▴ ") && line.contains("▾ "), "{line}");
    let counts: Vec<usize> = line
        .split_whitespace()
        .filter_map(|w| w.parse().ok())
        .collect();
    let shown = middle.lines().filter(|l| l.contains(" max ")).count();
    assert_eq!(counts.iter().sum::<usize>() + shown, 45, "{middle}");

    key(&mut app, KeyCode::Char('m'));
    keys(&mut app, &[Up]);
    let map = screen(&app);
    let line = map
        .lines()
        .find(|l| l.contains("more rows of"))
        .unwrap_or_else(|| panic!("no marker in\n{map}"));
    let counts: usize = line
        .split_whitespace()
        .filter_map(|w| w.parse::<usize>().ok())
        .sum();
    // Map rows are the lines with a cell glyph after the 8-column label.
    let drawn = map
        .lines()
        .filter(|l| l.chars().nth(8).is_some_and(|c| c == '█' || c == '·'))
        .count();
    assert_eq!(counts + drawn, 45, "{map}");
    assert!(map.contains(" of 65]"), "{map}");
    snap("more_map_80x24", map);
}

#[test]
fn the_help_overlay_cuts_no_word() {
    let mut app = app_for(Study::builtin_default(), scratch_dir());
    key(&mut app, KeyCode::Char('?'));
    let help = screen(&app);
    for words in ["design point", "unset a field", "draws it"] {
        assert!(help.contains(words), "{words} cut in\n{help}");
    }
}
