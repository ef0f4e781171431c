//! The Results screen: spectra, overturning maps, and a comparison of two variants, over the
//! results the app holds. Each view owns its cursor (`spectra`, `maps`, `compare`); the
//! spectra and the comparison share the quantity and the position along the axis.

mod compare;
pub mod design;
mod fragility;
mod maps;
mod risk;
mod spectra;

pub use compare::CompareView;
pub use design::DesignView;
pub use fragility::FragilityView;
pub use maps::MapsView;
pub use spectra::SpectraView;

use super::super::edit::LineEdit;
use super::super::theme::Theme;
use super::super::widgets::Hint;
use super::prompt::Prompt;
use super::{Action, Command, Component, Shared, command};
use crate::report::{self, OverturningMap, PointState, Quantity, Spectrum};
use crate::sim::SceneResult;
use crate::sim::check::{CheckCsvRow, Reproducibility};
use crate::study::ScenePoint;
use crate::sweep::SweepResults;
use crossterm::event::{KeyCode, KeyEvent};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

pub use super::super::widgets::strip::Mark;

/// Results and what is aggregated from them once, when they arrive.
pub struct Results {
    /// The results as computed (what `w` writes).
    pub results: SweepResults,
    /// The results plus a placeholder for every point of the study not run: what the spectra
    /// and maps are aggregated from (their outcome indices point here).
    padded: SweepResults,
    /// Per spectrum (as in `spectra`), what each of its points stands for.
    pub spectrum_marks: Vec<Vec<Mark>>,
    /// Per map (as in `maps`), [iy][ix] what each cell stands for.
    pub map_marks: Vec<Vec<Vec<Mark>>>,
    pub spectra: Vec<Spectrum>,
    pub maps: Vec<OverturningMap>,
    /// The quantities that have spectra, in order of first appearance.
    pub quantities: Vec<Quantity>,
    /// The sweep was cancelled: the results are partial.
    pub cancelled: bool,
    /// Scene index → its check, from a `check.csv` (`rocklab check`) beside the results.
    pub checks: std::collections::HashMap<usize, SceneCheck>,
    /// The fragility report (fragility.json) beside the results of a fragility study.
    pub fragility: Option<report::fragility::FragilityReport>,
    /// The seismic risk (risk.json) beside a fragility study's results, if computed.
    pub risk: Option<crate::risk::RiskReport>,
    /// A design study's answer (the search replayed on the scenes); empty for other studies.
    pub design: Vec<crate::sweep::design::DesignRow>,
}

/// One scene's lines of `check.csv`, as the readout shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneCheck {
    pub verdict: Reproducibility,
    /// The largest κ of the judged peaks.
    pub condition: f64,
}

impl Results {
    pub fn new(results: SweepResults, cancelled: bool) -> Self {
        // Aggregate over the study's every point, the unrun ones as placeholders, so the axes
        // keep the study's full range while a partial run is shown.
        // An adaptive map's inferred cells are no scenes, and no gaps either: the maps show
        // their verdicts (dim), the spectra leave them out.
        let ran: std::collections::HashSet<usize> = (results.outcomes.iter())
            .map(|o| o.point.index)
            .chain(results.inferred.iter().map(|c| c.index))
            .collect();
        let mut padded = results.clone();
        padded.outcomes.extend(
            results
                .study
                .as_ref()
                .and_then(|s| s.expand().ok())
                .unwrap_or_default()
                .into_iter()
                .filter(|p| {
                    !ran.contains(&p.index) && crate::sweep::in_shard(p.index, results.shard)
                })
                // A placeholder: its state is NotRun (below), never this text; never saved.
                .map(|point| crate::sweep::SceneOutcome {
                    point,
                    result: Err("not run".into()),
                }),
        );
        padded.outcomes.sort_by_key(|o| o.point.index);
        // What became of each padded outcome: the placeholders are the ones that did not run.
        let states: Vec<PointState> = (padded.outcomes.iter())
            .map(|o| match ran.contains(&o.point.index) {
                true => PointState::of(o),
                false => PointState::NotRun,
            })
            .collect();
        let mut spectra = report::spectra(&padded);
        // The spectra (and the comparison made of them) see a placeholder as not run, not
        // as failed.
        for s in &mut spectra {
            for (state, i) in s.states.iter_mut().zip(&s.outcomes) {
                *state = states[*i];
            }
        }
        let maps = report::maps(&padded);
        let mark =
            |outcome: Option<usize>, has_value: bool| match outcome.and_then(|i| states.get(i)) {
                _ if has_value => Mark::Value,
                Some(PointState::NotRun) | None => Mark::NotRun,
                Some(PointState::Failed) => Mark::Failed,
                Some(PointState::Survived | PointState::Overturned) => Mark::Overturned,
            };
        let spectrum_marks = spectra
            .iter()
            .map(|s| {
                (s.outcomes.iter().zip(&s.ys))
                    .map(|(i, y)| mark(Some(*i), y.is_some()))
                    .collect()
            })
            .collect();
        let map_marks = maps
            .iter()
            .map(|m| {
                (m.outcomes.iter().zip(&m.cells))
                    .map(|(row, cells)| {
                        (row.iter().zip(cells))
                            .map(|(i, cell)| match cell {
                                Some(true) => Mark::Overturned,
                                Some(false) => Mark::Value,
                                None => mark(*i, false),
                            })
                            .collect()
                    })
                    .collect()
            })
            .collect();
        let mut quantities: Vec<Quantity> = Vec::new();
        for s in &spectra {
            if !quantities.contains(&s.quantity) {
                quantities.push(s.quantity);
            }
        }
        Results {
            design: report::design::design_rows(&results).unwrap_or_default(),
            results,
            padded,
            spectrum_marks,
            map_marks,
            spectra,
            maps,
            quantities,
            cancelled,
            checks: Default::default(),
            fragility: None,
            risk: None,
        }
    }

