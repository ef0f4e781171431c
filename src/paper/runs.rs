//! The scenes the rows run, each run once per process however many rows read it (a cache keyed
//! by the scene), and the measures rows read from them: one acceleration measure per structure,
//! the paper's, with the other reported beside it.
//!
//! Histories are the ones `rocklab simulate --history` writes: the scene's whole duration,
//! resampled on the automatic grid (plus event rows), not the solver's steps.

use super::fair::Series;
use crate::presets::{self, flexible_fig14, rigid_fig8};
use crate::scene::*;
use crate::sim::{self, History, HistoryColumn, SceneResult};
use crate::study::Param;
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

/// The process's record library (embedded records, or `--records-dir`).
fn library() -> crate::error::Result<&'static crate::excitation::Library> {
    crate::excitation::library::global().map_err(|e| crate::error::error!("{e}"))
}

fn key(scene: &Scene) -> String {
    format!("{scene:?}")
}

type Cache<T> = OnceLock<Mutex<HashMap<String, Arc<T>>>>;

fn cached<T>(
    cache: &'static Cache<T>,
    k: String,
    f: impl FnOnce() -> crate::error::Result<T>,
) -> crate::error::Result<Arc<T>> {
    let map = cache.get_or_init(Default::default);
    if let Some(v) = map.lock().expect("paper cache").get(&k) {
        return Ok(Arc::clone(v));
    }
    let v = Arc::new(f()?);
    map.lock().expect("paper cache").insert(k, Arc::clone(&v));
    Ok(v)
}

/// Run scenes (in parallel, in order), each at most once per process.
pub fn results(scenes: &[Scene]) -> crate::error::Result<Vec<Arc<SceneResult>>> {
    static CACHE: Cache<SceneResult> = OnceLock::new();
    let lib = library()?;
    scenes
        .par_iter()
        .map(|s| {
            cached(&CACHE, key(s), || {
                sim::run(s, lib).map_err(|e| crate::error::error!("paper: {e}"))
            })
        })
        .collect()
}

pub fn result(scene: &Scene) -> crate::error::Result<Arc<SceneResult>> {
    Ok(results(std::slice::from_ref(scene))?.remove(0))
}

/// The scene's history as `simulate --history` writes it (whole duration, automatic grid).
pub fn history(scene: &Scene) -> crate::error::Result<Arc<(SceneResult, History)>> {
    static CACHE: Cache<(SceneResult, History)> = OnceLock::new();
    let lib = library()?;
    cached(&CACHE, key(scene), || {
        sim::run_history(&sim::history_scene(scene), lib, &sim::Sampling::Auto)
            .map_err(|e| crate::error::error!("paper: {e}"))
    })
}

/// History columns the rows read (from the table, [`HistoryColumn`]).
pub mod col {
    use crate::sim::HistoryColumn as C;
    pub const T: C = C::T;
    pub const THETA: C = C::Theta;
    pub const FLYWHEEL_A: C = C::FlywheelAVel;
    pub const FLYWHEEL_B: C = C::FlywheelBVel;
    pub const CLUTCH_A: C = C::ClutchForceA;
    pub const CLUTCH_B: C = C::ClutchForceB;
    pub const DEVICE_FORCE: C = C::DeviceForce;
    pub const X_DOT: C = C::XDot;
    pub const THETA_DOT: C = C::ThetaDot;
    pub const E_STRUCTURE: C = C::EStructure;
    pub const E_INERTER: C = C::EInerter;
    /// The device-side energy: flywheels + clutch spring and everything the device dissipates.
    pub const DEVICE_ENERGY: [C; 5] = [
        C::EInerter,
        C::EDeviceDamping,
        C::EFriction,
        C::EDisengagement,
        C::EReset,
    ];
}

/// A rocking block's impact event.
pub const IMPACT: &str = "impact";

/// The sequential law's engagement switch event.
pub const SEQUENTIAL_SWITCH: &str = "sequential_switch";

pub fn column(h: &History, column: HistoryColumn) -> crate::error::Result<Vec<f64>> {
    h.column(column)
        .ok_or_else(|| crate::error::error!("paper: history has no column {column}"))
}

/// A flexible structure's check on both responses the paper plots, rotation and column
/// deformation (prefixed so); the verdict is the worse of the two.
pub fn rotation_and_deformation(
    per: impl Fn(Measure) -> crate::error::Result<super::fair::Judgement>,
) -> crate::error::Result<super::fair::Judgement> {
    Ok(super::fair::both(
        per(Measure::Rotation)?,
        "rotation",
        per(Measure::Deformation)?,
        "deformation",
    ))
}

