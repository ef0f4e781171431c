//! The Run screen: a sweep of the study on a background job, its progress overall and per
//! variant, and its failures. A run here is a `rocklab run`: it goes through the same output
//! directory, journal, lock and atomic results files (the sweep's façade, [`sweep::DirRun`]),
//! so a finished scene is on disk as soon as it finishes and `r` after a cancel or a quit
//! resumes. The results go to the app.

use super::super::app::Screen;
use super::super::job::{AsyncSingleJob, JobEvent};
use super::super::theme::Theme;
use super::super::widgets::{Hint, fmt_coords, fmt_duration, gauge, pad, truncate};
use super::prompt::{Prompt, StopSweep};
use super::{Action, Check, Command, Component, Shared, command};
use crate::report;
use crate::study::{ScenePoint, Study};
use crate::sweep::estimate::{CostModel, RunEstimate, Strata};
use crate::sweep::{self, OpenOptions, Progress, SweepResults};
use crate::tui::edit::LineEdit;
use crossterm::event::{KeyCode, KeyEvent};
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
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
    /// Of `done`, scenes reused from the output directory's journal (not computed now).
    pub reused: usize,
    pub failed: Vec<usize>,
    /// Where the results go (the output directory).
    pub out_dir: PathBuf,
    /// Notes of opening the output directory (resuming, set-aside files), then any error.
    pub notes: Vec<String>,
    /// Failure messages, known once the sweep returns.
    pub failure_messages: Vec<(usize, String)>,
    pub groups: Vec<GroupProgress>,
    group_of: Vec<usize>,
    pub started: Instant,
    pub elapsed: Duration,
    /// None while running; Some(cancelled) once finished.
    pub finished: Option<bool>,
    pub cancel_requested: bool,
    /// The sweep was stopped with "discard": its results are not shown when it returns.
    pub discard: bool,
    /// The sweep returned an error (shown on the status line) instead of results.
    pub failed_to_finish: bool,
    /// Seconds left by the scenes' measured costs (see `sweep::estimate`), refreshed on poll.
    estimate: RunEstimate,
    pub seconds_left: Option<f64>,
}

impl RunState {
    pub fn running(&self) -> bool {
        self.finished.is_none()
    }

    /// Computed scenes per second and seconds left: reused scenes are not counted (they
    /// cost nothing and would make the ETA a fraction of the truth); the time left weighs
    /// the scenes left by their measured cost (`sweep::estimate`).
    pub fn rate_and_eta(&self) -> Option<(f64, f64)> {
        let secs = self.elapsed.as_secs_f64();
        let computed = self.done - self.reused;
        let eta = self
            .seconds_left
            .or_else(|| sweep::eta_seconds(secs, computed, self.total.saturating_sub(self.done)))?;
        (computed > 0 && secs > 0.0).then(|| (computed as f64 / secs, eta))
    }
}

/// What a poll of the sweep brought.
#[derive(Default)]
pub struct RunNews {
    /// Something visible changed.
    pub changed: bool,
    /// The sweep returned: its results, and whether it was cancelled.
    pub finished: Option<(Box<SweepResults>, bool)>,
    /// The sweep that returned was discarded (its results are not to be shown).
    pub discarded: bool,
    /// The sweep ended without results.
    pub lost: bool,
    /// What went wrong with the output directory (finished scenes are journalled).
    pub error: Option<String>,
}

/// What a sweep job returns: the results it has (None if the output directory could not be
/// used), the notes of opening it, and what went wrong (the journal keeps finished scenes).
pub struct SweepOutcome {
    pub results: Option<SweepResults>,
    pub notes: Vec<String>,
    pub error: Option<String>,
}

