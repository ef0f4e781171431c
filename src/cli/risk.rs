//! `rocklab risk`: the mean annual frequency of reaching each damage state at a site, from a
//! fragility study's results and the site's hazard curve; FEMA P695 margins with `--mce`.

use super::UsageError;
use crate::numfmt::fmt_sig;
use crate::report;
use crate::report::risk::{
    RISK_CSV, RISK_JSON, assess, im_factors, read_fragility, svg_options, write_risk,
};
use crate::risk::{HazardCurve, RiskOptions, RiskReport, p695};
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug, Clone)]
pub struct RiskArgs {
    /// A fragility study's results directory (out/<study>, holding fragility.json).
    pub results: PathBuf,
    /// The site's hazard curve: a CSV with the header `pga,annual_rate` (PGA in g),
    /// `pgv,annual_rate` (PGV in m/s) or `sa(T),annual_rate`, one point per row; lines
    /// starting with # are comments.
    #[arg(long)]
    pub hazard: PathBuf,
    /// Years of exposure for p_years = 1 − exp(−MAF · years).
    #[arg(long, default_value_t = 50.0, value_parser = positive)]
    pub years: f64,
    /// Print risk.json to standard output instead of the table.
    #[arg(long)]
    pub json: bool,
    /// FEMA P695 margins: the MCE intensity in the hazard's IM (g or m/s).
    #[arg(long, value_parser = positive)]
    pub mce: Option<f64>,
    /// β_TOT for the margins (with --mce). Left out for a study with uncertain parameters,
    /// each variant's fitted total β (records and parameters) serves.
    #[arg(long, value_parser = positive, conflicts_with = "ratings", requires = "mce")]
    pub beta_total: Option<f64>,
    /// β_TOT from P695 Table 7-2's quality ratings of design requirements, test data and
    /// modelling (A–D each, e.g. B,B,C) and β_RTR = min(0.1 + 0.1 μT, 0.4); rounded to the
    /// nearest 0.025 as P695 does.
    #[arg(long, requires = "mce")]
    pub ratings: Option<String>,
    /// Period-based ductility μT for β_RTR with --ratings (3 or more gives P695's 0.4).
    #[arg(long, default_value_t = 3.0, value_parser = positive)]
    pub mu_t: f64,
    /// Where risk.csv, risk.json and risk.svg go (default: the results directory).
    #[arg(long, short)]
    pub out: Option<PathBuf>,
}

fn positive(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("{text}: give a positive number")),
    }
}

/// What `rocklab risk` wrote: the report, the directory of risk.csv/risk.json, the figure.
pub struct Written {
    pub risk: RiskReport,
    pub out: PathBuf,
    pub figure: Option<PathBuf>,
}

/// Everything `rocklab risk` does but print: assess the results against the hazard and write
/// risk.csv, risk.json and the figure (Python's `Results.risk` calls this).
pub fn assess_and_write(args: &RiskArgs) -> anyhow::Result<Written> {
    let dir = if args.results.is_dir() {
        args.results.clone()
    } else {
        crate::fsutil::parent_dir(&args.results).to_path_buf()
    };
    let fragility = read_fragility(&dir)?;
    let hazard = HazardCurve::read(&args.hazard)?;
    let results = report::load_results(&super::compare::resolve_results(&dir))?;
    let study = results.study.as_ref().ok_or_else(|| {
        UsageError::new(format!(
            "{}: the results hold no study, so the structures' α and p are unknown (hint: \
             rerun the study with `rocklab run`)",
            dir.display()
        ))
    })?;
    let factors = im_factors(study, &results, &hazard, &args.hazard)?;
    let beta_total = match (&args.ratings, args.beta_total) {
        (Some(r), _) => Some(p695::beta_total(p695::Ratings::parse(r)?, args.mu_t)),
        (None, b) => b,
    };
    // A study with uncertain parameters gives each variant's total β itself.
    if args.mce.is_some() && beta_total.is_none() && fragility.uncertainty.is_empty() {
        return Err(UsageError::new(
            "--mce needs --beta-total B or --ratings DR,TD,MDL (or a study with uncertain \
             parameters, whose fitted total β serves)",
        )
        .into());
    }
    let opts = RiskOptions {
        years: args.years,
        mce: args.mce,
        beta_total,
    };
    // The file's name: risk.json and the table read the same wherever the file was.
    let source = args.hazard.file_name().map_or_else(
        || args.hazard.display().to_string(),
        |n| n.to_string_lossy().to_string(),
    );
    let risk = assess(&fragility, &hazard, &source, &factors, &opts);
    let out = args.out.clone().unwrap_or(dir);
    std::fs::create_dir_all(&out)?;
    write_risk(&out, &risk)?;
    let figure = report::plot_risk(&out, &svg_options(), &risk)?;
    Ok(Written { risk, out, figure })
}

