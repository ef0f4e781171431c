//! Comparing two device variants by meaning: pairs of spectra (or maps) matched on every
//! parameter they share, overturning-aware statistics per pair, overturning maps side by
//! side, and record-suite mean and dispersion spectra. Used by `rocklab compare`, the summary
//! and the workbench.

use super::aggregate::{Group, OverturningMap, PointState, Spectrum};
use super::select::{SelectError, Selector, axis_id, keep_on_axis, select, split_axes};
use crate::study::Part;
use crate::study::Quantity;
use crate::sweep::SweepResults;
use serde::Serialize;

/// Whether groups `a` and `b` describe the same situation apart from their devices: every
/// setting both have and that varies in the study agrees, except device settings a selector
/// names (`free`: `--a 'mechanistic(play: 0)' --b mechanistic` compares play 0 with every
/// play). Structure and excitation settings (record, amplitude, …) always agree. Settings
/// only one side has (a clutch grid) leave that side a grid.
pub fn same_situation(a: &Group, b: &Group, free: &[&str]) -> bool {
    a.settings.iter().all(|sa| {
        (sa.part == Part::Device && free.contains(&sa.id.as_str()))
            || match b.setting(&sa.id) {
                Some(sb) => {
                    (!sa.varies && !sb.varies) || (sa.value == sb.value && sa.name == sb.name)
                }
                None => true,
            }
    })
}

/// Pairs (index of A, index of B) of `groups`: every group the A selector picks with every
/// group the B selector picks that describes the same situation ([`same_situation`]). Where A
/// and B pick the same groups (one device's grid), the first member of each situation is
/// compared with each other one.
pub fn pair_groups(
    groups: &[&Group],
    a: &Selector,
    b: &Selector,
) -> Result<Vec<(usize, usize)>, SelectError> {
    let (sa, sb) = (select(groups, a)?, select(groups, b)?);
    if sa == sb {
        return first_against_others(groups, &sa).ok_or_else(|| {
            SelectError(format!(
                "A and B (`{}`) are the same single variant in every situation: pick another \
                 B (`b`, or `--b`) to compare with",
                a.text
            ))
        });
    }
    let free: Vec<&str> = a.ids().chain(b.ids()).collect();
    let pairs: Vec<(usize, usize)> = sa
        .iter()
        .flat_map(|&ia| sb.iter().map(move |&ib| (ia, ib)))
        .filter(|&(ia, ib)| ia != ib && same_situation(groups[ia], groups[ib], &free))
        .collect();
    if pairs.is_empty() {
        return Err(SelectError(format!(
            "`{}` and `{}` select groups that share no situation (record, structure, excitation)",
            a.text, b.text
        )));
    }
    Ok(pairs)
}

/// One selection against itself: in each situation, its first group (in study order) paired
/// with every other one. None if no situation has two groups.
fn first_against_others(groups: &[&Group], picked: &[usize]) -> Option<Vec<(usize, usize)>> {
    // Device settings (the grid) are what the members differ in.
    let free: Vec<&str> = picked
        .iter()
        .flat_map(|&i| &groups[i].settings)
        .filter(|s| s.part == Part::Device)
        .map(|s| s.id.as_str())
        .collect();
    let same = |i: usize, j: usize| {
        groups[i].variant == groups[j].variant
            && same_situation(groups[i], groups[j], &free)
            && same_situation(groups[j], groups[i], &free)
    };
    let mut pairs = Vec::new();
    for (k, &first) in picked.iter().enumerate() {
        if picked[..k].iter().any(|&e| same(e, first)) {
            continue;
        }
        pairs.extend(
            picked[k + 1..]
                .iter()
                .filter(|&&other| same(first, other))
                .map(|&other| (first, other)),
        );
    }
    (!pairs.is_empty()).then_some(pairs)
}

