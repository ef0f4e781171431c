//! `rocklab table`: the results as CSV in the layout another tool wants.

use crate::report::{self, CsvLayout};
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug, Clone)]
pub struct TableArgs {
    /// Results file (results.json) or the directory holding it.
    pub results: PathBuf,
    /// Tidy rows: one per scene and quantity, with `quantity` and `value` columns (the
    /// layout of results.csv; the default).
    #[arg(long, conflicts_with = "wide")]
    pub long: bool,
    /// One row per scene, one column per quantity.
    #[arg(long)]
    pub wide: bool,
    /// Write here (and the column metadata next to it as NAME.columns.csv) instead of
    /// standard output.
    #[arg(long, short)]
    pub out: Option<PathBuf>,
}

pub fn run(args: &TableArgs) -> anyhow::Result<()> {
    let results = report::load_results(&super::compare::resolve_results(&args.results))?;
    let layout = if args.wide {
        CsvLayout::Wide
    } else {
        CsvLayout::Long
    };
    let csv = report::results_csv_layout(&results, layout)?;
    match &args.out {
        None => {
            use std::io::Write;
            std::io::stdout().write_all(&csv)?;
        }
        Some(path) => {
            report::write_atomic(path, &csv)?;
            let meta = path.with_extension("columns.csv");
            report::write_atomic(&meta, &report::results_columns_csv(&results)?)?;
            println!("{}\n{}", path.display(), meta.display());
        }
    }
    Ok(())
}
