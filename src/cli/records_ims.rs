//! `rocklab records --ims`: every component's intensity measures (`excitation::ims`) beside
//! its metadata, as JSON (`--json`) or a text table; RotD50 where a suite record's two
//! components are both listed.

use super::records::RecordsArgs;
use crate::excitation::Record;
use crate::excitation::ims::{self, Accelerogram, Ims};
use rayon::prelude::*;
use std::sync::Arc;

/// One listed component: its JSON metadata, its record, and the key that pairs it with its
/// other horizontal component (suite set and record id), if any.
pub(super) struct Listed {
    pub meta: serde_json::Value,
    pub name: String,
    pub record: Arc<Record>,
    pub pair: Option<(String, u32)>,
}

/// The periods and damping `--ims` computes Sa at.
fn spectrum_options(args: &RecordsArgs) -> anyhow::Result<(Vec<f64>, f64)> {
    let periods = if args.periods.is_empty() {
        ims::DEFAULT_PERIODS.to_vec()
    } else {
        args.periods.clone()
    };
    if let Some(bad) = periods.iter().find(|t| !(t.is_finite() && **t > 0.0)) {
        anyhow::bail!("--periods: {bad} is not a period > 0 s (e.g. --periods 0.2,0.5,1.0)");
    }
    if !(0.0..1.0).contains(&args.damping) {
        anyhow::bail!(
            "--damping {}: a damping ratio in [0, 1), e.g. 0.05",
            args.damping
        );
    }
    Ok((periods, args.damping))
}

/// The IMs of every listed component (in parallel) and RotD50 of complete pairs.
fn compute(
    listed: &[Listed],
    periods: &[f64],
    damping: f64,
) -> anyhow::Result<Vec<(Ims, Option<Vec<f64>>)>> {
    let records: Vec<Accelerogram> = listed
        .iter()
        .map(|l| {
            Accelerogram::from_series(&l.record.series)
                .map_err(|e| anyhow::anyhow!("{}: {e}", l.name))
        })
        .collect::<anyhow::Result<_>>()?;
    let all: Vec<Ims> = records
        .par_iter()
        .zip(listed)
        .map(|(r, l)| Ims::of(r, periods, damping).map_err(|e| anyhow::anyhow!("{}: {e}", l.name)))
        .collect::<anyhow::Result<_>>()?;
    let partner = |i: usize| {
        let key = listed[i].pair.as_ref()?;
        let mates: Vec<usize> = (0..listed.len())
            .filter(|j| listed[*j].pair.as_ref() == Some(key))
            .collect();
        (mates.len() == 2).then(|| (mates[0], mates[1]))
    };
    let rotd: Vec<Option<Vec<f64>>> = (0..listed.len())
        .into_par_iter()
        .map(|i| match partner(i) {
            // Computed once per pair, at its first component, and copied to the second.
            // A pair whose components differ in dt or length (far_field/15: 2676 and 2300
            // samples) has no RotD50 (null), rather than failing the whole listing.
            Some((a, b)) if a == i => {
                match ims::spectrum::rotd50(&records[a], &records[b], periods, damping) {
                    Ok(v) => Ok(Some(v.iter().map(|s| s / ims::STANDARD_GRAVITY).collect())),
                    Err(ims::ImError::Pair(_)) => Ok(None),
                    Err(e) => Err(anyhow::anyhow!("{}: {e}", listed[i].name)),
                }
            }
            _ => Ok(None),
        })
        .collect::<anyhow::Result<_>>()?;
    let rotd: Vec<Option<Vec<f64>>> = (0..listed.len())
        .map(|i| match partner(i) {
            Some((a, _)) => rotd[a].clone(),
            None => None,
        })
        .collect();
    Ok(all.into_iter().zip(rotd).collect())
}

/// The JSON array `records --ims --json` prints: each record's metadata row with its
/// intensity measures (and `rotd50_g` where its suite pair is listed too).
pub(super) fn json(listed: Vec<Listed>, args: &RecordsArgs) -> anyhow::Result<serde_json::Value> {
    let (periods, damping) = spectrum_options(args)?;
    let rows = compute(&listed, &periods, damping)?;
    Ok(serde_json::Value::Array(
        listed
            .into_iter()
            .zip(rows)
            .map(|(l, (ims, rotd))| {
                let mut row = l.meta;
                if let (Some(obj), serde_json::Value::Object(extra)) = (
                    row.as_object_mut(),
                    serde_json::to_value(&ims).unwrap_or_default(),
                ) {
                    obj.extend(extra);
                    obj.insert("rotd50_g".into(), serde_json::json!(rotd));
                }
                row
            })
            .collect(),
    ))
}

pub(super) fn run(listed: Vec<Listed>, args: &RecordsArgs) -> anyhow::Result<()> {
    if args.json {
        println!("{}", json(listed, args)?);
        return Ok(());
    }
    let (periods, damping) = spectrum_options(args)?;
    let rows = compute(&listed, &periods, damping)?;
    print!("{}", table(&listed, &rows, &periods, damping));
    Ok(())
}

fn table(
    listed: &[Listed],
    rows: &[(Ims, Option<Vec<f64>>)],
    periods: &[f64],
    damping: f64,
) -> String {
    let mut out = format!(
        "intensity measures (g = {} m/s², records unscaled, from rest, no filtering); \
         Sa at ξ = {damping} in g; Tp only for pulse-like components\n",
        ims::STANDARD_GRAVITY
    );
    out.push_str(&format!(
        "{:<24} {:>6} {:>6} {:>6} {:>7} {:>6} {:>6} {:>6} {:>5} {:<5} {:>5}",
        "name", "PGA g", "PGV", "PGD m", "Arias", "CAV", "D5-75", "D5-95", "Tm", "pulse", "Tp s"
    ));
    for t in periods {
        out.push_str(&format!(" {:>8}", format!("Sa({t})")));
    }
    out.push('\n');
    for (l, (m, _)) in listed.iter().zip(rows) {
        out.push_str(&format!(
            "{:<24} {:>6.3} {:>6.3} {:>6.3} {:>7.3} {:>6.2} {:>6.2} {:>6.2} {:>5} {:<5} {:>5}",
            super::records::truncate(&l.name, 24),
            m.pga_g,
            m.pgv_m_s,
            m.pgd_m,
            m.arias_m_s,
            m.cav_m_s,
            m.d5_75_s,
            m.d5_95_s,
            m.tm_s.map_or("-".into(), |t| format!("{t:.2}")),
            if m.pulse_like { "yes" } else { "no" },
            m.tp_s.map_or("-".into(), |t| format!("{t:.2}")),
        ));
        for s in &m.sa_g {
            out.push_str(&format!(" {s:>8.3}"));
        }
        out.push('\n');
    }
    out
}
