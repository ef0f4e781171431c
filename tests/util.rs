//! Helpers shared by the test modules.

use std::process::{Command, Output};

/// The `rocklab` binary under test, ready for arguments.
pub fn rocklab_command(args: &[&str]) -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_rocklab"));
    cmd.args(args);
    cmd
}

/// Run the `rocklab` binary with `args` and collect its output.
pub fn rocklab(args: &[&str]) -> Output {
    rocklab_command(args).output().expect("rocklab runs")
}

/// `rocklab run STUDY --out OUT --quiet`.
pub fn run_into(study: &str, out: &std::path::Path) -> Output {
    rocklab(&["run", study, "--out", out.to_str().unwrap(), "--quiet"])
}

/// Load and run a study file with all cores; panics with the study's error if it fails to load.
pub fn run_study_file(path: &std::path::Path) -> rocklab::sweep::SweepResults {
    let study = rocklab::study::Study::load(path).unwrap_or_else(|e| panic!("{e}"));
    let cancel = std::sync::atomic::AtomicBool::new(false);
    rocklab::sweep::run_study(
        &study,
        &Default::default(),
        rocklab::excitation::library::global().unwrap(),
        &cancel,
        &|_| {},
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// `v` at 4 significant digits (scientific outside [1e-3, 1e5)), so snapshots and reports do
/// not churn on last-bit differences between machines.
pub fn sig4(v: f64) -> String {
    if !v.is_finite() || v == 0.0 {
        return format!("{v}");
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        return format!("{v:.3e}");
    }
    let decimals = (3 - a.log10().floor() as i32).max(0) as usize;
    format!("{v:.decimals$}")
}

/// Run the `rocklab` binary with `args`, which must succeed (stderr shown if not), and parse
/// its standard output as JSON.
pub fn rocklab_json(args: &[&str]) -> serde_json::Value {
    json_of(rocklab(args))
}

/// The JSON a successful `rocklab` run printed (stderr shown if it failed).
pub fn json_of(out: Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The shipped Fig. 12 study and its Fig. 8 scene (bare block, ωg/p = 4).
pub fn fig12_study_and_fig8_point() -> (rocklab::study::Study, rocklab::study::ScenePoint) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/fig12_rigid_spectra.ron"
    );
    let study = rocklab::study::Study::load(std::path::Path::new(path)).unwrap();
    let point = study
        .expand()
        .unwrap()
        .into_iter()
        .find(|p| p.scene.device == rocklab::scene::Device::None && p.coord("ωg/p") == Some(4.0))
        .expect("the Fig. 12 study holds the Fig. 8 scene");
    (study, point)
}
