//! The Run screen: a sweep of the study on a background job, its progress overall and per
//! variant, and its failures. The finished (or cancelled) results go to the app.

use super::super::app::Screen;
use super::super::job::{AsyncSingleJob, JobEvent};
use super::super::theme::Theme;
use super::super::widgets::{Hint, fmt_coords, fmt_duration, gauge, pad, truncate};
use super::{Action, Check, Component, Shared};
use crate::study::{ScenePoint, Study};
use crate::sweep::{self, Progress, SweepOptions, SweepResults};
use crossterm::event::{KeyCode, KeyEvent};
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};
use std::sync::Arc;
use std::time::{Duration, Instant};

pub struct GroupProgress {
    pub name: String,
    pub total: usize,
    pub done: usize,
    pub failed: usize,
}

pub struct RunState {
    pub points: Arc<Vec<ScenePoint>>,
    pub total: usize,
    pub done: usize,
    pub failed: Vec<usize>,
    /// Failure messages, known once the sweep returns.
    pub failure_messages: Vec<(usize, String)>,
    pub groups: Vec<GroupProgress>,
    group_of: Vec<usize>,
    pub started: Instant,
    pub elapsed: Duration,
    /// None while running; Some(cancelled) once finished.
    pub finished: Option<bool>,
    pub cancel_requested: bool,
}

impl RunState {
    pub fn running(&self) -> bool {
        self.finished.is_none()
    }

    /// Scenes per second and seconds left, from the wall clock.
    pub fn rate_and_eta(&self) -> Option<(f64, f64)> {
        let secs = self.elapsed.as_secs_f64();
        if self.done == 0 || secs <= 0.0 {
            return None;
        }
        let rate = self.done as f64 / secs;
        Some((rate, (self.total - self.done) as f64 / rate))
    }
}

/// What a poll of the sweep brought.
#[derive(Default)]
pub struct RunNews {
    /// Something visible changed.
    pub changed: bool,
    /// The sweep returned: its results, and whether it was cancelled.
    pub finished: Option<(Box<SweepResults>, bool)>,
    /// The sweep ended without results.
    pub lost: bool,
}

#[derive(Default)]
pub struct RunScreen {
    /// The last sweep (None before the first).
    pub state: Option<RunState>,
    sweep: AsyncSingleJob<Progress, SweepResults>,
}

impl RunScreen {
    pub fn is_running(&self) -> bool {
        self.state.as_ref().is_some_and(|r| r.running())
    }

    /// Start sweeping `points` of `study` in the background.
    pub fn start(&mut self, study: &Study, points: Arc<Vec<ScenePoint>>, jobs: Option<usize>) {
        let mut groups: Vec<GroupProgress> = Vec::new();
        let group_of = points
            .iter()
            .map(|p| match groups.iter().position(|g| g.name == p.group) {
                Some(i) => {
                    groups[i].total += 1;
                    i
                }
                None => {
                    groups.push(GroupProgress {
                        name: p.group.clone(),
                        total: 1,
                        done: 0,
                        failed: 0,
                    });
                    groups.len() - 1
                }
            })
            .collect();
        // The command line's record library (a broken records index already fails the study
        // check for a record study).
        let Ok(library) = crate::excitation::library::global() else {
            return;
        };
        let thread_points = points.clone();
        let study = study.clone();
        let opts = SweepOptions {
            jobs,
            shard: None,
            cache: None,
        };
        self.sweep.spawn(move |reporter, cancel| {
            let progress = |p| reporter.report(p);
            // The study itself goes along so that spectra and maps know its quantities and axes.
            sweep::run_study(&study, &opts, library, cancel, &progress)
                .unwrap_or_else(|_| sweep::run(&thread_points, &opts, library, cancel, &progress))
        });
        self.state = Some(RunState {
            total: points.len(),
            points,
            done: 0,
            failed: Vec::new(),
            failure_messages: Vec::new(),
            groups,
            group_of,
            started: Instant::now(),
            elapsed: Duration::ZERO,
            finished: None,
            cancel_requested: false,
        });
    }

    /// Ask the running sweep to stop; the scenes it finished are kept.
    pub fn cancel(&mut self) -> Action {
        match &mut self.state {
            Some(run) if run.running() => {
                self.sweep.cancel();
                run.cancel_requested = true;
                Action::Say("cancelling: finished scenes are kept".into())
            }
            _ => Action::None,
        }
    }

    /// Stop background work before the process exits.
    pub fn shutdown(&self) {
        self.sweep.cancel();
    }

