//! `rocklab slurm`: a study as a Slurm job array (task i runs `rocklab run --shard i/N` into one
//! output directory) plus a merge job that starts once every task has succeeded; `--submit`
//! hands both to sbatch. A task warned of its time limit stops cleanly, keeps its finished
//! scenes and requeues itself under the same job id, so the merge job keeps waiting for it.

use super::UsageError;
use super::run::load_study;
use anyhow::Context;
use clap::Args;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::AtomicBool;

/// Seconds before its time limit at which Slurm sends a task SIGTERM (`--signal=B:TERM@…`).
pub const STOP_WARNING_SECONDS: u64 = 60;
/// Slurm's default MaxArraySize is 1001 (indices 0–1000): the default sizing stays below it.
const MAX_DEFAULT_TASKS: usize = 1000;

/// Write (and with `--submit` submit) a Slurm job array for a study and its merge job.
#[derive(Args, Debug, Clone)]
pub struct SlurmArgs {
    /// Study file (RON), or `default` for the built-in study.
    pub study: String,
    /// Output directory of the shards and the merged results (default: out/<study name>).
    /// The scripts go to its `slurm/` folder, the tasks' logs to `slurm/logs/`.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Array tasks (shards). Default: from the scene count and a timed sample of scenes, so that
    /// a task needs about half of --time.
    #[arg(long)]
    pub tasks: Option<usize>,
    /// CPUs per task (rocklab's worker threads).
    #[arg(long, default_value_t = 1)]
    pub cpus_per_task: usize,
    /// Time limit per task: minutes, MM:SS, HH:MM:SS, D-HH, D-HH:MM or D-HH:MM:SS.
    #[arg(long, default_value = "01:00:00", value_parser = parse_time)]
    pub time: u64,
    /// Slurm partition(s): names of letters, digits, `_`, `-`, `.`, comma-separated.
    #[arg(long, value_parser = slurm_name)]
    pub partition: Option<String>,
    /// Slurm account: a name of letters, digits, `_`, `-`, `.`.
    #[arg(long, value_parser = slurm_name)]
    pub account: Option<String>,
    /// Times a task stopped before its time limit requeues itself to resume.
    #[arg(long, default_value_t = 3)]
    pub max_requeue: u32,
    /// Submit with sbatch (array, then the merge job with --dependency=afterok).
    #[arg(long)]
    pub submit: bool,
}

/// Everything the two scripts say; paths are absolute so the jobs run from anywhere.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    pub study_name: String,
    pub study_hash: String,
    pub scenes: usize,
    pub tasks: usize,
    pub cpus_per_task: usize,
    pub time_seconds: u64,
    pub partition: Option<String>,
    pub account: Option<String>,
    pub max_requeue: u32,
    /// The rocklab executable the tasks run.
    pub rocklab: PathBuf,
    /// The study argument of `rocklab run`: an absolute path, or `default`.
    pub study: String,
    pub out: PathBuf,
    /// Working directory of the jobs (where `rocklab slurm` ran).
    pub workdir: PathBuf,
}

/// Scenes of shard `i` of `tasks`: expansion indices i, i+N, i+2N, … below `scenes`.
pub fn shard_scenes(scenes: usize, tasks: usize, i: usize) -> usize {
    if i >= scenes {
        0
    } else {
        (scenes - i).div_ceil(tasks)
    }
}

/// Tasks for a study: enough that each needs about half its time limit at the estimated cost
/// per scene (leaving room for a loaded node), at most one per scene.
pub fn default_tasks(
    scenes: usize,
    seconds_per_scene: f64,
    cpus_per_task: usize,
    time_seconds: u64,
) -> usize {
    let budget = 0.5 * (time_seconds as f64) * cpus_per_task.max(1) as f64;
    let needed = (scenes as f64 * seconds_per_scene.max(0.0) / budget).ceil() as usize;
    needed.clamp(1, scenes.clamp(1, MAX_DEFAULT_TASKS))
}

/// Slurm's time formats to seconds.
pub fn parse_time(text: &str) -> Result<u64, String> {
    let bad = || {
        format!(
            "invalid time `{text}`: expected minutes, MM:SS, HH:MM:SS, D-HH, D-HH:MM or D-HH:MM:SS"
        )
    };
    let number = |s: &str| s.trim().parse::<u64>().map_err(|_| bad());
    let (days, rest) = match text.split_once('-') {
        Some((d, rest)) => (Some(number(d)?), rest),
        None => (None, text),
    };
    let parts = rest.split(':').map(number).collect::<Result<Vec<_>, _>>()?;
    let seconds = match (days, parts.as_slice()) {
        (None, [m]) => m * 60,
        (None, [m, s]) => m * 60 + s,
        (None, [h, m, s]) => h * 3600 + m * 60 + s,
        (Some(d), [h]) => d * 86400 + h * 3600,
        (Some(d), [h, m]) => d * 86400 + h * 3600 + m * 60,
        (Some(d), [h, m, s]) => d * 86400 + h * 3600 + m * 60 + s,
        _ => return Err(bad()),
    };
    if seconds == 0 {
        return Err(format!("invalid time `{text}`: must be positive"));
    }
    Ok(seconds)
}

