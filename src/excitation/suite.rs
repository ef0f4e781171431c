//! Record suites: the three FEMA P695 (ATC-63) record sets shipped in `records/fema-p695/`
//! (far-field 22 × 2 components, near-field pulse 14 × 2, near-field no-pulse 14 × 2) plus the
//! paper's Table 1 records, addressable by suite name and filtered by component, record id and
//! pulse / no-pulse. A suite component is a record named `<set>/<id><component>`, e.g.
//! `far_field/7a`; the library resolves such names like any other record.
//!
//! Each set's `index.csv` is the metadata as shipped (PROVENANCE.md): event, station, NGA RSN,
//! magnitude, Vs30, site class, fault type, npts, dt, PGA, PGV and the FEMA normalisation
//! factor. It is read with the `csv` crate from the records directory if there, else from the
//! copy embedded in the binary.

use serde::{Deserialize, Serialize};

/// One FEMA P695 record set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Set {
    FarField,
    NearFieldPulse,
    NearFieldNoPulse,
}

impl Set {
    pub const ALL: [Set; 3] = [Set::FarField, Set::NearFieldPulse, Set::NearFieldNoPulse];

    /// The suite name (and the prefix of its record names).
    pub fn name(self) -> &'static str {
        match self {
            Set::FarField => "far_field",
            Set::NearFieldPulse => "near_field_pulse",
            Set::NearFieldNoPulse => "near_field_no_pulse",
        }
    }

    /// The folder under `records/` that holds the set's files and `index.csv`.
    pub fn dir(self) -> &'static str {
        match self {
            Set::FarField => "fema-p695/farfield",
            Set::NearFieldPulse => "fema-p695/nearfield_pulse",
            Set::NearFieldNoPulse => "fema-p695/nearfield_no_pulse",
        }
    }

    /// Whether the set's records are pulse-like (None: far-field, not classified).
    pub fn pulse(self) -> Option<bool> {
        match self {
            Set::FarField => None,
            Set::NearFieldPulse => Some(true),
            Set::NearFieldNoPulse => Some(false),
        }
    }
}

/// Every suite name a study or `rocklab records --suite` accepts.
pub const SUITES: [&str; 5] = [
    "far_field",
    "near_field_pulse",
    "near_field_no_pulse",
    "near_field",
    "table1",
];

/// The sets a suite name covers (`table1` covers none: its records are the index's).
pub fn sets_of(suite: &str) -> Option<Vec<Set>> {
    match suite {
        "far_field" => Some(vec![Set::FarField]),
        "near_field_pulse" => Some(vec![Set::NearFieldPulse]),
        "near_field_no_pulse" => Some(vec![Set::NearFieldNoPulse]),
        "near_field" => Some(vec![Set::NearFieldPulse, Set::NearFieldNoPulse]),
        "table1" => Some(vec![]),
        _ => None,
    }
}

/// One row of a set's `index.csv` (the columns as shipped).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IndexRow {
    pub file: String,
    pub set: String,
    pub record_id: u32,
    /// `a` or `b` (for the near-field sets `a` is fault-normal).
    pub component: String,
    pub rsn: u32,
    pub component_name: String,
    pub earthquake: String,
    pub year: u32,
    pub station: String,
    pub magnitude: f64,
    pub vs30: f64,
    pub nehrp_class: String,
    pub fault_type: String,
    pub npts: usize,
    pub dt: f64,
    pub pga_g: f64,
    /// Max |v| of the trapezoidal integral of a·9.80665 from v0 = 0.
    pub pgv_m_s: f64,
    /// FEMA P695 normalisation factor (not applied to the shipped series).
    pub normalization_factor: f64,
    pub sha256: String,
}

/// A component of a suite record.
#[derive(Clone, Debug, PartialEq)]
pub struct SuiteRecord {
    pub set: Set,
    pub row: IndexRow,
}

impl SuiteRecord {
    /// Its record name: `<set>/<record_id><component>`, e.g. `far_field/7a`.
    pub fn id(&self) -> String {
        format!(
            "{}/{}{}",
            self.set.name(),
            self.row.record_id,
            self.row.component
        )
    }

    /// Its data file relative to the records directory.
    pub fn path(&self) -> String {
        format!("{}/{}", self.set.dir(), self.row.file)
    }
}