    pub fn poll(&mut self) -> RunNews {
        let mut news = RunNews::default();
        let Some(run) = self.state.as_mut() else {
            return news;
        };
        if !run.running() {
            return news;
        }
        run.elapsed = run.started.elapsed();
        for event in self.sweep.poll() {
            match event {
                JobEvent::Progress(Progress::Started { total }) => run.total = total,
                JobEvent::Progress(Progress::SceneDone { index, ok }) => {
                    run.done += 1;
                    if let Some(&g) = run.group_of.get(index) {
                        run.groups[g].done += 1;
                        if !ok {
                            run.groups[g].failed += 1;
                        }
                    }
                    if !ok {
                        run.failed.push(index);
                    }
                    news.changed = true;
                }
                JobEvent::Progress(Progress::Finished { .. }) => {}
                JobEvent::Done(results) => {
                    let cancelled = run.cancel_requested;
                    run.finished = Some(cancelled);
                    run.failure_messages = results
                        .outcomes
                        .iter()
                        .enumerate()
                        .filter_map(|(i, o)| o.result.as_ref().err().map(|e| (i, e.clone())))
                        .collect();
                    news.finished = Some((Box::new(results), cancelled));
                    news.changed = true;
                }
                JobEvent::Lost => {
                    run.finished = Some(true);
                    news.lost = true;
                    news.changed = true;
                }
            }
        }
        news
    }

    fn timing(&self, shared: &Shared, run: &RunState) -> String {
        if shared.options.deterministic {
            return String::new();
        }
        let elapsed = fmt_duration(run.elapsed.as_secs_f64());
        match (run.running(), run.rate_and_eta()) {
            (true, Some((rate, eta))) => {
                format!(
                    "{elapsed} elapsed  {rate:.1} scenes/s  ETA {}",
                    fmt_duration(eta)
                )
            }
            (false, Some((rate, _))) => format!("{elapsed}  {rate:.1} scenes/s"),
            _ => format!("{elapsed} elapsed"),
        }
    }
}

impl Component for RunScreen {
    fn handle_key(&mut self, key: KeyEvent, shared: &Shared) -> Action {
        match key.code {
            KeyCode::Char('r') => Action::StartRun,
            KeyCode::Char('c') | KeyCode::Esc => self.cancel(),
            KeyCode::Enter if shared.results.is_some() => Action::Show(Screen::Results),
            _ => Action::None,
        }
    }

    fn hints(&self, _: &Shared) -> Vec<Hint> {
        if self.is_running() {
            vec![("c", "cancel")]
        } else {
            vec![("r", "run"), ("Enter", "results")]
        }
    }

    fn draw(&self, shared: &Shared, theme: Theme, frame: &mut Frame, area: Rect) {
        let Some(run) = &self.state else {
            let text = match &shared.check {
                Check::Ok(points) => format!(
                    "No sweep yet. Press r to run the study ({} scenes).",
                    points.len()
                ),
                Check::Invalid(msg) => format!("The study is invalid: {msg}"),
            };
            frame.render_widget(Paragraph::new(text).wrap(Wrap { trim: true }), area);
            return;
        };
        let mut lines = Vec::new();
        let state = match run.finished {
            None if run.cancel_requested => Span::styled("cancelling…", theme.warn()),
            None => Span::styled("running", theme.warn()),
            Some(true) => Span::styled("cancelled (finished scenes kept)", theme.warn()),
            Some(false) => Span::styled("finished", theme.ok()),
        };
        let bar_width = (area.width as usize).saturating_sub(44).clamp(5, 40);
        let failed = run.failed.len();
        lines.push(Line::from(vec![
            Span::styled(pad("overall", 14), theme.field()),
            Span::raw(" "),
            gauge(theme, run.done, run.total, bar_width),
            Span::raw(format!(" {:>5}/{:<5}", run.done, run.total)),
            Span::styled(
                format!(" {failed} failed"),
                if failed > 0 {
                    theme.error()
                } else {
                    theme.dim()
                },
            ),
        ]));
        lines.push(Line::from(vec![
            state,
            Span::raw("  "),
            Span::raw(self.timing(shared, run)),
        ]));
        lines.push(Line::raw(""));
        for g in &run.groups {
            lines.push(Line::from(vec![
                Span::styled(pad(&truncate(&g.name, 14), 14), theme.field()),
                Span::raw(" "),
                gauge(theme, g.done, g.total, bar_width),
                Span::raw(format!(" {:>5}/{:<5}", g.done, g.total)),
                Span::styled(
                    if g.failed > 0 {
                        format!(" {} failed", g.failed)
                    } else {
                        String::new()
                    },
                    theme.error(),
                ),
            ]));
        }
        if failed > 0 {
            lines.push(Line::raw(""));
            lines.push(Line::styled("failures:", theme.error()));
            for &i in run.failed.iter() {
                let Some(p) = run.points.get(i) else { continue };
                let message = run
                    .failure_messages
                    .iter()
                    .find(|(j, _)| *j == i)
                    .map_or(String::new(), |(_, m)| format!(": {m}"));
                lines.push(Line::raw(format!(
                    "  #{i} {} {}{message}",
                    p.group,
                    fmt_coords(&p.coords)
                )));
            }
        }
        frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), area);
    }
}
