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