/// Sweep `points` of `study` into `out_dir` exactly as `rocklab run` does: open (lock, resume
/// from the journal), run with every finished scene journalled, write the results files.
fn sweep_into(
    study: &Study,
    points: &[ScenePoint],
    out_dir: &Path,
    jobs: Option<usize>,
    library: &crate::excitation::Library,
    cancel: &std::sync::atomic::AtomicBool,
    progress: &(dyn Fn(Progress) + Sync),
) -> SweepOutcome {
    let mut outcome = SweepOutcome {
        results: None,
        notes: Vec::new(),
        error: None,
    };
    let opened = sweep::DirRun::open(out_dir, None, study, points.len(), OpenOptions::default());
    let output = match opened {
        Ok(output) => output,
        Err(e) => {
            outcome.error = Some(format!("{e:#}"));
            return outcome;
        }
    };
    outcome.notes = output.notes().to_vec();
    let results = match output.run(
        study,
        points,
        jobs,
        library,
        Some(sweep::SCENE_TIME_LIMIT),
        cancel,
        progress,
        report::WRITERS,
    ) {
        Ok(finished) => finished,
        Err(e) => {
            outcome.error = Some(format!("{e:#}"));
            return outcome;
        }
    };
    outcome.error = results.written.err().map(|e| format!("{e:#}"));
    outcome.results = Some(results.results);
    outcome
}

#[derive(Default)]
pub struct RunScreen {
    /// The last sweep (None before the first).
    pub state: Option<RunState>,
    sweep: AsyncSingleJob<Progress, SweepOutcome>,
    /// First row of the scrolled part (groups, failures) shown.
    pub scroll: usize,
    /// Rows of the scrolled part the last frame had room for (for PgUp/PgDn and clamping).
    page: std::cell::Cell<usize>,
}

impl RunScreen {
    pub fn is_running(&self) -> bool {
        self.state.as_ref().is_some_and(|r| r.running())
    }

    /// Start sweeping `points` of `study` into `out_dir` in the background.
    pub fn start(
        &mut self,
        study: &Study,
        points: Arc<Vec<ScenePoint>>,
        jobs: Option<usize>,
        out_dir: PathBuf,
        costs: Option<(Strata, CostModel)>,
    ) {
        let mut groups: Vec<GroupProgress> = Vec::new();
        // By name through a map: a linear search per scene is quadratic on 300 000 scenes.
        let mut by_name: HashMap<&str, usize> = HashMap::new();
        let group_of = points
            .iter()
            .map(|p| match by_name.get(p.group.as_str()) {
                Some(&i) => {
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
                    by_name.insert(&p.group, groups.len() - 1);
                    groups.len() - 1
                }
            })
            .collect();
        drop(by_name);
        let threads = jobs.unwrap_or_else(rayon::current_num_threads);
        let (strata, model) = match costs {
            Some((strata, model)) => (strata, Some(model)),
            None => (sweep::estimate::study_strata(study, points.len()), None),
        };
        let estimate = RunEstimate::new(strata, model, threads);
        // The command line's record library (a broken records index already fails the study
        // check for a record study).
        let Ok(library) = crate::excitation::library::global() else {
            return;
        };
        let thread_points = points.clone();
        let study = study.clone();
        let dir = out_dir.clone();
        let returned = Arc::new(AtomicBool::new(false));
        let has_returned = returned.clone();
        self.sweep.spawn(move |reporter, cancel| {
            let progress = |p| reporter.report(p);
            let outcome = sweep_into(
                &study,
                &thread_points,
                &dir,
                jobs,
                library,
                cancel,
                &progress,
            );
            has_returned.store(true, Ordering::Relaxed);
            outcome
        });
        // A signal stops the sweep even when the event loop cannot run (tui/hangup.rs).
        if let Some(cancel) = self.sweep.cancel_flag() {
            crate::tui::hangup::sweep_started(cancel, returned);
        }
        self.state = Some(RunState {
            total: points.len(),
            points,
            done: 0,
            reused: 0,
            failed: Vec::new(),
            out_dir,
            notes: Vec::new(),
            failure_messages: Vec::new(),
            groups,
            group_of,
            started: Instant::now(),
            elapsed: Duration::ZERO,
            finished: None,
            cancel_requested: false,
            discard: false,
            failed_to_finish: false,
            estimate,
            seconds_left: None,
        });
    }