/// What a row reads from a scene's result; None where the structure overturned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Measure {
    /// |θ|max / α.
    Rotation,
    /// Column deformation |u|max (m), flexible structures.
    Deformation,
    Drift,
    /// The paper's acceleration: a rigid block's |θ̈|max/p² between impacts (§3, Fig. 5b,
    /// Fig. 12), a flexible structure's absolute horizontal acceleration |ẍ + a_g|max/g
    /// (Fig. 14, Fig. 24).
    Acceleration,
    /// The other one, reported beside: |ẍ + a_g|max/g of a rigid block's centre of mass.
    OtherAcceleration,
}

impl Measure {
    pub fn of(self, r: &SceneResult) -> Option<f64> {
        if r.overturned {
            return None;
        }
        let rigid = r.peaks.angular_acceleration_p2;
        Some(match self {
            Measure::Rotation => r.peak_rotation_ratio,
            Measure::Deformation => r.peaks.deformation,
            Measure::Drift => r.peaks.drift,
            Measure::Acceleration => rigid.unwrap_or(r.peaks.abs_acceleration_g),
            Measure::OtherAcceleration => r.peaks.abs_acceleration_g,
        })
    }

    pub fn series(self, rs: &[Arc<SceneResult>]) -> Series {
        rs.iter().map(|r| self.of(r)).collect()
    }
}

/// `from, from + step, …, to`.
pub fn grid(from: f64, to: f64, step: f64) -> Vec<f64> {
    let n = ((to - from) / step).round() as usize;
    (0..=n).map(|i| from + i as f64 * step).collect()
}

/// The same scene at each ωg/p of `xs`.
pub fn at_frequencies(scene: &Scene, xs: &[f64]) -> Vec<Scene> {
    xs.iter()
        .map(|&r| {
            let mut s = scene.clone();
            if let Excitation::Pulse { frequency, .. } = &mut s.excitation {
                *frequency = Frequency::Ratio(r);
            }
            s
        })
        .collect()
}

/// Fig. 12's axis: ωg/p = 2…10, step 0.25.
pub fn rigid_axis() -> Vec<f64> {
    grid(2.0, 10.0, 0.25)
}

/// Figs. 16, 18–23's axis: ωg/p = 3…20, step 1.
pub fn flexible_axis() -> Vec<f64> {
    grid(3.0, 20.0, 1.0)
}

/// Fig. 24's axis: ωn = 2…29 rad/s, step 3.
pub fn record_axis() -> Vec<f64> {
    grid(2.0, 29.0, 3.0)
}

/// The Fig. 12 spectrum (α = 10°, A/(gα) = 1.5, 15 s) of `device`.
pub fn rigid_spectrum(device: Device) -> crate::error::Result<Vec<Arc<SceneResult>>> {
    let scene = Scene {
        duration: 15.0,
        ..rigid_fig8(device)
    };
    results(&at_frequencies(&scene, &rigid_axis()))
}

/// The §7 spectrum (Fig. 14's structure, 15 s) of `device`.
pub fn flexible_spectrum(device: Device) -> crate::error::Result<Vec<Arc<SceneResult>>> {
    flexible_spectrum_at(device, 8.0)
}

/// The §7 spectrum with the column at ωn/p = `omega_n_p`.
pub fn flexible_spectrum_at(
    device: Device,
    omega_n_p: f64,
) -> crate::error::Result<Vec<Arc<SceneResult>>> {
    let scene = Scene {
        duration: 15.0,
        structure: presets::flexible_structure(omega_n_p * presets::flexible_p()),
        ..flexible_fig14(device)
    };
    results(&at_frequencies(&scene, &flexible_axis()))
}

/// The §7 spectrum with the column at ωn/p = `omega_n_p` over the ωg/p of `xs`.
pub fn flexible_spectrum_on(
    device: Device,
    omega_n_p: f64,
    xs: &[f64],
) -> crate::error::Result<Vec<Arc<SceneResult>>> {
    let scene = Scene {
        duration: 15.0,
        structure: presets::flexible_structure(omega_n_p * presets::flexible_p()),
        ..flexible_fig14(device)
    };
    results(&at_frequencies(&scene, xs))
}

/// Table 1's records, in order, and which are the real records (3 and 5 ship as stand-ins,
/// records/README.md).
pub const RECORDS: [(&str, bool); 5] = [
    ("landers", true),
    ("northridge", true),
    ("imperial_valley", false),
    ("superstition_hills", true),
    ("palm_springs", false),
];

/// Fig. 24's spectrum of `device` under `record` (60 s).
pub fn record_spectrum(
    record: &str,
    device: Device,
) -> crate::error::Result<Vec<Arc<SceneResult>>> {
    let scenes: Vec<Scene> = record_axis()
        .into_iter()
        .map(|w| presets::flexible_record(record, w, device.clone(), 60.0))
        .collect();
    results(&scenes)
}

/// The mechanistic clutch (σ = 0.5, paper defaults) changed by `f`.
pub fn clutch_with(f: impl FnOnce(&mut Clutch)) -> Device {
    let mut c = Clutch::paper_default(presets::SIGMA);
    f(&mut c);
    Device::Mechanistic(c)
}

