//! `rocklab ims RESULTS [--json]`: which intensity measure predicts each damage state best,
//! from an IDA study's results (the analysis is `report::ims`).

use crate::report;
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug, Clone)]
pub struct ImsArgs {
    /// Results file (results.json) of an IDA study, or the directory holding it.
    pub results: PathBuf,
    /// Print one JSON array of rows (device, the varying parameters, damage_state, im, beta,
    /// beta_lo, beta_hi, n, p_magnitude) instead of the ranked table.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &ImsArgs) -> anyhow::Result<()> {
    let path = super::compare::resolve_results(&args.results);
    let results = report::load_results(&path)?;
    let Some(study) = &results.study else {
        anyhow::bail!(
            "{}: the results hold no study, so there are no IDA capacities to read",
            path.display()
        );
    };
    let rows = report::ims::report(study, &results)?;
    if rows.is_empty() {
        anyhow::bail!(
            "{}: no finished IDA hunt reached a damage state, so no IM can be ranked",
            path.display()
        );
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&rows)?);
    } else {
        print!("{}", report::ims::table(&rows));
    }
    Ok(())
}