    /// What stopping the running sweep would mean, for the question asked first (None if no
    /// sweep runs).
    pub fn stop_question(&self, quit: bool) -> Option<StopSweep> {
        let run = self
            .state
            .as_ref()
            .filter(|r| r.running() && !r.cancel_requested)?;
        Some(StopSweep {
            quit,
            done: run.done,
            total: run.total,
            out_dir: run.out_dir.clone(),
        })
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

    /// Stop the running sweep and have its results not shown when it returns. False (and
    /// nothing done) if no sweep runs any more: a discard asked while it was finishing must
    /// not apply to a later run.
    pub fn discard(&mut self) -> bool {
        match &mut self.state {
            Some(run) if run.running() => {
                self.sweep.cancel();
                run.cancel_requested = true;
                run.discard = true;
                true
            }
            _ => false,
        }
    }

    /// The running sweep's finished and total scene counts (None once it has returned).
    pub fn live_counts(&self) -> Option<(usize, usize)> {
        let run = self.state.as_ref().filter(|r| r.running())?;
        Some((run.done, run.total))
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
        let events = self.sweep.poll();
        run.seconds_left = run.estimate.seconds_left(run.elapsed.as_secs_f64());
        for event in events {
            match event {
                JobEvent::Progress(Progress::Started { total }) => run.total = total,
                JobEvent::Progress(Progress::SceneDone { index, ok, reused }) => {
                    run.done += 1;
                    run.estimate.scene_done(index, reused);
                    run.reused += usize::from(reused);
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
                JobEvent::Done(outcome) => {
                    run.notes = outcome.notes;
                    news.error = outcome.error;
                    news.changed = true;
                    let Some(results) = outcome.results else {
                        run.finished = Some(true);
                        run.failed_to_finish = true;
                        continue;
                    };
                    let cancelled = run.cancel_requested || results.cancelled;
                    run.finished = Some(cancelled);
                    run.failure_messages = results
                        .outcomes
                        .iter()
                        .filter_map(|o| o.result.as_ref().err().map(|e| (o.point.index, e.clone())))
                        .collect();
                    news.finished = Some((Box::new(results), cancelled));
                    news.discarded = run.discard;
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

impl RunScreen {
    /// Rows of the scrolled part: one per group, then the failures.
    fn body_len(&self) -> usize {
        self.state.as_ref().map_or(0, |run| {
            let failed = run.failed.len();
            run.groups.len() + if failed > 0 { 2 + failed } else { 0 }
        })
    }

    fn scroll_by(&mut self, down: bool, by: usize) {
        let max = self.body_len().saturating_sub(self.page.get().max(1));
        self.scroll = if down {
            (self.scroll + by).min(max)
        } else {
            self.scroll.min(max).saturating_sub(by)
        };
    }
}

impl Component for RunScreen {
    fn commands(&self) -> &'static [Command] {
        const COMMANDS: &[Command] = &[
            command(
                "c / Esc",
                "stop (asks; finished scenes are kept, r resumes)",
            ),
            command("↑↓ d Enter", "scroll (PgUp/Dn g/G) / results dir / results"),
        ];
        COMMANDS
    }

    fn handle_key(&mut self, key: KeyEvent, shared: &Shared) -> Action {
        let page = self.page.get().max(2) - 1;
        match key.code {
            KeyCode::Down | KeyCode::Char('j') => self.scroll_by(true, 1),
            KeyCode::Up | KeyCode::Char('k') => self.scroll_by(false, 1),
            KeyCode::PageDown | KeyCode::Char(' ') => self.scroll_by(true, page),
            KeyCode::PageUp => self.scroll_by(false, page),
            KeyCode::Home | KeyCode::Char('g') => self.scroll = 0,
            KeyCode::End | KeyCode::Char('G') => self.scroll_by(true, usize::MAX / 2),
            _ => return self.command_key(key, shared),
        }
        Action::None
    }

    fn hints(&self, shared: &Shared) -> Vec<Hint> {
        self.own_hints(shared)
    }

    fn draw(&self, shared: &Shared, theme: Theme, frame: &mut Frame, area: Rect) {
        self.draw_run(shared, theme, frame, area)
    }
}

impl RunScreen {
    fn command_key(&mut self, key: KeyEvent, shared: &Shared) -> Action {
        match key.code {
            KeyCode::Char('r') => Action::StartRun,
            KeyCode::Char('d') if !self.is_running() => {
                Action::Prompt(Prompt::OutDir(LineEdit::new(
                    shared
                        .output_dir()
                        .map(|d| d.display().to_string())
                        .unwrap_or_default(),
                )))
            }
            KeyCode::Char('c') | KeyCode::Esc => match self.stop_question(false) {
                Some(stop) => Action::Prompt(Prompt::StopSweep(stop)),
                None => Action::None,
            },
            KeyCode::Enter if shared.results.is_some() => Action::Show(Screen::Results),
            _ => Action::None,
        }
    }

    fn own_hints(&self, _: &Shared) -> Vec<Hint> {
        let scrolls = self.body_len() > self.page.get();
        if self.is_running() {
            let mut hints = vec![("c", "stop")];
            if scrolls {
                hints.push(("↑↓ PgUp/Dn g/G", "scroll"));
            }
            hints
        } else {
            let mut hints = vec![("r", "run"), ("Enter", "results"), ("d", "results dir")];
            if scrolls {
                hints.push(("↑↓ PgUp/Dn g/G", "scroll"));
            }
            hints
        }
    }

    fn draw_run(&self, shared: &Shared, theme: Theme, frame: &mut Frame, area: Rect) {
        let Some(run) = &self.state else {
            let text = match &shared.check {
                Check::Ok(points) => format!(
                    "No sweep yet. Press r to run the study ({} scenes); results go to {}/ \
                     (d changes it), and a run stopped early resumes there.",
                    points.len(),
                    shared.output_dir_shown()
                ),
                Check::Invalid(msg) => format!("The study is invalid: {msg}"),
                Check::Pending { scenes } => format!(
                    "The study's {scenes} scenes are being expanded; r runs it once they are."
                ),
            };
            frame.render_widget(Paragraph::new(text).wrap(Wrap { trim: true }), area);
            return;
        };
        let mut lines = Vec::new();
        let state = match run.finished {
            None if run.cancel_requested => Span::styled("cancelling…", theme.warn()),
            None => Span::styled("running", theme.warn()),
            Some(true) if run.failed_to_finish && run.done == 0 => {
                Span::styled("not run (see the message below)", theme.error())
            }
            Some(true) if run.failed_to_finish => {
                Span::styled("stopped by an error (finished scenes kept)", theme.error())
            }
            Some(true) => Span::styled("cancelled (finished scenes kept)", theme.warn()),
            Some(false) => Span::styled("finished", theme.ok()),
        };
        // Names as wide as the longest (up to 2/5 of the width: "landers · sequential
        // sigma=0.5" must read whole at 80 columns), the bars take the rest.
        let name_width = run
            .groups
            .iter()
            .map(|g| g.name.chars().count())
            .max()
            .unwrap_or(0)
            .clamp(14, (area.width as usize * 2 / 5).max(14));
        let bar_width = (area.width as usize)
            .saturating_sub(name_width + 30)
            .clamp(5, 40);
        let failed = run.failed.len();
        lines.push(Line::from(vec![
            Span::styled(pad("overall", name_width), theme.field()),
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
        let mut status = vec![state, Span::raw("  "), Span::raw(self.timing(shared, run))];
        if run.reused > 0 {
            status.push(Span::styled(
                format!("  {} reused, {} new", run.reused, run.done - run.reused),
                theme.dim(),
            ));
        }
        lines.push(Line::from(status));
        lines.push(Line::from(vec![
            Span::styled("results in ", theme.dim()),
            Span::raw(format!("{}/", run.out_dir.display())),
        ]));
        let header = lines.len() + 1;
        // Only the rows in view are built: a study may have thousands of groups and failures.
        let body_len = self.body_len();
        let room = (area.height as usize).saturating_sub(header);
        self.page.set(room);
        let offset = self.scroll.min(body_len.saturating_sub(room));
        if body_len > room && room > 0 {
            lines.push(Line::styled(
                format!(
                    "rows {}–{} of {} (↑↓ PgUp/PgDn g/G scroll)",
                    offset + 1,
                    (offset + room).min(body_len),
                    body_len
                ),
                theme.dim(),
            ));
        } else {
            lines.push(Line::raw(""));
        }
        let groups = run.groups.len();
        for row in (offset..body_len).take(room) {
            if let Some(g) = run.groups.get(row) {
                lines.push(Line::from(vec![
                    Span::styled(
                        pad(&truncate(&g.name, name_width), name_width),
                        theme.field(),
                    ),
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
            } else if row == groups {
                lines.push(Line::raw(""));
            } else if row == groups + 1 {
                lines.push(Line::styled("failures:", theme.error()));
            } else if let Some(&i) = run.failed.get(row - groups - 2) {
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
        // Rows are cut, not wrapped: a wrapped row would push the last ones out of view.
        frame.render_widget(Paragraph::new(lines), area);
    }
}
