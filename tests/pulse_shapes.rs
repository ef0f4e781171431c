//! Several pulse shapes in one study (issue 42, item 6b): `shape: [sine, ricker]` is an axis
//! of the study: scenes expand over it, groups and figures name it, selectors pick by it; a
//! single shape writes back as a single value; an unknown shape gets "did you mean".

use rocklab::excitation::PulseShape;
use rocklab::report::select::{Selector, select};
use rocklab::scene::Excitation;
use rocklab::study::Study;

fn default_with_shape(shape: &str) -> String {
    include_str!("../studies/default.ron").replace("shape: sine", &format!("shape: {shape}"))
}

fn shape_of(e: &Excitation) -> PulseShape {
    match e {
        Excitation::Pulse { shape, .. } => *shape,
        other => panic!("not a pulse: {other:?}"),
    }
}

#[test]
fn several_shapes_expand_as_an_axis_and_are_named() {
    let one = Study::from_ron_str(&default_with_shape("sine"), "one").unwrap();
    let two = Study::from_ron_str(&default_with_shape("[sine, ricker]"), "two").unwrap();
    let (p1, p2) = (one.expand().unwrap(), two.expand().unwrap());
    assert_eq!(p2.len(), 2 * p1.len());
    let ricker: Vec<_> = p2
        .iter()
        .filter(|p| shape_of(&p.scene.excitation) == PulseShape::Ricker)
        .collect();
    assert_eq!(ricker.len(), p1.len());
    // The group names the shape only where it varies, the frequency axis stays the x axis.
    assert!(
        ricker.iter().all(|p| p.group.ends_with("shape=ricker")),
        "{}",
        ricker[0].group
    );
    assert!(p1.iter().all(|p| !p.group.contains("shape")));
    assert_eq!(p2[0].coords[0].0, p1[0].coords[0].0);
    // The sine half is the one-shape study, scene for scene (same cache keys).
    let sine: Vec<&String> = p2
        .iter()
        .filter(|p| shape_of(&p.scene.excitation) == PulseShape::Sine)
        .map(|p| &p.key)
        .collect();
    assert_eq!(sine, p1.iter().map(|p| &p.key).collect::<Vec<_>>());
}

#[test]
fn a_selector_picks_a_shape() {
    let two = Study::from_ron_str(&default_with_shape("[sine, ricker]"), "two").unwrap();
    let outcomes = two
        .expand()
        .unwrap()
        .into_iter()
        .map(|point| {
            let peaks = rocklab::sim::Peaks {
                rotation: 0.1,
                deformation: 0.0,
                drift: 0.0,
                abs_acceleration_g: 0.1,
                angular_acceleration_p2: None,
            };
            rocklab::sweep::SceneOutcome {
                point,
                result: Ok(rocklab::sim::SceneResult::from_peaks(
                    false, 10.0, peaks, 0.5,
                )),
            }
        })
        .collect();
    let results = rocklab::sweep::SweepResults {
        study_hash: two.hash(),
        study: Some(two.clone()),
        outcomes,
        ..Default::default()
    };
    let spectra = rocklab::report::spectra(&results);
    let groups: Vec<_> = spectra.iter().map(|s| &s.group).collect();
    assert!(!groups.is_empty());
    let picked = select(&groups, &Selector::parse("bare(shape: ricker)").unwrap()).unwrap();
    assert!(!picked.is_empty());
    for i in &picked {
        assert_eq!(
            groups[*i].setting("shape").unwrap().name.as_deref(),
            Some("ricker")
        );
    }
    let e = select(&groups, &Selector::parse("bare(shape: cosine)").unwrap()).unwrap_err();
    assert!(e.0.contains("sine") && e.0.contains("ricker"), "{}", e.0);
}

#[test]
fn shapes_round_trip_and_one_shape_stays_one_value() {
    let text = default_with_shape("sine");
    let one = Study::from_ron_str(&text, "one").unwrap();
    assert_eq!(one.to_ron_keeping(Some(&text)).text, text);
    assert!(
        one.to_ron_string().contains("shape: sine"),
        "{}",
        one.to_ron_string()
    );
    let two = Study::from_ron_str(&default_with_shape("[sine, ricker]"), "two").unwrap();
    for written in [two.to_ron_string(), two.to_ron_keeping(None).text] {
        assert!(written.contains("ricker"), "{written}");
        assert_eq!(Study::from_ron_str(&written, "back").unwrap(), two);
    }
}

#[test]
fn an_unknown_shape_is_named_with_the_nearest() {
    for shape in ["rikcer", "[sine, rikcer]"] {
        let e = Study::from_ron_str(&default_with_shape(shape), "s.ron").unwrap_err();
        let text = e.to_string();
        assert!(text.contains("unknown pulse shape `rikcer`"), "{text}");
        assert!(text.contains("did you mean `ricker`"), "{text}");
        assert!(text.contains("s.ron:") && e.line.is_some(), "{text}");
    }
    let e = Study::from_ron_str(&default_with_shape("[sine, sine]"), "s.ron").unwrap_err();
    assert!(
        e.to_string().contains("pulse shape `sine` is listed twice"),
        "{e}"
    );
}
