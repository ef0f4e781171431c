//! The draws of an uncertain study, made during the expansion: each scene's draw comes from
//! the seed and the scene's place on the record × stripe grid (never from the order scenes
//! run in), so every expansion of the same study, a resumed sweep's included, draws the
//! same values; each drawn scene keeps its values ([`Sample::Drawn`]) for results and
//! stripes.csv.

use super::{Range, Sampling, Uncertain};
use crate::scene::{ClutchStiffness, Coupling, Damping, Device, Impact, Scene, Structure};
use crate::study::{Layout, Param, ScenePoint, Study, StudyError, StudyKind, scene_key};
use chacha20::ChaCha12Rng;
use rand_core::{Rng, SeedableRng};
use serde::{Deserialize, Serialize};

/// What an uncertain study's scene is.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Sample {
    /// A drawn scene: its draw's place on the record × stripe grid (per record for an IDA)
    /// and the values drawn, by CSV name, in the section's order.
    Drawn {
        draw: usize,
        values: Vec<(String, f64)>,
    },
    /// The deterministic companion of the drawn scene at grid index `of`: every uncertain
    /// parameter at its distribution's centre. Fitted apart: the records-only dispersion.
    Companion { of: usize },
}

/// The random stream of one use: ChaCha12 keyed by the seed, on stream `stream`.
fn stream(seed: u64, stream: u64) -> ChaCha12Rng {
    let mut rng = ChaCha12Rng::seed_from_u64(seed);
    rng.set_stream(stream);
    rng
}

/// A uniform in the open interval (0, 1): 53 random bits, centred in their cell, so the
/// quantile functions never see 0 or 1.
fn open_unit(rng: &mut ChaCha12Rng) -> f64 {
    ((rng.next_u64() >> 11) as f64 + 0.5) * (1.0 / (1u64 << 53) as f64)
}

/// An index in 0..n (n ≥ 1) by the high half of a 64 × 64-bit product: its bias is below
/// n / 2⁶⁴, nothing for a study's few thousand draws.
fn below(rng: &mut ChaCha12Rng, n: usize) -> usize {
    ((u128::from(rng.next_u64()) * n as u128) >> 64) as usize
}

/// The streams of the draws are 0, 1, …; a Latin hypercube's permutations count down from
/// the top, so that the two never meet.
const PERMUTATION_STREAMS: u64 = u64::MAX;

/// `draws` rows of `parameters` uniforms in (0, 1): row i is draw i's, from the seed alone.
/// Monte Carlo: independent. Latin hypercube: parameter j's rows are a seeded permutation of
/// the strata [k/N, (k+1)/N), each jittered uniformly inside its stratum (McKay et al. 1979).
/// Written out rather than taken from a crate: the few crates that offer LHS draw from their
/// own unseeded or version-dependent streams, and a resumed sweep needs these exact numbers.
pub fn uniforms(sampling: Sampling, seed: u64, draws: usize, parameters: usize) -> Vec<Vec<f64>> {
    let mut rows: Vec<Vec<f64>> = (0..draws)
        .map(|i| {
            let mut rng = stream(seed, i as u64);
            (0..parameters).map(|_| open_unit(&mut rng)).collect()
        })
        .collect();
    if sampling == Sampling::LatinHypercube {
        for j in 0..parameters {
            let mut rng = stream(seed, PERMUTATION_STREAMS - j as u64);
            // Fisher–Yates.
            let mut strata: Vec<usize> = (0..draws).collect();
            for k in (1..draws).rev() {
                strata.swap(k, below(&mut rng, k + 1));
            }
            for (row, stratum) in rows.iter_mut().zip(strata) {
                row[j] = (stratum as f64 + row[j]) / draws as f64;
            }
        }
    }
    rows
}

