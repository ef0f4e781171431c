//! Recording a scene's time history while it runs: at the solver's own points, or resampled
//! from the dense output onto a time grid, with the exact instants of events kept as extra rows
//! (one before and one after each jump) so peaks, kinks and jumps are drawn where they are.

use super::History;
use crate::excitation::Motion;
use crate::model::{EndReason, SimModel};
use crate::solver::Dense;

/// Rows per history of the automatic grid over the scene's duration (a 15 s scene: 2 ms).
const AUTO_ROWS: f64 = 4000.0;
/// Rows per pulse of the automatic grid at least (a one-sine pulse drawn by 200 points).
const AUTO_ROWS_PER_PULSE: f64 = 200.0;
/// The most rows a grid may ask for: about 2 GB of history in memory would be a typo.
pub const MAX_GRID_ROWS: f64 = 10_000_000.0;

/// Where a history takes its rows.
#[derive(Clone, Debug, PartialEq)]
pub enum Sampling {
    /// At every accepted step, closed-form interval and idle end: the solver's own points,
    /// unevenly spaced (for checks of the solver itself).
    Steps,
    /// At t = k·dt (k = 0, 1, …) from the dense output, plus the instants of events.
    Uniform(f64),
    /// At these increasing times from the dense output, plus the instants of events.
    At(Vec<f64>),
    /// Uniform, with dt from the duration and the excitation ([`auto_step`]).
    Auto,
}

/// The step of [`Sampling::Auto`]: at least 4000 rows over the duration and 200 over a pulse,
/// rounded down to 1, 2 or 5 × 10ᵏ s so the CSV's times read cleanly.
pub fn auto_step(duration: f64, motion: &Motion) -> f64 {
    let mut dt = duration / AUTO_ROWS;
    if let crate::excitation::Horizontal::Pulse(p) = motion.ground() {
        dt = dt.min(p.end() / AUTO_ROWS_PER_PULSE);
    }
    nice_floor(dt)
}

/// The largest 1, 2 or 5 × 10ᵏ not above x (x > 0).
fn nice_floor(x: f64) -> f64 {
    let decade = 10f64.powf(x.log10().floor());
    let mantissa = [5.0, 2.0, 1.0]
        .into_iter()
        .find(|m| m * decade <= x * (1.0 + 1e-12))
        .unwrap_or(1.0);
    mantissa * decade
}

/// The sample times of a grid, consumed in order.
struct Grid {
    times: Times,
    next: usize,
    /// Times within this of a boundary count as on it (k·dt misses 15.0 by an ulp).
    slack: f64,
}

enum Times {
    Uniform(f64),
    List(Vec<f64>),
}

impl Grid {
    fn peek(&self) -> Option<f64> {
        match &self.times {
            Times::Uniform(dt) => Some(self.next as f64 * dt),
            Times::List(v) => v.get(self.next).copied(),
        }
    }
}

/// Collects a [`History`] from the event loop's calls.
pub(super) struct Recorder {
    history: History,
    /// None: one row per solver point ([`Sampling::Steps`]).
    grid: Option<Grid>,
    /// Rows kept at most, and whether a row was refused for it.
    max_rows: usize,
    full: bool,
}

impl Recorder {
    pub fn new(sampling: &Sampling, duration: f64, motion: &Motion) -> Recorder {
        let uniform = |dt: f64| Grid {
            times: Times::Uniform(dt),
            next: 0,
            slack: 1e-9 * dt,
        };
        let grid = match sampling {
            Sampling::Steps => None,
            Sampling::Uniform(dt) => Some(uniform(*dt)),
            Sampling::Auto => Some(uniform(auto_step(duration, motion))),
            Sampling::At(times) => Some(Grid {
                times: Times::List(times.clone()),
                next: 0,
                slack: 0.0,
            }),
        };
        Recorder {
            history: History::default(),
            grid,
            max_rows: usize::MAX,
            full: false,
        }
    }

    /// Keep at most `rows` rows; past them the recorder is full ([`Recorder::within_cap`]).
    pub fn with_max_rows(mut self, rows: usize) -> Self {
        self.max_rows = rows;
        self
    }

    /// An error once a row was refused for the cap: the run stops there, memory bounded.
    pub fn within_cap(&self, t: f64) -> Result<(), super::SimError> {
        if self.full {
            Err(super::SimError::HistoryCap(self.max_rows, t))
        } else {
            Ok(())
        }
    }

    pub fn finish(self) -> History {
        self.history
    }

    fn push<const N: usize, M: SimModel<N>>(&mut self, model: &M, t: f64, y: &[f64; N]) {
        if self.history.rows.len() >= self.max_rows {
            self.full = true;
            return;
        }
        self.history.rows.push(model.history_row(t, y));
    }

