//! The fragility figure and the Results screen's fragility view, on a report built here from
//! synthetic observations (records with lognormal capacities, four variants, three damage
//! states, one of them degenerate for one variant): what they show is checked against the
//! report's numbers, and the view is snapshotted at 80×24 and 160×48.

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use rocklab::report::fragility::{
    FRAGILITY_JSON, FitStatus, FragilityOptions, FragilityReport, StripeObservation, Variant,
    analyse_stripes, plot_fragility, write_fragility_json,
};
use rocklab::report::{FigureOptions, ImageFormat};
use rocklab::study::Study;
use rocklab::sweep::SweepResults;
use rocklab::tui::app::{App, Options, ResultsTab, Screen};
use rocklab::tui::draw::draw;
use rocklab::tui::theme::Theme;
use std::path::PathBuf;

use KeyCode::{Char, Down, Right};

const STRIPES: [f64; 8] = [1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0];
const DEVICES: [(&str, f64); 4] = [
    ("none", 1.0),
    ("inerter", 1.3),
    ("sequential", 1.5),
    ("mechanistic", 1.8),
];

/// 44 records with capacities ~ LN(ln 2.5, 0.5²), scaled per device; a record reaches damage
/// state d at IM ≥ d·capacity (response = IM/capacity) and overturns at 1. The sequential
/// variant's responses are raised to at least 0.5, so its 0.5 state is degenerate (all exceed).
pub fn synthetic_report() -> FragilityReport {
    let mut rng = fastrand::Rng::with_seed(26);
    let z: Vec<f64> = (0..44)
        .map(|_| {
            let (u, v) = (1.0 - rng.f64(), rng.f64());
            (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
        })
        .collect();
    let mut obs = Vec::new();
    for (device, factor) in DEVICES {
        let variant = Variant {
            device: device.into(),
            params: vec![("sigma".into(), 0.5)],
        };
        for (r, z) in z.iter().enumerate() {
            let capacity = factor * 2.5 * (0.5 * z).exp();
            for im in STRIPES {
                let response = im / capacity;
                obs.push(StripeObservation {
                    variant: variant.clone(),
                    record: format!("far_field/{r}"),
                    im,
                    // Sequential: every scene reaches 0.5 (a degenerate fit for that state).
                    response: if device == "sequential" {
                        response.max(0.5)
                    } else {
                        response
                    },
                    overturned: response >= 1.0,
                });
            }
        }
    }
    let opts = FragilityOptions {
        damage_states: vec![0.5, 0.75, 1.0],
        bootstrap: 200,
        seed: 7,
        confidence: 0.9,
    };
    let mut report = analyse_stripes(&obs, &opts);
    report.im = "PGA*".into();
    report.damage_measure = "θmax/α".into();
    report
}

#[test]
fn the_synthetic_report_has_what_the_views_show() {
    let r = synthetic_report();
    assert_eq!(r.curves.len(), 12);
    let seq_05 = r
        .curves
        .iter()
        .find(|c| c.variant.device == "sequential" && c.damage_state == 0.5)
        .unwrap();
    assert_eq!(seq_05.status, FitStatus::AllExceed);
    // Every other curve is fitted.
    let fitted = r
        .curves
        .iter()
        .filter(|c| c.status == FitStatus::Fitted)
        .count();
    assert_eq!(fitted, 11);
    // Three protected variants × three states, the degenerate one without a ratio value.
    assert_eq!(r.ratios.len(), 9);
    let mech = r
        .ratios
        .iter()
        .find(|x| x.a.device == "mechanistic" && x.damage_state == 1.0)
        .unwrap();
    // Capacities scaled by 1.8 record by record: the paired ratio is 1.8 up to the stripes'
    // resolution.
    let ratio = mech.ratio.unwrap();
    assert!((ratio / 1.8).ln().abs() < 0.1, "{ratio}");
    assert!(mech.lo.unwrap() <= ratio && ratio <= mech.hi.unwrap());
}

#[test]
fn the_figure_draws_every_variant_and_names_degenerate_fits() {
    let report = synthetic_report();
    let dir = tempfile::tempdir().unwrap();
    let svg = plot_fragility(dir.path(), &FigureOptions::new(ImageFormat::Svg), &report)
        .unwrap()
        .unwrap();
    assert_eq!(svg.file_name().unwrap(), "fragility.svg");
    let text = std::fs::read_to_string(&svg).unwrap();
    // Every variant has sigma=0.5: said once, in the title; the legend names the devices.
    assert!(text.contains("(every series: sigma=0.5)"), "{text}");
    let texts: Vec<&str> = text
        .split("<text")
        .skip(1)
        .filter_map(|t| Some(t.split_once('>')?.1.split_once("</text>")?.0.trim()))
        .collect();
    assert!(!texts.contains(&"none sigma=0.5"), "{texts:?}");
    assert!(
        texts.contains(&"none") && texts.contains(&"mechanistic"),
        "{texts:?}"
    );
    for label in [
        "θmax/α ≥ 0.5",
        "θmax/α ≥ 1",
        "PGA*",
        "sequential sigma=0.5: every record reached the state",
    ] {
        assert!(text.contains(label), "{label} missing from the SVG");
    }
    // Fitted curves are polylines of 160 samples; the first state's are solid (one polyline
    // each: 3, the sequential one being degenerate), the other states' dashed (many pieces).
    let long_lines = |text: &str| {
        text.split("<polyline")
            .skip(1)
            .filter(|rest| rest.split("/>").next().unwrap().matches(',').count() >= 150)
            .count()
    };
    assert_eq!(long_lines(&text), 3, "solid fitted curves drawn");
    // Overturning alone: one panel, every variant fitted and solid.
    let mut overturning = report.clone();
    overturning.curves.retain(|c| c.damage_state == 1.0);
    let one = plot_fragility(
        dir.path(),
        &FigureOptions::new(ImageFormat::Svg),
        &overturning,
    )
    .unwrap()
    .unwrap();
    assert_eq!(long_lines(&std::fs::read_to_string(one).unwrap()), 4);
    let png = plot_fragility(dir.path(), &FigureOptions::new(ImageFormat::Png), &report)
        .unwrap()
        .unwrap();
    assert!(std::fs::metadata(png).unwrap().len() > 10_000);
    // Nothing to draw: no figure.
    let empty = FragilityReport::default();
    assert!(
        plot_fragility(dir.path(), &FigureOptions::new(ImageFormat::Svg), &empty)
            .unwrap()
            .is_none()
    );
}

fn app_with_fragility() -> App {
    // A fixed directory (the frames show it in the message line).
    let dir = PathBuf::from("target/tui-tests/fragility");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    write_fragility_json(&synthetic_report(), &dir.join(FRAGILITY_JSON)).unwrap();
    let results: SweepResults =
        serde_json::from_str(include_str!("data/tui_small_map_results.json")).unwrap();
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

fn fmt(v: Option<f64>) -> String {
    rocklab::numfmt::fmt_digits(v.unwrap(), 3)
}

#[test]
fn the_fragility_view_reads_out_the_selected_curve() {
    let mut app = app_with_fragility();
    keys(&mut app, &[Char('p')]);
    assert_eq!(app.browser.tab, ResultsTab::Fragility);
    let report = app
        .shared
        .results
        .as_ref()
        .unwrap()
        .fragility
        .clone()
        .unwrap();
    let small = screen(&app, (80, 24));
    assert!(small.contains("θmax/α ≥ 0.5"), "{small}");
    // The bare variant's row: median and β with their intervals, as in the report.
    let bare = &report.curves[0];
    // The median is named as the intensity measure it is a value of, not "θ" (a rotation).
    let row = format!(
        "PGA* {} [{}, {}]",
        fmt(bare.median),
        fmt(bare.median_lo),
        fmt(bare.median_hi)
    );
    assert!(small.contains(&row), "{row} not in\n{small}");
    // At 80 columns the row gives β alone, the readout its interval.
    let beta = format!(
        "β {} [{}, {}], 44 records, 8 stripes",
        fmt(bare.beta),
        fmt(bare.beta_lo),
        fmt(bare.beta_hi)
    );
    assert!(small.contains(&beta), "{beta} not in\n{small}");
    snap("fragility_80x24", small);
    // Overturning (third state), the mechanistic variant, cursor on the third stripe.
    keys(
        &mut app,
        &[Char(']'), Char(']'), Down, Down, Down, Right, Right],
    );
    let large = screen(&app, (160, 48));
    let mech = report
        .curves
        .iter()
        .find(|c| c.variant.device == "mechanistic" && c.damage_state == 1.0)
        .unwrap();
    let ratio = report.ratio_of(mech).unwrap();
    let times = format!(
        "{} [{}, {}]× bare",
        fmt(ratio.ratio),
        fmt(ratio.lo),
        fmt(ratio.hi)
    );
    assert!(large.contains(&times), "{times} not in\n{large}");
    let p = mech.probability(2.5).unwrap();
    let at = format!(
        "PGA* = 2.5: fitted P = {p:.3}, observed {}/44 reached",
        mech.stripes[2].exceed
    );
    assert!(large.contains(&at), "{at} not in\n{large}");
    assert!(large.contains("θmax/α ≥ 1"), "{large}");
    snap("fragility_160x48", large);
    // The degenerate fit is named, not given numbers.
    keys(&mut app, &[Char(']'), KeyCode::Up]);
    let text = screen(&app, (160, 48));
    assert!(text.contains("every record reached the state"), "{text}");
}

#[test]
fn results_without_fragility_say_so() {
    let results: SweepResults =
        serde_json::from_str(include_str!("data/tui_small_map_results.json")).unwrap();
    let mut app = App::new(
        Study::builtin_default(),
        None,
        Options {
            deterministic: true,
            jobs: Some(1),
            out_root: PathBuf::from("target/tui-tests/no-fragility"),
        },
    );
    app.open_results(results, PathBuf::from("tests/data"));
    keys(&mut app, &[Char('p')]);
    assert!(screen(&app, (80, 24)).contains("no fragility curves"));
}

/// A small far-field fragility study (44 components × 3 stripes, bare): a run inside the
/// workbench shows its curves at once (`p`), with the median named PGA* and the numbers of
/// the fragility.json the run wrote; no reopening needed.
#[test]
fn a_fragility_run_in_the_workbench_shows_its_curves_at_once() {
    const STUDY: &str = r#"(
        version: 1,
        name: "tui_fragility_run",
        structure: rigid(p: 2.0, alpha: 0.2),
        devices: [none],
        excitation: record(suite: (name: "far_field"), scale: [2.0, 4.0, 7.0], scale_to: pga_star, tail: 5.0),
        quantities: [peak_rotation_ratio],
        spectrum: scale,
        fragility: (damage_states: levels([1.0]), bootstrap: 200, seed: 3),
    )"#;
    let out_root = PathBuf::from("target/tui-tests/fragility-run");
    let _ = std::fs::remove_dir_all(&out_root);
    let study = Study::from_ron_str(STUDY, "tui_fragility_run.ron").unwrap();
    let mut app = App::new(
        study,
        None,
        Options {
            deterministic: true,
            jobs: Some(2),
            out_root: out_root.clone(),
        },
    );
    keys(&mut app, &[Char('r')]);
    assert!(app.wait_idle(std::time::Duration::from_secs(300)));
    assert_eq!(app.screen, Screen::Results, "{:?}", app.message);
    let written = rocklab::report::fragility::read_fragility_json(
        &out_root.join("tui_fragility_run").join(FRAGILITY_JSON),
    )
    .unwrap();
    let shown = app.shared.results.as_ref().unwrap().fragility.clone();
    assert_eq!(shown.as_ref(), Some(&written), "the run's report is shown");
    keys(&mut app, &[Char('p')]);
    let small = screen(&app, (80, 24));
    assert!(!small.contains("no fragility curves"), "{small}");
    let bare = &written.curves[0];
    let row = format!(
        "PGA* {} [{}, {}]",
        fmt(bare.median),
        fmt(bare.median_lo),
        fmt(bare.median_hi)
    );
    assert!(small.contains(&row), "{row} not in\n{small}");
    snap("fragility_after_run_80x24", small);
}
