//! An incremental dynamic analysis's outputs (a fragility section with `method: ida(…)`):
//! the hunts replayed from the results' scenes (`sweep::ida::replay`, so a results file alone
//! gives them back), `ida.csv` (one row per record × variant × damage state: capacity, final
//! bracket, probes, resurrections, censored), and once every hunt has finished the lognormal
//! fitted to the first-exceedance intensities with records that never reached a state
//! censored at the ladder's top (`fragility::analyse_ida`): fragility.csv and fragility.json
//! with method `ida`.

use super::fragility::{
    FRAGILITY_CSV, FRAGILITY_JSON, FragilityReport, IdaObservation, Variant, analyse_ida,
    write_fragility_csv, write_fragility_json,
};
use super::stripes::{component_of, csv_axes, name_axes, options, variant_of};
use crate::excitation::library;
use crate::scene::Excitation;
use crate::study::fragility::Fragility;
use crate::study::{ScenePoint, Study};
use crate::sweep::SweepResults;
use crate::sweep::hunt::StateResult;
use crate::sweep::ida::replay;
use std::path::Path;

pub const IDA_CSV: &str = "ida.csv";

/// One record × variant × damage state of an IDA.
#[derive(Clone, Debug, PartialEq)]
pub struct IdaRow {
    pub variant: Variant,
    pub record: String,
    pub component: String,
    pub damage_state: f64,
    pub result: StateResult,
    /// Scenes the record's hunt ran (shared by its damage states).
    pub probes: usize,
    pub top: f64,
    /// `done`, `failed` (a scene of the hunt failed: left out of the fit) or `incomplete`.
    pub status: &'static str,
}

/// The IDA of a study's results: its rows, the scenes it ran and the scenes the same ladder
/// takes as stripes.
pub struct Ida {
    pub rows: Vec<IdaRow>,
    pub scenes: usize,
    /// Scenes of the same ladder as stripes (every record × variant × level).
    pub stripe_scenes: usize,
    /// Scenes of stripes as fine as the IDA's resolution (from the ladder's bottom to its
    /// top in steps of the resolution, every record × variant).
    pub fine_stripe_scenes: usize,
    pub complete: bool,
}

/// The IDA rows of a study's results (the hunts replayed on its scenes).
pub fn ida(study: &Study, results: &SweepResults) -> crate::error::Result<Ida> {
    let search = replay(study, &results.outcomes).map_err(|e| crate::error::error!("{e}"))?;
    let layout = study.layout()?;
    let library = library::global().ok();
    let on_grid: Vec<&ScenePoint> = Vec::new();
    let mut rows = Vec::new();
    for r in search.records() {
        let record = match &r.nominal.scene.excitation {
            Excitation::Record { name, .. } => name.clone(),
            _ => String::new(),
        };
        let status = if r.failed {
            "failed"
        } else if r.done {
            "done"
        } else {
            "incomplete"
        };
        for (ds, result) in r.states {
            rows.push(IdaRow {
                variant: variant_of(&layout, &r.nominal, &on_grid),
                component: component_of(library, &record),
                record: record.clone(),
                damage_state: ds,
                result,
                probes: r.probes,
                top: r.top,
                status,
            });
        }
    }
    Ok(Ida {
        rows,
        scenes: results.outcomes.len(),
        stripe_scenes: search.stripe_scenes(),
        fine_stripe_scenes: search.fine_stripe_scenes(),
        complete: search.complete(),
    })
}

/// The fit of the finished hunts (failed and unfinished ones left out).
pub fn analyse(f: &Fragility, study: &Study, rows: &[IdaRow]) -> FragilityReport {
    let obs: Vec<IdaObservation> = rows
        .iter()
        .filter(|r| r.status == "done")
        .map(|r| IdaObservation {
            variant: r.variant.clone(),
            record: r.record.clone(),
            damage_state: r.damage_state,
            capacity_im: r.result.capacity,
            top_im: r.top,
            resurrections: r.result.resurrections.clone(),
        })
        .collect();
    let mut report = analyse_ida(&obs, &options(f));
    // Uncertain parameters: the capacities' β is the total (no companions run in an IDA).
    if let Some(u) = &study.uncertain {
        report.uncertainty = u.describe(true);
    }
    name_axes(&mut report, f, study);
    report
}

/// ida.csv: device, the varying parameters, record, component, damage_state, the IM's name,
/// capacity (empty if censored), the final bracket, probes, resurrections (count and the
/// intensities that held, `;`-separated), censored, status.
pub fn ida_csv(study: &Study, rows: &[IdaRow]) -> crate::error::Result<Vec<u8>> {
    let (params, im) = csv_axes(study, rows.iter().map(|r| &r.variant));
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header = vec!["device".to_string()];
    header.extend(params.iter().cloned());
    header.extend(
        [
            "record",
            "component",
            "damage_state",
            "im_measure",
            "capacity",
            "bracket_lo",
            "bracket_hi",
            "probes",
            "resurrections",
            "resurrected_at",
            "censored",
            "status",
        ]
        .map(String::from),
    );
    w.write_record(&header)?;
    for r in rows {
        let mut row = vec![r.variant.device.clone()];
        for p in &params {
            let v = r.variant.params.iter().find(|(k, _)| k == p);
            row.push(v.map_or_else(String::new, |(_, v)| v.to_string()));
        }
        let s = &r.result;
        row.extend([
            r.record.clone(),
            r.component.clone(),
            r.damage_state.to_string(),
            im.to_string(),
            s.capacity.map_or_else(String::new, |c| c.to_string()),
            s.lo.to_string(),
            s.hi.to_string(),
            r.probes.to_string(),
            s.resurrections.len().to_string(),
            s.resurrections
                .iter()
                .map(|(held, _)| held.to_string())
                .collect::<Vec<_>>()
                .join(";"),
            s.censored.to_string(),
            r.status.to_string(),
        ]);
        w.write_record(&row)?;
    }
    Ok(w.into_inner()?)
}

/// How many scenes the IDA ran against the same ladder as stripes, for the summary.
pub fn scenes_line(ida: &Ida) -> String {
    format!(
        "IDA: {} scenes (every probe of the hunts{}); as stripes, the same ladder takes {} \
         and a ladder as fine as the resolution {}\n",
        ida.scenes,
        if ida.complete { "" } else { ", unfinished" },
        ida.stripe_scenes,
        ida.fine_stripe_scenes,
    )
}

/// ida.csv of an IDA study, and fragility.csv / fragility.json once every hunt has finished.
pub fn write(out: &Path, study: &Study, results: &SweepResults) -> crate::error::Result<()> {
    let ida = ida(study, results)?;
    super::write_atomic(&out.join(IDA_CSV), &ida_csv(study, &ida.rows)?)?;
    let Some(report) = super::stripes::fit(study, results)? else {
        return Ok(());
    };
    write_fragility_csv(&report, &out.join(FRAGILITY_CSV))?;
    write_fragility_json(&report, &out.join(FRAGILITY_JSON))?;
    Ok(super::risk::write_section(out, study, results, &report)?)
}
