//! `rocklab status OUT_DIR`: per results set (one per shard of a job array) how many scenes
//! are done, failed, missing, and whether a process is running it now, read from the journals
//! (results files for sets without one), and which array tasks to resubmit.

use crate::sweep::{self, SetStatus};
use clap::Args;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Show how far the runs into an output directory got (per shard for a job array).
#[derive(Args, Debug, Clone)]
pub struct StatusArgs {
    /// The output directory of `rocklab run --out DIR` (shards included).
    pub dir: PathBuf,
}

/// One results set found in a directory.
#[derive(Clone, Debug, PartialEq)]
pub struct ResultSet {
    pub shard: Option<(usize, usize)>,
    /// Where its results file is (or would be written).
    pub results_path: PathBuf,
}

/// `results.json` → None, `results.shard-i-of-N.json` → (i, N); with `.journal` too. A name
/// with more shards than any study has scenes is no set rocklab wrote (`run` refuses such a
/// shard count), and listing its absent shards would take forever: it is not a set.
fn parse_set_name(name: &str) -> Option<Option<(usize, usize)>> {
    let stem = name
        .strip_suffix(".json")
        .or_else(|| name.strip_suffix(".journal"))?;
    if stem == "results" {
        return Some(None);
    }
    let rest = stem.strip_prefix("results.shard-")?;
    let (i, n) = rest.split_once("-of-")?;
    let (i, n) = (i.parse().ok()?, n.parse().ok()?);
    (i < n && n <= crate::study::MAX_SCENES).then_some(Some((i, n)))
}

/// The results sets (by results file or journal) in `dir`, unsharded first, then by shard.
pub fn result_sets(dir: &Path) -> anyhow::Result<Vec<ResultSet>> {
    let mut sets = BTreeMap::new();
    let entries = std::fs::read_dir(dir)
        .map_err(|e| anyhow::anyhow!("cannot read the directory {}: {e}", dir.display()))?;
    for entry in entries.flatten() {
        let name = entry.file_name();
        if let Some(shard) = name.to_str().and_then(parse_set_name) {
            let key = shard.map_or((0, 0), |(i, n)| (n, i));
            sets.insert(
                key,
                ResultSet {
                    shard,
                    results_path: dir.join(sweep::results_name(shard)),
                },
            );
        }
    }
    Ok(sets.into_values().collect())
}

fn set_status(set: &ResultSet) -> SetStatus {
    sweep::set_status(&set.results_path, set.shard)
}

/// The status of every set in `dir`, with a line for each shard of an array that left no file.
pub fn dir_status(dir: &Path) -> anyhow::Result<Vec<SetStatus>> {
    let sets = result_sets(dir)?;
    let mut statuses: Vec<SetStatus> = sets.iter().map(set_status).collect();
    let arrays: std::collections::BTreeSet<usize> = statuses
        .iter()
        .filter_map(|s| s.shard.map(|(_, n)| n))
        .collect();
    // A set of the shards present: a scan of `statuses` per shard was quadratic in the
    // shard count (100 000 shard files took seconds).
    let present: std::collections::HashSet<(usize, usize)> =
        statuses.iter().filter_map(|s| s.shard).collect();
    for n in arrays {
        for i in 0..n {
            if !present.contains(&(i, n)) {
                statuses.push(SetStatus {
                    shard: Some((i, n)),
                    ok: 0,
                    failed: 0,
                    total: None,
                    running: None,
                    study_hash: None,
                    remaining_at_most: None,
                    note: None,
                });
            }
        }
    }
    statuses.sort_by_key(|s| s.shard.map_or((0, 0), |(i, n)| (n, i + 1)));
    Ok(statuses)
}

/// Array task ids (shard indices) to resubmit: sets not running with scenes missing.
pub fn to_resubmit(statuses: &[SetStatus]) -> Vec<(usize, usize)> {
    statuses
        .iter()
        .filter(|s| s.running.is_none() && s.missing() != Some(0))
        .filter_map(|s| s.shard)
        .collect()
}