    /// Read `dir/fragility.json` if there is one: whether there was, or why it could not be
    /// read.
    pub fn load_fragility(&mut self, dir: &std::path::Path) -> Result<bool, String> {
        let path = dir.join(report::fragility::FRAGILITY_JSON);
        if !path.exists() {
            return Ok(false);
        }
        let report = report::fragility::read_fragility_json(&path).map_err(|e| format!("{e:#}"))?;
        self.fragility = Some(report);
        self.risk = report::risk::read_risk(dir);
        Ok(true)
    }

    /// Read `dir/check.csv` if there is one: the number of scenes it checks, or why it could
    /// not be read.
    pub fn load_checks(&mut self, dir: &std::path::Path) -> Result<usize, String> {
        let path = dir.join("check.csv");
        if !path.exists() {
            return Ok(0);
        }
        let fail = |e: csv::Error| format!("{}: {e}", path.display());
        let mut reader = csv::Reader::from_path(&path).map_err(fail)?;
        let mut checks = std::collections::HashMap::<usize, SceneCheck>::new();
        for row in reader.deserialize::<CheckCsvRow>() {
            let row = row.map_err(fail)?;
            let entry = checks.entry(row.scene).or_insert(SceneCheck {
                verdict: row.verdict,
                condition: 0.0,
            });
            if !row.negligible {
                entry.condition = entry.condition.max(row.condition);
            }
        }
        self.checks = checks;
        Ok(self.checks.len())
    }

    /// The scene of a spectrum's point `x` (none for a point of no scene).
    pub fn scene_at(&self, spectrum: &Spectrum, x: usize) -> Option<usize> {
        let outcome = spectrum.outcomes.get(x)?;
        Some(self.padded.outcomes.get(*outcome)?.point.index)
    }

    /// The result of the scene behind a map cell, if it ran and finished.
    pub fn map_result(&self, map: &OverturningMap, ix: usize, iy: usize) -> Option<&SceneResult> {
        let i = (*map.outcomes.get(iy)?.get(ix)?)?;
        self.padded.outcomes.get(i)?.result.as_ref().ok()
    }

