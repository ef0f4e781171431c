//! `rocklab paper`: the paper's claims rerun against rocklab ([`crate::paper`]), printed as the
//! PAPER.md table or, with `--json`, one object per row.

use clap::Args;

#[derive(Args, Debug, Clone)]
pub struct PaperArgs {
    /// Only the rows whose id or figure contains this (e.g. `fig24`, `Fig. 12`).
    #[arg(long)]
    pub only: Option<String>,
    /// Print the rows as JSON: id, figure, claim, check, values, verdict, reason.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &PaperArgs) -> anyhow::Result<()> {
    let rows = crate::paper::rows(args.only.as_deref())?;
    if args.json {
        println!("{}", crate::paper::json(&rows)?);
    } else {
        print!("{}", crate::paper::markdown(&rows));
    }
    Ok(())
}
