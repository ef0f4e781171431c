//! `rocklab records --suite NAME`: the components of a record suite with their metadata
//! (`index.csv`) and the npts, dt, PGA and PGV rocklab computes from the data.

use super::records::{RecordsArgs, row_json, standard_pgv, truncate};
use crate::excitation::suite::{SuiteRecord, SuiteSelect};
use crate::excitation::{G, Library, Record};
use std::sync::Arc;

/// The suite's records with their metadata, in the suite's order.
fn load<'a>(
    library: &'a Library,
    suite: &str,
    args: &RecordsArgs,
) -> anyhow::Result<Vec<(Option<&'a SuiteRecord>, Arc<Record>)>> {
    let select = SuiteSelect {
        name: suite.to_string(),
        ..SuiteSelect::default()
    };
    let names = library.suite(&select)?;
    let mut rows = Vec::new();
    for name in &names {
        rows.push((
            library.suite_entry(name),
            library.load(name, args.baseline)?,
        ));
    }
    Ok(rows)
}

/// The suite's components as `records --ims` lists them: metadata, name and suite pair.
fn listed(rows: Vec<(Option<&SuiteRecord>, Arc<Record>)>) -> Vec<super::records_ims::Listed> {
    rows.into_iter()
        .map(|(entry, record)| super::records_ims::Listed {
            meta: json(entry, &record),
            name: entry.map_or_else(|| record.name.clone(), SuiteRecord::id),
            pair: entry.map(|e| (e.set.name().to_string(), e.row.record_id)),
            record,
        })
        .collect()
}

/// The JSON array `records --suite NAME --json [--ims]` prints.
pub fn json_rows(
    library: &Library,
    suite: &str,
    args: &RecordsArgs,
) -> anyhow::Result<serde_json::Value> {
    let rows = load(library, suite, args)?;
    if args.ims {
        return super::records_ims::json(listed(rows), args);
    }
    Ok(rows_json(&rows))
}

fn rows_json(rows: &[(Option<&SuiteRecord>, Arc<Record>)]) -> serde_json::Value {
    serde_json::Value::Array(rows.iter().map(|(e, r)| json(*e, r)).collect())
}

pub fn run(library: &Library, suite: &str, args: &RecordsArgs) -> anyhow::Result<()> {
    let rows = load(library, suite, args)?;
    if args.ims {
        return super::records_ims::run(listed(rows), args);
    }
    if args.json {
        println!("{}", rows_json(&rows));
    } else {
        print!("{}", table(suite, &rows));
    }
    Ok(())
}

fn json(entry: Option<&SuiteRecord>, r: &Record) -> serde_json::Value {
    let Some(e) = entry else {
        return row_json(r);
    };
    let s = &r.series;
    let m = &e.row;
    serde_json::json!({
        "name": e.id(),
        "set": e.set.name(),
        "record_id": m.record_id,
        "component": m.component,
        "component_name": m.component_name,
        "pulse": e.set.pulse(),
        "nga": m.rsn,
        "event": m.earthquake,
        "year": m.year,
        "station": m.station,
        "mw": m.magnitude,
        "vs30": m.vs30,
        "site_class": m.nehrp_class,
        "fault_type": m.fault_type,
        "normalization_factor": m.normalization_factor,
        "file": e.path(),
        "sha256": m.sha256,
        "source": r.source.kind(),
        "npts": s.npts(),
        "dt": s.dt(),
        "duration": s.end(),
        "pga_g": s.pga() / G,
        "pgv": standard_pgv(r),
        "index_npts": m.npts,
        "index_dt": m.dt,
        "index_pga_g": m.pga_g,
        "index_pgv": m.pgv_m_s,
    })
}

fn table(suite: &str, rows: &[(Option<&SuiteRecord>, Arc<Record>)]) -> String {
    let mut out = format!(
        "suite {suite}: {} components. PGA (g) and PGV (m/s) computed from the data (g = {}); \
         FEMA NF = the FEMA P695 normalisation factor (`scale_to: fema`).\n",
        rows.len(),
        crate::excitation::ims::STANDARD_GRAVITY
    );
    out.push_str(&format!(
        "{:<24} {:>5} {:<36} {:>4} {:>5} {:<2} {:<18} {:>6} {:>6} {:>6} {:>6} {:>6} {:>5} {:<5}\n",
        "name",
        "RSN",
        "event year, station",
        "Mw",
        "Vs30",
        "cl",
        "fault",
        "npts",
        "dt s",
        "dur s",
        "PGA",
        "PGV",
        "NF",
        "pulse"
    ));
    for (entry, r) in rows {
        let s = &r.series;
        let line = match entry {
            Some(e) => {
                let m = &e.row;
                format!(
                    "{:<24} {:>5} {:<36} {:>4.1} {:>5.0} {:<2} {:<18} {:>6} {:>6} {:>6.1} {:>6.3} {:>6.3} {:>5.2} {:<5}\n",
                    e.id(),
                    m.rsn,
                    truncate(&format!("{} {}, {}", m.earthquake, m.year, m.station), 36),
                    m.magnitude,
                    m.vs30,
                    m.nehrp_class,
                    truncate(&m.fault_type, 18),
                    s.npts(),
                    s.dt(),
                    s.end(),
                    s.pga() / G,
                    standard_pgv(r),
                    m.normalization_factor,
                    e.set.pulse().map_or("-", |p| if p { "yes" } else { "no" }),
                )
            }
            None => {
                let meta = r.meta.as_ref();
                format!(
                    "{:<24} {:>5} {:<36} {:>4} {:>5} {:<2} {:<18} {:>6} {:>6} {:>6.1} {:>6.3} {:>6.3} {:>5} {:<5}\n",
                    r.name,
                    meta.and_then(|m| m.nga)
                        .map_or("-".into(), |n| n.to_string()),
                    truncate(
                        &meta.map_or(String::new(), |m| format!(
                            "{} {}, {}",
                            m.event, m.year, m.station
                        )),
                        36
                    ),
                    meta.map_or("-".into(), |m| format!("{:.1}", m.mw)),
                    "-",
                    "-",
                    "-",
                    s.npts(),
                    s.dt(),
                    s.end(),
                    s.pga() / G,
                    standard_pgv(r),
                    "-",
                    // Table 1's records are the paper's pulse-like set.
                    if meta.and_then(|m| m.table1).is_some() {
                        "yes"
                    } else {
                        "-"
                    },
                )
            }
        };
        out.push_str(&line);
    }
    out
}
