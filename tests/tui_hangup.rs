//! A lost SSH session while a sweep runs, for real: `rocklab tui` in a tmux pane whose server
//! is killed (the pane's terminal goes away and the process gets SIGHUP, as when an SSH
//! connection drops). The sweep must stop at once and write its results files with the scenes
//! it finished, instead of computing on until the process is ended from outside its stuck
//! event loop (which left no results file, only the journal). Skipped if tmux is absent.

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

/// 200 scenes of an elastic block (restitution 1) rocking for 3000 s at a tight tolerance:
/// about 0.1 s each, 20 s in all, far longer than the test lets the sweep run.
const SLOW: &str = r#"(
    version: 1,
    name: "slow",
    structure: rigid(p: 2.0, alpha: 0.2),
    devices: [none],
    excitation: pulse(shape: sine, amplitude: alpha_ratio(1.2),
                      frequency: ratio((from: 4.0, to: 6.0, steps: 200))),
    impact: housner(restitution: 1.0),
    rtol: 1e-12,
    duration: 3000.0,
    stop_when_settled: false,
)"#;

/// Poll `done` every 50 ms for at most `secs` seconds.
fn wait(secs: u64, mut done: impl FnMut() -> bool) -> bool {
    let until = Instant::now() + Duration::from_secs(secs);
    while Instant::now() < until {
        if done() {
            return true;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    done()
}

/// Finished scenes in a journal (its first line is the header).
fn journalled(path: &Path) -> usize {
    std::fs::read_to_string(path).map_or(0, |t| t.lines().count().saturating_sub(1))
}

#[test]
fn a_hangup_stops_the_sweep_at_once_and_keeps_its_finished_scenes() {
    if Command::new("tmux").arg("-V").output().is_err() {
        eprintln!("notice: hang-up test skipped: tmux is not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("slow.ron"), SLOW).unwrap();
    let socket = format!("rocklab-hangup-{}", std::process::id());
    let tmux = |args: &[&str]| {
        Command::new("tmux")
            .args(["-L", &socket, "-f", "/dev/null"])
            .args(args)
            .output()
            .unwrap()
    };
    let command = format!(
        "cd '{}' && exec '{}' tui slow.ron",
        dir.path().display(),
        env!("CARGO_BIN_EXE_rocklab")
    );
    let started = tmux(&[
        "new-session",
        "-d",
        "-s",
        "hup",
        "-x",
        "80",
        "-y",
        "24",
        &command,
    ]);
    assert!(started.status.success(), "{started:?}");
    let screen =
        || String::from_utf8_lossy(&tmux(&["capture-pane", "-p", "-t", "hup"]).stdout).to_string();
    assert!(wait(20, || screen().contains("scenes in")), "{}", screen());
    let pid =
        String::from_utf8(tmux(&["display", "-p", "-t", "hup", "#{pane_pid}"]).stdout).unwrap();
    let proc_dir = format!("/proc/{}", pid.trim());
    tmux(&["send-keys", "-t", "hup", "r"]);
    let out = dir.path().join("out/slow");
    let journal = out.join("results.journal");
    assert!(wait(60, || journalled(&journal) >= 2), "{}", screen());

    tmux(&["kill-server"]);
    assert!(
        wait(30, || !Path::new(&proc_dir).exists()),
        "rocklab tui did not exit"
    );
    let finished = journalled(&journal);
    // Stopped, not run to the end: the sweep had 200 scenes of ~0.1 s each.
    assert!(finished < 200, "{finished} scenes: the sweep ran on");
    // The stopped sweep wrote its results files, with every scene its journal holds.
    let (results, _) = rocklab::tui::app::load_results_at(&out).unwrap_or_else(|e| {
        panic!("no results written after the hang-up ({finished} scenes journalled): {e:#}")
    });
    assert!(results.cancelled);
    assert_eq!(results.outcomes.len(), finished);
    // Nothing computes on after the exit.
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(journalled(&journal), finished);
}
