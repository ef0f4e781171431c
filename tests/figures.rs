//! Figures and tables of every shipped study: the figures render at the asked size with every
//! series, axis units and the paper's layouts (Fig. 12 side by side, Fig. 24 one panel per
//! quantity), and results.csv has plain ASCII identifier columns with a metadata sidecar.
//!
//! The results are the studies' real expansions with synthetic peaks (one real scene result
//! cloned and rescaled): drawing does not depend on the physics, and running every shipped
//! study here would take minutes.

use rocklab::report::fragility::{FitStatus, plot_fragility};
use rocklab::report::{
    self, CsvLayout, FigureOptions, FigureSize, ImageFormat, PlotChoice, Quantity,
};
use rocklab::study::Study;
use rocklab::sweep::{SceneOutcome, SweepResults};
use std::path::{Path, PathBuf};

fn shipped_studies() -> Vec<(String, Study)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies");
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    paths.sort();
    assert!(paths.len() >= 8, "{paths:?}");
    paths
        .into_iter()
        .map(|p| {
            let name = p.file_stem().unwrap().to_string_lossy().into_owned();
            (name, Study::load(&p).unwrap())
        })
        .collect()
}

/// The study's scenes with made-up peaks: a smooth function of the point's index, and the
/// first scene of every 9 overturned, so overturned marks are drawn too.
fn synthetic_results(study: &Study) -> SweepResults {
    let points = study.expand().unwrap();
    let outcomes = points
        .into_iter()
        .map(|point| {
            let f = 0.2 + 0.5 * ((point.index as f64) * 0.37).sin().abs();
            let peaks = rocklab::sim::Peaks {
                rotation: f * 0.17,
                deformation: f * 0.01,
                drift: f * 0.05,
                abs_acceleration_g: f * 0.4,
                angular_acceleration_p2: Some(f * 0.3),
            };
            let overturned = point.index % 9 == 0;
            let r = rocklab::sim::SceneResult::from_peaks(overturned, 10.0, peaks, f);
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

fn svg_options() -> FigureOptions {
    FigureOptions::new(ImageFormat::Svg)
}

/// The text elements of an SVG, unescaped enough for labels.
fn svg_texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let body = t.split_once('>')?.1;
            Some(body.split_once("</text>")?.0.trim().replace("&amp;", "&"))
        })
        .collect()
}

/// The physical size an SVG declares, in mm.
fn svg_size_mm(svg: &str) -> (f64, f64) {
    let attr = |name: &str| -> f64 {
        let start = svg.find(&format!("{name}=\"")).unwrap() + name.len() + 2;
        let rest = &svg[start..];
        rest[..rest.find("mm\"").unwrap()].parse().unwrap()
    };
    (attr("width"), attr("height"))
}

fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    (be(16), be(20))
}

