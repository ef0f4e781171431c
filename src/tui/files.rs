//! What the workbench opens from disk: telling a results path from a study file, and loading
//! the fullest results there through the sweep's façade.

use crate::sweep::SweepResults;
use std::path::PathBuf;

/// Whether `path` names results (a results directory, a results or journal file) rather than
/// a study file.
pub fn is_results_path(path: &std::path::Path) -> bool {
    path.is_dir()
        || path
            .extension()
            .is_some_and(|e| e == "json" || e == "journal")
}

/// Results from a results directory (its `results.json`, or its journal if the run was
/// stopped before writing it: whichever holds more), a results file or a journal; with the
/// directory they belong to.
pub fn load_results_at(path: &std::path::Path) -> anyhow::Result<(SweepResults, PathBuf)> {
    let Some((results, file)) = crate::sweep::load_fullest(path)? else {
        anyhow::bail!(
            "{}: no results there (neither a results file nor its journal)",
            path.display()
        );
    };
    let dir = file
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .map_or_else(|| PathBuf::from("."), PathBuf::from);
    Ok((results, dir))
}
