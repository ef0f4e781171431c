//! Aggregation of sweep results: spectra, overturning maps, comparisons, sparklines. Pure
//! functions of the results.

use crate::study::{Axis, DeviceKind, Layout, MapAxes, Part, Quantity};
use crate::sweep::{SceneOutcome, SweepResults};
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// One parameter value that defines a group, by its study field name.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Setting {
    /// Study field name: `k_theta`, `play`, `omega_n`, `amplitude`, `record`, …
    pub id: String,
    pub part: Part,
    /// Paper notation (`kθ`, `up`, `ωn`).
    pub label: String,
    /// The exact value (a record's position in the study's `names`).
    pub value: f64,
    /// The record's name, for the `record` setting.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// The value as labels show it (the record's name, or the number with as many digits as
    /// tell the study's values of this parameter apart): for filters and pickers.
    pub text: String,
    /// Whether the study gives this parameter more than one value.
    pub varies: bool,
}

/// What a spectrum or map is of, as data: the device variant and every parameter value that
/// is fixed along it (structure, device with its clutch grid values, excitation and record).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Group {
    pub device: DeviceKind,
    /// Position of the variant in the study's `devices`.
    pub variant: usize,
    /// The variant's label (its `label: "…"`, or its kind; `bare` for none).
    pub device_label: String,
    pub settings: Vec<Setting>,
}

impl Group {
    pub fn setting(&self, id: &str) -> Option<&Setting> {
        self.settings.iter().find(|s| s.id == id)
    }

    /// The record's name, for record studies.
    pub fn record(&self) -> Option<&str> {
        self.setting("record").and_then(|s| s.name.as_deref())
    }

    /// Whether `self` and `other` agree on `setting` (both lack it, or both have the same).
    pub fn same(&self, other: &Group, id: &str) -> bool {
        match (self.setting(id), other.setting(id)) {
            (Some(a), Some(b)) => a.value == b.value && a.name == b.name,
            (None, None) => true,
            _ => false,
        }
    }
}

/// What became of the scene behind a spectrum or map point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PointState {
    /// Ran and did not overturn: the value is a response.
    Survived,
    Overturned,
    /// The scene failed (its reason is in the outcome).
    Failed,
    /// Not in the results (cancelled, another shard's).
    NotRun,
}