/// The default pair of a list of spectra (for the workbench): sequential vs mechanistic in
/// the same situation if there, else the pair of different variants in the same situation
/// with the most points where both survive.
pub fn default_pair(rows: &[&Spectrum]) -> Option<(usize, usize)> {
    use crate::study::DeviceKind::{Mechanistic, Sequential};
    let mut best: Option<((bool, usize), usize, usize)> = None;
    for (a, sa) in rows.iter().enumerate() {
        for (b, sb) in rows.iter().enumerate() {
            if sa.group.variant == sb.group.variant || !same_situation(&sa.group, &sb.group, &[]) {
                continue;
            }
            let classic = sa.group.device == Sequential && sb.group.device == Mechanistic;
            let common = pair_points(sa, sb)
                .iter()
                .filter(|p| p.ratio.is_some())
                .count();
            let score = (classic, common);
            if best.as_ref().is_none_or(|(s, _, _)| score > *s) {
                best = Some((score, a, b));
            }
        }
    }
    best.map(|(_, a, b)| (a, b))
}

/// The devices (variant labels) A and B are when the user names neither, as `compare` and
/// the workbench choose them: [`default_pair`]'s, each side its whole device; with a single
/// device, that device on both sides (its first grid member against each other one).
pub fn default_sides(rows: &[&Spectrum]) -> Option<(String, String)> {
    let (a, b) = match default_pair(rows) {
        Some((a, b)) => (rows[a], rows[b]),
        None => (*rows.first()?, *rows.last()?),
    };
    Some((a.group.device_label.clone(), b.group.device_label.clone()))
}

/// One point of the spectrum axis seen from both sides.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PointPair {
    pub x: f64,
    pub a: Option<f64>,
    pub b: Option<f64>,
    pub a_state: PointState,
    pub b_state: PointState,
    /// B/A where both survive and A is not zero.
    pub ratio: Option<f64>,
}

/// The points of two spectra over the union of their x values (sorted); a point one side
/// lacks did not run there.
pub fn pair_points(a: &Spectrum, b: &Spectrum) -> Vec<PointPair> {
    let mut xs: Vec<f64> = a.xs.iter().chain(&b.xs).copied().collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    let side = |s: &Spectrum, x: f64| match s.xs.iter().position(|v| *v == x) {
        Some(i) => (s.ys[i], s.states[i]),
        None => (None, PointState::NotRun),
    };
    xs.into_iter()
        .map(|x| {
            let ((a, a_state), (b, b_state)) = (side(a, x), side(b, x));
            let ratio = match (a, b) {
                (Some(a), Some(b)) if a != 0.0 => Some(b / a),
                _ => None,
            };
            PointPair {
                x,
                a,
                b,
                a_state,
                b_state,
                ratio,
            }
        })
        .collect()
}

/// Statistics of one pair. Ratios are taken only where both variants survive (and A is not
/// zero); the overturning counts say where that leaves points out.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct PairStats {
    /// Points on the axis (either side).
    pub points: usize,
    /// Points where both survive and A ≠ 0: the support of every ratio below.
    pub ratio_points: usize,
    /// Pointwise B/A: mean, median, smallest and largest.
    pub mean_ratio: Option<f64>,
    pub median_ratio: Option<f64>,
    pub min_ratio: Option<f64>,
    pub max_ratio: Option<f64>,
    /// Largest A and largest B over the points where both survive, and B/A of those peaks.
    pub peak_a: Option<f64>,
    pub peak_b: Option<f64>,
    pub peak_ratio: Option<f64>,
    /// Points where A overturns and B survives (B prevents overturning), and the reverse.
    pub a_overturns_b_survives: usize,
    pub b_overturns_a_survives: usize,
    pub both_overturn: usize,
    /// Points where both survive but A is zero (no uplift): no ratio.
    pub zero_a: usize,
    /// Points where either side failed, or did not run (counted apart, never as overturned).
    pub failed: usize,
    pub not_run: usize,
}

