//! An output directory owned by one run: checked writable before the first scene, locked,
//! and resumed from its journal. Results of another study there (an edited study, most often)
//! are set aside and every finished scene of theirs whose scene is unchanged is reused: a
//! scene's key is a hash of the scene and its solver settings, so a scene is a pure function
//! of its key whatever else the study holds.
//!
//! File names per results set (one per shard, so the tasks of a job array share a directory):
//! `results.json` / `results.shard-i-of-N.json` (final results), the same stem with
//! `.journal` (the journal) and `.lock` (the lock).

use super::journal::{self, Journal, JournalHeader};
use super::{SceneResult, build_id};
use crate::error::Context;
use crate::study::Study;
use std::collections::HashMap;
use std::fs::File;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

/// Why an output directory cannot be used; said before any scene runs.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error(
        "another rocklab{pid} is writing {path}; wait for it to finish (`rocklab status {dir}`) or use another --out"
    )]
    Locked {
        path: String,
        dir: String,
        pid: String,
    },
    #[error("cannot write in the output directory {dir}: {reason}; nothing was run")]
    NotWritable { dir: String, reason: String },
    #[error(
        "the study's name {name:?} would put its results outside {root} (an absolute path or \
         `..`); give the study a plain name, or choose the directory with --out"
    )]
    NameLeavesRoot { name: String, root: String },
}

/// Where a study's results go when no `--out` is given: `root/<name>`, the name made one path
/// component (`a/b` is `a_b`). A name that is absolute or climbs with `..` is refused rather
/// than renamed, so that `run`, `slurm` (and so its `status` and `merge` lines) and the
/// workbench never disagree about it and never write outside `root`.
pub fn default_out_dir(root: &Path, study_name: &str) -> Result<PathBuf, OutputError> {
    let climbs = study_name
        .split(['/', '\\'])
        .any(|part| part.trim() == "..");
    let absolute = Path::new(study_name).has_root() || study_name.starts_with(['/', '\\']);
    if climbs || absolute {
        return Err(OutputError::NameLeavesRoot {
            name: study_name.to_string(),
            root: root.display().to_string(),
        });
    }
    Ok(root.join(crate::fsutil::single_component(study_name)))
}

impl From<OutputError> for crate::error::Error {
    fn from(e: OutputError) -> Self {
        crate::error::Error::Other(Box::new(e))
    }
}

pub fn results_name(shard: Option<(usize, usize)>) -> String {
    match shard {
        Some((i, n)) => format!("results.shard-{i}-of-{n}.json"),
        None => "results.json".into(),
    }
}

/// The journal that goes with a results file.
pub fn journal_path(results: &Path) -> PathBuf {
    results.with_extension("journal")
}

pub fn lock_path(results: &Path) -> PathBuf {
    results.with_extension("lock")
}

/// An exclusive lock on one results set, held while the process lives.
///
/// `flock`-style locks via std's `File::try_lock` (no crate needed since Rust 1.89): the
/// kernel drops them when the holder dies however it dies, so a lock can never go stale;
/// the file keeps the holder's pid only to name it in the message. The file is never
/// removed: unlinking a lock file lets two processes lock two different inodes.
#[derive(Debug)]
pub struct OutputLock {
    _file: File,
}

impl OutputLock {
    pub fn acquire(results: &Path) -> crate::error::Result<OutputLock> {
        let path = lock_path(results);
        let mut file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .with_context(|| format!("cannot create the lock file {}", path.display()))?;
        match file.try_lock() {
            Ok(()) => {}
            Err(std::fs::TryLockError::WouldBlock) => {
                let mut pid = String::new();
                let _ = file.read_to_string(&mut pid);
                let pid = pid.trim();
                return Err(OutputError::Locked {
                    path: results.display().to_string(),
                    dir: crate::fsutil::parent_dir(results).display().to_string(),
                    pid: if pid.is_empty() {
                        String::new()
                    } else {
                        format!(" (pid {pid})")
                    },
                }
                .into());
            }
            Err(std::fs::TryLockError::Error(e)) => {
                return Err(e).with_context(|| format!("cannot lock {}", path.display()));
            }
        }
        file.set_len(0)?;
        writeln!(file, "{}", std::process::id())?;
        Ok(OutputLock { _file: file })
    }

    /// Whether some process holds the lock of `results` now (for `status`), with its pid.
    pub fn holder(results: &Path) -> Option<String> {
        let mut file = File::open(lock_path(results)).ok()?;
        match file.try_lock_shared() {
            Ok(()) => None,
            Err(_) => {
                let mut pid = String::new();
                let _ = file.read_to_string(&mut pid);
                Some(pid.trim().to_string())
            }
        }
    }
}

#[derive(Clone, Copy, Debug, Default)]
pub struct OpenOptions {
    /// Rerun every scene; the previous results stay in place until the new run has finished.
    pub fresh: bool,
}

