//! `rocklab compare`: two device variants of one results file side by side, paired by meaning
//! (same record, structure and excitation; one side may be a grid), with overturning-aware
//! statistics per pair, record-suite statistics and overturning maps side by side.

use super::UsageError;
use crate::numfmt::fmt_num;
use crate::report::compare::{self, MapComparison, PairStats, PointPair, SpectrumPair, SuitePair};
use crate::report::select::Selector;
use crate::report::{self, PointState, Quantity};
use clap::{Args, ValueEnum};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(Args, Debug, Clone)]
pub struct CompareArgs {
    /// Results file (results.json) or the directory holding it.
    pub results: PathBuf,
    /// Reference variant: a device, optionally with parameter values in the study's syntax,
    /// e.g. `sequential`, `bare`, `mechanistic(k_theta: 3.0, play: 0.005)`. Default, as in
    /// the workbench: sequential if there with mechanistic, else the pair of devices with
    /// most points where both survive; with a single device, its first grid member.
    #[arg(long)]
    pub a: Option<String>,
    /// Variant compared against it; it may be a grid (`mechanistic`: one row per member).
    /// The same as A: the first member of the grid against each other one.
    #[arg(long)]
    pub b: Option<String>,
    /// Quantity to compare (default: the study's first), or `all`.
    #[arg(long)]
    pub quantity: Option<String>,
    /// Row order (default: `mean` when one side is a grid, else the study's order).
    #[arg(long, value_enum)]
    pub sort: Option<SortBy>,
    /// Print every pair's point-by-point table (always printed for a single pair).
    #[arg(long)]
    pub points: bool,
    /// Machine-readable output (JSON) instead of text.
    #[arg(long)]
    pub json: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SortBy {
    /// The study's expansion order.
    Study,
    /// Mean pointwise B/A, smallest first.
    Mean,
    /// Median pointwise B/A, smallest first.
    Median,
    /// B/A of the peaks, smallest first.
    Peak,
    /// Points where B survives and A overturns, most first.
    BSaves,
}

pub fn resolve_results(path: &std::path::Path) -> PathBuf {
    if path.is_dir() {
        path.join("results.json")
    } else {
        path.to_path_buf()
    }
}

/// Everything one `compare` call finds, as `--json` prints it.
#[derive(Serialize)]
struct Comparison {
    a: String,
    b: String,
    pairs: Vec<SpectrumPair>,
    suites: Vec<SuitePair>,
    maps: Vec<MapComparison>,
    /// Records that ran as stand-ins, not the real ground motions.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    stand_in_records: Vec<String>,
}

/// The JSON `compare --json` prints: Python's `Results.compare` reads its pairs.
pub fn json(args: &CompareArgs) -> anyhow::Result<serde_json::Value> {
    Ok(serde_json::to_value(comparison(args)?.0)?)
}

pub fn run(args: &CompareArgs) -> anyhow::Result<()> {
    let (all, text) = comparison(args)?;
    // A closed pipe (`compare … | head`) ends the output quietly.
    if args.json {
        super::run::print_out(&format!("{}\n", serde_json::to_string_pretty(&all)?))
    } else {
        super::run::print_out(&text)
    }
}

/// Everything `compare` finds, and the text it prints without `--json`.
fn comparison(args: &CompareArgs) -> anyhow::Result<(Comparison, String)> {
    let results = report::load_results(&resolve_results(&args.results))?;
    let quantities = selected_quantities(args, &report::quantities(&results))?;
    let usage = |e: report::select::SelectError| UsageError::new(format!("{e}"));
    let spectra = report::spectra(&results);
    let (default_a, default_b) = {
        let rows: Vec<&report::Spectrum> = spectra
            .iter()
            .filter(|s| Some(&s.quantity) == quantities.first())
            .collect();
        compare::default_sides(&rows).unwrap_or_default()
    };
    let a = args.a.clone().unwrap_or(default_a);
    let b = args.b.clone().unwrap_or(default_b);
    let a = Selector::parse(&a).map_err(|e| UsageError::new(format!("--a: {e}")))?;
    let b = Selector::parse(&b).map_err(|e| UsageError::new(format!("--b: {e}")))?;
    let suites = compare::suite_spectra(&results, &spectra);
    let mut all = Comparison {
        a: a.text.clone(),
        b: b.text.clone(),
        pairs: vec![],
        suites: vec![],
        maps: vec![],
        stand_in_records: report::stand_in_records(&results),
    };
    let mut text = format!("A = {}, B = {}\n", a.text, b.text);
    if !all.stand_in_records.is_empty() {
        let _ = writeln!(
            text,
            "{}: {}",
            crate::excitation::library::STAND_IN_NOTE,
            all.stand_in_records.join(", ")
        );
    }
    for (i, &q) in quantities.iter().enumerate() {
        if i > 0 {
            text.push('\n');
        }
        let mut pairs = compare::compare_spectra(&spectra, q, &a, &b).map_err(usage)?;
        let grid = is_grid(&pairs);
        sort_pairs(
            &mut pairs,
            args.sort
                .unwrap_or(if grid { SortBy::Mean } else { SortBy::Study }),
        );
        let suite_pairs = compare::compare_suites(&suites, q, &a, &b).map_err(usage)?;
        text.push_str(&pairs_text(q, &pairs, args.points || pairs.len() == 1));
        text.push_str(&suites_text(&suite_pairs));
        all.pairs.extend(pairs);
        all.suites.extend(suite_pairs);
    }
    let maps = report::maps(&results);
    if !maps.is_empty() {
        all.maps = compare::compare_maps(&maps, &a, &b).map_err(usage)?;
        for m in &all.maps {
            text.push('\n');
            text.push_str(&compare::map_text(m));
        }
    }
    Ok((all, text))
}

fn selected_quantities(args: &CompareArgs, study: &[Quantity]) -> anyhow::Result<Vec<Quantity>> {
    Ok(match args.quantity.as_deref() {
        Some("all") => study.to_vec(),
        Some(name) => vec![Quantity::from_name(name).ok_or_else(|| {
            let names: Vec<_> = Quantity::ALL.iter().map(|q| q.name()).collect();
            UsageError::new(format!(
                "unknown --quantity `{name}`; expected `all` or one of: {}",
                names.join(", ")
            ))
        })?],
        None => study[..1].to_vec(),
    })
}

/// Whether one A is paired with several Bs (or the reverse): a grid side.
fn is_grid(pairs: &[SpectrumPair]) -> bool {
    let count = |f: &dyn Fn(&SpectrumPair) -> &str| {
        let mut seen: Vec<&str> = pairs.iter().map(f).collect();
        seen.sort();
        seen.dedup();
        seen.len()
    };
    count(&|p| &p.a) < pairs.len() || count(&|p| &p.b) < pairs.len()
}

fn sort_pairs(pairs: &mut [SpectrumPair], by: SortBy) {
    let key = |s: &PairStats| -> f64 {
        match by {
            SortBy::Study => 0.0,
            SortBy::Mean => s.mean_ratio.unwrap_or(f64::INFINITY),
            SortBy::Median => s.median_ratio.unwrap_or(f64::INFINITY),
            SortBy::Peak => s.peak_ratio.unwrap_or(f64::INFINITY),
            SortBy::BSaves => -(s.a_overturns_b_survives as f64),
        }
    };
    // Stable: ties keep the study's order.
    pairs.sort_by(|x, y| key(&x.stats).total_cmp(&key(&y.stats)));
}

const LEGEND: &str = "  mean, median, min–max: pointwise B/A over the points where both survive (n); \
peak: max B / max A over those points;\n  A↯: A overturns where B survives, B↯: the reverse, \
both↯: both overturn; A=0: both survive but A is zero (no ratio);\n  failed and not-run points counted apart, never as overturned\n";

fn pct(r: Option<f64>) -> String {
    r.map_or("—".into(), |r| format!("{:+.1}%", 100.0 * (r - 1.0)))
}

fn ratio(r: Option<f64>) -> String {
    r.map_or("—".into(), |r| format!("{r:.3}"))
}

fn pairs_text(q: Quantity, pairs: &[SpectrumPair], details: bool) -> String {
    let mut s = String::new();
    let axis = pairs.first().map_or("", |p| p.axis.as_str());
    let _ = writeln!(
        s,
        "{} ({}) over {axis}: B/A for {} pair{}",
        q.label(),
        q.name(),
        pairs.len(),
        if pairs.len() == 1 { "" } else { "s" }
    );
    s.push_str(LEGEND);
    let wa = pairs
        .iter()
        .map(|p| p.a.chars().count())
        .max()
        .unwrap_or(1)
        .max(1);
    let wb = pairs
        .iter()
        .map(|p| p.b.chars().count())
        .max()
        .unwrap_or(1)
        .max(1);
    let _ = writeln!(
        s,
        "  {:wa$}  {:wb$}  {:>3}  {:>6} {:>7}  {:>6}  {:>13}  {:>6} {:>7}  {:>3} {:>3} {:>5} {:>3}  {:>6} {:>7}",
        "A",
        "B",
        "n",
        "mean",
        "",
        "median",
        "min–max",
        "peak",
        "",
        "A↯",
        "B↯",
        "both↯",
        "A=0",
        "failed",
        "not run"
    );
    for p in pairs {
        let st = &p.stats;
        let _ = writeln!(
            s,
            "  {:wa$}  {:wb$}  {:>3}  {:>6} {:>7}  {:>6}  {:>13}  {:>6} {:>7}  {:>3} {:>3} {:>5} {:>3}  {:>6} {:>7}",
            p.a,
            p.b,
            st.ratio_points,
            ratio(st.mean_ratio),
            pct(st.mean_ratio),
            ratio(st.median_ratio),
            min_max(st),
            ratio(st.peak_ratio),
            pct(st.peak_ratio),
            st.a_overturns_b_survives,
            st.b_overturns_a_survives,
            st.both_overturn,
            st.zero_a,
            st.failed,
            st.not_run,
        );
    }
    if details {
        for p in pairs {
            s.push_str(&side_by_side(p));
        }
    }
    s
}

/// One pair point by point: A, B (values or what happened instead) and B/A, with sparklines.
pub fn side_by_side(p: &SpectrumPair) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "\n  A = {}, B = {}", p.a, p.b);
    let ys = |f: &dyn Fn(&PointPair) -> Option<f64>| -> Vec<Option<f64>> {
        p.points.iter().map(f).collect()
    };
    let _ = writeln!(s, "  A   {}", report::sparkline(&ys(&|q| q.a)));
    let _ = writeln!(s, "  B   {}", report::sparkline(&ys(&|q| q.b)));
    let _ = writeln!(s, "  B/A {}", report::sparkline(&ys(&|q| q.ratio)));
    let _ = writeln!(s, "  {:>10} {:>12} {:>12} {:>8}", p.axis, "A", "B", "B/A");
    let cell = |v: Option<f64>, state: PointState| match state {
        PointState::Survived => v.map_or("—".into(), |v| format!("{v:.5}")),
        PointState::Overturned => "overturned".into(),
        PointState::Failed => "failed".into(),
        PointState::NotRun => "not run".into(),
    };
    for q in &p.points {
        let _ = writeln!(
            s,
            "  {:>10} {:>12} {:>12} {:>8}",
            fmt_num(q.x),
            cell(q.a, q.a_state),
            cell(q.b, q.b_state),
            ratio(q.ratio)
        );
    }
    s
}

