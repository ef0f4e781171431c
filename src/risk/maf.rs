//! The mean annual frequency of reaching a damage state, λ_DS = ∫ P(DS | x) |dλ/dx| dx, for a
//! lognormal fragility P(DS | x) = Φ(ln(x/θ)/β) over a log-log interpolated hazard curve.
//!
//! Each table segment is a power law λ = λi (x/xi)^−ki, and over one the integral has a closed
//! form (by parts, ∫ P |dλ| = [−P λ] + ∫ λ dP, and the Gaussian integral Cornell et al. 2002
//! use for the whole curve): with u = ln x, t = (u − ln θ)/β,
//!
//!   ∫_{ui}^{ui+1} P k λ du = Φ(ti) λi − Φ(ti+1) λi+1 + λi e^{k (ui − ln θ) + k²β²/2}
//!                            · [Φ(ti+1 + kβ) − Φ(ti + kβ)],
//!
//! so the integration is exact (no quadrature error) for the interpolated curve. Ends: below
//! the first point λ stays λ1 and nothing is counted; above the last one the last segment's
//! power law goes on to infinity (included). What the first segment's power law continued
//! downward would add is reported as a share, as is the share held above the last point.

use super::hazard::HazardCurve;
use crate::stats::normal;
use serde::{Deserialize, Serialize};

/// The MAF of one fragility over one hazard and where it comes from.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Maf {
    /// Mean annual frequency of reaching the state (1/yr).
    pub maf: f64,
    /// What the first segment's power law continued below the table would add, as a share of
    /// the MAF with it.
    pub share_below: f64,
    /// The share of the MAF from above the last point (the power-law extrapolation).
    pub share_above: f64,
    /// The intensities (in the hazard's IM as integrated) below which 10 %, 50 % and 90 % of
    /// the MAF accrue: the deaggregation of the integrand, [p10, p90] holds 80 % of it.
    pub deaggregation: [f64; 3],
}

/// The integrand per unit ln x, P(DS | x) |dλ/dx| x (1/yr): where the MAF comes from.
pub fn integrand(h: &HazardCurve, median: f64, beta: f64, x: f64) -> f64 {
    normal::cdf((x / median).ln() / beta) * h.slope_at(x) * h.rate(x)
}

/// P(a < Z < b) for a standard normal Z, without cancellation in either tail.
fn normal_mass(a: f64, b: f64) -> f64 {
    if a > 0.0 {
        normal::cdf(-a) - normal::cdf(-b)
    } else {
        normal::cdf(b) - normal::cdf(a)
    }
}

/// One power-law piece λ = rate0 e^{−k (u − u0)} on [u0, u1] (u1 may be +∞).
struct Piece {
    u0: f64,
    u1: f64,
    rate0: f64,
    k: f64,
}

impl Piece {
    fn rate(&self, u: f64) -> f64 {
        if u == f64::INFINITY {
            0.0
        } else {
            self.rate0 * (-self.k * (u - self.u0)).exp()
        }
    }

    /// ∫_{u0}^{u} Φ((v − m)/β) k λ(v) dv, by the closed form above.
    fn integral_to(&self, u: f64, m: f64, beta: f64) -> f64 {
        if self.k <= 0.0 || u <= self.u0 {
            return 0.0;
        }
        let (t0, t1) = ((self.u0 - m) / beta, (u - m) / beta);
        let p1 = if u == f64::INFINITY {
            0.0
        } else {
            normal::cdf(t1) * self.rate(u)
        };
        let kb = self.k * beta;
        let gauss = (self.k * (self.u0 - m) + 0.5 * kb * kb).exp() * normal_mass(t0 + kb, t1 + kb);
        (normal::cdf(t0) * self.rate0 - p1 + self.rate0 * gauss).max(0.0)
    }
}

/// The table's pieces in u = ln x, the last one running to +∞.
fn pieces(h: &HazardCurve) -> Vec<Piece> {
    let n = h.x.len();
    (0..n - 1)
        .map(|i| Piece {
            u0: h.x[i].ln(),
            u1: h.x[i + 1].ln(),
            rate0: h.rate[i],
            k: h.slope(i),
        })
        .chain(std::iter::once(Piece {
            u0: h.x[n - 1].ln(),
            u1: f64::INFINITY,
            rate0: h.rate[n - 1],
            k: h.slope(n - 2),
        }))
        .collect()
}

/// λ_DS for a lognormal fragility with median `median` and dispersion `beta`, both in the
/// hazard curve's intensity measure.
pub fn maf(h: &HazardCurve, median: f64, beta: f64) -> Maf {
    let m = median.ln();
    let pieces = pieces(h);
    let parts: Vec<f64> = pieces
        .iter()
        .map(|p| p.integral_to(p.u1, m, beta))
        .collect();
    let total: f64 = parts.iter().sum();
    // Below the table: the first segment's power law from −∞ to u0, the same closed form with
    // Φ(t0 + kβ) for the Gaussian part (the P λ term vanishes at −∞).
    let first = &pieces[0];
    let below = if first.k > 0.0 {
        let t0 = (first.u0 - m) / beta;
        let kb = first.k * beta;
        let gauss = (first.k * (first.u0 - m) + 0.5 * kb * kb).exp() * normal::cdf(t0 + kb);
        (first.rate0 * gauss - normal::cdf(t0) * first.rate0).max(0.0)
    } else {
        0.0
    };
    let share = |part: f64, of: f64| if of > 0.0 { part / of } else { 0.0 };
    Maf {
        maf: total,
        share_below: share(below, total + below),
        share_above: share(parts[parts.len() - 1], total),
        deaggregation: [0.1, 0.5, 0.9].map(|q| quantile(&pieces, &parts, total, q, m, beta)),
    }
}