/// Which component(s) of each record a selection takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Component {
    /// The first horizontal component (fault-normal in the near-field sets).
    A,
    /// The second (fault-parallel in the near-field sets).
    B,
}

impl Component {
    pub fn letter(self) -> &'static str {
        match self {
            Component::A => "a",
            Component::B => "b",
        }
    }
}

/// A suite, optionally filtered, as a study or the command line gives it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SuiteSelect {
    /// far_field, near_field_pulse, near_field_no_pulse, near_field (both) or table1.
    pub name: String,
    /// Only this component of every record (default: both).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub component: Option<Component>,
    /// Only these record ids of the set (1-based, as `index.csv` numbers them); left out, every
    /// record. Given, the list is not empty.
    #[serde(
        default,
        skip_serializing_if = "Vec::is_empty",
        deserialize_with = "some_record_ids"
    )]
    pub records: Vec<u32>,
    /// Only pulse-like (true) or only no-pulse (false) records (near-field sets).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pulse: Option<bool>,
}

/// A `records` filter as written: `records: []` would select nothing, yet read as left out it
/// would select every record, so an empty list is refused.
fn some_record_ids<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<u32>, D::Error> {
    let ids = Vec::<u32>::deserialize(d)?;
    if ids.is_empty() {
        return Err(serde::de::Error::custom(
            "an empty list selects no record; list record ids, e.g. records: [1, 2], or leave \
             `records` out for every record of the suite",
        ));
    }
    Ok(ids)
}

/// Read a set's `index.csv` text; an error gives the line (0: the file as a whole) and what
/// is wrong.
pub fn parse_index(set: Set, text: &str) -> Result<Vec<SuiteRecord>, (usize, String)> {
    let mut reader = csv::Reader::from_reader(text.as_bytes());
    let mut out = Vec::new();
    for row in reader.deserialize::<IndexRow>() {
        let row = row.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line() as usize);
            (
                line,
                format!("{e} (the columns are those of the shipped index.csv)"),
            )
        })?;
        out.push(SuiteRecord { set, row });
    }
    Ok(out)
}

/// The members of `select` among `records` (every set's components, in index order), by
/// record name; `table1` gives the index entries with a Table 1 number. Errors say what is
/// wrong with the selection, with the valid choices.
pub fn select(
    select: &SuiteSelect,
    records: &[SuiteRecord],
    table1: &[String],
) -> Result<Vec<String>, String> {
    let sets = sets_of(&select.name).ok_or_else(|| {
        format!(
            "unknown suite `{}`; suites: {}",
            select.name,
            SUITES.join(", ")
        )
    })?;
    if select.name == "table1" {
        if select.component.is_some() || !select.records.is_empty() || select.pulse == Some(false) {
            return Err(
                "the table1 suite is the paper's five fault-normal pulse records: it takes no component, records or pulse filter"
                    .into(),
            );
        }
        return Ok(table1.to_vec());
    }
    let chosen: Vec<&SuiteRecord> = records
        .iter()
        .filter(|r| sets.contains(&r.set))
        .filter(|r| select.pulse.is_none() || r.set.pulse() == select.pulse)
        .filter(|r| {
            select
                .component
                .is_none_or(|c| r.row.component == c.letter())
        })
        .filter(|r| select.records.is_empty() || select.records.contains(&r.row.record_id))
        .collect();
    if let Some(missing) = select.records.iter().find(|id| {
        !records
            .iter()
            .any(|r| sets.contains(&r.set) && r.row.record_id == **id)
    }) {
        return Err(format!(
            "suite `{}` has no record {missing}; `rocklab records --suite {}` lists its ids",
            select.name, select.name
        ));
    }
    if chosen.is_empty() {
        return Err(format!(
            "the filter leaves no record of suite `{}` ({} on a set that is {})",
            select.name,
            match select.pulse {
                Some(pulse) => format!("pulse: {pulse}"),
                None => "no pulse filter".to_string(),
            },
            if sets.iter().all(|s| s.pulse().is_none()) {
                "not classified by pulse"
            } else {
                "classified otherwise"
            }
        ));
    }
    Ok(chosen.into_iter().map(SuiteRecord::id).collect())
}