/// Seconds as Slurm's `[D-]HH:MM:SS`.
pub fn format_time(seconds: u64) -> String {
    let (d, h, m, s) = (
        seconds / 86400,
        seconds % 86400 / 3600,
        seconds % 3600 / 60,
        seconds % 60,
    );
    if d > 0 {
        format!("{d}-{h:02}:{m:02}:{s:02}")
    } else {
        format!("{h:02}:{m:02}:{s:02}")
    }
}

/// A Slurm partition or account name, checked before it goes into an `#SBATCH` line (those
/// lines are not shell words and cannot be quoted: a newline would add a directive).
pub fn slurm_name(text: &str) -> Result<String, String> {
    let ok = |c: char| c.is_ascii_alphanumeric() || "_-.,".contains(c);
    if !text.is_empty() && text.len() <= 64 && text.chars().all(ok) {
        Ok(text.to_string())
    } else {
        Err(format!(
            "{:?} is not a Slurm name: use letters, digits, `_`, `-` and `.` (partitions may be \
             a comma-separated list), at most 64 characters",
            text
        ))
    }
}

/// The study's name as a Slurm job name and a comment: anything but letters, digits and
/// `_-.` becomes `_` (a study name is free text; a newline in it must not reach a script).
fn job_word(text: &str) -> String {
    let word: String = text
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "_-.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .take(64)
        .collect();
    if word.is_empty() {
        "study".into()
    } else {
        word
    }
}

/// A path in an `#SBATCH` line: sbatch splits these at white space and reads no shell
/// quoting, so a path that holds white space, a quote or a control character is refused
/// (`what` names the flag or place it came from).
fn sbatch_path(path: &Path, what: &str) -> anyhow::Result<String> {
    let text = path.display().to_string();
    if text
        .chars()
        .any(|c| c.is_whitespace() || c.is_control() || "\"'\\".contains(c))
    {
        return Err(UsageError::new(format!(
            "{what} {text:?} holds white space, a quote or a control character, which an \
             #SBATCH line cannot hold; choose a path of plain characters"
        ))
        .into());
    }
    Ok(text)
}

/// A word for bash: single-quoted unless it is plainly safe.
fn quote(text: &str) -> String {
    let safe = |c: char| c.is_ascii_alphanumeric() || "/._-+=:,@".contains(c);
    if !text.is_empty() && text.chars().all(safe) {
        text.to_string()
    } else {
        format!("'{}'", text.replace('\'', r"'\''"))
    }
}

impl Plan {
    pub fn scripts_dir(&self) -> PathBuf {
        self.out.join("slurm")
    }

    pub fn logs_dir(&self) -> PathBuf {
        self.scripts_dir().join("logs")
    }

    /// `4 tasks of 150 scenes`, `7 tasks of 85–86 scenes`.
    pub fn tasks_text(&self) -> String {
        let (fewest, most) = self.scenes_per_task();
        let tasks = match self.tasks {
            1 => "1 task".to_string(),
            n => format!("{n} tasks"),
        };
        match (fewest == most, most) {
            (true, 1) => format!("{tasks} of 1 scene"),
            (true, n) => format!("{tasks} of {n} scenes"),
            (false, _) => format!("{tasks} of {fewest}–{most} scenes"),
        }
    }

    /// (fewest, most) scenes per task.
    pub fn scenes_per_task(&self) -> (usize, usize) {
        (
            shard_scenes(self.scenes, self.tasks, self.tasks - 1),
            shard_scenes(self.scenes, self.tasks, 0),
        )
    }

