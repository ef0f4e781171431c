//! fragility.csv (one row per variant × damage state, with the ratio to the bare variant) and
//! fragility.json (the whole report, read back by `rocklab plot` and the TUI).

use super::{Curve, FragilityReport, Variant};
use crate::error::Context;
use crate::report::write_atomic;
use std::path::Path;

pub const FRAGILITY_CSV: &str = "fragility.csv";
pub const FRAGILITY_JSON: &str = "fragility.json";

fn num(v: Option<f64>) -> String {
    v.map_or_else(String::new, |v| v.to_string())
}

type Cell = fn(&FragilityReport, &Curve) -> String;

/// The columns after `device` and the varying parameters: header and value, one table.
const COLUMNS: [(&str, Cell); 19] = [
    ("damage_state", |_, c| c.damage_state.to_string()),
    ("median", |_, c| num(c.median)),
    ("beta", |_, c| num(c.beta)),
    ("median_lo", |_, c| num(c.median_lo)),
    ("median_hi", |_, c| num(c.median_hi)),
    ("beta_lo", |_, c| num(c.beta_lo)),
    ("beta_hi", |_, c| num(c.beta_hi)),
    // With uncertain parameters: the fit over the deterministic companion scenes (records
    // alone), and the parameters' share √(β² − β_records²); empty otherwise.
    ("median_records", |_, c| num(c.median_records)),
    ("beta_records", |_, c| num(c.beta_records)),
    ("beta_parameters", |_, c| num(c.beta_parameters())),
    ("n_records", |_, c| c.n_records.to_string()),
    ("n_stripes", |_, c| c.n_stripes.to_string()),
    ("method", |_, c| c.method.name().to_string()),
    ("status", |_, c| c.status.name().to_string()),
    // Against the bare variant with the same parameters (empty for the bare one).
    ("median_ratio", |r, c| {
        num(r.ratio_of(c).and_then(|x| x.ratio))
    }),
    ("median_ratio_lo", |r, c| {
        num(r.ratio_of(c).and_then(|x| x.lo))
    }),
    ("median_ratio_hi", |r, c| {
        num(r.ratio_of(c).and_then(|x| x.hi))
    }),
    ("crosses_bare", |r, c| {
        r.ratio_of(c)
            .map_or_else(String::new, |x| x.curves_cross.to_string())
    }),
    // Why a fitted curve is doubtful (`Curve::warnings`), `;`-separated; empty if nothing.
    ("warnings", |_, c| c.warnings().join(";")),
];

/// The varying parameters' names over all curves, in order of first appearance.
pub fn parameter_names(report: &FragilityReport) -> Vec<String> {
    variant_parameter_names(report.curves.iter().map(|c| &c.variant))
}

/// The varying parameters' names over these variants, in order of first appearance.
pub fn variant_parameter_names<'a>(variants: impl Iterator<Item = &'a Variant>) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for v in variants {
        for (k, _) in &v.params {
            if !names.contains(k) {
                names.push(k.clone());
            }
        }
    }
    names
}

/// fragility.csv as bytes: device, each varying parameter, then [`COLUMNS`].
pub fn fragility_csv(report: &FragilityReport) -> crate::error::Result<Vec<u8>> {
    let params = parameter_names(report);
    let mut w = csv::Writer::from_writer(Vec::new());
    let header = std::iter::once("device")
        .chain(params.iter().map(String::as_str))
        .chain(COLUMNS.iter().map(|(h, _)| *h));
    w.write_record(header)?;
    for c in &report.curves {
        let mut row = vec![c.variant.device.clone()];
        for p in &params {
            let v = c.variant.params.iter().find(|(k, _)| k == p);
            row.push(num(v.map(|(_, v)| *v)));
        }
        row.extend(COLUMNS.iter().map(|(_, cell)| cell(report, c)));
        w.write_record(&row)?;
    }
    Ok(w.into_inner()?)
}

pub fn write_fragility_csv(report: &FragilityReport, path: &Path) -> crate::error::Result<()> {
    write_atomic(path, &fragility_csv(report)?)
}

pub fn write_fragility_json(report: &FragilityReport, path: &Path) -> crate::error::Result<()> {
    let mut bytes = serde_json::to_vec_pretty(report)?;
    bytes.push(b'\n');
    write_atomic(path, &bytes)
}

/// Read a fragility.json written by [`write_fragility_json`].
pub fn read_fragility_json(path: &Path) -> crate::error::Result<FragilityReport> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    serde_json::from_str(&text).map_err(|e| {
        crate::error::error!(
            "{}:{}:{}: not a fragility report: {e}\n  hint: rerun `rocklab run` on the study to rewrite it",
            path.display(),
            e.line(),
            e.column()
        )
    })
}

#[cfg(test)]
mod tests {
    use super::super::{FragilityOptions, FragilityReport, Variant, analyse_ida};
    use super::fragility_csv;
    use crate::stats::tests::{capacities, ida_obs, variant};

    #[test]
    fn csv_has_one_row_per_variant_and_state_with_the_contract_columns() {
        let bare = capacities(9, 30, 1.5, 0.45);
        let mut obs = ida_obs(&variant("none"), &bare, 2.0);
        obs.extend(ida_obs(&variant("inerter"), &bare, 2.0));
        obs.extend(ida_obs(
            &Variant {
                device: "none".into(),
                params: vec![("alpha".into(), 0.3)],
            },
            &[],
            2.0,
        ));
        let opts = FragilityOptions {
            damage_states: vec![1.0],
            bootstrap: 50,
            ..Default::default()
        };
        let report = analyse_ida(&obs, &opts);
        let text = String::from_utf8(fragility_csv(&report).unwrap()).unwrap();
        let mut lines = text.lines();
        assert_eq!(
            lines.next().unwrap(),
            "device,alpha,damage_state,median,beta,median_lo,median_hi,beta_lo,beta_hi,\
             median_records,beta_records,beta_parameters,n_records,n_stripes,method,status,median_ratio,median_ratio_lo,median_ratio_hi,crosses_bare,warnings"
        );
        let rows: Vec<&str> = lines.collect();
        assert_eq!(rows.len(), 2);
        assert!(rows[0].starts_with("none,0.2,1,"), "{}", rows[0]);
        assert!(rows[0].ends_with(",30,0,ida,fitted,,,,,"), "{}", rows[0]);
        // Identical capacities: the ratio is 1 in every resample, and equal curves do not cross.
        assert!(
            rows[1].ends_with(",30,0,ida,fitted,1,1,1,false,"),
            "{}",
            rows[1]
        );
        // The JSON round-trips.
        let json = serde_json::to_string(&report).unwrap();
        assert_eq!(
            serde_json::from_str::<FragilityReport>(&json).unwrap(),
            report
        );
    }
}
