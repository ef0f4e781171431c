//! Results to files (CSV histories, atomic writes) and aggregation of sweep results
//! (spectra, overturning maps, comparisons).

mod aggregate;
mod export;
mod figure;
mod plot;

pub use aggregate::{
    OverturningMap, Quantity, Spectrum, compare, maps, quantities, sparkline, spectra,
};
pub use export::{
    CsvLayout, Parameter, load_results, parameter, results_columns_csv, results_csv,
    results_csv_layout, results_json, save_results, summary,
};
pub use figure::{FigureOptions, FigureSize, ImageFormat};
pub use plot::{MAX_SERIES, PlotChoice, plot_history, plot_maps, plot_spectra, scene_title};

use crate::sim::History;
use anyhow::Context;
use std::io::Write;
use std::path::Path;

/// Write `bytes` to `path` atomically: a temporary file in the same directory, then rename,
/// so a reader never sees a half-written result.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut tmp = tempfile::NamedTempFile::new_in(dir)
        .with_context(|| format!("cannot create a file in {}", dir.display()))?;
    tmp.write_all(bytes)?;
    tmp.as_file().sync_all()?;
    readable_by_all(tmp.as_file())?;
    tmp.persist(path)
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

/// Temporary files are created private (0600); results are for sharing (0644).
pub fn readable_by_all(file: &std::fs::File) -> anyhow::Result<()> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        file.set_permissions(std::fs::Permissions::from_mode(0o644))?;
    }
    #[cfg(not(unix))]
    let _ = file;
    Ok(())
}

/// A history as CSV: one header line, then one row per accepted step or event.
pub fn history_csv(history: &History) -> anyhow::Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(&history.columns)?;
    for row in &history.rows {
        w.write_record(row.iter().map(|v| format!("{v:.10e}")))?;
    }
    Ok(w.into_inner()?)
}

pub fn write_history_csv(path: &Path, history: &History) -> anyhow::Result<()> {
    write_atomic(path, &history_csv(history)?)
}
