//! Sweep results to files: a tidy long CSV, a JSON results file (study, hash, every scene with
//! its result, spectra, maps) and a plain-text summary with sparklines.

use super::aggregate::{OverturningMap, Spectrum, maps, quantities, sparkline, spectra};
use crate::numfmt::{fmt_num, fmt_sig};
use crate::study::{Param, StudyKind};
use crate::sweep::SweepResults;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

/// Spectra and maps stored next to the results for readers outside rocklab.
#[derive(Serialize)]
struct Derived {
    spectra: Vec<Spectrum>,
    maps: Vec<OverturningMap>,
    /// Records that ran as stand-ins ([`stand_in_records`]); absent when none did.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    stand_in_records: Vec<String>,
}

pub fn results_json(results: &SweepResults) -> crate::error::Result<Vec<u8>> {
    let derived = Derived {
        spectra: spectra(results),
        maps: maps(results),
        stand_in_records: stand_in_records(results),
    };
    crate::sweep::results_file_json(results, &derived)
}

pub fn save_results(path: &Path, results: &SweepResults) -> crate::error::Result<()> {
    super::write_atomic(path, &results_json(results)?)
}

/// CSV (with its column sidecar), summary and the canonical study next to the results file
/// (`rocklab run`, `merge` and the workbench's runs write the same set).
/// The overturning boundary of a study with a map, beside its results.
pub const BOUNDARY_CSV: &str = "boundary.csv";
/// A design study's answers, beside its results.
pub const DESIGN_CSV: &str = "design.csv";

pub fn write_tables(
    out: &Path,
    study: &crate::study::Study,
    results: &SweepResults,
) -> crate::error::Result<()> {
    super::write_atomic(&out.join("results.csv"), &results_csv(results)?)?;
    super::write_atomic(
        &out.join("results.columns.csv"),
        &results_columns_csv(results)?,
    )?;
    super::write_atomic(
        &out.join("summary.txt"),
        study_summary(study, results)?.as_bytes(),
    )?;
    if study.map.is_some() {
        super::write_atomic(&out.join(BOUNDARY_CSV), &boundary_csv(results)?)?;
    }
    if let Some(rows) = super::design::design_rows(results) {
        super::write_atomic(
            &out.join(DESIGN_CSV),
            &super::design::design_csv(study, &rows)?,
        )?;
    }
    // A fragility study's stripes.csv, and its fit once every scene has run.
    super::stripes::write(out, study, results)?;
    Ok(study.save(&out.join("study.ron"))?)
}

/// [`summary`] and what the study's analyses add: an IDA's scene count and a fragility
/// study's fitted medians (summary.txt, and what `rocklab run` prints).
pub fn study_summary(
    study: &crate::study::Study,
    results: &SweepResults,
) -> crate::error::Result<String> {
    let mut text = summary(results);
    if study.kind() == StudyKind::Ida {
        text.push_str(&super::ida::scenes_line(&super::ida::ida(study, results)?));
    }
    // A design's probes are no fragility study of their own: its answers are its summary
    // (design.csv), not a fitted curve per probed device.
    if study.kind() != StudyKind::Design
        && let Some(report) = super::stripes::fit(study, results)?
    {
        text.push_str(&super::fragility::summary_text(&report));
    }
    Ok(text)
}

/// The overturning boundary of every map: one row per pair of neighbouring grid cells where
/// one overturned and the other survived, at the midpoint of the pair (`between` says along
/// which axis the pair lies). Inferred cells of an adaptive map count like run ones.
pub fn boundary_csv(results: &SweepResults) -> crate::error::Result<Vec<u8>> {
    let maps = maps(results);
    let mut w = csv::Writer::from_writer(Vec::new());
    let names = |m: &OverturningMap| (parameter(&m.x_axis).name, parameter(&m.y_axis).name);
    match maps.first().map(names) {
        Some((x, y)) => w.write_record(["map", x.as_str(), y.as_str(), "between"])?,
        None => w.write_record(["map", "x", "y", "between"])?,
    }
    for m in &maps {
        for (x, y, along) in m.boundary() {
            w.write_record([
                m.label.clone(),
                format!("{x}"),
                format!("{y}"),
                along.to_string(),
            ])?;
        }
    }
    Ok(w.into_inner()?)
}

/// A coordinate of the study in files other tools read: an ASCII identifier (valid in MATLAB,
/// pandas and R without renaming), the study file's field name and the unit.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    pub name: String,
    pub field: &'static str,
    pub unit: &'static str,
}

