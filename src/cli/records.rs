//! `rocklab records`: the ground-motion records this binary can run, with PGA and PGV computed
//! from the data, the paper's Table 1 PGV beside them, and where each record came from.

use crate::excitation::{G, Library, Record, ims};
use clap::Args;
use std::path::PathBuf;

/// List the ground-motion records (npts, dt, duration, PGA, PGV, source, sparkline).
#[derive(Args, Debug, Clone)]
pub struct RecordsArgs {
    /// Records directory (default: $ROCKLAB_RECORDS, else ./records if it holds an index.ron; the shipped
    /// records are also embedded in the binary).
    #[arg(long)]
    pub records_dir: Option<PathBuf>,
    /// Apply the baseline correction before computing PGA/PGV.
    #[arg(long)]
    pub baseline: bool,
    /// Print one JSON array on stdout.
    #[arg(long)]
    pub json: bool,
    /// List a record suite instead, with its metadata: far_field, near_field_pulse,
    /// near_field_no_pulse, near_field (both) or table1.
    #[arg(long)]
    pub suite: Option<String>,
    /// Compute every component's intensity measures (PGA, PGV, PGD, Arias, CAV, D5-75, D5-95,
    /// Sa at --periods, Tm, pulse classification and Tp; RotD50 for suite pairs).
    #[arg(long)]
    pub ims: bool,
    /// Periods (s) of Sa with --ims, comma separated (default 0.1,0.2,0.3,0.5,0.75,1,1.5,2,3,4,5).
    #[arg(long, value_delimiter = ',', requires = "ims")]
    pub periods: Vec<f64>,
    /// Damping ratio of Sa with --ims.
    #[arg(long, default_value_t = crate::excitation::ims::DEFAULT_DAMPING, requires = "ims")]
    pub damping: f64,
    /// Records to list instead of the library's: names, suite components (far_field/7a) or
    /// files (AT2, one- or two-column).
    #[arg(conflicts_with = "suite")]
    pub records: Vec<String>,
}

/// PGV (m/s) as the intensity measures define it: a record in g converted with standard
/// gravity, exact integration of the piecewise-linear record (`excitation::ims`).
pub(super) fn standard_pgv(r: &Record) -> f64 {
    ims::Accelerogram::from_series(&r.series).map_or(0.0, |a| ims::kinematics(&a).pgv)
}

const SPARK: [char; 8] = ['▁', '▂', '▃', '▄', '▅', '▆', '▇', '█'];

/// The |a| envelope in `width` bins, each the bin's peak relative to the record's PGA.
pub fn sparkline(samples: &[f64], width: usize) -> String {
    let peak = samples.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
    if samples.is_empty() || peak == 0.0 {
        return SPARK[0].to_string().repeat(width);
    }
    (0..width)
        .map(|b| {
            let lo = b * samples.len() / width;
            let hi = ((b + 1) * samples.len() / width)
                .max(lo + 1)
                .min(samples.len());
            let m = samples[lo..hi].iter().fold(0.0_f64, |m, a| m.max(a.abs()));
            SPARK[((m / peak) * 7.0).round() as usize]
        })
        .collect()
}

pub(super) fn row_json(r: &Record) -> serde_json::Value {
    let s = &r.series;
    let meta = r.meta.as_ref();
    serde_json::json!({
        "name": r.name,
        "table1": meta.and_then(|m| m.table1),
        "event": meta.map(|m| &m.event),
        "year": meta.map(|m| m.year),
        "station": meta.map(|m| &m.station),
        "component": meta.map(|m| &m.component),
        "nga": meta.and_then(|m| m.nga),
        "mw": meta.map(|m| m.mw),
        "tp": meta.and_then(|m| m.tp),
        "source": r.source.kind(),
        "source_detail": r.source.label(),
        "npts": s.npts(),
        "dt": s.dt(),
        "duration": s.end(),
        "pga_g": s.pga() / G,
        "pgv": standard_pgv(r),
        "pgv_table1": meta.and_then(|m| m.pgv_table1),
    })
}

/// The library `--records-dir` (or the default) names.
fn library(args: &RecordsArgs) -> anyhow::Result<Library> {
    if let Some(dir) = &args.records_dir {
        super::existing_records_dir(dir)?;
    }
    let dir = match &args.records_dir {
        Some(dir) => Some(dir.clone()),
        None => Library::checked_default_dir()?,
    };
    Ok(Library::open(dir)?)
}

/// The records named on the command line, or else every record of the library.
fn names(library: &Library, args: &RecordsArgs) -> Vec<String> {
    if args.records.is_empty() {
        library.names()
    } else {
        args.records.clone()
    }
}

