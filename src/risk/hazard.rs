//! Site hazard curves: the annual rate λ(x) of exceeding an intensity x, read from a CSV of
//! points (header `pga,annual_rate`, `pgv,annual_rate` or `sa(T),annual_rate`) and
//! interpolated log-log between them: each segment is a power law λ = λi (x/xi)^−ki, the
//! form USGS and OpenQuake curves are drawn in and the one Cornell et al. (2002) integrate in
//! closed form. Outside the table (`crate::risk` "ends"): below the first point the rate
//! stays λ1 (no ground motion weaker than the table's first point is counted), above the last
//! one the last segment's power law goes on.

use super::RiskError;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The intensity measure a hazard curve is given in, with its unit.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HazardIm {
    /// Peak ground acceleration in g.
    Pga,
    /// Peak ground velocity in m/s.
    Pgv,
    /// 5 %-damped pseudo-spectral acceleration at period T (s), in g.
    Sa { period: f64 },
}

impl HazardIm {
    /// `pga`, `pgv` or `sa(T)` (any case, spaces ignored); None otherwise.
    pub fn parse(name: &str) -> Option<Self> {
        let name: String = name
            .chars()
            .filter(|c| !c.is_whitespace())
            .collect::<String>()
            .to_ascii_lowercase();
        match name.as_str() {
            "pga" => Some(HazardIm::Pga),
            "pgv" => Some(HazardIm::Pgv),
            _ => {
                let period: f64 = name.strip_prefix("sa(")?.strip_suffix(')')?.parse().ok()?;
                (period.is_finite() && period > 0.0).then_some(HazardIm::Sa { period })
            }
        }
    }

    /// The header name: `pga`, `pgv`, `sa(1)`.
    pub fn name(&self) -> String {
        match self {
            HazardIm::Pga => "pga".into(),
            HazardIm::Pgv => "pgv".into(),
            HazardIm::Sa { period } => format!("sa({period})"),
        }
    }

    pub fn unit(&self) -> &'static str {
        match self {
            HazardIm::Pga | HazardIm::Sa { .. } => "g",
            HazardIm::Pgv => "m/s",
        }
    }
}

/// The second column's header.
pub const RATE_COLUMN: &str = "annual_rate";

/// A hazard curve: intensities in increasing order and their annual rates of exceedance.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HazardCurve {
    pub im: HazardIm,
    /// Intensities, strictly increasing and positive.
    pub x: Vec<f64>,
    /// Annual rates of exceedance, positive and non-increasing.
    pub rate: Vec<f64>,
}

/// λ(x) = k0 x^−k.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PowerLaw {
    pub k0: f64,
    pub k: f64,
}

impl PowerLaw {
    pub fn rate(&self, x: f64) -> f64 {
        self.k0 * x.powf(-self.k)
    }
}

fn hazard_error(path: &Path, line: u64, field: &str, message: String, hint: &str) -> RiskError {
    RiskError::Hazard {
        path: path.to_path_buf(),
        line,
        field: field.to_string(),
        message,
        hint: hint.to_string(),
    }
}