    /// The marks of one of `spectra` (none if it is not one of them).
    pub fn marks_of(&self, spectrum: &Spectrum) -> &[Mark] {
        self.spectra
            .iter()
            .position(|s| std::ptr::eq(s, spectrum))
            .and_then(|i| self.spectrum_marks.get(i))
            .map_or(&[], Vec::as_slice)
    }
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ResultsTab {
    #[default]
    Spectra,
    Maps,
    Compare,
    Fragility,
    Design,
}

#[derive(Default)]
pub struct ResultsScreen {
    pub tab: ResultsTab,
    pub spectra: SpectraView,
    pub maps: MapsView,
    pub compare: CompareView,
    pub fragility: FragilityView,
    pub design: DesignView,
}

impl ResultsScreen {
    /// Fresh cursors for new results: a design study's answer first, else spectra (maps if
    /// there are no spectra), and the comparison on its default pair.
    pub fn reset(&mut self, data: &Results) {
        *self = ResultsScreen::default();
        if data.spectra.is_empty() && !data.maps.is_empty() {
            self.tab = ResultsTab::Maps;
        }
        if !data.design.is_empty() {
            self.tab = ResultsTab::Design;
        }
        self.compare = CompareView::default_pair(&self.all_rows(data));
    }

    pub fn current_quantity(&self, data: &Results) -> Option<Quantity> {
        data.quantities.get(self.spectra.quantity).copied()
    }

    /// The spectra of the current quantity, one per variant (and axis).
    pub fn all_rows<'a>(&self, data: &'a Results) -> Vec<&'a Spectrum> {
        let q = self.current_quantity(data);
        data.spectra
            .iter()
            .filter(|s| Some(s.quantity) == q)
            .collect()
    }

    /// The spectra rows shown: those of the current quantity that the filter (`f`) picks.
    pub fn rows<'a>(&self, data: &'a Results) -> Vec<&'a Spectrum> {
        let all = self.all_rows(data);
        match &self.spectra.filter {
            None => all,
            Some(sel) => {
                let groups: Vec<&report::Group> = all.iter().map(|s| &s.group).collect();
                report::select::select(&groups, sel)
                    .map(|found| found.into_iter().map(|i| all[i]).collect())
                    .unwrap_or_default()
            }
        }
    }

    /// The scene behind the point under the cursor (in the comparison: B's).
    pub fn point_at_cursor<'a>(&self, data: &'a Results) -> Option<&'a ScenePoint> {
        // Spectra and maps carry the index of each point's outcome: no label matching.
        let outcome = match self.tab {
            ResultsTab::Spectra => *self
                .rows(data)
                .get(self.spectra.row)?
                .outcomes
                .get(self.spectra.x)?,
            ResultsTab::Compare => {
                // B's point of the selected pair, found by its group (no label matching).
                let pairs = self
                    .compare
                    .pairs(data, self.current_quantity(data)?)
                    .ok()?;
                let pair = pairs.get(self.compare.pair.min(pairs.len().saturating_sub(1)))?;
                let x = pair.points.get(self.spectra.x)?.x;
                let b = self
                    .all_rows(data)
                    .into_iter()
                    .find(|s| s.group == pair.b_group)?;
                *b.outcomes.get(b.xs.iter().position(|v| *v == x)?)?
            }
            ResultsTab::Maps => {
                let m = data.maps.get(self.maps.map)?;
                (*m.outcomes.get(self.maps.cell.1)?.get(self.maps.cell.0)?)?
            }
            // A fragility curve or a design point is many scenes: none is under the cursor.
            ResultsTab::Fragility | ResultsTab::Design => return None,
        };
        data.padded.outcomes.get(outcome).map(|o| &o.point)
    }

    /// The tabs line: key and name of every view (`named` false: names of the open one only).
    fn tab_spans(&self, theme: Theme, named: bool) -> Vec<Span<'static>> {
        [
            (ResultsTab::Spectra, "s", "spectra"),
            (ResultsTab::Maps, "m", "maps"),
            (ResultsTab::Compare, "c", "compare"),
            (ResultsTab::Fragility, "p", "fragility"),
            (ResultsTab::Design, "g", "design"),
        ]
        .into_iter()
        .map(|(tab, key, name)| match self.tab == tab {
            true => Span::styled(format!(" {key} {name} "), theme.tab_active()),
            false if named => Span::styled(format!(" {key} {name} "), theme.base()),
            false => Span::styled(format!(" {key} "), theme.base()),
        })
        .collect()
    }

    /// `[ ] quantity (i/n)`: the header of the spectra and the comparison.
    fn quantity_line(&self, data: &Results, theme: Theme) -> Line<'static> {
        let name = self
            .current_quantity(data)
            .map_or("no spectra", Quantity::label);
        Line::from(vec![
            Span::styled("[ ] ", theme.key()),
            Span::styled(name.to_string(), theme.title()),
            Span::styled(
                format!(
                    "  ({}/{})",
                    self.spectra.quantity + 1,
                    data.quantities.len().max(1)
                ),
                theme.dim(),
            ),
        ])
    }
}

