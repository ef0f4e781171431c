//! The workbench's background work: starting a sweep, and on every tick taking in what the
//! calibration, the sweep and the scene jobs report (and keeping the stop question in step
//! with the sweep it asks about).

use super::{App, Check, JobEvent, Prompt, Screen};
use crate::sweep::estimate;
use std::time::{Duration, Instant};

impl App {
    pub fn start_run(&mut self) {
        if self.is_running() {
            self.complain("a sweep is already running (c cancels it)");
            return;
        }
        let points = match &self.shared.check {
            Check::Ok(points) => points.clone(),
            Check::Invalid(msg) => {
                let msg = format!("cannot run: {msg}");
                self.complain(msg);
                return;
            }
            Check::Pending { scenes } => {
                let msg = format!(
                    "the study's {scenes} scenes are still being expanded: r again once the count shows"
                );
                self.complain(msg);
                return;
            }
        };
        let out = match self.shared.output_dir() {
            Ok(out) => out,
            Err(e) => {
                self.complain(format!("cannot run: {e}"));
                return;
            }
        };
        self.calibration.abandon();
        self.runs.start(
            &self.shared.study,
            points,
            self.shared.options.jobs,
            out,
            self.shared.costs.clone(),
        );
        self.screen = Screen::Run;
    }

    /// Poll background work. Returns true if anything visible changed.
    pub fn tick(&mut self) -> bool {
        let mut changed = self.take_expansion();
        for event in self.calibration.poll() {
            if let JobEvent::Done(Some(costs)) = event {
                self.shared.costs = Some(costs);
                changed = true;
            }
        }
        let news = self.runs.poll();
        changed |= news.changed;
        if news.lost {
            self.complain("the sweep stopped unexpectedly");
        }
        if let Some(error) = news.error {
            self.complain(error);
        }
        if let Some((results, cancelled)) = news.finished {
            // The run's own scene times price the next estimate of this study.
            if let Check::Ok(points) = &self.shared.check {
                let strata = estimate::study_strata(&self.shared.study, points.len());
                let walls: Vec<(usize, f64)> = (results.outcomes.iter())
                    .filter_map(|o| {
                        let wall = o.result.as_ref().ok()?.wall_seconds;
                        Some((strata.of(o.point.index)?, wall))
                    })
                    .collect();
                if let Some(model) = estimate::CostModel::from_samples(&strata, &walls) {
                    self.shared.costs = Some((strata, model));
                }
            }
            let done = results.outcomes.len();
            if news.discarded {
                self.say(format!(
                    "sweep discarded: its {done} finished scenes stay in {}/, not shown",
                    self.shared.output_dir_shown()
                ));
            } else if cancelled {
                self.show_results(*results, cancelled);
                self.say(format!("sweep cancelled: {done} finished scenes kept"));
            } else {
                self.show_results(*results, cancelled);
                // The run wrote its fragility report beside the results: show it now, not
                // only after the directory is reopened.
                let beside = match self.shared.output_dir() {
                    Ok(dir) => self.load_beside(&dir),
                    Err(_) => String::new(),
                };
                if !beside.is_empty() {
                    self.say(format!("sweep finished: {done} scenes{beside}"));
                }
                if self.screen == Screen::Run {
                    self.screen = Screen::Results;
                }
            }
        }
        changed |= self.refresh_stop_question();
        changed |= self.scene.poll();
        changed
    }

    /// The stop question counts the sweep's scenes as they finish, and goes away (saying so)
    /// once the sweep has returned: there is nothing left to stop or discard then.
    fn refresh_stop_question(&mut self) -> bool {
        let Some(Prompt::StopSweep(stop)) = &mut self.prompt else {
            return false;
        };
        match self.runs.live_counts() {
            Some(counts) if counts == (stop.done, stop.total) => false,
            Some((done, total)) => {
                (stop.done, stop.total) = (done, total);
                true
            }
            None => {
                self.prompt = None;
                self.say("the sweep finished before an answer: nothing to stop");
                true
            }
        }
    }

    /// Tick until background work (a sweep, a scene, an expansion) settles or `deadline`
    /// passes (tests and scripts).
    /// True if everything finished in time.
    pub fn wait_idle(&mut self, deadline: Duration) -> bool {
        let until = Instant::now() + deadline;
        loop {
            self.tick();
            if !self.is_running() && !self.scene.is_running() && !self.expansion_pending() {
                return true;
            }
            if Instant::now() >= until {
                return false;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }
}
