//! The results journal: every finished scene appended to a file in the output directory as it
//! completes, so a stop of any kind (signal, kill, out-of-memory, lost session, power loss)
//! loses at most the scenes in flight.
//!
//! Format: JSON lines. The first line is a [`JournalHeader`] (which study, build and shard the
//! lines belong to); every further line is one scene `{"index", "key", "result"}`. Why JSON
//! lines rather than an embedded database: the write pattern is pure append (one writer, no
//! updates, no queries), a line is written with one `write` call to an `O_APPEND` file (in the
//! kernel's hands at once, so SIGKILL and OOM kills cannot lose it), a torn last line after a
//! power loss is detectable and cut off, the records are the same serde types results.json
//! uses, and the file stays readable with `head`/`jq` on a cluster login node. Scene data
//! (the expanded point) is not repeated: the study in the header re-expands to the points.
//!
//! Every scene line carries a checksum of itself (`{"sum":"…","index":…}`: the first 16 hex
//! digits of the SHA-256 of the line from its `"index"` on, with the leading `{`), so a line
//! changed on disk (a flipped bit, an edit) is found, reported and its scene recomputed, never
//! reused; the line stays one JSON object for `jq`.
//!
//! Durability against power loss: the data is synced at most once a second and on close, so
//! a power cut loses at most the last second of scenes; a sync per scene would cost a disk
//! flush per scene.

use super::{SceneOutcome, SweepResults};
use crate::error::Context;
use crate::sim::SceneResult;
use crate::study::{Study, StudyKind};
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::fs::File;
use std::io::{BufRead, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The journal format version (2: scene lines carry a checksum).
pub const JOURNAL_FORMAT: u32 = 2;

/// The start of a checked scene line, before its checksum.
const SUM_PREFIX: &[u8] = b"{\"sum\":\"";
/// Hex digits of a line's checksum.
const SUM_DIGITS: usize = 16;

/// The checksum of a scene line's body (`{"index":…}`).
fn checksum(body: &[u8]) -> String {
    use sha2::{Digest, Sha256};
    let digest = Sha256::digest(body);
    digest[..SUM_DIGITS / 2]
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// A scene entry's JSON as a checked line: `{"sum":"…",` then the body after its `{`.
fn checked_line(body: &[u8]) -> Vec<u8> {
    let mut line = Vec::with_capacity(body.len() + SUM_PREFIX.len() + SUM_DIGITS + 3);
    line.extend_from_slice(SUM_PREFIX);
    line.extend_from_slice(checksum(body).as_bytes());
    line.extend_from_slice(b"\",");
    line.extend_from_slice(&body[1..]);
    line.push(b'\n');
    line
}

/// Whether a scene line (newline included or not) matches its checksum.
fn line_is_intact(line: &[u8]) -> bool {
    let line = line.strip_suffix(b"\n").unwrap_or(line);
    let Some(rest) = line.strip_prefix(SUM_PREFIX) else {
        return false;
    };
    if rest.len() < SUM_DIGITS + 2 || &rest[SUM_DIGITS..SUM_DIGITS + 2] != b"\"," {
        return false;
    }
    let mut body = Vec::with_capacity(rest.len() - SUM_DIGITS - 1);
    body.push(b'{');
    body.extend_from_slice(&rest[SUM_DIGITS + 2..]);
    checksum(&body).as_bytes() == &rest[..SUM_DIGITS]
}

/// What the scene lines of a journal belong to.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JournalHeader {
    pub journal: u32,
    pub study_hash: String,
    pub build: String,
    pub shard: Option<(usize, usize)>,
    /// Scenes this run (this shard) has to go through.
    pub total: usize,
    pub study: Option<Study>,
}

/// One finished scene, as written.
#[derive(Serialize)]
struct EntryOut<'a> {
    index: usize,
    key: &'a str,
    result: &'a Result<SceneResult, String>,
}

/// One finished scene, as read back.
#[derive(Deserialize)]
pub struct Entry {
    pub index: usize,
    pub key: String,
    pub result: Result<SceneResult, String>,
}

/// A journal open for appending. Shared by the sweep's worker threads.
#[derive(Debug)]
pub struct Journal {
    path: PathBuf,
    file: Mutex<Appender>,
}

#[derive(Debug)]
struct Appender {
    file: File,
    last_sync: Instant,
    /// The first write error; later appends are refused so the sweep stops.
    failure: Option<String>,
}