/// A change of one setting the paper does not state: the parameter it changes (None for the
/// reset rule, which is no grid parameter), how the paper's rows name the change, the change.
#[derive(Clone, Copy)]
pub struct Unstated {
    pub param: Option<Param>,
    pub name: &'static str,
    pub change: fn(&mut Clutch),
}

const fn unstated(param: Option<Param>, name: &'static str, change: fn(&mut Clutch)) -> Unstated {
    Unstated {
        param,
        name,
        change,
    }
}

/// The plausible values of the clutch settings the paper leaves unstated, for the sensitivity
/// runs behind each disagreement: c̄ (rigid block; §5.2 chose 1 s⁻¹ "to obtain comparable
/// responses"), kθ, ρ, η and the reset rule.
pub const UNSTATED: [Unstated; 8] = [
    unstated(Some(Param::Cbar), "c̄ = 0.5 s⁻¹", |c| {
        c.damping = Damping::CBar(0.5)
    }),
    unstated(Some(Param::Cbar), "c̄ = 2 s⁻¹", |c| {
        c.damping = Damping::CBar(2.0)
    }),
    unstated(
        Some(Param::ClutchFrequencyRatio),
        "√(kθ/J) = 10 p",
        |c| c.stiffness = ClutchStiffness::FrequencyRatio(10.0),
    ),
    unstated(
        Some(Param::ClutchFrequencyRatio),
        "√(kθ/J) = 50 p",
        |c| c.stiffness = ClutchStiffness::FrequencyRatio(50.0),
    ),
    unstated(
        Some(Param::ClutchFrequencyRatio),
        "√(kθ/J) = 100 p",
        |c| c.stiffness = ClutchStiffness::FrequencyRatio(100.0),
    ),
    unstated(Some(Param::Rho), "ρ = 0.1 m", |c| c.rho = 0.1),
    unstated(Some(Param::Eta), "η = 1000 s/rad", |c| c.eta = 1000.0),
    unstated(None, "strict reset rule", |c| c.reset = ResetRule::Strict),
];

/// [`UNSTATED`] without the device damping c̄, for rows whose damping the paper states (ξθ)
/// or whose claim is about the damping.
pub fn unstated_but_damping() -> Vec<Unstated> {
    UNSTATED
        .iter()
        .filter(|u| u.param != Some(Param::Cbar))
        .copied()
        .collect()
}

/// `device` with `change` applied when it is a mechanistic clutch.
pub fn changed(device: &Device, change: fn(&mut Clutch)) -> Device {
    match device {
        Device::Mechanistic(c) => {
            let mut c = c.clone();
            change(&mut c);
            Device::Mechanistic(c)
        }
        d => d.clone(),
    }
}

/// Judge the same check with each of the `unstated` changes applied to the clutch(es) the
/// check runs: the reason line ("agrees for …; disagrees for …") and its values.
pub fn sensitivity(
    unstated: &[Unstated],
    check: impl Fn(fn(&mut Clutch)) -> crate::error::Result<super::fair::Judgement>,
) -> crate::error::Result<(String, Vec<(String, f64)>)> {
    let variants: Vec<(String, super::fair::Judgement)> = unstated
        .iter()
        .map(|u| Ok((u.name.to_string(), check(u.change)?)))
        .collect::<crate::error::Result<_>>()?;
    Ok(super::fair::sensitivity("unstated settings", &variants))
}

/// No change (the rows' own settings).
pub fn as_is(_: &mut Clutch) {}

/// Energy dissipated inside the device by the end of a run (viscous, friction, the sequential
/// law's disengagement loss, resets) as a share of the input: the one measure of "energy
/// dissipation" every row uses, so runs that take in different energy compare fairly. None
/// where the structure overturned.
pub fn device_share(r: &SceneResult) -> Option<f64> {
    let e = &r.energy;
    (!r.overturned).then(|| (e.device_damping + e.friction + e.disengagement + e.reset) / e.input)
}

/// Energy the device hands back to the structure over what it took, from the history's
/// device-side energy D (a drop of D is energy flowing back).
pub fn returned_fraction(scene: &Scene) -> crate::error::Result<f64> {
    let h = history(scene)?;
    let parts: Vec<Vec<f64>> = col::DEVICE_ENERGY
        .iter()
        .map(|c| column(&h.1, *c))
        .collect::<crate::error::Result<_>>()?;
    let d: Vec<f64> = (0..parts[0].len())
        .map(|i| parts.iter().map(|p| p[i]).sum())
        .collect();
    let (mut taken, mut returned) = (0.0, 0.0);
    for w in d.windows(2) {
        let delta = w[1] - w[0];
        if delta > 0.0 {
            taken += delta;
        } else {
            returned -= delta;
        }
    }
    Ok(if taken > 0.0 { returned / taken } else { 0.0 })
}
