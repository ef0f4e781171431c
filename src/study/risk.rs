//! The `risk` section of a fragility study: after the fit, the mean annual frequency of
//! reaching each damage state at a site (`crate::risk`), written as risk.csv / risk.json and
//! the risk figure beside fragility.csv. The hazard file's path is relative to the study
//! file's directory (so a study and its hazard curve travel together); `Study::load` resolves
//! it and checks the file, so a bad hazard is refused before any scene runs.

use super::{Study, StudyError};
use crate::risk::{HazardCurve, RiskOptions};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Risk {
    /// The site's hazard curve CSV (`pga,annual_rate` or `pgv,annual_rate`), relative to the
    /// study file's directory.
    pub hazard: String,
    /// Years of exposure for p_years = 1 − exp(−MAF · years).
    #[serde(default = "default_years")]
    pub years: f64,
    /// FEMA P695 margins: the MCE intensity in the hazard's IM, and β_TOT.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mce: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beta_total: Option<f64>,
    /// The study file's directory, set by `Study::load` (not part of the study's text).
    #[serde(skip)]
    pub base: Option<PathBuf>,
}

/// Equal as written: where the file was loaded from is no part of the study.
impl PartialEq for Risk {
    fn eq(&self, other: &Self) -> bool {
        (&self.hazard, self.years, self.mce, self.beta_total)
            == (&other.hazard, other.years, other.mce, other.beta_total)
    }
}

fn default_years() -> f64 {
    50.0
}

impl Risk {
    /// The hazard file: relative to the study's directory when the study was loaded from a
    /// file, else as written.
    pub fn hazard_path(&self) -> PathBuf {
        match &self.base {
            Some(base) => base.join(&self.hazard),
            None => PathBuf::from(&self.hazard),
        }
    }

    pub fn options(&self) -> RiskOptions {
        RiskOptions {
            years: self.years,
            mce: self.mce,
            beta_total: self.beta_total,
        }
    }
}

/// The section's own checks (the hazard file is read by [`resolve`]).
pub fn validate(study: &Study) -> Result<(), StudyError> {
    let Some(r) = &study.risk else {
        return Ok(());
    };
    if study.fragility.is_none() {
        return Err(StudyError::field(
            "risk",
            "a risk is computed from fragility curves",
            "add a fragility section: fragility: (damage_states: levels([0.2, 0.5, 1.0]))",
        ));
    }
    let positive = |v: f64| v.is_finite() && v > 0.0;
    if !positive(r.years) {
        return Err(StudyError::field(
            "risk.years",
            "years of exposure must be a positive number",
            "years: 50.0",
        ));
    }
    for (field, v) in [("risk.mce", r.mce), ("risk.beta_total", r.beta_total)] {
        if v.is_some_and(|v| !positive(v)) {
            return Err(StudyError::field(
                field,
                "must be a positive number",
                "mce: 0.7",
            ));
        }
    }
    if r.mce.is_some() != r.beta_total.is_some() {
        return Err(StudyError::field(
            "risk.mce",
            "P695 margins need both the MCE intensity and β_TOT",
            "mce: 0.7, beta_total: 0.525",
        ));
    }
    Ok(())
}

/// Resolve a loaded study's hazard path against its file's directory and read the curve.
pub fn resolve(study: &mut Study, study_path: &Path) -> Result<Option<HazardCurve>, StudyError> {
    let Some(r) = &mut study.risk else {
        return Ok(None);
    };
    r.base = Some(crate::fsutil::parent_dir(study_path).to_path_buf());
    HazardCurve::read(&r.hazard_path()).map(Some).map_err(|e| {
        StudyError::field(
            "risk.hazard",
            &e.to_string(),
            "the hazard file's path is relative to the study file's directory",
        )
    })
}
