//! The flexible structure's full-contact phase in closed form. With no device or a rigidly
//! coupled inerter, full contact under a record is a linear SDOF under piecewise-linear
//! forcing: it is advanced exactly ([`super::sdof`]), one record sample at a time, with its
//! peaks, energy integrals and the first uplift located on the closed form, and handed over to
//! the integrator at the uplift.

use super::flexible::Column;
use super::sdof::{Basis, Oscillator, Segment, gauss_legendre_5_nodes};
use super::shell::{Accumulator, Layout};
use super::{Peaks, refined_max_of_samples};
use crate::excitation::RecordMotion;

/// Full contact with a linear device: (m + mc) ü + c u̇ + k u = −m a_g (Eq. 41 with
/// Fd = −mc ü), i.e. ü + 2ζω u̇ + ω² u = −(m/M) a_g with M = m + mc, ω² = k/M, 2ζω = c/M.
pub struct ClosedFormContact {
    osc: Oscillator,
    /// m/M: the share of the ground's inertial load per unit moving mass.
    load_ratio: f64,
    /// Longest closed-form interval (ωd h ≤ 0.5 rad), so that samples at quarters resolve
    /// every extremum and the quadrature stays at roundoff.
    max_interval: f64,
    /// The closed form's basis at the nodes of the last few interval lengths.
    nodes: [Option<IntervalNodes>; 4],
    nodes_next: usize,
    /// State indices of the input-work and column-damping integrals (None without the
    /// energy ledger).
    ledger: Option<(usize, usize)>,
}

/// The closed form's basis (e^{−στ}, cos ωd τ, sin ωd τ) at the interior quarter points, the
/// end and the Gauss–Legendre nodes of an interval of length h.
#[derive(Clone, Copy, Debug)]
struct IntervalNodes {
    h: f64,
    quarters: [Basis; 3],
    end: Basis,
    gauss: [(Basis, f64); 5],
}

impl IntervalNodes {
    fn new(osc: &Oscillator, h: f64) -> Self {
        IntervalNodes {
            h,
            quarters: std::array::from_fn(|k| osc.basis(h * (k + 1) as f64 / 4.0)),
            end: osc.basis(h),
            gauss: gauss_legendre_5_nodes(h).map(|(tau, w)| (osc.basis(tau), w)),
        }
    }
}

/// The closed-form state (u, u̇, ü) at one instant τ of a contact segment.
#[derive(Clone, Copy, Debug)]
struct Sample {
    tau: f64,
    u: f64,
    v: f64,
    a: f64,
}

impl Sample {
    fn new(seg: &Segment, basis: &Basis) -> Self {
        let (u, v) = seg.state_at(basis);
        Sample {
            tau: basis.tau,
            u,
            v,
            a: seg.accel(basis.tau, u, v),
        }
    }
}

impl ClosedFormContact {
    /// The contact oscillator of `column` with coupled mass `mc`, for a state laid out by
    /// `layout`; None for a critically damped or overdamped column (the integrator handles
    /// those).
    pub fn new(column: &Column, mc: f64, layout: Layout) -> Option<Self> {
        let total = column.m + mc;
        let omega = (column.k / total).sqrt();
        let zeta = column.c / (2.0 * (column.k * total).sqrt());
        Oscillator::new(omega, zeta).map(|osc| ClosedFormContact {
            osc,
            load_ratio: column.m / total,
            max_interval: 0.5 / osc.omega_d(),
            nodes: [None; 4],
            nodes_next: 0,
            ledger: layout
                .accumulator(Accumulator::Input)
                .zip(layout.accumulator(Accumulator::Own)),
        })
    }