    fn common_header(&self, out: &mut String, job_name: &str, log: &str, cpus: usize) {
        let lines = [
            format!("--job-name={job_name}"),
            format!("--cpus-per-task={cpus}"),
            format!("--time={}", format_time(self.time_seconds)),
        ];
        for line in lines {
            let _ = writeln!(out, "#SBATCH {line}");
        }
        // Checked by `slurm_name` (and again here: a Plan may be built by hand).
        for (flag, name) in [("partition", &self.partition), ("account", &self.account)] {
            if let Some(name) = name.as_deref().and_then(|n| slurm_name(n).ok()) {
                let _ = writeln!(out, "#SBATCH --{flag}={name}");
            }
        }
        // sbatch expands `%j`, `%A`, … in --output: a `%` of the folder's own name is
        // written `%%`; the log's file name keeps its patterns.
        let _ = writeln!(
            out,
            "#SBATCH --output={}/{log}",
            self.logs_dir().display().to_string().replace('%', "%%")
        );
        let _ = writeln!(out, "#SBATCH --chdir={}", self.workdir.display());
    }

    /// The job array: task i runs shard i/N; on SIGTERM it stops, then requeues itself.
    pub fn array_script(&self) -> String {
        let n = self.tasks;
        let mut s = String::from("#!/bin/bash\n");
        let _ = writeln!(
            s,
            "# Written by `rocklab slurm` for study {} (hash {}): {} scenes in {}.",
            job_word(&self.study_name),
            job_word(&self.study_hash),
            self.scenes,
            self.tasks_text()
        );
        s.push_str(
            "# Task i runs shard i/N into the output directory; rerun, it reuses the scenes it finished.\n",
        );
        self.common_header(
            &mut s,
            &format!("rocklab-{}", job_word(&self.study_name)),
            "array-%A_%a.log",
            self.cpus_per_task,
        );
        let _ = writeln!(s, "#SBATCH --array=0-{}", n - 1);
        s.push_str("#SBATCH --requeue\n#SBATCH --open-mode=append\n");
        let _ = writeln!(s, "#SBATCH --signal=B:TERM@{STOP_WARNING_SECONDS}");
        let _ = write!(
            s,
            r#"
task="${{SLURM_ARRAY_JOB_ID}}_${{SLURM_ARRAY_TASK_ID}}"
restarts="${{SLURM_RESTART_COUNT:-0}}"
echo "rocklab: task $task, shard ${{SLURM_ARRAY_TASK_ID}}/{n}, restart $restarts, on $(hostname) at $(date -Is)"
# rocklab runs as a child so that this shell can requeue the task once rocklab has stopped.
# SIGTERM ({STOP_WARNING_SECONDS} s before the time limit, or `scancel --batch --signal=TERM`) is passed
# on to rocklab, which stops starting scenes; run again, it resumes from the shard's journal.
stopped=0
{rocklab} run {study} --out {out} --quiet \
    --jobs "${{SLURM_CPUS_PER_TASK:-1}}" --shard "${{SLURM_ARRAY_TASK_ID}}/{n}" &
pid=$!
trap 'stopped=1; kill -TERM "$pid" 2>/dev/null' TERM
wait "$pid"
# A trapped signal ends `wait` early: wait until rocklab has exited, then take its own status.
while kill -0 "$pid" 2>/dev/null; do wait "$pid"; done
wait "$pid"
status=$?
if [ "$stopped" = 1 ]; then
    state=$(squeue -h -j "$task" -o %T 2>/dev/null || true)
    # Requeue only a task that is still running: a cancelled or timed-out task stays ended.
    if [ "$state" = RUNNING ] && [ "$restarts" -lt {max_requeue} ]; then
        echo "rocklab: task $task stopped by SIGTERM (exit $status); requeueing it to resume its shard"
        if scontrol requeue "$task"; then
            sleep 300 # Slurm ends this shell as it requeues the task
            exit 0
        fi
    fi
    echo "rocklab: task $task stopped by SIGTERM (exit $status), not requeued (state $state, restart $restarts of {max_requeue})"
fi
exit "$status"
"#,
            rocklab = quote(&self.rocklab.display().to_string()),
            study = quote(&self.study),
            out = quote(&self.out.display().to_string()),
            max_requeue = self.max_requeue,
        );
        s
    }

    /// The merge job: every shard file present, then `rocklab merge`.
    pub fn merge_script(&self) -> String {
        let n = self.tasks;
        let mut s = String::from("#!/bin/bash\n");
        let _ = writeln!(
            s,
            "# Written by `rocklab slurm` for study {} (hash {}): merges the {n} shards of the array.",
            job_word(&self.study_name),
            job_word(&self.study_hash)
        );
        self.common_header(
            &mut s,
            &format!("rocklab-{}-merge", job_word(&self.study_name)),
            "merge-%j.log",
            1,
        );
        let out = quote(&self.out.display().to_string());
        let _ = write!(
            s,
            r#"
set -euo pipefail
shopt -s nullglob
shards=({out}/results.shard-*-of-{n}.json)
if [ "${{#shards[@]}}" -ne {n} ]; then
    echo "rocklab: found ${{#shards[@]}} of {n} shard files in "{out}"; submit the array again to finish them" >&2
    exit 1
fi
exec {rocklab} merge "${{shards[@]}}" --out {out}
"#,
            rocklab = quote(&self.rocklab.display().to_string()),
        );
        s
    }
}

