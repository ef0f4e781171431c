//! The mechanistic one-way clutch (docs/MODEL.md "Devices", paper Eqs. 19–21, 55–59), in the
//! translational form y = ρ θ_flywheel: spring k = kθ/ρ², smoothing ε̂ = ε/ρ, flywheel mass mr.

use std::f64::consts::PI;

/// Smoothed one-sided spring of clutch a: f = ½ k [1 + tanh(ε̂ z)] z with z = δ − up.
/// Clutch b is the mirror image: f_b(δ) = −f_a(−δ).
#[inline]
pub fn clutch_force(k: f64, eps_hat: f64, z: f64) -> f64 {
    0.5 * k * (1.0 + (eps_hat * z).tanh()) * z
}

/// Potential of [`clutch_force`], V(z) = ∫_{-∞}^{z} f dz, exact for any ε̂:
/// with w = 2ε̂z, V = k/(4ε̂²) · (w·softplus(w) + Li₂(−eʷ)). For w ≫ 1 this is ½kz² − kπ²/(24ε̂²).
pub fn clutch_potential(k: f64, eps_hat: f64, z: f64) -> f64 {
    let w = 2.0 * eps_hat * z;
    if w > 60.0 {
        // Li₂(−eʷ) = −π²/6 − w²/2 − Li₂(−e⁻ʷ), and Li₂(−e⁻ʷ) < 1e-26 here.
        return 0.5 * k * z * z - k * PI * PI / (24.0 * eps_hat * eps_hat);
    }
    if w < -60.0 {
        return 0.0;
    }
    let softplus = if w > 0.0 {
        w + (-w).exp().ln_1p()
    } else {
        w.exp().ln_1p()
    };
    k / (4.0 * eps_hat * eps_hat) * (w * softplus + dilog_neg_exp(w))
}

/// Li₂(−eʷ) for real w.
fn dilog_neg_exp(w: f64) -> f64 {
    if w > 0.0 {
        // Inversion: Li₂(−x) = −π²/6 − ½ ln²x − Li₂(−1/x).
        -PI * PI / 6.0 - 0.5 * w * w - dilog_neg_exp(-w)
    } else {
        dilog_small(-(w.exp()))
    }
}

/// Li₂(x) for x ∈ [−1, 0], via the Bernoulli series in u = −ln(1 − x) (|u| ≤ ln 2).
fn dilog_small(x: f64) -> f64 {
    // B_n / (n+1)! for n = 0..: 1, −1/4, 1/36, 0, −1/3600, 0, 1/211680, 0, −1/10886400, ...
    const COEF: [f64; 10] = [
        1.0,
        -0.25,
        1.0 / 36.0,
        -1.0 / 3600.0,
        1.0 / 211_680.0,
        -1.0 / 10_886_400.0,
        1.0 / 526_901_760.0,
        -4.064_761_645_144_225_5e-11,
        8.921_691_020_456_453e-13,
        -1.993_929_586_072_107_6e-14,
    ];
    let u = -(-x).ln_1p();
    // Terms: u − u²/4 + Σ_{j≥1} COEF[j+1] u^{2j+1}.
    let u2 = u * u;
    let mut sum = u - 0.25 * u2;
    let mut p = u * u2;
    for c in &COEF[2..] {
        sum += c * p;
        p *= u2;
    }
    sum
}

/// Dry friction of a flywheel: Fμ = (2 F/π) atan(η ẏ/ρ), F the friction force magnitude.
#[inline]
pub fn friction_force(force: f64, eta: f64, rho: f64, ydot: f64) -> f64 {
    if force == 0.0 {
        0.0
    } else {
        2.0 * force / PI * (eta * ydot / rho).atan()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dilog_matches_known_values() {
        // Li₂(−1) = −π²/12, Li₂(−1/2) = −0.4484142069236462.
        assert!((dilog_small(-1.0) + PI * PI / 12.0).abs() < 1e-14);
        assert!((dilog_small(-0.5) + 0.448_414_206_923_646_2).abs() < 1e-14);
        assert_eq!(dilog_small(0.0), 0.0);
    }

    #[test]
    fn potential_is_the_antiderivative_of_the_force() {
        let (k, e) = (5000.0, 200.0);
        for z in [-0.02, -0.004, -1e-4, 0.0, 1e-4, 0.003, 0.05] {
            let h = 1e-7;
            let dv = (clutch_potential(k, e, z + h) - clutch_potential(k, e, z - h)) / (2.0 * h);
            let f = clutch_force(k, e, z);
            assert!(
                (dv - f).abs() < 1e-6 * (1.0 + f.abs()),
                "z={z}: dV={dv} f={f}"
            );
        }
        assert!(clutch_potential(k, e, -1.0).abs() < 1e-30);
    }
}
