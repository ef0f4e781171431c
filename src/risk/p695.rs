//! FEMA P695 (ATC-63) collapse margins, Chapter 7: the collapse margin ratio CMR = median
//! collapse intensity / MCE intensity, the total system collapse uncertainty β_TOT from the
//! quality ratings (Table 7-2) and record-to-record β_RTR, and the acceptable adjusted margins
//! ACMR(p) = exp(−β_TOT Φ⁻¹(p)) = exp(√2 β_TOT erfc⁻¹(2p)) for a collapse probability p at
//! the MCE (10 % and 20 %, Table 7-3).

use super::RiskError;
use crate::stats::normal;
use serde::{Deserialize, Serialize};

/// A quality rating of Table 7-2: design requirements, test data or modelling.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Rating {
    /// Superior.
    A,
    /// Good.
    B,
    /// Fair.
    C,
    /// Poor.
    D,
}

impl Rating {
    /// The rating's uncertainty β (Table 7-2's values).
    pub fn beta(self) -> f64 {
        match self {
            Rating::A => 0.10,
            Rating::B => 0.20,
            Rating::C => 0.35,
            Rating::D => 0.50,
        }
    }

    pub fn parse(letter: &str) -> Option<Self> {
        match letter.trim().to_ascii_uppercase().as_str() {
            "A" => Some(Rating::A),
            "B" => Some(Rating::B),
            "C" => Some(Rating::C),
            "D" => Some(Rating::D),
            _ => None,
        }
    }
}

/// The three ratings of β_TOT: design requirements (DR), test data (TD), modelling (MDL).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Ratings {
    pub design: Rating,
    pub test_data: Rating,
    pub modelling: Rating,
}

impl Ratings {
    /// `DR,TD,MDL` as three letters A–D, e.g. `B,B,C`.
    pub fn parse(text: &str) -> Result<Self, RiskError> {
        const HINT: &str = "three quality ratings A (superior), B (good), C (fair) or D (poor) \
                            for design requirements, test data and modelling, e.g. B,B,C";
        let letters: Vec<&str> = text.split(',').collect();
        let parsed: Vec<Option<Rating>> = letters.iter().map(|l| Rating::parse(l)).collect();
        match parsed.as_slice() {
            [Some(design), Some(test_data), Some(modelling)] => Ok(Ratings {
                design: *design,
                test_data: *test_data,
                modelling: *modelling,
            }),
            _ => Err(RiskError::option(
                "--ratings",
                format!("`{text}` is not three ratings"),
                HINT,
            )),
        }
    }
}

/// Record-to-record uncertainty from the period-based ductility μT: 0.1 + 0.1 μT, at most 0.4.
pub fn beta_rtr(mu_t: f64) -> f64 {
    (0.1 + 0.1 * mu_t).min(0.4)
}

/// β_TOT = √(β_RTR² + β_DR² + β_TD² + β_MDL²), rounded to the nearest 0.025 as P695 does.
pub fn beta_total(ratings: Ratings, mu_t: f64) -> f64 {
    let squares: f64 = [
        beta_rtr(mu_t),
        ratings.design.beta(),
        ratings.test_data.beta(),
        ratings.modelling.beta(),
    ]
    .iter()
    .map(|b| b * b)
    .sum();
    (squares.sqrt() / 0.025).round() * 0.025
}

/// Φ⁻¹(p) for 0 < p < 1: the one standard normal quantile, `stats::normal::quantile` (the
/// uncertain parameters' draws use it too).
pub fn normal_quantile(p: f64) -> f64 {
    normal::quantile(p)
}

/// The acceptable adjusted collapse margin ratio for a collapse probability p at the MCE.
pub fn acmr(beta_total: f64, p: f64) -> f64 {
    (-beta_total * normal_quantile(p)).exp()
}

/// One variant's collapse margin against the MCE.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Margin {
    /// The median collapse intensity, in the hazard's IM.
    pub median_capacity: f64,
    pub mce: f64,
    /// Median capacity / MCE.
    pub cmr: f64,
    /// The spectral shape factor: 1 for a rigid rocking block (no period in P695's sense).
    pub ssf: f64,
    /// SSF · CMR.
    pub acmr: f64,
    pub beta_total: f64,
    /// Acceptable ACMR for 10 % and 20 % collapse probability at the MCE.
    pub acmr_10: f64,
    pub acmr_20: f64,
    /// ACMR ≥ ACMR10 (P695's test of a performance group's mean).
    pub pass_10: bool,
    /// ACMR ≥ ACMR20 (P695's test of each archetype).
    pub pass_20: bool,
}