/// An output directory ready for a run.
#[derive(Debug)]
pub struct Output {
    pub results_path: PathBuf,
    pub journal: Journal,
    /// Finished scenes of previous runs of this study (already in the journal), by key.
    pub reuse: HashMap<String, Result<SceneResult, String>>,
    /// Finished scenes of another study's results found here (the study was edited), by key:
    /// those whose key the study still has are copied into the journal and reused.
    pub adopted: HashMap<String, SceneResult>,
    /// After [`super::run_into`]: scenes reused instead of computed (journal and adopted).
    pub reused: usize,
    /// What was found and decided, for the user (resumed, discarded, set aside).
    pub notes: Vec<String>,
    /// `--fresh` with a previous results file: it is not replaced unless the run completes.
    pub keep_previous_results: bool,
    /// A previous journal moved aside; removed once the new run has finished.
    pub set_aside: Option<PathBuf>,
    _lock: OutputLock,
}

/// Bytes a scene costs on disk, journal and results file together (measured ≈ 2.5 KB on the
/// shipped studies, rounded up).
const BYTES_PER_SCENE: u64 = 4096;

/// Prepare `dir` for `study`'s run of `total` scenes (of shard `shard`): create it, check it
/// is writable and has room, lock the results set, decide what to reuse.
pub fn open_output(
    dir: &Path,
    shard: Option<(usize, usize)>,
    study: &Study,
    total: usize,
    opts: OpenOptions,
) -> crate::error::Result<Output> {
    let not_writable = |reason: String| OutputError::NotWritable {
        dir: dir.display().to_string(),
        reason,
    };
    std::fs::create_dir_all(dir).map_err(|e| not_writable(e.to_string()))?;
    let results_path = dir.join(results_name(shard));
    let journal_path = journal_path(&results_path);
    for path in [&results_path, &journal_path] {
        if let Ok(meta) = std::fs::metadata(path)
            && !meta.is_file()
        {
            return Err(not_writable(format!("{} is not a regular file", path.display())).into());
        }
    }
    probe_writable(dir).map_err(|e| not_writable(e.to_string()))?;
    if let Ok(free) = fs4::available_space(dir) {
        let needed = total as u64 * BYTES_PER_SCENE;
        if free < needed {
            return Err(not_writable(format!(
                "{total} scenes need about {} MB, {} MB are free",
                needed.div_ceil(1 << 20),
                free / (1 << 20)
            ))
            .into());
        }
    }
    let lock = OutputLock::acquire(&results_path)?;
    let hash = study.hash();
    let header = JournalHeader {
        journal: journal::JOURNAL_FORMAT,
        study_hash: hash.clone(),
        build: build_id().to_string(),
        shard,
        total,
        study: Some(study.clone()),
    };
    let mut notes = Vec::new();
    let mut adopted = HashMap::new();
    if results_path.exists()
        && let Ok((other_hash, name)) = super::store::results_identity(&results_path)
        && other_hash != hash
    {
        let found = match super::load_results(&results_path) {
            _ if opts.fresh => "not reused: --fresh".into(),
            Ok(previous) if super::reusable(&previous) => {
                let n = adopted.len();
                adopted.extend(
                    previous
                        .outcomes
                        .into_iter()
                        .filter_map(|o| Some((o.point.key, o.result.ok()?))),
                );
                format!("{} finished scenes", adopted.len() - n)
            }
            Ok(_) => "scenes of another build of rocklab (not reused)".into(),
            Err(e) => format!("nothing readable ({e:#})"),
        };
        let aside = free_aside(&results_path);
        std::fs::rename(&results_path, &aside)
            .with_context(|| format!("cannot move {} aside", results_path.display()))?;
        notes.push(format!(
            "{} held results of {} ({found}), kept as {}",
            results_path.display(),
            other_name(name.as_deref(), &study.name),
            aside.display()
        ));
    }
    // The journal is the record of the last run; the results file is used only without one
    // (written by a build from before journals).
    let mut resume_journal = false;
    let mut set_aside = None;
    let previous_header = journal_path
        .exists()
        .then(|| journal::read_header(&journal_path));
    match &previous_header {
        // Another study's journal (set aside below): its finished scenes are adopted if this
        // build wrote them.
        Some(Ok(h))
            if h.study_hash != hash
                && !opts.fresh
                && h.build == header.build
                && h.build != "unknown" =>
        {
            let contents = journal::read_journal(&journal_path, false)?;
            let n = contents.entries.len();
            adopted.extend(
                contents
                    .entries
                    .into_values()
                    .filter_map(|e| Some((e.key, e.result.ok()?))),
            );
            let name = h.study.as_ref().map(|s| s.name.as_str());
            notes.push(format!(
                "{} is the journal of {} ({n} scenes); the unchanged scenes are reused",
                journal_path.display(),
                other_name(name, &study.name)
            ));
        }
        Some(Ok(h)) if h.study_hash == hash && h.shard == shard && !opts.fresh => {
            if h.build == header.build && h.build != "unknown" {
                resume_journal = true;
            } else {
                notes.push(format!(
                    "{} was written by another build of rocklab; rerunning every scene",
                    journal_path.display()
                ));
            }
        }
        Some(Err(e)) => notes.push(format!("discarded an unreadable journal: {e:#}")),
        _ => {}
    }
    if previous_header.is_some() && !resume_journal {
        let aside = journal_path.with_extension("journal.previous");
        std::fs::rename(&journal_path, &aside)
            .with_context(|| format!("cannot move {} aside", journal_path.display()))?;
        if opts.fresh {
            notes.push(format!(
                "--fresh: the previous journal is kept as {} until this run finishes",
                aside.display()
            ));
        }
        set_aside = Some(aside);
    }

    let mut reuse = HashMap::new();
    let journal = if resume_journal {
        // Continuing a run that set an older journal aside (--fresh, then stopped): that
        // one goes once this run completes.
        let previous = journal_path.with_extension("journal.previous");
        set_aside = previous.exists().then_some(previous);
        let contents = journal::read_journal(&journal_path, true)?;
        if contents.damaged_lines > 0 {
            notes.push(format!(
                "{}: {} damaged line(s) skipped (a write cut short); those scenes rerun",
                journal_path.display(),
                contents.damaged_lines
            ));
        }
        let (ok, failed) =
            contents
                .entries
                .values()
                .fold((0, 0), |(ok, failed), e| match e.result {
                    Ok(_) => (ok + 1, failed),
                    Err(_) => (ok, failed + 1),
                });
        notes.push(format!(
            "resuming from {}: {ok} finished scenes reused{}",
            journal_path.display(),
            if failed > 0 {
                format!(", {failed} failed ones rerun")
            } else {
                String::new()
            }
        ));
        // Failures are not reused: they may come from the environment (a missing record
        // file) and rerunning them is cheap.
        reuse.extend(
            contents
                .entries
                .into_iter()
                .filter(|(_, e)| e.result.is_ok())
                .map(|(k, e)| (k, e.result)),
        );
        Journal::append_to(&journal_path)?
    } else {
        let journal = Journal::create(&journal_path, &header)?;
        if previous_header.is_none() && !opts.fresh && results_path.exists() {
            match super::load_results(&results_path) {
                Ok(previous) if previous.study_hash == hash && super::reusable(&previous) => {
                    // Copied into the journal, which is from now on the record.
                    for o in previous.outcomes.into_iter().filter(|o| o.result.is_ok()) {
                        journal.append(o.point.index, &o.point.key, &o.result);
                        reuse.insert(o.point.key, o.result);
                    }
                    notes.push(format!(
                        "reusing {} finished scenes of {}",
                        reuse.len(),
                        results_path.display()
                    ));
                }
                Ok(_) => notes.push(format!(
                    "{} was written by another build of rocklab; rerunning every scene",
                    results_path.display()
                )),
                Err(e) => notes.push(format!(
                    "discarded {} (it cannot be read: {e:#}); rerunning every scene",
                    results_path.display()
                )),
            }
        }
        journal
    };
    Ok(Output {
        adopted,
        reused: 0,
        keep_previous_results: opts.fresh && results_path.exists(),
        results_path,
        journal,
        reuse,
        notes,
        set_aside,
        _lock: lock,
    })
}

/// How the notes name the study whose results were found: the same name is this study
/// before an edit.
fn other_name(name: Option<&str>, this: &str) -> String {
    match name {
        Some(n) if n == this => format!("an earlier version of '{n}'"),
        Some(n) => format!("study '{n}'"),
        None => "an unnamed study".into(),
    }
}

/// Create, write and sync a small file: catches a read-only or full file system, a missing
/// permission, before any scene runs.
fn probe_writable(dir: &Path) -> std::io::Result<()> {
    let mut probe = tempfile::Builder::new()
        .prefix(".rocklab-probe")
        .tempfile_in(dir)?;
    probe.write_all(&[0u8; 4096])?;
    probe.as_file().sync_all()
}

/// Where results set aside by `--force` go: `results.json.previous`, or the first free
/// `results.json.previous.N` (N ≥ 2) if that is taken, so that no set-aside results are ever
/// overwritten by a later `--force`.
fn free_aside(results: &Path) -> PathBuf {
    let first = results.with_extension("json.previous");
    if !first.exists() {
        return first;
    }
    (2..)
        .map(|n| results.with_extension(format!("json.previous.{n}")))
        .find(|p| !p.exists())
        .expect("some number is free")
}
