//! Ground motions: what the structure's base does. A [`Motion`] is compiled once per scene (or
//! shared across scenes) and evaluated in the right-hand side, so evaluation must be cheap and
//! allocation free.
//!
//! - [`pulse`]: analytic pulses (sine, cosine, Ricker, antisymmetric Ricker,
//!   Mavroeidis–Papageorgiou), all scaled by peak acceleration and ω.
//! - [`record`]: sampled records, linear between samples, O(1) lookup, shared via `Arc`.
//! - [`reader`]: PEER AT2, one- and two-column files.
//! - [`ims`]: intensity measures of a record (PGA … Sa, durations, pulse classification).
//! - [`library`]: record names → parsed records (directory, embedded copies, stand-ins), cached.

pub mod gravity;
pub mod ims;
pub mod library;
pub mod pulse;
pub mod reader;
pub mod record;
pub mod suite;

pub use gravity::{Gravity, Vertical};
pub use library::{Library, Record, RecordError, RecordMeta, Source, StandIn};
pub use pulse::{Pulse, PulseShape};
pub use reader::ParseError;
pub use record::{KinkPolicy, RecordMotion, Series};

use crate::solver::search::brent_max;

/// Standard gravity used throughout rocklab (docs/MODEL.md: g = 9.81 m/s²): the constant part of
/// [`Motion::gravity`], and the unit of accelerations given "in g".
pub const G: f64 = 9.81;

/// The ground motion a scene's structure stands on: its horizontal acceleration a_g(t) and the
/// gravity it feels, g + ü_v(t) ([`Gravity`], the one accessor of the vertical motion).
#[derive(Clone, Debug)]
pub struct Motion {
    horizontal: Horizontal,
    gravity: Gravity,
}

impl Motion {
    /// A horizontal motion under standard, constant gravity.
    pub fn horizontal(horizontal: Horizontal) -> Self {
        Motion {
            horizontal,
            gravity: Gravity::STANDARD,
        }
    }

    /// A horizontal motion with the gravity (vertical motion) it comes with.
    pub fn with_gravity(horizontal: Horizontal, gravity: Gravity) -> Self {
        Motion {
            horizontal,
            gravity,
        }
    }

    pub fn pulse(pulse: Pulse) -> Self {
        Motion::horizontal(Horizontal::Pulse(pulse))
    }

    pub fn record(record: RecordMotion) -> Self {
        Motion::horizontal(Horizontal::Record(record))
    }

    /// The horizontal ground acceleration.
    pub fn ground(&self) -> &Horizontal {
        &self.horizontal
    }

    /// The gravity the structure feels under this ground motion: g + ü_v(t).
    #[inline(always)]
    pub fn gravity(&self) -> &Gravity {
        &self.gravity
    }

    /// Horizontal ground acceleration (m/s²) at time t.
    #[inline(always)]
    pub fn accel(&self, t: f64) -> f64 {
        self.horizontal.accel(t)
    }

    /// Time after which the ground is at rest: a_g ≡ 0 and ü_v constant.
    pub fn end(&self) -> f64 {
        self.gravity.end().max(self.horizontal.end())
    }

    /// The next time strictly after `t` where a_g or ü_v is not smooth.
    pub fn next_breakpoint(&self, t: f64) -> Option<f64> {
        earliest(
            self.horizontal.next_breakpoint(t),
            self.gravity.next_kink(t, Horizontal::next_breakpoint),
        )
    }

    /// [`Horizontal::next_kink`] of both components.
    pub fn next_kink(&self, t: f64) -> Option<f64> {
        earliest(
            self.horizontal.next_kink(t),
            self.gravity.next_kink(t, Horizontal::next_kink),
        )
    }

    /// Whether a_g or ü_v jumps at breakpoint `t`.
    pub fn jumps_at(&self, t: f64) -> bool {
        self.horizontal.jumps_at(t) || self.gravity.jumps_at(t)
    }

    /// First time ≥ t0 at which |a_g| exceeds `level`, if any.
    pub fn first_exceedance(&self, t0: f64, level: f64) -> Option<f64> {
        self.horizontal.first_exceedance(t0, level)
    }

    /// [`Horizontal::accel_bound`].
    pub fn accel_bound(&self, t0: f64, t1: f64) -> f64 {
        self.horizontal.accel_bound(t0, t1)
    }

    /// Peak |a_g| over [t0, t1].
    pub fn peak_abs(&self, t0: f64, t1: f64) -> f64 {
        self.horizontal.peak_abs(t0, t1)
    }
}

fn earliest(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, None) => a,
        (None, b) => b,
    }
}

/// A ground acceleration history a_g(t) in m/s², zero after [`Horizontal::end`] (the
/// horizontal motion, or a vertical one given by its own pulse or record).
#[derive(Clone, Debug)]
pub enum Horizontal {
    Pulse(Pulse),
    /// A sampled record, linear between samples.
    Record(RecordMotion),
}

