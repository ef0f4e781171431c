//! No stop loses a finished scene: real `rocklab run` processes stopped by SIGTERM, SIGHUP,
//! SIGKILL and SIGINT mid-sweep, then rerun: every scene journalled before the signal is
//! reused (none is computed twice) and the final results equal an uninterrupted run's. Also:
//! an unwritable output directory fails before the first scene, `--fresh` + Ctrl-C keeps the
//! old results, two runs cannot write one directory, merge and status read the journals.
//!
//! No timing assertions: the tests wait for journal lines (with generous timeouts so they
//! never hang) before they signal.

use crate::util::{rocklab, rocklab_command};
use rocklab::sweep::{self, SceneOutcome};
use std::path::{Path, PathBuf};
use std::process::{Child, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// 300 flexible-structure scenes under records: long enough (seconds on one thread) that a
/// signal sent after the first few journal lines lands mid-sweep.
const STUDY: &str = r#"(
    version: 1,
    name: "checkpoint",
    structure: flexible(r0: 10.0, alpha: 0.2, xi: 0.02, omega_n: (from: 2.0, to: 29.3, steps: 20)),
    devices: [none, sequential(sigma: 0.5), mechanistic(sigma: 0.5, xi_theta: 0.02)],
    excitation: record(
        names: ["landers", "northridge", "imperial_valley", "superstition_hills", "palm_springs"],
        scale: 1.0,
    ),
    quantities: [peak_rotation_ratio, peak_deformation],
    spectrum: omega_n,
    duration: 60.0,
)"#;
const SCENES: usize = 300;
/// Journal lines to wait for before a signal.
const BEFORE_SIGNAL: usize = 12;
const PATIENCE: Duration = Duration::from_secs(600);

fn write_study(dir: &Path) -> String {
    let path = dir.join("checkpoint.ron");
    std::fs::write(&path, STUDY).unwrap();
    path.display().to_string()
}

/// Results without wall-clock times (the only field that legitimately varies between runs).
fn timeless(mut outcomes: Vec<SceneOutcome>) -> Vec<SceneOutcome> {
    for o in &mut outcomes {
        if let Ok(r) = &mut o.result {
            r.wall_seconds = 0.0;
        }
    }
    outcomes
}

fn outcomes(results: &Path) -> Vec<SceneOutcome> {
    let r = rocklab::report::load_results(results).unwrap();
    timeless(r.outcomes)
}

/// The uninterrupted run, computed once for all tests.
fn reference() -> &'static [SceneOutcome] {
    static REFERENCE: OnceLock<Vec<SceneOutcome>> = OnceLock::new();
    REFERENCE.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let study = write_study(dir.path());
        let out = dir.path().join("out");
        let o = crate::util::run_into(&study, &out);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let all = outcomes(&out.join("results.json"));
        assert_eq!(all.len(), SCENES);
        assert!(all.iter().all(|o| o.result.is_ok()));
        all
    })
}

/// Complete lines in a file (a torn last line does not count).
pub(crate) fn lines(path: &Path) -> usize {
    std::fs::read(path)
        .map(|b| b.iter().filter(|c| **c == b'\n').count())
        .unwrap_or(0)
}