pub fn pair_stats(points: &[PointPair]) -> PairStats {
    use PointState::*;
    let mut s = PairStats {
        points: points.len(),
        ..Default::default()
    };
    let mut ratios = Vec::new();
    let (mut peak_a, mut peak_b): (Option<f64>, Option<f64>) = (None, None);
    for p in points {
        match (p.a_state, p.b_state) {
            (NotRun, _) | (_, NotRun) => s.not_run += 1,
            (Failed, _) | (_, Failed) => s.failed += 1,
            (Overturned, Overturned) => s.both_overturn += 1,
            (Overturned, Survived) => s.a_overturns_b_survives += 1,
            (Survived, Overturned) => s.b_overturns_a_survives += 1,
            (Survived, Survived) => match p.ratio {
                Some(r) => {
                    ratios.push(r);
                    let (a, b) = (p.a.unwrap_or(0.0), p.b.unwrap_or(0.0));
                    peak_a = Some(peak_a.map_or(a, |m| m.max(a)));
                    peak_b = Some(peak_b.map_or(b, |m| m.max(b)));
                }
                None => s.zero_a += 1,
            },
        }
    }
    s.ratio_points = ratios.len();
    s.mean_ratio = mean(&ratios);
    s.median_ratio = median(&ratios);
    s.min_ratio = ratios.iter().copied().reduce(f64::min);
    s.max_ratio = ratios.iter().copied().reduce(f64::max);
    s.peak_a = peak_a;
    s.peak_b = peak_b;
    s.peak_ratio = match (peak_a, peak_b) {
        (Some(a), Some(b)) if a != 0.0 => Some(b / a),
        _ => None,
    };
    s
}

pub fn mean(v: &[f64]) -> Option<f64> {
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

pub fn median(v: &[f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    Some(if n % 2 == 1 {
        s[n / 2]
    } else {
        (s[n / 2 - 1] + s[n / 2]) / 2.0
    })
}

/// A compared pair of spectra, as `compare --json` writes it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SpectrumPair {
    pub quantity: Quantity,
    pub a: String,
    pub b: String,
    pub a_group: Group,
    pub b_group: Group,
    pub axis: String,
    pub stats: PairStats,
    pub points: Vec<PointPair>,
}

/// Every pair of spectra of `quantity` that the selectors make.
pub fn compare_spectra(
    spectra: &[Spectrum],
    quantity: Quantity,
    a: &Selector,
    b: &Selector,
) -> Result<Vec<SpectrumPair>, SelectError> {
    let of_q: Vec<&Spectrum> = spectra.iter().filter(|s| s.quantity == quantity).collect();
    let groups: Vec<&Group> = of_q.iter().map(|s| &s.group).collect();
    // A filter on the spectrum's own axis (`frequency: 2.0`) picks points, not spectra.
    let axis = of_q.first().and_then(|s| axis_id(&s.axis));
    let axes: Vec<&str> = axis.into_iter().collect();
    let ((a_rest, a_axis), (b_rest, b_axis)) = (split_axes(a, &axes), split_axes(b, &axes));
    let pairs = pair_groups(&groups, &a_rest, &b_rest)?;
    let mut out = Vec::new();
    for (ia, ib) in pairs {
        let (sa, sb) = (of_q[ia], of_q[ib]);
        let mut points = pair_points(sa, sb);
        if let Some(id) = axis.filter(|_| !a_axis.is_empty() || !b_axis.is_empty()) {
            let xs: Vec<f64> = points.iter().map(|p| p.x).collect();
            let keep_a = keep_on_axis(&a.text, id, &xs, &a_axis)?;
            let keep_b = keep_on_axis(&b.text, id, &xs, &b_axis)?;
            let mut k = 0;
            points.retain(|_| {
                k += 1;
                keep_a[k - 1] && keep_b[k - 1]
            });
            if points.is_empty() {
                return Err(SelectError(format!(
                    "`{}` and `{}` pick no common `{id}`",
                    a.text, b.text
                )));
            }
        }
        out.push(SpectrumPair {
            quantity,
            a: sa.label.clone(),
            b: sb.label.clone(),
            a_group: sa.group.clone(),
            b_group: sb.group.clone(),
            axis: sa.axis.clone(),
            stats: pair_stats(&points),
            points,
        });
    }
    Ok(out)
}

/// A cell of two overturning maps side by side.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MapCell {
    BothSurvive,
    /// B survives where A overturns: B's protective benefit.
    OnlyBSurvives,
    /// A survives where B overturns.
    OnlyASurvives,
    BothOverturn,
    /// Failed or not run on either side.
    Missing,
}