impl Horizontal {
    /// A sampling step fine enough to see every lobe of a pulse (None for a record, whose
    /// samples are its own kinks).
    pub fn sampling_step(&self) -> Option<f64> {
        match self {
            Horizontal::Pulse(p) => Some(p.period() / PULSE_SAMPLES_PER_PERIOD),
            Horizontal::Record(_) => None,
        }
    }

    /// Ground acceleration (m/s²) at time t.
    #[inline]
    pub fn accel(&self, t: f64) -> f64 {
        match self {
            Horizontal::Pulse(p) => p.accel(t),
            Horizontal::Record(r) => r.accel(t),
        }
    }

    /// Time after which the ground is at rest (a_g ≡ 0).
    pub fn end(&self) -> f64 {
        match self {
            Horizontal::Pulse(p) => p.end(),
            Horizontal::Record(r) => r.end(),
        }
    }

    /// The next time strictly after `t` where a_g is not smooth (a kink or a jump), so the
    /// integrator can stop there instead of stepping across it.
    pub fn next_breakpoint(&self, t: f64) -> Option<f64> {
        match self {
            Horizontal::Pulse(p) => p.next_breakpoint(t),
            Horizontal::Record(r) => r.next_breakpoint(t),
        }
    }

    /// Like [`Horizontal::next_breakpoint`], but a record stops at every sample whatever its kink
    /// policy: for a phase whose event functions read a_g itself, not only through the state.
    pub fn next_kink(&self, t: f64) -> Option<f64> {
        match self {
            Horizontal::Pulse(p) => p.next_breakpoint(t),
            Horizontal::Record(r) => r.next_kink(t),
        }
    }

    /// Whether a_g jumps (not just kinks) at breakpoint `t`.
    pub fn jumps_at(&self, t: f64) -> bool {
        match self {
            Horizontal::Pulse(p) => p.jumps_at(t),
            Horizontal::Record(r) => r.jumps_at(t),
        }
    }

    /// First time ≥ t0 at which |a_g| exceeds `level`, if any.
    pub fn first_exceedance(&self, t0: f64, level: f64) -> Option<f64> {
        match self {
            Horizontal::Pulse(p) => p
                .first_exceedance_closed(t0, level)
                .unwrap_or_else(|| scan_exceedance(|t| p.accel(t), t0, p.end(), level, p.period())),
            Horizontal::Record(r) => r.first_exceedance(t0, level),
        }
    }

    /// An upper bound of |a_g| over [t0, t1], cheaper than [`Horizontal::peak_abs`] for a pulse
    /// (a record's peak is exact and cheap: the samples in the interval).
    pub fn accel_bound(&self, t0: f64, t1: f64) -> f64 {
        match self {
            Horizontal::Pulse(p) => p.accel_bound(t0, t1),
            Horizontal::Record(r) => r.peak_abs(t0, t1),
        }
    }

    /// Peak |a_g| over [t0, t1].
    pub fn peak_abs(&self, t0: f64, t1: f64) -> f64 {
        match self {
            Horizontal::Pulse(p) => p
                .peak_abs_closed(t0, t1)
                .unwrap_or_else(|| scan_peak(|t| p.accel(t), t0, t1.min(p.end()), p.period())),
            Horizontal::Record(r) => r.peak_abs(t0, t1),
        }
    }
}

/// Samples per period (2π/ω) in the scans of an analytic pulse's |a_g|. Every shape varies on
/// the scale of 1/ω (the narrowest lobe, the Ricker wavelet's central one, spans a third of a
/// period), so at this spacing |a_g| has at most one maximum between neighbouring samples, and
/// each of its maxima lies next to a sample that beats its neighbours, where a Brent search
/// from that sample and its neighbours finds it (`brent_max`). The scans used to sample at
/// period/2000 under the same assumption: 30× the sine evaluations for the same answer.
const PULSE_SAMPLES_PER_PERIOD: f64 = 64.0;

/// What a walk along a pulse's samples meets, in time order ([`walk_pulse`]).
enum Met {
    /// A new sample (t, |a|) and the one before it.
    Sample { before: (f64, f64), at: (f64, f64) },
    /// A maximum (t, |a|) refined around a sample at least its neighbours, and the sample
    /// before that one: |a| rises monotonically from `before` to `at`.
    Maximum { before: (f64, f64), at: (f64, f64) },
}

