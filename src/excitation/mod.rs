//! Ground motions: what the structure's base does. A [`Motion`] is compiled once per scene (or
//! shared across scenes) and evaluated in the right-hand side, so evaluation must be cheap and
//! allocation free.
//!
//! - [`pulse`]: analytic pulses (sine, cosine, Ricker, antisymmetric Ricker,
//!   Mavroeidis–Papageorgiou), all scaled by peak acceleration and ω.
//! - [`record`]: sampled records, linear between samples, O(1) lookup, shared via `Arc`.
//! - [`reader`]: PEER AT2, one- and two-column files.
//! - [`library`]: record names → parsed records (directory, embedded copies, stand-ins), cached.

pub mod library;
pub mod pulse;
pub mod reader;
pub mod record;

pub use library::{Library, Record, RecordError, RecordMeta, Source, StandIn};
pub use pulse::{Pulse, PulseShape};
pub use reader::ParseError;
pub use record::{KinkPolicy, RecordMotion, Series};

/// Standard gravity used throughout rocklab (MODEL.md: g = 9.81 m/s²).
pub const G: f64 = 9.81;

/// A ground acceleration history a_g(t) in m/s², zero after [`Motion::end`].
#[derive(Clone, Debug)]
pub enum Motion {
    Pulse(Pulse),
    /// A sampled record, linear between samples.
    Record(RecordMotion),
}

impl Motion {
    /// Ground acceleration (m/s²) at time t.
    #[inline]
    pub fn accel(&self, t: f64) -> f64 {
        match self {
            Motion::Pulse(p) => p.accel(t),
            Motion::Record(r) => r.accel(t),
        }
    }

    /// Time after which the ground is at rest (a_g ≡ 0).
    pub fn end(&self) -> f64 {
        match self {
            Motion::Pulse(p) => p.end(),
            Motion::Record(r) => r.end(),
        }
    }

    /// The next time strictly after `t` where a_g is not smooth (a kink or a jump), so the
    /// integrator can stop there instead of stepping across it.
    pub fn next_breakpoint(&self, t: f64) -> Option<f64> {
        match self {
            Motion::Pulse(p) => p.next_breakpoint(t),
            Motion::Record(r) => r.next_breakpoint(t),
        }
    }

    /// Like [`Motion::next_breakpoint`], but a record stops at every sample whatever its kink
    /// policy: for a phase whose event functions read a_g itself, not only through the state.
    pub fn next_kink(&self, t: f64) -> Option<f64> {
        match self {
            Motion::Pulse(p) => p.next_breakpoint(t),
            Motion::Record(r) => r.next_kink(t),
        }
    }

    /// Whether a_g jumps (not just kinks) at breakpoint `t`.
    pub fn jumps_at(&self, t: f64) -> bool {
        match self {
            Motion::Pulse(p) => p.jumps_at(t),
            Motion::Record(r) => r.jumps_at(t),
        }
    }

    /// First time ≥ t0 at which |a_g| exceeds `level`, if any.
    pub fn first_exceedance(&self, t0: f64, level: f64) -> Option<f64> {
        match self {
            Motion::Pulse(p) => scan_exceedance(|t| p.accel(t), t0, p.end(), level, p.period()),
            Motion::Record(r) => r.first_exceedance(t0, level),
        }
    }

    /// Peak |a_g| over [t0, t1].
    pub fn peak_abs(&self, t0: f64, t1: f64) -> f64 {
        match self {
            Motion::Pulse(p) => scan_peak(|t| p.accel(t), t0, t1.min(p.end()), p.period()),
            Motion::Record(r) => r.peak_abs(t0, t1),
        }
    }
}

/// First crossing of |a(t)| > level on [t0, end], for smooth a: sample finely, then bisect.
fn scan_exceedance(
    a: impl Fn(f64) -> f64,
    t0: f64,
    end: f64,
    level: f64,
    period: f64,
) -> Option<f64> {
    if t0 >= end {
        return None;
    }
    if a(t0).abs() > level {
        return Some(t0);
    }
    let dt = period / 2000.0;
    let mut lo = t0;
    while lo < end {
        let hi = (lo + dt).min(end);
        if a(hi).abs() > level {
            let (mut l, mut h) = (lo, hi);
            for _ in 0..80 {
                let m = 0.5 * (l + h);
                if a(m).abs() > level { h = m } else { l = m }
            }
            return Some(h);
        }
        lo = hi;
    }
    None
}

fn scan_peak(a: impl Fn(f64) -> f64, t0: f64, t1: f64, period: f64) -> f64 {
    if t1 <= t0 {
        return 0.0;
    }
    let n = ((t1 - t0) / period * 2000.0).ceil().max(1.0) as usize;
    let at = |k: usize| t0 + (t1 - t0) * k as f64 / n as f64;
    let best = (0..=n)
        .max_by(|&i, &j| a(at(i)).abs().total_cmp(&a(at(j)).abs()))
        .unwrap_or(0);
    // Golden-section refinement of the smooth maximum around the best sample.
    let (mut lo, mut hi) = (at(best.saturating_sub(1)), at((best + 1).min(n)));
    let r = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..80 {
        let (c, d) = (hi - r * (hi - lo), lo + r * (hi - lo));
        if a(c).abs() > a(d).abs() {
            hi = d
        } else {
            lo = c
        }
    }
    a(0.5 * (lo + hi)).abs().max(a(at(best)).abs())
}