impl MapCell {
    pub const ALL: [MapCell; 5] = [
        MapCell::BothSurvive,
        MapCell::OnlyBSurvives,
        MapCell::OnlyASurvives,
        MapCell::BothOverturn,
        MapCell::Missing,
    ];

    pub fn glyph(self) -> char {
        match self {
            MapCell::BothSurvive => '·',
            MapCell::OnlyBSurvives => 'B',
            MapCell::OnlyASurvives => 'A',
            MapCell::BothOverturn => '█',
            MapCell::Missing => '?',
        }
    }

    pub fn meaning(self) -> &'static str {
        match self {
            MapCell::BothSurvive => "both survive",
            MapCell::OnlyBSurvives => "only B survives",
            MapCell::OnlyASurvives => "only A survives",
            MapCell::BothOverturn => "both overturn",
            MapCell::Missing => "failed or not run",
        }
    }
}

/// Two overturning maps over the same axes, cell by cell (A's axes; B's cells matched by
/// value).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MapComparison {
    pub a: String,
    pub b: String,
    pub a_group: Group,
    pub b_group: Group,
    pub x_axis: String,
    pub y_axis: String,
    pub xs: Vec<f64>,
    pub ys: Vec<f64>,
    /// [iy][ix], y ascending.
    pub cells: Vec<Vec<MapCell>>,
}

impl MapComparison {
    /// The comparison on the kept columns (`keep_x`) and rows (`keep_y`) only.
    pub fn cropped(self, keep_x: &[bool], keep_y: &[bool]) -> MapComparison {
        let pick = |v: &[f64], keep: &[bool]| -> Vec<f64> {
            v.iter()
                .zip(keep)
                .filter(|(_, k)| **k)
                .map(|(x, _)| *x)
                .collect()
        };
        let cells = self
            .cells
            .iter()
            .zip(keep_y)
            .filter(|(_, k)| **k)
            .map(|(row, _)| {
                row.iter()
                    .zip(keep_x)
                    .filter(|(_, k)| **k)
                    .map(|(c, _)| *c)
                    .collect()
            })
            .collect();
        MapComparison {
            xs: pick(&self.xs, keep_x),
            ys: pick(&self.ys, keep_y),
            cells,
            ..self
        }
    }

    pub fn count(&self, kind: MapCell) -> usize {
        self.cells.iter().flatten().filter(|c| **c == kind).count()
    }
}

pub fn compare_map_pair(a: &OverturningMap, b: &OverturningMap) -> MapComparison {
    let cell_b = |x: f64, y: f64| -> Option<bool> {
        let ix = b.xs.iter().position(|v| *v == x)?;
        let iy = b.ys.iter().position(|v| *v == y)?;
        b.cells[iy][ix]
    };
    let cells =
        a.ys.iter()
            .enumerate()
            .map(|(iy, &y)| {
                a.xs.iter()
                    .enumerate()
                    .map(|(ix, &x)| match (a.cells[iy][ix], cell_b(x, y)) {
                        (Some(false), Some(false)) => MapCell::BothSurvive,
                        (Some(true), Some(false)) => MapCell::OnlyBSurvives,
                        (Some(false), Some(true)) => MapCell::OnlyASurvives,
                        (Some(true), Some(true)) => MapCell::BothOverturn,
                        _ => MapCell::Missing,
                    })
                    .collect()
            })
            .collect();
    MapComparison {
        a: a.label.clone(),
        b: b.label.clone(),
        a_group: a.group.clone(),
        b_group: b.group.clone(),
        x_axis: a.x_axis.clone(),
        y_axis: a.y_axis.clone(),
        xs: a.xs.clone(),
        ys: a.ys.clone(),
        cells,
    }
}

