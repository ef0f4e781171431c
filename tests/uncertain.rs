//! Uncertain parameters (study/uncertain): zero dispersion is the deterministic study bit for
//! bit; draws follow from the seed and each scene's record × stripe, so a killed and resumed
//! `rocklab run` reproduces them; a Latin hypercube of a study is stratified; the total β
//! combines records and parameters by the square-root-of-sum-of-squares rule; bad sections
//! are refused naming file, line and field.

use crate::checkpoint::{finish, journalled, lines, reused, signal, spawn_run, wait_for_lines};
use rocklab::report::fragility::Variant;
use rocklab::report::stripes::{self, StripeRow};
use rocklab::study::uncertain::{Distribution, Range, Sample};
use rocklab::study::{Param, ScenePoint, Study};
use rocklab::sweep::{SceneOutcome, SweepResults};

/// A small fragility study over far-field records (component a) at six PGA stripes,
/// with `impact` and an `uncertain` section spliced in.
fn study_text(records: &str, devices: &str, impact: &str, uncertain: &str) -> String {
    format!(
        r#"(
    version: 1,
    name: "uncertain_test",
    structure: rigid(p: 2.0, alpha: 0.2),
    devices: [{devices}],
    excitation: record(
        suite: (name: "far_field", component: a, records: [{records}]),
        scale: [0.25, 0.35, 0.45, 0.55, 0.7, 1.0],
        scale_to: pga,
        tail: 2.0,
    ),
    quantities: [peak_rotation_ratio],
    spectrum: scale,
    impact: {impact},
    fragility: (damage_states: levels([0.5, 1.0]), bootstrap: 0),
{uncertain}
)"#
    )
}

fn run(study: &Study) -> SweepResults {
    let cancel = std::sync::atomic::AtomicBool::new(false);
    rocklab::sweep::run_study(
        study,
        &Default::default(),
        rocklab::excitation::library::global().unwrap(),
        &cancel,
        &|_| {},
    )
    .unwrap()
}

/// Outcomes without wall-clock times (the one field that differs between two runs).
fn timeless(mut outcomes: Vec<SceneOutcome>) -> Vec<SceneOutcome> {
    for o in &mut outcomes {
        if let Ok(r) = &mut o.result {
            r.wall_seconds = 0.0;
        }
    }
    outcomes
}

fn drawn(p: &ScenePoint) -> &[(String, f64)] {
    match &p.uncertain {
        Some(Sample::Drawn { values, .. }) => values,
        other => panic!("scene {} is not drawn: {other:?}", p.index),
    }
}

