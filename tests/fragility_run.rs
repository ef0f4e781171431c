//! A fragility study run end to end by real `rocklab run` processes: stripes.csv says each
//! scene's record, IM and scale factor (checked against the record's PGA), fragility.json's
//! per-stripe exceedances are the counts of stripes.csv, and a run stopped by SIGTERM
//! mid-sweep reruns reusing every finished scene into the same files.

use crate::checkpoint::{finish, journalled, lines, reused, signal, spawn_run, wait_for_lines};
use rocklab::excitation::{G, Library};
use std::path::{Path, PathBuf};

/// 44 far-field components × 4 stripes × 2 variants = 352 scenes.
const STUDY: &str = r#"(
    version: 1,
    name: "fragility_run",
    structure: rigid(p: 2.0, alpha: 0.2),
    devices: [none, mechanistic(sigma: 0.5)],
    excitation: record(suite: (name: "far_field"), scale: [1.5, 3.0, 5.0, 8.0], scale_to: pga_star, tail: 10.0),
    quantities: [peak_rotation_ratio],
    spectrum: scale,
    fragility: (damage_states: levels([0.2, 0.5, 1.0]), bootstrap: 200, seed: 7),
)"#;
const SCENES: usize = 352;

fn write_study(dir: &Path) -> String {
    let path = dir.join("fragility_run.ron");
    std::fs::write(&path, STUDY).unwrap();
    path.display().to_string()
}

fn records_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("records")
}

fn read(out: &Path, file: &str) -> String {
    std::fs::read_to_string(out.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"))
}

#[test]
fn a_fragility_run_writes_stripes_and_fits_and_resumes_after_a_stop() {
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path());
    // The uninterrupted run.
    let full = dir.path().join("full");
    let o = crate::util::run_into(&study, &full);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stripes = read(&full, "stripes.csv");
    let mut csv = csv::Reader::from_reader(stripes.as_bytes());
    let header: Vec<String> = csv.headers().unwrap().iter().map(String::from).collect();
    for column in [
        "device",
        "record",
        "component",
        "im",
        "scale",
        "peak_rotation_ratio",
        "overturned",
    ] {
        assert!(header.iter().any(|h| h == column), "{column}: {header:?}");
    }
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let rows: Vec<csv::StringRecord> = csv.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), SCENES);
    let lib = Library::open(Some(records_dir())).unwrap();
    // (device, im, damage state) → (scenes, exceedances), counted from stripes.csv.
    type StripeKey = (String, f64, f64);
    let mut counts: Vec<(StripeKey, (usize, usize))> = Vec::new();
    for r in &rows {
        let record = &r[col("record")];
        let im: f64 = r[col("im")].parse().unwrap();
        let scale: f64 = r[col("scale")].parse().unwrap();
        // PGA* = scale·PGA/(g·tan α) is the stripe's value.
        let pga = lib.load(record, false).unwrap().series.pga();
        assert!(
            (scale * pga / (G * 0.2_f64.tan()) / im - 1.0).abs() < 1e-8,
            "{record} at {im}: scale {scale}"
        );
        let component = &r[col("component")];
        assert!(record.ends_with(component), "{record} {component}");
        let overturned = &r[col("overturned")] == "true";
        let ratio: Option<f64> = r[col("peak_rotation_ratio")].parse().ok();
        assert_eq!(overturned, ratio.is_none(), "{r:?}");
        for ds in [0.2, 0.5, 1.0] {
            let key = (r[col("device")].to_string(), im, ds);
            let exceeds = overturned || ratio.unwrap() >= ds;
            match counts.iter_mut().find(|(k, _)| *k == key) {
                Some((_, (n, e))) => {
                    *n += 1;
                    *e += usize::from(exceeds);
                }
                None => counts.push((key, (1, usize::from(exceeds)))),
            }
        }
    }
    let report =
        rocklab::report::fragility::read_fragility_json(&full.join("fragility.json")).unwrap();
    assert_eq!(report.curves.len(), 2 * 3);
    for c in &report.curves {
        assert_eq!(c.n_records, 44, "{c:?}");
        assert_eq!(c.stripes.len(), 4);
        for s in &c.stripes {
            let key = (c.variant.device.clone(), s.im, c.damage_state);
            let (_, (n, e)) = counts.iter().find(|(k, _)| *k == key).unwrap();
            assert_eq!((s.n, s.exceed), (*n, *e), "{key:?}");
        }
    }
    let fragility_csv = read(&full, "fragility.csv");
    assert_eq!(fragility_csv.lines().count(), 1 + 6);
    // summary.txt (what `rocklab run` prints) gives each fitted median as the PGA* it is, with
    // the report's interval; a median outside the stripes (1.5 … 8) is flagged, in the summary
    // and in fragility.csv's warnings column.
    let summary = read(&full, "summary.txt");
    let fmt = |v: Option<f64>| rocklab::numfmt::fmt_digits(v.unwrap(), 3);
    let mut csv = csv::Reader::from_reader(fragility_csv.as_bytes());
    let warn_col = csv.headers().unwrap().iter().position(|h| h == "warnings");
    let warnings: Vec<String> = csv
        .records()
        .map(|r| r.unwrap()[warn_col.expect("a warnings column")].to_string())
        .collect();
    for (c, warning) in report.curves.iter().zip(&warnings) {
        let Some(median) = c.median else { continue };
        let shown = format!(
            "median PGA* {} [{}, {}]",
            fmt(c.median),
            fmt(c.median_lo),
            fmt(c.median_hi)
        );
        let line = summary
            .lines()
            .find(|l| l.contains(&shown) && l.contains(device_word(&c.variant.device)))
            .unwrap_or_else(|| panic!("{shown} not in\n{summary}"));
        let expected = match median {
            m if m < 1.5 => "median_below_data",
            m if m > 8.0 => "median_above_data",
            _ => "",
        };
        let flagged = warning.split(';').find(|w| w.starts_with("median_"));
        assert_eq!(flagged.unwrap_or(""), expected, "{c:?}: {warning}");
        assert_eq!(line.contains("WARNING"), !expected.is_empty(), "{line}");
    }

    // Stopped by SIGTERM mid-sweep, then rerun: every journalled scene is reused and the
    // files are the uninterrupted run's.
    let out = dir.path().join("stopped");
    let journal = out.join("results.journal");
    let mut child = spawn_run(&study, &out, &["--jobs", "1"]);
    wait_for_lines(&mut child, &journal, 1 + 12);
    signal(&child, "TERM");
    let (status, stderr) = finish(child);
    assert!(!status.success(), "{stderr}");
    let before = journalled(&journal);
    assert!((12..SCENES).contains(&before), "{before} journalled");
    assert!(
        !out.join("fragility.csv").exists(),
        "no fit of part of the scenes"
    );
    let (status, stderr) = finish(spawn_run(&study, &out, &[]));
    assert!(status.success(), "{stderr}");
    assert_eq!(reused(&stderr), before);
    assert_eq!(lines(&journal), 1 + SCENES, "no scene computed twice");
    for file in ["stripes.csv", "fragility.csv", "fragility.json"] {
        assert_eq!(read(&out, file), read(&full, file), "{file}");
    }
}

/// The summary calls the variant with no device "bare" (as its ratios do).
fn device_word(device: &str) -> &str {
    match device {
        "none" => "bare",
        other => other,
    }
}
