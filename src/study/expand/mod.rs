//! Expansion of a study into scenes: the cartesian product of every parameter grid, one
//! device variant at a time; the last parameter (the excitation's frequency or the record
//! scale) varies fastest. The grids and the labels they give groups are in `layout.rs`, the
//! checks that run before anything expands in `validate.rs`.

mod layout;
mod validate;

pub use layout::{DeviceKind, Layout, MAX_SCENES, Parameter, Part, VariantLayout, device_label};

use super::{
    AmplitudeAxis, Axis, CouplingFamily, DeviceVariant, ExcitationFamily, FrequencyAxis, Param,
    ScenePoint, StructureFamily, Study, StudyError, scene_key,
};
use crate::scene::{
    Amplitude, Clutch, ClutchStiffness, Coupling, Damping, Device, Excitation, FlexibleStructure,
    Frequency, RigidBlock, Scene, Structure,
};
use validate::{check_axes, check_records, check_top_level, invalid_scene};

pub fn validate(study: &Study) -> Result<(), StudyError> {
    expand(study).map(|_| ())
}

pub fn expand(study: &Study) -> Result<Vec<ScenePoint>, StudyError> {
    check_top_level(study)?;
    check_records(study)?;
    let layout = Layout::of(study)?;
    let free = layout.point_axes();
    let mut points = Vec::with_capacity(layout.len());
    for (d, (device, variant)) in study.devices.iter().zip(&layout.variants).enumerate() {
        let params = &variant.params;
        check_axes(study, params)?;
        let mut odometer = vec![0usize; params.len()];
        loop {
            let point = Point {
                params,
                odometer: &odometer,
            };
            let excitation = build_excitation(&study.excitation, &point)?;
            let scene = Scene {
                structure: build_structure(&study.structure, &point)?,
                device: build_device(device, &point)?,
                impact: study.impact,
                duration: crate::study::suites::scene_duration(study, &excitation)?,
                excitation,
                vertical: study.excitation.vertical().cloned(),
                rtol: study.rtol,
                initial_rotation: 0.0,
                stop_when_settled: study.stop_when_settled,
                closed_form_contact: study.closed_form_contact,
                method: study.method,
            };
            scene
                .validate()
                .map_err(|e| invalid_scene(e, study, params, d))?;
            points.push(ScenePoint {
                index: points.len(),
                key: scene_key(&scene),
                scene,
                group: layout.label(d, &odometer, &free),
                coords: coords(study, params, &odometer),
                uncertain: None,
            });
            if !advance(&mut odometer, params) {
                break;
            }
        }
    }
    crate::study::uncertain::apply(study, &layout, points)
}

/// Step the odometer (last parameter fastest); false when it wraps around.
fn advance(odometer: &mut [usize], params: &[Parameter]) -> bool {
    for i in (0..params.len()).rev() {
        odometer[i] += 1;
        if odometer[i] < params[i].values.len() {
            return true;
        }
        odometer[i] = 0;
    }
    false
}

/// One point of a variant's grid: each parameter's value at the odometer.
struct Point<'a> {
    params: &'a [Parameter],
    odometer: &'a [usize],
}

impl Point<'_> {
    /// The parameter's value at this point, None if the variant has no such parameter.
    fn value(&self, param: Param) -> Option<f64> {
        self.params
            .iter()
            .zip(self.odometer)
            .find(|(p, _)| p.param == param)
            .map(|(p, &i)| p.values[i])
    }

    /// A parameter the layout gives this variant: if it is missing, the expansion and the
    /// layout disagree, which is reported (never a NaN in a scene).
    fn get(&self, param: Param) -> Result<f64, StudyError> {
        self.value(param).ok_or_else(|| {
            StudyError::field(
                param.field(),
                format!(
                    "internal: no value of {} in this variant's grid",
                    param.label()
                ),
                "report this: the layout (study/expand/layout.rs) lists the grid's parameters",
            )
        })
    }
}

fn build_structure(s: &StructureFamily, point: &Point) -> Result<Structure, StudyError> {
    Ok(match s {
        StructureFamily::Rigid { form, .. } => {
            let size = match point.value(Param::Size) {
                Some(size) => size,
                None => {
                    // p = √(3g/4R)  ⇒  R = 3g/(4p²)
                    let p = point.get(Param::P)?;
                    3.0 * crate::excitation::G / (4.0 * p * p)
                }
            };
            Structure::Rigid(RigidBlock {
                size,
                alpha: point.get(Param::Alpha)?,
                mass: point.get(Param::Mass)?,
                form: *form,
            })
        }
        StructureFamily::Flexible { .. } => {
            let r0 = point.get(Param::R0)?;
            let omega_n = match point.value(Param::OmegaN) {
                Some(w) => w,
                // ωn = (ωn/p)·p with p = √(g/R0)
                None => point.get(Param::OmegaRatio)? * (crate::excitation::G / r0).sqrt(),
            };
            Structure::Flexible(FlexibleStructure {
                r0,
                alpha: point.get(Param::Alpha)?,
                mass: point.get(Param::Mass)?,
                xi: point.get(Param::Xi)?,
                omega_n,
            })
        }
    })
}