fn absolute(path: &Path) -> anyhow::Result<PathBuf> {
    Ok(if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir()?.join(path)
    })
}

pub fn run(args: &SlurmArgs) -> anyhow::Result<()> {
    let study = load_study(&args.study)?;
    super::run::refuse_adaptive_shards(&study, "a Slurm job array")?;
    super::run::refuse_design_shards(&study, "a Slurm job array")?;
    let points = study.expand().map_err(|e| UsageError::new(e.to_string()))?;
    if points.is_empty() {
        return Err(UsageError::new("the study has no scenes").into());
    }
    if args.cpus_per_task == 0 {
        return Err(UsageError::new("--cpus-per-task must be at least 1").into());
    }
    if args.time < 3 * STOP_WARNING_SECONDS {
        return Err(UsageError::new(format!(
            "--time {} is too short: tasks are told to stop {STOP_WARNING_SECONDS} s before their limit; give at least {}",
            format_time(args.time),
            format_time(3 * STOP_WARNING_SECONDS)
        ))
        .into());
    }
    let tasks = match args.tasks {
        Some(0) => return Err(UsageError::new("--tasks must be at least 1").into()),
        Some(t) if t > points.len() => {
            eprintln!(
                "note: {} scenes: {} tasks instead of {t}",
                points.len(),
                points.len()
            );
            points.len()
        }
        Some(t) => t,
        None => {
            let cost =
                crate::sweep::seconds_per_scene(&points, &AtomicBool::new(false)).unwrap_or(0.0);
            let tasks = default_tasks(points.len(), cost, args.cpus_per_task, args.time);
            eprintln!(
                "sizing: ~{:.1} ms per scene (timed on a sample) → {tasks} task(s) of about {} each (--tasks to choose)",
                cost * 1e3,
                format_time(
                    (cost * shard_scenes(points.len(), tasks, 0) as f64).ceil() as u64
                        / args.cpus_per_task as u64
                )
            );
            tasks
        }
    };
    let study_arg = if args.study == "default" && !Path::new("default").exists() {
        "default".to_string()
    } else {
        let path = Path::new(&args.study);
        path.canonicalize()
            .with_context(|| format!("cannot resolve {}", path.display()))?
            .display()
            .to_string()
    };
    let out = absolute(&match &args.out {
        Some(out) => out.clone(),
        None => super::run::default_out(&study.name)?,
    })?;
    let plan = Plan {
        study_name: study.name.clone(),
        study_hash: study.hash(),
        scenes: points.len(),
        tasks,
        cpus_per_task: args.cpus_per_task,
        time_seconds: args.time,
        partition: args.partition.clone(),
        account: args.account.clone(),
        max_requeue: args.max_requeue,
        rocklab: std::env::current_exe().context("cannot locate the rocklab executable")?,
        study: study_arg,
        out,
        workdir: std::env::current_dir()?,
    };
    sbatch_path(&plan.logs_dir(), "--out")?;
    sbatch_path(&plan.workdir, "the working directory")?;
    let logs = plan.logs_dir();
    std::fs::create_dir_all(&logs).with_context(|| format!("cannot create {}", logs.display()))?;
    let array = plan.scripts_dir().join("array.sh");
    let merge = plan.scripts_dir().join("merge.sh");
    crate::report::write_atomic(&array, plan.array_script().as_bytes())?;
    crate::report::write_atomic(&merge, plan.merge_script().as_bytes())?;
    println!(
        "study {} (hash {}): {} scenes in {}, {} CPU(s) and {} each",
        plan.study_name,
        plan.study_hash,
        plan.scenes,
        plan.tasks_text(),
        plan.cpus_per_task,
        format_time(plan.time_seconds)
    );
    println!(
        "wrote {}  (job array 0-{}: rocklab run --shard i/{tasks})",
        array.display(),
        tasks - 1
    );
    println!(
        "wrote {}  (rocklab merge, once every task has succeeded)",
        merge.display()
    );
    let results = plan.out.join("results.json");
    if !args.submit {
        println!(
            "submit:  id=$(sbatch --parsable {}) && sbatch --dependency=afterok:$id {}",
            quote(&array.display().to_string()),
            quote(&merge.display().to_string())
        );
        println!("         (or run this command again with --submit)");
        println!("results: {}", results.display());
        return Ok(());
    }
    let array_id = sbatch(&[], &array)?;
    let merge_id = sbatch(&[format!("--dependency=afterok:{array_id}")], &merge)?;
    println!("submitted: array job {array_id}, merge job {merge_id}");
    println!("follow:  squeue -j {array_id},{merge_id}");
    println!(
        "         sacct -j {array_id},{merge_id} --format=JobID,JobName,State,Elapsed,ExitCode"
    );
    println!(
        "         {} status {}",
        quote(&plan.rocklab.display().to_string()),
        quote(&plan.out.display().to_string())
    );
    println!("logs:    {}", logs.display());
    println!(
        "results: {} once job {merge_id} has finished",
        results.display()
    );
    Ok(())
}

