//! The gravity a structure feels: g + ü_v(t), the one place a vertical ground motion enters
//! the models (docs/MODEL.md "Vertical ground motion"). Positive ü_v is up: the ground
//! accelerating upward presses the structure down, as if gravity were g + ü_v.

use super::{G, Horizontal};

/// The gravity a structure feels, as its model reads it ([`super::Motion::gravity`], the one
/// accessor: `model/` and `sim/` never name [`G`]). [`Gravity::g`] is the constant part (the
/// unit of accelerations in g, the static scales a model derives once); [`Gravity::at`] is
/// g + ü_v(t). Without a vertical motion `at` is one predictable branch and returns g itself,
/// so the results are those of a constant g bit for bit.
#[derive(Clone, Debug)]
pub struct Gravity {
    g: f64,
    vertical: Option<Vertical>,
    /// (t, g + ü_v(t)) where g_eff is lowest ([`Gravity::lowest`]), found once.
    lowest: (f64, f64),
}

/// A vertical ground acceleration ü_v(t) (m/s², positive up), compiled for a scene.
#[derive(Clone, Debug)]
pub enum Vertical {
    /// ü_v = c (m/s²) at every time.
    Constant(f64),
    /// ü_v(t) = r · a_g(t) of the horizontal motion (a copy of it, shared data).
    Ratio(f64, Horizontal),
    /// ü_v(t) from its own pulse or record, zero after its end.
    Own(Horizontal),
}

impl Vertical {
    #[inline]
    fn accel(&self, t: f64) -> f64 {
        match self {
            Vertical::Constant(c) => *c,
            Vertical::Ratio(r, h) => r * h.accel(t),
            Vertical::Own(h) => h.accel(t),
        }
    }

    /// Whether ü_v ≡ 0 (a zero constant or ratio): no vertical motion at all.
    fn is_zero(&self) -> bool {
        match self {
            Vertical::Constant(c) | Vertical::Ratio(c, _) => *c == 0.0,
            Vertical::Own(_) => false,
        }
    }
}

impl Gravity {
    /// Standard gravity, constant in time.
    pub const STANDARD: Gravity = Gravity {
        g: G,
        vertical: None,
        lowest: (0.0, G),
    };

    /// Standard gravity plus a vertical ground motion; a vertical motion that is identically
    /// zero (constant(0), ratio(0)) is no vertical motion, so its results are bit-identical
    /// to a scene without one.
    pub fn with_vertical(vertical: Vertical) -> Self {
        let (t, v) = match &vertical {
            Vertical::Constant(c) => (0.0, *c),
            Vertical::Ratio(r, h) => lowest_of(h, *r),
            Vertical::Own(h) => lowest_of(h, 1.0),
        };
        Gravity {
            g: G,
            vertical: (!vertical.is_zero()).then_some(vertical),
            lowest: (t, G + v),
        }
    }

    /// The constant part g (m/s²).
    #[inline(always)]
    pub fn g(&self) -> f64 {
        self.g
    }

    /// Gravity at time t (m/s²): g + ü_v(t).
    #[inline(always)]
    pub fn at(&self, t: f64) -> f64 {
        match &self.vertical {
            None => self.g,
            Some(v) => self.g + v.accel(t),
        }
    }

    /// Whether the ground moves vertically (or g is shifted by a constant).
    pub fn has_vertical(&self) -> bool {
        self.vertical.is_some()
    }

    /// Whether g_eff is constant in time (no vertical motion, or a constant one).
    pub fn is_constant(&self) -> bool {
        matches!(self.vertical, None | Some(Vertical::Constant(_)))
    }

    /// Gravity once the ground has stopped (a constant vertical acceleration stays).
    pub fn at_rest(&self) -> f64 {
        match &self.vertical {
            Some(Vertical::Constant(c)) => self.g + c,
            _ => self.g,
        }
    }

    /// Time after which ü_v is constant (0 unless it has its own pulse or record).
    pub fn end(&self) -> f64 {
        match &self.vertical {
            Some(Vertical::Own(h)) => h.end(),
            _ => 0.0,
        }
    }

