//! Saving a study keeps what its user wrote (comments, spelling, defaults left out, short
//! lists on one line) and always reads back as the same study; angles may be given in
//! degrees (`alpha: deg(10)`) and are recorded in radians.

use rocklab::study::Study;
use rocklab::study::writer::{WIDTH, write};
use std::path::Path;

fn shipped_studies() -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = std::fs::read_dir("studies")
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .map(|p| {
            (
                p.display().to_string(),
                std::fs::read_to_string(&p).unwrap(),
            )
        })
        .collect();
    out.sort();
    assert!(out.len() >= 8, "{out:?}");
    out
}

/// The comments of a study file, each trimmed.
fn comments(text: &str) -> Vec<String> {
    text.lines()
        .filter_map(|l| l.find("//").map(|at| l[at..].trim().to_string()))
        .collect()
}

/// Edits a user may make, each a study that differs from the file's.
fn edits(study: &Study) -> Vec<Study> {
    let mut out = Vec::new();
    let mut renamed = study.clone();
    renamed.name.push_str("_v2");
    out.push(renamed);
    let mut longer = study.clone();
    longer.duration = longer.duration.map(|d| 2.0 * d);
    out.push(longer);
    let mut tighter = study.clone();
    tighter.rtol /= 10.0;
    tighter.stop_when_settled = !tighter.stop_when_settled;
    out.push(tighter);
    out
}

/// Every shipped study: saved unedited it is its file, byte for byte; saved after an edit it
/// reads back as the edited study and keeps every comment of the file; saved with no file
/// behind it (every field written) it reads back too; no line is longer than it must be.
#[test]
fn shipped_studies_save_as_written_and_read_back_the_same() {
    for (path, text) in shipped_studies() {
        let study = Study::from_ron_str(&text, &path).unwrap();
        let unedited = write(&study, Some(&text));
        assert!(unedited.lost.is_empty(), "{path}: {:?}", unedited.lost);
        assert_eq!(unedited.text, text, "{path}: an unedited study is its file");
        for edited in edits(&study) {
            let saved = write(&edited, Some(&text));
            assert!(saved.lost.is_empty(), "{path}: {:?}", saved.lost);
            let back = Study::from_ron_str(&saved.text, &path)
                .unwrap_or_else(|e| panic!("{path}: {e}\n{}", saved.text));
            assert_eq!(back, edited, "{path}:\n{}", saved.text);
            assert_eq!(comments(&saved.text), comments(&text), "{path}");
        }
        let plain = write(&study, None).text;
        assert_eq!(
            Study::from_ron_str(&plain, &path).unwrap(),
            study,
            "{plain}"
        );
        for line in plain.lines() {
            // Only a long string (a description) may pass the width.
            assert!(
                line.chars().count() <= WIDTH || line.ends_with("\","),
                "{path}: {line}"
            );
        }
    }
}

/// A device deleted with its comment: the comment is reported lost (the TUI asks before
/// dropping it), the rest is kept and the text reads back as the edited study.
#[test]
fn a_comment_whose_field_is_gone_is_reported() {
    let text = std::fs::read_to_string("studies/default.ron").unwrap();
    let commented = text.replace(
        "        sequential(sigma: 0.5),\n",
        "        // Makris–Kampas\n        sequential(sigma: 0.5),\n",
    );
    let mut study = Study::from_ron_str(&commented, "c.ron").unwrap();
    study.devices.remove(1);
    let saved = write(&study, Some(&commented));
    assert_eq!(saved.lost, ["// Makris–Kampas"]);
    assert_eq!(Study::from_ron_str(&saved.text, "c.ron").unwrap(), study);
    assert!(saved.text.starts_with("// The built-in default study"));
}

/// `deg(…)` gives the same study as its radians, for a number, a list and a range.
#[test]
fn degrees_expand_like_their_radians() {
    let text = std::fs::read_to_string("studies/default.ron").unwrap();
    let radians = Study::from_ron_str(&text, "r.ron").unwrap();
    assert!(text.contains("alpha: 0.17453292519943295"));
    let degrees = Study::from_ron_str(
        &text.replace("alpha: 0.17453292519943295", "alpha: deg(10)"),
        "d.ron",
    )
    .unwrap();
    assert_eq!(degrees, radians, "recorded in radians");
    assert_eq!(degrees.expand().unwrap(), radians.expand().unwrap());
    assert_eq!(degrees.hash(), radians.hash());

    let alphas = |alpha: &str| {
        let study =
            Study::from_ron_str(&text.replace("0.17453292519943295", alpha), "a.ron").unwrap();
        study
            .expand()
            .unwrap()
            .iter()
            .map(|p| p.coord("α"))
            .collect::<Vec<_>>()
    };
    let in_radians = alphas(&format!(
        "[{:?}, {:?}]",
        5f64.to_radians(),
        15f64.to_radians()
    ));
    assert_eq!(alphas("deg([5, 15])"), in_radians);
    assert_eq!(alphas("[deg(5), deg(15.0)]"), in_radians);
    assert_eq!(
        alphas("deg((from: 5, to: 15, steps: 2))"),
        alphas(&format!(
            "(from: {:?}, to: {:?}, steps: 2)",
            5f64.to_radians(),
            15f64.to_radians()
        ))
    );
}

/// Bad degrees are located errors with the field and a hint, never a different study.
#[test]
fn bad_degrees_are_located_errors() {
    let text = std::fs::read_to_string("studies/default.ron").unwrap();
    let line = text
        .lines()
        .position(|l| l.contains("structure: rigid"))
        .unwrap()
        + 1;
    for (bad, field, says) in [
        ("alpha: deg(abc)", "alpha", "not a number"),
        ("alpha: deg()", "alpha", "no angle"),
        ("alpha: deg(1e999)", "alpha", "not an angle"),
        ("alpha: deg(deg(10))", "alpha", "not a number"),
    ] {
        let e = Study::from_ron_str(&text.replace("alpha: 0.17453292519943295", bad), "bad.ron")
            .unwrap_err();
        let shown = e.to_string();
        assert_eq!(e.line, Some(line), "{shown}");
        assert_eq!(e.field.as_deref(), Some(field), "{shown}");
        assert!(shown.contains(says), "{bad}: {shown}");
        assert!(shown.starts_with("bad.ron:"), "{shown}");
        assert!(e.hint.as_deref().unwrap_or("").contains("deg"), "{shown}");
    }
    let e = Study::from_ron_str(&text.replace("p: 2.0", "p: deg(2)"), "bad.ron").unwrap_err();
    assert_eq!(e.field.as_deref(), Some("p"), "{e}");
    assert!(e.to_string().contains("not an angle"), "{e}");
    assert!(e.hint.as_deref().unwrap().contains("alpha"), "{e}");
}

/// A study saved by `rocklab run` beside its results (every field written) reads back. A
/// `risk` section's hazard path is relative to the study file, so the shipped hazards travel
/// with the studies (as `rocklab run` copies them beside its results).
#[test]
fn study_save_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("hazards")).unwrap();
    for entry in std::fs::read_dir("studies/hazards").unwrap() {
        let from = entry.unwrap().path();
        std::fs::copy(
            &from,
            dir.path().join("hazards").join(from.file_name().unwrap()),
        )
        .unwrap();
    }
    for (path, text) in shipped_studies() {
        let study = Study::from_ron_str(&text, &path).unwrap();
        let file = dir.path().join(Path::new(&path).file_name().unwrap());
        study.save(&file).unwrap();
        assert_eq!(Study::load(&file).unwrap(), study, "{path}");
    }
}
