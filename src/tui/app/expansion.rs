//! The open study's check off the UI thread: a study of more than [`EXPAND_AT_ONCE`] scenes
//! is expanded on a background worker (the check is pending meanwhile, and a newer study
//! drops a stale output by its generation), and once the scenes are in, a few of every
//! stratum are timed for the run-time estimate (`sweep::estimate`).

use super::{App, Check, EXPAND_AT_ONCE, JobEvent};
use crate::study::{ScenePoint, Study};
use crate::sweep::estimate;
use std::sync::Arc;
use std::time::Duration;

/// What the background expansion of a study returns: for which generation, the scenes (or
/// why the study is invalid), and how many groups they make.
pub struct Expanded {
    generation: u64,
    points: Result<Vec<ScenePoint>, String>,
    groups: usize,
}

/// Distinct group labels of an expansion (counted once, not per frame).
fn count_groups(points: &[ScenePoint]) -> usize {
    points
        .iter()
        .map(|p| p.group.as_str())
        .collect::<std::collections::HashSet<_>>()
        .len()
}

impl App {
    /// Validate `study` by expanding it: at once if small (or already expanded), else on the
    /// background worker with the check pending meanwhile. A newer study supersedes an
    /// expansion still running: its output is dropped when it lands.
    pub(super) fn begin_check(&mut self, study: &Study, points: Option<Vec<ScenePoint>>) {
        self.generation += 1;
        self.shared.costs = None;
        let points = match points {
            Some(points) => Ok(points),
            None => match study.layout().map(|l| l.len()) {
                Ok(scenes) if scenes > EXPAND_AT_ONCE => {
                    let generation = self.generation;
                    let study = study.clone();
                    self.calibration.abandon();
                    self.expansion.spawn(move |_, _| {
                        let points = study.expand().map_err(|e| e.to_string());
                        let groups = points.as_ref().map_or(0, |p| count_groups(p));
                        Expanded {
                            generation,
                            points,
                            groups,
                        }
                    });
                    self.replace_check(Check::Pending { scenes }, 0);
                    return;
                }
                _ => study.expand().map_err(|e| e.to_string()),
            },
        };
        self.expansion.abandon();
        let groups = points.as_ref().map_or(0, |p| count_groups(p));
        self.expanded(points, groups);
    }

    /// An expansion is in: it becomes the study's check, and the estimate's sample starts.
    fn expanded(&mut self, points: Result<Vec<ScenePoint>, String>, groups: usize) {
        let check = match points {
            Ok(points) => Check::Ok(Arc::new(points)),
            Err(msg) => Check::Invalid(msg),
        };
        self.replace_check(check, groups);
        self.start_calibration();
    }

    /// Take the background expansion's output if it is for the current study.
    pub(super) fn take_expansion(&mut self) -> bool {
        let mut changed = false;
        for event in self.expansion.poll() {
            match event {
                JobEvent::Done(done) if done.generation == self.generation => {
                    if let Err(msg) = &done.points {
                        self.complain(msg.clone());
                    }
                    self.expanded(done.points, done.groups);
                    changed = true;
                }
                JobEvent::Lost => {
                    self.replace_check(Check::Invalid("the expansion failed".into()), 0);
                    changed = true;
                }
                _ => {}
            }
        }
        changed
    }

    /// Set the check; a large expansion it replaces is freed on another thread (freeing
    /// 300 000 scenes takes a noticeable part of a second).
    fn replace_check(&mut self, check: Check, groups: usize) {
        let old = std::mem::replace(&mut self.shared.check, check);
        self.shared.groups = groups;
        if let Check::Ok(points) = old
            && points.len() > EXPAND_AT_ONCE
        {
            std::thread::spawn(move || drop(points));
        }
    }

    /// Time a few scenes of every stratum of the study in the background for the run-time
    /// estimate. A newer study replaces a calibration still running (its result would be
    /// stale), so fast edits do not pile up threads.
    pub(super) fn start_calibration(&mut self) {
        if self.shared.options.deterministic || self.is_running() {
            return;
        }
        let Check::Ok(points) = &self.shared.check else {
            return;
        };
        if points.is_empty() {
            return;
        }
        let points = Arc::clone(points);
        let strata = estimate::study_strata(&self.shared.study, points.len());
        let measures = crate::study::Quantity::measures(&self.shared.study.quantities);
        self.calibration.spawn(move |_, cancel| {
            let library = crate::excitation::library::global().ok()?;
            let budget = Duration::from_secs(4);
            let model = estimate::sample_costs(
                &points,
                measures,
                &strata,
                estimate::SAMPLES_PER_STRATUM,
                budget,
                library,
                cancel,
            )?;
            Some((strata, model))
        });
    }
}
