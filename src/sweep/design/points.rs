//! The design points of a study (its expansion grouped by variant and every parameter off
//! the excitation axes) and the scene a probe runs (the sized parameter set to a value).

use super::Point;
use crate::scene::{ClutchStiffness, Damping, Device, Scene};
use crate::study::design::{Design, DesignParameter};
use crate::study::{Layout, Study, StudyError};
use std::collections::HashMap;

/// The scene with the sized parameter set to `value` (σ = 0: the bare structure).
pub fn with_parameter(scene: &Scene, parameter: DesignParameter, value: f64) -> Scene {
    let mut scene = scene.clone();
    if parameter == DesignParameter::Sigma && value == 0.0 {
        scene.device = Device::None;
        return scene;
    }
    match (&mut scene.device, parameter) {
        (Device::Inerter { sigma, .. } | Device::Sequential { sigma }, DesignParameter::Sigma) => {
            *sigma = value
        }
        (Device::Mechanistic(c), p) => match p {
            DesignParameter::Sigma => c.sigma = value,
            DesignParameter::Cbar => c.damping = Damping::CBar(value),
            DesignParameter::XiTheta => c.damping = Damping::XiTheta(value),
            DesignParameter::Friction => c.friction = value,
            DesignParameter::KTheta => c.stiffness = ClutchStiffness::KTheta(value),
            DesignParameter::ClutchFrequencyRatio => {
                c.stiffness = ClutchStiffness::FrequencyRatio(value)
            }
        },
        _ => {}
    }
    scene
}

/// The design points of a study: its expansion grouped by device variant and every
/// parameter off the excitation axes (the sized parameter is single-valued: validation).
pub(super) fn design_points(study: &Study, design: &Design) -> Result<Vec<Point>, StudyError> {
    let layout = Layout::of(study)?;
    let over = design.over_ids(study);
    let mut points: Vec<Point> = Vec::new();
    let mut by_key: HashMap<(usize, Vec<usize>), usize> = HashMap::new();
    for nominal in study.expand()? {
        let Some((v, at)) = layout.locate(nominal.index) else {
            continue;
        };
        let params = &layout.variants[v].params;
        let is_over = |i: usize| over.contains(&params[i].id);
        let key: Vec<usize> = (0..at.len())
            .map(|i| if is_over(i) { usize::MAX } else { at[i] })
            .collect();
        let excitation: Vec<String> = (0..at.len())
            .filter(|&i| is_over(i))
            .map(|i| {
                format!(
                    "{}={}",
                    params[i].label,
                    layout.value_text(&params[i], at[i])
                )
            })
            .collect();
        // An ordered axis (not a record list) at its first or last value.
        let edge = (0..at.len())
            .filter(|&i| is_over(i) && params[i].varies() && params[i].names.is_none())
            .find_map(|i| {
                let end = match at[i] {
                    0 => "lowest",
                    a if a + 1 == params[i].values.len() => "highest",
                    _ => return None,
                };
                Some(format!(
                    "governed at the {end} {} of the study ({}): the worst case may lie \
                     beyond the axis",
                    params[i].label,
                    layout.value_text(&params[i], at[i])
                ))
            });
        let next = points.len();
        let p = *by_key.entry((v, key)).or_insert(next);
        if p == next {
            let mut label_axes = Vec::new();
            let mut record = None;
            for (i, param) in params.iter().enumerate() {
                if is_over(i) || param.id == design.parameter.id() {
                    continue;
                }
                if param.param == crate::study::Param::Record {
                    record = Some(layout.value_text(param, at[i]));
                } else if param.varies() {
                    label_axes.push((param.label.clone(), param.values[at[i]]));
                }
            }
            points.push(Point {
                variant: v,
                device: layout.variants[v].label.clone(),
                label_axes,
                record,
                sized: design.parameter.sizes(&study.devices[v]),
                nominal: Vec::new(),
                excitation: Vec::new(),
                edges: Vec::new(),
            });
        }
        points[p].nominal.push(nominal);
        points[p].excitation.push(excitation.join(" "));
        points[p].edges.push(edge);
    }
    Ok(points)
}
