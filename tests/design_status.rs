//! `rocklab status` on a design study: a search runs an unknown number of probes, so a
//! stopped one reports the scenes run so far, the design points answered and an upper bound
//! on what is left (never the nominal grid's size); its journal alone gives its probe scenes
//! back; the resumed search is complete with nothing missing.

use crate::util::{rocklab, sweep_in};
use rocklab::study::Study;
use rocklab::sweep::{self, SweepOptions};
use std::collections::HashSet;
use std::sync::atomic::AtomicBool;

/// Two blocks, the bare block and a mechanistic clutch, three pulses: 4 design points.
const STUDY: &str = r#"(
    version: 1,
    name: "design_status",
    structure: rigid(p: 2.0, alpha: [deg(8), deg(12)]),
    devices: [none, mechanistic(sigma: 0.5, cbar: 1.0)],
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
        bracket: (0.0, 3.0),
        resolution: 0.05,
        target: limit(quantity: peak_rotation_ratio, max: 0.5),
    ),
)"#;

#[test]
fn status_of_a_stopped_design_search_bounds_what_is_left() {
    let study = Study::from_ron_str(STUDY, "design_status.ron").unwrap_or_else(|e| panic!("{e}"));
    let library = rocklab::excitation::library::global().unwrap();
    let full = sweep::run_study(
        &study,
        &SweepOptions::default(),
        library,
        &AtomicBool::new(false),
        &|_| {},
    )
    .unwrap();
    let distinct: HashSet<&str> = full.outcomes.iter().map(|o| o.point.key.as_str()).collect();
    let distinct = distinct.len();
    let points = study.expand().unwrap();
    // The nominal grid: what the journal's header counts, and what status must not report.
    assert_eq!(points.len(), 2 * 2 * 3);

    let dir = tempfile::tempdir().unwrap();
    // Stopped after 15 scenes: the bracket ends and a few bisections.
    let first = sweep_in(dir.path(), &study, &points, Some(15));
    let (stopped, results_file, journal) = (first.results, first.results_file, first.journal);
    assert!(stopped.cancelled);
    let status = sweep::set_status(&results_file, None);
    let ran = status.ok + status.failed;
    assert!((15..distinct).contains(&ran), "{status:?}");
    assert_eq!(status.total, None, "unknown until the search ends");
    let most = status.remaining_at_most.expect("a bound");
    assert!(most >= distinct - ran, "{most} < {} left", distinct - ran);
    // Each point: 2 ends + ⌈log2(1000/0.05)⌉ = 15 bisections + 4 verifications, 3 scenes a
    // probe; the bare blocks' one probe each.
    assert!(most <= 2 * 21 * 3 + 2 * 3, "{most}");
    let note = status.note.clone().unwrap();
    assert!(note.contains("of 4 design points answered"), "{note}");
    assert!(
        note.contains(&format!("at most {most} more scenes")),
        "{note}"
    );
    let text =
        String::from_utf8(rocklab(&["status", dir.path().to_str().unwrap()]).stdout).unwrap();
    assert!(text.contains(&format!("≤{most}")), "{text}");
    assert!(text.contains("stopped, incomplete"), "{text}");
    assert!(text.contains(&note), "{text}");

    // The journal alone gives the probe scenes back (they are off the nominal grid).
    let saved = std::fs::read(&results_file).unwrap();
    std::fs::remove_file(&results_file).unwrap();
    let (from_journal, _) = sweep::load_fullest(&journal).unwrap().unwrap();
    std::fs::write(&results_file, saved).unwrap();
    assert!(from_journal.cancelled);
    let keys: HashSet<&str> = (from_journal.outcomes.iter())
        .map(|o| o.point.key.as_str())
        .collect();
    assert_eq!(keys.len(), ran);

    // Resumed to the end: complete, nothing missing, every point answered.
    let resumed = sweep_in(dir.path(), &study, &points, None).results;
    assert!(!resumed.cancelled);
    let status = sweep::set_status(&results_file, None);
    assert_eq!(status.ok + status.failed, distinct);
    assert_eq!(status.total, Some(distinct));
    assert_eq!(status.missing(), Some(0));
    assert_eq!(status.remaining_at_most, None);
    let note = status.note.unwrap();
    assert!(note.contains("4 of 4 design points answered"), "{note}");
    let text =
        String::from_utf8(rocklab(&["status", dir.path().to_str().unwrap()]).stdout).unwrap();
    assert!(text.contains("complete"), "{text}");
}
