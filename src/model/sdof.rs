//! Exact step of an underdamped linear oscillator under piecewise-linear forcing (Nigam &
//! Jennings 1969; Chopra, "Dynamics of Structures", §5.2):
//!
//!   ü + 2σ u̇ + ω² u = f(τ),  f(τ) = f0 + b τ on [0, h],  σ = ζω, 0 ≤ ζ < 1.
//!
//! The solution is the particular response to the ramp plus a damped free vibration,
//!   u(τ) = P + Q τ + e^{−στ} (C1 cos ωd τ + C2 sin ωd τ),  ωd = ω √(1 − ζ²),
//!   Q = b/ω², P = (f0 − 2σ Q)/ω²,  C1 = u0 − P,  C2 = (v0 − Q + σ C1)/ωd,
//! which is the A, B, C, D recurrence of the references written out once per interval, so
//! the state can also be read at any instant inside it (events, peaks, quadratures).

/// The homogeneous part of the oscillator: ω, σ = ζω, ωd.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Oscillator {
    omega: f64,
    sigma: f64,
    omega_d: f64,
}

impl Oscillator {
    /// ü + 2ζω u̇ + ω² u = f. `None` unless ω > 0 and 0 ≤ ζ < 1 (critically damped and
    /// overdamped columns have another closed form; the general integrator handles them).
    pub fn new(omega: f64, zeta: f64) -> Option<Self> {
        (omega > 0.0 && omega.is_finite() && (0.0..1.0).contains(&zeta)).then(|| Oscillator {
            omega,
            sigma: zeta * omega,
            omega_d: omega * (1.0 - zeta * zeta).sqrt(),
        })
    }

    pub fn omega_d(&self) -> f64 {
        self.omega_d
    }

    /// The free-vibration basis at τ.
    #[inline]
    pub fn basis(&self, tau: f64) -> Basis {
        let (sin, cos) = (self.omega_d * tau).sin_cos();
        Basis {
            tau,
            decay: (-self.sigma * tau).exp(),
            cos,
            sin,
        }
    }

    /// The response from (u0, v0) to the forcing f0 + b τ.
    pub fn segment(&self, u0: f64, v0: f64, f0: f64, b: f64) -> Segment {
        let w2 = self.omega * self.omega;
        let q = b / w2;
        let p = (f0 - 2.0 * self.sigma * q) / w2;
        let c1 = u0 - p;
        let c2 = (v0 - q + self.sigma * c1) / self.omega_d;
        Segment {
            osc: *self,
            f0,
            b,
            p,
            q,
            c1,
            c2,
        }
    }
}

/// e^{−στ}, cos ωd τ and sin ωd τ at one instant τ: all the closed form needs that costs
/// transcendental functions, so intervals of one length can share them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Basis {
    pub tau: f64,
    decay: f64,
    cos: f64,
    sin: f64,
}

/// The closed-form response over one interval, τ measured from its start.
#[derive(Clone, Copy, Debug)]
pub struct Segment {
    osc: Oscillator,
    f0: f64,
    b: f64,
    p: f64,
    q: f64,
    c1: f64,
    c2: f64,
}

impl Segment {
    /// (u, u̇) at τ.
    #[inline]
    pub fn state(&self, tau: f64) -> (f64, f64) {
        self.state_at(&self.osc.basis(tau))
    }

    /// (u, u̇) at the instant of a precomputed basis (no transcendental functions).
    #[inline]
    pub fn state_at(&self, basis: &Basis) -> (f64, f64) {
        let Oscillator { sigma, omega_d, .. } = self.osc;
        let Basis {
            tau,
            decay: e,
            cos: cs,
            sin: sn,
        } = *basis;
        let (c1, c2) = (self.c1, self.c2);
        let u = self.p + self.q * tau + e * (c1 * cs + c2 * sn);
        let v = self.q + e * ((omega_d * c2 - sigma * c1) * cs - (sigma * c2 + omega_d * c1) * sn);
        (u, v)
    }

