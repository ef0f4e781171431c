//! Results to files (CSV histories, atomic writes) and aggregation of sweep results
//! (spectra, overturning maps, comparisons).

mod aggregate;
pub mod compare;
pub mod design;
mod export;
mod figure;
pub mod fragility;
pub mod ida;
pub mod ims;
mod legend;
pub mod naming;
mod plot;
mod plot_design;
pub mod risk;
mod risk_plot;
pub mod select;
pub mod stripes;

pub use crate::fsutil::readable_by_all;

/// [`crate::fsutil::write_atomic`], its error as the report's.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> crate::error::Result<()> {
    Ok(crate::fsutil::write_atomic(path, bytes)?)
}
pub use crate::study::Quantity;
pub use crate::sweep::load_results;
pub use aggregate::{
    Group, OverturningMap, PointState, Setting, Spectrum, compare, maps, quantities, sparkline,
    spectra,
};
pub use export::{
    BOUNDARY_CSV, CsvLayout, DESIGN_CSV, Parameter, axis_columns, boundary_csv, parameter,
    results_columns_csv, results_csv, results_csv_layout, results_json, save_results,
    stand_in_records, study_summary, summary, write_tables,
};
pub use figure::{FigureOptions, FigureSize, ImageFormat, MAX_MEGAPIXELS, MEGAPIXELS_CEILING};
pub use plot::{
    MAX_SERIES, PlotChoice, panel_title, plot_history, plot_map_differences, plot_maps,
    plot_spectra, scene_label, scene_title, study_title, with_shared,
};
pub use plot_design::{design_title, plot_design};
pub use risk_plot::plot_risk;

use crate::sim::History;
use std::path::Path;

/// The tables a run writes beside its results (when the study has them), by name: what
/// Python's `Results.fragility()`, `.risk()`, `.stripes()`, `.ida()`, `.design()` and
/// `.boundary()` read.
pub const TABLE_FILES: [(&str, &str); 6] = [
    ("fragility", fragility::FRAGILITY_CSV),
    ("risk", risk::RISK_CSV),
    ("stripes", stripes::STRIPES_CSV),
    ("ida", ida::IDA_CSV),
    ("design", DESIGN_CSV),
    ("boundary", BOUNDARY_CSV),
];

/// How a run writes its results file and tables, for [`crate::sweep::DirRun::run`].
pub const WRITERS: crate::sweep::Writers<'static> = crate::sweep::Writers {
    results: &save_results,
    tables: &write_tables,
};

/// A history as CSV: one header line, then one row per sample (see [`crate::sim::Sampling`]).
pub fn history_csv(history: &History) -> crate::error::Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(history.columns.iter().map(|c| c.name()))?;
    for row in &history.rows {
        w.write_record(row.iter().map(|v| format!("{v:.10e}")))?;
    }
    Ok(w.into_inner()?)
}

pub fn write_history_csv(path: &Path, history: &History) -> crate::error::Result<()> {
    write_atomic(path, &history_csv(history)?)
}