/// Walk |a| on [t0, t1] at [`PULSE_SAMPLES_PER_PERIOD`], meeting each sample and each refined
/// maximum in time order, until `visit` returns true.
fn walk_pulse(
    a: impl Fn(f64) -> f64,
    t0: f64,
    t1: f64,
    period: f64,
    mut visit: impl FnMut(Met) -> bool,
) {
    let n = ((t1 - t0) / period * PULSE_SAMPLES_PER_PERIOD)
        .ceil()
        .max(1.0) as usize;
    let at = |k: usize| {
        if k == n {
            t1
        } else {
            t0 + (t1 - t0) * k as f64 / n as f64
        }
    };
    let abs = |t: f64| a(t).abs();
    let mut prev = (t0, abs(t0));
    let mut here = prev;
    for k in 0..=n {
        let next = if k < n {
            let t = at(k + 1);
            (t, abs(t))
        } else {
            here
        };
        if here.1 >= prev.1 && here.1 >= next.1 {
            let (t, v) = brent_max(abs, prev, here, next);
            let top = if here.1 >= v { here } else { (t, v) };
            let before = if top.0 < here.0 { prev } else { here };
            if visit(Met::Maximum { before, at: top }) {
                return;
            }
        }
        if k < n
            && visit(Met::Sample {
                before: here,
                at: next,
            })
        {
            return;
        }
        (prev, here) = (here, next);
    }
}

/// First crossing of |a(t)| > level on [t0, end], for smooth a: the first sample or refined
/// maximum above the level ([`walk_pulse`]), then bisection from the point before it.
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
    let mut crossing = None;
    walk_pulse(&a, t0, end, period, |met| {
        let (Met::Sample { before, at } | Met::Maximum { before, at }) = met;
        if at.1 <= level {
            return false;
        }
        // Everything met so far is at most the level: |a| crosses it once in (before, at).
        let (mut l, mut h) = (before.0, at.0);
        for _ in 0..80 {
            let m = 0.5 * (l + h);
            if a(m).abs() > level { h = m } else { l = m }
        }
        crossing = Some(h);
        true
    });
    crossing
}

/// Peak |a| over [t0, t1]: the largest of its maxima ([`walk_pulse`]).
fn scan_peak(a: impl Fn(f64) -> f64, t0: f64, t1: f64, period: f64) -> f64 {
    if t1 <= t0 {
        return 0.0;
    }
    let mut peak = 0.0f64;
    walk_pulse(a, t0, t1, period, |met| {
        if let Met::Maximum { at, .. } = met {
            peak = peak.max(at.1);
        }
        false
    });
    peak
}

#[cfg(test)]
mod tests {
    use super::*;
    use pulse::PulseShape;

    /// A start a few ulps into an arc, where |a_g| still rounds to the level or below, is
    /// answered in that arc (it used to jump to the next one, or to never).
    #[test]
    fn a_start_just_inside_an_arc_stays_in_it() {
        let p = Pulse::new(PulseShape::Sine, 1.0, 1.0);
        let (level, t0) = (0.675, 0.7409647022030201);
        let closed = p.first_exceedance_closed(t0, level).flatten();
        let scanned = scan_exceedance(|t| p.accel(t), t0, p.end(), level, p.period());
        assert!(
            closed.is_some_and(|c| (c - t0).abs() < 1e-12),
            "{closed:?} vs {scanned:?}"
        );
        assert!(scanned.is_some_and(|s| (s - t0).abs() < 1e-12));
    }

    /// The sine and cosine pulses' closed forms agree with the scans every other shape uses,
    /// over start times, levels and intervals that cut arcs and crests anywhere.
    #[test]
    fn closed_forms_match_the_scans_for_sine_and_cosine() {
        for shape in [PulseShape::Sine, PulseShape::Cosine] {
            for amplitude in [2.7, -1.3] {
                let p = Pulse::new(shape, amplitude, 3.1);
                let (end, period) = (p.end(), p.period());
                for i in 0..=60 {
                    let t0 = end * (i as f64 / 50.0) - 0.1 * end;
                    for j in 0..=20 {
                        let level = amplitude.abs() * j as f64 / 19.5;
                        let Some(closed) = p.first_exceedance_closed(t0, level) else {
                            continue; // the scan decides (rounding at an arc's start)
                        };
                        let scanned =
                            scan_exceedance(|t| p.accel(t), t0.max(0.0), end, level, period);
                        match (closed, scanned) {
                            (Some(c), Some(s)) => {
                                assert!(
                                    (c - s).abs() < 1e-12 * end,
                                    "{shape:?} {t0} {level}: {c} vs {s}"
                                );
                                assert!(p.accel(c).abs() > level && c >= t0);
                            }
                            (None, None) => {}
                            other => panic!("{shape:?} {t0} {level}: {other:?}"),
                        }
                        let t1 = t0 + end * j as f64 / 37.0;
                        let closed = p.peak_abs_closed(t0, t1).unwrap();
                        let scanned = scan_peak(|t| p.accel(t), t0.max(0.0), t1.min(end), period);
                        assert!(
                            (closed - scanned).abs() < 1e-12 * amplitude.abs(),
                            "{shape:?} [{t0}, {t1}]: {closed} vs {scanned}"
                        );
                    }
                }
            }
        }
    }
}