fn build_device(d: &DeviceVariant, point: &Point) -> Result<Device, StudyError> {
    let get = |param| point.get(param);
    // A clutch's or flywheel's spring and damping, as layout.rs gives their parameters.
    let stiffness = || -> Result<ClutchStiffness, StudyError> {
        Ok(match point.value(Param::KTheta) {
            Some(k) => ClutchStiffness::KTheta(k),
            None => ClutchStiffness::FrequencyRatio(get(Param::ClutchFrequencyRatio)?),
        })
    };
    let damping = || -> Result<Damping, StudyError> {
        Ok(match point.value(Param::XiTheta) {
            Some(x) => Damping::XiTheta(x),
            None => Damping::CBar(get(Param::Cbar)?),
        })
    };
    Ok(match d {
        DeviceVariant::None => Device::None,
        DeviceVariant::Inerter { coupling, .. } => Device::Inerter {
            sigma: get(Param::Sigma)?,
            coupling: match coupling {
                CouplingFamily::Rigid => Coupling::Rigid,
                CouplingFamily::Flywheel { .. } => Coupling::Flywheel {
                    stiffness: stiffness()?,
                    rho: get(Param::Rho)?,
                    damping: damping()?,
                },
            },
        },
        DeviceVariant::Sequential { .. } => Device::Sequential {
            sigma: get(Param::Sigma)?,
        },
        DeviceVariant::Mechanistic { reset, .. } => Device::Mechanistic(Clutch {
            sigma: get(Param::Sigma)?,
            stiffness: stiffness()?,
            rho: get(Param::Rho)?,
            epsilon: get(Param::Epsilon)?,
            damping: damping()?,
            friction: get(Param::Friction)?,
            eta: get(Param::Eta)?,
            play: get(Param::Play)?,
            reset: *reset,
        }),
    })
}

fn build_excitation(e: &ExcitationFamily, point: &Point) -> Result<Excitation, StudyError> {
    match e {
        ExcitationFamily::Pulse {
            shape,
            amplitude,
            frequency,
            ..
        } => {
            let a = point.get(amplitude.param())?;
            let w = point.get(frequency.param())?;
            let shapes = shape.list();
            let at = point.get(Param::Shape)? as usize;
            let shape = *shapes.get(at).ok_or_else(|| {
                StudyError::field(
                    "excitation.shape",
                    "internal: a shape index past the study's list",
                    "report this: the layout lists the shapes",
                )
            })?;
            Ok(Excitation::Pulse {
                shape,
                amplitude: match amplitude {
                    AmplitudeAxis::G(_) => Amplitude::G(a),
                    AmplitudeAxis::TanAlphaRatio(_) => Amplitude::TanAlphaRatio(a),
                    AmplitudeAxis::AlphaRatio(_) => Amplitude::AlphaRatio(a),
                },
                frequency: match frequency {
                    FrequencyAxis::RadPerSec(_) => Frequency::RadPerSec(w),
                    FrequencyAxis::Ratio(_) => Frequency::Ratio(w),
                },
            })
        }
        ExcitationFamily::Record {
            scale_to,
            baseline,
            kinks,
            ..
        } => {
            let index = point.get(Param::Record)? as usize;
            let name = point
                .params
                .iter()
                .filter(|p| p.param == Param::Record)
                .find_map(|p| p.names.as_ref())
                .map(|names| names[index].clone())
                .unwrap_or_default();
            Ok(Excitation::Record {
                scale: crate::study::suites::scene_scale(
                    *scale_to,
                    point.get(Param::Scale)?,
                    &name,
                    *baseline,
                )?,
                name,
                baseline: *baseline,
                kinks: *kinks,
            })
        }
    }
}

/// Coordinates of the point at `odometer`: the spectrum axis first, then the map's axes,
/// then the other varying parameters (records are named in the group, not here).
fn coords(study: &Study, params: &[Parameter], odometer: &[usize]) -> Vec<(String, f64)> {
    let map_axes: Vec<Axis> = study.map.map(|m| vec![m.x, m.y]).unwrap_or_default();
    let mut first: Vec<(String, f64)> = Vec::new();
    let mut rest: Vec<(String, f64)> = Vec::new();
    for (p, &i) in params.iter().zip(odometer) {
        if p.names.is_some() {
            continue;
        }
        let v = p.values[i];
        if p.axis == Some(study.spectrum) {
            first.insert(0, (p.label.clone(), v));
        } else if p.axis.is_some_and(|a| map_axes.contains(&a)) {
            first.push((p.label.clone(), v));
        } else if p.varies() {
            rest.push((p.label.clone(), v));
        }
    }
    first.extend(rest);
    first
}