pub(crate) fn spawn_run(study: &str, out: &Path, extra: &[&str]) -> Child {
    let mut args = vec!["run", study, "--out", out.to_str().unwrap(), "--quiet"];
    args.extend_from_slice(extra);
    rocklab_command(&args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("rocklab starts")
}

/// Wait until `path` has at least `n` complete lines (or the child ended).
pub(crate) fn wait_for_lines(child: &mut Child, path: &Path, n: usize) {
    let start = Instant::now();
    while lines(path) < n {
        if let Ok(Some(status)) = child.try_wait() {
            panic!(
                "rocklab ended ({status}) before {} had {n} lines",
                path.display()
            );
        }
        assert!(
            start.elapsed() < PATIENCE,
            "no progress in {}",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

pub(crate) fn signal(child: &Child, name: &str) {
    let ok = std::process::Command::new("kill")
        .args([&format!("-{name}"), &child.id().to_string()])
        .status()
        .expect("kill runs")
        .success();
    assert!(ok, "kill -{name} failed");
}

/// Wait for the child (killing it if it outlives the patience) and return its stderr.
pub(crate) fn finish(mut child: Child) -> (std::process::ExitStatus, String) {
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            use std::io::Read;
            if let Some(mut e) = child.stderr.take() {
                let _ = e.read_to_string(&mut err);
            }
            return (status, err);
        }
        if start.elapsed() > PATIENCE {
            let _ = child.kill();
            panic!("rocklab did not stop");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Scenes finished (journalled) in a journal, as `rocklab status` counts them.
pub(crate) fn journalled(path: &Path) -> usize {
    let status = sweep::set_status(&path.with_extension("json"), None);
    assert!(status.total.is_some(), "{} unreadable", path.display());
    status.ok + status.failed
}

/// The scene count in "resuming from …: N finished scenes reused".
pub(crate) fn reused(stderr: &str) -> usize {
    let at = stderr
        .find("finished scenes reused")
        .unwrap_or_else(|| panic!("no resume note in: {stderr}"));
    stderr[..at]
        .split_whitespace()
        .last()
        .unwrap()
        .parse()
        .unwrap()
}

/// Stop a run with `name` mid-sweep, rerun, and check reuse counts and the final identity.
fn stopped_then_resumed(name: &str) {
    let reference = reference();
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path());
    let out = dir.path().join("out");
    let journal_path = out.join("results.journal");
    let mut child = spawn_run(&study, &out, &["--jobs", "1"]);
    wait_for_lines(&mut child, &journal_path, 1 + BEFORE_SIGNAL);
    signal(&child, name);
    let (status, stderr) = finish(child);
    assert!(
        !status.success(),
        "SIG{name} must end the run non-zero: {stderr}"
    );
    let before = journalled(&journal_path);
    assert!(
        (BEFORE_SIGNAL..SCENES).contains(&before),
        "{before} scenes journalled"
    );
    if name != "KILL" {
        // Handled like SIGINT: the finished scenes are also in a (partial) results file.
        assert!(stderr.contains("cancelled"), "{stderr}");
        let partial = rocklab::report::load_results(&out.join("results.json")).unwrap();
        assert!(partial.cancelled);
        assert_eq!(partial.outcomes.len(), before);
    }
    let again = spawn_run(&study, &out, &[]);
    let (status, stderr) = finish(again);
    assert!(status.success(), "{stderr}");
    assert_eq!(reused(&stderr), before, "every journalled scene is reused");
    // Each scene was computed exactly once over both runs: header + one line per scene.
    assert_eq!(lines(&journal_path), 1 + SCENES);
    assert_eq!(outcomes(&out.join("results.json")), reference);
}

#[test]
fn sigterm_mid_sweep_loses_no_finished_scene() {
    stopped_then_resumed("TERM");
}

#[test]
fn sighup_mid_sweep_loses_no_finished_scene() {
    stopped_then_resumed("HUP");
}

#[test]
fn sigkill_mid_sweep_loses_no_finished_scene() {
    stopped_then_resumed("KILL");
}

#[test]
fn a_shard_stopped_by_sigterm_resumes_from_its_journal_and_merges_to_the_full_run() {
    let reference = reference();
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path());
    let out = dir.path().join("out");
    let journal_path = out.join("results.shard-0-of-2.journal");
    let mut child = spawn_run(&study, &out, &["--jobs", "1", "--shard", "0/2"]);
    wait_for_lines(&mut child, &journal_path, 1 + BEFORE_SIGNAL);
    signal(&child, "TERM");
    let (status, _) = finish(child);
    assert!(!status.success());
    let before = journalled(&journal_path);

    // status: shard 0 stopped with scenes missing, shard 1 never started; both to resubmit.
    let s = rocklab(&["status", out.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&s.stdout);
    assert!(s.status.success(), "{text}");
    let row = text.lines().find(|l| l.starts_with("0/2")).unwrap();
    let cells: Vec<&str> = row.split_whitespace().collect();
    assert_eq!(cells[1].parse::<usize>().unwrap(), before, "{row}");
    assert_eq!(
        cells[3].parse::<usize>().unwrap(),
        SCENES / 2 - before,
        "{row}"
    );
    assert!(
        text.contains("1/2") && text.contains("not started"),
        "{text}"
    );
    assert!(text.contains("resubmit array tasks 0,1"), "{text}");

    let (status, stderr) = finish(spawn_run(&study, &out, &["--shard", "0/2"]));
    assert!(status.success(), "{stderr}");
    assert_eq!(reused(&stderr), before);
    assert_eq!(lines(&journal_path), 1 + SCENES / 2);
    let (status, stderr) = finish(spawn_run(&study, &out, &["--shard", "1/2"]));
    assert!(status.success(), "{stderr}");
    let s = rocklab(&["status", out.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&s.stdout).contains("every set is complete"));

    let merged = dir.path().join("merged");
    let m = rocklab(&[
        "merge",
        out.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(m.status.success(), "{}", String::from_utf8_lossy(&m.stderr));
    assert_eq!(outcomes(&merged.join("results.json")), reference);
}

#[test]
fn merge_reads_a_shard_whose_final_write_never_happened_from_its_journal() {
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path());
    let out = dir.path().join("out");
    let journal_path = out.join("results.shard-1-of-2.journal");
    let mut child = spawn_run(&study, &out, &["--jobs", "1", "--shard", "1/2"]);
    wait_for_lines(&mut child, &journal_path, 1 + BEFORE_SIGNAL);
    signal(&child, "KILL");
    finish(child);
    assert!(!out.join("results.shard-1-of-2.json").exists());
    let before = journalled(&journal_path);
    let merged = dir.path().join("merged");
    let m = rocklab(&[
        "merge",
        journal_path.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
        "--quiet",
    ]);
    let err = String::from_utf8_lossy(&m.stderr);
    assert!(m.status.success(), "{err}");
    assert!(err.contains("incomplete"), "{err}");
    let got = outcomes(&merged.join("results.json"));
    assert_eq!(got.len(), before);
    let reference = reference();
    for o in &got {
        assert_eq!(
            Some(o),
            reference.iter().find(|r| r.point.index == o.point.index)
        );
    }
}

#[test]
fn fresh_then_ctrl_c_keeps_the_previous_complete_results() {
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path());
    let out = dir.path().join("out");
    let (status, stderr) = finish(spawn_run(&study, &out, &[]));
    assert!(status.success(), "{stderr}");
    let complete = std::fs::read(out.join("results.json")).unwrap();

    let journal_path = out.join("results.journal");
    let mut child = spawn_run(&study, &out, &["--fresh", "--jobs", "1"]);
    // The fresh run sets the old journal aside and starts a new one: wait for its scenes.
    let start = Instant::now();
    while !out.join("results.journal.previous").exists() {
        if let Ok(Some(s)) = child.try_wait() {
            panic!("the fresh run ended early: {s}");
        }
        assert!(start.elapsed() < PATIENCE);
        std::thread::sleep(Duration::from_millis(5));
    }
    wait_for_lines(&mut child, &journal_path, 1 + BEFORE_SIGNAL);
    signal(&child, "INT");
    let (status, stderr) = finish(child);
    assert!(!status.success());
    assert!(stderr.contains("previous complete results"), "{stderr}");
    assert_eq!(std::fs::read(out.join("results.json")).unwrap(), complete);
    // Running on (without --fresh) continues the fresh run and then replaces the results.
    let (status, stderr) = finish(spawn_run(&study, &out, &[]));
    assert!(status.success(), "{stderr}");
    assert_eq!(lines(&journal_path), 1 + SCENES);
    assert_eq!(outcomes(&out.join("results.json")), reference());
    assert!(!out.join("results.journal.previous").exists());
}

#[test]
fn two_runs_cannot_write_one_directory() {
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path());
    let out = dir.path().join("out");
    let mut first = spawn_run(&study, &out, &["--jobs", "1"]);
    wait_for_lines(&mut first, &out.join("results.journal"), 2);
    let second = crate::util::run_into(&study, &out);
    let err = String::from_utf8_lossy(&second.stderr);
    assert!(!second.status.success());
    assert!(
        err.contains(&format!("another rocklab (pid {})", first.id())),
        "{err}"
    );
    // While it runs, status says so.
    let s = rocklab(&["status", out.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&s.stdout).contains(&format!("running (pid {})", first.id())));
    signal(&first, "TERM");
    finish(first);
}

/// A small rigid-block study: 2 devices × 6 frequencies.
const SMALL: &str = r#"(
    version: 1,
    name: "small",
    structure: rigid(p: 2.0, alpha: 0.2),
    devices: [none, sequential(sigma: 0.5)],
    excitation: pulse(shape: sine, amplitude: alpha_ratio(1.5), frequency: ratio((from: 2.0, to: 7.0, steps: 6))),
    duration: 6.0,
)"#;

/// An edited study run into the same directory (`rocklab run` again) reuses every finished
/// scene whose scene is unchanged, whatever else changed, says "N reused, M new", journals
/// the reused ones under the new study and gives what a fresh run gives. Another study's
/// results there are set aside (kept), never refused.
#[test]
fn an_edited_study_reuses_its_unchanged_scenes() {
    let dir = tempfile::tempdir().unwrap();
    let (study, out) = (dir.path().join("small.ron"), dir.path().join("out"));
    let run = |text: &str| {
        std::fs::write(&study, text).unwrap();
        let o = crate::util::run_into(study.to_str().unwrap(), &out);
        let err = String::from_utf8_lossy(&o.stderr).to_string();
        assert!(o.status.success(), "{err}");
        err
    };
    let err = run(SMALL);
    assert!(err.contains("12 scenes (0 reused, 12 new)"), "{err}");
    // A device added: the first run's 12 scenes are unchanged.
    let edited = SMALL.replace(
        "sequential(sigma: 0.5)]",
        "sequential(sigma: 0.5), mechanistic(sigma: 0.5)]",
    );
    let err = run(&edited);
    assert!(err.contains("18 scenes (12 reused, 6 new)"), "{err}");
    assert!(err.contains("an earlier version of 'small'"), "{err}");
    assert_eq!(lines(&out.join("results.journal")), 1 + 18);
    let fresh = dir.path().join("fresh");
    let o = crate::util::run_into(study.to_str().unwrap(), &fresh);
    assert!(o.status.success());
    assert_eq!(
        outcomes(&out.join("results.json")),
        outcomes(&fresh.join("results.json"))
    );
    // A longer duration changes every scene: nothing is reused.
    let longer = edited.replace("duration: 6.0", "duration: 7.0");
    let err = run(&longer);
    assert!(err.contains("18 scenes (0 reused, 18 new)"), "{err}");
    // Another study (another name) into the directory: its results are set aside, kept.
    let err = run(&longer.replace("\"small\"", "\"other\""));
    assert!(err.contains("study 'small'"), "{err}");
    assert!(err.contains("18 scenes (18 reused, 0 new)"), "{err}");
    assert!(out.join("results.json.previous").exists());
}

/// A small tmpfs mounted for the test (root only), unmounted when dropped.
struct Mount(PathBuf);

impl Mount {
    fn tmpfs(path: &Path, options: &str) -> Option<Mount> {
        std::fs::create_dir_all(path).unwrap();
        let ok = std::process::Command::new("mount")
            .args([
                "-t",
                "tmpfs",
                "-o",
                options,
                "tmpfs",
                path.to_str().unwrap(),
            ])
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success());
        ok.then(|| Mount(path.to_path_buf()))
    }
}

impl Drop for Mount {
    fn drop(&mut self) {
        let _ = std::process::Command::new("umount").arg(&self.0).status();
    }
}

fn is_root() -> bool {
    std::process::Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

/// The run fails at once, before any scene, saying which directory and why.
fn refused_before_the_first_scene(study: &str, out: &Path, why: &str) {
    let o = crate::util::run_into(study, out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        err.contains("cannot write in the output directory") && err.contains("nothing was run"),
        "{err}"
    );
    assert!(err.contains(why), "{err}");
    assert!(!out.join("results.journal").exists());
}

#[test]
fn a_read_only_output_directory_fails_before_the_first_scene() {
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path());
    let out = dir.path().join("ro");
    let _mount = if is_root() {
        // Root writes through permission bits: a read-only file system it is.
        let Some(m) = Mount::tmpfs(&out, "ro,size=1m") else {
            eprintln!("SKIPPED: root without permission to mount a read-only tmpfs");
            return;
        };
        Some(m)
    } else {
        use std::os::unix::fs::PermissionsExt;
        std::fs::create_dir(&out).unwrap();
        std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o555)).unwrap();
        None
    };
    let why = if is_root() {
        "Read-only file system"
    } else {
        "Permission denied"
    };
    refused_before_the_first_scene(&study, &out, why);
}

