//! The Scene screen: one scene of the results rerun with its histories on a background job,
//! its verdict, and charts of rotation, flywheels, clutch forces and energies.

use super::super::app::Screen;
use super::super::job::{AsyncSingleJob, JobEvent};
use super::super::theme::Theme;
use super::super::widgets::chart::draw_chart;
use super::super::widgets::{Hint, fmt_coords, fmt_num};
use super::{Action, Component, Shared};
use crate::sim::{self, History, SceneResult};
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

pub struct SceneView {
    pub point: ScenePoint,
    pub state: SceneState,
}

type SceneOutput = Result<(SceneResult, History), String>;

#[derive(Default)]
pub struct SceneScreen {
    /// The scene on screen (None before the first).
    pub view: Option<SceneView>,
    job: AsyncSingleJob<(), SceneOutput>,
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
        self.view = Some(SceneView {
            point,
            state: SceneState::Running,
        });
    }

    /// Show a scene computed elsewhere (no rerun): results opened from a file, or tests that
    /// draw fixed data.
    pub fn show(&mut self, point: ScenePoint, result: SceneResult, history: History) {
        self.job.abandon();
        self.view = Some(SceneView {
            point,
            state: SceneState::Done(Box::new(result), history),
        });
    }

    pub fn is_running(&self) -> bool {
        self.job.is_busy()
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
        changed
    }
}

impl Component for SceneScreen {
    fn handle_key(&mut self, key: KeyEvent, _: &Shared) -> Action {
        match key.code {
            KeyCode::Esc | KeyCode::Backspace => Action::Show(Screen::Results),
            KeyCode::Char('r') => Action::StartRun,
            _ => Action::None,
        }
    }

    fn hints(&self, _: &Shared) -> Vec<Hint> {
        vec![("Esc", "back")]
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
        let [head, body] =
            Layout::vertical([Constraint::Length(2), Constraint::Min(1)]).areas(area);
        let mut lines = vec![Line::from(vec![
            Span::styled(view.point.group.clone(), theme.title()),
            Span::raw(format!("  {}", fmt_coords(&view.point.coords))),
        ])];
        match &view.state {
            SceneState::Running => lines.push(Line::styled("simulating…", theme.warn())),
            SceneState::Failed(e) => {
                lines.push(Line::styled(format!("failed: {e}"), theme.error()))
            }
            SceneState::Done(r, _) => {
                let mut text = format!(
                    "{}  θmax/α {}  impacts {}  engagements {}",
                    if r.overturned { "OVERTURNED" } else { "safe" },
                    fmt_num(r.peak_rotation_ratio),
                    r.counters.impacts,
                    r.counters.engagements,
                );
                // The energy residual is at the level of the solver tolerance: it changes with
                // any change to the integrator, so reproducible frames leave it out.
                if !shared.options.deterministic {
                    text.push_str(&format!("  energy residual {:.1e}", r.energy_residual));
                }
                lines.push(Line::raw(text));
            }
        }
        frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: true }), head);
        if let SceneState::Done(_, history) = &view.state {
            draw_histories(history, theme, frame, body);
        }
    }
}

/// One chart: title and (legend name, history column) of each series.
struct Panel {
    title: String,
    series: Vec<(String, &'static str)>,
}

/// The charts of a scene, from the columns its model records: rotation (and the column
/// deformation of a flexible structure), flywheel velocities, clutch forces, and every
/// energy term.
fn panels(history: &History) -> [Panel; 4] {
    let has = |c: &str| history.columns.contains(&c);
    let mut rotation = Panel {
        title: "rotation θ (rad)".into(),
        series: vec![("θ".into(), "theta")],
    };
    if has("u") {
        rotation.title = "rotation θ (rad), deformation u (m)".into();
        rotation.series.push(("u".into(), "u"));
    }
    let pair = |title: &str, a: &'static str, b: &'static str| Panel {
        title: title.into(),
        series: vec![("a".into(), a), ("b".into(), b)],
    };
    let energy = Panel {
        title: "energy (J)".into(),
        series: history
            .columns
            .iter()
            .filter_map(|c| Some((c.strip_prefix("e_")?.replace('_', " "), *c)))
            .collect(),
    };
    [
        rotation,
        pair("flywheel velocities", "flywheel_a_vel", "flywheel_b_vel"),
        pair("clutch force (N)", "clutch_force_a", "clutch_force_b"),
        energy,
    ]
}

fn draw_histories(history: &History, theme: Theme, frame: &mut Frame, area: Rect) {
    let [top, bottom] =
        Layout::vertical([Constraint::Percentage(50), Constraint::Percentage(50)]).areas(area);
    let [a, b] =
        Layout::horizontal([Constraint::Percentage(50), Constraint::Percentage(50)]).areas(top);
    let [c, d] =
        Layout::horizontal([Constraint::Percentage(50), Constraint::Percentage(50)]).areas(bottom);
    let t = history.column("t").unwrap_or_default();
    for (panel, rect) in panels(history).iter().zip([a, b, c, d]) {
        let series: Vec<(&str, Vec<f64>)> = panel
            .series
            .iter()
            .filter_map(|(name, col)| Some((name.as_str(), history.column(col)?)))
            .collect();
        draw_chart(frame, rect, theme, &panel.title, &t, &series);
    }
}
