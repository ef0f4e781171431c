//! The shape of a study's expansion: per device variant its parameter grids (structure,
//! device, excitation), the expansion indices it covers, and the labels of its groups.

use super::super::{
    Axis, CouplingFamily, DeviceVariant, ExcitationFamily, MapAxes, Param, StructureFamily, Study,
    StudyError, Values,
};
use crate::numfmt::fmt_digits;
use serde::{Deserialize, Serialize};
use std::collections::HashSet;

/// Studies larger than this are almost certainly a typo in a range.
pub const MAX_SCENES: usize = 1_000_000;

/// Where a parameter sits in the study file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Part {
    Structure,
    Device,
    Excitation,
}

all_variants! {
/// The kind of a device variant, named as in study files (`none` is the bare structure).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DeviceKind {
    None,
    Inerter,
    Sequential,
    Mechanistic,
}
}

impl DeviceKind {
    pub fn of(device: &DeviceVariant) -> DeviceKind {
        match device {
            DeviceVariant::None => DeviceKind::None,
            DeviceVariant::Inerter { .. } => DeviceKind::Inerter,
            DeviceVariant::Sequential { .. } => DeviceKind::Sequential,
            DeviceVariant::Mechanistic { .. } => DeviceKind::Mechanistic,
        }
    }

    /// The name in study files (`none`), as `Device::name` gives it for scenes.
    pub fn name(self) -> &'static str {
        match self {
            DeviceKind::None => "none",
            DeviceKind::Inerter => "inerter",
            DeviceKind::Sequential => "sequential",
            DeviceKind::Mechanistic => "mechanistic",
        }
    }

    /// A kind by its study-file name, or `bare` for `none`.
    pub fn from_name(name: &str) -> Option<DeviceKind> {
        match name {
            "bare" => Some(DeviceKind::None),
            _ => DeviceKind::ALL.into_iter().find(|k| k.name() == name),
        }
    }
}

/// One grid parameter of a device variant's expansion.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    /// Which parameter it is.
    pub param: Param,
    /// Study field name (also the key used to build the scene), e.g. `k_theta`, `record`.
    pub id: &'static str,
    pub part: Part,
    /// Path of the field in the study file, for messages.
    pub path: String,
    /// Axis label in coordinates and groups (paper notation).
    pub label: String,
    pub axis: Option<Axis>,
    /// The values in expansion order (exact, as the study gives them).
    pub values: Vec<f64>,
    /// Names for a categorical parameter (records); values are then indices.
    pub names: Option<Vec<String>>,
    /// What is wrong with the list or range itself, if anything.
    shape_error: Option<(String, &'static str)>,
}

impl Parameter {
    fn new(param: Param, part: Part, path: String, axis: Option<Axis>, v: &Values) -> Self {
        Parameter {
            param,
            id: param.field(),
            part,
            path,
            label: param.label().to_string(),
            axis,
            // A malformed range is reported, never expanded (it may be astronomically long).
            values: if v.shape_error().is_some() {
                vec![]
            } else {
                v.expand()
            },
            names: None,
            shape_error: v.shape_error(),
        }
    }

    /// Whether the study gives this parameter more than one value.
    pub fn varies(&self) -> bool {
        self.values.len() > 1
    }
}