/// The ASCII name, study field and unit of a coordinate label (`ωg/p`, `kθ`, `up`, …), from
/// the parameter table ([`Param::info`]). A label that names no parameter (a derived axis
/// such as `θ0/α`) has no field or unit and gets an ASCII identifier spelt from it.
pub fn parameter(label: &str) -> Parameter {
    match Param::from_label(label) {
        Some(param) => {
            let info = param.info();
            Parameter {
                name: info.name.into(),
                field: info.field,
                unit: info.unit,
            }
        }
        None => Parameter {
            name: ascii_identifier(label),
            field: "",
            unit: "",
        },
    }
}

/// A fallback ASCII identifier for a label no table knows: Greek letters spelt out, anything
/// else an underscore, never starting with a digit.
fn ascii_identifier(label: &str) -> String {
    let mut out = String::new();
    for c in label.chars() {
        let spelt = match c {
            'α' => "alpha",
            'θ' => "theta",
            'ω' => "omega",
            'ξ' => "xi",
            'μ' => "mu",
            'σ' => "sigma",
            'ρ' => "rho",
            'ε' => "epsilon",
            'η' => "eta",
            c if c.is_ascii_alphanumeric() => {
                out.push(c.to_ascii_lowercase());
                continue;
            }
            _ => "_",
        };
        if spelt != "_" && !out.is_empty() && !out.ends_with('_') {
            out.push('_');
        }
        out.push_str(spelt);
    }
    let trimmed: Vec<&str> = out.split('_').filter(|p| !p.is_empty()).collect();
    let s = trimmed.join("_");
    if s.is_empty() || s.starts_with(|c: char| c.is_ascii_digit()) {
        format!("x_{s}")
    } else {
        s
    }
}

/// The varying coordinates of the results, in order of first appearance.
fn axes_of(results: &SweepResults) -> Vec<String> {
    let mut axes: Vec<String> = Vec::new();
    for o in &results.outcomes {
        for (name, _) in &o.point.coords {
            if !axes.contains(name) {
                axes.push(name.clone());
            }
        }
    }
    axes
}

/// An uncertain study's parameters as results.csv columns (after `draw`): each parameter
/// with the value its deterministic companions take (study/uncertain); empty otherwise.
fn uncertain_columns(results: &SweepResults) -> Vec<(crate::study::Param, f64)> {
    (results.study.iter())
        .filter_map(|s| s.uncertain.as_ref())
        .flat_map(|u| u.parameters())
        .map(|(p, d)| (p, d.centre()))
        .collect()
}

/// A scene's `draw` and uncertain-parameter cells: its draw's place and drawn values, or
/// `nominal` and the centres for a deterministic companion.
fn uncertain_cells(
    point: &crate::study::ScenePoint,
    columns: &[(crate::study::Param, f64)],
) -> Vec<String> {
    use crate::study::uncertain::Sample;
    match &point.uncertain {
        Some(Sample::Drawn { draw, values }) => std::iter::once(draw.to_string())
            .chain(columns.iter().map(|(p, _)| {
                (values.iter())
                    .find(|(name, _)| name == p.info().name)
                    .map_or_else(String::new, |(_, v)| v.to_string())
            }))
            .collect(),
        Some(Sample::Companion { .. }) => std::iter::once("nominal".to_string())
            .chain(columns.iter().map(|(_, centre)| centre.to_string()))
            .collect(),
        None => vec![String::new(); columns.len() + 1],
    }
}

/// The description of results.csv's `draw` column.
const DRAW_COLUMN: (&str, &str) = (
    "draw",
    "uncertain parameters: the scene's draw (its place on the record × stripe grid), or \
     nominal for a drawn scene's deterministic companion",
);

/// Column layout of the results CSV.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CsvLayout {
    /// Tidy: one row per scene and quantity (`quantity`, `value`).
    #[default]
    Long,
    /// One row per scene, one column per quantity.
    Wide,
}

const ID_COLUMNS: [(&str, &str, &str); 6] = [
    ("scene", "index of the scene in the study's expansion", ""),
    (
        "key",
        "cache key: hash of the scene and solver settings",
        "",
    ),
    (
        "group",
        "variant label (device and grid parameters, paper notation)",
        "",
    ),
    ("device", "device kind", ""),
    ("excitation", "record name or pulse shape", ""),
    (
        "record_source",
        "where a record's samples come from: file, embedded, or stand-in (a \
         Mavroeidis–Papageorgiou pulse fitted to Table 1, not the real ground motion); empty \
         for pulses",
        "",
    ),
];

