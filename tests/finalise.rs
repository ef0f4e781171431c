//! Signals honoured while a finished sweep writes its results (issue 29): a study big enough
//! that writing results.json and the tables takes a while is signalled once the run says it
//! is writing; the process stops then (status 128 + signal), not after the writes, with
//! every scene in its journal, and the same command run again writes the results computing
//! nothing.
//!
//! No timing assertions: "stops at once" is asserted as the signal's exit status and message
//! (a run that finished its writes first exits 0, and the test says so).

use crate::checkpoint::{finish, journalled, lines, reused, signal};
use crate::util::rocklab_command;
use std::io::BufRead;
use std::path::Path;
use std::process::Stdio;
use std::time::Duration;

/// 60 000 cheap rigid-block scenes (0.05 s each, nothing rocks): seconds to compute, about a
/// second to write (results.json alone is some 80 MB).
const STUDY: &str = r#"(
    version: 1,
    name: "finalise",
    structure: rigid(p: 2.0, alpha: 0.17453292519943295),
    devices: [none],
    excitation: pulse(
        shape: sine,
        amplitude: tan_alpha_ratio((from: 1.0, to: 8.0, steps: 60)),
        frequency: ratio((from: 1.0, to: 12.0, steps: 1000)),
    ),
    quantities: [peak_rotation_ratio],
    map: (x: frequency, y: amplitude),
    duration: 0.05,
)"#;
const SCENES: usize = 60_000;

/// Run the study into `out`, send `name` once it says it is writing, and return its exit
/// status and stderr.
fn signalled_while_writing(study: &Path, out: &Path, name: &str) -> (Option<i32>, String) {
    let mut child = rocklab_command(&[
        "run",
        study.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ])
    .stdout(Stdio::null())
    .stderr(Stdio::piped())
    .spawn()
    .expect("rocklab starts");
    let stderr = child.stderr.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    let reader = std::thread::spawn(move || {
        let mut all = String::new();
        for line in std::io::BufReader::new(stderr)
            .lines()
            .map_while(Result::ok)
        {
            if line.starts_with("writing the results") {
                let _ = tx.send(());
            }
            all.push_str(&line);
            all.push('\n');
        }
        all
    });
    let writing = rx.recv_timeout(Duration::from_secs(600)).is_ok();
    assert!(writing, "the run never said it was writing its results");
    signal(&child, name);
    let (status, _) = finish(child);
    (status.code(), reader.join().unwrap())
}

#[test]
fn a_signal_while_the_results_are_written_stops_at_once_and_loses_no_scene() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("finalise.ron");
    std::fs::write(&study, STUDY).unwrap();
    for (name, number) in [("TERM", 15), ("HUP", 1)] {
        let out = dir.path().join(format!("out-{name}"));
        let (code, stderr) = signalled_while_writing(&study, &out, name);
        assert_eq!(
            code,
            Some(128 + number),
            "SIG{name} during the writes must stop the run (exit 0 means the writes won the \
             race: the study is too small for this machine): {stderr}"
        );
        assert!(
            stderr.contains(&format!("stopped by signal {number} while writing")),
            "{stderr}"
        );
        // Every scene is in the journal (header + one line each), none lost.
        let journal = out.join("results.journal");
        assert_eq!(lines(&journal), 1 + SCENES);
        assert_eq!(journalled(&journal), SCENES);
        // The same command writes the results from the journal, computing nothing.
        let again = rocklab_command(&[
            "run",
            study.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ])
        .output()
        .unwrap();
        let stderr = String::from_utf8_lossy(&again.stderr);
        assert!(again.status.success(), "{stderr}");
        assert_eq!(reused(&stderr), SCENES, "{stderr}");
        assert!(
            stderr.contains(&format!("({SCENES} reused, 0 new)")),
            "{stderr}"
        );
        assert_eq!(lines(&journal), 1 + SCENES, "nothing computed twice");
        let results = rocklab::report::load_results(&out.join("results.json")).unwrap();
        assert!(!results.cancelled);
        assert_eq!(results.outcomes.len(), SCENES);
        // One CSV row per scene and quantity, after the header.
        assert_eq!(lines(&out.join("results.csv")), 1 + SCENES);
    }
}