pub fn run(args: &RiskArgs) -> anyhow::Result<()> {
    let Written { risk, out, figure } = assess_and_write(args)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&risk)?);
    } else {
        print!("{}", table(&risk));
        println!(
            "written: {}, {}",
            out.join(RISK_CSV).display(),
            out.join(RISK_JSON).display()
        );
        if let Some(f) = figure {
            println!("figure: {}", f.display());
        }
    }
    for w in &risk.warnings {
        eprintln!("warning: {w}");
    }
    Ok(())
}

fn opt(v: Option<f64>) -> String {
    v.map_or_else(|| "-".to_string(), fmt_sig)
}

/// The printed table: one line per variant × state, then the margins.
pub fn table(risk: &RiskReport) -> String {
    let h = &risk.hazard;
    let mut s = format!(
        "hazard {} ({} points, {} in {}; power law λ ≈ {} x^-{})\n",
        h.source,
        h.curve.x.len(),
        h.curve.im.name(),
        h.curve.im.unit(),
        fmt_sig(h.power_law.k0),
        fmt_sig(h.power_law.k),
    );
    s.push_str(&format!(
        "{:<28} {:>5} {:>10} {:>22} {:>9} {:>18} {:>17}  status\n",
        "variant",
        "DS",
        "MAF (1/yr)",
        format!("{:.0} % interval", 100.0 * risk.confidence),
        format!("P({:.0} yr)", risk.years),
        "MAF / bare",
        "IM p10–p90",
    ));
    for r in &risk.rows {
        s.push_str(&format!(
            "{:<28} {:>5} {:>10} {:>22} {:>9} {:>18} {:>17}  {}\n",
            r.variant.label(),
            r.damage_state,
            opt(r.maf),
            format!("[{}, {}]", opt(r.maf_lo), opt(r.maf_hi)),
            opt(r.p_years),
            match r.ratio_to_bare {
                Some(x) => format!("{} [{}, {}]", fmt_sig(x), opt(r.ratio_lo), opt(r.ratio_hi)),
                None => "-".into(),
            },
            format!("{}–{}", opt(r.deagg_p10), opt(r.deagg_p90)),
            r.status
        ));
    }
    if !risk.margins.is_empty() {
        s.push_str("FEMA P695 margins (collapse = the highest damage state; SSF = 1):\n");
        for m in &risk.margins {
            let g = &m.margin;
            s.push_str(&format!(
                "{:<28} CMR {} (median {} / MCE {})  β_TOT {}  ACMR10 {}  ACMR20 {}  {}\n",
                m.variant.label(),
                fmt_sig(g.cmr),
                fmt_sig(g.median_capacity),
                fmt_sig(g.mce),
                crate::numfmt::fmt_digits(g.beta_total, 4),
                fmt_sig(g.acmr_10),
                fmt_sig(g.acmr_20),
                match (g.pass_10, g.pass_20) {
                    (true, _) => "passes (≥ ACMR10)",
                    (false, true) => "passes ACMR20 only",
                    (false, false) => "fails",
                }
            ));
        }
    }
    s
}