const STATUS_COLUMNS: [(&str, &str, &str); 2] = [
    (
        "overturned",
        "whether the structure overturned (its peaks are then left empty)",
        "",
    ),
    ("status", "ok, or failed: reason", ""),
];

/// The results CSV: ASCII identifier column names only (a MATLAB `readtable`, pandas
/// `read_csv` or R `read.csv` reads it with no option or renaming); the paper's Unicode
/// labels and units are in [`results_columns_csv`].
pub fn results_csv(results: &SweepResults) -> crate::error::Result<Vec<u8>> {
    results_csv_layout(results, CsvLayout::Long)
}

pub fn results_csv_layout(
    results: &SweepResults,
    layout: CsvLayout,
) -> crate::error::Result<Vec<u8>> {
    let axes = axes_of(results);
    let quantities = quantities(results);
    let mut w = csv::Writer::from_writer(Vec::new());
    let sources = record_sources(results);
    let mut header: Vec<String> = ID_COLUMNS.iter().map(|c| c.0.to_string()).collect();
    header.extend(axes.iter().map(|a| parameter(a).name));
    let uncertain = uncertain_columns(results);
    if !uncertain.is_empty() {
        header.push(DRAW_COLUMN.0.to_string());
        header.extend(uncertain.iter().map(|(p, _)| p.info().name.to_string()));
    }
    match layout {
        CsvLayout::Long => header.extend(["quantity", "value"].map(String::from)),
        CsvLayout::Wide => header.extend(quantities.iter().map(|q| q.name().to_string())),
    }
    header.extend(STATUS_COLUMNS.iter().map(|c| c.0.to_string()));
    w.write_record(&header)?;
    for o in &results.outcomes {
        let mut ids = vec![
            o.point.index.to_string(),
            o.point.key.clone(),
            o.point.group.clone(),
            o.point.scene.device.name().to_string(),
            excitation_name(&o.point.scene.excitation),
            record_source(&o.point.scene.excitation, &sources),
        ];
        for axis in &axes {
            ids.push(
                o.point
                    .coord(axis)
                    .map(|v| format!("{v}"))
                    .unwrap_or_default(),
            );
        }
        if !uncertain.is_empty() {
            ids.extend(uncertain_cells(&o.point, &uncertain));
        }
        let value = |q: &crate::report::Quantity| match &o.result {
            Ok(r) => q.of(r).map(|v| format!("{v:.9e}")).unwrap_or_default(),
            Err(_) => String::new(),
        };
        let status = match &o.result {
            Ok(r) => vec![r.overturned.to_string(), "ok".into()],
            Err(reason) => vec![String::new(), format!("failed: {reason}")],
        };
        match layout {
            CsvLayout::Long => {
                for q in &quantities {
                    let mut row = ids.clone();
                    row.extend([q.name().to_string(), value(q)]);
                    row.extend(status.iter().cloned());
                    w.write_record(&row)?;
                }
            }
            CsvLayout::Wide => {
                let mut row = ids;
                row.extend(quantities.iter().map(value));
                row.extend(status);
                w.write_record(&row)?;
            }
        }
    }
    Ok(w.into_inner()?)
}

/// The results CSV's coordinate columns (one per study axis), after its id columns.
pub fn axis_columns(results: &SweepResults) -> Vec<String> {
    axes_of(results).iter().map(|a| parameter(a).name).collect()
}

/// The metadata of the results CSV's columns, itself a CSV any tool reads: `name` (the column
/// in results.csv), `label` (the paper's notation), `unit`, `description`.
pub fn results_columns_csv(results: &SweepResults) -> crate::error::Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(["name", "label", "unit", "description"])?;
    for (name, description, unit) in ID_COLUMNS {
        w.write_record([name, name, unit, description])?;
    }
    for axis in axes_of(results) {
        let p = parameter(&axis);
        let description = if p.field.is_empty() {
            "study coordinate".to_string()
        } else {
            format!("study coordinate (field `{}` in the study file)", p.field)
        };
        w.write_record([p.name.as_str(), axis.as_str(), p.unit, description.as_str()])?;
    }
    let uncertain = uncertain_columns(results);
    if !uncertain.is_empty() {
        w.write_record([DRAW_COLUMN.0, DRAW_COLUMN.0, "", DRAW_COLUMN.1])?;
    }
    for (p, _) in uncertain {
        let info = p.info();
        let description = format!(
            "uncertain parameter: the value drawn for the scene (field `{}` of the study's \
             uncertain section)",
            info.field
        );
        w.write_record([info.name, info.label, info.unit, description.as_str()])?;
    }
    w.write_record([
        "quantity",
        "quantity",
        "",
        "response quantity (long layout)",
    ])?;
    w.write_record([
        "value",
        "value",
        "",
        "the quantity's value (long layout; unit below)",
    ])?;
    for q in quantities(results) {
        w.write_record([q.name(), q.label(), q.info().unit, "response quantity"])?;
    }
    for (name, description, unit) in STATUS_COLUMNS {
        w.write_record([name, name, unit, description])?;
    }
    Ok(w.into_inner()?)
}

