//! The results store: the results file (`results.json`, or a shard's file) written atomically
//! and read back into typed structs. The sweep owns it because the sweep reuses it as a cache;
//! the report only adds derived tables (spectra, maps) through [`results_file_json`].

use super::{SceneOutcome, SweepResults};
use crate::error::Context;
use crate::study::Study;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The results file format version.
pub const RESULTS_FORMAT: u32 = 1;

#[derive(Serialize)]
struct ResultsFile<'a, D: Serialize> {
    format: u32,
    #[serde(flatten)]
    results: &'a SweepResults,
    /// Tables derived from the results (the report's spectra and maps), stored for readers
    /// outside rocklab; never read back.
    #[serde(flatten)]
    derived: &'a D,
}

/// The results file's bytes: format, the results, then `derived`'s fields.
pub fn results_file_json<D: Serialize>(
    results: &SweepResults,
    derived: &D,
) -> crate::error::Result<Vec<u8>> {
    let file = ResultsFile {
        format: RESULTS_FORMAT,
        results,
        derived,
    };
    // Compact: a study of 10⁵ scenes would otherwise spend half its file on indentation.
    Ok(serde_json::to_vec(&file)?)
}

/// The stored fields, read straight into typed structs: derived tables are skipped without
/// being built (a generic JSON tree cost 18 KB per scene on resume).
#[derive(Deserialize)]
struct StoredResults {
    format: u32,
    study_hash: String,
    #[serde(default)]
    study: Option<Study>,
    outcomes: Vec<SceneOutcome>,
    #[serde(default)]
    cancelled: bool,
    #[serde(default)]
    shard: Option<(usize, usize)>,
    #[serde(default)]
    build: String,
    #[serde(default)]
    inferred: Vec<super::InferredCell>,
}

/// Only the version, to explain why a file of another format did not parse.
#[derive(Deserialize)]
struct FormatOnly {
    format: Option<u64>,
}

/// Read a results file written by [`results_file_json`].
pub fn load_results(path: &Path) -> crate::error::Result<SweepResults> {
    let bytes = std::fs::read(path)
        .with_context(|| format!("cannot read results file {}", path.display()))?;
    let stored: StoredResults = match serde_json::from_slice(&bytes) {
        Ok(s) => s,
        Err(e) => {
            let format = serde_json::from_slice::<FormatOnly>(&bytes).map(|f| f.format);
            return Err(match format {
                Ok(Some(f)) if f != RESULTS_FORMAT as u64 => crate::error::error!(
                    "{}: results format {f} is not supported (this build reads format {RESULTS_FORMAT})",
                    path.display()
                ),
                Ok(_) => {
                    crate::error::error!("{} is not a rocklab results file: {e}", path.display())
                }
                Err(_) => crate::error::error!(
                    "{} is not a rocklab results file (bad JSON: {e})",
                    path.display()
                ),
            });
        }
    };
    if stored.format != RESULTS_FORMAT {
        crate::error::bail!(
            "{}: results format {} is not supported (this build reads format {RESULTS_FORMAT})",
            path.display(),
            stored.format
        );
    }
    Ok(SweepResults {
        study_hash: stored.study_hash,
        study: stored.study,
        outcomes: stored.outcomes,
        cancelled: stored.cancelled,
        shard: stored.shard,
        build: stored.build,
        inferred: stored.inferred,
    })
}

/// The study hash and name of a results file, read without building its results.
pub fn results_identity(path: &Path) -> crate::error::Result<(String, Option<String>)> {
    #[derive(Deserialize)]
    struct Named {
        name: String,
    }
    #[derive(Deserialize)]
    struct Identity {
        study_hash: String,
        #[serde(default)]
        study: Option<Named>,
    }
    let file = std::fs::File::open(path)
        .with_context(|| format!("cannot read results file {}", path.display()))?;
    let id: Identity = serde_json::from_reader(std::io::BufReader::new(file))
        .with_context(|| format!("{} is not a rocklab results file", path.display()))?;
    Ok((id.study_hash, id.study.map(|s| s.name)))
}
