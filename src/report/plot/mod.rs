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
use super::select::{Selector, select};
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
/// `mechanistic(k_theta: 3.0, play: 0.005)`, `sequential(record: landers)`. A selector that
/// is malformed is an error; one that matches nothing says what there is and picks nothing.
pub(super) fn selection(choice: &PlotChoice, groups: &[&Group]) -> crate::error::Result<Vec<bool>> {
    if choice.select.is_empty() {
        return Ok(vec![true; groups.len()]);
    }
    let mut picked = vec![false; groups.len()];
    for text in &choice.select {
        let sel = Selector::parse(text).map_err(|e| crate::error::error!("--select: {e}"))?;
        match select(groups, &sel) {
            Ok(found) => found.into_iter().for_each(|i| picked[i] = true),
            Err(e) => eprintln!("--select {text}: {e}"),
        }
    }
    Ok(picked)
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
    results.study.as_ref().map_or("results".into(), |s| {
        if s.description.is_empty() {
            s.name.clone()
        } else {
            s.description.clone()
        }
    })
}

pub(super) fn panel_letter(i: usize) -> char {
    (b'a' + (i % 26) as u8) as char
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