    /// The next kink of ü_v after t by `kink` (the horizontal's own breakpoints cover a ratio).
    pub fn next_kink(&self, t: f64, kink: fn(&Horizontal, f64) -> Option<f64>) -> Option<f64> {
        match &self.vertical {
            Some(Vertical::Own(h)) => kink(h, t),
            _ => None,
        }
    }

    /// Whether ü_v jumps at t.
    pub fn jumps_at(&self, t: f64) -> bool {
        match &self.vertical {
            Some(Vertical::Own(h)) => h.jumps_at(t),
            _ => false,
        }
    }

    /// A step fine enough to see every lobe of a pulse that moves g (None: constant, or
    /// records, whose samples are breakpoints).
    pub fn sampling_step(&self) -> Option<f64> {
        match &self.vertical {
            Some(Vertical::Ratio(_, h) | Vertical::Own(h)) => h.sampling_step(),
            _ => None,
        }
    }

    /// A horizontal acceleration level below which the ground cannot lift a block whose
    /// uplift needs |a_g| > g_eff(t) · `ratio` (ratio = tan α, or α). Exact for a constant
    /// g_eff (the uplift happens at its first exceedance, [`Gravity::is_constant`]);
    /// otherwise a lower bound: with ü_v = r a_g, |a_g| > (g − |r||a_g|) ratio needs
    /// |a_g| > g ratio / (1 + |r| ratio); with its own ü_v, g + min ü_v bounds g_eff.
    pub fn uplift_level(&self, ratio: f64) -> f64 {
        match &self.vertical {
            None => self.g * ratio,
            Some(Vertical::Constant(c)) => (self.g + c) * ratio,
            Some(Vertical::Ratio(r, _)) => self.g * ratio / (1.0 + r.abs() * ratio),
            Some(Vertical::Own(_)) => self.lowest().1.max(0.0) * ratio,
        }
    }

    /// The time and value of the lowest g + ü_v(t) (over the motion's samples; a pulse on a
    /// grid of [`LOWEST_SAMPLES_PER_PERIOD`]).
    pub fn lowest(&self) -> (f64, f64) {
        self.lowest
    }

    /// Refuse a vertical motion that takes g + ü_v below zero: the structure would leave
    /// the ground (free flight), which no model here describes.
    /// (The message is the caller's error: `error` depends on this module.)
    pub fn check_contact(&self) -> Result<(), String> {
        let (t, low) = self.lowest();
        if low >= 0.0 {
            return Ok(());
        }
        Err(format!(
            "vertical ground acceleration {:.4} g at t = {t:.4} s is below -1 g (g + ü_v = {low:.4} \
             m/s² < 0): the structure would leave the ground in free flight, which is not \
             modelled; lower the vertical motion (its ratio, amplitude or constant)",
            (low - self.g) / self.g,
        ))
    }
}

/// Grid of the scan for the lowest vertical acceleration of a pulse: a peak between two
/// samples is missed by at most ~(π/N)²/2 of its value (5e-6 here).
const LOWEST_SAMPLES_PER_PERIOD: f64 = 1024.0;

/// (t, min of r·a(t)) over the samples of a record or a fine grid on a pulse.
fn lowest_of(h: &Horizontal, r: f64) -> (f64, f64) {
    let mut best = (0.0, 0.0f64);
    let mut visit = |t: f64, a: f64| {
        if r * a < best.1 {
            best = (t, r * a);
        }
    };
    match h {
        Horizontal::Record(m) => {
            let (t0, dt) = (m.series.t0(), m.series.dt());
            for (k, a) in m.series.samples().iter().enumerate() {
                visit(t0 + k as f64 * dt, m.factor * a);
            }
        }
        Horizontal::Pulse(p) => {
            let n = (p.end() / p.period() * LOWEST_SAMPLES_PER_PERIOD).ceil() as usize;
            for k in 0..=n {
                let t = p.end() * k as f64 / n as f64;
                visit(t, p.accel(t));
            }
        }
    }
    best
}