/// The records as `records --ims` lists them (no suite pairs: RotD50 needs `--suite`).
fn listed(
    library: &Library,
    args: &RecordsArgs,
) -> anyhow::Result<Vec<super::records_ims::Listed>> {
    names(library, args)
        .iter()
        .map(|name| -> anyhow::Result<super::records_ims::Listed> {
            let record = library.load(name, args.baseline)?;
            Ok(super::records_ims::Listed {
                meta: row_json(&record),
                name: record.name.clone(),
                record,
                pair: None,
            })
        })
        .collect()
}

/// The named records (or every record of the library), and a line for each one that could
/// not be read.
fn load_all(library: &Library, args: &RecordsArgs) -> (Vec<std::sync::Arc<Record>>, Vec<String>) {
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    for name in names(library, args) {
        match library.load(&name, args.baseline) {
            Ok(r) => rows.push(r),
            Err(e) => failures.push(format!("{name}: {e}")),
        }
    }
    (rows, failures)
}

fn unreadable(failures: &[String]) -> anyhow::Result<()> {
    if failures.is_empty() {
        Ok(())
    } else {
        anyhow::bail!(
            "records that could not be read:\n  {}",
            failures.join("\n  ")
        )
    }
}

/// The JSON array `records --json` prints (a suite's with `--suite`): what Python's
/// `rocklab.records` returns as a table.
pub fn json(args: &RecordsArgs) -> anyhow::Result<serde_json::Value> {
    let library = library(args)?;
    if let Some(suite) = &args.suite {
        return super::records_suite::json_rows(&library, suite, args);
    }
    if args.ims {
        return super::records_ims::json(listed(&library, args)?, args);
    }
    let (rows, failures) = load_all(&library, args);
    unreadable(&failures)?;
    Ok(serde_json::Value::Array(
        rows.iter().map(|r| row_json(r)).collect(),
    ))
}

pub fn run(args: &RecordsArgs) -> anyhow::Result<()> {
    let library = library(args)?;
    if let Some(suite) = &args.suite {
        return super::records_suite::run(&library, suite, args);
    }
    if args.ims {
        return super::records_ims::run(listed(&library, args)?, args);
    }
    let (rows, failures) = load_all(&library, args);
    if args.json {
        let list: Vec<_> = rows.iter().map(|r| row_json(r)).collect();
        println!("{}", serde_json::Value::Array(list));
    } else {
        print!("{}", table(&library, &rows));
    }
    unreadable(&failures)
}

fn table(library: &Library, rows: &[std::sync::Arc<Record>]) -> String {
    let mut out = format!(
        "records directory: {}\n",
        library
            .dir()
            .map_or("(none; embedded records only)".to_string(), |d| d
                .display()
                .to_string())
    );
    out.push_str(
        "PGA (g) and PGV (m/s, standard gravity) are computed from the data; Tab1 PGV and Tp are the paper's Table 1.\n",
    );
    out.push_str(&format!(
        "{:<2} {:<19} {:<44} {:>6} {:>6} {:>7} {:>6} {:>6} {:>8} {:>5} {:<9} {}\n",
        "#",
        "name",
        "event, station",
        "npts",
        "dt s",
        "dur s",
        "PGA",
        "PGV",
        "Tab1 PGV",
        "Tp s",
        "source",
        "|a| envelope"
    ));
    for r in rows {
        let s = &r.series;
        let meta = r.meta.as_ref();
        let place = meta.map_or(String::new(), |m| {
            format!("{} {}, {}", m.event, m.year, m.station)
        });
        out.push_str(&format!(
            "{:<2} {:<19} {:<44} {:>6} {:>6} {:>7.2} {:>6.3} {:>6.3} {:>8} {:>5} {:<9} {}\n",
            meta.and_then(|m| m.table1)
                .map_or("-".into(), |n| n.to_string()),
            r.name,
            truncate(&place, 44),
            s.npts(),
            s.dt(),
            s.end(),
            s.pga() / G,
            standard_pgv(r),
            meta.and_then(|m| m.pgv_table1)
                .map_or("-".into(), |v| format!("{v:.2}")),
            meta.and_then(|m| m.tp)
                .map_or("-".into(), |v| format!("{v:.1}")),
            r.source.kind(),
            sparkline(s.samples(), 32),
        ));
    }
    for r in rows {
        out.push_str(&format!("{}: {}\n", r.name, r.source.label()));
    }
    out
}

pub(super) fn truncate(s: &str, width: usize) -> String {
    if s.chars().count() <= width {
        s.to_string()
    } else {
        let mut t: String = s.chars().take(width - 1).collect();
        t.push('…');
        t
    }
}
