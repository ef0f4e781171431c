//! `rocklab slurm`: the job-array and merge scripts (golden text), their sizes from the study's
//! scene count, flag errors, and the array script's stop-and-requeue logic run under bash with
//! stand-ins for rocklab, squeue and scontrol. The real scheduler is exercised by
//! scripts/slurm-test.sh (in .ci/run).

use crate::util::rocklab;
use rocklab::cli::slurm::{Plan, shard_scenes};
use std::os::unix::fs::PermissionsExt;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn plan() -> Plan {
    Plan {
        study_name: "fig24_records".into(),
        study_hash: "47e55c11a3a174de".into(),
        scenes: 600,
        tasks: 7,
        cpus_per_task: 4,
        time_seconds: 2 * 86400 + 1800,
        partition: Some("compute".into()),
        account: Some("quake-lab".into()),
        max_requeue: 3,
        rocklab: "/opt/rocklab/bin/rocklab".into(),
        study: "/home/ana/my studies/fig24_records.ron".into(),
        out: "/scratch/ana/fig24".into(),
        workdir: "/home/ana".into(),
    }
}

#[test]
fn scripts_golden() {
    let plan = plan();
    assert_eq!(plan.scenes_per_task(), (85, 86));
    insta::with_settings!({snapshot_path => "../snapshots", prepend_module_to_snapshot => false}, {
        insta::assert_snapshot!("slurm_array_script", plan.array_script());
        insta::assert_snapshot!("slurm_merge_script", plan.merge_script());
    });
}

fn written(out: &Path, name: &str) -> String {
    std::fs::read_to_string(out.join("slurm").join(name)).expect("script written")
}

