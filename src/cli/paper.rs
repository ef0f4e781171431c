//! `rocklab paper`: the paper's claims rerun against rocklab ([`crate::paper`]), printed as the
//! PAPER.md table.

use clap::Args;

#[derive(Args, Debug, Clone)]
pub struct PaperArgs {
    /// Only the checks whose figure contains this (e.g. `24`).
    #[arg(long)]
    pub only: Option<String>,
}

pub fn run(args: &PaperArgs) -> anyhow::Result<()> {
    let claims = crate::paper::claims(args.only.as_deref())?;
    print!("{}", crate::paper::markdown(&claims));
    Ok(())
}