/// Every pair of overturning maps that the selectors make.
pub fn compare_maps(
    maps: &[OverturningMap],
    a: &Selector,
    b: &Selector,
) -> Result<Vec<MapComparison>, SelectError> {
    let groups: Vec<&Group> = maps.iter().map(|m| &m.group).collect();
    // Filters on the maps' own axes (`amplitude: 1.5`) pick rows and columns, not maps.
    let axes: Vec<&str> = maps
        .first()
        .into_iter()
        .flat_map(|m| [axis_id(&m.x_axis), axis_id(&m.y_axis)])
        .flatten()
        .collect();
    let ((a_rest, a_axis), (b_rest, b_axis)) = (split_axes(a, &axes), split_axes(b, &axes));
    let mut out = Vec::new();
    for (ia, ib) in pair_groups(&groups, &a_rest, &b_rest)? {
        let m = compare_map_pair(&maps[ia], &maps[ib]);
        let keep = |id: Option<&str>, values: &[f64]| -> Result<Vec<bool>, SelectError> {
            let Some(id) = id else {
                return Ok(vec![true; values.len()]);
            };
            let ka = keep_on_axis(&a.text, id, values, &a_axis)?;
            let kb = keep_on_axis(&b.text, id, values, &b_axis)?;
            let both: Vec<bool> = ka.iter().zip(&kb).map(|(x, y)| *x && *y).collect();
            if !both.contains(&true) {
                return Err(SelectError(format!(
                    "`{}` and `{}` pick no common `{id}`",
                    a.text, b.text
                )));
            }
            Ok(both)
        };
        let keep_x = keep(axis_id(&m.x_axis), &m.xs)?;
        let keep_y = keep(axis_id(&m.y_axis), &m.ys)?;
        out.push(m.cropped(&keep_x, &keep_y));
    }
    Ok(out)
}

/// The categorised map as text: one row per y value (largest on top), one character per x.
pub fn map_text(m: &MapComparison) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let legend: Vec<String> = MapCell::ALL
        .iter()
        .map(|c| format!("{} {} ({})", c.glyph(), c.meaning(), m.count(*c)))
        .collect();
    let _ = writeln!(
        s,
        "overturning maps, A = {} vs B = {}: {} (→) × {} (↑)",
        m.a, m.b, m.x_axis, m.y_axis
    );
    let _ = writeln!(s, "  {}", legend.join(", "));
    for (iy, row) in m.cells.iter().enumerate().rev() {
        let line: String = row.iter().map(|c| c.glyph()).collect();
        let _ = writeln!(s, "  {:>8} {line}", crate::numfmt::fmt_num(m.ys[iy]));
    }
    if let (Some(lo), Some(hi)) = (m.xs.first(), m.xs.last()) {
        let _ = writeln!(
            s,
            "  {:>8} {} … {}",
            "",
            crate::numfmt::fmt_num(*lo),
            crate::numfmt::fmt_num(*hi)
        );
    }
    s
}

/// The spectra of one variant over a suite of records: at each x, the mean over the records
/// where it survives and their coefficient of variation (sample standard deviation / mean),
/// with the records where it overturns, failed or did not run counted.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SuiteSpectrum {
    pub quantity: Quantity,
    /// The variant's label without the record.
    pub label: String,
    /// The shared settings (the record's left out).
    pub group: Group,
    pub axis: String,
    pub records: Vec<String>,
    pub xs: Vec<f64>,
    pub mean: Vec<Option<f64>>,
    /// None with fewer than two surviving records or a zero mean.
    pub cv: Vec<Option<f64>>,
    pub overturned: Vec<usize>,
    pub missing: Vec<usize>,
}