impl Journal {
    /// Start a new journal at `path` (replacing any file there) with its header.
    pub fn create(path: &Path, header: &JournalHeader) -> crate::error::Result<Journal> {
        let mut line = serde_json::to_vec(header)?;
        line.push(b'\n');
        let mut file = File::create(path)
            .with_context(|| format!("cannot create the journal {}", path.display()))?;
        file.write_all(&line)
            .and_then(|()| file.sync_all())
            .with_context(|| format!("cannot write the journal {}", path.display()))?;
        crate::fsutil::sync_dir(crate::fsutil::parent_dir(path));
        Self::append_to(path)
    }

    /// Continue an existing journal (after [`read_journal`] checked it and cut a torn tail).
    pub fn append_to(path: &Path) -> crate::error::Result<Journal> {
        let file = std::fs::OpenOptions::new()
            .append(true)
            .open(path)
            .with_context(|| format!("cannot open the journal {}", path.display()))?;
        Ok(Journal {
            path: path.to_path_buf(),
            file: Mutex::new(Appender {
                file,
                last_sync: Instant::now(),
                failure: None,
            }),
        })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Append one finished scene. Returns false (and remembers why) if it could not be
    /// written: the sweep then stops starting scenes.
    pub fn append(&self, index: usize, key: &str, result: &Result<SceneResult, String>) -> bool {
        // Serialise outside the lock: workers only queue for the write itself.
        let line = serde_json::to_vec(&EntryOut { index, key, result }).map(|b| checked_line(&b));
        let Ok(mut appender) = self.file.lock() else {
            return false;
        };
        if appender.failure.is_some() {
            return false;
        }
        let written = match line {
            Ok(line) => appender.file.write_all(&line).map_err(|e| e.to_string()),
            Err(e) => Err(e.to_string()),
        };
        if let Err(e) = written {
            appender.failure = Some(e);
            return false;
        }
        if appender.last_sync.elapsed() >= Duration::from_secs(1) {
            appender.last_sync = Instant::now();
            if let Err(e) = appender.file.sync_data() {
                appender.failure = Some(e.to_string());
                return false;
            }
        }
        true
    }

    /// Make everything appended so far durable.
    pub fn sync(&self) -> crate::error::Result<()> {
        if let Ok(appender) = self.file.lock() {
            appender
                .file
                .sync_data()
                .with_context(|| format!("cannot sync the journal {}", self.path.display()))?;
        }
        Ok(())
    }

    /// Why appending failed, if it did (a full disk, a removed directory).
    pub fn failure(&self) -> Option<String> {
        self.file.lock().ok().and_then(|a| a.failure.clone())
    }
}

/// A journal read back: its header, finished scenes by key, and what was repaired.
pub struct JournalContents {
    pub header: JournalHeader,
    /// Finished scenes, keyed by scene key (the last line wins for a key written twice).
    pub entries: HashMap<String, Entry>,
    /// Lines that could not be read or fail their checksum (a torn tail from a power loss,
    /// a line changed on disk): their scenes are recomputed.
    pub damaged_lines: usize,
}

/// Only the header line, for a quick look (`status`, deciding whether to resume).
pub fn read_header(path: &Path) -> crate::error::Result<JournalHeader> {
    let file =
        File::open(path).with_context(|| format!("cannot read the journal {}", path.display()))?;
    let mut first = Vec::new();
    std::io::BufReader::new(file)
        .read_until(b'\n', &mut first)
        .with_context(|| format!("cannot read the journal {}", path.display()))?;
    let header: JournalHeader = serde_json::from_slice(&first)
        .with_context(|| format!("{} is not a rocklab journal (bad header)", path.display()))?;
    if header.journal != JOURNAL_FORMAT {
        crate::error::bail!(
            "{}: journal format {} is not supported (this build reads {JOURNAL_FORMAT})",
            path.display(),
            header.journal
        );
    }
    Ok(header)
}

/// Read a whole journal, one line at a time (memory: the typed results, nothing more). With
/// `repair`, a torn last line (no newline: the writer was stopped mid-line) is cut off so
/// appends continue on a line of their own.
pub fn read_journal(path: &Path, repair: bool) -> crate::error::Result<JournalContents> {
    let header = read_header(path)?;
    let file =
        File::open(path).with_context(|| format!("cannot read the journal {}", path.display()))?;
    let mut reader = std::io::BufReader::new(file);
    let mut line = Vec::new();
    let mut offset = reader.read_until(b'\n', &mut line)? as u64;
    let mut entries = HashMap::new();
    let mut damaged_lines = 0;
    loop {
        line.clear();
        let n = reader.read_until(b'\n', &mut line)?;
        if n == 0 {
            break;
        }
        if line.last() != Some(&b'\n') {
            // A torn tail: never acknowledged as written.
            damaged_lines += 1;
            if repair {
                let f = std::fs::OpenOptions::new().write(true).open(path)?;
                f.set_len(offset)?;
                f.sync_all()?;
            }
            break;
        }
        offset += n as u64;
        if !line_is_intact(&line) {
            damaged_lines += 1;
            continue;
        }
        match serde_json::from_slice::<Entry>(&line) {
            Ok(entry) => {
                entries.insert(entry.key.clone(), entry);
            }
            Err(_) => damaged_lines += 1,
        }
    }
    Ok(JournalContents {
        header,
        entries,
        damaged_lines,
    })
}

/// Scene counts of a journal without holding its results (for `rocklab status`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JournalCounts {
    pub ok: usize,
    pub failed: usize,
}

