//! Figures read as words (issue 42, item 9): titles from the study's description (or its name
//! in words, never a file slug), no code identifiers in the design chart's title, a parameter
//! every series shares said once in the title, and tick values on every axis of a scene's
//! history, the device force `Fd [N]` included.

use rocklab::excitation::library;
use rocklab::report::{self, FigureOptions, ImageFormat};
use rocklab::sim::{self, Sampling};
use rocklab::study::design::DesignTarget;
use rocklab::study::{Quantity, StructureFamily, Study, Values};

fn svg_texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let body = t.split_once('>')?.1;
            Some(body.split_once("</text>")?.0.trim().replace("&amp;", "&"))
        })
        .collect()
}

/// A word that is a code identifier: snake_case, or `<=`/`>=` for ≤/≥.
fn code_words(text: &str) -> Vec<&str> {
    text.split([' ', ',', ':', '(', ')'])
        .filter(|w| w.contains('_') || w.contains("<=") || w.contains(">="))
        .collect()
}

#[test]
fn a_study_without_a_description_is_titled_by_its_name_in_words() {
    let mut study = Study::builtin_default();
    assert_eq!(report::study_title(&study), study.description);
    study.description = "  ".into();
    study.name = "fig12_rigid-spectra".into();
    assert_eq!(report::study_title(&study), "fig12 rigid spectra");
}

#[test]
fn the_design_title_speaks_no_code() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/design_sigma_rigid.ron"
    );
    let mut study = Study::load(std::path::Path::new(path)).unwrap();
    let mut design = study.design.clone().unwrap();
    design.target = DesignTarget::Limit {
        quantity: Quantity::PeakRotationRatio,
        max: 0.5,
    };
    study.design = Some(design.clone());
    let title = report::design_title(&study, &design);
    assert!(title.starts_with(&report::study_title(&study)), "{title}");
    assert!(
        title.contains(&format!("{} ≤ 0.5", Quantity::PeakRotationRatio.label())),
        "{title}"
    );
    assert!(code_words(&title).is_empty(), "{title}");
    // The study's own target too (whatever it is), and its name is no slug.
    let own = Study::load(std::path::Path::new(path)).unwrap();
    let title = report::design_title(&own, own.design.as_ref().unwrap());
    assert!(code_words(&title).is_empty(), "{title}");
}

#[test]
fn a_shared_parameter_is_said_once_in_the_title() {
    assert_eq!(report::with_shared("Spectra", ""), "Spectra");
    assert_eq!(
        report::with_shared("Spectra", "σ=0.5"),
        "Spectra (every series: σ=0.5)"
    );
    assert_eq!(report::panel_title(0, 1, ""), "");
    assert_eq!(report::panel_title(0, 1, "bare"), "bare");
    assert_eq!(report::panel_title(1, 2, "bare"), "(b) bare");
    assert_eq!(report::panel_title(0, 2, ""), "(a)");
}

/// A mechanistic clutch on a heavy block: the device force runs to tens of kN, a range on
/// which the three labels a short panel asks for gave plotters one tick (`0`).
#[test]
fn the_device_force_axis_of_a_history_has_tick_values() {
    let mut study = Study::builtin_default();
    if let StructureFamily::Rigid { mass, .. } = &mut study.structure {
        *mass = Values::One(20_000.0);
    }
    let point = study
        .expand()
        .unwrap()
        .into_iter()
        .find(|p| p.group.starts_with("mechanistic") && p.coord("ωg/p") == Some(3.0))
        .unwrap();
    let lib = library::global().unwrap();
    let (_, history) =
        sim::run_history(&sim::history_scene(&point.scene), lib, &Sampling::Auto).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.svg");
    let options = FigureOptions::new(ImageFormat::Svg);
    report::plot_history(&path, &options, "scene", &point.scene, &history).unwrap();
    let texts = svg_texts(&std::fs::read_to_string(&path).unwrap());
    let at = texts
        .iter()
        .position(|t| t == "Fd [N]")
        .expect("an Fd panel");
    let end = texts[at + 1..]
        .iter()
        .position(|t| t.ends_with(']') || t == "θ/α")
        .map_or(texts.len(), |i| at + 1 + i);
    // The time axis's ticks are at most the duration; the force's are kN.
    let duration = 15.0;
    let force_ticks: Vec<&String> = texts[at + 1..end]
        .iter()
        .filter(|t| {
            t.parse::<f64>()
                .is_ok_and(|v| v.abs() > duration || v < 0.0)
        })
        .collect();
    assert!(force_ticks.len() >= 2, "{:?}", &texts[at..end]);
}