#[test]
fn every_shipped_study_draws_with_every_series_and_units_on_every_axis() {
    for (name, study) in shipped_studies() {
        // A design study's scenes are probes: its figure is the design chart (tests/design.rs).
        if study.design.is_some() {
            continue;
        }
        // A fragility study's figure is its fragility curves, not spectra over its records.
        if study.fragility.is_some() {
            check_fragility_figure(&name, &study);
            continue;
        }
        let results = synthetic_results(&study);
        let dir = tempfile::tempdir().unwrap();
        let spectra = report::spectra(&results);
        let choice = PlotChoice::default();
        let figure =
            report::plot_spectra(dir.path(), &svg_options(), &results, &spectra, &choice).unwrap();
        let maps = report::maps(&results);
        let map_figure =
            report::plot_maps(dir.path(), &svg_options(), &results, &maps, &choice).unwrap();
        let groups: usize = {
            let mut g: Vec<&str> = spectra.iter().map(|s| s.label.as_str()).collect();
            g.sort();
            g.dedup();
            g.len()
        };
        match &figure {
            Some(path) => {
                let svg = std::fs::read_to_string(path).unwrap();
                assert!(svg.starts_with("<svg"), "{name}");
                let texts = svg_texts(&svg);
                // Titled from the study's description.
                assert!(
                    texts[0].starts_with(&study.description),
                    "{name}: {texts:?}"
                );
                let lone = texts.iter().any(|t| t == "(a)") && !texts.iter().any(|t| t == "(b)");
                assert!(!lone, "{name}: a lone (a)");
                // Every series is in the legend: its group label (less the parameters every
                // series shares, said once in the title), or its record and device.
                let shared = texts[0]
                    .strip_prefix(&study.description)
                    .and_then(|t| t.strip_prefix(" (every series: "))
                    .and_then(|t| t.strip_suffix(')'))
                    .unwrap_or("");
                let own = |label: &str| -> String {
                    label
                        .split(' ')
                        .filter(|w| !shared.split(' ').any(|s| s == *w))
                        .collect::<Vec<_>>()
                        .join(" ")
                };
                for s in &spectra {
                    let named = texts.contains(&s.label)
                        || texts.contains(&own(&s.label))
                        || s.label.split_once(" · ").is_some_and(|(device, record)| {
                            texts.iter().any(|t| t == record) && texts.iter().any(|t| t == device)
                        });
                    assert!(named, "{name}: series {} missing from {texts:?}", s.label);
                }
                // One panel per quantity, each with its axis labels and units.
                for q in &study.quantities {
                    let label = match q {
                        Quantity::PeakRotation => "θmax [rad]",
                        Quantity::PeakRotationRatio => "θmax/α",
                        Quantity::PeakDeformation => "umax [m]",
                        Quantity::PeakDrift => "drift |X|max/H",
                        Quantity::PeakAbsAcceleration => "ẍmax [g]",
                        Quantity::PeakAngularAcceleration => "θ̈max/p²",
                    };
                    assert_eq!(
                        texts.iter().filter(|t| *t == label).count(),
                        1,
                        "{name}: {label} in {texts:?}"
                    );
                }
                let x_label = &spectra[0].axis;
                let x_texts = texts.iter().filter(|t| t.starts_with(x_label.as_str()));
                assert_eq!(x_texts.clone().count(), study.quantities.len(), "{name}");
                if x_label == "ωn" {
                    assert!(x_texts.into_iter().all(|t| t == "ωn [rad/s]"), "{name}");
                }
                // Overturned points are marked and explained.
                assert!(
                    texts.iter().any(|t| t.starts_with("overturned")),
                    "{name}: {texts:?}"
                );
                // No tick label like `1. 0` or `1.0000001`.
                for t in &texts {
                    if t.parse::<f64>().is_ok() {
                        assert!(!t.contains(' ') && t.len() <= 6, "{name}: tick {t:?}");
                    }
                }
                let (w, h) = svg_size_mm(&svg);
                assert!(w >= 100.0 && h >= 50.0, "{name}: {w}×{h} mm");
            }
            None => {
                // Too many series for one panel: only a study with a map may skip its
                // spectra, and then it draws its maps.
                assert!(
                    groups > report::MAX_SERIES,
                    "{name}: {groups} groups, no figure"
                );
                assert!(map_figure.is_some(), "{name}");
            }
        }
        if let Some(path) = &map_figure {
            let svg = std::fs::read_to_string(path).unwrap();
            let texts = svg_texts(&svg);
            for m in &maps {
                assert!(
                    texts.iter().any(|t| t.ends_with(&format!(") {}", m.label))
                        || (maps.len() == 1 && *t == m.label)),
                    "{name}: map {} in {texts:?}",
                    m.label
                );
            }
            assert!(texts.iter().any(|t| t == "overturned"), "{name}");
        }
        assert_eq!(map_figure.is_some(), study.map.is_some(), "{name}");
    }
}

