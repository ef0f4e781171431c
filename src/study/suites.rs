//! A record excitation's records (its `names`, then its `suite`'s members) and the scene
//! scaling each record gets: the study side of record suites and intensity-measure scaling.

use super::{ExcitationFamily, RecordScaling, Study, StudyError};
use crate::excitation::ims;
use crate::excitation::library::{self, Library};
use crate::scene::{Excitation, RecordScale};

fn library() -> Result<&'static Library, StudyError> {
    library::global().map_err(|e| {
        StudyError::field(
            "excitation.names",
            format!("the record library cannot be opened: {e}"),
            "set ROCKLAB_RECORDS to the records directory, or run from the repository",
        )
    })
}

impl ExcitationFamily {
    /// The records of a record excitation, in expansion order: `names`, then the members of
    /// `suite` (resolved in the command line's library). Empty for pulses.
    pub fn record_names(&self) -> Result<Vec<String>, StudyError> {
        let ExcitationFamily::Record { names, suite, .. } = self else {
            return Ok(Vec::new());
        };
        let mut out = names.clone();
        if let Some(select) = suite {
            let members = library()?.suite(select).map_err(|e| {
                StudyError::field(
                    "excitation.suite",
                    e.to_string(),
                    "e.g. suite: (name: \"far_field\", component: a, records: [1, 2]); \
                     `rocklab records --suite far_field` lists a suite",
                )
            })?;
            for m in members {
                if out.contains(&m) {
                    return Err(StudyError::field(
                        "excitation.suite",
                        format!("record `{m}` is both in `names` and in the suite"),
                        "list each record once",
                    ));
                }
                out.push(m);
            }
        }
        if out.is_empty() {
            return Err(StudyError::field(
                "excitation.names",
                "no records",
                "list record names from `rocklab records`, or give a suite: (name: \"far_field\")",
            ));
        }
        Ok(out)
    }
}

/// The scene scaling of record `name` for the study value `value` of `scale`.
pub(crate) fn scene_scale(
    scale_to: RecordScaling,
    value: f64,
    name: &str,
    baseline: bool,
) -> Result<RecordScale, StudyError> {
    // An IM of the record itself (unscaled, standard gravity), for the scalings that are
    // neither a factor nor a PGA/PGV the scene computes.
    let im = |measure: &dyn Fn(&ims::Accelerogram) -> Result<f64, ims::ImError>| -> Result<f64, StudyError> {
        let bad = |message: String| {
            StudyError::field(
                "excitation.scale_to",
                format!("record `{name}`: {message}"),
                "e.g. scale_to: sa(period: 1.0), sa_avg(from: 0.5, to: 2.0) or arias",
            )
        };
        let record = library()?
            .load(name, baseline)
            .map_err(|e| bad(e.to_string()))?;
        let value = ims::Accelerogram::from_series(&record.series)
            .and_then(|r| measure(&r))
            .map_err(|e| bad(e.to_string()))?;
        if !(value.is_finite() && value > 0.0) {
            return Err(bad(format!(
                "its intensity is {value}, so no factor reaches the target"
            )));
        }
        Ok(value)
    };
    Ok(match scale_to {
        RecordScaling::Sa { period, damping } => {
            let sa = im(&|r| {
                ims::spectrum::sa(r, &[period], damping.unwrap_or(ims::DEFAULT_DAMPING))
                    .map(|v| v[0] / ims::STANDARD_GRAVITY)
            })?;
            RecordScale::Factor(value / sa)
        }
        RecordScaling::SaAvg { from, to } => {
            let sa = im(&|r| {
                ims::spectrum::sa_avg(r, from, to, ims::DEFAULT_DAMPING)
                    .map(|v| v / ims::STANDARD_GRAVITY)
            })?;
            RecordScale::Factor(value / sa)
        }
        RecordScaling::Arias => {
            let ia = im(&|r| Ok(ims::arias(r)))?;
            RecordScale::Factor((value / ia).sqrt())
        }
        RecordScaling::Factor => RecordScale::Factor(value),
        RecordScaling::Pga => RecordScale::Pga(value),
        RecordScaling::Pgv => RecordScale::Pgv(value),
        RecordScaling::PgaStar => RecordScale::PgaStar(value),
        RecordScaling::PgvStar => RecordScale::PgvStar(value),
        RecordScaling::Fema => {
            let nf = library()?
                .suite_entry(name)
                .map(|r| r.row.normalization_factor)
                .ok_or_else(|| {
                    StudyError::field(
                        "excitation.scale_to",
                        format!("record `{name}` has no FEMA P695 normalisation factor"),
                        "`scale_to: fema` takes suite records only (e.g. suite: (name: \"far_field\")); \
                         use `factor`, `pga` or `pgv` for other records",
                    )
                })?;
            RecordScale::Factor(value * nf)
        }
    })
}

/// A scene's simulated time: the study's `duration`, or with a record excitation's `tail` its
/// record's length plus the tail.
pub(super) fn scene_duration(study: &Study, excitation: &Excitation) -> Result<f64, StudyError> {
    let (
        ExcitationFamily::Record {
            tail: Some(tail), ..
        },
        Excitation::Record { name, baseline, .. },
    ) = (&study.excitation, excitation)
    else {
        return study.duration.ok_or_else(|| {
            StudyError::field(
                "duration",
                "missing: how long each scene is simulated",
                "add `duration: 10.0` (seconds), or for records `tail: 10.0` in the excitation",
            )
        });
    };
    if !(tail.is_finite() && *tail >= 0.0) {
        return Err(StudyError::field(
            "excitation.tail",
            format!("{tail} is not a duration"),
            "seconds simulated after the record ends, ≥ 0, e.g. tail: 10.0",
        ));
    }
    let record = library()?.load(name, *baseline).map_err(|e| {
        StudyError::field(
            "excitation.names",
            e.to_string(),
            "`rocklab records` lists the library's record names",
        )
    })?;
    Ok(record.series.end() + tail)
}