    /// One closed-form interval of full contact: from t to the next record sample (or t_stop,
    /// or the longest interval), stopping early at an uplift. Updates (u, u̇) and the input
    /// and column-damping integrals in `y`, and the peaks. Returns the new time and the side
    /// of the uplift it stopped at, if any; None if there is no interval left to advance.
    pub fn advance(
        &mut self,
        column: &Column,
        record: &RecordMotion,
        peaks: &mut Peaks,
        t: f64,
        t_stop: f64,
        y: &mut [f64],
    ) -> Option<(f64, Option<f64>)> {
        use super::flexible::{U, U_DOT};
        let (t1, a0, a1) = record_interval(record, t, t_stop, self.max_interval);
        let h = t1 - t;
        if h <= 0.0 {
            return None;
        }
        let slope = (a1 - a0) / h;
        let ground = |tau: f64| a0 + slope * tau;
        let osc = self.osc;
        let seg = osc.segment(
            y[U],
            y[U_DOT],
            -self.load_ratio * a0,
            -self.load_ratio * slope,
        );
        let nodes = self.interval_nodes(&osc, h);
        let at = |basis: &Basis| Sample::new(&seg, basis);
        let mut samples = [
            Sample::new(&seg, &osc.basis(0.0)),
            at(&nodes.quarters[0]),
            at(&nodes.quarters[1]),
            at(&nodes.quarters[2]),
            at(&nodes.end),
        ];
        let (tau_end, uplift, gauss) = match first_uplift(column, &seg, &samples) {
            Some((tau, side)) => {
                samples = std::array::from_fn(|k| at(&osc.basis(tau * k as f64 / 4.0)));
                let gauss = gauss_legendre_5_nodes(tau).map(|(x, w)| (osc.basis(x), w));
                (tau, Some(side), gauss)
            }
            None => {
                let stretch = h / nodes.h;
                (h, None, nodes.gauss.map(|(b, w)| (b, w * stretch)))
            }
        };
        observe_segment(column, peaks, &seg, &samples, &ground);
        if let Some((input, damping)) = self.ledger {
            for (basis, w) in gauss {
                let (_, v) = seg.state_at(&basis);
                y[input] -= w * column.m * ground(basis.tau) * v;
                y[damping] += w * column.c * v * v;
            }
        }
        (y[U], y[U_DOT]) = (samples[4].u, samples[4].v);
        let t_end = if tau_end == h { t1 } else { t + tau_end };
        Some((t_end, uplift))
    }

    /// The bases at the nodes of an interval of length h, from a small cache keyed by h's bits:
    /// a record's intervals t0 + k dt take only a few distinct lengths (dt to roundoff), so
    /// an interval rarely costs a transcendental function.
    fn interval_nodes(&mut self, osc: &Oscillator, h: f64) -> IntervalNodes {
        if let Some(n) = self.nodes.iter().flatten().find(|n| n.h == h) {
            return *n;
        }
        let slot = self.nodes_next % self.nodes.len();
        self.nodes_next += 1;
        *self.nodes[slot].insert(IntervalNodes::new(osc, h))
    }
}

/// The earliest uplift (Eqs. 37–38, either side) on a contact segment: the margin rising
/// through zero between two samples, or peaking above zero between samples where it is
/// negative (its rate turns from + to − and the end tangents allow it to reach zero).
/// The margin is linear in (u, u̇), so its second derivative is a damped free vibration
/// with zeros π/ωd apart: samples ≤ ωd h/4 ≤ 0.125 rad apart hold at most one inflection,
/// the peak lies on a concave stretch, below the tangent at one end (the factor 2 is
/// margin). Not seen: a rate turning −, +, − within one piece, which can only graze zero by
/// a third-order amount. Located by bisection to roundoff; the returned τ is on the lifted
/// side (margin ≥ 0).
fn first_uplift(column: &Column, seg: &Segment, samples: &[Sample; 5]) -> Option<(f64, f64)> {
    let margin = |side: f64, s: &Sample| column.uplift_margin(side, s.u, s.v);
    // d/dt of the margin: s (k u̇ + c ü) H + m g s u̇.
    let rate = |side: f64, s: &Sample| {
        side * ((column.k * s.v + column.c * s.a) * column.h + column.m * column.g * s.v)
    };
    let fresh = |tau: f64| Sample::new(seg, &seg.basis(tau));
    for pair in samples.windows(2) {
        let (lo, hi) = (&pair[0], &pair[1]);
        let width = hi.tau - lo.tau;
        let mut found: Option<(f64, f64)> = None;
        for side in [1.0, -1.0] {
            let (g_lo, g_hi) = (margin(side, lo), margin(side, hi));
            if g_lo >= 0.0 {
                // Already on the lifted side at the start (a grazing landing): not a rise.
                continue;
            }
            let (r_lo, r_hi) = (rate(side, lo), rate(side, hi));
            let crossing_end = if g_hi >= 0.0 {
                Some(hi.tau)
            } else if r_lo > 0.0
                && r_hi < 0.0
                && (g_lo + 2.0 * r_lo * width >= 0.0 || g_hi - 2.0 * r_hi * width >= 0.0)
            {
                let top = bisect(lo.tau, hi.tau, 60, |tau| rate(side, &fresh(tau)) > 0.0).0;
                (margin(side, &fresh(top)) >= 0.0).then_some(top)
            } else {
                None
            };
            if let Some(end) = crossing_end {
                let tau = bisect(lo.tau, end, 200, |tau| margin(side, &fresh(tau)) < 0.0).1;
                if found.is_none_or(|(t0, _)| tau < t0) {
                    found = Some((tau, side));
                }
            }
        }
        if found.is_some() {
            return found;
        }
    }
    None
}