/// A fragility study's scenes with made-up responses that grow with the stripe: each record
/// (group) has a capacity spread lognormally around the stripes' geometric mean, the response
/// is (IM / capacity)², so the lower damage states are reached at lower stripes, and a scene
/// at or above its capacity overturns.
fn synthetic_fragility_results(study: &Study) -> SweepResults {
    let mut results = synthetic_results(study);
    let stripes: Vec<f64> = results
        .outcomes
        .iter()
        .filter_map(|o| o.point.coord("scale"))
        .collect();
    let centre = (stripes.iter().map(|v| v.ln()).sum::<f64>() / stripes.len() as f64).exp();
    for o in &mut results.outcomes {
        let im = o.point.coord("scale").unwrap();
        let z = (o.point.group.bytes().map(u64::from).sum::<u64>() % 29) as f64 / 14.0 - 1.0;
        let response = (im / (centre * (0.5 * z).exp())).powi(2);
        let r = o.result.as_mut().unwrap();
        r.overturned = response >= 1.0;
        r.peak_rotation_ratio = response.min(1.0);
        r.peaks.drift = response.min(1.0) * 0.05;
        r.peaks.deformation = response.min(1.0) * 0.01;
    }
    results
}

/// The fragility figure of a shipped fragility study: titled by its intensity measure, one
/// panel per damage state with its axes, every variant in the legend, every fit drawn.
fn check_fragility_figure(name: &str, study: &Study) {
    let f = study.fragility.as_ref().unwrap();
    let results = synthetic_fragility_results(study);
    let rows = report::stripes::rows(study, &results).unwrap();
    let fragility = report::stripes::analyse(f, study, &rows);
    let states = f.damage_states.levels();
    let variants = study.devices.len();
    assert_eq!(fragility.curves.len(), variants * states.len(), "{name}");
    for c in &fragility.curves {
        // Capacities within e^±0.5 of the stripes' centre: every state is fitted.
        assert_eq!(c.status, FitStatus::Fitted, "{name}: {c:?}");
        assert_eq!(c.n_stripes, study_stripes(study), "{name}");
    }
    let dir = tempfile::tempdir().unwrap();
    let path = plot_fragility(dir.path(), &svg_options(), &fragility)
        .unwrap()
        .unwrap();
    let svg = std::fs::read_to_string(path).unwrap();
    assert!(svg.starts_with("<svg"), "{name}");
    let texts = svg_texts(&svg);
    assert!(
        texts[0].starts_with("Fragility: P(damage state reached | ")
            && texts[0].contains(&fragility.im),
        "{name}: {texts:?}"
    );
    let count = |t: &str| texts.iter().filter(|x| *x == t).count();
    assert!(!fragility.im.is_empty(), "{name}");
    assert_eq!(
        count(&fragility.im),
        states.len(),
        "{name}: x labels in {texts:?}"
    );
    assert_eq!(
        count("P(exceed)"),
        states.len(),
        "{name}: y labels in {texts:?}"
    );
    for (j, ds) in states.iter().enumerate() {
        // A letter only among several panels.
        let panel = report::panel_title(j, states.len(), &format!("θmax/α ≥ {ds}"));
        assert_eq!(count(&panel), 1, "{name}: {panel} in {texts:?}");
        assert_eq!(panel.starts_with("(a)"), j == 0 && states.len() > 1);
    }
    assert!(!texts.iter().any(|t| t == "(a)"), "{name}: a lone (a)");
    // A parameter every variant has is said once, in the title, not in each entry.
    let first: Vec<&rocklab::report::fragility::Curve> = fragility
        .curves
        .iter()
        .filter(|c| c.damage_state == states[0])
        .collect();
    let labels: Vec<String> = first.iter().map(|c| c.variant.label()).collect();
    let (shared, own) = report::naming::factor_shared(&labels);
    if !shared.is_empty() {
        assert!(
            texts[0].ends_with(&format!("(every series: {shared})")),
            "{name}: {texts:?}"
        );
        assert!(!own.iter().any(|l| l.contains(&shared)), "{name}: {own:?}");
    }
    for (c, own) in first.iter().zip(&own) {
        let label = c.variant.label();
        assert_eq!(count(own), 1, "{name}: legend {own} in {texts:?}");
        // No degenerate-fit note: every curve is drawn.
        let note = format!("{label}: ");
        assert!(
            !texts.iter().any(|t| t.starts_with(&note)),
            "{name}: {texts:?}"
        );
    }
    let (w, h) = svg_size_mm(&svg);
    assert!(w >= 100.0 && h >= 50.0, "{name}: {w}×{h} mm");
}

