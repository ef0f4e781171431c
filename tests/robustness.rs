//! Each reproduction of issue #12 as a regression test: scenes that never ended, inputs that
//! panicked or aborted, silently different studies, unsafe writes. Every case ends in a clear
//! error (exit 2 for bad input) or a bounded failure, never a panic or a hang.

use crate::util::{default_run_with_scene_time_limit, rocklab, rocklab_command};
use std::path::Path;
use std::process::Stdio;

const RIGID: [&str; 4] = ["--alpha", "0.2", "--size", "1"];

fn simulate(extra: &[&str]) -> std::process::Output {
    let mut args = vec!["simulate"];
    args.extend_from_slice(&RIGID);
    args.extend_from_slice(extra);
    rocklab(&args)
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Exit 2 with `expect` in the message, and no panic.
fn refused(o: &std::process::Output, expect: &str) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains(expect), "expected {expect:?} in: {err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn parameters_no_scene_can_resolve_are_refused() {
    // Ran forever: a pulse of 1e308 half-cycles.
    refused(
        &simulate(&[
            "--pulse", "mp", "--gamma", "1e308", "--nu", "0", "--tp", "1", "--pgv", "1",
        ]),
        "γ must be in (1, 20]",
    );
    // Panicked at "a step was taken".
    refused(
        &rocklab(&[
            "simulate",
            "--alpha",
            "0.2",
            "--size",
            "1e-300",
            "--amplitude-ratio",
            "2",
            "--frequency",
            "5",
        ]),
        "invalid value 1e-300 for --size",
    );
    refused(
        &simulate(&[
            "--pulse", "mp", "--tp", "1e-300", "--gamma", "2", "--pgv", "1",
        ]),
        "--tp: pulse period must be ≥ 1 ms",
    );
}

#[test]
fn a_study_with_an_endless_pulse_is_refused_before_it_runs() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("mp.ron");
    std::fs::write(
        &study,
        r#"(version: 1, name: "mp", structure: rigid(p: 2.0, alpha: 0.2),
            devices: [none],
            excitation: pulse(shape: mavroeidis_papageorgiou(gamma: 1e308, nu: 0.0),
                              amplitude: alpha_ratio(1.5), frequency: ratio([2.0, 3.0])),
            duration: 5.0)"#,
    )
    .unwrap();
    refused(
        &rocklab(&["run", study.to_str().unwrap(), "--dry-run"]),
        "gamma",
    );
}

#[test]
fn record_headers_are_checked_before_allocating_and_time_steps_have_a_floor() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        // Aborted allocating 8 TB.
        (
            "huge.at2",
            "t\nt\nt\nNPTS= 1E12, DT= .01 SEC\n0.1 0.2\n",
            "NPTS = 1000000000000 but the data hold only 2 values",
        ),
        // Panicked with "capacity overflow".
        (
            "overflow.at2",
            "t\nt\nt\nNPTS= 1E20, DT= .01 SEC\n0.1 0.2\n",
            "more values than any file holds",
        ),
        // Ran forever.
        (
            "tiny.txt",
            "# dt: 1e-310\n0.1\n0.2\n",
            "is not a usable time step",
        ),
        // Panicked at "a step was taken".
        (
            "small.txt",
            "# dt: 3e-11\n0.1\n0.2\n0.1\n",
            "is not a usable time step",
        ),
        (
            "twocol.txt",
            "0 0.1\n1e-12 0.2\n2e-12 0.1\n",
            "is not a usable time step",
        ),
        // Overflowed to infinity in m/s²; refused as implausible first (issue 43, F9).
        (
            "inf.txt",
            "# dt: 0.01\n1e308\n0.2\n",
            "inf.txt:2: 1e308 g is not a plausible ground acceleration",
        ),
    ];
    for (name, text, expect) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        refused(&simulate(&["--record", path.to_str().unwrap()]), expect);
    }
}

