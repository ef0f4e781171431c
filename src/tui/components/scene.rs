//! The Scene screen: one scene of the results rerun with its histories on a background job,
//! its verdict, and charts of rotation, flywheels, clutch forces and energies; on request
//! (`c`) the scene's check (`sim::check`: converged, not converged or ill-conditioned) on a
//! second job.

use super::super::app::Screen;
use super::super::job::{AsyncSingleJob, JobEvent};
use super::super::theme::Theme;
use super::super::widgets::chart::draw_chart;
use super::super::widgets::{Hint, fmt_num};
use super::{Action, Command, Component, Shared, command};
use crate::numfmt::fmt_condition;
use crate::sim::check::{Check, Reproducibility, short_name};
use crate::sim::{self, EnergyRole, History, HistoryColumn, SceneResult};
use crate::study::ScenePoint;
use crossterm::event::{KeyCode, KeyEvent};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

pub enum SceneState {
    Running,
    Done(Box<SceneResult>, History),
    Failed(String),
}

pub enum CheckState {
    Running,
    Done(Box<Check>),
    Failed(String),
}

pub struct SceneView {
    pub point: ScenePoint,
    pub state: SceneState,
    /// The scene's check, once asked for.
    pub check: Option<CheckState>,
}

type SceneOutput = Result<(SceneResult, History), String>;

#[derive(Default)]
pub struct SceneScreen {
    /// The scene on screen (None before the first).
    pub view: Option<SceneView>,
    job: AsyncSingleJob<(), SceneOutput>,
    check_job: AsyncSingleJob<(), Result<Check, String>>,
}

impl SceneScreen {
    /// Rerun `point` with histories; a newer request replaces one still running.
    pub fn open(&mut self, point: ScenePoint) {
        let scene = point.scene.clone();
        self.job.spawn(move |_, _| {
            let library = crate::excitation::library::global().map_err(|e| e.to_string())?;
            // The whole duration (a sweep's scene may stop once settled), on a uniform grid.
            sim::run_history(&sim::history_scene(&scene), library, &sim::Sampling::Auto)
                .map_err(|e| e.to_string())
        });
        self.check_job.abandon();
        self.view = Some(SceneView {
            point,
            state: SceneState::Running,
            check: None,
        });
    }

    /// Check the scene on screen: its own run at its tolerance, then the reference and the
    /// scaled runs of `sim::check`.
    pub fn start_check(&mut self) {
        let Some(view) = &mut self.view else {
            return;
        };
        let scene = view.point.scene.clone();
        self.check_job.spawn(move |_, cancel| {
            let library = crate::excitation::library::global().map_err(|e| e.to_string())?;
            let bounds = sim::Bounds {
                cancel: Some(cancel),
                ..Default::default()
            };
            let result = sim::run_bounded(&scene, library, bounds).map_err(|e| e.to_string())?;
            sim::check::check(&scene, &result, library, bounds).map_err(|e| e.to_string())
        });
        view.check = Some(CheckState::Running);
    }

    /// Show a scene computed elsewhere (no rerun): results opened from a file, or tests that
    /// draw fixed data.
    pub fn show(&mut self, point: ScenePoint, result: SceneResult, history: History) {
        self.job.abandon();
        self.check_job.abandon();
        self.view = Some(SceneView {
            point,
            state: SceneState::Done(Box::new(result), history),
            check: None,
        });
    }

    pub fn is_running(&self) -> bool {
        self.job.is_busy() || self.check_job.is_busy()
    }

    /// True if the scene finished (or failed) since the last poll.
    pub fn poll(&mut self) -> bool {
        let mut changed = false;
        for event in self.job.poll() {
            let state = match event {
                JobEvent::Progress(()) => continue,
                JobEvent::Done(Ok((result, history))) => {
                    SceneState::Done(Box::new(result), history)
                }
                JobEvent::Done(Err(e)) => SceneState::Failed(e),
                JobEvent::Lost => SceneState::Failed("the scene run stopped".into()),
            };
            if let Some(view) = &mut self.view {
                view.state = state;
                changed = true;
            }
        }
        for event in self.check_job.poll() {
            let state = match event {
                JobEvent::Progress(()) => continue,
                JobEvent::Done(Ok(check)) => CheckState::Done(Box::new(check)),
                JobEvent::Done(Err(e)) => CheckState::Failed(e),
                JobEvent::Lost => CheckState::Failed("the check stopped".into()),
            };
            if let Some(view) = &mut self.view {
                view.check = Some(state);
                changed = true;
            }
        }
        changed
    }
}