fn study_stripes(study: &Study) -> usize {
    match &study.excitation {
        rocklab::study::ExcitationFamily::Record { scale, .. } => scale.expand().len(),
        _ => panic!("a fragility study scales records"),
    }
}

#[test]
fn fig12_is_two_panels_side_by_side_at_the_asked_size_and_resolution() {
    let study =
        Study::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/fig12_rigid_spectra.ron"))
            .unwrap();
    let results = synthetic_results(&study);
    let dir = tempfile::tempdir().unwrap();
    let options = FigureOptions {
        format: ImageFormat::Png,
        size: Some(FigureSize::parse("160x80mm").unwrap()),
        dpi: 300.0,
        max_megapixels: 100.0,
    };
    let spectra = report::spectra(&results);
    let path = report::plot_spectra(
        dir.path(),
        &options,
        &results,
        &spectra,
        &PlotChoice::default(),
    )
    .unwrap()
    .unwrap();
    let bytes = std::fs::read(&path).unwrap();
    // 160 mm × 80 mm at 300 dpi.
    assert_eq!(png_size(&bytes), (1890, 945));
    assert!(
        bytes.len() > 20_000,
        "{} bytes: an empty figure?",
        bytes.len()
    );
    // The same figure as SVG: panels (a) and (b) side by side, 6.3 in wide.
    let options = FigureOptions {
        format: ImageFormat::Svg,
        size: Some(FigureSize::parse("6.3x3.15in").unwrap()),
        dpi: 300.0,
        max_megapixels: 100.0,
    };
    let path = report::plot_spectra(
        dir.path(),
        &options,
        &results,
        &spectra,
        &PlotChoice::default(),
    )
    .unwrap()
    .unwrap();
    let svg = std::fs::read_to_string(path).unwrap();
    let (w, h) = svg_size_mm(&svg);
    assert!(
        (w - 160.02).abs() < 0.01 && (h - 80.01).abs() < 0.01,
        "{w}×{h}"
    );
    let texts = svg_texts(&svg);
    assert!(texts.contains(&"(a)".to_string()) && texts.contains(&"(b)".to_string()));
    assert!(!texts.contains(&"(c)".to_string()));
}