#[test]
fn sized_from_the_study_scene_count() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fig24");
    let o = rocklab(&[
        "slurm",
        "studies/fig24_records.ron",
        "--tasks",
        "7",
        "--cpus-per-task",
        "2",
        "--time",
        "90",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // fig24: 5 records × 3 devices × 40 ωn = 600 scenes; 600 = 5·86 + 2·85.
    assert!(
        stdout.contains("600 scenes in 7 tasks of 85–86 scenes"),
        "{stdout}"
    );
    assert_eq!(
        (0..7).map(|i| shard_scenes(600, 7, i)).collect::<Vec<_>>(),
        [86, 86, 86, 86, 86, 85, 85]
    );
    let array = written(&out, "array.sh");
    for line in [
        "#SBATCH --array=0-6",
        "#SBATCH --cpus-per-task=2",
        "#SBATCH --time=01:30:00",
        "#SBATCH --requeue",
        "#SBATCH --signal=B:TERM@60",
        "--shard \"${SLURM_ARRAY_TASK_ID}/7\"",
    ] {
        assert!(array.contains(line), "no `{line}` in\n{array}");
    }
    let study = std::fs::canonicalize("studies/fig24_records.ron").unwrap();
    assert!(array.contains(&format!("run {} --out {}", study.display(), out.display())));
    let merge = written(&out, "merge.sh");
    assert!(merge.contains("results.shard-*-of-7.json") && merge.contains("-ne 7"));
    assert!(
        stdout.contains("sbatch --dependency=afterok:$id"),
        "{stdout}"
    );
    for script in ["array.sh", "merge.sh"] {
        let check = Command::new("bash")
            .arg("-n")
            .arg(out.join("slurm").join(script))
            .status()
            .unwrap();
        assert!(check.success(), "{script} is not valid bash");
    }
}

#[test]
fn never_more_tasks_than_scenes() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("d");
    // The built-in default study has 36 scenes.
    let o = rocklab(&[
        "slurm",
        "default",
        "--tasks",
        "50",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("36 tasks instead of 50"));
    let array = written(&out, "array.sh");
    assert!(array.contains("#SBATCH --array=0-35"), "{array}");
    assert!(array.contains(" run default --out "), "{array}");
}

#[test]
fn bad_flags_are_usage_errors() {
    for (flags, message) in [
        (&["--tasks", "0"][..], "--tasks must be at least 1"),
        (&["--time", "2"][..], "is too short"),
        (&["--time", "1:2:3:4"][..], "invalid time"),
        (
            &["--cpus-per-task", "0"][..],
            "--cpus-per-task must be at least 1",
        ),
    ] {
        let mut args = vec!["slurm", "default", "--out", "/nonexistent/never-written"];
        args.extend_from_slice(flags);
        let o = rocklab(&args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{flags:?}: {stderr}");
        assert!(stderr.contains(message), "{flags:?}: {stderr}");
    }
}

/// The array script, run by bash as Slurm would run task 5_1, with stand-ins on PATH: `squeue`
/// reports `state`, `scontrol` records its arguments then ends the script's process group (as
/// Slurm does when it requeues a task), and "rocklab" waits for SIGTERM (exit 3) or finishes.
struct Task {
    dir: tempfile::TempDir,
}

impl Task {
    fn new(state: &str, rocklab_finishes: bool) -> Task {
        let dir = tempfile::tempdir().unwrap();
        let bin = dir.path().join("bin");
        std::fs::create_dir(&bin).unwrap();
        let d = dir.path().display();
        let stub = |name: &str, body: String| {
            let path = bin.join(name);
            std::fs::write(&path, format!("#!/bin/bash\n{body}\n")).unwrap();
            std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
        };
        stub("squeue", format!("echo {state}"));
        stub(
            "scontrol",
            // The script leads its own process group (see `run`), so its pid is the group id.
            format!("echo \"$*\" >> {d}/scontrol.txt\nkill -KILL -- -$PPID"),
        );
        let work = if rocklab_finishes {
            "exit 0"
        } else {
            "sleep 20 & wait"
        };
        stub(
            "rocklab",
            format!(
                "trap 'echo stopped >> {d}/rocklab.txt; exit 3' TERM\necho \"$*\" > {d}/args.txt\n{work}"
            ),
        );
        let mut plan = plan();
        plan.tasks = 2;
        plan.rocklab = bin.join("rocklab");
        std::fs::write(dir.path().join("array.sh"), plan.array_script()).unwrap();
        Task { dir }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    /// Run the task with `restarts` earlier runs; send SIGTERM once rocklab has started if
    /// `term`. Returns the script's exit code (None if killed by a signal).
    fn run(&self, restarts: u32, term: bool) -> Option<i32> {
        let path = format!(
            "{}:{}",
            self.path("bin").display(),
            std::env::var("PATH").unwrap()
        );
        let mut child = Command::new("bash")
            .arg(self.path("array.sh"))
            .env("PATH", path)
            .env("SLURM_ARRAY_JOB_ID", "5")
            .env("SLURM_ARRAY_TASK_ID", "1")
            .env("SLURM_CPUS_PER_TASK", "2")
            .env("SLURM_RESTART_COUNT", restarts.to_string())
            .stdout(Stdio::null())
            .process_group(0)
            .spawn()
            .unwrap();
        let started = Instant::now();
        while !self.path("args.txt").exists() {
            assert!(
                started.elapsed() < Duration::from_secs(10),
                "rocklab never started"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        if term {
            std::thread::sleep(Duration::from_millis(200));
            Command::new("kill")
                .args(["-TERM", &child.id().to_string()])
                .status()
                .unwrap();
        }
        let status = child.wait().unwrap();
        status.code()
    }

    fn read(&self, name: &str) -> String {
        std::fs::read_to_string(self.path(name)).unwrap_or_default()
    }
}

#[test]
fn a_task_told_to_stop_passes_sigterm_on_and_requeues_itself() {
    let task = Task::new("RUNNING", false);
    // Ended by the process-group kill of the stand-in scontrol, as Slurm ends a requeued task.
    assert_eq!(task.run(0, true), None);
    assert_eq!(
        task.read("args.txt").trim(),
        "run /home/ana/my studies/fig24_records.ron --out /scratch/ana/fig24 --quiet --jobs 2 --shard 1/2"
    );
    assert_eq!(
        task.read("rocklab.txt"),
        "stopped\n",
        "rocklab got SIGTERM once"
    );
    assert_eq!(task.read("scontrol.txt"), "requeue 5_1\n");
}

#[test]
fn a_task_is_not_requeued_when_cancelled_or_out_of_requeues() {
    // Cancelled (e.g. `scancel`): rocklab's exit status is the task's, no requeue.
    let task = Task::new("CANCELLED", false);
    assert_eq!(task.run(0, true), Some(3));
    assert_eq!(task.read("rocklab.txt"), "stopped\n");
    assert_eq!(task.read("scontrol.txt"), "");
    // Requeued --max-requeue times already.
    let task = Task::new("RUNNING", false);
    assert_eq!(task.run(3, true), Some(3));
    assert_eq!(task.read("scontrol.txt"), "");
    // Finished normally.
    let task = Task::new("RUNNING", true);
    assert_eq!(task.run(0, false), Some(0));
    assert_eq!(task.read("scontrol.txt"), "");
}

/// Every value that reaches a job script, hostile: Slurm names are refused, paths that an
/// `#SBATCH` line cannot hold are refused, a study's free-text name is reduced to a job name,
/// and the words of the shell body are quoted so that bash reads them back unchanged.
#[test]
fn hostile_values_never_reach_a_script_as_code() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("d");
    for (flag, value) in [
        ("--partition", "p\n#SBATCH --wrap=evil"),
        ("--partition", "p;id"),
        ("--account", "a b;id"),
        ("--account", "$(id)"),
        ("--out", "/tmp/x\n#SBATCH --wrap=evil"),
        ("--out", "/tmp/my out"),
    ] {
        let mut args = vec!["slurm", "default", "--out", out.to_str().unwrap()];
        args.extend_from_slice(&[flag, value]);
        let o = rocklab(&args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{flag} {value:?}: {stderr}");
        assert!(
            stderr.contains(flag) || stderr.contains("Slurm name"),
            "{stderr}"
        );
    }
    // A study whose name is hostile: the directives stay the ones rocklab writes.
    let study = dir.path().join("evil study $(id).ron");
    let text = std::fs::read_to_string("studies/default.ron")
        .unwrap()
        .replacen(
            "name: \"default\"",
            "name: \"x\\n#SBATCH --wrap=evil $(id) `id`\"",
            1,
        );
    assert!(
        text.contains("--wrap=evil"),
        "the default study's name moved"
    );
    std::fs::write(&study, text).unwrap();
    let o = rocklab(&[
        "slurm",
        study.to_str().unwrap(),
        "--tasks",
        "2",
        "--partition",
        "short,long",
        "--account",
        "quake-lab.1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for script in ["array.sh", "merge.sh"] {
        let text = written(&out, script);
        let directives: Vec<&str> = text.lines().filter(|l| l.starts_with("#SBATCH")).collect();
        // Only rocklab's own directives, each one word after `#SBATCH`.
        let known = [
            "--job-name=rocklab-",
            "--cpus-per-task=",
            "--time=",
            "--partition=",
            "--account=",
            "--output=",
            "--chdir=",
            "--array=",
            "--requeue",
            "--open-mode=",
            "--signal=",
        ];
        for d in &directives {
            let word = d.strip_prefix("#SBATCH ").unwrap();
            assert!(known.iter().any(|k| word.starts_with(k)), "{d}\n{text}");
            assert!(!word.contains([' ', '$', '`', ';']), "{d}\n{text}");
        }
        assert!(
            directives.contains(&"#SBATCH --partition=short,long"),
            "{text}"
        );
        assert!(
            directives.contains(&"#SBATCH --account=quake-lab.1"),
            "{text}"
        );
        assert!(
            text.lines().all(|l| !l.starts_with("#SBATCH --wrap")),
            "{text}"
        );
        // The study path is one quoted word: bash reads it back as written.
        if script == "array.sh" {
            let line = text
                .lines()
                .find(|l| l.contains(" run ") && l.contains(" --out "))
                .unwrap();
            let word = line
                .split(" run ")
                .nth(1)
                .unwrap()
                .split(" --out")
                .next()
                .unwrap();
            let echo = Command::new("bash")
                .args(["-c", &format!("printf %s {word}")])
                .output()
                .unwrap();
            assert_eq!(
                String::from_utf8_lossy(&echo.stdout),
                std::fs::canonicalize(&study).unwrap().to_str().unwrap()
            );
        }
    }
}