impl Component for SceneScreen {
    fn commands(&self) -> &'static [Command] {
        const COMMANDS: &[Command] = &[command(
            "Esc  c",
            "back / check; `rocklab plot DIR --scene N` draws it",
        )];
        COMMANDS
    }

    fn handle_key(&mut self, key: KeyEvent, _: &Shared) -> Action {
        match key.code {
            KeyCode::Esc | KeyCode::Backspace => Action::Show(Screen::Results),
            KeyCode::Char('r') => Action::StartRun,
            KeyCode::Char('c') => {
                self.start_check();
                Action::None
            }
            _ => Action::None,
        }
    }

    fn hints(&self, _: &Shared) -> Vec<Hint> {
        vec![("Esc", "back"), ("c", "check")]
    }

    fn draw(&self, shared: &Shared, theme: Theme, frame: &mut Frame, area: Rect) {
        let Some(view) = &self.view else {
            frame.render_widget(
                Paragraph::new(
                    "No scene open. On the Results screen, put the cursor on a point of a spectrum or a map cell and press Enter.",
                )
                .wrap(Wrap { trim: true }),
                area,
            );
            return;
        };

        // The index is what `rocklab plot --scene N` and `rocklab check` name the scene by.
        let mut lines = vec![Line::from(vec![
            Span::styled(format!("scene {}", view.point.index), theme.title()),
            Span::raw(format!("  {}", crate::report::scene_label(&view.point))),
        ])];
        match &view.state {
            SceneState::Running => lines.push(Line::styled("simulating…", theme.warn())),
            SceneState::Failed(e) => {
                lines.push(Line::styled(format!("failed: {e}"), theme.error()))
            }
            SceneState::Done(r, history) => {
                // Counted over the whole history (the rerun does not stop once settled; a
                // block at rest stays so until the end).
                let span = history.rows.last().map_or(r.end_time, |row| row[0]);
                let mut text = format!(
                    "{}  0–{} s: impacts {}",
                    verdict(&view.point.scene.structure, r),
                    fmt_num(span),
                    r.counters.impacts,
                );
                if view.point.scene.device != crate::scene::Device::None {
                    text.push_str(&format!("  engagements {}", r.counters.engagements));
                }
                // The energy residual is at the level of the solver tolerance: it changes with
                // any change to the integrator, so reproducible frames leave it out.
                if !shared.options.deterministic {
                    text.push_str(&format!("  energy residual {:.1e}", r.energy_residual));
                }
                lines.push(Line::raw(text));
            }
        }
        match &view.check {
            None => {}
            Some(CheckState::Running) => lines.push(Line::styled("checking…", theme.warn())),
            Some(CheckState::Failed(e)) => {
                lines.push(Line::styled(format!("check failed: {e}"), theme.error()))
            }
            Some(CheckState::Done(c)) => lines.push(check_line(c, theme)),
        }
        // As many rows as the lines take wrapped (a word wrap can take a little more than
        // width / columns: one spare row when anything wraps), at most half the screen.
        let columns = area.width.max(1) as usize;
        let wrapped: usize = lines
            .iter()
            .map(|l| l.width().max(1).div_ceil(columns))
            .sum();
        let head_rows = (wrapped + usize::from(wrapped > lines.len())) as u16;
        let [head, body] = Layout::vertical([
            Constraint::Length(head_rows.min(area.height / 2)),
            Constraint::Min(1),
        ])
        .areas(area);
        frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: true }), head);
        if let SceneState::Done(_, history) = &view.state {
            draw_histories(history, theme, frame, body);
        }
    }
}

/// Overturned or safe, by the structure's own criterion: a rigid block overturns when
/// |θ| reaches α, so θmax/α is its measure; a flexible structure when its mass passes over the
/// pivot (docs/MODEL.md), i.e. when the drift |X|/H reaches B/H = tan α, before θ reaches α
/// (the column leans the mass outward): its measure is the drift against tan α, with θmax/α
/// after it.
fn verdict(structure: &crate::scene::Structure, r: &SceneResult) -> String {
    use crate::sim::Quantity;
    let word = if r.overturned { "OVERTURNED" } else { "safe" };
    let rotation = format!(
        "{} {}",
        Quantity::PeakRotationRatio.info().axis,
        fmt_num(r.peak_rotation_ratio)
    );
    match (structure, Quantity::PeakDrift.peak(r)) {
        (crate::scene::Structure::Flexible(f), Some(drift)) => {
            let limit = fmt_num(f.alpha.tan());
            let criterion = if r.overturned {
                "= tan α: mass over the pivot".to_string()
            } else {
                format!("overturns at tan α = {limit}")
            };
            format!(
                "{word}  {} {} ({criterion})  {rotation}",
                Quantity::PeakDrift.info().axis,
                fmt_num(drift),
            )
        }
        _ => format!("{word}  {rotation}"),
    }
}