#[test]
fn zero_dispersion_is_the_deterministic_study_bit_for_bit() {
    let impact = "housner(restitution: 0.9)";
    let records = "1, 2, 3, 4, 5, 6";
    let plain = Study::from_ron_str(&study_text(records, "none", impact, ""), "plain").unwrap();
    let section = "    uncertain: (seed: 3, alpha: normal(mean: 0.2, sd: 0.0), \
                   restitution: uniform(lo: 0.9, hi: 0.9)),";
    let text = study_text(records, "none", impact, section);
    let uncertain = Study::from_ron_str(&text, "uncertain").unwrap();
    let (a, b) = (run(&plain), run(&uncertain));
    let grid = a.outcomes.len();
    assert_eq!(grid, 6 * 6);
    // The drawn scenes, then as many deterministic companions.
    assert_eq!(b.outcomes.len(), 2 * grid);
    let (drawn_half, companions) = b.outcomes.split_at(grid);
    for (x, y) in timeless(a.outcomes.clone())
        .iter()
        .zip(timeless(drawn_half.to_vec()))
    {
        assert_eq!(
            x.point.key, y.point.key,
            "the same scene, the same cache key"
        );
        assert_eq!(x.point.scene, y.point.scene);
        assert_eq!(x.result, y.result);
        assert_eq!(
            drawn(&y.point),
            [("alpha".to_string(), 0.2), ("restitution".to_string(), 0.9)]
        );
    }
    for (x, c) in a.outcomes.iter().zip(companions) {
        assert_eq!(
            c.point.uncertain,
            Some(Sample::Companion { of: x.point.index })
        );
        assert_eq!(x.point.key, c.point.key);
    }
    // results.csv shows each scene's draw and drawn values (and results.columns.csv says so).
    let csv = String::from_utf8(rocklab::report::results_csv(&b).unwrap()).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let at = header
        .iter()
        .position(|h| *h == "draw")
        .expect("a draw column");
    assert_eq!(header[at + 1..at + 3], ["alpha", "restitution"]);
    let nominal = (csv.lines().skip(1))
        .filter(|l| l.split(',').nth(at) == Some("nominal"))
        .count();
    assert_eq!(nominal, grid);
    let meta = String::from_utf8(rocklab::report::results_columns_csv(&b).unwrap()).unwrap();
    assert!(
        meta.lines()
            .any(|l| l.starts_with("restitution,r,,uncertain parameter")),
        "{meta}"
    );
    // And the fits: the total is the deterministic fit, and so is the records-only one.
    let fit = |study: &Study, results: &SweepResults| {
        let f = study.fragility.as_ref().unwrap();
        stripes::analyse(f, study, &stripes::rows(study, results).unwrap())
    };
    let (fa, fb) = (fit(&plain, &a), fit(&uncertain, &b));
    assert_eq!(fa.curves.len(), fb.curves.len());
    assert!(
        fa.curves.iter().any(|c| c.median.is_some()),
        "no curve fitted"
    );
    for (x, y) in fa.curves.iter().zip(&fb.curves) {
        assert_eq!((x.median, x.beta), (y.median, y.beta));
        assert_eq!((x.median, x.beta), (y.median_records, y.beta_records));
        if y.beta.is_some() {
            assert_eq!(y.beta_parameters(), Some(0.0));
        }
    }
}

/// The uncertain study of the kill/resume and draw tests: α and r drawn around the block's.
fn drawn_study(records: &str, seed: u64) -> String {
    study_text(
        records,
        "none, mechanistic(sigma: 0.5)",
        "housner()",
        &format!(
            "    uncertain: (seed: {seed}, sampling: latin_hypercube, \
             alpha: normal(mean: deg(11.5), sd: deg(0.5)), \
             restitution: uniform(lo: 0.8, hi: 0.95)),"
        ),
    )
}

/// Every device meets the same draw at a record × stripe; the draws are a function of the
/// seed (another seed, other values); the restitution draws of the N = records × stripes
/// places fill the N strata of U(0.8, 0.95) once each; companions sit at the centres.
#[test]
fn draws_follow_the_seed_and_the_record_stripe_and_are_stratified() {
    let study = Study::from_ron_str(&drawn_study("1, 2, 3, 4", 7), "t").unwrap();
    let points = study.expand().unwrap();
    let layout = study.layout().unwrap();
    let grid = layout.len();
    assert_eq!(grid, 2 * 4 * 6);
    assert_eq!(points.len(), 2 * grid);
    let (bare, clutch) = points[..grid].split_at(grid / 2);
    for (b, c) in bare.iter().zip(clutch) {
        assert_eq!(drawn(b), drawn(c), "both devices meet one draw");
    }
    let places = grid / 2;
    let mut strata: Vec<usize> = bare
        .iter()
        .map(|p| {
            let r = drawn(p)[1].1;
            ((r - 0.8) / 0.15 * places as f64) as usize
        })
        .collect();
    strata.sort_unstable();
    assert_eq!(strata, (0..places).collect::<Vec<_>>());
    // The drawn α is the scene's (and its cache key differs from the nominal scene's).
    for p in bare {
        assert_eq!(p.scene.structure.alpha(), drawn(p)[0].1);
    }
    for c in &points[grid..] {
        assert_eq!(c.scene.structure.alpha(), 11.5f64.to_radians());
        assert!(c.group.ends_with("· nominal"), "{}", c.group);
    }
    let again = Study::from_ron_str(&drawn_study("1, 2, 3, 4", 7), "t").unwrap();
    assert_eq!(again.expand().unwrap(), points);
    let other = Study::from_ron_str(&drawn_study("1, 2, 3, 4", 8), "t").unwrap();
    let other = other.expand().unwrap();
    assert!(
        (0..grid).all(|i| drawn(&other[i]) != drawn(&points[i])),
        "seed 8 repeats a draw of seed 7"
    );
}

