//! Named scenes of the paper's figures, one definition shared by `rocklab bench`, the tests and
//! the paper checks (`rocklab paper`). Built from the public scene types only (no model or
//! solver internals, no record library: a record is named, and loaded when the scene runs).
//!
//! Where the paper leaves a value unstated, the preset says which value rocklab chose.

use crate::excitation::{G, PulseShape};
use crate::scene::*;

/// Apparent mass ratio σ of every protected system in the paper's §5–§8.
pub const SIGMA: f64 = 0.5;

/// Frequency parameter p (rad/s) of rocklab's rigid block for Figs. 5, 8, 11 and 12. The paper
/// gives α, A/(gα) and ωg/p but not the block's size; p matters only through the device's
/// dimensional parameters (c̄ = 1 s⁻¹ against p). p = 2 rad/s is R = 3g/16 ≈ 1.84 m.
pub const RIGID_P: f64 = 2.0;

/// Flexible structure of §6–§8: R0 = 10 m, α = 0.2, ξ = 0.02 (p = √(g/R0) ≈ 0.990 rad/s).
pub const FLEXIBLE_R0: f64 = 10.0;
pub const FLEXIBLE_ALPHA: f64 = 0.2;
pub const FLEXIBLE_XI: f64 = 0.02;

/// A named scene.
#[derive(Clone, Debug)]
pub struct Preset {
    /// Short unique name, e.g. `fig8-mechanistic`.
    pub name: &'static str,
    /// What the paper shows with it.
    pub description: &'static str,
    pub scene: Scene,
}

/// Half-diagonal R (m) of a rectangular block with frequency parameter p: p² = 3g/(4R).
pub fn rigid_size_for_p(p: f64) -> f64 {
    3.0 * G / (4.0 * p * p)
}

/// One-sine acceleration pulse of the given amplitude at ωg/p = `ratio`.
pub fn sine_pulse(amplitude: Amplitude, ratio: f64) -> Excitation {
    Excitation::Pulse {
        shape: PulseShape::Sine,
        amplitude,
        frequency: Frequency::Ratio(ratio),
    }
}

/// A library record (name, Table 1 number or path) at its natural scale, loaded when the scene
/// runs.
pub fn record(name: &str) -> Excitation {
    Excitation::Record {
        name: name.into(),
        scale: RecordScale::Factor(1.0),
        baseline: false,
        kinks: Default::default(),
    }
}

/// A scene with the defaults every preset shares: Housner impact, the default tolerance, at
/// rest on the ground, run to the end.
pub fn scene(structure: Structure, device: Device, excitation: Excitation, duration: f64) -> Scene {
    Scene {
        structure,
        device,
        impact: Impact::default(),
        excitation,
        vertical: None,
        duration,
        rtol: default_rtol(),
        initial_rotation: 0.0,
        stop_when_settled: false,
        closed_form_contact: default_closed_form_contact(),
        method: Default::default(),
    }
}

/// The paper's flexible structure with column frequency ωn (rad/s).
pub fn flexible_structure(omega_n: f64) -> Structure {
    Structure::Flexible(FlexibleStructure {
        r0: FLEXIBLE_R0,
        alpha: FLEXIBLE_ALPHA,
        mass: 1.0,
        xi: FLEXIBLE_XI,
        omega_n,
    })
}

/// p (rad/s) of the paper's flexible structure.
pub fn flexible_p() -> f64 {
    (G / FLEXIBLE_R0).sqrt()
}

/// Single inerter σ = 0.5, rigidly attached (no clutch, no dissipation).
pub fn inerter() -> Device {
    Device::Inerter {
        sigma: SIGMA,
        coupling: Coupling::Rigid,
    }
}

/// Single inerter σ = 0.5 "with dissipation" (§6.2): an explicit flywheel behind the default
/// clutch spring, c̄ = 1 s⁻¹.
pub fn inerter_with_dissipation() -> Device {
    Device::Inerter {
        sigma: SIGMA,
        coupling: Coupling::Flywheel {
            stiffness: ClutchStiffness::default(),
            rho: default_rho(),
            damping: Damping::CBar(1.0),
        },
    }
}

/// Twin clutched inerters σ = 0.5, sequential (Makris–Kampas) law.
pub fn sequential() -> Device {
    Device::Sequential { sigma: SIGMA }
}

/// Twin clutched inerters σ = 0.5, mechanistic clutch with the paper's c̄ = 1 s⁻¹ (§5.2, §6.2)
/// and the default clutch stiffness.
pub fn mechanistic() -> Device {
    Device::Mechanistic(Clutch::paper_default(SIGMA))
}

/// The mechanistic clutch with its damping given as ξθ (§6.3, §7.2, §8).
pub fn mechanistic_xi_theta(xi_theta: f64) -> Device {
    Device::Mechanistic(Clutch {
        damping: Damping::XiTheta(xi_theta),
        ..Clutch::paper_default(SIGMA)
    })
}

/// The rigid block of Figs. 5, 8, 11, 12: α = 10°, p = 2 rad/s, one-sine A/(gα) = 1.5,
/// ωg/p = 4, 10 s.
pub fn rigid_fig8(device: Device) -> Scene {
    scene(
        Structure::Rigid(RigidBlock {
            size: rigid_size_for_p(RIGID_P),
            alpha: 10f64.to_radians(),
            mass: 1.0,
            form: Form::Exact,
        }),
        device,
        sine_pulse(Amplitude::AlphaRatio(1.5), 4.0),
        10.0,
    )
}