/// Submit a script; the job id sbatch printed.
fn sbatch(flags: &[String], script: &Path) -> anyhow::Result<String> {
    let output = Command::new("sbatch")
        .arg("--parsable")
        .args(flags)
        .arg(script)
        .output()
        .map_err(|e| {
            anyhow::anyhow!(
                "cannot run sbatch ({e}); is this a Slurm login node? The scripts are written: submit them by hand"
            )
        })?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    if !output.status.success() {
        anyhow::bail!(
            "sbatch {} failed ({}): {}",
            script.display(),
            output.status,
            String::from_utf8_lossy(&output.stderr).trim()
        );
    }
    // `--parsable` prints `id` or `id;cluster`.
    let id = stdout
        .trim()
        .split(';')
        .next()
        .unwrap_or_default()
        .to_string();
    if id.is_empty() || !id.chars().all(|c| c.is_ascii_digit()) {
        anyhow::bail!("sbatch printed no job id: {:?}", stdout.trim());
    }
    Ok(id)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_in_slurm_formats() {
        assert_eq!(parse_time("90"), Ok(5400));
        assert_eq!(parse_time("5:30"), Ok(330));
        assert_eq!(parse_time("01:00:00"), Ok(3600));
        assert_eq!(parse_time("2-12"), Ok(2 * 86400 + 12 * 3600));
        assert_eq!(parse_time("1-00:30"), Ok(86400 + 1800));
        assert_eq!(parse_time("1-02:03:04"), Ok(86400 + 7384));
        for bad in ["", "1:2:3:4", "x", "1-", "-5", "0", "1.5"] {
            assert!(parse_time(bad).is_err(), "{bad}");
        }
        for s in [5400, 330, 86400 + 7384, 59] {
            assert_eq!(parse_time(&format_time(s)), Ok(s));
        }
        assert_eq!(format_time(86400 + 7384), "1-02:03:04");
    }

    #[test]
    fn shards_cover_every_scene_once() {
        for (scenes, tasks) in [(600, 4), (601, 4), (7, 3), (3, 3), (1, 1), (1000, 7)] {
            let sizes: Vec<usize> = (0..tasks).map(|i| shard_scenes(scenes, tasks, i)).collect();
            assert_eq!(sizes.iter().sum::<usize>(), scenes, "{scenes}/{tasks}");
            let (min, max) = (sizes.iter().min().unwrap(), sizes.iter().max().unwrap());
            assert!(max - min <= 1, "{sizes:?}");
            // Shard i holds the indices ≡ i (mod N).
            for (i, &n) in sizes.iter().enumerate() {
                assert_eq!(n, (0..scenes).filter(|k| k % tasks == i).count());
            }
        }
    }

    #[test]
    fn default_tasks_fit_half_the_time_limit() {
        // 6000 scenes × 0.1 s = 600 CPU-s; 1 CPU, 10 min limit → 300 s budget → 2 tasks.
        assert_eq!(default_tasks(6000, 0.1, 1, 600), 2);
        assert_eq!(default_tasks(6000, 0.1, 4, 600), 1);
        assert_eq!(default_tasks(6001, 0.1, 1, 600), 3);
        // Never more tasks than scenes, never more than Slurm's default array size.
        assert_eq!(default_tasks(5, 1000.0, 1, 600), 5);
        assert_eq!(default_tasks(1_000_000, 1.0, 1, 600), MAX_DEFAULT_TASKS);
        assert_eq!(default_tasks(10, 0.0, 1, 600), 1);
    }

    #[test]
    fn quoting_for_bash() {
        assert_eq!(quote("/a/b-c_d.ron"), "/a/b-c_d.ron");
        assert_eq!(quote("/my studies/x.ron"), "'/my studies/x.ron'");
        assert_eq!(quote("it's"), r"'it'\''s'");
    }
}
