//! Checks of a study before it expands: the top-level fields, the spectrum and map axes,
//! the records, and a scene's own validation pointed back at the study field.

use super::super::{Axis, ExcitationFamily, StructureFamily, Study, StudyError, VERSION};
use super::{Parameter, device_label};
use crate::numfmt::fmt_exact;

pub(super) fn check_top_level(study: &Study) -> Result<(), StudyError> {
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
    let tail = matches!(
        &study.excitation,
        ExcitationFamily::Record { tail: Some(_), .. }
    );
    match (study.duration, tail) {
        (Some(_), true) => {
            return Err(StudyError::field(
                "duration",
                "unused: with `excitation.tail` each scene lasts its record's length plus the tail",
                "remove `duration`, or remove `tail` to give every scene the same duration",
            ));
        }
        (None, false) => {
            return Err(StudyError::field(
                "duration",
                "missing: how long each scene is simulated",
                "add `duration: 10.0` (seconds), or for records `tail: 10.0` in the excitation \
                 (each scene: its record's length plus 10 s)",
            ));
        }
        (Some(d), false) if !(d.is_finite() && d > 0.0) => {
            return Err(StudyError::field(
                "duration",
                format!("{} is not a duration", fmt_exact(d)),
                "simulated time per scene in seconds, > 0",
            ));
        }
        _ => {}
    }
    if !(1e-14..=0.1).contains(&study.rtol) {
        return Err(StudyError::field(
            "rtol",
            format!("{} is out of range", fmt_exact(study.rtol)),
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
    study.excitation.record_names()?;
    Ok(())
}

/// The spectrum and map axes must be parameters of the study; all values well formed.
pub(super) fn check_axes(study: &Study, params: &[Parameter]) -> Result<(), StudyError> {
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
                format!("{} is not a finite number", fmt_exact(*v)),
                "",
            ));
        }
    }
    // A value given twice would run the same scenes twice under one label. Sets, not a scan
    // of the values before each: a range may have a million steps.
    for p in params {
        if let Some(names) = &p.names {
            let mut seen = std::collections::HashSet::new();
            if let Some((i, name)) = names
                .iter()
                .enumerate()
                .find(|(_, n)| !seen.insert(n.as_str()))
            {
                let (what, hint) = if p.param == super::Param::Shape {
                    ("pulse shape", "list each pulse shape once")
                } else {
                    ("record", "list each record once")
                };
                return Err(StudyError::field(
                    format!("{}[{i}]", p.path),
                    format!("{what} `{name}` is listed twice"),
                    hint,
                ));
            }
        } else if let Some(v) = {
            // Equal as numbers: -0.0 + 0.0 is 0.0 (the values are finite, checked above).
            let mut seen = std::collections::HashSet::new();
            p.values
                .iter()
                .find(|v| !seen.insert((**v + 0.0).to_bits()))
        } {
            return Err(StudyError::field(
                p.path.clone(),
                format!("the value {} is given twice", fmt_exact(*v)),
                "each value of a list or range must be distinct (a range needs from ≠ to)",
            ));
        }
    }
    Ok(())
}

fn axis_name(axis: Axis) -> String {
    ron::to_string(&axis).unwrap_or_default()
}

/// Every record the study names must be in the library (loading it also parses it once for
/// the whole sweep).
pub(super) fn check_records(study: &Study) -> Result<(), StudyError> {
    if let ExcitationFamily::Record { baseline, .. } = &study.excitation {
        let names = study.excitation.record_names()?;
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
pub(super) fn invalid_scene(
    e: crate::scene::Invalid,
    study: &Study,
    params: &[Parameter],
    d: usize,
) -> StudyError {
    let path = match e.field {
        "duration" | "rtol" => e.field.to_string(),
        "scale" | "scale_pga" | "scale_pgv" | "scale_pga_star" | "scale_pgv_star" => {
            "excitation.scale".to_string()
        }
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
        // A device parameter where the study writes it (a flywheel's under `coupling`).
        f => params
            .iter()
            .find(|p| p.id == f && p.path.starts_with(&format!("devices[{d}].")))
            .map_or_else(|| format!("devices[{d}].{f}"), |p| p.path.clone()),
    };
    // A size derived from p: the message speaks of the p the user wrote.
    let what = match path.as_str() {
        "structure.p" => format!(
            "gives a size R = {} m, which {}",
            fmt_exact(e.value),
            e.expected
        ),
        _ => e.to_string(),
    };
    StudyError::field(
        path,
        what,
        "physically invalid values are rejected before anything runs",
    )
}
