//! Every shipped study in studies/ runs here, and its headless summary (counts, one sparkline
//! per spectrum, overturning maps, key numbers at 4 significant digits) is an insta snapshot,
//! snapshots/study_<name>.snap. A change of physics or defaults then shows as a reviewed diff.

use crate::util::{run_study_file, sig4};
use rocklab::report;
use rocklab::sweep::SweepResults;
use std::fmt::Write;
use std::path::PathBuf;

/// Values rounded to 4 significant digits of the spectrum's largest magnitude, so a sparkline
/// does not amplify roundoff (a spectrum of zeros stays flat).
fn quantised(ys: &[Option<f64>]) -> Vec<Option<f64>> {
    let top = ys.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    if top == 0.0 || !top.is_finite() {
        return ys.iter().map(|y| y.map(|_| 0.0)).collect();
    }
    let quantum = 10f64.powi(top.log10().floor() as i32 - 3);
    ys.iter()
        .map(|y| y.map(|v| (v / quantum).round() * quantum))
        .collect()
}

/// The headless summary of a study's results, at a precision that is stable across machines.
fn summary(results: &SweepResults) -> String {
    let mut s = String::new();
    let count = |f: &dyn Fn(&rocklab::sweep::SceneOutcome) -> bool| {
        results.outcomes.iter().filter(|o| f(o)).count()
    };
    let failed = count(&|o| o.result.is_err());
    let overturned = count(&|o| o.result.as_ref().is_ok_and(|r| r.overturned));
    let _ = writeln!(
        s,
        "{} scenes, {overturned} overturned, {failed} failed",
        results.outcomes.len()
    );
    for o in results.outcomes.iter().filter(|o| o.result.is_err()) {
        let _ = writeln!(s, "  failed scene {}: {:?}", o.point.index, o.result);
    }
    if let Some(rows) = report::design::design_rows(results) {
        let num = |v: Option<f64>| v.map_or("-".into(), sig4);
        for r in rows {
            let axes: Vec<String> = r
                .axes
                .iter()
                .map(|(l, v)| format!("{l}={}", sig4(*v)))
                .collect();
            let _ = writeln!(
                s,
                "  {} {} {}: {} in ({}, {}], {} probes, governing {} ({}){}",
                r.device,
                axes.join(" "),
                r.status.name(),
                num(r.value),
                sig4(r.lo),
                sig4(r.hi),
                r.probes,
                r.governing,
                r.achieved_note.map_or(num(r.achieved), String::from),
                if r.fails_above.is_empty() {
                    String::new()
                } else {
                    format!(", fails again at {:?}", r.fails_above)
                },
            );
        }
        return s;
    }
    let spectra = report::spectra(results);
    let width = spectra
        .iter()
        .map(|sp| sp.label.chars().count())
        .max()
        .unwrap_or(0);
    let mut last = None;
    for sp in &spectra {
        if last != Some(sp.quantity) {
            let (lo, hi) = (sp.xs.first().copied(), sp.xs.last().copied());
            let _ = writeln!(
                s,
                "\n{} over {} ({} … {}); blank = overturned or failed",
                sp.quantity.label(),
                sp.axis,
                lo.map_or("-".into(), sig4),
                hi.map_or("-".into(), sig4),
            );
            last = Some(sp.quantity);
        }
        let present: Vec<(f64, f64)> = sp
            .xs
            .iter()
            .zip(&sp.ys)
            .filter_map(|(x, y)| y.map(|y| (*x, y)))
            .collect();
        let key = match present.iter().max_by(|a, b| a.1.total_cmp(&b.1)) {
            Some((x, max)) => {
                let mean = present.iter().map(|p| p.1).sum::<f64>() / present.len() as f64;
                format!("max {} at {}, mean {}", sig4(*max), sig4(*x), sig4(mean))
            }
            None => "all overturned or failed".into(),
        };
        let _ = writeln!(
            s,
            "  {:width$}  {}  {key}",
            sp.label,
            report::sparkline(&quantised(&sp.ys)),
        );
    }
    if let Some(study) = &results.study
        && let Some(f) = &study.fragility
    {
        fragility_summary(&mut s, study, f, results);
    }
    for m in report::maps(results) {
        let _ = writeln!(
            s,
            "\noverturning map, {}: {} (→ {} … {}) × {} (↑); █ overturned, · safe, ? missing",
            m.label,
            m.x_axis,
            m.xs.first().map_or("-".into(), |v| sig4(*v)),
            m.xs.last().map_or("-".into(), |v| sig4(*v)),
            m.y_axis
        );
        for (iy, row) in m.cells.iter().enumerate().rev() {
            let line: String = row
                .iter()
                .map(|c| match c {
                    Some(true) => '█',
                    Some(false) => '·',
                    None => '?',
                })
                .collect();
            let _ = writeln!(s, "  {:>9} {line}", sig4(m.ys[iy]));
        }
    }
    s
}