impl SuiteSpectrum {
    /// The mean of the CV over the axis (where defined).
    pub fn mean_cv(&self) -> Option<f64> {
        mean(&self.cv.iter().flatten().copied().collect::<Vec<_>>())
    }

    /// Record points (record × x) where the variant overturns.
    pub fn overturned_total(&self) -> usize {
        self.overturned.iter().sum()
    }

    /// As a spectrum of means, for pairing and ratios (a point is overturned when every
    /// record that ran overturned there).
    fn as_spectrum(&self) -> Spectrum {
        Spectrum {
            quantity: self.quantity,
            label: self.label.clone(),
            group: self.group.clone(),
            axis: self.axis.clone(),
            xs: self.xs.clone(),
            ys: self.mean.clone(),
            states: self
                .mean
                .iter()
                .zip(&self.overturned)
                .map(|(m, o)| match (m, o) {
                    (Some(_), _) => PointState::Survived,
                    (None, 1..) => PointState::Overturned,
                    (None, 0) => PointState::Failed,
                })
                .collect(),
            outcomes: vec![],
        }
    }
}

/// Record-suite spectra: one per variant and quantity, over the spectra of the same group
/// apart from the record; empty unless the results hold more than one record.
pub fn suite_spectra(results: &SweepResults, spectra: &[Spectrum]) -> Vec<SuiteSpectrum> {
    let layout = results
        .study
        .as_ref()
        .and_then(|s| Some((s.layout().ok()?, s.spectrum)));
    let Some((layout, spectrum_axis)) = layout else {
        return vec![];
    };
    let without_record = |g: &Group| Group {
        settings: g
            .settings
            .iter()
            .filter(|s| s.id != "record")
            .cloned()
            .collect(),
        ..g.clone()
    };
    let mut suites: Vec<(Group, Vec<&Spectrum>)> = Vec::new();
    for s in spectra.iter().filter(|s| s.group.record().is_some()) {
        let key = without_record(&s.group);
        match suites
            .iter_mut()
            .find(|(g, members)| *g == key && members[0].quantity == s.quantity)
        {
            Some((_, members)) => members.push(s),
            None => suites.push((key, vec![s])),
        }
    }
    suites
        .into_iter()
        .filter(|(_, members)| members.len() > 1)
        .map(|(group, members)| {
            let mut xs: Vec<f64> = members.iter().flat_map(|s| s.xs.clone()).collect();
            xs.sort_by(f64::total_cmp);
            xs.dedup();
            let (mut mean_v, mut cv, mut overturned, mut missing) =
                (Vec::new(), Vec::new(), Vec::new(), Vec::new());
            for &x in &xs {
                let mut values = Vec::new();
                let (mut o, mut m) = (0, 0);
                for s in &members {
                    match s.xs.iter().position(|v| *v == x) {
                        Some(i) => match (s.states[i], s.ys[i]) {
                            (PointState::Survived, Some(y)) => values.push(y),
                            (PointState::Overturned, _) => o += 1,
                            _ => m += 1,
                        },
                        None => m += 1,
                    }
                }
                let mu = mean(&values);
                cv.push(match mu {
                    Some(mu) if values.len() > 1 && mu != 0.0 => {
                        let var = values.iter().map(|v| (v - mu).powi(2)).sum::<f64>()
                            / (values.len() - 1) as f64;
                        Some(var.sqrt() / mu.abs())
                    }
                    _ => None,
                });
                mean_v.push(mu);
                overturned.push(o);
                missing.push(m);
            }
            let first = members[0];
            let label = first
                .outcomes
                .first()
                .and_then(|&i| layout.locate(results.outcomes[i].point.index))
                .map(|(v, at)| layout.suite_label(v, &at, &[spectrum_axis]))
                .unwrap_or_else(|| group.device_label.clone());
            SuiteSpectrum {
                quantity: first.quantity,
                label,
                group,
                axis: first.axis.clone(),
                records: members
                    .iter()
                    .filter_map(|s| s.group.record().map(String::from))
                    .collect(),
                xs,
                mean: mean_v,
                cv,
                overturned,
                missing,
            }
        })
        .collect()
}

