//! Response spectra: Sa(T, ξ) = ω² max|u| of u'' + 2ξω u' + ω² u = −a(t) from rest, by the
//! Nigam & Jennings (1969) recurrence, exact for the piecewise-linear record. The peak is
//! taken at the samples and over the record's duration (no free vibration after it), as
//! eqsig and pyrotd's time-domain peak do; between samples |u| can be a little larger (a few
//! % at T ≈ 10 dt, negligible at T ≥ 50 dt).

use super::{Accelerogram, ImError};

/// The recurrence's coefficients for one (ω, ξ, dt): (u, v) at the next sample from (u, v) at
/// this one and the accelerations at both ends of the step.
struct Step {
    a: [[f64; 2]; 2],
    b: [[f64; 2]; 2],
}

impl Step {
    fn new(omega: f64, xi: f64, dt: f64) -> Step {
        let w = omega;
        let root = (1.0 - xi * xi).sqrt();
        let wd = w * root;
        let e = (-xi * w * dt).exp();
        let (s, c) = (wd * dt).sin_cos();
        let xr = xi / root;
        let a = [
            [e * (xr * s + c), e * s / wd],
            [-w / root * e * s, e * (c - xr * s)],
        ];
        // Nigam & Jennings' B for the forcing −a varying linearly from a_i to a_{i+1}.
        let k1 = (2.0 * xi * xi - 1.0) / (w * w * dt);
        let k2 = 2.0 * xi / (w * w * w * dt);
        let b11 = e * ((k1 + xi / w) * s / wd + (k2 + 1.0 / (w * w)) * c) - k2;
        let b12 = -e * (k1 * s / wd + k2 * c) - 1.0 / (w * w) + k2;
        let ds = c - xr * s;
        let dc = wd * s + xi * w * c;
        let b21 = e * ((k1 + xi / w) * ds - (k2 + 1.0 / (w * w)) * dc) + 1.0 / (w * w * dt);
        let b22 = -e * (k1 * ds - k2 * dc) - 1.0 / (w * w * dt);
        Step {
            a,
            b: [[b11, b12], [b21, b22]],
        }
    }
}

fn check(period: f64, damping: f64) -> Result<(), ImError> {
    if !(period.is_finite() && period > 0.0) {
        return Err(ImError::Period(period));
    }
    if !(0.0..1.0).contains(&damping) {
        return Err(ImError::Damping(damping));
    }
    Ok(())
}

/// The relative displacement u at every sample of an oscillator of period T and damping ξ.
pub fn displacement(rec: &Accelerogram, period: f64, damping: f64) -> Result<Vec<f64>, ImError> {
    check(period, damping)?;
    let omega = 2.0 * std::f64::consts::PI / period;
    let step = Step::new(omega, damping, rec.dt);
    let (a, b) = (step.a, step.b);
    let mut out = Vec::with_capacity(rec.accel.len());
    let (mut u, mut v) = (0.0, 0.0);
    out.push(u);
    for w in rec.accel.windows(2) {
        let (p0, p1) = (w[0], w[1]);
        (u, v) = (
            a[0][0] * u + a[0][1] * v + b[0][0] * p0 + b[0][1] * p1,
            a[1][0] * u + a[1][1] * v + b[1][0] * p0 + b[1][1] * p1,
        );
        out.push(u);
    }
    Ok(out)
}

/// Sa(T, ξ) in m/s² at each period: ω² times the peak |u| at the samples.
pub fn sa(rec: &Accelerogram, periods: &[f64], damping: f64) -> Result<Vec<f64>, ImError> {
    periods
        .iter()
        .map(|&t| {
            let omega = 2.0 * std::f64::consts::PI / t;
            let u = displacement(rec, t, damping)?;
            Ok(omega * omega * u.iter().fold(0.0_f64, |m, x| m.max(x.abs())))
        })
        .collect()
}

/// The periods Sa_avg averages over: `SA_AVG_POINTS` log-spaced from `from` to `to`, both ends
/// included (Eads et al. 2015 average Sa over a range; the number of periods is rocklab's
/// choice and stated in docs/MODEL.md).
pub fn sa_avg_periods(from: f64, to: f64) -> Result<Vec<f64>, ImError> {
    if !(from > 0.0 && to > from && to.is_finite()) {
        return Err(ImError::Range { from, to });
    }
    let n = SA_AVG_POINTS;
    Ok((0..n)
        .map(|k| from * (to / from).powf(k as f64 / (n - 1) as f64))
        .collect())
}

/// How many periods Sa_avg averages.
pub const SA_AVG_POINTS: usize = 10;

/// Sa_avg (m/s²): the geometric mean of Sa over [`sa_avg_periods`].
pub fn sa_avg(rec: &Accelerogram, from: f64, to: f64, damping: f64) -> Result<f64, ImError> {
    let sa = sa(rec, &sa_avg_periods(from, to)?, damping)?;
    Ok((sa.iter().map(|s| s.ln()).sum::<f64>() / sa.len() as f64).exp())
}

/// The rotation angles RotD50 takes the median over: 0°, 1°, …, 179° (pyrotd's default).
const ROTD_ANGLES: usize = 180;