/// Plain-text summary: counts, one sparkline per spectrum, maps as character grids.
pub fn summary(results: &SweepResults) -> String {
    let mut s = String::new();
    let name = results
        .study
        .as_ref()
        .map_or("(points)", |s| s.name.as_str());
    let failed = results
        .outcomes
        .iter()
        .filter(|o| o.result.is_err())
        .count();
    let overturned = results
        .outcomes
        .iter()
        .filter(|o| o.result.as_ref().is_ok_and(|r| r.overturned))
        .count();
    let _ = writeln!(
        s,
        "study {name} (hash {}): {} scenes, {overturned} overturned, {failed} failed{}",
        results.study_hash,
        results.outcomes.len(),
        if results.cancelled {
            ", INCOMPLETE (cancelled or missing shards)"
        } else {
            ""
        }
    );
    let stand_ins = stand_in_records(results);
    if !stand_ins.is_empty() {
        let _ = writeln!(
            s,
            "{}: {}",
            crate::excitation::library::STAND_IN_NOTE,
            stand_ins.join(", ")
        );
    }
    for o in results
        .outcomes
        .iter()
        .filter(|o| o.result.is_err())
        .take(5)
    {
        let _ = writeln!(
            s,
            "  failed scene {} ({}): {}",
            o.point.index,
            o.point.group,
            o.result.as_ref().err().map_or("", |e| e.as_str())
        );
    }
    if let (Some(study), Some(rows)) = (&results.study, super::design::design_rows(results)) {
        let distinct: std::collections::HashSet<&str> = results
            .outcomes
            .iter()
            .map(|o| o.point.key.as_str())
            .collect();
        s.push_str(&super::design::design_summary(study, &rows, distinct.len()));
        return s;
    }
    let mut spectra = spectra(results);
    // Maps over a fine amplitude grid make hundreds of spectra: show the first few per quantity.
    const SHOWN: usize = 24;
    let mut hidden = 0;
    let mut seen: Vec<(crate::report::Quantity, usize)> = Vec::new();
    spectra.retain(|sp| {
        let count = match seen.iter_mut().find(|(q, _)| *q == sp.quantity) {
            Some((_, n)) => {
                *n += 1;
                *n
            }
            None => {
                seen.push((sp.quantity, 1));
                1
            }
        };
        if count > SHOWN {
            hidden += 1;
        }
        count <= SHOWN
    });
    let width = spectra
        .iter()
        .map(|sp| sp.label.chars().count())
        .max()
        .unwrap_or(0);
    let mut last_q = None;
    for sp in &spectra {
        if last_q != Some(sp.quantity) {
            let (lo, hi) = (sp.xs.first(), sp.xs.last());
            let _ = writeln!(
                s,
                "\n{} over {} ({} … {}); blank = overturned or failed",
                sp.quantity.label(),
                sp.axis,
                lo.map_or(String::new(), |v| fmt_num(*v)),
                hi.map_or(String::new(), |v| fmt_num(*v))
            );
            last_q = Some(sp.quantity);
        }
        let peak = sp
            .xs
            .iter()
            .zip(&sp.ys)
            .filter_map(|(x, y)| y.map(|y| (*x, y)))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let peak = peak.map_or("—".to_string(), |(x, y)| {
            format!("max {} at {}={}", fmt_sig(y), sp.axis, fmt_num(x))
        });
        let _ = writeln!(
            s,
            "  {:width$}  {}  {peak}",
            sp.label,
            sparkline(&sp.ys),
            width = width
        );
    }
    if hidden > 0 {
        let _ = writeln!(
            s,
            "  … {hidden} more spectra in results.csv / results.json (`rocklab plot` draws up to 12 per panel; pick with --select, split with --facet)"
        );
    }
    s.push_str(&super::compare::suite_summary(
        results,
        &super::aggregate::spectra(results),
    ));
    let maps = maps(results);
    let maps_empty = maps.is_empty();
    const MAPS_SHOWN: usize = 6;
    if maps.len() > MAPS_SHOWN {
        let _ = writeln!(
            s,
            "\n{} overturning maps; the first {MAPS_SHOWN} follow (`rocklab plot` draws up to 12 in one figure; pick with --select)",
            maps.len()
        );
    }
    if !results.inferred.is_empty() {
        let _ = writeln!(
            s,
            "\nadaptive maps: {} scenes run, {} cells inferred by refinement (results.json \
             `inferred`; boundary.csv has the boundary)",
            results.outcomes.len(),
            results.inferred.len()
        );
    }
    for m in maps.into_iter().take(MAPS_SHOWN) {
        let _ = writeln!(
            s,
            "\noverturning map, {}: {} (→) × {} (↑); █ overturned, · safe, ? missing",
            m.label, m.x_axis, m.y_axis
        );
        for (iy, row) in m.cells.iter().enumerate().rev() {
            let line: String = row
                .iter()
                .map(|c| match c {
                    Some(true) => '█',
                    Some(false) => '·',
                    None => '?',
                })
                .collect();
            let _ = writeln!(s, "  {:>8} {line}", fmt_num(m.ys[iy]));
        }
    }
    let _ = writeln!(
        s,
        "\n{}",
        plot_note(spectra_per_quantity(results), !maps_empty)
    );

    s
}