/// The check in one line: the verdict, the worst change against the reference and the worst
/// condition number, and what to do.
fn check_line(c: &Check, theme: Theme) -> Line<'static> {
    let measured = match (c.worst_change(), c.worst_peak()) {
        (Some(changed), Some(sensitive)) => format!(
            " · worst rel. change {:.1e} ({}) · max κ {} ({}) · rtol {:e} vs {:e}",
            changed.change,
            short_name(changed.quantity),
            fmt_condition(sensitive.condition),
            short_name(sensitive.quantity),
            c.rtol,
            c.reference_rtol,
        ),
        _ => " · every peak negligible (the structure barely rocks)".to_string(),
    };
    let (verdict, advice, style) = match c.verdict {
        Reproducibility::Converged => ("converged", String::new(), theme.ok()),
        Reproducibility::NotConverged => (
            "not converged",
            " · a tighter rtol fixes it".to_string(),
            theme.warn(),
        ),
        Reproducibility::IllConditioned if c.overturn_flips => (
            "ill-conditioned",
            " · on the overturning boundary".to_string(),
            theme.error(),
        ),
        Reproducibility::IllConditioned => (
            "ill-conditioned",
            match c.suggested_rtol() {
                Some(rtol) => format!(
                    " · a 1e-7 change of the inputs moves it; reproducible from rtol ≲ {rtol:e}"
                ),
                None => " · it appears or vanishes under a 1e-7 change of the inputs".into(),
            },
            theme.error(),
        ),
    };
    Line::from(vec![
        Span::styled(format!("check: {verdict}"), style),
        Span::raw(format!("{measured}{advice}")),
    ])
}

/// One chart: title, unit of its values, and (legend name, values) of each series.
struct Panel {
    title: &'static str,
    unit: &'static str,
    series: Vec<(&'static str, Vec<f64>)>,
}

/// The charts of a scene from the columns its model records, one quantity (one unit) per
/// chart: rotation θ; the column deformation u of a flexible structure; the flywheel
/// velocities and the clutch (or device) forces where a device moves; the energy balance
/// (input, stored, dissipated). A device chart whose series are all zero (a bare structure) is
/// left out.
fn panels(history: &History) -> Vec<Panel> {
    use HistoryColumn as C;
    let col = |c: C| history.column(c);
    let moving = |c: C| {
        col(c)
            .filter(|v| v.iter().any(|x| *x != 0.0))
            .map(|v| (c.label(), v))
    };
    let mut panels = vec![Panel {
        title: "rotation θ",
        unit: C::Theta.info().unit,
        series: col(C::Theta)
            .map(|v| (C::Theta.label(), v))
            .into_iter()
            .collect(),
    }];
    if let Some(u) = col(C::U) {
        panels.push(Panel {
            title: "deformation u",
            unit: C::U.info().unit,
            series: vec![(C::U.label(), u)],
        });
    }
    // A device chart with the series of `columns` that move, if any does.
    let moving_panel = |title, columns: [C; 2]| {
        let series: Vec<_> = columns.into_iter().filter_map(moving).collect();
        (!series.is_empty()).then_some(Panel {
            title,
            unit: columns[0].info().unit,
            series,
        })
    };
    panels.extend(moving_panel(
        "flywheel velocity ẏ",
        [C::FlywheelAVel, C::FlywheelBVel],
    ));
    if let Some(clutches) = moving_panel("clutch force", [C::ClutchForceA, C::ClutchForceB]) {
        panels.push(clutches);
    } else if let Some(device) = moving(C::DeviceForce) {
        panels.push(Panel {
            title: "device force",
            unit: C::DeviceForce.info().unit,
            series: vec![device],
        });
    }
    let sum = |columns: &[C]| -> Option<Vec<f64>> {
        let columns: Vec<Vec<f64>> = columns.iter().filter_map(|c| col(*c)).collect();
        let first = columns.first()?;
        Some(
            (0..first.len())
                .map(|i| columns.iter().map(|c| c[i]).sum())
                .collect(),
        )
    };
    let role = |role: EnergyRole| -> Vec<C> {
        let of_role = history.columns.iter().copied();
        of_role.filter(|c| c.energy() == Some(role)).collect()
    };
    let energy: Vec<_> = [
        ("input", sum(&role(EnergyRole::Input))),
        ("stored", sum(&role(EnergyRole::Stored))),
        ("dissipated", sum(&role(EnergyRole::Dissipated))),
    ]
    .into_iter()
    .filter_map(|(l, v)| Some((l, v?)))
    .collect();
    if !energy.is_empty() {
        panels.push(Panel {
            title: "energy",
            unit: C::EInput.info().unit,
            series: energy,
        });
    }
    panels
}

/// The panels two to a row, an odd last one across the whole width.
fn draw_histories(history: &History, theme: Theme, frame: &mut Frame, area: Rect) {
    let panels = panels(history);
    let rows = panels.len().div_ceil(2).max(1);
    let row_areas = Layout::vertical(vec![Constraint::Ratio(1, rows as u32); rows]).split(area);
    let t = history.column(HistoryColumn::T).unwrap_or_default();
    for (pair, row) in panels.chunks(2).zip(row_areas.iter()) {
        let cells = Layout::horizontal(vec![Constraint::Ratio(1, pair.len() as u32); pair.len()])
            .split(*row);
        for (panel, cell) in pair.iter().zip(cells.iter()) {
            draw_chart(
                frame,
                *cell,
                theme,
                panel.title,
                panel.unit,
                &t,
                &panel.series,
            );
        }
    }
}
