//! Validation and expansion of a study into scenes: the cartesian product of every parameter
//! grid, one device variant at a time; the last parameter (the excitation's frequency or the
//! record scale) varies fastest.

// Over 800 lines: validation, expansion and group identity/labels walk the same study grids;
// the group labelling (bottom half) is the next candidate for its own file.

use super::{
    AmplitudeAxis, Axis, DeviceVariant, ExcitationFamily, FrequencyAxis, MapAxes, RecordScaling,
    ScenePoint, StructureFamily, Study, StudyError, VERSION, Values, scene_key,
};
use crate::scene::{
    Amplitude, Clutch, ClutchStiffness, Damping, Device, Excitation, FlexibleStructure, Frequency,
    RecordScale, RigidBlock, Scene, Structure,
};
use serde::{Deserialize, Serialize};

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

/// The kind of a device variant, named as in study files (`none` is the bare structure).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DeviceKind {
    None,
    Inerter,
    Sequential,
    Mechanistic,
}

impl DeviceKind {
    pub const ALL: [DeviceKind; 4] = [
        DeviceKind::None,
        DeviceKind::Inerter,
        DeviceKind::Sequential,
        DeviceKind::Mechanistic,
    ];

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
    fn new(
        id: &'static str,
        part: Part,
        path: String,
        label: &str,
        axis: Option<Axis>,
        v: &Values,
    ) -> Self {
        Parameter {
            id,
            part,
            path,
            label: label.to_string(),
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
                if p.names.is_some() {
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
    let mut values: Vec<(&'static str, Vec<f64>)> = Vec::new();
    for p in variants.iter().flat_map(|v| &v.params) {
        if p.names.is_some() {
            continue;
        }
        let entry = match values.iter_mut().find(|(id, _)| *id == p.id) {
            Some(e) => e,
            None => {
                values.push((p.id, Vec::new()));
                values.last_mut().expect("just pushed")
            }
        };
        for v in &p.values {
            if !entry.1.contains(v) {
                entry.1.push(*v);
            }
        }
    }
    values
        .into_iter()
        .map(|(id, vs)| {
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

/// `v` rounded to `digits` significant digits, without trailing zeros: plain decimals from
/// 1e-3 to 1e6, scientific notation (`5.623e-5`) beyond.
pub fn fmt_digits(v: f64, digits: usize) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let sci = format!("{:.*e}", digits.max(1) - 1, v);
    let (mantissa, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let trim = |s: &str| -> String {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s.to_string()
        }
    };
    if (-3..6).contains(&exp) {
        let decimals = (digits as i32 - 1 - exp).max(0) as usize;
        trim(&format!("{v:.decimals$}"))
    } else {
        format!("{}e{exp}", trim(mantissa))
    }
}

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
            let value = |id: &str| {
                params
                    .iter()
                    .zip(&odometer)
                    .find(|(p, _)| p.id == id)
                    .map(|(p, &i)| p.values[i])
            };
            let scene = Scene {
                structure: build_structure(&study.structure, &value),
                device: build_device(device, &value),
                impact: study.impact,
                excitation: build_excitation(&study.excitation, params, &odometer)?,
                duration: study.duration,
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
            });
            if !advance(&mut odometer, params) {
                break;
            }
        }
    }
    Ok(points)
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

fn check_top_level(study: &Study) -> Result<(), StudyError> {
    if study.version != VERSION {
        return Err(StudyError::field(
            "version",
            format!("schema version {} is not supported", study.version),
            &format!("this build reads `version: {VERSION}`"),
        ));
    }
    if study.name.trim().is_empty() {
        return Err(StudyError::field(
            "name",
            "empty name",
            "the name labels the results",
        ));
    }
    if study.devices.is_empty() {
        return Err(StudyError::field(
            "devices",
            "no device variants",
            "list at least one, e.g. devices: [none]",
        ));
    }
    if study.quantities.is_empty() {
        return Err(StudyError::field(
            "quantities",
            "no response quantities",
            "e.g. quantities: [peak_rotation_ratio]",
        ));
    }
    let labels: Vec<String> = study.devices.iter().map(device_label).collect();
    for (i, label) in labels.iter().enumerate() {
        if labels[..i].contains(label) {
            return Err(StudyError::field(
                format!("devices[{i}]"),
                format!("two device variants are both labelled `{label}`"),
                "give one a `label: \"…\"` so their spectra stay apart",
            ));
        }
    }
    if !(study.duration.is_finite() && study.duration > 0.0) {
        return Err(StudyError::field(
            "duration",
            format!("{} is not a duration", study.duration),
            "simulated time per scene in seconds, > 0",
        ));
    }
    if !(1e-14..=0.1).contains(&study.rtol) {
        return Err(StudyError::field(
            "rtol",
            format!("{} is out of range", study.rtol),
            "relative tolerance must be in [1e-14, 0.1]; 1e-5 is the default",
        ));
    }
    if let Some(map) = study.map
        && map.x == map.y
    {
        return Err(StudyError::field(
            "map",
            "the map's x and y axes are the same",
            "e.g. map: (x: frequency, y: amplitude)",
        ));
    }
    if let Some(levels) = study.map.and_then(|m| m.refine_levels())
        && !(1..=8).contains(&levels)
    {
        return Err(StudyError::field(
            "map.refine.levels",
            format!("{levels} refinement levels are out of range"),
            "1 to 8: the coarse lattice steps 2^levels grid values, e.g. refine: (levels: 2)",
        ));
    }
    match &study.structure {
        StructureFamily::Rigid { size, p, .. } if size.is_some() == p.is_some() => {
            return Err(StudyError::field(
                "structure.size",
                "give exactly one of `size` (R, m) and `p` (rad/s)",
                "p = √(3g/4R); e.g. rigid(p: 2.0, alpha: 0.1745)",
            ));
        }
        StructureFamily::Flexible {
            omega_n,
            omega_ratio,
            ..
        } if omega_n.is_some() == omega_ratio.is_some() => {
            return Err(StudyError::field(
                "structure.omega_n",
                "give exactly one of `omega_n` (rad/s) and `omega_ratio` (ωn/p)",
                "e.g. flexible(r0: 10.0, alpha: 0.2, xi: 0.02, omega_ratio: 8.0)",
            ));
        }
        _ => {}
    }
    if let ExcitationFamily::Record { names, .. } = &study.excitation
        && names.is_empty()
    {
        return Err(StudyError::field(
            "excitation.names",
            "no records",
            "list record names from `rocklab records`",
        ));
    }
    Ok(())
}

fn structure_params(s: &StructureFamily) -> Vec<Parameter> {
    let f = |id, label, axis, v: &Values| {
        Parameter::new(
            id,
            Part::Structure,
            format!("structure.{id}"),
            label,
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
                out.push(f("size", "R", Some(Axis::Size), size));
            }
            if let Some(p) = p {
                out.push(f("p", "p", Some(Axis::P), p));
            }
            out.push(f("alpha", "α", Some(Axis::Alpha), alpha));
            out.push(f("mass", "m", None, mass));
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
                f("r0", "R0", Some(Axis::R0), r0),
                f("alpha", "α", Some(Axis::Alpha), alpha),
                f("xi", "ξ", Some(Axis::Xi), xi),
            ];
            if let Some(w) = omega_n {
                out.push(f("omega_n", "ωn", Some(Axis::OmegaN), w));
            }
            if let Some(r) = omega_ratio {
                out.push(f("omega_ratio", "ωn/p", Some(Axis::OmegaRatio), r));
            }
            out.push(f("mass", "m", None, mass));
            out
        }
    }
}

fn device_params(device: &DeviceVariant, d: usize) -> Result<Vec<Parameter>, StudyError> {
    let f = |id, label, v: &Values| {
        Parameter::new(
            id,
            Part::Device,
            format!("devices[{d}].{id}"),
            label,
            None,
            v,
        )
    };
    Ok(match device {
        DeviceVariant::None => vec![],
        DeviceVariant::Inerter { sigma, .. } | DeviceVariant::Sequential { sigma, .. } => {
            vec![f("sigma", "σ", sigma)]
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
            if k_theta.is_some() && clutch_frequency_ratio.is_some() {
                return Err(StudyError::field(
                    format!("devices[{d}].k_theta"),
                    "give at most one of `k_theta` and `clutch_frequency_ratio`",
                    "kθ in N·m/rad, or the clutch frequency √(k/mr) as a multiple of p",
                ));
            }
            if cbar.is_some() && xi_theta.is_some() {
                return Err(StudyError::field(
                    format!("devices[{d}].cbar"),
                    "give at most one of `cbar` and `xi_theta`",
                    "c̄ = c/J in 1/s, or the damping ratio ξθ = c/(2√(kθ J))",
                ));
            }
            let mut out = vec![f("sigma", "σ", sigma)];
            match (k_theta, clutch_frequency_ratio) {
                (Some(k), _) => out.push(f("k_theta", "kθ", k)),
                (None, Some(r)) => out.push(f("clutch_frequency_ratio", "ωc/p", r)),
                (None, None) => out.push(f(
                    "clutch_frequency_ratio",
                    "ωc/p",
                    &Values::One(match ClutchStiffness::default() {
                        ClutchStiffness::FrequencyRatio(r) | ClutchStiffness::KTheta(r) => r,
                    }),
                )),
            }
            match (cbar, xi_theta) {
                (_, Some(x)) => out.push(f("xi_theta", "ξθ", x)),
                (Some(c), None) => out.push(f("cbar", "c̄", c)),
                (None, None) => out.push(f(
                    "cbar",
                    "c̄",
                    &Values::One(match Damping::default() {
                        Damping::CBar(c) | Damping::XiTheta(c) => c,
                    }),
                )),
            }
            out.extend([
                f("friction", "fμ", friction),
                f("eta", "η", eta),
                f("play", "up", play),
                f("epsilon", "ε", epsilon),
                f("rho", "ρ", rho),
            ]);
            out
        }
    })
}

fn excitation_params(e: &ExcitationFamily) -> Result<Vec<Parameter>, StudyError> {
    Ok(match e {
        ExcitationFamily::Pulse {
            amplitude,
            frequency,
            ..
        } => {
            let (alabel, avalues) = match amplitude {
                AmplitudeAxis::G(v) => ("A/g", v),
                AmplitudeAxis::TanAlphaRatio(v) => ("A/(g·tanα)", v),
                AmplitudeAxis::AlphaRatio(v) => ("A/(g·α)", v),
            };
            let (flabel, fvalues) = match frequency {
                FrequencyAxis::RadPerSec(v) => ("ωg", v),
                FrequencyAxis::Ratio(v) => ("ωg/p", v),
            };
            vec![
                Parameter::new(
                    "amplitude",
                    Part::Excitation,
                    "excitation.amplitude".into(),
                    alabel,
                    Some(Axis::Amplitude),
                    avalues,
                ),
                Parameter::new(
                    "frequency",
                    Part::Excitation,
                    "excitation.frequency".into(),
                    flabel,
                    Some(Axis::Frequency),
                    fvalues,
                ),
            ]
        }
        ExcitationFamily::Record { names, scale, .. } => {
            let mut record = Parameter::new(
                "record",
                Part::Excitation,
                "excitation.names".into(),
                "record",
                None,
                &Values::List((0..names.len()).map(|i| i as f64).collect()),
            );
            record.names = Some(names.clone());
            vec![
                record,
                Parameter::new(
                    "scale",
                    Part::Excitation,
                    "excitation.scale".into(),
                    "scale",
                    Some(Axis::Scale),
                    scale,
                ),
            ]
        }
    })
}

/// The spectrum and map axes must be parameters of the study; all values well formed.
fn check_axes(study: &Study, params: &[Parameter]) -> Result<(), StudyError> {
    let has = |axis: Axis| params.iter().any(|p| p.axis == Some(axis));
    if !has(study.spectrum) {
        return Err(StudyError::field(
            "spectrum",
            format!(
                "the spectrum axis `{}` is not a parameter of this study",
                axis_name(study.spectrum)
            ),
            "pulse studies use `frequency`; record studies an axis of the structure, e.g. `omega_n`",
        ));
    }
    if let Some(map) = study.map {
        for axis in [map.x, map.y] {
            if !has(axis) {
                return Err(StudyError::field(
                    "map",
                    format!(
                        "the map axis `{}` is not a parameter of this study",
                        axis_name(axis)
                    ),
                    "e.g. map: (x: frequency, y: amplitude) with lists or ranges for both",
                ));
            }
        }
    }
    let all_values = params.iter().map(|p| (p.path.as_str(), &p.values));
    for (path, values) in all_values {
        if let Some(v) = values.iter().find(|v| !v.is_finite()) {
            return Err(StudyError::field(
                path,
                format!("{v} is not a finite number"),
                "",
            ));
        }
    }
    // A value given twice would run the same scenes twice under one label.
    for p in params {
        if let Some(names) = &p.names {
            if let Some((i, name)) = names
                .iter()
                .enumerate()
                .find(|(i, n)| names[..*i].contains(n))
            {
                return Err(StudyError::field(
                    format!("{}[{i}]", p.path),
                    format!("record `{name}` is listed twice"),
                    "list each record once",
                ));
            }
        } else if let Some(v) = p
            .values
            .iter()
            .enumerate()
            .find(|(i, v)| p.values[..*i].contains(v))
            .map(|(_, v)| *v)
        {
            return Err(StudyError::field(
                p.path.clone(),
                format!("the value {v} is given twice"),
                "each value of a list or range must be distinct (a range needs from ≠ to)",
            ));
        }
    }
    Ok(())
}

fn axis_name(axis: Axis) -> String {
    ron::to_string(&axis).unwrap_or_default()
}

fn build_structure(s: &StructureFamily, value: &dyn Fn(&str) -> Option<f64>) -> Structure {
    let get = |id: &str| value(id).unwrap_or(f64::NAN);
    match s {
        StructureFamily::Rigid { form, .. } => {
            let size = value("size").unwrap_or_else(|| {
                // p = √(3g/4R)  ⇒  R = 3g/(4p²)
                let p = get("p");
                3.0 * crate::excitation::G / (4.0 * p * p)
            });
            Structure::Rigid(RigidBlock {
                size,
                alpha: get("alpha"),
                mass: get("mass"),
                form: *form,
            })
        }
        StructureFamily::Flexible { .. } => {
            let r0 = get("r0");
            let omega_n = value("omega_n").unwrap_or_else(|| {
                // ωn = (ωn/p)·p with p = √(g/R0)
                get("omega_ratio") * (crate::excitation::G / r0).sqrt()
            });
            Structure::Flexible(FlexibleStructure {
                r0,
                alpha: get("alpha"),
                mass: get("mass"),
                xi: get("xi"),
                omega_n,
            })
        }
    }
}

fn build_device(d: &DeviceVariant, value: &dyn Fn(&str) -> Option<f64>) -> Device {
    let get = |id: &str| value(id).unwrap_or(f64::NAN);
    match d {
        DeviceVariant::None => Device::None,
        DeviceVariant::Inerter { coupling, .. } => Device::Inerter {
            sigma: get("sigma"),
            coupling: coupling.clone(),
        },
        DeviceVariant::Sequential { .. } => Device::Sequential {
            sigma: get("sigma"),
        },
        DeviceVariant::Mechanistic { reset, .. } => Device::Mechanistic(Clutch {
            sigma: get("sigma"),
            stiffness: match value("k_theta") {
                Some(k) => ClutchStiffness::KTheta(k),
                None => ClutchStiffness::FrequencyRatio(get("clutch_frequency_ratio")),
            },
            rho: get("rho"),
            epsilon: get("epsilon"),
            damping: match value("xi_theta") {
                Some(x) => Damping::XiTheta(x),
                None => Damping::CBar(get("cbar")),
            },
            friction: get("friction"),
            eta: get("eta"),
            play: get("play"),
            reset: *reset,
        }),
    }
}

fn build_excitation(
    e: &ExcitationFamily,
    params: &[Parameter],
    odometer: &[usize],
) -> Result<Excitation, StudyError> {
    let value = |id: &str| {
        params
            .iter()
            .zip(odometer)
            .find(|(p, _)| p.id == id)
            .map(|(p, &i)| p.values[i])
            .unwrap_or(f64::NAN)
    };
    match e {
        ExcitationFamily::Pulse {
            shape,
            amplitude,
            frequency,
        } => {
            let a = value("amplitude");
            let w = value("frequency");
            Ok(Excitation::Pulse {
                shape: *shape,
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
            names,
            scale_to,
            baseline,
            kinks,
            ..
        } => {
            let index = value("record") as usize;
            let scale = value("scale");
            Ok(Excitation::Record {
                name: names[index].clone(),
                scale: match scale_to {
                    RecordScaling::Factor => RecordScale::Factor(scale),
                    RecordScaling::Pga => RecordScale::Pga(scale),
                    RecordScaling::Pgv => RecordScale::Pgv(scale),
                },
                baseline: *baseline,
                kinks: *kinks,
            })
        }
    }
}

/// Every record the study names must be in the library (loading it also parses it once for
/// the whole sweep).
fn check_records(study: &Study) -> Result<(), StudyError> {
    if let ExcitationFamily::Record {
        names, baseline, ..
    } = &study.excitation
    {
        let library = crate::excitation::library::global().map_err(|e| {
            StudyError::field(
                "excitation.names",
                format!("the record library cannot be opened: {e}"),
                "set ROCKLAB_RECORDS to the records directory, or run from the repository",
            )
        })?;
        for (i, name) in names.iter().enumerate() {
            library.load(name, *baseline).map_err(|e| {
                StudyError::field(
                    format!("excitation.names[{i}]"),
                    e.to_string(),
                    "`rocklab records` lists the library's record names",
                )
            })?;
        }
    }
    Ok(())
}

/// A scene-level validation failure, pointed at the study field that produced it.
fn invalid_scene(
    e: crate::scene::Invalid,
    study: &Study,
    params: &[Parameter],
    d: usize,
) -> StudyError {
    let path = match e.field {
        "duration" | "rtol" => e.field.to_string(),
        "restitution" | "width" => "impact".to_string(),
        "amplitude" | "frequency" => format!("excitation.{}", e.field),
        // Scene::validate names the flexible R0 `size`.
        "size" => match &study.structure {
            StructureFamily::Flexible { .. } => "structure.r0".into(),
            StructureFamily::Rigid { p: Some(_), .. } => "structure.p".into(),
            StructureFamily::Rigid { .. } => "structure.size".into(),
        },
        f if params
            .iter()
            .any(|p| p.id == f && p.path.starts_with("structure")) =>
        {
            format!("structure.{f}")
        }
        f => format!("devices[{d}].{f}"),
    };
    StudyError::field(
        path,
        format!("{} = {}: {}", e.field, e.value, e.expected),
        "physically invalid values are rejected before anything runs",
    )
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

pub fn device_label(device: &DeviceVariant) -> String {
    let (label, default) = match device {
        DeviceVariant::None => (None, "bare"),
        DeviceVariant::Inerter { label, .. } => (label.as_ref(), "inerter"),
        DeviceVariant::Sequential { label, .. } => (label.as_ref(), "sequential"),
        DeviceVariant::Mechanistic { label, .. } => (label.as_ref(), "mechanistic"),
    };
    label.cloned().unwrap_or_else(|| default.to_string())
}

/// A short, exact-enough rendering of a parameter value for labels.
pub fn fmt_num(v: f64) -> String {
    if v == v.round() && v.abs() < 1e9 {
        return format!("{}", v as i64);
    }
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "0" || s == "-0" {
        format!("{v:.3e}")
    } else {
        s.to_string()
    }
}