impl PointState {
    pub fn of(outcome: &SceneOutcome) -> PointState {
        match &outcome.result {
            Ok(r) if r.overturned => PointState::Overturned,
            Ok(_) => PointState::Survived,
            Err(_) => PointState::Failed,
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Spectrum {
    pub quantity: Quantity,
    /// Display label, derived from `group` (never parse it).
    pub label: String,
    pub group: Group,
    pub axis: String,
    pub xs: Vec<f64>,
    /// None: overturned or failed (`states` says which).
    pub ys: Vec<Option<f64>>,
    pub states: Vec<PointState>,
    /// Index in `SweepResults::outcomes` of each point.
    pub outcomes: Vec<usize>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OverturningMap {
    /// Display label, derived from `group` (never parse it).
    pub label: String,
    pub group: Group,
    pub x_axis: String,
    pub y_axis: String,
    pub xs: Vec<f64>,
    pub ys: Vec<f64>,
    /// [iy][ix]: Some(true) overturned, Some(false) survived, None failed or not run.
    pub cells: Vec<Vec<Option<bool>>>,
    /// [iy][ix]: index in `SweepResults::outcomes` of the cell's scene, if it ran. A cell
    /// with a verdict and no outcome was inferred by an adaptive map ([`Self::inferred`]).
    pub outcomes: Vec<Vec<Option<usize>>>,
}

impl OverturningMap {
    /// Whether cell (ix, iy) holds a verdict that an adaptive map inferred without running it.
    pub fn inferred(&self, ix: usize, iy: usize) -> bool {
        fn at<T: Copy>(grid: &[Vec<Option<T>>], ix: usize, iy: usize) -> Option<T> {
            grid.get(iy).and_then(|r| r.get(ix)).copied().flatten()
        }
        at(&self.cells, ix, iy).is_some() && at(&self.outcomes, ix, iy).is_none()
    }

    /// The overturning boundary: between every two neighbouring cells (along a row or a
    /// column) where one overturned and the other survived, the midpoint of their grid
    /// values, as (x, y, along) with `along` the axis the pair lies on ('x' or 'y').
    pub fn boundary(&self) -> Vec<(f64, f64, char)> {
        let mut out = Vec::new();
        for (iy, row) in self.cells.iter().enumerate() {
            for ix in 0..row.len() {
                let here = row[ix];
                if let (Some(a), Some(Some(b))) = (here, row.get(ix + 1))
                    && a != *b
                {
                    out.push(((self.xs[ix] + self.xs[ix + 1]) / 2.0, self.ys[iy], 'x'));
                }
                let above = self.cells.get(iy + 1).and_then(|r| r.get(ix)).copied();
                if let (Some(a), Some(Some(b))) = (here, above)
                    && a != b
                {
                    out.push((self.xs[ix], (self.ys[iy] + self.ys[iy + 1]) / 2.0, 'y'));
                }
            }
        }
        out
    }
}

/// The study's quantities (or the peak rotation ratio for ad-hoc point lists).
pub fn quantities(results: &SweepResults) -> Vec<Quantity> {
    results
        .study
        .as_ref()
        .map(|s| s.quantities.clone())
        .unwrap_or_else(|| vec![Quantity::PeakRotationRatio])
}

/// How outcomes are grouped: by the study's layout (exact parameter values, from each
/// point's expansion index), or, for ad-hoc point lists without a study, by label.
struct Grouping {
    layout: Option<(Layout, Option<MapAxes>, Axis)>,
}

/// A group's identity: the variant and the value position of every parameter not on a
/// free axis (free ones are `usize::MAX`), or the label when there is no layout.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum GroupKey {
    Grid(usize, Vec<usize>),
    Label(String),
}

impl Grouping {
    fn new(results: &SweepResults) -> Grouping {
        Grouping {
            layout: results
                .study
                .as_ref()
                .and_then(|s| Some((s.layout().ok()?, s.map, s.spectrum))),
        }
    }

    /// The variant and value positions of a point, if the layout knows it (and it agrees
    /// with the point's scene, as a check that the results belong to this study).
    fn locate(&self, outcome: &SceneOutcome) -> Option<(usize, Vec<usize>)> {
        let (layout, ..) = self.layout.as_ref()?;
        let (v, at) = layout.locate(outcome.point.index)?;
        (layout.variants[v].kind.name() == outcome.point.scene.device.name()).then_some((v, at))
    }

    fn key(&self, outcome: &SceneOutcome, free: &[Axis]) -> GroupKey {
        match self.locate(outcome) {
            Some((v, at)) => self.grid_key(v, at, free),
            None => GroupKey::Label(outcome.point.group.clone()),
        }
    }

    /// The group of variant `v` at value positions `at`, with the free axes blanked.
    fn grid_key(&self, v: usize, mut at: Vec<usize>, free: &[Axis]) -> GroupKey {
        if let Some((layout, ..)) = &self.layout {
            for (p, i) in layout.variants[v].params.iter().zip(at.iter_mut()) {
                if p.axis.is_some_and(|a| free.contains(&a)) {
                    *i = usize::MAX;
                }
            }
        }
        GroupKey::Grid(v, at)
    }

    /// Label and structured group of a key.
    fn describe(&self, key: &GroupKey, outcome: &SceneOutcome, free: &[Axis]) -> (String, Group) {
        match (key, &self.layout) {
            (GroupKey::Grid(v, at), Some((layout, ..))) => {
                let variant = &layout.variants[*v];
                let settings = variant
                    .params
                    .iter()
                    .zip(at)
                    .filter(|(_, i)| **i != usize::MAX)
                    .map(|(p, &i)| Setting {
                        id: p.id.to_string(),
                        part: p.part,
                        label: p.label.clone(),
                        value: p.values[i],
                        name: p.names.as_ref().map(|n| n[i].clone()),
                        text: layout.value_text(p, i),
                        varies: p.varies(),
                    })
                    .collect();
                let full_at = self.locate(outcome).map(|(_, a)| a).unwrap_or_default();
                (
                    layout.label(*v, &full_at, free),
                    Group {
                        device: variant.kind,
                        variant: *v,
                        device_label: variant.label.clone(),
                        settings,
                    },
                )
            }
            _ => (
                outcome.point.group.clone(),
                Group {
                    device: DeviceKind::from_name(outcome.point.scene.device.name())
                        .unwrap_or(DeviceKind::None),
                    variant: 0,
                    device_label: outcome.point.scene.device.name().to_string(),
                    settings: vec![],
                },
            ),
        }
    }
}

/// One spectrum per group and quantity over the study's spectrum axis (the first coordinate
/// of the points), sorted by x. A group holds every point with the same exact values of all
/// other parameters (a map's other axis included), in order of first appearance.
pub fn spectra(results: &SweepResults) -> Vec<Spectrum> {
    let grouping = Grouping::new(results);
    let free: Vec<Axis> = grouping
        .layout
        .as_ref()
        .map(|(_, _, s)| vec![*s])
        .unwrap_or_default();
    // (key, axis, points (x, outcome index)) in order of first appearance.
    type Series = (GroupKey, String, Vec<(f64, usize)>);
    let mut series: Vec<Series> = Vec::new();
    let mut index: HashMap<GroupKey, usize> = HashMap::new();
    for (i, o) in results.outcomes.iter().enumerate() {
        let Some((axis, x)) = o.point.coords.first() else {
            continue;
        };
        let key = grouping.key(o, &free);
        match index.get(&key) {
            Some(&s) => series[s].2.push((*x, i)),
            None => {
                index.insert(key.clone(), series.len());
                series.push((key, axis.clone(), vec![(*x, i)]));
            }
        }
    }
    let described: Vec<(String, Group)> = series
        .iter()
        .map(|(key, _, pts)| grouping.describe(key, &results.outcomes[pts[0].1], &free))
        .collect();
    let mut out = Vec::new();
    for q in quantities(results) {
        for ((_, axis, pts), (label, group)) in series.iter().zip(&described) {
            let mut pts = pts.clone();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            let outcome = |i: usize| &results.outcomes[i];
            out.push(Spectrum {
                quantity: q,
                label: label.clone(),
                group: group.clone(),
                axis: axis.clone(),
                xs: pts.iter().map(|(x, _)| *x).collect(),
                ys: pts
                    .iter()
                    .map(|(_, i)| outcome(*i).result.as_ref().ok().and_then(|r| q.of(r)))
                    .collect(),
                states: pts
                    .iter()
                    .map(|(_, i)| PointState::of(outcome(*i)))
                    .collect(),
                outcomes: pts.iter().map(|(_, i)| *i).collect(),
            });
        }
    }
    out
}

/// One overturning map per group (every parameter but the map's two axes), if the study asks
/// for one. The axes hold every value of the study, so a partial run shows its gaps.
pub fn maps(results: &SweepResults) -> Vec<OverturningMap> {
    let grouping = Grouping::new(results);
    let Some((layout, Some(axes), _)) = &grouping.layout else {
        return vec![];
    };
    let study = results.study.as_ref().expect("a layout comes from a study");
    let (xl, yl) = (study.axis_label(axes.x), study.axis_label(axes.y));
    let free = [axes.x, axes.y];
    let mut keys: Vec<(GroupKey, usize)> = Vec::new();
    let mut index: HashMap<GroupKey, usize> = HashMap::new();
    let mut members: Vec<Vec<usize>> = Vec::new();
    for (i, o) in results.outcomes.iter().enumerate() {
        let key = grouping.key(o, &free);
        if !matches!(key, GroupKey::Grid(..)) {
            continue;
        }
        match index.get(&key) {
            Some(&g) => members[g].push(i),
            None => {
                index.insert(key.clone(), keys.len());
                keys.push((key, i));
                members.push(vec![i]);
            }
        }
    }
    // Cells an adaptive map inferred, by group: (value positions, overturned).
    let mut inferred: HashMap<GroupKey, Vec<(Vec<usize>, bool)>> = HashMap::new();
    for c in &results.inferred {
        if let Some((v, at)) = layout.locate(c.index) {
            let key = grouping.grid_key(v, at.clone(), &free);
            inferred.entry(key).or_default().push((at, c.overturned));
        }
    }
    keys.into_iter()
        .zip(members)
        .filter_map(|((key, first), members)| {
            let GroupKey::Grid(v, _) = &key else {
                return None;
            };
            let params = &layout.variants[*v].params;
            let axis_values = |axis: Axis| -> Option<(usize, Vec<f64>)> {
                let i = params.iter().position(|p| p.axis == Some(axis))?;
                let mut vs = params[i].values.clone();
                vs.sort_by(f64::total_cmp);
                Some((i, vs))
            };
            let ((ixp, xs), (iyp, ys)) = (axis_values(axes.x)?, axis_values(axes.y)?);
            let mut cells = vec![vec![None; xs.len()]; ys.len()];
            let mut outcomes = vec![vec![None; xs.len()]; ys.len()];
            for i in members {
                let o = &results.outcomes[i];
                let Some((_, at)) = grouping.locate(o) else {
                    continue;
                };
                let (x, y) = (params[ixp].values[at[ixp]], params[iyp].values[at[iyp]]);
                let (ix, iy) = (sorted_position(&xs, x), sorted_position(&ys, y));
                if let (Some(ix), Some(iy)) = (ix, iy) {
                    cells[iy][ix] = o.result.as_ref().ok().map(|r| r.overturned);
                    outcomes[iy][ix] = Some(i);
                }
            }
            for (at, overturned) in inferred.get(&key).into_iter().flatten() {
                let (x, y) = (params[ixp].values[at[ixp]], params[iyp].values[at[iyp]]);
                let (ix, iy) = (sorted_position(&xs, x), sorted_position(&ys, y));
                if let (Some(ix), Some(iy)) = (ix, iy)
                    && outcomes[iy][ix].is_none()
                {
                    cells[iy][ix] = Some(*overturned);
                }
            }
            let (label, group) = grouping.describe(&key, &results.outcomes[first], &free);
            Some(OverturningMap {
                label,
                group,
                x_axis: xl.clone(),
                y_axis: yl.clone(),
                xs,
                ys,
                cells,
                outcomes,
            })
        })
        .collect()
}

/// Ratio b/a per point of two spectra over the same axis (matched by x); None where either is
/// missing or a is zero.
pub fn compare(a: &Spectrum, b: &Spectrum) -> Vec<Option<f64>> {
    a.xs.iter()
        .zip(&a.ys)
        .map(|(x, ya)| {
            let i = b.xs.iter().position(|xb| xb == x)?;
            match (ya, b.ys[i]) {
                (Some(ya), Some(yb)) if *ya != 0.0 => Some(yb / ya),
                _ => None,
            }
        })
        .collect()
}

/// Unicode sparkline from the smallest (▁) to the largest (█) value; gaps (None) are spaces.
pub fn sparkline(values: &[Option<f64>]) -> String {
    const BARS: [char; 8] = ['▁', '▂', '▃', '▄', '▅', '▆', '▇', '█'];
    let finite = values.iter().flatten().filter(|v| v.is_finite());
    let max = finite.clone().fold(f64::NEG_INFINITY, |m, v| m.max(*v));
    let min = finite.fold(f64::INFINITY, |m, v| m.min(*v));
    values
        .iter()
        .map(|v| match v {
            Some(v) if v.is_finite() => {
                let span = max - min;
                let f = if span > 0.0 { (v - min) / span } else { 0.0 };
                BARS[((f * 7.0).round() as usize).min(7)]
            }
            _ => ' ',
        })
        .collect()
}

/// Where `v` sits in `sorted` (sorted by `total_cmp`): a binary search, so that placing every
/// scene of an n-cell map costs n·log n, not n·√n scans.
fn sorted_position(sorted: &[f64], v: f64) -> Option<usize> {
    sorted
        .binary_search_by(|x| x.total_cmp(&v))
        .ok()
        .or_else(|| sorted.iter().position(|x| *x == v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sparkline_scales_to_the_maximum_and_leaves_gaps() {
        assert_eq!(sparkline(&[Some(0.0), Some(0.5), None, Some(1.0)]), "▁▅ █");
        assert_eq!(sparkline(&[]), "");
        // Scaled between the extremes, so small variations show.
        assert_eq!(sparkline(&[Some(20.0), Some(21.0), Some(22.0)]), "▁▅█");
    }

    #[test]
    fn compare_matches_points_by_x() {
        let s = |xs: Vec<f64>, ys: Vec<Option<f64>>| Spectrum {
            quantity: Quantity::PeakRotationRatio,
            label: String::new(),
            group: Group {
                device: DeviceKind::None,
                variant: 0,
                device_label: "bare".into(),
                settings: vec![],
            },
            axis: "x".into(),
            states: vec![PointState::Survived; xs.len()],
            outcomes: (0..xs.len()).collect(),
            xs,
            ys,
        };
        let a = s(vec![1.0, 2.0, 3.0], vec![Some(2.0), Some(4.0), None]);
        let b = s(vec![2.0, 1.0, 3.0], vec![Some(3.0), Some(1.0), Some(1.0)]);
        assert_eq!(compare(&a, &b), vec![Some(0.5), Some(0.75), None]);
    }
}