/// A drawn (or central) value put into a scene.
fn set(scene: &mut Scene, param: Param, v: f64) {
    let mut clutch = |f: &mut dyn FnMut(&mut ClutchStiffness, &mut Damping)| match &mut scene.device
    {
        Device::Mechanistic(c) => f(&mut c.stiffness, &mut c.damping),
        Device::Inerter {
            coupling: Coupling::Flywheel {
                stiffness, damping, ..
            },
            ..
        } => f(stiffness, damping),
        Device::None | Device::Sequential { .. } | Device::Inerter { .. } => {}
    };
    match param {
        Param::KTheta => clutch(&mut |k, _| *k = ClutchStiffness::KTheta(v)),
        Param::ClutchFrequencyRatio => clutch(&mut |k, _| *k = ClutchStiffness::FrequencyRatio(v)),
        Param::Cbar => clutch(&mut |_, c| *c = Damping::CBar(v)),
        Param::XiTheta => clutch(&mut |_, c| *c = Damping::XiTheta(v)),
        Param::Restitution => {
            scene.impact = Impact::Housner {
                restitution: Some(v),
            }
        }
        Param::Alpha => match &mut scene.structure {
            Structure::Rigid(b) => b.alpha = v,
            Structure::Flexible(f) => f.alpha = v,
        },
        Param::Size => {
            if let Structure::Rigid(b) = &mut scene.structure {
                b.size = v;
            }
        }
        // R = 3g/(4p²), as the expansion builds a block given by p.
        Param::P => {
            if let Structure::Rigid(b) = &mut scene.structure {
                b.size = 3.0 * crate::excitation::G / (4.0 * v * v);
            }
        }
        // Validation admits only the parameters above (`Uncertain::parameters`).
        _ => {}
    }
}

/// Where a grid point's draw sits: (its place, how many places): record × stripe, or the
/// record alone for an IDA.
fn place(layout: &Layout, index: usize, per_record: bool) -> Option<(usize, usize)> {
    let (v, at) = layout.locate(index)?;
    let params = &layout.variants[v].params;
    let record = params.iter().position(|p| p.param == Param::Record)?;
    let records = params[record].values.len();
    if per_record {
        return Some((at[record], records));
    }
    let scale = params.iter().position(|p| p.param == Param::Scale)?;
    let stripes = params[scale].values.len();
    Some((at[record] * stripes + at[scale], records * stripes))
}

/// The study's grid points with their uncertain parameters drawn, then (a stripes study)
/// each one's deterministic companion, numbered after the grid. A study without an
/// `uncertain` section comes back as it is.
pub fn apply(
    study: &Study,
    layout: &Layout,
    mut points: Vec<ScenePoint>,
) -> Result<Vec<ScenePoint>, StudyError> {
    let Some(section) = &study.uncertain else {
        return Ok(points);
    };
    let parameters: Vec<_> = Uncertain::parameters(section);
    let per_record = match study.kind() {
        StudyKind::Ida => true,
        StudyKind::Stripes => false,
        // Refused by validation (`super::validate`), which names the field.
        _ => return Ok(points),
    };
    // Each distribution is checked before it is drawn from (validation names the field).
    for (param, d) in &parameters {
        super::check_distribution(*param, d)?;
    }
    let places: Vec<Option<(usize, usize)>> = points
        .iter()
        .map(|p| place(layout, p.index, per_record))
        .collect();
    let Some(count) = places.iter().flatten().map(|(_, n)| *n).max() else {
        return Err(StudyError::field(
            "uncertain",
            "the study has no record × stripe grid to draw on",
            "uncertain parameters need `excitation: record(…)` with a fragility section",
        ));
    };
    let u = uniforms(section.sampling, section.seed, count, parameters.len());
    let mut companions = Vec::new();
    let first_companion = layout.len();
    for (point, place) in points.iter_mut().zip(places) {
        let Some((draw, _)) = place else { continue };
        let nominal = point.scene.clone();
        let mut values = Vec::with_capacity(parameters.len());
        for ((param, d), &uj) in parameters.iter().zip(&u[draw]) {
            let v = d.value(uj, Range::of(*param));
            set(&mut point.scene, *param, v);
            values.push((param.info().name.to_string(), v));
        }
        check_scene(&point.scene, draw)?;
        point.key = scene_key(&point.scene);
        point.uncertain = Some(Sample::Drawn { draw, values });
        if !per_record {
            let mut scene = nominal;
            for (param, d) in &parameters {
                set(&mut scene, *param, d.centre());
            }
            check_scene(&scene, draw)?;
            companions.push(ScenePoint {
                index: first_companion + point.index,
                key: scene_key(&scene),
                scene,
                group: format!("{} · nominal", point.group),
                coords: point.coords.clone(),
                uncertain: Some(Sample::Companion { of: point.index }),
            });
        }
    }
    points.extend(companions);
    Ok(points)
}

/// A drawn scene the model refuses (truncation keeps draws in range, so this is a
/// combination the ranges do not see, e.g. a clutch spring the device refuses).
fn check_scene(scene: &Scene, draw: usize) -> Result<(), StudyError> {
    scene.validate().map_err(|e| {
        StudyError::field(
            "uncertain",
            format!("draw {draw} gives an invalid scene: {e}"),
            "narrow the distributions so that every draw is a valid scene",
        )
    })
}