    fn last_time(&self) -> f64 {
        self.history.rows.last().map_or(f64::NEG_INFINITY, |r| r[0])
    }

    /// The first row, at the start of the run.
    pub fn start<const N: usize, M: SimModel<N>>(&mut self, model: &M, t: f64, y: &[f64; N]) {
        self.history.columns = model.history_columns();
        self.exact(model, t, y);
    }

    /// A row where the state is known exactly (either side of an event's jump, the end of an
    /// idle period): kept whatever the sampling; grid times up to t are covered by it.
    pub fn exact<const N: usize, M: SimModel<N>>(&mut self, model: &M, t: f64, y: &[f64; N]) {
        self.push(model, t, y);
        if let Some(grid) = &mut self.grid {
            while grid.peek().is_some_and(|g| g <= t + grid.slack) {
                grid.next += 1;
            }
        }
    }

    pub fn event(&mut self, t: f64, name: &'static str) {
        self.history.events.push((t, name));
    }

    /// An accepted integrator step ending at (t1, y1), with its dense output when a step was
    /// taken. A step that ends at an event leaves its end to the event's rows.
    pub fn step<const N: usize, M: SimModel<N>>(
        &mut self,
        model: &M,
        dense: Option<&Dense<N>>,
        t1: f64,
        y1: &[f64; N],
        at_event: bool,
    ) {
        let Some(grid) = &mut self.grid else {
            if !at_event {
                self.push(model, t1, y1);
            }
            return;
        };
        let Some(dense) = dense else { return };
        let room = self.max_rows.saturating_sub(self.history.rows.len());
        let mut rows = Vec::new();
        while let Some(g) = grid.peek() {
            if rows.len() >= room {
                self.full = true;
                break;
            }
            let inside = if at_event {
                g < t1 - grid.slack
            } else {
                g <= t1 + grid.slack
            };
            if !inside {
                break;
            }
            let t = g.min(t1);
            rows.push(model.history_row(t, &dense.state(t)));
            grid.next += 1;
        }
        self.history.rows.extend(rows);
    }

    /// The next time a closed-form interval should end at, to put a row there (None: any).
    pub fn next_stop(&self) -> Option<f64> {
        self.grid.as_ref().and_then(Grid::peek)
    }

    /// The end (t, y) of a closed-form interval: a row if it is a sample time.
    pub fn interval_end<const N: usize, M: SimModel<N>>(
        &mut self,
        model: &M,
        t: f64,
        y: &[f64; N],
    ) {
        match &self.grid {
            None => self.push(model, t, y),
            Some(grid) if grid.peek().is_some_and(|g| g <= t + grid.slack) => {
                self.exact(model, t, y)
            }
            Some(_) => {}
        }
    }

    /// Rows at the sample times before `until` while the state stays y (an idle period: the
    /// block rides the ground; the ground acceleration column still moves).
    pub fn hold<const N: usize, M: SimModel<N>>(&mut self, model: &M, until: f64, y: &[f64; N]) {
        let Some(grid) = &mut self.grid else { return };
        let room = self.max_rows.saturating_sub(self.history.rows.len());
        let mut rows = Vec::new();
        while let Some(g) = grid.peek().filter(|g| *g < until - grid.slack) {
            if rows.len() >= room {
                self.full = true;
                break;
            }
            rows.push(model.history_row(g, y));
            grid.next += 1;
        }
        self.history.rows.extend(rows);
    }

    /// The run ended at (t, y) for `reason`: on a grid, a row at the end instant, and a run
    /// that came to rest before `duration` stays at rest until then.
    pub fn end<const N: usize, M: SimModel<N>>(
        &mut self,
        model: &M,
        t: f64,
        y: &[f64; N],
        reason: EndReason,
        duration: f64,
    ) {
        if self.grid.is_none() {
            return;
        }
        if self.last_time() < t {
            self.exact(model, t, y);
        }
        if reason == EndReason::Rest && t < duration {
            self.hold(model, duration, y);
            self.exact(model, duration, y);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::nice_floor;

    #[test]
    fn nice_steps_round_down_to_one_two_five() {
        for (x, want) in [
            (15.0 / 4000.0, 0.002),
            (60.0 / 4000.0, 0.01),
            (0.005, 0.005),
            (0.0049, 0.002),
            (0.001, 0.001),
            (0.0999, 0.05),
            (3.0, 2.0),
        ] {
            assert!(
                (nice_floor(x) - want).abs() < 1e-15 * want,
                "{x}: {}",
                nice_floor(x)
            );
        }
    }
}