/// The intensity below which a share q of the MAF accrues: the piece holding it, then
/// bisection in u on the piece's closed-form partial integral.
fn quantile(pieces: &[Piece], parts: &[f64], total: f64, q: f64, m: f64, beta: f64) -> f64 {
    if total <= 0.0 {
        return f64::NAN;
    }
    let target = q * total;
    let mut before = 0.0;
    for (p, &part) in pieces.iter().zip(parts) {
        if before + part < target && p.u1.is_finite() {
            before += part;
            continue;
        }
        let want = target - before;
        // The last piece is unbounded: bracket it first (the integrand decays as e^{−k u}).
        let mut hi = if p.u1.is_finite() { p.u1 } else { p.u0 + 1.0 };
        while !p.u1.is_finite() && p.integral_to(hi, m, beta) < want && hi < p.u0 + 200.0 {
            hi += 1.0;
        }
        let mut lo = p.u0;
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if p.integral_to(mid, m, beta) < want {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        return (0.5 * (lo + hi)).exp();
    }
    f64::NAN
}

#[cfg(test)]
mod tests {
    use super::super::hazard::HazardIm;
    use super::*;

    /// A hazard table sampled from λ = k0 x^−k at `n` log-spaced points over [lo, hi].
    fn power_law_table(k0: f64, k: f64, lo: f64, hi: f64, n: usize) -> HazardCurve {
        let x: Vec<f64> = (0..n)
            .map(|i| lo * (hi / lo).powf(i as f64 / (n - 1) as f64))
            .collect();
        HazardCurve {
            im: HazardIm::Pga,
            rate: x.iter().map(|x| k0 * x.powf(-k)).collect(),
            x,
        }
    }

    #[test]
    fn a_power_law_hazard_gives_cornells_closed_form() {
        // Cornell, Jalayer, Hamburger & Foutch (2002): λ_DS = k0 θ^−k exp(k²β²/2).
        for (k0, k, theta, beta) in [
            (1e-4, 2.0, 0.8, 0.4),
            (4.0e-4, 3.0, 1.5, 0.3),
            (2.5e-5, 1.5, 0.3, 0.6),
            (1e-3, 2.6, 4.0, 0.5),
            (0.02, 4.0, 6.0, 0.25),
        ] {
            let closed = k0 * f64::powf(theta, -k) * (k * k * beta * beta / 2.0).exp();
            // A table from 30 % of the first intensity that matters up to θ·e^{2β}: the
            // closed form's whole integrand lies inside or above it.
            let lo = theta * (-6.0 * beta - k * beta * beta).exp();
            let h = power_law_table(k0, k, lo, theta * (2.0 * beta).exp(), 9);
            let r = maf(&h, theta, beta);
            assert!(
                (r.maf / closed - 1.0).abs() < 1e-4,
                "k0 {k0} k {k} θ {theta} β {beta}: {} vs {closed}",
                r.maf
            );
            assert!(r.share_below < 1e-4, "{}", r.share_below);
        }
    }

    #[test]
    fn a_table_cut_above_the_integrand_reports_what_its_lower_end_could_hold() {
        let (k0, k, theta, beta) = (1e-4, 2.5, 1.0, 0.5);
        let closed = k0 * (k * k * beta * beta / 2.0_f64).exp();
        // Starting at the median: the points below hold most of the risk.
        let h = power_law_table(k0, k, theta, 20.0 * theta, 6);
        let r = maf(&h, theta, beta);
        // Counted: everything above the first point; the share below completes the closed form.
        let with_below = r.maf / (1.0 - r.share_below);
        assert!(
            (with_below / closed - 1.0).abs() < 1e-12,
            "{with_below} vs {closed}"
        );
        assert!(r.share_below > 0.5, "{r:?}");
    }

    #[test]
    fn a_curved_hazard_agrees_with_brute_force_quadrature() {
        // A hazard whose log-log slope changes at every point; the MAF of its interpolation
        // against a fine midpoint rule on P(x)|dλ/dx| in ln x (segments' slopes, exact λ).
        let x: Vec<f64> = (0..12).map(|i| 0.05 * 1.4f64.powi(i)).collect();
        let rate: Vec<f64> = x
            .iter()
            .map(|x: &f64| (-4.0 - 1.8 * x.ln() - 0.25 * x.ln().powi(2)).exp())
            .collect();
        let h = HazardCurve {
            im: HazardIm::Pga,
            x: x.clone(),
            rate,
        };
        let (theta, beta) = (0.6, 0.45);
        let r = maf(&h, theta, beta);
        // Midpoints within each segment (the integrand jumps where the slope does).
        let mut ends: Vec<f64> = x.iter().map(|x| x.ln()).collect();
        ends.push(x[11].ln() + 12.0);
        let mut cumulative = vec![(ends[0], 0.0)];
        for j in 0..ends.len() - 1 {
            let n = 20_000;
            let du = (ends[j + 1] - ends[j]) / n as f64;
            let k = h.slope(j.min(10));
            for i in 0..n {
                let u = ends[j] + (i as f64 + 0.5) * du;
                let p = normal::cdf((u - f64::ln(theta)) / beta);
                let sum = cumulative.last().unwrap().1 + p * k * h.rate(u.exp()) * du;
                cumulative.push((u + 0.5 * du, sum));
            }
        }
        let brute = cumulative.last().unwrap().1;
        assert!((r.maf / brute - 1.0).abs() < 1e-7, "{} vs {brute}", r.maf);
        for (q, found) in [0.1, 0.5, 0.9].iter().zip(r.deaggregation) {
            let at = cumulative.iter().find(|(_, c)| *c >= q * brute).unwrap().0;
            assert!(
                (found.ln() - at).abs() < 1e-3,
                "q {q}: {found} vs {}",
                at.exp()
            );
        }
    }
}
