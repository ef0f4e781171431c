//! The rocking model as the solver's [`OdeSystem`] and the simulation driver's [`SimModel`].

use super::{Body, Ev, Phase, Rocking};
use crate::model::column::HistoryColumn;
use crate::model::device::DeviceRates;
use crate::model::rigid::below_peak;
use crate::model::{
    Action, ClosedFormEnd, Counters, EndReason, Energy, Peaks, SimModel, StepEnd, refine_sampled,
};
use crate::solver::{Dense, Direction, OdeSystem, store_pairs};

impl<const N: usize, B: Body> OdeSystem<N> for Rocking<'_, B> {
    /// Without device states and accumulators (a bare block, a rigidly coupled or sequential
    /// inerter, in a run that keeps no energy ledger) the right-hand side is the body's
    /// equations alone: no device call, no accumulator, the state zeroed at its constant
    /// length. The same numbers as the general path ([`Rocking::rhs_kin`]).
    #[inline]
    fn rhs(&self, t: f64, y: &[f64; N], dydt: &mut [f64; N]) {
        let m = &self.mode;
        if m.layout.device_dofs == 0 && !m.layout.ledger {
            // a_g first: it depends on t alone, and its sine then runs beside the
            // kinematics' instead of after it on the stage's critical path.
            let ag = m.motion.accel(t);
            let g_eff = m.motion.gravity().at(t);
            let k = self.body.kin(m, y);
            let fd = DeviceRates::STATELESS.force;
            // In registers, then stored whole (see `store_pairs`).
            let mut d = [0.0; N];
            self.body
                .derivatives(m, &k, ag, g_eff, y, fd, m.coupled_mass(), &mut d);
            store_pairs(dydt, d);
        } else {
            self.rhs_kin(t, y, &self.body.kin(m, y), dydt)
        }
    }

    fn event_count(&self) -> usize {
        self.n_events
    }

    /// Body and flywheel states; the energy accumulators after them are no event's input.
    fn event_inputs(&self) -> usize {
        self.mode.layout.physical_len()
    }

    fn event_direction(&self, index: usize) -> Direction {
        match self.events[index] {
            Ev::Impact => Direction::Falling,
            Ev::Overturn | Ev::Uplift(_) => Direction::Rising,
            Ev::Device(e) => e.direction(),
            Ev::Switch if self.mode.switch_engaged => Direction::Falling,
            Ev::Switch => Direction::Rising,
            Ev::Own(i) => self.body.own_event_direction(i),
        }
    }

    /// The kinematics (one sin/cos for the rigid block) are computed once per sample and
    /// shared by every event function that reads X or Ẋ.
    fn events(&self, t: f64, y: &[f64; N], g: &mut [f64]) {
        let kx = self.events_read_x.then(|| {
            let k = self.body.kin(&self.mode, y);
            (k, self.body.x_xdot_kin(&self.mode, &k, y))
        });
        for (i, gi) in g.iter_mut().enumerate() {
            *gi = self.event_value(self.events[i], t, y, kx.as_ref());
        }
    }

    /// While rocking, every function has its rate in closed form: the impact margin's is
    /// pivot·θ̇, the overturn margin's the body's, a clutch's from Ẋ, Ẍ and the flywheels'
    /// rates, and the others are constants of the phase. One call of the kinematics then
    /// gives the screen what two calls of [`OdeSystem::events`] gave by differencing. In
    /// contact (an uplift margin reads a_g(t)) and with the sequential law (its switch reads
    /// Ẍ) the integrator differences.
    fn events_with_rates(
        &self,
        t: f64,
        y: &[f64; N],
        dydt: &[f64; N],
        g: &mut [f64],
        rates: &mut [f64],
    ) -> bool {
        let m = &self.mode;
        let events = &self.events[..self.n_events];
        let closed_form = |ev: &Ev| match ev {
            Ev::Impact | Ev::Uplift(_) | Ev::Device(_) => true,
            Ev::Overturn => self.body.overturn_margin_rate(m, y, dydt).is_some(),
            Ev::Switch | Ev::Own(_) => false,
        };
        if !m.rocking() || !events.iter().all(closed_form) {
            return false;
        }
        // The kinematics only where a function reads X (a bare block's read θ alone).
        let kx = self.events_read_x.then(|| {
            let k = self.body.kin(m, y);
            let (x, xdot) = self.body.x_xdot_kin(m, &k, y);
            (k, (x, xdot), self.body.xddot(m, &k, y, dydt))
        });
        let kin_x = kx.map(|(k, v, _)| (k, v));
        let (states, states_dot) = (m.layout.device_states(y), m.layout.device_states(dydt));
        // Zipped, not indexed: one pass without bounds checks (this runs twice per step of a
        // record scene, which stops at every sample).
        for ((ev, gi), rate) in events.iter().zip(g.iter_mut()).zip(rates.iter_mut()) {
            *gi = self.event_value(*ev, t, y, kin_x.as_ref());
            *rate = match (ev, &kx) {
                (Ev::Impact, _) => m.pivot * dydt[B::THETA],
                (Ev::Overturn, _) => self.body.overturn_margin_rate(m, y, dydt).unwrap_or(0.0),
                (Ev::Device(e), Some((_, (x, xdot), xddot))) => {
                    m.dev
                        .event_rate(*e, (*x, *xdot, *xddot), states, states_dot)
                }
                _ => 0.0,
            };
        }
        true
    }

    /// While rocking: the impact margin (pivot·θ) and the device's own events (a mechanistic
    /// clutch's), the ones refined by the hundred (chattering impacts, clutch contacts and
    /// resets). (The impact margin reads θ alone.)
    fn event_rate_inputs(&self, index: usize) -> usize {
        match self.events[index] {
            _ if !self.mode.rocking() => 0,
            Ev::Impact => B::THETA + 1,
            Ev::Device(_) => self.mode.layout.physical_len(),
            _ => 0,
        }
    }

    fn event_with_rate(
        &self,
        index: usize,
        _t: f64,
        y: &[f64; N],
        dydt: &[f64; N],
    ) -> Option<(f64, f64)> {
        let m = &self.mode;
        match self.events[index] {
            _ if !m.rocking() => None,
            Ev::Impact => Some((m.pivot * y[B::THETA], m.pivot * dydt[B::THETA])),
            Ev::Device(e) => {
                let k = self.body.kin(m, y);
                let (x, xdot) = self.body.x_xdot_kin(m, &k, y);
                let xddot = self.body.xddot(m, &k, y, dydt);
                let (states, states_dot) =
                    (m.layout.device_states(y), m.layout.device_states(dydt));
                Some((
                    m.dev.event_value(e, x, xdot, states),
                    m.dev.event_rate(e, (x, xdot, xddot), states, states_dot),
                ))
            }
            _ => None,
        }
    }

    /// One function alone: an impact or overturn margin reads θ only, without the
    /// kinematics every function that reads X needs.
    fn event(&self, index: usize, t: f64, y: &[f64; N]) -> f64 {
        self.event_value(self.events[index], t, y, None)
    }

    fn max_step(&self) -> f64 {
        self.body.max_step(&self.mode)
    }

    fn sign_after_zero(&self, index: usize, _t: f64, y: &[f64; N]) -> f64 {
        match self.events[index] {
            // At uplift (θ = θ̇ = 0, sθ̈ > 0) the base moves onto its pivot's side. Knowing
            // this matters: after an impact the uplift margin can already be falling, so the
            // base lands again within the first step, a crossing an undetermined start misses.
            Ev::Impact if y[B::THETA_DOT] == 0.0 => 1.0,
            Ev::Impact => (self.mode.pivot * y[B::THETA_DOT]).signum(),
            // From rest (Ẋ = 0) |Ẋ| grows.
            Ev::Switch if self.x_xdot(y).1 == 0.0 => 1.0,
            _ => 0.0,
        }
    }
}