/// Series per quantity: what one panel of `rocklab plot` would hold.
fn spectra_per_quantity(results: &SweepResults) -> usize {
    let spectra = spectra(results);
    let first = spectra.first().map(|s| s.quantity);
    spectra.iter().filter(|s| Some(s.quantity) == first).count()
}

/// What `rocklab plot` draws from these results, in the summary's words.
fn plot_note(series: usize, has_maps: bool) -> String {
    let max = super::plot::MAX_SERIES;
    let spectra = if series == 0 {
        "no spectra".to_string()
    } else if series <= max {
        format!("the spectra as one figure, a panel per quantity ({series} series each)")
    } else {
        format!(
            "no spectra unless chosen: {series} series per quantity is more than {max} per \
             panel (pick with --select, split with --facet)"
        )
    };
    let maps = if has_maps {
        " and the overturning maps"
    } else {
        ""
    };
    format!(
        "figures: `rocklab plot DIR --png FIGS` draws {spectra}{maps}; results.csv has every \
         scene (`rocklab table DIR --wide`: one column per quantity)"
    )
}

/// Where each record of `results` comes from in the records library of this process
/// ([`crate::excitation::library::Source::kind`]: file, embedded, stand-in), by name.
fn record_sources(results: &SweepResults) -> std::collections::BTreeMap<String, &'static str> {
    let library = crate::excitation::library::global().ok();
    let mut out = std::collections::BTreeMap::new();
    for o in &results.outcomes {
        if let crate::scene::Excitation::Record { name, .. } = &o.point.scene.excitation
            && !out.contains_key(name)
        {
            let kind = library
                .and_then(|l| l.load(name, false).ok())
                .map_or("unknown", |r| r.source.kind());
            out.insert(name.clone(), kind);
        }
    }
    out
}

/// The records of `results` that run as stand-ins, sorted: every output flags them
/// ([`crate::excitation::library::STAND_IN_NOTE`]).
pub fn stand_in_records(results: &SweepResults) -> Vec<String> {
    record_sources(results)
        .into_iter()
        .filter(|(_, kind)| *kind == "stand-in")
        .map(|(name, _)| name)
        .collect()
}

/// The `record_source` column: the record's source kind, empty for pulses.
fn record_source(
    e: &crate::scene::Excitation,
    sources: &std::collections::BTreeMap<String, &'static str>,
) -> String {
    match e {
        crate::scene::Excitation::Record { name, .. } => {
            sources.get(name).copied().unwrap_or("unknown").into()
        }
        _ => String::new(),
    }
}

/// The record's name, or the pulse's shape: the categorical part of the excitation.
fn excitation_name(e: &crate::scene::Excitation) -> String {
    use crate::scene::Excitation;
    match e {
        Excitation::Record { name, .. } => name.clone(),
        Excitation::Pulse { shape, .. } => ron::to_string(shape).unwrap_or_default(),
        Excitation::MpPulse { .. } => "mp_pulse".into(),
    }
}