#[test]
fn selectors_pick_series_and_facets_split_them_into_rows() {
    let study =
        Study::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/fig23_gear_play.ron"))
            .unwrap();
    let results = synthetic_results(&study);
    let spectra = report::spectra(&results);
    let dir = tempfile::tempdir().unwrap();
    let draw = |choice: PlotChoice| {
        let path = report::plot_spectra(dir.path(), &svg_options(), &results, &spectra, &choice)
            .unwrap()
            .unwrap();
        svg_texts(&std::fs::read_to_string(path).unwrap())
    };
    // `compare`'s selectors (report/select.rs): a value, a list, another spelling of it.
    for selector in [
        "mechanistic(play: 0.005)",
        "mechanistic(play: [0.005])",
        "mechanistic(play: 5e-3)",
    ] {
        let texts = draw(PlotChoice {
            select: vec![selector.into()],
            ..Default::default()
        });
        assert!(
            texts.contains(&"mechanistic up=0.005".to_string()),
            "{selector}"
        );
        assert!(
            !texts.contains(&"mechanistic up=0.01".to_string()),
            "{selector}"
        );
    }
    // Two selectors: both series.
    let texts = draw(PlotChoice {
        select: vec![
            "mechanistic(play: 0)".into(),
            "mechanistic(play: 0.01)".into(),
        ],
        ..Default::default()
    });
    assert!(texts.contains(&"mechanistic up=0".to_string()));
    assert!(texts.contains(&"mechanistic up=0.01".to_string()));
    assert!(!texts.contains(&"mechanistic up=0.0025".to_string()));
    // One row per play value, one column per quantity: 4 rows of panels titled with the value,
    // lettered row by row.
    let texts = draw(PlotChoice {
        facet: Some("play".into()),
        ..Default::default()
    });
    let titled = |play: &str| -> Vec<char> {
        texts
            .iter()
            .filter_map(|t| {
                let letter = t.strip_prefix('(')?.chars().next()?;
                t.ends_with(&format!(") up = {play} m")).then_some(letter)
            })
            .collect()
    };
    let rows: Vec<Vec<char>> = ["0", "0.0025", "0.005", "0.01"]
        .iter()
        .map(|play| titled(play))
        .collect();
    let per_row = rows[0].len();
    assert!(per_row >= 2, "one panel per quantity in {texts:?}");
    for (i, row) in rows.iter().enumerate() {
        let first = (b'a' + (i * per_row) as u8) as char;
        assert_eq!(row.len(), per_row, "{texts:?}");
        assert_eq!(row[0], first, "row {i} starts at ({first}) in {texts:?}");
    }
    // Nothing matches: an error naming the devices there are, never a figure silently left
    // out (issue 42, item 3).
    let none = report::plot_spectra(
        dir.path(),
        &svg_options(),
        &results,
        &spectra,
        &PlotChoice {
            select: vec!["bare".into()],
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(none.contains("sequential, mechanistic"), "{none}");
    // An unknown facet parameter is an error naming the parameters there are.
    let e = report::plot_spectra(
        dir.path(),
        &svg_options(),
        &results,
        &spectra,
        &PlotChoice {
            facet: Some("k_theta".into()),
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("k_theta") && e.contains("play (up)"), "{e}");
}

#[test]
fn record_suites_draw_one_style_per_device_one_colour_per_record_or_a_band() {
    let study =
        Study::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/fig24_records.ron"))
            .unwrap();
    let results = synthetic_results(&study);
    let spectra = report::spectra(&results);
    let dir = tempfile::tempdir().unwrap();
    let path = report::plot_spectra(
        dir.path(),
        &svg_options(),
        &results,
        &spectra,
        &PlotChoice::default(),
    )
    .unwrap()
    .unwrap();
    let texts = svg_texts(&std::fs::read_to_string(path).unwrap());
    // Four quantities: four panels, each with its own y label.
    for p in ["(a)", "(b)", "(c)", "(d)"] {
        assert!(texts.contains(&p.to_string()), "{p}");
    }
    for key in [
        "bare",
        "sequential",
        "mechanistic",
        "landers",
        "palm_springs",
    ] {
        assert_eq!(
            texts.iter().filter(|t| *t == key).count(),
            1,
            "{key}: {texts:?}"
        );
    }
    let path = report::plot_spectra(
        dir.path(),
        &svg_options(),
        &results,
        &spectra,
        &PlotChoice {
            band: true,
            ..Default::default()
        },
    )
    .unwrap()
    .unwrap();
    let texts = svg_texts(&std::fs::read_to_string(path).unwrap());
    assert!(
        texts.contains(&"mechanistic: mean ± 1 s.d. over 5 records".to_string()),
        "{texts:?}"
    );
    assert!(!texts.contains(&"landers".to_string()));
}

#[test]
fn results_csv_headers_are_ascii_identifiers_with_a_metadata_sidecar() {
    for (name, study) in shipped_studies() {
        let results = synthetic_results(&study);
        for layout in [CsvLayout::Long, CsvLayout::Wide] {
            let csv = report::results_csv_layout(&results, layout).unwrap();
            let mut reader = csv::Reader::from_reader(csv.as_slice());
            let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
            for h in &header {
                // A valid MATLAB / R / Python identifier: what readtable keeps unrenamed.
                assert!(
                    h.starts_with(|c: char| c.is_ascii_alphabetic())
                        && h.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
                        && h.len() <= 63,
                    "{name}: column {h:?}"
                );
            }
            let mut sorted = header.clone();
            sorted.sort();
            sorted.dedup();
            assert_eq!(
                sorted.len(),
                header.len(),
                "{name}: duplicate columns {header:?}"
            );
            let rows = reader.records().count();
            let scenes = results.outcomes.len();
            match layout {
                CsvLayout::Long => assert_eq!(rows, scenes * study.quantities.len(), "{name}"),
                CsvLayout::Wide => {
                    assert_eq!(rows, scenes, "{name}");
                    for q in &study.quantities {
                        assert!(header.contains(&q.name().to_string()), "{name}");
                    }
                }
            }
            if layout == CsvLayout::Long {
                // Every column is described once in results.columns.csv, with its label.
                let meta = report::results_columns_csv(&results).unwrap();
                let mut meta = csv::Reader::from_reader(meta.as_slice());
                assert_eq!(
                    meta.headers().unwrap().iter().collect::<Vec<_>>(),
                    ["name", "label", "unit", "description"]
                );
                let described: Vec<(String, String, String)> = meta
                    .records()
                    .map(|r| {
                        let r = r.unwrap();
                        (r[0].to_string(), r[1].to_string(), r[2].to_string())
                    })
                    .collect();
                for h in &header {
                    assert_eq!(
                        described.iter().filter(|d| d.0 == *h).count(),
                        1,
                        "{name}: {h} in {described:?}"
                    );
                }
                for (label, _) in &results.outcomes[0].point.coords {
                    assert!(described.iter().any(|d| d.1 == *label), "{name}: {label}");
                }
            }
        }
    }
}

#[test]
fn coordinates_get_the_names_the_issue_and_the_study_files_use() {
    for (label, name, unit) in [
        ("ωg/p", "omega_g_over_p", ""),
        ("ξθ", "xi_theta", ""),
        ("fμ", "f_mu", "mr·g"),
        ("kθ", "k_theta", "N·m/rad"),
        ("up", "play", "m"),
        ("ωn", "omega_n", "rad/s"),
        ("A/(g·tanα)", "a_over_g_tan_alpha", ""),
    ] {
        let p = report::parameter(label);
        assert_eq!((p.name.as_str(), p.unit), (name, unit), "{label}");
    }
    // A label no table knows still becomes an identifier.
    assert_eq!(report::parameter("θ0/α").name, "theta0_alpha");
    assert_eq!(report::parameter("2x").name, "x_2x");
}

#[test]
fn overturning_maps_compare_cell_by_cell_with_a_legend() {
    // Results of a small map study (3 variants × 4 frequencies × 3 amplitudes).
    let results: rocklab::sweep::SweepResults =
        serde_json::from_str(include_str!("data/tui_small_map_results.json")).unwrap();
    let maps = report::maps(&results);
    let dir = tempfile::tempdir().unwrap();
    let path = report::plot_map_differences(
        dir.path(),
        &svg_options(),
        &maps,
        "sequential",
        "mechanistic",
    )
    .unwrap()
    .unwrap();
    assert!(path.ends_with("maps-difference.svg"));
    let svg = std::fs::read_to_string(&path).unwrap();
    let texts = svg_texts(&svg);
    for c in report::compare::MapCell::ALL {
        assert!(texts.contains(&c.meaning().to_string()), "{c:?}: {texts:?}");
    }
    // One pair: one panel, and no lone "(a)".
    assert!(
        texts.contains(&"sequential vs mechanistic".to_string()),
        "{texts:?}"
    );
    assert!(!texts.iter().any(|t| t.starts_with("(a)")), "{texts:?}");
    // One filled cell per map point, plus the legend's five swatches.
    let pair = &report::compare::compare_maps(
        &maps,
        &report::select::Selector::parse("sequential").unwrap(),
        &report::select::Selector::parse("mechanistic").unwrap(),
    )
    .unwrap()[0];
    let both_overturn = pair.count(report::compare::MapCell::BothOverturn);
    assert!(both_overturn > 0);
    let dark = svg.matches("fill=\"#404040\"").count();
    assert_eq!(
        dark,
        both_overturn + 1,
        "dark cells: both overturn, and the legend"
    );
    // A selector that matches no map is an error that says what there is.
    let e = report::plot_map_differences(dir.path(), &svg_options(), &maps, "inerter", "bare")
        .unwrap_err()
        .to_string();
    assert!(e.contains("devices here"), "{e}");
}