/// RotD50 (m/s²) at each period: the median over rotation angles θ of ω² max|u1 cos θ +
/// u2 sin θ| (Boore 2010); the median of an even count is the mean of the middle two, as
/// numpy's percentile gives.
pub fn rotd50(
    first: &Accelerogram,
    second: &Accelerogram,
    periods: &[f64],
    damping: f64,
) -> Result<Vec<f64>, ImError> {
    if first.dt != second.dt || first.accel.len() != second.accel.len() {
        return Err(ImError::Pair(format!(
            "dt {} and {}, {} and {} samples",
            first.dt,
            second.dt,
            first.accel.len(),
            second.accel.len()
        )));
    }
    let rotations: Vec<(f64, f64)> = (0..ROTD_ANGLES)
        .map(|k| (k as f64).to_radians().sin_cos())
        .collect();
    periods
        .iter()
        .map(|&t| {
            let omega = 2.0 * std::f64::consts::PI / t;
            let u1 = displacement(first, t, damping)?;
            let u2 = displacement(second, t, damping)?;
            let mut peaks: Vec<f64> = rotations
                .iter()
                .map(|(s, c)| {
                    u1.iter()
                        .zip(&u2)
                        .fold(0.0_f64, |m, (x, y)| m.max((x * c + y * s).abs()))
                })
                .collect();
            peaks.sort_by(f64::total_cmp);
            let mid = ROTD_ANGLES / 2;
            Ok(omega * omega * 0.5 * (peaks[mid - 1] + peaks[mid]))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Undamped oscillator under a constant a0 from rest: u = −(a0/ω²)(1 − cos ωt), exact at
    /// every sample (the record is linear between samples, so the recurrence is exact).
    #[test]
    fn step_response_is_exact_at_the_samples() {
        let (a0, period, dt) = (2.5, 0.7, 0.013);
        let rec = Accelerogram::new(dt, vec![a0; 400]).unwrap();
        let w = 2.0 * PI / period;
        let u = displacement(&rec, period, 0.0).unwrap();
        for (k, uk) in u.iter().enumerate() {
            let exact = -(a0 / (w * w)) * (1.0 - (w * k as f64 * dt).cos());
            assert!((uk - exact).abs() < 1e-12, "{k}: {uk} vs {exact}");
        }
        // A ramp a = r t, damped: u tends to the particular solution −(r/ω²)(t − 2ξ/ω).
        let (r, xi) = (0.8, 0.3);
        let rec = Accelerogram::new(dt, (0..4000).map(|k| r * k as f64 * dt).collect()).unwrap();
        let u = displacement(&rec, period, xi).unwrap();
        let t = 3999.0 * dt;
        let particular = -(r / (w * w)) * (t - 2.0 * xi / w);
        assert!(
            (u[3999] - particular).abs() < 1e-9,
            "{} {particular}",
            u[3999]
        );
    }

    /// Sa of a long sine at resonance tends to the steady state: u amplitude
    /// A / (2 ξ ω²), so Sa = A / (2ξ); the transient decays as exp(−ξωt).
    #[test]
    fn sa_of_a_sine_at_resonance_is_the_steady_state() {
        let (amp, period, xi, dt) = (1.3, 0.5, 0.05, 0.001);
        let w = 2.0 * PI / period;
        // 200 periods: the transient is exp(−ξ·2π·200) ≈ 0.
        let n = (200.0 * period / dt) as usize;
        let rec = Accelerogram::new(
            dt,
            (0..n).map(|k| amp * (w * k as f64 * dt).sin()).collect(),
        )
        .unwrap();
        let sa = sa(&rec, &[period], xi).unwrap()[0];
        // At resonance the damped steady state is exactly A/(2ξω²) in amplitude (peak read at
        // samples: 500 per period, relative error ≤ 1 − cos(π/500) ≈ 2e-5).
        let steady = amp / (2.0 * xi);
        assert!((sa - steady).abs() < 1e-4 * steady, "{sa} vs {steady}");
    }

    /// RotD50 of identical components is √2·cos(θ − 45°)'s median times Sa: the rotated
    /// history is (cos θ + sin θ) u, whose median |·| over 0..179° is that of |√2 cos(θ−45°)|.
    #[test]
    fn rotd50_of_identical_components() {
        let dt = 0.01;
        let rec = Accelerogram::new(
            dt,
            (0..2000)
                .map(|k| (k as f64 * dt * 7.0).sin() * (-(k as f64) * dt * 0.3).exp())
                .collect(),
        )
        .unwrap();
        let periods = [0.3, 1.0];
        let single = sa(&rec, &periods, 0.05).unwrap();
        let rot = rotd50(&rec, &rec, &periods, 0.05).unwrap();
        let mut factors: Vec<f64> = (0..180)
            .map(|k| {
                let (s, c) = (k as f64).to_radians().sin_cos();
                (s + c).abs()
            })
            .collect();
        factors.sort_by(f64::total_cmp);
        let median = 0.5 * (factors[89] + factors[90]);
        for (r, s) in rot.iter().zip(&single) {
            assert!((r - median * s).abs() < 1e-12 * s, "{r} vs {}", median * s);
        }
    }

    #[test]
    fn bad_periods_and_damping_are_refused() {
        let rec = Accelerogram::new(0.01, vec![0.0, 1.0, 0.0]).unwrap();
        assert_eq!(sa(&rec, &[0.0], 0.05), Err(ImError::Period(0.0)));
        assert_eq!(sa(&rec, &[1.0], 1.0), Err(ImError::Damping(1.0)));
        assert!(sa_avg(&rec, 2.0, 1.0, 0.05).is_err());
    }
}
