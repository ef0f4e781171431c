//! The paper's claims, every one of the results sections (§2–§8) and the conclusions (§9),
//! rerun against rocklab one row each: `rocklab paper` prints them as PAPER.md, `rocklab paper
//! --json` as one object per row, and tests/paper.rs asserts each row's numbers.
//!
//! Seams: [`claims`] is the table of quotes (id, figure, the sentence in full); [`fair`] holds
//! the one check per kind of claim that every row of that kind uses; [`runs`] runs (and caches)
//! the scenes rows share, histories resampled as `simulate --history` writes them;
//! `histories` reads forces, contacts and jumps off them; the row modules measure; [`render`]
//! writes the markdown.

mod claims;
pub mod fair;
mod histories;
mod render;
mod rows_clutch_settings;
mod rows_flexible;
mod rows_mechanisms;
mod rows_records;
mod rows_rigid;
pub mod runs;

pub use render::{counts, markdown};

use serde::Serialize;

/// What rocklab finds for a claim: how far it agrees. Serialized under the JSON key `verdict`
/// (issue 27's field list); the type is not called Verdict because the crate uses that word
/// for other things (a sweep cell's, a design scene's).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Agreement {
    Agrees,
    /// Same direction, short of the claim's strength; the row's reason states the gap.
    Roughly,
    Disagrees,
    /// Cannot be checked here; the row's reason says why.
    Untestable,
}

impl Agreement {
    pub const ALL: [Agreement; 4] = [
        Agreement::Agrees,
        Agreement::Roughly,
        Agreement::Disagrees,
        Agreement::Untestable,
    ];

    pub fn label(self) -> &'static str {
        match self {
            Agreement::Agrees => "agrees",
            Agreement::Roughly => "roughly",
            Agreement::Disagrees => "disagrees",
            Agreement::Untestable => "untestable",
        }
    }
}

/// One claim and what rocklab measures for it.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// Stable name, e.g. `fig12-trend`.
    pub id: &'static str,
    pub figure: &'static str,
    /// The paper's sentence, quoted in full.
    pub claim: &'static str,
    /// The fair check of the claim's kind, with the scenes it runs.
    pub check: String,
    /// The measured numbers, by name.
    #[serde(serialize_with = "values_as_object")]
    pub values: Vec<(String, f64)>,
    pub verdict: Agreement,
    /// The gap (roughly), the measured reason (disagrees), why not (untestable), or the
    /// disclosed choices (agrees).
    pub reason: String,
}

fn values_as_object<S: serde::Serializer>(v: &[(String, f64)], s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeMap;
    let mut m = s.serialize_map(Some(v.len()))?;
    for (k, x) in v {
        // JSON has no NaN: a value that does not exist (an overturned scene) is null.
        m.serialize_entry(k, &x.is_finite().then_some(*x))?;
    }
    m.end()
}

impl Row {
    /// The value named `name` (tests read rows' numbers by name).
    pub fn value(&self, name: &str) -> Option<f64> {
        self.values.iter().find(|(k, _)| k == name).map(|(_, x)| *x)
    }
}

/// How one row is measured.
type Measure = fn() -> crate::error::Result<Row>;

/// Every row, in the paper's order: the claim table's ids paired with their measurements.
fn measures() -> Vec<Measure> {
    let mut v = rows_rigid::ROWS.to_vec();
    v.extend(rows_mechanisms::ROWS);
    v.extend(rows_flexible::ROWS);
    v.extend(rows_clutch_settings::ROWS);
    v.extend(rows_records::ROWS);
    v
}

/// Run every row (or those whose id or figure contains `only`).
pub fn rows(only: Option<&str>) -> crate::error::Result<Vec<Row>> {
    let mut out = Vec::new();
    for (claim, measure) in claims::CLAIMS.iter().zip(measures()) {
        if only.is_some_and(|o| !claim.id.contains(o) && !claim.figure.contains(o)) {
            continue;
        }
        let row = measure()?;
        crate::error::ensure!(
            row.id == claim.id,
            "paper: row {} measured for claim {}",
            row.id,
            claim.id
        );
        out.push(row);
    }
    Ok(out)
}

/// The row with this id.
pub fn row(id: &str) -> crate::error::Result<Row> {
    let i = claims::CLAIMS
        .iter()
        .position(|c| c.id == id)
        .ok_or_else(|| crate::error::error!("paper: no claim {id}"))?;
    measures()[i]()
}

/// Number of claims in the table.
pub fn claim_count() -> usize {
    claims::CLAIMS.len()
}

/// Ids in the table, in order.
pub fn claim_ids() -> Vec<&'static str> {
    claims::CLAIMS.iter().map(|c| c.id).collect()
}

/// The JSON `rocklab paper --json` prints: one object per row.
pub fn json(rows: &[Row]) -> crate::error::Result<String> {
    Ok(serde_json::to_string_pretty(rows)?)
}

/// A row of the claim table measured with the judgement of its fair check.
fn judged(id: &'static str, j: fair::Judgement, reason: impl Into<String>) -> Row {
    let c = claims::get(id);
    let mut reason = reason.into();
    if !j.gap.is_empty() {
        reason = if reason.is_empty() {
            j.gap
        } else {
            format!("{}; {reason}", j.gap)
        };
    }
    Row {
        id: c.id,
        figure: c.figure,
        claim: c.claim,
        check: j.check,
        values: j.values,
        verdict: j.verdict,
        reason,
    }
}

/// A row whose check runs the mechanistic clutch: judged as the paper's settings stand and,
/// short of agreeing, rerun over the unstated settings ([`runs::UNSTATED`]) for the reason.
pub(super) fn explained(
    unstated: &[runs::Unstated],
    id: &'static str,
    finding: &str,
    check: impl Fn(fn(&mut crate::scene::Clutch)) -> crate::error::Result<fair::Judgement>,
) -> crate::error::Result<Row> {
    let mut j = check(runs::as_is)?;
    if j.verdict == Agreement::Agrees {
        return Ok(judged(id, j, ""));
    }
    let (sens, values) = runs::sensitivity(unstated, check)?;
    j.values.extend(values);
    Ok(judged(id, j, format!("{finding}{sens}")))
}