pub fn run(args: &StatusArgs) -> anyhow::Result<()> {
    let statuses = dir_status(&args.dir)?;
    if statuses.is_empty() {
        return Err(super::UsageError::new(format!(
            "{}: no results or journals there (nothing was run into it)",
            args.dir.display()
        ))
        .into());
    }
    let mut text = format!(
        "{:<10} {:>8} {:>8} {:>8}  state\n",
        "shard", "done", "failed", "missing"
    );
    for s in &statuses {
        let shard = s.shard.map_or("-".into(), |(i, n)| format!("{i}/{n}"));
        let known = s.total.is_some() || s.ok + s.failed > 0;
        let missing = match (s.missing(), s.remaining_at_most) {
            (Some(m), _) => m.to_string(),
            (None, Some(most)) => format!("≤{most}"),
            (None, None) => "?".into(),
        };
        let state = match (&s.running, s.missing()) {
            (Some(pid), _) if pid.is_empty() => "running".to_string(),
            (Some(pid), _) => format!("running (pid {pid})"),
            (None, Some(0)) => "complete".into(),
            (None, _) if !known => "not started".into(),
            (None, _) => "stopped, incomplete".into(),
        };
        text.push_str(&format!(
            "{shard:<10} {:>8} {:>8} {missing:>8}  {state}\n",
            s.ok + s.failed,
            s.failed
        ));
        if let Some(note) = &s.note {
            text.push_str(&format!("{:<10} {note}\n", ""));
        }
    }
    let hashes: std::collections::BTreeSet<&String> = statuses
        .iter()
        .filter_map(|s| s.study_hash.as_ref())
        .collect();
    if hashes.len() > 1 {
        text.push_str("warning: the sets belong to different studies (hashes differ)\n");
    }
    let resubmit = to_resubmit(&statuses);
    if !resubmit.is_empty() {
        let ids: Vec<String> = resubmit.iter().map(|(i, _)| i.to_string()).collect();
        text.push_str(&format!(
            // A bare `sbatch --array=…` would leave `rocklab slurm`'s merge job waiting on the
            // failed array for ever, so point at the command that submits both again.
            "resubmit array tasks {}: run the same `rocklab slurm … --submit` again (a new array \
             and merge job; every task resumes from its journal, finished ones at once)\n",
            ids.join(",")
        ));
    } else if statuses.iter().all(|s| s.missing() == Some(0)) {
        text.push_str("every set is complete");
        if statuses.iter().any(|s| s.shard.is_some()) {
            text.push_str(&format!(
                "; combine them with `rocklab merge {} --out DIR`",
                args.dir.display()
            ));
        }
        text.push('\n');
    }
    super::run::print_out(&text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_names_parse() {
        assert_eq!(parse_set_name("results.json"), Some(None));
        assert_eq!(parse_set_name("results.journal"), Some(None));
        assert_eq!(
            parse_set_name("results.shard-2-of-4.journal"),
            Some(Some((2, 4)))
        );
        assert_eq!(parse_set_name("results.shard-4-of-4.json"), None);
        assert_eq!(
            parse_set_name("results.shard-0-of-1000000.json"),
            Some(Some((0, 1_000_000)))
        );
        assert_eq!(parse_set_name("results.shard-0-of-1000001.json"), None);
        assert_eq!(parse_set_name("results.csv"), None);
        assert_eq!(parse_set_name("results.json.previous"), None);
    }

    #[test]
    fn resubmit_lists_stopped_and_absent_shards_only() {
        let s = |i, ok, total: Option<usize>, running: Option<&str>| SetStatus {
            shard: Some((i, 4)),
            ok,
            failed: 0,
            total,
            running: running.map(String::from),
            study_hash: None,
            remaining_at_most: None,
            note: None,
        };
        let statuses = [
            s(0, 10, Some(10), None),
            s(1, 3, Some(10), None),
            s(2, 3, Some(10), Some("77")),
            s(3, 0, None, None),
        ];
        assert_eq!(to_resubmit(&statuses), vec![(1, 4), (3, 4)]);
    }
}