/// The flexible structure of Fig. 14 (docs/MODEL.md case 6): R0 = 10 m, α = 0.2, ξ = 0.02,
/// ωn/p = 8, one-sine A/(g tan α) = 1.5, ωg/p = 8, 30 s.
pub fn flexible_fig14(device: Device) -> Scene {
    scene(
        flexible_structure(8.0 * flexible_p()),
        device,
        sine_pulse(Amplitude::TanAlphaRatio(1.5), 8.0),
        30.0,
    )
}

/// The Fig. 24 structure (R0 = 10 m, α = 0.2, ξ = 0.02) with column frequency ωn (rad/s) under
/// a record at its natural scale for `duration` seconds.
pub fn flexible_record(record_name: &str, omega_n: f64, device: Device, duration: f64) -> Scene {
    scene(
        flexible_structure(omega_n),
        device,
        record(record_name),
        duration,
    )
}

/// The Fig. 24 structure at ωn = 12 rad/s under Landers–Lucerne (48 s record + 10 s).
pub fn flexible_landers(device: Device) -> Scene {
    flexible_record("landers", 12.0, device, 58.0)
}

/// The Fig. 24 structure at ωn = 12 rad/s under Northridge–Rinaldi (20 s record + 10 s).
pub fn flexible_northridge(device: Device) -> Scene {
    flexible_record("northridge", 12.0, device, 30.0)
}

/// The Fig. 24 column on a base wide enough (α = 1.3) never to lift under Landers: the whole
/// run is full contact.
pub fn flexible_wide_landers(device: Device) -> Scene {
    let mut s = flexible_landers(device);
    if let Structure::Flexible(f) = &mut s.structure {
        f.alpha = 1.3;
    }
    s
}

/// A rigid block R = 5 m, α = 0.2 under Northridge–Rinaldi (30 s).
pub fn rigid_northridge(device: Device) -> Scene {
    scene(
        Structure::Rigid(RigidBlock {
            size: 5.0,
            alpha: 0.2,
            mass: 1.0,
            form: Form::Exact,
        }),
        device,
        record("northridge"),
        30.0,
    )
}

/// Fig. 8 (and 11): the rigid block bare, with a single inerter, and with twin clutched
/// inerters under both clutch laws.
pub fn fig8() -> Vec<Preset> {
    vec![
        Preset {
            name: "fig8-none",
            description: "Fig. 8 rigid block, bare (σ = 0)",
            scene: rigid_fig8(Device::None),
        },
        Preset {
            name: "fig8-inerter",
            description: "Fig. 8 rigid block, single inerter σ = 0.5",
            scene: rigid_fig8(inerter()),
        },
        Preset {
            name: "fig8-sequential",
            description: "Fig. 8 rigid block, sequential clutch σ = 0.5",
            scene: rigid_fig8(sequential()),
        },
        Preset {
            name: "fig8-mechanistic",
            description: "Fig. 8 rigid block, mechanistic clutch σ = 0.5, c̄ = 1 s⁻¹",
            scene: rigid_fig8(mechanistic()),
        },
    ]
}

/// Fig. 14 (and 15): the flexible structure bare, with single inerters without and with
/// dissipation, and with twin clutched inerters under both clutch laws.
pub fn fig14() -> Vec<Preset> {
    vec![
        Preset {
            name: "fig14-none",
            description: "Fig. 14 flexible structure, bare (σ = 0)",
            scene: flexible_fig14(Device::None),
        },
        Preset {
            name: "fig14-inerter",
            description: "Fig. 14 flexible structure, single inerter without dissipation",
            scene: flexible_fig14(inerter()),
        },
        Preset {
            name: "fig14-inerter-dissipative",
            description: "Fig. 14 flexible structure, single inerter with c̄ = 1 s⁻¹",
            scene: flexible_fig14(inerter_with_dissipation()),
        },
        Preset {
            name: "fig14-sequential",
            description: "Fig. 14 flexible structure, sequential clutch σ = 0.5",
            scene: flexible_fig14(sequential()),
        },
        Preset {
            name: "fig14-mechanistic",
            description: "Fig. 14 flexible structure, mechanistic clutch σ = 0.5, c̄ = 1 s⁻¹",
            scene: flexible_fig14(mechanistic()),
        },
    ]
}

/// Every named preset.
pub fn all() -> Vec<Preset> {
    let mut v = fig8();
    v.extend(fig14());
    v
}

/// The preset of this name.
pub fn by_name(name: &str) -> Option<Preset> {
    all().into_iter().find(|p| p.name == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_scenes_valid() {
        let all = all();
        for (i, p) in all.iter().enumerate() {
            assert!(all[i + 1..].iter().all(|q| q.name != p.name), "{}", p.name);
            p.scene
                .validate()
                .unwrap_or_else(|e| panic!("{}: {e}", p.name));
        }
        assert_eq!(
            by_name("fig8-mechanistic").unwrap().scene,
            rigid_fig8(mechanistic())
        );
    }

    #[test]
    fn rigid_block_has_the_stated_p() {
        let s = rigid_fig8(Device::None);
        assert!((s.structure.p() - RIGID_P).abs() < 1e-12);
    }
}