/// A fragility study's fit: per variant and damage state the status, median, β and their
/// intervals at 4 significant digits, and the exceedances per stripe; then the median ratios.
fn fragility_summary(
    s: &mut String,
    study: &rocklab::study::Study,
    f: &rocklab::study::fragility::Fragility,
    results: &SweepResults,
) {
    let fit = if f.method.ida_resolution().is_some() {
        let ida = report::ida::ida(study, results).expect("the study lays out");
        s.push_str(&report::ida::scenes_line(&ida));
        report::ida::analyse(f, study, &ida.rows)
    } else {
        let rows = report::stripes::rows(study, results).expect("the study lays out");
        report::stripes::analyse(f, study, &rows)
    };
    let num = |v: Option<f64>| v.map_or("-".into(), sig4);
    let _ = writeln!(
        s,
        "\nfragility of {} over {} ({} bootstrap resamples, seed {}):",
        fit.damage_measure, fit.im, fit.bootstrap, fit.seed
    );
    for c in &fit.curves {
        let stripes: Vec<String> = c
            .stripes
            .iter()
            .map(|p| format!("{}/{}", p.exceed, p.n))
            .collect();
        let _ = writeln!(
            s,
            "  {} ≥ {}: {} median {} [{}, {}] β {} [{}, {}]; {}",
            c.variant.label(),
            c.damage_state,
            c.status.name(),
            num(c.median),
            num(c.median_lo),
            num(c.median_hi),
            num(c.beta),
            num(c.beta_lo),
            num(c.beta_hi),
            if c.method == rocklab::report::fragility::Method::Ida {
                format!(
                    "{} records, {} censored, {} resurrections",
                    c.n_records, c.n_censored, c.resurrections
                )
            } else {
                format!("exceed {}", stripes.join(" "))
            }
        );
        // An uncertain study: the fit over the deterministic companions beside the total.
        if c.beta_records.is_some() {
            let _ = writeln!(
                s,
                "    records alone: median {} β {}; parameters add β {}",
                num(c.median_records),
                num(c.beta_records),
                num(c.beta_parameters())
            );
        }
    }
    for r in &fit.ratios {
        let _ = writeln!(
            s,
            "  median {} / {} at ≥ {}: {} [{}, {}]{}",
            r.a.label(),
            r.b.label(),
            r.damage_state,
            num(r.ratio),
            num(r.lo),
            num(r.hi),
            if r.curves_cross { ", curves cross" } else { "" }
        );
    }
}

fn shipped_studies() -> Vec<PathBuf> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/studies");
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("studies/ exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    paths.sort();
    paths
}

/// One snapshot per shipped study. Every study is checked before the test fails, so one
/// `INSTA_UPDATE=always cargo test --release studies` run rewrites all changed snapshots.
#[test]
fn every_shipped_study_matches_its_snapshot() {
    let paths = shipped_studies();
    assert!(paths.len() >= 9, "shipped studies missing: {paths:?}");
    let mut mismatched = Vec::new();
    for path in paths {
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let results = run_study_file(&path);
        let text = summary(&results);
        let outcome = std::panic::catch_unwind(|| {
            insta::with_settings!({
                snapshot_path => concat!(env!("CARGO_MANIFEST_DIR"), "/snapshots"),
                prepend_module_to_snapshot => false,
                omit_expression => true,
                description => format!("rocklab run studies/{name}.ron (headless summary)"),
            }, {
                insta::assert_snapshot!(format!("study_{name}"), text);
            });
        });
        if outcome.is_err() {
            mismatched.push(name);
        }
    }
    assert!(
        mismatched.is_empty(),
        "study snapshots changed: {mismatched:?}"
    );
}
