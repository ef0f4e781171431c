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

/// One run of a study into `dir` through the sweep's façade (as `rocklab run --out dir`
/// does: it resumes what the directory holds), one thread, stopped after `stop_after`
/// scenes if given.
pub(crate) struct DirSweep {
    pub results: rocklab::sweep::SweepResults,
    pub results_file: std::path::PathBuf,
    pub journal: std::path::PathBuf,
    /// Scenes taken from the journal and scenes computed, as the progress reported them.
    pub reused: usize,
    pub computed: usize,
}

pub(crate) fn sweep_in(
    dir: &std::path::Path,
    study: &rocklab::study::Study,
    points: &[rocklab::study::ScenePoint],
    stop_after: Option<usize>,
) -> DirSweep {
    use rocklab::sweep::{DirRun, OpenOptions, Progress};
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
    let output = DirRun::open(dir, None, study, points.len(), OpenOptions::default()).unwrap();
    let results_file = output.results_path().to_path_buf();
    let journal = output.journal_path().to_path_buf();
    let cancel = AtomicBool::new(false);
    let (reused, computed) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let progress = |p: Progress| {
        if let Progress::SceneDone { reused: r, .. } = p {
            if r { &reused } else { &computed }.fetch_add(1, Ordering::Relaxed);
            let done = reused.load(Ordering::Relaxed) + computed.load(Ordering::Relaxed);
            if stop_after.is_some_and(|n| done >= n) {
                cancel.store(true, Ordering::Relaxed);
            }
        }
    };
    let library = rocklab::excitation::library::global().unwrap();
    let results = output
        .run(
            study,
            points,
            Some(1),
            library,
            None,
            &cancel,
            &progress,
            rocklab::report::WRITERS,
        )
        .unwrap()
        .results;
    DirSweep {
        results,
        results_file,
        journal,
        reused: reused.into_inner(),
        computed: computed.into_inner(),
    }
}

/// `rocklab run default --scene-time-limit LIMIT` into a fresh directory: the outcomes' failure
/// reasons, one per scene (`None` for a scene that finished).
pub(crate) fn default_run_with_scene_time_limit(limit: &str) -> Vec<Option<String>> {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = rocklab(&[
        "run",
        "default",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
        "--scene-time-limit",
        limit,
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let results = rocklab::report::load_results(&out.join("results.json")).unwrap();
    results
        .outcomes
        .into_iter()
        .map(|o| o.result.err())
        .collect()
}