#[test]
fn a_full_output_directory_fails_before_the_first_scene() {
    if !is_root() {
        eprintln!("SKIPPED: a full file system needs root to mount a small tmpfs");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path());
    let out = dir.path().join("full");
    let Some(_mount) = Mount::tmpfs(&out, "size=64k") else {
        eprintln!("SKIPPED: root without permission to mount a tmpfs");
        return;
    };
    // Room for less than the sweep's results: refused by the space check.
    refused_before_the_first_scene(&study, &out, "MB are free");
    // Completely full: the probe write itself fails.
    let filler = vec![0u8; 16 * 1024];
    let mut i = 0;
    while std::fs::write(out.join(format!("fill{i}")), &filler).is_ok() {
        i += 1;
        assert!(i < 1000);
    }
    refused_before_the_first_scene(&study, &out, "No space left");
}

#[test]
fn a_torn_journal_line_and_a_corrupt_results_file_are_reported_and_repaired() {
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path());
    let out = dir.path().join("out");
    let (status, stderr) = finish(spawn_run(&study, &out, &[]));
    assert!(status.success(), "{stderr}");
    // A write cut short by a power loss: a last line without its newline.
    let journal_path = out.join("results.journal");
    let mut bytes = std::fs::read(&journal_path).unwrap();
    let last_start = bytes[..bytes.len() - 1]
        .iter()
        .rposition(|b| *b == b'\n')
        .unwrap()
        + 1;
    bytes.truncate(last_start + 40);
    std::fs::write(&journal_path, &bytes).unwrap();
    let (status, stderr) = finish(spawn_run(&study, &out, &[]));
    assert!(status.success(), "{stderr}");
    assert!(stderr.contains("1 damaged line(s) skipped"), "{stderr}");
    assert_eq!(reused(&stderr), SCENES - 1);
    assert_eq!(lines(&journal_path), 1 + SCENES);
    assert_eq!(outcomes(&out.join("results.json")), reference());

    // Without a journal, a corrupt results file is reported, not silently recomputed.
    std::fs::remove_file(&journal_path).unwrap();
    std::fs::write(out.join("results.json"), b"{\"format\": 1, \"outc").unwrap();
    let (status, stderr) = finish(spawn_run(&study, &out, &[]));
    assert!(status.success(), "{stderr}");
    assert!(stderr.contains("discarded"), "{stderr}");
    assert_eq!(outcomes(&out.join("results.json")), reference());
}

