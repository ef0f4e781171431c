//! Maximum-likelihood lognormal fits: the binomial (probit) fit over stripes (Baker 2015,
//! Earthquake Spectra 31(1), eq. 11) and the right-censored fit to IDA capacities, plus the
//! method of moments that the censored fit reduces to when nothing is censored.
//!
//! Both likelihoods are maximised in a reparametrisation where they are globally concave, so
//! Newton's method with step halving converges from any start:
//! - stripes: P(exceed | x) = Φ(a + b ln x) with b = 1/β, a = −ln θ/β (the probit GLM);
//! - IDA: ln C ~ N(μ, σ²) with a = μ/σ, b = 1/σ (Olsen's reparametrisation of the Tobit model).
//!
//! The optimiser is written out (about forty lines) rather than taken from a crate: the problem
//! is two-dimensional with exact gradients and Hessians, and an optimisation crate (argmin and
//! its linear-algebra stack) would be a far larger dependency than the code it replaces.

use super::normal::{ln_cdf, mills, mills_slope};
use super::{FitStatus, StripePoint};

/// A lognormal fit: median θ and logarithmic standard deviation β.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lognormal {
    pub median: f64,
    pub beta: f64,
}

type Eval = (f64, [f64; 2], [[f64; 2]; 2]);

const MAX_ITERATIONS: usize = 200;

/// Maximise a concave function of two variables given its value, gradient and Hessian.
/// None if the iteration leaves the finite numbers or does not settle.
fn maximise(start: [f64; 2], f: impl Fn([f64; 2]) -> Eval) -> Option<[f64; 2]> {
    let mut x = start;
    let (mut value, mut g, mut h) = f(x);
    for _ in 0..MAX_ITERATIONS {
        let det = h[0][0] * h[1][1] - h[0][1] * h[1][0];
        // Newton's direction −H⁻¹g where H is negative definite, else plain ascent.
        let d = if h[0][0] < 0.0 && det > 0.0 {
            [
                -(h[1][1] * g[0] - h[0][1] * g[1]) / det,
                -(h[0][0] * g[1] - h[1][0] * g[0]) / det,
            ]
        } else {
            g
        };
        let mut step = 1.0;
        loop {
            let trial = [x[0] + step * d[0], x[1] + step * d[1]];
            let (v, tg, th) = f(trial);
            if v.is_finite() && v >= value - 1e-12 * value.abs() {
                let moved = (step * d[0]).abs().max((step * d[1]).abs());
                (x, value, g, h) = (trial, v, tg, th);
                if moved <= 1e-11 * (1.0 + x[0].abs().max(x[1].abs())) {
                    return Some(x);
                }
                break;
            }
            step *= 0.5;
            if step < 1e-12 {
                // No ascent along the direction: a maximum to working precision.
                return Some(x).filter(|x| x.iter().all(|v| v.is_finite()));
            }
        }
    }
    None
}

/// Stripes sorted by IM with equal IMs merged; stripes with no observation, or at an IM that
/// is not a positive number (no lognormal fragility reaches it), dropped.
pub fn merge_stripes(points: &[StripePoint]) -> Vec<StripePoint> {
    let mut sorted: Vec<StripePoint> = (points.iter().copied())
        .filter(|p| p.n > 0 && p.im > 0.0 && p.im.is_finite())
        .collect();
    sorted.sort_by(|a, b| a.im.total_cmp(&b.im));
    let mut merged: Vec<StripePoint> = Vec::with_capacity(sorted.len());
    for p in sorted {
        match merged.last_mut() {
            Some(last) if last.im == p.im => {
                last.n += p.n;
                last.exceed += p.exceed;
            }
            _ => merged.push(p),
        }
    }
    merged
}

/// Why a set of stripes has no finite maximum-likelihood fit, if it has none. `points` must
/// come from [`merge_stripes`].
pub fn stripes_degeneracy(points: &[StripePoint]) -> Option<FitStatus> {
    let exceed: usize = points.iter().map(|p| p.exceed).sum();
    let total: usize = points.iter().map(|p| p.n).sum();
    let with_exceedance = points.iter().filter(|p| p.exceed > 0).count();
    if total == 0 {
        Some(FitStatus::NoData)
    } else if points.len() < 2 {
        Some(FitStatus::OneStripe)
    } else if exceed == 0 {
        Some(FitStatus::NoExceedance)
    } else if exceed == total {
        Some(FitStatus::AllExceed)
    } else if with_exceedance == 1 {
        Some(FitStatus::OneStripeExceeds)
    } else if (0..points.len()).any(|k| {
        points[..k].iter().all(|p| p.exceed == 0) && points[k + 1..].iter().all(|p| p.exceed == p.n)
    }) {
        // (Quasi-)complete separation: none exceed below one stripe, all above it, so the
        // likelihood grows without bound as β → 0.
        Some(FitStatus::Separated)
    } else {
        None
    }
}