fn suites_text(pairs: &[SuitePair]) -> String {
    let mut s = String::new();
    if pairs.is_empty() {
        return s;
    }
    let _ = writeln!(
        s,
        "\n  record suite ({} records): B/A of the suite-mean spectra (mean over the records where each survives); \
CV = dispersion over records (sample std / mean), averaged over the axis; ↯ = record points overturned",
        pairs[0].records
    );
    for p in pairs {
        let st = &p.stats;
        let _ = writeln!(
            s,
            "  {} vs {}: mean B/A {} ({}), median {}, min–max {}, peak B/A {} over {} points; \
CV A {} B {}; ↯ A {} B {}",
            p.a,
            p.b,
            ratio(st.mean_ratio),
            pct(st.mean_ratio),
            ratio(st.median_ratio),
            min_max(st),
            ratio(st.peak_ratio),
            st.ratio_points,
            ratio(p.mean_cv_a),
            ratio(p.mean_cv_b),
            p.overturned_a,
            p.overturned_b,
        );
    }
    s
}

/// The min–max range of the pointwise B/A, or a dash when no point has a ratio.
fn min_max(st: &PairStats) -> String {
    match (st.min_ratio, st.max_ratio) {
        (Some(lo), Some(hi)) => format!("{lo:.3}–{hi:.3}"),
        _ => "—".into(),
    }
}