/// An IDA draws once per record: its hunt climbs one drawn structure, and it has no
/// companions (its records-only dispersion is not computed).
#[test]
fn an_ida_draws_once_per_record() {
    let text = drawn_study("1, 2, 3", 5).replace(
        "fragility: (",
        "fragility: (method: ida(resolution: 0.05), ",
    );
    let study = Study::from_ron_str(&text, "ida").unwrap();
    assert!(rocklab::sweep::is_ida(&study));
    let points = study.expand().unwrap();
    assert_eq!(points.len(), study.layout().unwrap().len());
    let record = |p: &ScenePoint| match &p.scene.excitation {
        rocklab::scene::Excitation::Record { name, .. } => name.clone(),
        _ => unreachable!(),
    };
    for p in &points {
        for q in &points {
            let same_draw = drawn(p) == drawn(q);
            assert_eq!(
                same_draw,
                record(p) == record(q),
                "{} vs {}",
                p.group,
                q.group
            );
        }
    }
}

/// A standard normal by Box–Muller from a seeded generator.
fn normals(seed: u64, n: usize) -> Vec<f64> {
    let mut rng = fastrand::Rng::with_seed(seed);
    (0..n)
        .map(|_| {
            let (u, v) = (1.0 - rng.f64(), rng.f64());
            (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
        })
        .collect()
}

/// Capacities ln C = ln 0.8 + 0.4 z (records) and, per record × stripe, a parameter term
/// 0.3 w: the companions exceed at IM ≥ C, the drawn scenes at IM ≥ C·e^{0.3 w}. The total
/// is then lognormal with β = √(0.4² + 0.3²) = 0.5 exactly, so the fitted total, records-only
/// and parameter dispersions must come out near 0.5, 0.4 and 0.3 (400 records: standard
/// errors ≈ 0.02), and the total above the records-only one.
#[test]
fn the_total_beta_adds_the_parameters_to_the_records_by_srss() {
    let text = drawn_study("1", 1);
    let study = Study::from_ron_str(&text, "t").unwrap();
    let f = study.fragility.clone().unwrap();
    let ims: Vec<f64> = (0..12).map(|k| 0.25 * 1.25f64.powi(k)).collect();
    let (records, (beta_r, beta_u)) = (400, (0.4, 0.3));
    let z = normals(11, records);
    let w = normals(12, records * ims.len());
    let row = |record: usize, im: f64, capacity: f64, companion: bool| StripeRow {
        variant: Variant {
            device: "none".into(),
            params: vec![],
        },
        record: format!("r{record}"),
        component: String::new(),
        im,
        scale: im,
        // The damage measure grows with IM and reaches 1 at the capacity.
        values: vec![Some(im / capacity)],
        overturned: false,
        failed: None,
        drawn: vec![],
        draw: (!companion).then_some(0),
        companion,
    };
    let mut rows = Vec::new();
    for r in 0..records {
        let capacity = 0.8 * (beta_r * z[r]).exp();
        for (s, &im) in ims.iter().enumerate() {
            let drawn = capacity * (beta_u * w[r * ims.len() + s]).exp();
            rows.push(row(r, im, drawn, false));
            rows.push(row(r, im, capacity, true));
        }
    }
    let report = stripes::analyse(&f, &study, &rows);
    let c = (report.curves.iter())
        .find(|c| c.damage_state == 1.0)
        .unwrap();
    let (total, alone) = (c.beta.unwrap(), c.beta_records.unwrap());
    let parameters = c.beta_parameters().unwrap();
    assert!(total >= alone, "{total} < {alone}");
    assert!((total - 0.5).abs() < 0.05, "β_total {total}");
    assert!((alone - beta_r).abs() < 0.05, "β_records {alone}");
    assert!(
        (parameters - beta_u).abs() < 0.08,
        "β_parameters {parameters}"
    );
    // The parameters' share is the SRSS remainder of the two fits, exactly.
    assert!((parameters.powi(2) + alone.powi(2) - total.powi(2)).abs() < 1e-12);
    // Both medians near e^{ln 0.8} (the parameter term has median 1).
    let (m, mr) = (c.median.unwrap(), c.median_records.unwrap());
    assert!(
        (m / 0.8 - 1.0).abs() < 0.1 && (mr / 0.8 - 1.0).abs() < 0.1,
        "{m} {mr}"
    );
}

#[test]
fn the_section_round_trips_through_the_writer() {
    let text = drawn_study("1, 2", 7).replace(
        "restitution: uniform(lo: 0.8, hi: 0.95)",
        "restitution: uniform(lo: 0.8, hi: 0.95), size: lognormal(median: 2.0, beta: 0.1)",
    );
    // (size and p: the study gives p, the draw replaces the block's size.)
    let study = Study::from_ron_str(&text, "t").unwrap();
    let kept = study.to_ron_keeping(Some(&text)).text;
    assert!(kept.contains("deg(11.5)"), "{kept}");
    assert_eq!(Study::from_ron_str(&kept, "kept").unwrap(), study);
    let fresh = study.to_ron_keeping(None).text;
    assert_eq!(
        Study::from_ron_str(&fresh, "fresh").unwrap(),
        study,
        "{fresh}"
    );
    let plain = study.to_ron_string();
    assert_eq!(Study::from_ron_str(&plain, "plain").unwrap(), study);
}

/// Each bad section is refused by `Study::load` with the file, the line of the offending
/// field, the field's path and a hint.
#[test]
fn bad_sections_are_refused_naming_file_line_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, &str, &str); 8] = [
        ("alhpa: normal(mean: 0.2, sd: 0.01)", "alhpa", "alpha"),
        (
            "alpha: normal(mean: 0.2, sd: -0.01)",
            "uncertain.alpha",
            "negative",
        ),
        (
            "restitution: uniform(lo: 0.95, hi: 0.8)",
            "uncertain.restitution",
            "above",
        ),
        (
            "size: lognormal(median: 0.0, beta: 0.1)",
            "uncertain.size",
            "not positive",
        ),
        (
            "restitution: normal(mean: 0.95, sd: 0.05)",
            "uncertain.restitution",
            "outside",
        ),
        (
            "alpha: uniform(lo: 0.0, hi: 1.7)",
            "uncertain.alpha",
            "outside",
        ),
        (
            "size: lognormal(median: 2.0, beta: deg(1))",
            "beta",
            "not an angle",
        ),
        (
            "k_theta: normal(mean: 1000.0, sd: 10.0)",
            "uncertain.k_theta",
            "clutch",
        ),
    ];
    for (i, (field, names, says)) in cases.iter().enumerate() {
        let section = format!("    uncertain: (\n        seed: 1,\n        {field},\n    ),");
        let text = study_text("1", "none", "housner()", &section);
        let line = text.lines().position(|l| l.contains(field)).unwrap() + 1;
        let path = dir.path().join(format!("bad{i}.ron"));
        std::fs::write(&path, &text).unwrap();
        let e = Study::load(&path).unwrap_err();
        let shown = e.to_string();
        assert_eq!(e.origin, path.display().to_string(), "{shown}");
        assert_eq!(e.line, Some(line), "{field}: {shown}");
        assert!(
            e.field.as_deref().is_some_and(|f| f.contains(names)) || shown.contains(names),
            "{field}: {shown}"
        );
        assert!(shown.contains(says), "{field}: {shown}");
        assert!(e.hint.is_some(), "{field}: {shown}");
    }
    // Not a fragility study: refused, naming the section.
    let spectra = study_text(
        "1",
        "none",
        "housner()",
        "    uncertain: (alpha: normal(mean: 0.2, sd: 0.01)),",
    )
    .replace(
        "    fragility: (damage_states: levels([0.5, 1.0]), bootstrap: 0),\n",
        "",
    );
    let e = Study::from_ron_str(&spectra, "spectra.ron").unwrap_err();
    assert_eq!(e.field.as_deref(), Some("uncertain"), "{e}");
    assert!(e.line.is_some(), "{e}");
}