/// The margin of a median collapse capacity against the MCE, both in the same IM.
pub fn margin(median_capacity: f64, mce: f64, beta_total: f64, ssf: f64) -> Margin {
    let cmr = median_capacity / mce;
    let (acmr_10, acmr_20) = (acmr(beta_total, 0.10), acmr(beta_total, 0.20));
    Margin {
        median_capacity,
        mce,
        cmr,
        ssf,
        acmr: ssf * cmr,
        beta_total,
        acmr_10,
        acmr_20,
        pass_10: ssf * cmr >= acmr_10,
        pass_20: ssf * cmr >= acmr_20,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn acceptable_margins_match_p695s_table() {
        // FEMA P695 Table 7-3 (4 decimals as printed): β 0.5 → ACMR20 1.5232, ACMR10 1.8980;
        // β 0.2 → 1.1833, 1.2922.
        for (beta, a20, a10) in [(0.5, 1.5232, 1.8980), (0.2, 1.1833, 1.2922)] {
            assert!((acmr(beta, 0.20) - a20).abs() < 5e-5, "{}", acmr(beta, 0.2));
            assert!((acmr(beta, 0.10) - a10).abs() < 5e-5, "{}", acmr(beta, 0.1));
        }
        // Other β: Φ⁻¹(0.1) = −1.2815515655446004, Φ⁻¹(0.2) = −0.8416212335729143
        // (Wichura's AS241 to 16 digits), so ACMR10 = e^{1.28155 β}, ACMR20 = e^{0.84162 β}.
        for beta in [0.275f64, 0.4, 0.525, 0.725, 0.95] {
            let a10 = (1.281_551_565_544_600_4 * beta).exp();
            let a20 = (0.841_621_233_572_914_3 * beta).exp();
            assert!((acmr(beta, 0.10) / a10 - 1.0).abs() < 1e-13);
            assert!((acmr(beta, 0.20) / a20 - 1.0).abs() < 1e-13);
        }
        // The quantile inverts Φ across the range.
        for p in [1e-10, 0.001, 0.3, 0.5, 0.77, 0.999_999] {
            assert!(
                (normal::cdf(normal_quantile(p)) / p - 1.0).abs() < 1e-12,
                "{p}"
            );
        }
    }

    #[test]
    fn beta_total_combines_ratings_and_rounds_to_0_025() {
        // μT ≥ 3: β_RTR = 0.4; B, B, B: √(0.16 + 3·0.04) = 0.5292 → 0.525 (P695 Table 7-2b).
        let bbb = Ratings::parse("B,B,B").unwrap();
        assert!((beta_total(bbb, 3.0) - 0.525).abs() < 1e-12);
        // A, A, A and μT = 1: √(0.04 + 0.03) = 0.2646 → 0.275.
        let aaa = Ratings::parse("a, a, a").unwrap();
        assert!((beta_total(aaa, 1.0) - 0.275).abs() < 1e-12);
        // D, D, D: √(0.16 + 0.75) = 0.9539 → 0.950.
        let ddd = Ratings::parse("D,D,D").unwrap();
        assert!((beta_total(ddd, 8.0) - 0.95).abs() < 1e-12);
        assert_eq!(beta_rtr(1.0), 0.2);
        assert_eq!(beta_rtr(5.0), 0.4);
        let e = Ratings::parse("B,E,C").unwrap_err().to_string();
        assert!(e.contains("--ratings") && e.contains("hint"), "{e}");
    }

    #[test]
    fn a_margin_passes_when_it_clears_the_acceptable_value() {
        let m = margin(3.0, 1.5, 0.5, 1.0);
        assert_eq!(m.cmr, 2.0);
        assert!(m.pass_10 && m.pass_20);
        let m = margin(2.5, 1.5, 0.5, 1.0);
        assert!(!m.pass_10 && m.pass_20, "{m:?}");
    }
}