impl HazardCurve {
    /// Read a hazard CSV (lines starting with `#` are comments: the place for its source).
    pub fn read(path: &Path) -> Result<Self, RiskError> {
        let text = std::fs::read_to_string(path).map_err(|source| RiskError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(path, &text)
    }

    /// Parse a hazard CSV's text; `path` names it in errors.
    pub fn parse(path: &Path, text: &str) -> Result<Self, RiskError> {
        const SHAPE: &str = "a hazard curve is a CSV with the header `pga,annual_rate` (g), \
                             `pgv,annual_rate` (m/s) or `sa(T),annual_rate` (g), then one \
                             `intensity,rate` row per point";
        let mut reader = csv::ReaderBuilder::new()
            .comment(Some(b'#'))
            .trim(csv::Trim::All)
            .flexible(true)
            .from_reader(text.as_bytes());
        let header_line = reader.position().line().max(1);
        let headers = reader
            .headers()
            .map_err(|e| hazard_error(path, header_line, "header", e.to_string(), SHAPE))?
            .clone();
        let header_line = headers.position().map_or(1, |p| p.line());
        if headers.len() != 2 {
            return Err(hazard_error(
                path,
                header_line,
                "header",
                format!("{} columns, expected 2", headers.len()),
                SHAPE,
            ));
        }
        let im = HazardIm::parse(&headers[0]).ok_or_else(|| {
            hazard_error(
                path,
                header_line,
                &headers[0],
                "not an intensity measure rocklab knows".into(),
                "the first column is `pga` (g), `pgv` (m/s) or `sa(T)` with T in s (g)",
            )
        })?;
        if !headers[1].eq_ignore_ascii_case(RATE_COLUMN) {
            return Err(hazard_error(
                path,
                header_line,
                &headers[1],
                format!("expected `{RATE_COLUMN}`"),
                "the second column is the annual rate of exceedance (1/yr); a probability of \
                 exceedance P in t years is the rate −ln(1 − P)/t",
            ));
        }
        let (mut x, mut rate) = (Vec::new(), Vec::new());
        for record in reader.records() {
            let record = record.map_err(|e| {
                let line = e.position().map_or(0, |p| p.line());
                hazard_error(path, line, "row", e.to_string(), SHAPE)
            })?;
            let line = record.position().map_or(0, |p| p.line());
            if record.len() != 2 {
                return Err(hazard_error(
                    path,
                    line,
                    "row",
                    format!("{} fields, expected 2", record.len()),
                    SHAPE,
                ));
            }
            let value = |i: usize, field: &str, what: &str| -> Result<f64, RiskError> {
                match record[i].parse::<f64>() {
                    Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
                    _ => Err(hazard_error(
                        path,
                        line,
                        field,
                        format!("`{}` is not a positive number", &record[i]),
                        what,
                    )),
                }
            };
            let xi = value(
                0,
                &headers[0],
                "intensities are positive numbers in the header's unit",
            )?;
            let ri = value(
                1,
                RATE_COLUMN,
                "rates are positive (log-log interpolation needs them); leave out rows whose \
                 rate is 0",
            )?;
            if let (Some(&xp), Some(&rp)) = (x.last(), rate.last()) {
                if xi <= xp {
                    return Err(hazard_error(
                        path,
                        line,
                        &headers[0],
                        format!("{xi} does not exceed the row before ({xp})"),
                        "list the intensities in increasing order, each once",
                    ));
                }
                if ri > rp {
                    return Err(hazard_error(
                        path,
                        line,
                        RATE_COLUMN,
                        format!("{ri} exceeds the rate of the weaker intensity before ({rp})"),
                        "a rate of exceedance cannot grow with intensity: check the columns' \
                         order and units",
                    ));
                }
            }
            x.push(xi);
            rate.push(ri);
        }
        if x.len() < 2 {
            return Err(hazard_error(
                path,
                header_line,
                "rows",
                format!("{} point(s), at least 2 needed", x.len()),
                SHAPE,
            ));
        }
        Ok(HazardCurve { im, x, rate })
    }

    /// The power-law exponent of segment i (between points i and i + 1).
    pub fn slope(&self, i: usize) -> f64 {
        -(self.rate[i + 1] / self.rate[i]).ln() / (self.x[i + 1] / self.x[i]).ln()
    }

    /// −d ln λ / d ln x at x: the slope of the segment holding x (0 below the table, where λ
    /// is held constant; the last segment's above it).
    pub fn slope_at(&self, x: f64) -> f64 {
        if x < self.x[0] {
            return 0.0;
        }
        let n = self.x.len();
        self.slope(self.x.partition_point(|&xi| xi <= x).clamp(1, n - 1) - 1)
    }

    /// λ(x), log-log interpolated; λ1 below the table, the last segment's power law above it.
    pub fn rate(&self, x: f64) -> f64 {
        let n = self.x.len();
        if x <= self.x[0] {
            return self.rate[0];
        }
        let i = self.x.partition_point(|&xi| xi <= x).min(n - 1) - 1;
        self.rate[i] * (x / self.x[i]).powf(-self.slope(i))
    }

    /// The same hazard in an intensity measure `factor` times this one (a rate is unchanged by
    /// renaming the intensity it is the rate of).
    pub fn scaled(&self, factor: f64) -> HazardCurve {
        HazardCurve {
            im: self.im,
            x: self.x.iter().map(|x| x * factor).collect(),
            rate: self.rate.clone(),
        }
    }

    /// The least-squares power law through the points in log-log, λ ≈ k0 x^−k (what
    /// closed-form risk estimates such as Cornell et al. 2002 take as the hazard).
    pub fn power_law(&self) -> PowerLaw {
        let n = self.x.len() as f64;
        let u: Vec<f64> = self.x.iter().map(|x| x.ln()).collect();
        let v: Vec<f64> = self.rate.iter().map(|r| r.ln()).collect();
        let (mu, mv) = (u.iter().sum::<f64>() / n, v.iter().sum::<f64>() / n);
        let suv: f64 = u.iter().zip(&v).map(|(a, b)| (a - mu) * (b - mv)).sum();
        let suu: f64 = u.iter().map(|a| (a - mu) * (a - mu)).sum();
        let k = -suv / suu;
        PowerLaw {
            k0: (mv + k * mu).exp(),
            k,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<HazardCurve, RiskError> {
        HazardCurve::parse(Path::new("site.csv"), text)
    }

    #[test]
    fn reads_points_and_interpolates_log_log() {
        let h = parse("# illustrative\npga,annual_rate\n0.1,1e-2\n0.4,1e-3\n1.0,1e-4\n").unwrap();
        assert_eq!(h.im, HazardIm::Pga);
        assert_eq!(h.x, [0.1, 0.4, 1.0]);
        // Halfway in ln x between two points the rate is their geometric mean.
        assert!((h.rate(0.2) / (1e-2f64 * 1e-3).sqrt() - 1.0).abs() < 1e-12);
        assert_eq!(h.rate(0.05), 1e-2);
        // Above the table the last segment's power law goes on.
        let k = h.slope(1);
        assert!((h.rate(2.0) / (1e-4 * 2f64.powf(-k)) - 1.0).abs() < 1e-12);
        let pgv = parse("PGV , Annual_Rate\n0.1,1e-2\n1,1e-4\n").unwrap();
        assert_eq!(pgv.im, HazardIm::Pgv);
        let sa = parse("sa(1.0),annual_rate\n0.1,1e-2\n1,1e-4\n").unwrap();
        assert_eq!(sa.im, HazardIm::Sa { period: 1.0 });
    }

    #[test]
    fn the_power_law_fit_recovers_a_power_law() {
        let text: String = std::iter::once("pga,annual_rate\n".to_string())
            .chain((0..6).map(|i| {
                let x = 0.05 * 2f64.powi(i);
                format!("{x},{}\n", 3e-4 * x.powf(-2.7))
            }))
            .collect();
        let fit = parse(&text).unwrap().power_law();
        assert!((fit.k - 2.7).abs() < 1e-9 && (fit.k0 / 3e-4 - 1.0).abs() < 1e-9);
    }

    #[test]
    fn bad_files_name_the_line_and_field() {
        let e = parse("pga,rate\n0.1,1e-2\n").unwrap_err().to_string();
        assert!(
            e.starts_with("site.csv:1: rate: expected `annual_rate`"),
            "{e}"
        );
        let e = parse("pgd,annual_rate\n0.1,1e-2\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("site.csv:1: pgd: not an intensity"), "{e}");
        let e = parse("pga,annual_rate\n0.1,1e-2\n0.2,0\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("site.csv:3: annual_rate: `0` is not a positive"),
            "{e}"
        );
        let e = parse("pga,annual_rate\n0.2,1e-2\n0.1,1e-3\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("site.csv:3: pga: 0.1 does not exceed"), "{e}");
        let e = parse("pga,annual_rate\n0.1,1e-3\n0.2,1e-2\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("cannot grow"), "{e}");
        let e = parse("pga,annual_rate\n0.1,1e-3\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("at least 2"), "{e}");
        let e = parse("pga,annual_rate\n0.1,1e-3,4\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("site.csv:2: row: 3 fields"), "{e}");
        assert!(e.contains("hint:"), "{e}");
    }
}