pub fn count_journal(path: &Path) -> crate::error::Result<(JournalHeader, JournalCounts)> {
    /// The result's variant only; the payload is skipped unread.
    #[derive(Deserialize)]
    struct Light {
        index: usize,
        result: Result<serde::de::IgnoredAny, serde::de::IgnoredAny>,
    }
    let header = read_header(path)?;
    let reader = std::io::BufReader::new(File::open(path)?);
    let mut seen = std::collections::HashSet::new();
    let mut counts = JournalCounts::default();
    for line in reader.lines().skip(1) {
        let Ok(line) = line else { break };
        if line_is_intact(line.as_bytes())
            && let Ok(entry) = serde_json::from_str::<Light>(&line)
            && seen.insert(entry.index)
        {
            match entry.result {
                Ok(_) => counts.ok += 1,
                Err(_) => counts.failed += 1,
            }
        }
    }
    Ok((header, counts))
}

/// The results a journal holds, in expansion order, with its study (for `merge` of a shard
/// whose final write never happened). Points come from re-expanding the header's study.
pub fn results_from_journal(path: &Path) -> crate::error::Result<SweepResults> {
    let contents = read_journal(path, false)?;
    let header = contents.header;
    let Some(study) = header.study.clone() else {
        crate::error::bail!("{}: the journal names no study", path.display());
    };
    if study.kind() == StudyKind::Design {
        // A design search's scenes are its probes, off the expansion: the search replayed on
        // the journalled scenes gives them back (design studies are never sharded).
        let finished = (contents.entries.into_iter())
            .map(|(key, entry)| (key, entry.result))
            .collect();
        let progress = super::design::progress(&study, &finished).map_err(|e| {
            crate::error::error!("{}: its study no longer expands: {e}", path.display())
        })?;
        return Ok(SweepResults {
            study_hash: header.study_hash,
            cancelled: !progress.complete,
            study: Some(study),
            outcomes: progress.outcomes,
            shard: header.shard,
            build: header.build,
            inferred: Vec::new(),
        });
    }
    let points = study.expand().map_err(|e| {
        crate::error::error!("{}: its study no longer expands: {e}", path.display())
    })?;
    let mut entries = contents.entries;
    let mut total = 0;
    let mut outcomes = Vec::new();
    for point in points {
        if !super::in_shard(point.index, header.shard) {
            continue;
        }
        total += 1;
        if let Some(entry) = entries.remove(&point.key)
            && entry.index == point.index
        {
            outcomes.push(SceneOutcome {
                point,
                result: entry.result,
            });
        }
    }
    // An adaptive map runs only part of its grid: it is complete when its refinement is.
    let adaptive = study.kind() == StudyKind::RefinedMap;
    let inferred = super::adaptive::replay(&study, &outcomes);
    Ok(SweepResults {
        study_hash: header.study_hash,
        cancelled: if adaptive {
            inferred.is_none()
        } else {
            outcomes.len() < total
        },
        study: Some(study),
        outcomes,
        shard: header.shard,
        build: header.build,
        inferred: inferred.unwrap_or_default(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_changed_anywhere_fails_its_checksum() {
        let body = br#"{"index":3,"key":"ab","result":{"Ok":{"peak_rotation_ratio":0.0}}}"#;
        let line = checked_line(body);
        assert!(line_is_intact(&line));
        assert!(line.starts_with(SUM_PREFIX) && line.ends_with(b"}\n"));
        let entry: serde_json::Value = serde_json::from_slice(&line).unwrap();
        assert_eq!(entry["index"], 3);
        for at in SUM_PREFIX.len()..line.len() - 1 {
            let mut bad = line.clone();
            bad[at] = if bad[at] == b'7' { b'8' } else { b'7' };
            assert!(!line_is_intact(&bad), "a change at byte {at} went unseen");
        }
        assert!(!line_is_intact(&body[..]));
    }
}
