//! `rocklab bench --record-suite`: throughput of a fragility study's scenes. Every component
//! of a record suite at every stripe, for the bare, sequential and mechanistic blocks of
//! `studies/fragility_far_field.ron` (a rigid block α = 0.2 rad, p = 2 rad/s; σ = 0.5, the
//! defaults otherwise; stripes PGA* = PGA/(g tan α) = 1.5 … 8; each scene its record's length
//! plus 10 s, computing the study's quantity, |θ|max/α). Reports scenes per second on one
//! thread (per core) and on two, and the scaling between them.

use super::bench::BenchArgs;
use crate::excitation::library::Library;
use crate::presets::{mechanistic, scene, sequential};
use crate::scene::{Device, Excitation, Form, RecordScale, RigidBlock, Scene, Structure};
use crate::sim;
use crate::study::Quantity;
use rayon::prelude::*;
use std::path::Path;
use std::time::Instant;

/// The stripes of `studies/fragility_far_field.ron` (PGA*).
pub const STRIPES: [f64; 8] = [1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0];
const ALPHA: f64 = 0.2;
const P: f64 = 2.0;
/// Seconds of free motion after each record.
const TAIL: f64 = 10.0;

/// The record files of a suite directory, sorted by name (what a study of the suite runs).
fn suite_files(dir: &Path) -> anyhow::Result<Vec<String>> {
    let entries = std::fs::read_dir(dir).map_err(|e| {
        anyhow::anyhow!(
            "--suite-dir {}: {e} (hint: the FEMA P695 far-field set lives in \
             records/fema-p695/farfield once the record suites are shipped)",
            dir.display()
        )
    })?;
    let mut files: Vec<String> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.extension().is_some_and(|x| {
                ["txt", "at2"].contains(&x.to_ascii_lowercase().to_str().unwrap_or(""))
            })
        })
        .map(|p| p.display().to_string())
        .collect();
    files.sort();
    anyhow::ensure!(
        !files.is_empty(),
        "--suite-dir {}: no record files",
        dir.display()
    );
    Ok(files)
}

/// One scene of the suite: `device` under `record` scaled to the stripe `pga_star`.
fn suite_scene(
    record: &str,
    pga_star: f64,
    device: Device,
    library: &Library,
) -> anyhow::Result<Scene> {
    let block = RigidBlock {
        size: 3.0 * crate::excitation::G / (4.0 * P * P),
        alpha: ALPHA,
        mass: 1.0,
        form: Form::Exact,
    };
    let excitation = Excitation::Record {
        name: record.to_string(),
        scale: RecordScale::Pga(pga_star * ALPHA.tan()),
        baseline: false,
        kinks: Default::default(),
    };
    let mut s = scene(Structure::Rigid(block), device, excitation, 0.0);
    s.duration = sim::motion_for(&s, library)?.end() + TAIL;
    Ok(s)
}

/// (scenes, wall seconds) of running `scenes` on `threads` worker threads.
fn throughput(scenes: &[Scene], library: &Library, threads: usize) -> anyhow::Result<f64> {
    let bounds = sim::Bounds {
        measures: Quantity::measures(&[Quantity::PeakRotationRatio]),
        ..Default::default()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    let start = Instant::now();
    pool.install(|| {
        scenes
            .par_iter()
            .try_for_each(|s| sim::run_bounded(s, library, bounds).map(|_| ()))
    })?;
    Ok(start.elapsed().as_secs_f64())
}

/// Print the record-suite table.
pub fn print(args: &BenchArgs) -> anyhow::Result<()> {
    let library = crate::excitation::library::global()?;
    let mut files = suite_files(&args.suite_dir)?;
    if let Some(n) = args.suite_records {
        // Every k-th component, so a sample spans the suite.
        let k = files.len().div_ceil(n.max(1));
        files = files.into_iter().step_by(k.max(1)).collect();
    }
    println!(
        "rocklab bench --record-suite: {} components of {} × {} stripes (PGA* {:?}), rigid block \
         α = {ALPHA}, p = {P}, record + {TAIL} s, |θ|max/α only; best of {} runs",
        files.len(),
        args.suite_dir.display(),
        STRIPES.len(),
        STRIPES,
        args.repeats.max(1)
    );
    println!();
    println!(
        "| device | scenes | record samples per scene (stops) | 1 thread (scenes/s) | 2 threads (scenes/s) | 2-thread scaling |"
    );
    println!("|---|---|---|---|---|---|");
    for (label, device) in [
        ("bare", Device::None),
        ("sequential", sequential()),
        ("mechanistic", mechanistic()),
    ] {
        let mut scenes = Vec::new();
        let mut samples = 0usize;
        for file in &files {
            for &stripe in &STRIPES {
                let s = suite_scene(file, stripe, device.clone(), library)?;
                if let crate::excitation::Horizontal::Record(m) =
                    sim::motion_for(&s, library)?.ground()
                {
                    samples += m.series.npts();
                }
                scenes.push(s);
            }
        }
        let best = |threads| -> anyhow::Result<f64> {
            let mut best = f64::INFINITY;
            for _ in 0..args.repeats.max(1) {
                best = best.min(throughput(&scenes, library, threads)?);
            }
            Ok(best)
        };
        let (one, two) = (best(1)?, best(2)?);
        let n = scenes.len() as f64;
        println!(
            "| {label} | {} | {:.0} | {:.1} | {:.1} | {:.2} |",
            scenes.len(),
            samples as f64 / n,
            n / one,
            n / two,
            one / two
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::excitation::G;

    /// A suite scene puts the record's PGA at PGA*·g·tan α and lasts the record plus the tail.
    #[test]
    fn a_suite_scene_is_scaled_to_its_stripe_and_outlasts_its_record() {
        let library = crate::excitation::library::global().unwrap();
        let file = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/records/RSN879_LANDERS_LCN239_FN.txt"
        );
        for stripe in [1.5, 8.0] {
            let s = suite_scene(file, stripe, Device::None, library).unwrap();
            let motion = sim::motion_for(&s, library).unwrap();
            let crate::excitation::Horizontal::Record(m) = motion.ground() else {
                panic!("a record scene");
            };
            let pga = m.factor * m.series.pga();
            let target = stripe * G * ALPHA.tan();
            assert!((pga / target - 1.0).abs() < 1e-12, "{pga} vs {target}");
            // 9625 samples 0.005 s apart.
            assert!(
                (s.duration - (9624.0 * 0.005 + TAIL)).abs() < 1e-9,
                "{}",
                s.duration
            );
        }
    }

    #[test]
    fn a_missing_suite_directory_is_named_with_a_hint() {
        let err = suite_files(Path::new("/nonexistent/suite"))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("/nonexistent/suite") && err.contains("hint"),
            "{err}"
        );
    }
}
