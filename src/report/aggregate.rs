//! Aggregation of sweep results: spectra, overturning maps, comparisons, sparklines. Pure
//! functions of the results.

use crate::study::Quantity;
use crate::sweep::SweepResults;
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Spectrum {
    pub quantity: Quantity,
    pub group: String,
    pub axis: String,
    pub xs: Vec<f64>,
    /// None: overturned or failed.
    pub ys: Vec<Option<f64>>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OverturningMap {
    pub group: String,
    pub x_axis: String,
    pub y_axis: String,
    pub xs: Vec<f64>,
    pub ys: Vec<f64>,
    /// [iy][ix]: Some(true) overturned, Some(false) survived, None failed or not run.
    pub cells: Vec<Vec<Option<bool>>>,
}

/// The study's quantities (or the peak rotation ratio for ad-hoc point lists).
pub fn quantities(results: &SweepResults) -> Vec<Quantity> {
    results
        .study
        .as_ref()
        .map(|s| s.quantities.clone())
        .unwrap_or_else(|| vec![Quantity::PeakRotationRatio])
}

/// One spectrum per group (plus the map's y value when the study has a map) and quantity,
/// over the first coordinate of the points (the study's spectrum axis), sorted by x.
pub fn spectra(results: &SweepResults) -> Vec<Spectrum> {
    // Map axes other than the spectrum axis separate spectra (one per amplitude, say).
    let map_labels: Vec<String> = results
        .study
        .as_ref()
        .and_then(|s| s.map.map(|m| [s.axis_label(m.x), s.axis_label(m.y)]))
        .map(Vec::from)
        .unwrap_or_default();
    // (group, axis, points (x, outcome)) in order of first appearance.
    type Series<'a> = (String, String, Vec<(f64, &'a crate::sweep::SceneOutcome)>);
    let mut series: Vec<Series> = Vec::new();
    for o in &results.outcomes {
        let Some((axis, x)) = o.point.coords.first() else {
            continue;
        };
        let mut group = o.point.group.clone();
        for (label, v) in &o.point.coords[1..] {
            if map_labels.contains(label) {
                group = format!("{group} {label}={}", crate::study::fmt_num(*v));
            }
        }
        match series.iter_mut().find(|(g, _, _)| *g == group) {
            Some((_, _, pts)) => pts.push((*x, o)),
            None => series.push((group, axis.clone(), vec![(*x, o)])),
        }
    }
    let mut out = Vec::new();
    for q in quantities(results) {
        for (group, axis, pts) in &series {
            let mut pts = pts.clone();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            out.push(Spectrum {
                quantity: q,
                group: group.clone(),
                axis: axis.clone(),
                xs: pts.iter().map(|(x, _)| *x).collect(),
                ys: pts
                    .iter()
                    .map(|(_, o)| o.result.as_ref().ok().and_then(|r| q.of(r)))
                    .collect(),
            });
        }
    }
    out
}

/// One overturning map per group, if the study asks for one.
pub fn maps(results: &SweepResults) -> Vec<OverturningMap> {
    let Some(study) = &results.study else {
        return vec![];
    };
    let Some(axes) = study.map else {
        return vec![];
    };
    let (xl, yl) = (study.axis_label(axes.x), study.axis_label(axes.y));
    let mut groups: Vec<String> = Vec::new();
    for o in &results.outcomes {
        if !groups.contains(&o.point.group) {
            groups.push(o.point.group.clone());
        }
    }
    // Axis values come from the full expansion, so a partial run shows its gaps (or from the
    // results alone where the study cannot be expanded here, e.g. without its records).
    let all: Vec<crate::study::ScenePoint> = study
        .expand()
        .unwrap_or_else(|_| results.outcomes.iter().map(|o| o.point.clone()).collect());
    groups
        .into_iter()
        .map(|group| {
            let in_group = |g: &String| *g == group;
            let mut xs: Vec<f64> = Vec::new();
            let mut ys: Vec<f64> = Vec::new();
            for p in all.iter().filter(|p| in_group(&p.group)) {
                if let (Some(x), Some(y)) = (p.coord(&xl), p.coord(&yl)) {
                    push_unique(&mut xs, x);
                    push_unique(&mut ys, y);
                }
            }
            xs.sort_by(f64::total_cmp);
            ys.sort_by(f64::total_cmp);
            let mut cells = vec![vec![None; xs.len()]; ys.len()];
            for o in results.outcomes.iter().filter(|o| in_group(&o.point.group)) {
                let (Some(x), Some(y)) = (o.point.coord(&xl), o.point.coord(&yl)) else {
                    continue;
                };
                let ix = xs.iter().position(|v| *v == x);
                let iy = ys.iter().position(|v| *v == y);
                if let (Some(ix), Some(iy)) = (ix, iy) {
                    cells[iy][ix] = o.result.as_ref().ok().map(|r| r.overturned);
                }
            }
            OverturningMap {
                group,
                x_axis: xl.clone(),
                y_axis: yl.clone(),
                xs,
                ys,
                cells,
            }
        })
        .collect()
}

fn push_unique(v: &mut Vec<f64>, x: f64) {
    if !v.contains(&x) {
        v.push(x);
    }
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
            group: String::new(),
            axis: "x".into(),
            xs,
            ys,
        };
        let a = s(vec![1.0, 2.0, 3.0], vec![Some(2.0), Some(4.0), None]);
        let b = s(vec![2.0, 1.0, 3.0], vec![Some(3.0), Some(1.0), Some(1.0)]);
        assert_eq!(compare(&a, &b), vec![Some(0.5), Some(0.75), None]);
    }
}
