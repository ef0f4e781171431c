//! The paper's figures from sweep results: spectra with one panel per quantity (and per facet
//! value) in `spectra.rs`, overturning maps with one panel per group (and two maps compared) in
//! `maps.rs`, and a scene's histories stacked like the paper's Figs. 8/9/14 with the energy
//! partition as a stacked area (Fig. 15) in `history.rs`. Looks (size, font, styles, ticks,
//! legend) live in `../figure.rs`, selection in `../select.rs`; what the three share is here.

mod history;
mod maps;
mod spectra;

pub use history::plot_history;
pub use maps::{plot_map_differences, plot_maps};
pub use spectra::plot_spectra;

use super::aggregate::Group;
use super::export::parameter;
use super::select::{Filter, Selector, keep_on_axis, select, split_axes};
use crate::numfmt::fmt_num;
use crate::sweep::SweepResults;

/// What to draw: which series (selectors), one panel row per value of a parameter (facet),
/// record suites as mean ± one standard deviation (band), and the most series in one panel.
#[derive(Clone, Debug, Default)]
pub struct PlotChoice {
    /// A series is drawn if it matches any selector (all if none given).
    pub select: Vec<String>,
    pub facet: Option<String>,
    pub band: bool,
    pub max_series: usize,
}

/// Most series in one panel unless `--max-series` says otherwise.
pub const MAX_SERIES: usize = 12;

/// Which of `groups` the `--select` selectors pick (the union; all without selectors), in
/// `compare`'s selector language (report/select.rs): `mechanistic`, `bare`,
/// `mechanistic(k_theta: 3.0, play: 0.005)`, `sequential(record: landers)`, and the
/// selectors' filters on the figure's own `axes` (a spectrum's x, a map's axes:
/// `mechanistic(amplitude: 1.5)`), which [`keep_on_axes`] applies to the points. A selector
/// that is malformed, or matches nothing, is an error saying what there is (never a figure
/// silently left out while the command succeeds).
pub(super) fn selection(
    choice: &PlotChoice,
    groups: &[&Group],
    axes: &[&str],
) -> crate::error::Result<(Vec<bool>, AxisFilters)> {
    if choice.select.is_empty() {
        return Ok((vec![true; groups.len()], Vec::new()));
    }
    let mut picked = vec![false; groups.len()];
    let mut on_axes = Vec::new();
    for text in &choice.select {
        let sel = Selector::parse(text).map_err(|e| crate::error::error!("--select: {e}"))?;
        let (rest, filters) = split_axes(&sel, axes);
        match select(groups, &rest) {
            Ok(found) => found.into_iter().for_each(|i| picked[i] = true),
            Err(e) => crate::error::bail!("--select {text}: {e}"),
        }
        if !filters.is_empty() {
            on_axes.push((sel.text.clone(), filters));
        }
    }
    Ok((picked, on_axes))
}

/// Each selector's text and its filters on a figure's own axes.
pub(super) type AxisFilters = Vec<(String, Vec<Filter>)>;

/// Which of an axis's `values` (study field `id`, None: an axis no selector can name) every
/// selector's filters keep; an error if they keep none.
pub(super) fn keep_on_axes(
    id: Option<&str>,
    values: &[f64],
    on_axes: &AxisFilters,
) -> crate::error::Result<Vec<bool>> {
    let mut keep = vec![true; values.len()];
    let Some(id) = id else {
        return Ok(keep);
    };
    for (text, filters) in on_axes {
        let k = keep_on_axis(text, id, values, filters)
            .map_err(|e| crate::error::error!("--select {text}: {e}"))?;
        keep.iter_mut().zip(k).for_each(|(a, b)| *a &= b);
    }
    if !keep.contains(&true) {
        crate::error::bail!("--select: the selectors keep no common `{id}`");
    }
    Ok(keep)
}

/// The items of `v` that `keep` keeps.
pub(super) fn kept<T: Clone>(v: &[T], keep: &[bool]) -> Vec<T> {
    v.iter()
        .zip(keep)
        .filter(|(_, k)| **k)
        .map(|(x, _)| x.clone())
        .collect()
}

/// A coordinate's axis label with its unit, e.g. `ωn [rad/s]`.
pub(super) fn coordinate_axis(label: &str) -> String {
    let unit = parameter(label).unit;
    if unit.is_empty() {
        label.to_string()
    } else {
        format!("{label} [{unit}]")
    }
}

pub(super) fn figure_title(results: &SweepResults) -> String {
    results.study.as_ref().map_or("results".into(), study_title)
}

/// A figure's title from its study: the description, or (without one) the study's name in
/// words (`fig12_rigid_spectra` → `fig12 rigid spectra`), never a file slug.
pub fn study_title(study: &crate::study::Study) -> String {
    let description = study.description.trim();
    if !description.is_empty() {
        return description.to_string();
    }
    study
        .name
        .split(['_', '-'])
        .filter(|w| !w.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

/// A title with the parameters every series shares said once after it.
pub fn with_shared(title: &str, shared: &str) -> String {
    if shared.is_empty() {
        title.to_string()
    } else {
        format!("{title} (every series: {shared})")
    }
}

pub(super) fn panel_letter(i: usize) -> char {
    (b'a' + (i % 26) as u8) as char
}

/// A panel's title: `(b) text` among several panels; a figure of one panel has no letter.
pub fn panel_title(i: usize, panels: usize, text: &str) -> String {
    match (panels > 1, text.is_empty()) {
        (true, true) => format!("({})", panel_letter(i)),
        (true, false) => format!("({}) {text}", panel_letter(i)),
        (false, _) => text.to_string(),
    }
}

pub(super) fn device_name(g: &Group) -> String {
    match g.device {
        crate::study::DeviceKind::None => "bare".into(),
        k => k.name().into(),
    }
}

pub(super) fn range_of(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    if hi > lo {
        (lo, hi)
    } else {
        (lo - 0.5, hi + 0.5)
    }
}

/// A selector naming a group's device and its first varying parameter.
pub(super) fn example_of(g: &Group) -> String {
    let device = device_name(g);
    match g.settings.iter().find(|s| s.varies && s.id != "record") {
        Some(s) => format!("{device}({}: {})", s.id, s.text),
        None => device,
    }
}

/// A readable label for a scene, for history plots, `check` and the workbench's Scene screen:
/// its index (what `plot --scene` takes), then [`scene_label`].
pub fn scene_title(point: &crate::study::ScenePoint) -> String {
    format!("scene {}: {}", point.index, scene_label(point))
}

/// A scene's group, then the coordinates the group does not already name (the axes: a varying
/// parameter that is no axis is in both), each parameter once.
pub fn scene_label(point: &crate::study::ScenePoint) -> String {
    let named = |n: &str| {
        let prefix = format!("{n}=");
        point
            .group
            .split_whitespace()
            .any(|w| w.starts_with(&prefix))
    };
    let mut text = point.group.clone();
    for (n, v) in point.coords.iter().filter(|(n, _)| !named(n)) {
        text.push_str(&format!(", {n} = {}", fmt_num(*v)));
    }
    text
}