    /// ü at τ, from the equation of motion.
    #[inline]
    pub fn accel(&self, tau: f64, u: f64, v: f64) -> f64 {
        self.forcing(tau) - 2.0 * self.osc.sigma * v - self.osc.omega * self.osc.omega * u
    }

    /// The basis of this segment's oscillator at τ.
    #[inline]
    pub fn basis(&self, tau: f64) -> Basis {
        self.osc.basis(tau)
    }

    #[inline]
    pub fn forcing(&self, tau: f64) -> f64 {
        self.f0 + self.b * tau
    }
}

/// Nodes τ_i and weights w_i of 5-point Gauss–Legendre on [0, h]: ∫₀^h g ≈ Σ w_i g(τ_i).
pub fn gauss_legendre_5_nodes(h: f64) -> [(f64, f64); 5] {
    let half = 0.5 * h;
    std::array::from_fn(|i| (half * (1.0 + GL5_NODES[i]), half * GL5_WEIGHTS[i]))
}

const GL5_NODES: [f64; 5] = [
    0.0,
    -0.538_469_310_105_683_1,
    0.538_469_310_105_683_1,
    -0.906_179_845_938_664,
    0.906_179_845_938_664,
];
const GL5_WEIGHTS: [f64; 5] = [
    0.568_888_888_888_888_9,
    0.478_628_670_499_366_47,
    0.478_628_670_499_366_47,
    0.236_926_885_056_189_08,
    0.236_926_885_056_189_08,
];

/// ∫₀^h g(τ) dτ by 5-point Gauss–Legendre: exact for polynomials of degree 9. On the closed
/// form the integrands (u̇², f u̇) are analytic with frequency ≤ 2ω, and the rule's error is
/// ~ 4e-13 h max|g| (2ωh)^10; callers keep ωh ≤ 0.5, and a record's ωh ≈ 0.06 gives ~1e-22.
pub fn gauss_legendre_5<const K: usize>(h: f64, g: impl Fn(f64) -> [f64; K]) -> [f64; K] {
    let mut sum = [0.0; K];
    for (tau, w) in gauss_legendre_5_nodes(h) {
        for (s, v) in sum.iter_mut().zip(g(tau)) {
            *s += w * v;
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The segment satisfies its own equation and initial conditions (finite differences).
    #[test]
    fn segment_satisfies_the_equation_of_motion() {
        for zeta in [0.0, 0.02, 0.5, 0.95] {
            let osc = Oscillator::new(12.0, zeta).unwrap();
            let seg = osc.segment(0.01, -0.3, 2.0, -40.0);
            assert!((seg.state(0.0).0 - 0.01).abs() < 1e-17);
            assert!((seg.state(0.0).1 + 0.3).abs() < 1e-15);
            let d = 1e-5;
            for tau in [0.001, 0.01, 0.1] {
                let (u, v) = seg.state(tau);
                let (up, vp) = seg.state(tau + d);
                let (um, vm) = seg.state(tau - d);
                assert!(((up - um) / (2.0 * d) - v).abs() < 1e-8);
                let a = (vp - vm) / (2.0 * d);
                assert!((a - seg.accel(tau, u, v)).abs() < 1e-6 * a.abs().max(1.0));
            }
        }
    }

    #[test]
    fn critical_and_overdamped_are_refused() {
        assert!(Oscillator::new(12.0, 1.0).is_none());
        assert!(Oscillator::new(12.0, 1.5).is_none());
        assert!(Oscillator::new(0.0, 0.1).is_none());
        assert!(Oscillator::new(12.0, -0.1).is_none());
    }

    #[test]
    fn gauss_legendre_integrates_degree_nine_exactly() {
        let exact = 2f64.powi(10) / 10.0;
        let [p9, sin] = gauss_legendre_5(2.0, |t| [t.powi(9), (t / 4.0).sin()]);
        assert!((p9 - exact).abs() < 1e-12 * exact);
        assert!((sin - 4.0 * (1.0 - 0.5f64.cos())).abs() < 1e-15);
    }
}