/// Binomial log-likelihood of stripes under P = Φ(a + b ln x), with gradient and Hessian.
fn probit_likelihood(points: &[StripePoint], [a, b]: [f64; 2]) -> Eval {
    let (mut v, mut g, mut h) = (0.0, [0.0; 2], [[0.0; 2]; 2]);
    for p in points {
        let lx = p.im.ln();
        let eta = a + b * lx;
        let (z, s) = (p.exceed as f64, (p.n - p.exceed) as f64);
        v += z * ln_cdf(eta) + s * ln_cdf(-eta);
        let d1 = z * mills(eta) - s * mills(-eta);
        let d2 = z * mills_slope(eta) + s * mills_slope(-eta);
        g[0] += d1;
        g[1] += d1 * lx;
        h[0][0] += d2;
        h[0][1] += d2 * lx;
        h[1][1] += d2 * lx * lx;
    }
    h[1][0] = h[0][1];
    (v, g, h)
}

/// Median and β maximising Baker's binomial likelihood over stripes, or why there is none.
pub fn fit_binomial_mle(points: &[StripePoint]) -> Result<Lognormal, FitStatus> {
    let points = merge_stripes(points);
    if let Some(status) = stripes_degeneracy(&points) {
        return Err(status);
    }
    // Start: median at the stripe whose exceedance fraction is nearest one half, β = 0.5.
    let frac = |p: &StripePoint| p.exceed as f64 / p.n as f64;
    let centre = points
        .iter()
        .min_by(|p, q| (frac(p) - 0.5).abs().total_cmp(&(frac(q) - 0.5).abs()))
        .map_or(1.0, |p| p.im);
    let start = [-centre.ln() / 0.5, 1.0 / 0.5];
    let [a, b] =
        maximise(start, |x| probit_likelihood(&points, x)).ok_or(FitStatus::NotConverged)?;
    if b <= 0.0 {
        return Err(FitStatus::Decreasing);
    }
    Ok(Lognormal {
        median: (-a / b).exp(),
        beta: 1.0 / b,
    })
}

/// Method of moments on ln capacities: median exp(mean), β the standard deviation (divisor n,
/// which is also the maximum-likelihood estimate).
pub fn fit_moments(capacities: &[f64]) -> Option<Lognormal> {
    let n = capacities.len() as f64;
    if capacities.len() < 2 {
        return None;
    }
    let mean = capacities.iter().map(|c| c.ln()).sum::<f64>() / n;
    let var = capacities
        .iter()
        .map(|c| (c.ln() - mean).powi(2))
        .sum::<f64>()
        / n;
    (var > 0.0).then(|| Lognormal {
        median: mean.exp(),
        beta: var.sqrt(),
    })
}

/// Log-likelihood of right-censored lognormal data in (a, b) = (μ/σ, 1/σ).
fn censored_likelihood(ln_cap: &[f64], ln_top: &[f64], [a, b]: [f64; 2]) -> Eval {
    let (mut v, mut g, mut h) = (0.0, [0.0; 2], [[0.0; 2]; 2]);
    for &y in ln_cap {
        let u = b * y - a;
        v += b.ln() - 0.5 * u * u;
        g[0] += u;
        g[1] += 1.0 / b - u * y;
        h[0][0] -= 1.0;
        h[0][1] += y;
        h[1][1] -= 1.0 / (b * b) + y * y;
    }
    for &y in ln_top {
        // Survived to `top`: ln P(C > top) = ln Φ(−u).
        let u = b * y - a;
        v += ln_cdf(-u);
        let k = -mills_slope(-u);
        g[0] += mills(-u);
        g[1] -= mills(-u) * y;
        h[0][0] -= k;
        h[0][1] += k * y;
        h[1][1] -= k * y * y;
    }
    h[1][0] = h[0][1];
    if b <= 0.0 {
        v = f64::NEG_INFINITY;
    }
    (v, g, h)
}

/// Lognormal fit to capacities (first IM reaching the state) with right-censoring: `tops` are
/// the top IMs of records that never reached the state.
pub fn fit_censored(capacities: &[f64], tops: &[f64]) -> Result<Lognormal, FitStatus> {
    // IMs that are not positive numbers carry no information on a lognormal capacity.
    let usable = |v: &&f64| **v > 0.0 && v.is_finite();
    let capacities: Vec<f64> = capacities.iter().filter(usable).copied().collect();
    let tops: Vec<f64> = tops.iter().filter(usable).copied().collect();
    let (capacities, tops) = (capacities.as_slice(), tops.as_slice());
    if capacities.is_empty() && tops.is_empty() {
        return Err(FitStatus::NoData);
    }
    if capacities.is_empty() {
        return Err(FitStatus::NoExceedance);
    }
    let first = capacities[0];
    if capacities.iter().all(|&c| c == first) {
        return Err(FitStatus::TooFewCapacities);
    }
    // Start from the moments of the uncensored capacities (the answer when none is censored:
    // the iteration then only confirms it, which the tests use as a cross-check).
    let start = fit_moments(capacities).ok_or(FitStatus::TooFewCapacities)?;
    let ln_cap: Vec<f64> = capacities.iter().map(|c| c.ln()).collect();
    let ln_top: Vec<f64> = tops.iter().map(|c| c.ln()).collect();
    let x0 = [start.median.ln() / start.beta, 1.0 / start.beta];
    let [a, b] = maximise(x0, |x| censored_likelihood(&ln_cap, &ln_top, x))
        .ok_or(FitStatus::NotConverged)?;
    Ok(Lognormal {
        median: (a / b).exp(),
        beta: 1.0 / b,
    })
}
