//! The fragility report's outputs: fragility.csv / fragility.json (`table.rs`) and the figure
//! (`plot.rs`), the summary text (`summary.rs`). The statistics themselves (the fits, the bootstrap, the report's types) are
//! `crate::stats`, re-exported here so the report's callers name one module.

mod plot;
mod summary;
mod table;

pub use crate::stats::*;
pub use plot::{data_points, plot_fragility};
pub use summary::{
    curve_line, damage_state_name, fmt_fit, summary_text, variant_name, with_interval,
};
pub use table::{
    FRAGILITY_CSV, FRAGILITY_JSON, fragility_csv, read_fragility_json, variant_parameter_names,
    write_fragility_csv, write_fragility_json,
};