/// Peaks over a contact segment from its samples, where X = u (θ = 0): |u| at the samples
/// and at interior zeros of u̇, and the absolute acceleration ü + a_g refined like
/// [`super::refined_max`] does on an integrator step.
fn observe_segment(
    column: &Column,
    peaks: &mut Peaks,
    seg: &Segment,
    samples: &[Sample; 5],
    ground: &impl Fn(f64) -> f64,
) {
    let mut deformation = samples.iter().fold(0.0f64, |m, s| m.max(s.u.abs()));
    for pair in samples.windows(2) {
        if pair[0].v * pair[1].v < 0.0 {
            // |u| is flat at its extremum: a bracket of 2⁻³⁰ of the sample spacing leaves
            // a relative error ~ (ω δτ)² far below roundoff.
            let rising = pair[0].v > 0.0;
            let (a, b) = bisect(pair[0].tau, pair[1].tau, 30, |tau| {
                (seg.state(tau).1 > 0.0) == rising
            });
            deformation = deformation.max(seg.state(0.5 * (a + b)).0.abs());
        }
    }
    peaks.deformation = peaks.deformation.max(deformation);
    peaks.drift = peaks.drift.max(deformation / column.h);
    let accel_g = |tau: f64| {
        let (u, v) = seg.state(tau);
        (seg.accel(tau, u, v) + ground(tau)).abs() / column.g
    };
    let sampled = samples.map(|s| (s.tau, (s.a + ground(s.tau)).abs() / column.g));
    let floor = peaks.abs_acceleration_g;
    let peak = refined_max_of_samples(accel_g, &sampled, floor);
    peaks.abs_acceleration_g = floor.max(peak);
}

/// The closed-form interval from t: up to the next sample of the record (a_g linear on it),
/// t_stop or t + `longest`, with a_g at its ends taken from inside it (a record that starts
/// or ends on a nonzero sample jumps there; a_g = 0 outside it).
fn record_interval(record: &RecordMotion, t: f64, t_stop: f64, longest: f64) -> (f64, f64, f64) {
    let s = &*record.series;
    let cap = t_stop.min(t + longest);
    if t < s.t0() {
        return (cap.min(s.t0()), 0.0, 0.0);
    }
    if t >= s.end() {
        return (cap, 0.0, 0.0);
    }
    // The first sample strictly after t, computed as the integrator's breakpoints are.
    let time = |k: usize| s.t0() + k as f64 * s.dt();
    let mut k = ((t - s.t0()) / s.dt()).floor() as usize + 1;
    if time(k) <= t + 1e-9 * s.dt() {
        k += 1;
    }
    let t1 = cap.min(time(k.min(s.npts() - 1)));
    (t1, record.accel(t), record.accel(t1))
}

/// Bisection of [a, b] where `left(a)` holds and `left(b)` does not, for at most `iterations`
/// halvings or down to adjacent floating-point numbers: the final bracket (a, b).
fn bisect(mut a: f64, mut b: f64, iterations: usize, left: impl Fn(f64) -> bool) -> (f64, f64) {
    for _ in 0..iterations {
        let mid = 0.5 * (a + b);
        if mid <= a || mid >= b {
            break;
        }
        if left(mid) { a = mid } else { b = mid }
    }
    (a, b)
}