/// Two variants' record suites compared: the suite-mean spectra paired point by point, and
/// each side's dispersion and overturning count.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SuitePair {
    pub quantity: Quantity,
    pub a: String,
    pub b: String,
    pub records: usize,
    /// Statistics of B's suite-mean spectrum over A's.
    pub stats: PairStats,
    /// Mean over the axis of each side's CV over records.
    pub mean_cv_a: Option<f64>,
    pub mean_cv_b: Option<f64>,
    /// Record points (record × x) where each side overturns.
    pub overturned_a: usize,
    pub overturned_b: usize,
}

pub fn compare_suites(
    suites: &[SuiteSpectrum],
    quantity: Quantity,
    a: &Selector,
    b: &Selector,
) -> Result<Vec<SuitePair>, SelectError> {
    let of_q: Vec<&SuiteSpectrum> = suites.iter().filter(|s| s.quantity == quantity).collect();
    if of_q.is_empty() {
        return Ok(vec![]);
    }
    let groups: Vec<&Group> = of_q.iter().map(|s| &s.group).collect();
    // Selectors naming a record do not apply to suites (they span every record).
    let strip = |s: &Selector| Selector {
        filters: s
            .filters
            .iter()
            .filter(|f| f.id != "record")
            .cloned()
            .collect(),
        ..s.clone()
    };
    Ok(pair_groups(&groups, &strip(a), &strip(b))?
        .into_iter()
        .map(|(ia, ib)| {
            let (sa, sb) = (of_q[ia], of_q[ib]);
            let points = pair_points(&sa.as_spectrum(), &sb.as_spectrum());
            SuitePair {
                quantity,
                a: sa.label.clone(),
                b: sb.label.clone(),
                records: sa.records.len(),
                stats: pair_stats(&points),
                mean_cv_a: sa.mean_cv(),
                mean_cv_b: sb.mean_cv(),
                overturned_a: sa.overturned_total(),
                overturned_b: sb.overturned_total(),
            }
        })
        .collect())
}

/// The record-suite spectra as summary text: per quantity and variant, sparklines of the mean
/// and of the CV over records, the CV averaged over the axis and the overturned record points.
/// Empty unless the results hold more than one record.
pub fn suite_summary(results: &SweepResults, spectra: &[Spectrum]) -> String {
    use std::fmt::Write as _;
    let suites = suite_spectra(results, spectra);
    let mut s = String::new();
    let Some(first) = suites.first() else {
        return s;
    };
    let _ = writeln!(
        s,
        "\nrecord suite ({} records: {}): mean over the records that survive, CV = sample std / mean over them",
        first.records.len(),
        first.records.join(", ")
    );
    let width = suites
        .iter()
        .map(|x| x.label.chars().count())
        .max()
        .unwrap_or(0);
    let mut last = None;
    for suite in &suites {
        if last != Some(suite.quantity) {
            let _ = writeln!(s, "{} over {}", suite.quantity.label(), suite.axis);
            last = Some(suite.quantity);
        }
        let _ = writeln!(
            s,
            "  {:width$}  mean {}  CV {}  mean CV {}, {} record points overturned",
            suite.label,
            super::sparkline(&suite.mean),
            super::sparkline(&suite.cv),
            suite.mean_cv().map_or("—".into(), |c| format!("{c:.3}")),
            suite.overturned_total(),
        );
    }
    s
}