/// A `rocklab run` of an uncertain study killed (SIGKILL) mid-sweep and run again reuses every
/// journalled scene, computes each scene once over both runs, and ends with the outcomes of an
/// uninterrupted run: the same draws (recorded in each scene) and the same results.
#[test]
fn a_killed_and_resumed_run_reproduces_the_draws() {
    let records = (1..=22)
        .map(|r| r.to_string())
        .collect::<Vec<_>>()
        .join(", ");
    let text = drawn_study(&records, 7);
    let study = Study::from_ron_str(&text, "t").unwrap();
    let scenes = study.expand().unwrap().len();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("uncertain.ron");
    std::fs::write(&path, &text).unwrap();
    let study_path = path.display().to_string();
    let load = |out: &std::path::Path| {
        timeless(
            rocklab::report::load_results(&out.join("results.json"))
                .unwrap()
                .outcomes,
        )
    };
    let reference_dir = dir.path().join("reference");
    let o = crate::util::run_into(&study_path, &reference_dir);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let reference = load(&reference_dir);
    assert_eq!(reference.len(), scenes);
    // The draws recorded are the expansion's: a function of the study alone.
    let points = study.expand().unwrap();
    for (o, p) in reference.iter().zip(&points) {
        assert_eq!(o.point.uncertain, p.uncertain);
    }
    let out = dir.path().join("out");
    let journal = out.join("results.journal");
    let mut child = spawn_run(&study_path, &out, &["--jobs", "1"]);
    wait_for_lines(&mut child, &journal, 1 + 12);
    signal(&child, "KILL");
    let (status, stderr) = finish(child);
    assert!(!status.success(), "SIGKILL must end the run: {stderr}");
    let before = journalled(&journal);
    assert!(
        (12..scenes).contains(&before),
        "{before} of {scenes} journalled"
    );
    let (status, stderr) = finish(spawn_run(&study_path, &out, &[]));
    assert!(status.success(), "{stderr}");
    assert_eq!(reused(&stderr), before, "every journalled scene is reused");
    assert_eq!(lines(&journal), 1 + scenes, "each scene computed once");
    assert_eq!(load(&out), reference);
}

/// The draws' values and the truncation rule, as the section's documentation states them.
#[test]
fn a_distributions_centre_is_its_companions_value() {
    for (d, centre) in [
        (
            Distribution::Normal {
                mean: 0.2,
                sd: 0.01,
            },
            0.2,
        ),
        (
            Distribution::Lognormal {
                median: 2.0,
                beta: 0.1,
            },
            2.0,
        ),
        (Distribution::Uniform { lo: 0.8, hi: 0.95 }, 0.875),
    ] {
        assert_eq!(d.centre(), centre);
        // The median draw (u = ½) of a symmetric or log-symmetric one is its centre.
        let mid = d.value(0.5, Range::of(Param::Size));
        assert!((mid - centre).abs() < 1e-12 * centre, "{d:?}: {mid}");
    }
}