#[test]
fn closed_form_steps_count_against_the_step_budget() {
    // Ran ~75 minutes: a 1e9 s record scene advanced in closed form, uncounted.
    let o = rocklab(&[
        "simulate",
        "--structure",
        "flexible",
        "--alpha",
        "0.2",
        "--size",
        "10",
        "--omega-n",
        "10",
        "--xi",
        "0",
        "--record",
        "landers",
        "--duration",
        "1e9",
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(
        err.matches("step budget of 5000000 steps exhausted")
            .count(),
        1,
        "{err}"
    );
}

#[test]
fn an_explicit_records_dir_must_exist() {
    refused(
        &simulate(&[
            "--record",
            "landers",
            "--records-dir",
            "/nonexistent/records",
        ]),
        "--records-dir /nonexistent/records: no such directory",
    );
    refused(
        &rocklab(&["records", "--records-dir", "/nonexistent/records"]),
        "no such directory",
    );
}

/// The reader goes away before the command writes: no panic, no error text.
fn quiet_when_the_pipe_closes(args: &[&str]) {
    let mut child = rocklab_command(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !err.contains("panicked") && !err.contains("Broken pipe"),
        "{err}"
    );
}

#[test]
fn broken_pipes_end_output_quietly() {
    quiet_when_the_pipe_closes(&["run", "default", "--dry-run"]);
    quiet_when_the_pipe_closes(&["records"]);
    quiet_when_the_pipe_closes(&[
        "simulate",
        "--alpha",
        "0.2",
        "--size",
        "1",
        "--amplitude-ratio",
        "2",
        "--frequency",
        "5",
    ]);
}

#[test]
fn jobs_beyond_a_few_per_core_are_capped_with_a_warning() {
    let o = rocklab(&["run", "default", "--dry-run", "--jobs", "100000"]);
    assert!(o.status.success());
    assert!(
        stderr(&o).contains("warning: --jobs 100000"),
        "{}",
        stderr(&o)
    );
}

fn default_study_with(from: &str, to: &str) -> String {
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/default.ron"))
            .unwrap();
    assert!(
        text.contains(from),
        "studies/default.ron changed: no {from}"
    );
    text.replace(from, to)
}

#[test]
fn unknown_wrappers_and_fields_are_rejected_with_the_valid_names_and_a_bom_is_tolerated() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.display().to_string()
    };
    // Was the 3-point list [1, 12, 24].
    let lin = write(
        "lin.ron",
        &default_study_with(
            "ratio((from: 1.0, to: 12.0, steps: 12))",
            "ratio(linspace(1.0, 12.0, 24))",
        ),
    );
    let o = rocklab(&["run", &lin, "--dry-run"]);
    refused(&o, "unknown name `linspace(`");
    let line = 1 + std::fs::read_to_string(&lin)
        .unwrap()
        .lines()
        .position(|l| l.contains("linspace("))
        .unwrap();
    assert!(
        stderr(&o).contains(&format!("lin.ron:{line}:")),
        "{}",
        stderr(&o)
    );
    assert!(
        stderr(&o).contains("rad_per_sec, ratio"),
        "the valid names are listed"
    );
    // Was accepted as 1.5.
    let foo = write(
        "foo.ron",
        &default_study_with("alpha_ratio(1.5)", "alpha_ratio(foo(1.5))"),
    );
    refused(&rocklab(&["run", &foo, "--dry-run"]), "unknown name `foo(`");
    let field = write("field.ron", &default_study_with("duration:", "durration:"));
    refused(
        &rocklab(&["run", &field, "--dry-run"]),
        "expected one of `version`",
    );
    // Was refused with "Expected opening `(`".
    let bom = write(
        "bom.ron",
        &format!("\u{feff}{}", default_study_with("", "")),
    );
    let o = rocklab(&["run", &bom, "--dry-run"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let plain = rocklab(&["run", "studies/default.ron", "--dry-run"]);
    assert_eq!(o.stdout, plain.stdout);
}

#[test]
fn a_study_name_that_leaves_out_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("escape.ron");
    std::fs::write(
        &study,
        default_study_with("name: \"default\"", "name: \"../../escape\"")
            .replace("steps: 12", "steps: 2"),
    )
    .unwrap();
    let work = dir.path().join("a/b");
    std::fs::create_dir_all(&work).unwrap();
    let o = rocklab_command(&["run", study.to_str().unwrap(), "--quiet"])
        .current_dir(&work)
        .output()
        .unwrap();
    // Issue 43 (F3): a name that would leave out/ is refused, not renamed, so that `run` and
    // `slurm` never disagree about it; nothing is written anywhere.
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--out"), "{}", stderr(&o));
    assert!(!work.join("out").exists());
    assert!(!dir.path().join("escape").exists());
}

#[test]
fn writes_never_replace_a_device_or_a_directory() {
    // As root, `--history /dev/full` replaced the device node.
    let o = simulate(&[
        "--amplitude-ratio",
        "2",
        "--frequency",
        "5",
        "--history",
        "/dev/null",
    ]);
    let err = stderr(&o);
    assert!(!o.status.success());
    assert!(
        err.contains("/dev/null exists and is not a regular file"),
        "{err}"
    );
    use std::os::unix::fs::FileTypeExt;
    assert!(
        std::fs::metadata("/dev/null")
            .unwrap()
            .file_type()
            .is_char_device()
    );
    // results.json as a directory is found before the first scene.
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("results.json")).unwrap();
    let o = rocklab(&[
        "run",
        "default",
        "--out",
        dir.path().to_str().unwrap(),
        "--quiet",
    ]);
    let err = stderr(&o);
    assert!(!o.status.success());
    assert!(
        err.contains("results.json is not a regular file") && err.contains("nothing was run"),
        "{err}"
    );
}

#[test]
fn a_scene_over_its_wall_clock_limit_fails_with_the_reason_and_the_sweep_goes_on() {
    // A limit no scene can meet: every scene fails, with the reason, and the run completes.
    let reasons = default_run_with_scene_time_limit("1e-9");
    assert_eq!(reasons.len(), 36);
    for reason in reasons {
        let reason = reason.expect("every scene fails");
        assert!(reason.contains("wall-clock limit"), "{reason}");
    }
}