#[test]
fn merge_refuses_shards_of_different_builds_unless_forced() {
    use rocklab::sweep::{SweepResults, merge};
    let part = |shard, build: &str| SweepResults {
        study_hash: "h".into(),
        shard: Some(shard),
        build: build.into(),
        ..Default::default()
    };
    let err = merge(vec![part((0, 2), "aaaa"), part((1, 2), "bbbb")], false).unwrap_err();
    assert!(err.to_string().contains("different builds"), "{err}");
    let forced = merge(vec![part((0, 2), "aaaa"), part((1, 2), "bbbb")], true).unwrap();
    assert_eq!(forced.build, "mixed");
    assert!(!rocklab::sweep::reusable(&forced));
    let same = merge(vec![part((0, 2), "aaaa"), part((1, 2), "aaaa")], false).unwrap();
    assert_eq!(same.build, "aaaa");
}

/// `run --force` of studies A, B, then C into one directory: A's results are set aside as
/// results.json.previous, B's beside them as results.json.previous.2; none is overwritten.
#[test]
fn forced_runs_never_overwrite_set_aside_results() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    for name in ["a", "b", "c"] {
        let study = dir.path().join(format!("{name}.ron"));
        let text = format!(
            "(version: 1, name: \"{name}\", structure: rigid(p: 2.0, alpha: 0.2), \
             devices: [none], excitation: pulse(shape: sine, amplitude: alpha_ratio(2.0), \
             frequency: ratio([2.0, 4.0])), duration: 2.0)"
        );
        std::fs::write(&study, text).unwrap();
        let o = rocklab(&[
            "run",
            study.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--force",
            "--quiet",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let name = |file: &str| {
        let r = rocklab::sweep::load_results(&out.join(file)).unwrap();
        r.study.unwrap().name
    };
    assert_eq!(name("results.json"), "c");
    assert_eq!(name("results.json.previous"), "a");
    assert_eq!(name("results.json.previous.2"), "b");
}

/// A journal line edited on disk (a peak changed to 7.0) fails its checksum: the rerun says
/// so, recomputes that scene, and the results are the ones of the untouched run.
#[test]
fn an_edited_journal_line_is_recomputed_not_reused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let study = dir.path().join("s.ron");
    std::fs::write(
        &study,
        "(version: 1, name: \"s\", structure: rigid(p: 2.0, alpha: 0.2), devices: [none], \
         excitation: pulse(shape: sine, amplitude: alpha_ratio(2.0), frequency: ratio([2.0, \
         4.0, 8.0])), duration: 2.0)",
    )
    .unwrap();
    let o = crate::util::run_into(study.to_str().unwrap(), &out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let before = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let journal_path = out.join("results.journal");
    let text = std::fs::read_to_string(&journal_path).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let field = "\"peak_rotation_ratio\":";
    let at = lines[2].find(field).expect("a peak in the line") + field.len();
    let end = at + lines[2][at..].find([',', '}']).unwrap();
    assert_ne!(&lines[2][at..end], "7.0");
    lines[2].replace_range(at..end, "7.0");
    std::fs::write(&journal_path, lines.join("\n") + "\n").unwrap();
    // The edited line counts as no scene (as `rocklab status` counts them).
    assert_eq!(journalled(&journal_path), 2);

    let o = crate::util::run_into(study.to_str().unwrap(), &out);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    assert!(stderr.contains("1 damaged line"), "{stderr}");
    assert_eq!(
        std::fs::read_to_string(out.join("results.csv")).unwrap(),
        before
    );
    assert_eq!(journalled(&journal_path), 3);
}
