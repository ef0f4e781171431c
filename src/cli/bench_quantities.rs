//! `rocklab bench --quantity-costs`: what each optional quantity costs a scene. The same scene
//! runs computing the rotation alone, the rotation plus one optional quantity, and everything;
//! a quantity's cost is its run's time over the rotation-only run's, its share that extra
//! over the time of the full set. Times are the best of repeats, the cells of a scene in turn.

use super::bench::BenchArgs;
use crate::presets::{mechanistic, rigid_fig8, rigid_size_for_p};
use crate::scene::*;
use crate::sim::{self, Bounds, Measures, SceneResult};
use std::time::Instant;

/// The scenes: the Fig. 8 block bare and with mechanistic clutches, and a cell of the shipped
/// overturning map near its boundary (mechanistic, A/(g tanα) = 2, ωg/p = 4, 10 s).
fn scenes() -> Vec<(&'static str, Scene)> {
    let map_cell = Scene {
        structure: Structure::Rigid(RigidBlock {
            size: rigid_size_for_p(2.0),
            alpha: 10f64.to_radians(),
            mass: 1.0,
            form: Form::Exact,
        }),
        excitation: Excitation::Pulse {
            shape: crate::excitation::PulseShape::Sine,
            amplitude: Amplitude::TanAlphaRatio(2.0),
            frequency: Frequency::Ratio(4.0),
        },
        ..rigid_fig8(mechanistic())
    };
    vec![
        ("rigid bare, Fig. 8", rigid_fig8(Device::None)),
        ("rigid mechanistic, Fig. 8", rigid_fig8(mechanistic())),
        ("overturning map cell (mechanistic)", map_cell),
    ]
}

/// The optional quantities one at a time, each with the rotation.
fn measures() -> Vec<(&'static str, Measures)> {
    let rotation = Measures::ROTATION;
    vec![
        ("rotation only", rotation),
        (
            "+ drift",
            Measures {
                drift: true,
                ..rotation
            },
        ),
        (
            "+ \\|ẍ\\|max (absolute acceleration)",
            Measures {
                abs_acceleration: true,
                ..rotation
            },
        ),
        (
            "+ \\|θ̈\\|max (angular acceleration)",
            Measures {
                angular_acceleration: true,
                ..rotation
            },
        ),
        (
            "+ energy ledger",
            Measures {
                energy: true,
                ..rotation
            },
        ),
        ("all (simulate's default)", Measures::ALL),
    ]
}

/// Wall time of one run of `scene` computing `measures`, and its result.
fn timed_once(scene: &Scene, measures: Measures) -> anyhow::Result<(SceneResult, f64)> {
    let library = crate::excitation::library::global()?;
    let bounds = Bounds {
        measures,
        ..Default::default()
    };
    let start = Instant::now();
    let r = sim::run_bounded(scene, library, bounds)?;
    Ok((r, start.elapsed().as_secs_f64()))
}

pub fn print(args: &BenchArgs) -> anyhow::Result<()> {
    println!(
        "rocklab bench --quantity-costs: best of {} runs per cell (the cells of a scene run \
         in turn, so a load affects them alike), default tolerance",
        args.repeats
    );
    let sets = measures();
    for (name, scene) in scenes() {
        println!("\n## {name} (rtol {:e})\n", scene.rtol);
        println!("| computed | time (µs) | × rotation only | share of the full set | RHS evals |");
        println!("|---|---|---|---|---|");
        let mut best = vec![f64::INFINITY; sets.len()];
        let mut results = Vec::new();
        for _ in 0..args.repeats.max(1) {
            results.clear();
            for (i, (_, m)) in sets.iter().enumerate() {
                let (r, t) = timed_once(&scene, *m)?;
                best[i] = best[i].min(t);
                results.push(r);
            }
        }
        let (rotation, all) = (best[0], best[sets.len() - 1]);
        for (((label, _), r), t) in sets.iter().zip(&results).zip(&best) {
            println!(
                "| {label} | {:.1} | {:.2} | {:.0}% | {} |",
                t * 1e6,
                t / rotation,
                100.0 * (t - rotation) / all,
                r.stats.rhs_evals
            );
        }
    }
    Ok(())
}