/// The shape of a study's expansion, known without running or loading anything: per device
/// variant its parameters (last varies fastest) and the range of expansion indices it covers.
/// A scene's index alone then says every parameter value that defines it.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    pub variants: Vec<VariantLayout>,
    /// Significant digits per parameter id in labels: the fewest (at least 4) that tell
    /// every value of that parameter in the study apart.
    digits: Vec<(&'static str, usize)>,
    spectrum: Axis,
    map: Option<MapAxes>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct VariantLayout {
    pub kind: DeviceKind,
    /// The variant's label: its `label: "…"` or its kind (`bare` for none).
    pub label: String,
    pub params: Vec<Parameter>,
    /// Expansion index of the variant's first scene, and its scene count.
    pub first: usize,
    pub count: usize,
}

impl Layout {
    /// The layout of a valid study's expansion (records are not loaded).
    pub fn of(study: &Study) -> Result<Layout, StudyError> {
        let mut variants = Vec::new();
        let mut first = 0usize;
        for (d, device) in study.devices.iter().enumerate() {
            let mut params = structure_params(&study.structure);
            params.extend(device_params(device, d)?);
            params.extend(excitation_params(&study.excitation)?);
            for p in &params {
                if let Some((message, hint)) = &p.shape_error {
                    return Err(StudyError::field(p.path.clone(), message.clone(), hint));
                }
            }
            let count: usize = params
                .iter()
                .map(|p| p.values.len())
                .try_fold(1usize, |acc, n| acc.checked_mul(n))
                .unwrap_or(usize::MAX);
            if first.saturating_add(count) > MAX_SCENES {
                return Err(StudyError::field(
                    "devices",
                    format!("the study expands to more than {MAX_SCENES} scenes"),
                    "shorten a range or list; every list multiplies the scene count",
                ));
            }
            variants.push(VariantLayout {
                kind: DeviceKind::of(device),
                label: device_label(device),
                params,
                first,
                count,
            });
            first += count;
        }
        let mut layout = Layout {
            variants,
            digits: Vec::new(),
            spectrum: study.spectrum,
            map: study.map,
        };
        layout.digits = label_digits(&layout.variants);
        Ok(layout)
    }

    /// Total number of scenes.
    pub fn len(&self) -> usize {
        self.variants.last().map_or(0, |v| v.first + v.count)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The variant and the position in each of its parameters' values of the scene with
    /// expansion index `index`.
    pub fn locate(&self, index: usize) -> Option<(usize, Vec<usize>)> {
        let v = self
            .variants
            .iter()
            .position(|v| (v.first..v.first + v.count).contains(&index))?;
        let variant = &self.variants[v];
        let mut rest = index - variant.first;
        let mut at = vec![0; variant.params.len()];
        for (i, p) in variant.params.iter().enumerate().rev() {
            at[i] = rest % p.values.len();
            rest /= p.values.len();
        }
        Some((v, at))
    }

    /// A value of a parameter as labels show it: the record's name, or the number with as
    /// many digits as tell the study's values of this parameter apart.
    pub fn value_text(&self, p: &Parameter, i: usize) -> String {
        match &p.names {
            Some(names) => names[i].clone(),
            None => {
                let digits = self
                    .digits
                    .iter()
                    .find(|(id, _)| *id == p.id)
                    .map_or(MIN_LABEL_DIGITS, |(_, d)| *d);
                fmt_digits(p.values[i], digits)
            }
        }
    }

    /// Label of the scenes of `variant` at `at`, leaving out parameters on the `free` axes
    /// (a spectrum's x, a map's x and y): the device, then the parameters that vary in the
    /// study (device grid first, then structure, then excitation), then ` · record`.
    pub fn label(&self, variant: usize, at: &[usize], free: &[Axis]) -> String {
        self.label_with(variant, at, free, true)
    }

    /// [`Layout::label`] without the record: the label of a variant's record suite.
    pub fn suite_label(&self, variant: usize, at: &[usize], free: &[Axis]) -> String {
        self.label_with(variant, at, free, false)
    }

    fn label_with(&self, variant: usize, at: &[usize], free: &[Axis], with_record: bool) -> String {
        let v = &self.variants[variant];
        let mut text = v.label.clone();
        let mut record = None;
        for part in [Part::Device, Part::Structure, Part::Excitation] {
            for (p, &i) in v.params.iter().zip(at).filter(|(p, _)| p.part == part) {
                if p.axis.is_some_and(|a| free.contains(&a)) {
                    continue;
                }
                if p.param == Param::Record {
                    record = Some(self.value_text(p, i));
                } else if p.varies() {
                    text = format!("{text} {}={}", p.label, self.value_text(p, i));
                }
            }
        }
        if let Some(r) = record.filter(|_| with_record) {
            text = format!("{text} · {r}");
        }
        text
    }

    /// The axes a scene's group leaves free: the spectrum axis and the map's axes.
    pub fn point_axes(&self) -> Vec<Axis> {
        let mut axes = vec![self.spectrum];
        if let Some(m) = self.map {
            axes.extend([m.x, m.y]);
        }
        axes
    }
}

/// Fewest significant digits a label shows.
const MIN_LABEL_DIGITS: usize = 4;

/// Per parameter id, the fewest significant digits (at least 4) that keep every distinct
/// value of that parameter in the study distinct in labels.
fn label_digits(variants: &[VariantLayout]) -> Vec<(&'static str, usize)> {
    // Distinct values per parameter, found with a set of their bits (0.0 and -0.0 are one
    // value, as `==` has it): a scan per value was quadratic in a long range's length.
    let mut values: Vec<(&'static str, Vec<f64>, HashSet<u64>)> = Vec::new();
    for p in variants.iter().flat_map(|v| &v.params) {
        if p.names.is_some() {
            continue;
        }
        let entry = match values.iter_mut().find(|(id, _, _)| *id == p.id) {
            Some(e) => e,
            None => {
                values.push((p.id, Vec::new(), HashSet::new()));
                values.last_mut().expect("just pushed")
            }
        };
        for &v in &p.values {
            let bits = if v == 0.0 { 0 } else { v.to_bits() };
            if entry.2.insert(bits) {
                entry.1.push(v);
            }
        }
    }
    values
        .into_iter()
        .map(|(id, vs, _)| {
            let digits = (MIN_LABEL_DIGITS..=17)
                .find(|&d| {
                    let mut texts: Vec<String> = vs.iter().map(|v| fmt_digits(*v, d)).collect();
                    texts.sort();
                    texts.dedup();
                    texts.len() == vs.len()
                })
                .unwrap_or(17);
            (id, digits)
        })
        .collect()
}

fn structure_params(s: &StructureFamily) -> Vec<Parameter> {
    let f = |param: Param, axis, v: &Values| {
        Parameter::new(
            param,
            Part::Structure,
            format!("structure.{}", param.field()),
            axis,
            v,
        )
    };
    match s {
        StructureFamily::Rigid {
            size,
            p,
            alpha,
            mass,
            ..
        } => {
            let mut out = Vec::new();
            if let Some(size) = size {
                out.push(f(Param::Size, Some(Axis::Size), size));
            }
            if let Some(p) = p {
                out.push(f(Param::P, Some(Axis::P), p));
            }
            out.push(f(Param::Alpha, Some(Axis::Alpha), alpha));
            out.push(f(Param::Mass, None, mass));
            out
        }
        StructureFamily::Flexible {
            r0,
            alpha,
            xi,
            omega_n,
            omega_ratio,
            mass,
        } => {
            let mut out = vec![
                f(Param::R0, Some(Axis::R0), r0),
                f(Param::Alpha, Some(Axis::Alpha), alpha),
                f(Param::Xi, Some(Axis::Xi), xi),
            ];
            if let Some(w) = omega_n {
                out.push(f(Param::OmegaN, Some(Axis::OmegaN), w));
            }
            if let Some(r) = omega_ratio {
                out.push(f(Param::OmegaRatio, Some(Axis::OmegaRatio), r));
            }
            out.push(f(Param::Mass, None, mass));
            out
        }
    }
}

fn device_params(device: &DeviceVariant, d: usize) -> Result<Vec<Parameter>, StudyError> {
    let prefix = format!("devices[{d}].");
    let f = |param, v: &Values| device_param(&prefix, param, v);
    Ok(match device {
        DeviceVariant::None => vec![],
        DeviceVariant::Inerter {
            sigma,
            coupling: CouplingFamily::Rigid,
            ..
        }
        | DeviceVariant::Sequential { sigma, .. } => vec![f(Param::Sigma, sigma)],
        DeviceVariant::Inerter {
            sigma,
            coupling:
                CouplingFamily::Flywheel {
                    k_theta,
                    clutch_frequency_ratio,
                    cbar,
                    xi_theta,
                    rho,
                },
            ..
        } => {
            let prefix = format!("devices[{d}].coupling.");
            let spring = Spring {
                k_theta,
                clutch_frequency_ratio,
                cbar,
                xi_theta,
            };
            let mut out = vec![f(Param::Sigma, sigma)];
            out.extend(spring.params(&prefix)?);
            out.push(device_param(&prefix, Param::Rho, rho));
            out
        }
        DeviceVariant::Mechanistic {
            sigma,
            k_theta,
            clutch_frequency_ratio,
            cbar,
            xi_theta,
            friction,
            eta,
            play,
            epsilon,
            rho,
            ..
        } => {
            let spring = Spring {
                k_theta,
                clutch_frequency_ratio,
                cbar,
                xi_theta,
            };
            let mut out = vec![f(Param::Sigma, sigma)];
            out.extend(spring.params(&prefix)?);
            out.extend([
                f(Param::Friction, friction),
                f(Param::Eta, eta),
                f(Param::Play, play),
                f(Param::Epsilon, epsilon),
                f(Param::Rho, rho),
            ]);
            out
        }
    })
}

/// A device parameter at `prefix` (`devices[1].`, `devices[1].coupling.`) in the study.
fn device_param(prefix: &str, param: Param, v: &Values) -> Parameter {
    let path = format!("{prefix}{}", param.field());
    Parameter::new(param, Part::Device, path, None, v)
}

/// The spring and damping of a clutch or of a flywheel coupling: one of `k_theta` and
/// `clutch_frequency_ratio` (default the clutch's ratio), one of `cbar` (default the
/// clutch's) and `xi_theta`.
struct Spring<'a> {
    k_theta: &'a Option<Values>,
    clutch_frequency_ratio: &'a Option<Values>,
    cbar: &'a Option<Values>,
    xi_theta: &'a Option<Values>,
}

impl Spring<'_> {
    /// The two parameters, at `prefix` (`devices[1].`) in the study.
    fn params(&self, prefix: &str) -> Result<Vec<Parameter>, StudyError> {
        let f = |param, v: &Values| device_param(prefix, param, v);
        let path = |id| format!("{prefix}{id}");
        if self.k_theta.is_some() && self.clutch_frequency_ratio.is_some() {
            return Err(StudyError::field(
                path("k_theta"),
                "give at most one of `k_theta` and `clutch_frequency_ratio`",
                "kθ in N·m/rad, or the clutch frequency √(k/mr) as a multiple of p",
            ));
        }
        if self.cbar.is_some() && self.xi_theta.is_some() {
            return Err(StudyError::field(
                path("cbar"),
                "give at most one of `cbar` and `xi_theta`",
                "c̄ = c/J in 1/s, or the damping ratio ξθ = c/(2√(kθ J))",
            ));
        }
        let stiffness = match (self.k_theta, self.clutch_frequency_ratio) {
            (Some(k), _) => f(Param::KTheta, k),
            (None, Some(r)) => f(Param::ClutchFrequencyRatio, r),
            (None, None) => f(
                Param::ClutchFrequencyRatio,
                &crate::study::default_clutch_frequency_ratio(),
            ),
        };
        let damping = match (self.cbar, self.xi_theta) {
            (_, Some(x)) => f(Param::XiTheta, x),
            (Some(c), None) => f(Param::Cbar, c),
            (None, None) => f(Param::Cbar, &crate::study::default_cbar()),
        };
        Ok(vec![stiffness, damping])
    }
}

fn excitation_params(e: &ExcitationFamily) -> Result<Vec<Parameter>, StudyError> {
    Ok(match e {
        ExcitationFamily::Pulse {
            shape,
            amplitude,
            frequency,
            ..
        } => {
            let (aparam, avalues) = (amplitude.param(), amplitude.values());
            let (fparam, fvalues) = (frequency.param(), frequency.values());
            // The shapes: a categorical parameter (values are positions in the list).
            let shapes = shape.list();
            let mut shape = Parameter::new(
                Param::Shape,
                Part::Excitation,
                "excitation.shape".into(),
                None,
                &Values::List((0..shapes.len()).map(|i| i as f64).collect()),
            );
            shape.names = Some(
                shapes
                    .iter()
                    .map(crate::study::shapes::shape_name)
                    .collect(),
            );
            vec![
                shape,
                Parameter::new(
                    aparam,
                    Part::Excitation,
                    "excitation.amplitude".into(),
                    Some(Axis::Amplitude),
                    avalues,
                ),
                Parameter::new(
                    fparam,
                    Part::Excitation,
                    "excitation.frequency".into(),
                    Some(Axis::Frequency),
                    fvalues,
                ),
            ]
        }
        ExcitationFamily::Record { scale, .. } => {
            let names = e.record_names()?;
            let mut record = Parameter::new(
                Param::Record,
                Part::Excitation,
                "excitation.names".into(),
                None,
                &Values::List((0..names.len()).map(|i| i as f64).collect()),
            );
            record.names = Some(names);
            vec![
                record,
                Parameter::new(
                    Param::Scale,
                    Part::Excitation,
                    "excitation.scale".into(),
                    Some(Axis::Scale),
                    scale,
                ),
            ]
        }
    })
}

pub fn device_label(device: &DeviceVariant) -> String {
    let (label, default) = match device {
        DeviceVariant::None => (None, "bare"),
        DeviceVariant::Inerter {
            label,
            coupling: CouplingFamily::Rigid,
            ..
        } => (label.as_ref(), "inerter"),
        DeviceVariant::Inerter { label, .. } => (label.as_ref(), "flywheel inerter"),
        DeviceVariant::Sequential { label, .. } => (label.as_ref(), "sequential"),
        DeviceVariant::Mechanistic { label, .. } => (label.as_ref(), "mechanistic"),
    };
    label.cloned().unwrap_or_else(|| default.to_string())
}