impl<const N: usize, B: Body> SimModel<N> for Rocking<'_, B> {
    fn state_len(&self) -> usize {
        self.mode.layout.state_len()
    }

    fn start(&mut self, y: &mut [f64; N]) -> Action {
        let action = if self.initial_rotation != 0.0 {
            self.mode.phase = Phase::Rocking;
            self.mode.pivot = self.initial_rotation.signum();
            y[B::THETA] = self.initial_rotation;
            // Released from rest with the device relaxed: flywheels sit where X is.
            let (x, _) = self.x_xdot(y);
            for i in 0..self.mode.layout.device_dofs {
                y[self.mode.layout.device_dof(i)] = x;
            }
            Action::Continue
        } else {
            self.land(0.0, y)
        };
        if B::MOVES_IN_CONTACT {
            self.engage_switch_from_rest();
        }
        action
    }

    fn on_event(&mut self, index: usize, t: f64, y: &mut [f64; N]) -> Action {
        let action = self.apply_event(index, t, y);
        self.catch_up(action, t, y)
    }

    fn wake(&mut self, t: f64, y: &mut [f64; N]) -> Action {
        match self.body.wake_side(&self.mode, t) {
            Some(side) => self.uplift(side, t, y),
            // A varying g_eff idles only to a lower bound of the uplift (`Gravity::
            // uplift_level`): from there the uplift events are integrated.
            None if self.mode.motion.gravity().has_vertical() && t < self.mode.motion.end() => {
                Action::Continue
            }
            None => Action::Stop(EndReason::Rest),
        }
    }

    /// A wake that lifted the base; a varying gravity may wake to integrate from a bound
    /// of the uplift without lifting it yet.
    fn wake_name(&self) -> Option<&'static str> {
        self.mode.rocking().then_some("uplift")
    }

    /// A body that does not move in contact is lifted by the ground itself: while it is flat
    /// its uplift test reads a_g directly.
    fn events_read_ground(&self) -> bool {
        !B::MOVES_IN_CONTACT && !self.mode.rocking()
    }

    /// Flat after the ground stopped, a body that cannot move in contact stays put: a
    /// flywheel can only spin down and drift away from engagement (its velocity never changes
    /// sign), so nothing can lift it. A flexible column decays but never stops (see
    /// [`SimModel::settled`] for its early stop).
    fn at_rest(&self, _t: f64, _y: &[f64; N]) -> bool {
        !B::MOVES_IN_CONTACT && self.mode.phase == Phase::Contact
    }

    /// A measure not asked for cannot hold the run: its peak counts as out of reach.
    fn settled(&self, y: &[f64; N]) -> bool {
        let mut peaks = self.peaks;
        let unasked = |asked: bool, peak: &mut f64| {
            if !asked {
                *peak = f64::INFINITY
            }
        };
        unasked(self.measures.deformation, &mut peaks.deformation);
        unasked(self.measures.drift, &mut peaks.drift);
        unasked(
            self.measures.abs_acceleration,
            &mut peaks.abs_acceleration_g,
        );
        if !self.measures.angular_acceleration {
            peaks.angular_acceleration_p2 = Some(f64::INFINITY);
        }
        self.body.settled(&self.mode, y, self.returnable(y), &peaks)
    }

    fn advance_closed_form(
        &mut self,
        t: f64,
        t_stop: f64,
        y: &mut [f64; N],
    ) -> Option<(f64, ClosedFormEnd)> {
        let (t1, uplift) =
            self.body
                .advance_closed_form(&self.mode, &mut self.peaks, t, t_stop, y)?;
        let end = match uplift {
            None => ClosedFormEnd::Reached,
            Some(side) => ClosedFormEnd::Event(
                self.events[..self.n_events]
                    .iter()
                    .position(|e| *e == Ev::Uplift(side))
                    .expect("uplift events exist in both directions"),
            ),
        };
        Some((t1, end))
    }

    /// The acceleration peaks read every step's interior; the body's own peaks only where its
    /// bound from the step's ends does not rule a rise out.
    fn step_reads_interior(&self, start: StepEnd<'_, N>, end: StepEnd<'_, N>) -> bool {
        let m = &self.mode;
        self.measures.abs_acceleration
            || (m.rocking() && self.peaks.angular_acceleration_p2.is_some())
            || self.body.step_may_raise_peaks(
                m,
                (start.0, &start.1[..], &start.2[..]),
                (end.0, &end.1[..], &end.2[..]),
                &self.peaks,
            )
    }

    /// The acceleration peaks are the largest of 4 + 1 samples per step, refined around the
    /// best one when it reaches the running peak ([`refine_sampled`]). The samples of both
    /// share one state, one set of kinematics and one right-hand side. A step whose bound
    /// ([`Body::acceleration_bounds`], from bounds of the interpolant over the whole step and,
    /// while the ground moves, of |a_g|: [`Motion::accel_bound`]) lies below the level at
    /// which the search could change the peak is skipped: every sample, and every point the
    /// refinement visits, lies below it too, so the result is the same as searching (for
    /// |θ̈| up to the margin the rigid block's bound documents).
    fn observe_step(&mut self, dense: &Dense<N>, t_end: f64) {
        self.body
            .observe_step(&self.mode, self.measures, dense, t_end, &mut self.peaks);
        let mut angular_floor = self
            .peaks
            .angular_acceleration_p2
            .filter(|_| self.mode.rocking());
        let mut abs_floor = self
            .measures
            .abs_acceleration
            .then_some(self.peaks.abs_acceleration_g);
        if angular_floor.is_none() && abs_floor.is_none() {
            return;
        }
        // refine_sampled leaves the peak unchanged when every sample is below this.
        let unreachable = |bound: Option<f64>, floor: f64| {
            bound.is_some_and(|b| below_peak(b, floor * (1.0 - 1e-9)))
        };
        let bounds = |ground: f64| {
            self.body.acceleration_bounds(
                &self.mode,
                |i| dense.bound(i),
                |i| dense.rate_bound(i),
                ground,
            )
        };
        // The bounds are lowest with the ground at rest; where even those reach a running peak
        // (while it grows), the bound of |a_g|, which costs evaluations of a_g, is not needed.
        let (abs_low, angular_low) = bounds(0.0);
        let may_skip = angular_floor.is_some_and(|f| unreachable(angular_low, f))
            || abs_floor.is_some_and(|f| unreachable(abs_low, f));
        if may_skip {
            let (abs_bound, angular_bound) = bounds(self.mode.motion.accel_bound(dense.t0, t_end));
            if angular_floor.is_some_and(|f| unreachable(angular_bound, f)) {
                angular_floor = None;
            }
            if abs_floor.is_some_and(|f| unreachable(abs_bound, f)) {
                abs_floor = None;
            }
        }
        if angular_floor.is_none() && abs_floor.is_none() {
            return;
        }
        const SAMPLES: usize = 4;
        let (t0, mut abs_values, mut angular_values) =
            (dense.t0, [0.0; SAMPLES + 1], [0.0; SAMPLES + 1]);
        for k in 0..=SAMPLES {
            let t = t0 + (t_end - t0) * k as f64 / SAMPLES as f64;
            let dy = abs_floor.map(|_| dense.derivative(t));
            let (a, w) =
                self.accelerations_at(t, &dense.state(t), dy.as_ref(), angular_floor.is_some());
            abs_values[k] = a;
            angular_values[k] = w;
        }
        if let Some(floor) = angular_floor {
            let theta_dd = |t: f64| self.accelerations_at(t, &dense.state(t), None, true).1;
            let peak = refine_sampled(theta_dd, t0, t_end, &angular_values, floor);
            self.peaks.angular_acceleration_p2 = Some(floor.max(peak));
        }
        if let Some(floor) = abs_floor {
            let accel_g = |t: f64| {
                let dy = dense.derivative(t);
                self.accelerations_at(t, &dense.state(t), Some(&dy), false)
                    .0
            };
            let peak = refine_sampled(accel_g, t0, t_end, &abs_values, floor);
            self.peaks.abs_acceleration_g = self.peaks.abs_acceleration_g.max(peak);
        }
    }

    fn observe_point(&mut self, t: f64, y: &[f64; N]) {
        self.body
            .observe_point(&self.mode, self.measures, y, &mut self.peaks);
        if !self.measures.abs_acceleration && self.peaks.angular_acceleration_p2.is_none() {
            return;
        }
        let k = self.body.kin(&self.mode, y);
        let mut dy = [0.0; N];
        self.rhs_kin(t, y, &k, &mut dy);
        if self.measures.abs_acceleration {
            let a = self.absolute_acceleration(t, &k, y, &dy);
            self.peaks.abs_acceleration_g = self
                .peaks
                .abs_acceleration_g
                .max(a.abs() / self.mode.motion.gravity().g());
        }
        // After a jump this is the one-sided value just past it (the jump itself excluded).
        if let Some(peak) = self.peaks.angular_acceleration_p2
            && let Some(p2) = self.body.angular_acceleration_scale()
            && self.mode.rocking()
        {
            self.peaks.angular_acceleration_p2 = Some(peak.max(dy[B::THETA_DOT].abs() / p2));
        }
    }

    fn observe_idle(&mut self, t0: f64, t1: f64) {
        if !self.measures.abs_acceleration {
            return;
        }
        let a = self.mode.motion.peak_abs(t0, t1);
        self.peaks.abs_acceleration_g = self
            .peaks
            .abs_acceleration_g
            .max(a / self.mode.motion.gravity().g());
    }

    fn energy(&self, y: &[f64; N]) -> Energy {
        self.energy_of(y)
    }

    fn peaks(&self) -> Peaks {
        self.peaks
    }

    fn counters(&self) -> Counters {
        self.counters
    }

    fn tolerance_scales(&self) -> Vec<f64> {
        let (mut state, device) = self.body.tolerance_scales(&self.mode);
        for _ in 0..self.mode.layout.device_dofs {
            state.extend(device);
        }
        state
    }

    fn event_name(&self, index: usize) -> &'static str {
        match self.events[index] {
            Ev::Impact => "impact",
            Ev::Overturn => "overturn",
            Ev::Uplift(_) => "uplift",
            Ev::Switch => "sequential_switch",
            Ev::Own(i) => self.body.own_event_name(i),
            Ev::Device(e) => e.name(),
        }
    }

    fn history_columns(&self) -> Vec<HistoryColumn> {
        std::iter::once(HistoryColumn::T)
            .chain(B::COORDINATES.iter().copied())
            .chain(HistoryColumn::DEVICE)
            .chain(HistoryColumn::ENERGY)
            .collect()
    }

    fn history_row(&self, t: f64, y: &[f64; N]) -> Vec<f64> {
        let layout = self.mode.layout;
        let (x, xdot) = self.x_xdot(y);
        let (fa, fb, fd) = self.device_force(t, y);
        // In the order of HistoryColumn::DEVICE.
        let device = [
            self.mode.motion.accel(t),
            x,
            xdot,
            layout.device_velocity(y, 0),
            layout.device_velocity(y, 1),
            fa,
            fb,
            fd,
        ];
        std::iter::once(t)
            .chain(y[..layout.coordinates].iter().copied())
            .chain(device)
            .chain(self.energy_of(y).terms())
            .collect()
    }
}
