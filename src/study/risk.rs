//! The `risk` section of a fragility study: after the fit, the mean annual frequency of
//! reaching each damage state at a site (`crate::risk`), written as risk.csv / risk.json and
//! the risk figure beside fragility.csv. The hazard file's path is relative to the study
//! file's directory (so a study and its hazard curve travel together); `Study::load` resolves
//! it and checks the file, so a bad hazard is refused before any scene runs.

use super::{ExcitationFamily, RecordScaling, Study, StudyError};
use crate::excitation::G;
use crate::risk::{HazardCurve, HazardIm, RiskOptions};
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
    // With uncertain parameters the study's own fitted total β serves as β_TOT.
    let own_beta = study.uncertain.is_some();
    if r.beta_total.is_some() && r.mce.is_none()
        || r.mce.is_some() && !own_beta && r.beta_total.is_none()
    {
        return Err(StudyError::field(
            "risk.mce",
            "P695 margins need both the MCE intensity and β_TOT",
            "mce: 0.7, beta_total: 0.525 (a study with uncertain parameters may leave out \
             beta_total: its fitted total β serves)",
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
            e.to_string(),
            "the hazard file's path is relative to the study file's directory",
        )
    })
}

/// x* = factor(α, p) · x: the hazard's IM x converted to a structure's scaling IM x*.
pub type ImFactor = fn(f64, f64) -> f64;

/// How a hazard in `im` converts to the study's scaling measure (PGA* = PGA/(g tan α) with
/// PGA in g, PGV* = PGV·p/(g tan α)), from each structure's α and p; Err: the measures do not
/// match, with what the study scales to and a hint.
pub fn im_factor(study: &Study, im: HazardIm) -> Result<ImFactor, (&'static str, &'static str)> {
    let scale_to = match &study.excitation {
        ExcitationFamily::Record { scale_to, .. } => Some(*scale_to),
        _ => None,
    };
    match (scale_to, im) {
        (Some(RecordScaling::PgaStar), HazardIm::Pga) => Ok(|alpha, _| 1.0 / alpha.tan()),
        (Some(RecordScaling::PgvStar), HazardIm::Pgv) => Ok(|alpha, p| p / (G * alpha.tan())),
        (Some(RecordScaling::Pga), HazardIm::Pga) | (Some(RecordScaling::Pgv), HazardIm::Pgv) => {
            Ok(|_, _| 1.0)
        }
        // Sa at the study's own period and damping is the scaling measure itself.
        (Some(RecordScaling::Sa { period, damping }), HazardIm::Sa { period: t })
            if (period - t).abs() <= 1e-9 * t
                && damping.is_none_or(|d| d == crate::excitation::ims::DEFAULT_DAMPING) =>
        {
            Ok(|_, _| 1.0)
        }
        (Some(RecordScaling::Sa { .. }), _) => Err((
            "Sa(T) (scale_to: sa(period: T))",
            "give the site's hazard in Sa at the study's period and 5 % damping: the header \
             `sa(T),annual_rate` with the same T, Sa in g",
        )),
        (Some(RecordScaling::PgaStar | RecordScaling::Pga), _) => Err((
            "PGA (pga_star or pga)",
            "give the site's hazard in PGA: the header `pga,annual_rate`, PGA in g",
        )),
        (Some(RecordScaling::PgvStar | RecordScaling::Pgv), _) => Err((
            "PGV (pgv_star or pgv)",
            "give the site's hazard in PGV: the header `pgv,annual_rate`, PGV in m/s",
        )),
        _ => Err((
            "a scale factor, not an intensity measure",
            "a risk needs fragility over an intensity measure: scale the records with \
             `scale_to: pga_star`, `pga`, `pgv`, `pgv_star` or `sa(period: T)`",
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn study(scale_to: &str) -> Study {
        let text = format!(
            r#"(version: 1, name: "t", structure: rigid(p: 2.0, alpha: 0.2), devices: [none],
               excitation: record(suite: (name: "far_field", records: [1]), scale: [0.5, 1.0],
                                  scale_to: {scale_to}),
               quantities: [peak_rotation_ratio], spectrum: scale)"#
        );
        Study::parse_ron(&text, "t.ron").unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn the_hazard_measure_converts_to_the_studys_scaling_measure() {
        let (alpha, p) = (0.2_f64, 2.0);
        let f = im_factor(&study("pga_star"), HazardIm::Pga).unwrap();
        assert!((f(alpha, p) - 1.0 / alpha.tan()).abs() < 1e-15);
        let f = im_factor(&study("pgv_star"), HazardIm::Pgv).unwrap();
        assert!((f(alpha, p) - p / (G * alpha.tan())).abs() < 1e-15);
        // Sa at the study's own period and 5 % damping is the scaling measure itself.
        let f = im_factor(&study("sa(period: 1.0)"), HazardIm::Sa { period: 1.0 }).unwrap();
        assert_eq!(f(alpha, p), 1.0);
        let f = im_factor(
            &study("sa(period: 1.0, damping: 0.05)"),
            HazardIm::Sa { period: 1.0 },
        );
        assert!(f.is_ok());
        // Another period, another damping, or PGA against Sa: refused, saying what fits.
        for (scale_to, im) in [
            ("sa(period: 1.0)", HazardIm::Sa { period: 2.0 }),
            (
                "sa(period: 1.0, damping: 0.02)",
                HazardIm::Sa { period: 1.0 },
            ),
            ("sa(period: 1.0)", HazardIm::Pga),
            ("pga_star", HazardIm::Sa { period: 1.0 }),
        ] {
            assert!(
                im_factor(&study(scale_to), im).is_err(),
                "{scale_to} {im:?}"
            );
        }
    }
}