impl Component for ResultsScreen {
    fn commands(&self) -> &'static [Command] {
        const COMMANDS: &[Command] = &[
            command("s m c p g", "spectra / maps / compare / fragility / design"),
            command(
                "←→ ↑↓",
                "cursor along the axis / variant, cell or design point",
            ),
            command("[ ]  f", "prev/next quantity, map or state; f filter rows"),
            command("a b x", "compare: pick A / B (device, values), swap"),
            command("o y d", "compare: sort pairs, one y scale or two, maps"),
            command(
                "Enter  w",
                "open the scene under the cursor / write results",
            ),
        ];
        COMMANDS
    }

    fn handle_key(&mut self, key: KeyEvent, shared: &Shared) -> Action {
        let Some(data) = &shared.results else {
            return match key.code {
                KeyCode::Char('r') => Action::StartRun,
                _ => Action::None,
            };
        };
        // The filter line and the pair picker take every key while open.
        if self.spectra.filter_edit.is_some() {
            let groups: Vec<&report::Group> =
                self.all_rows(data).iter().map(|s| &s.group).collect();
            self.spectra.filter_key(key, &groups);
            let rows = self.rows(data);
            self.spectra.clamp(rows.len(), spectra::axis_len(&rows));
            return Action::None;
        }
        if self.tab == ResultsTab::Compare && self.compare.picking.is_some() {
            let groups: Vec<&report::Group> =
                self.all_rows(data).iter().map(|s| &s.group).collect();
            self.compare.handle_key(key, &groups, 0);
            return Action::None;
        }
        match key.code {
            KeyCode::Char('s') => self.tab = ResultsTab::Spectra,
            KeyCode::Char('m') => self.tab = ResultsTab::Maps,
            KeyCode::Char('c') => self.tab = ResultsTab::Compare,
            KeyCode::Char('p') => self.tab = ResultsTab::Fragility,
            KeyCode::Char('g') => self.tab = ResultsTab::Design,
            KeyCode::Char('r') => return Action::StartRun,
            KeyCode::Char('w') => {
                let name = data
                    .results
                    .study
                    .as_ref()
                    .map_or("study", |s| s.name.as_str());
                let default = format!("out/{name}/results.json");
                return Action::Prompt(Prompt::SaveResults(LineEdit::new(default)));
            }
            KeyCode::Enter => {
                return match self.point_at_cursor(data) {
                    Some(point) => Action::OpenScene(Box::new(point.clone())),
                    None => Action::Complain("no scene under the cursor".into()),
                };
            }
            _ => {}
        }
        match self.tab {
            ResultsTab::Spectra => {
                if self.spectra.filter_start(key) {
                    return Action::None;
                }
                let rows = self.rows(data);
                let (nrows, nx) = (rows.len(), spectra::axis_len(&rows));
                self.spectra
                    .handle_key(key, nrows, nx, data.quantities.len());
                // The quantity may have changed: keep every cursor on a row.
                let rows = self.rows(data);
                self.spectra.clamp(rows.len(), spectra::axis_len(&rows));
            }
            ResultsTab::Compare => {
                let groups: Vec<&report::Group> =
                    self.all_rows(data).iter().map(|s| &s.group).collect();
                let npairs = self
                    .current_quantity(data)
                    .and_then(|q| self.compare.pairs(data, q).ok())
                    .map_or(0, |p| p.len());
                let npairs = if self.compare.show_map {
                    self.compare.map_pairs(data).map_or(0, |m| m.len())
                } else {
                    npairs
                };
                if !self.compare.handle_key(key, &groups, npairs) {
                    // ←→ along the axis, [ ] quantity: the spectra's cursor.
                    let rows = self.all_rows(data);
                    let nx = spectra::axis_len(&rows);
                    let row = self.spectra.row;
                    self.spectra
                        .handle_key(key, rows.len(), nx, data.quantities.len());
                    self.spectra.row = row;
                    let rows = self.rows(data);
                    self.spectra.clamp(rows.len(), spectra::axis_len(&rows));
                }
            }
            ResultsTab::Maps => self.maps.handle_key(key, data),
            ResultsTab::Fragility => self.fragility.handle_key(key, data.fragility.as_ref()),
            ResultsTab::Design => self.design.handle_key(key, data.design.len()),
        }
        Action::None
    }

    fn hints(&self, _: &Shared) -> Vec<Hint> {
        let mut hints = vec![
            ("s/m/c/p/g", "view"),
            ("←→↑↓", "cursor"),
            ("[ ]", "quantity"),
        ];
        match self.tab {
            ResultsTab::Spectra => hints.push(("f", "filter")),
            ResultsTab::Compare => {
                hints = vec![
                    ("a/b", "pick A/B"),
                    ("↑↓", "pair"),
                    ("o", "sort"),
                    ("y", "scale"),
                    ("d", "maps"),
                    ("x", "swap"),
                    ("←→", "cursor"),
                    ("[ ]", "quantity"),
                ]
            }
            ResultsTab::Maps => {}
            ResultsTab::Fragility => {
                hints = vec![
                    ("s/m/c/p/g", "view"),
                    ("↑↓", "variant"),
                    ("←→", "IM"),
                    ("[ ]", "damage state"),
                ]
            }
            ResultsTab::Design => hints = vec![("s/m/c/p/g", "view"), ("↑↓", "design point")],
        }
        if !matches!(self.tab, ResultsTab::Fragility | ResultsTab::Design) {
            hints.push(("Enter", "scene"));
        }
        hints.push(("w", "write results"));
        hints
    }

    fn captures_keys(&self) -> bool {
        self.spectra.filter_edit.is_some()
            || (self.tab == ResultsTab::Compare && self.compare.picking.is_some())
    }

    fn draw(&self, shared: &Shared, theme: Theme, frame: &mut Frame, area: Rect) {
        let Some(data) = &shared.results else {
            frame.render_widget(
                Paragraph::new("No results yet. Press r to run the study.")
                    .wrap(Wrap { trim: true }),
                area,
            );
            return;
        };
        let [tabs, body] =
            Layout::vertical([Constraint::Length(1), Constraint::Min(1)]).areas(area);
        let mut notes = Vec::new();
        if data.cancelled {
            notes.push(Span::styled("  partial: sweep cancelled", theme.warn()));
        }
        if data
            .results
            .study
            .as_ref()
            .is_some_and(|s| *s != shared.study)
        {
            notes.push(Span::styled(
                "  study edited since this run (r reruns)",
                theme.warn(),
            ));
        }
        let mut spans = self.tab_spans(theme, true);
        let width = |spans: &[Span]| spans.iter().map(|s| s.width()).sum::<usize>();
        // Too narrow for every tab's name and the notes: only the open tab keeps its name.
        if width(&spans) + width(&notes) > tabs.width as usize {
            spans = self.tab_spans(theme, false);
        }
        spans.extend(notes);
        frame.render_widget(Paragraph::new(Line::from(spans)), tabs);
        match self.tab {
            ResultsTab::Spectra => spectra::draw(self, data, theme, frame, body),
            ResultsTab::Maps => self.maps.draw(data, theme, frame, body),
            ResultsTab::Compare => compare::draw(self, data, theme, frame, body),
            ResultsTab::Fragility => {
                // With a risk.json: two lines of risk for the selected curve below the view.
                let body = match (&data.risk, &data.fragility) {
                    (Some(risk), Some(f)) => {
                        let [view, lines] =
                            Layout::vertical([Constraint::Min(8), Constraint::Length(2)])
                                .areas(body);
                        risk::draw(risk, self.fragility.selected(f), theme, frame, lines);
                        view
                    }
                    _ => body,
                };
                self.fragility
                    .draw(data.fragility.as_ref(), theme, frame, body)
            }
            ResultsTab::Design => self.design.draw(
                data.results.study.as_ref(),
                &data.design,
                theme,
                frame,
                body,
            ),
        }
    }
}

/// Width of the row names left of the bars: the longest name, within limits.
fn label_width(names: &[String], area: Rect) -> usize {
    let longest = names.iter().map(|s| s.chars().count()).max().unwrap_or(0);
    // Up to half the width: rows a cut name would make look alike (a clutch grid at 80
    // columns) matter more than how many points the strip shows at once; it scrolls.
    longest.clamp(8, (area.width as usize / 2).max(8))
}
