//! Incremental dynamic analysis run end to end by real `rocklab run` processes: ida.csv's
//! capacities, brackets and resurrections are checked against the raw probe scenes of
//! stripes.csv (the first intensity that reached the state, the highest that held below it,
//! every level that held above it), fragility.json fits the capacities with censoring, and a
//! run stopped by SIGTERM mid-hunt reruns reusing every finished probe into the same files.

use crate::checkpoint::{finish, journalled, lines, reused, signal, spawn_run, wait_for_lines};
use rocklab::report::fragility::{FitStatus, Method, read_fragility_json};
use rocklab::study::Study;
use std::collections::HashMap;
use std::path::Path;

/// 4 far-field records × 2 components × 2 variants = 16 hunts over a 7-level PGA* ladder.
const STUDY: &str = r#"(
    version: 1,
    name: "fragility_ida",
    structure: rigid(p: 2.0, alpha: 0.2),
    devices: [none, mechanistic(sigma: 0.5)],
    excitation: record(suite: (name: "far_field", records: [1, 2, 3, 4]),
                       scale: (from: 1.5, to: 12.0, steps: 7, log: true), scale_to: pga_star,
                       tail: 10.0),
    quantities: [peak_rotation_ratio],
    spectrum: scale,
    fragility: (method: ida(resolution: 0.2), damage_states: levels([0.5, 1.0]),
                bootstrap: 200, seed: 3),
)"#;
const HUNTS: usize = 16;
/// A probe scene of stripes.csv: (IM, θmax/α unless overturned, overturned).
type Probe = (f64, Option<f64>, bool);
const RESOLUTION: f64 = 0.2;
const TOP: f64 = 12.0;

fn write_study(dir: &Path) -> String {
    let path = dir.join("fragility_ida.ron");
    std::fs::write(&path, STUDY).unwrap();
    path.display().to_string()
}

fn read(out: &Path, file: &str) -> String {
    std::fs::read_to_string(out.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"))
}

fn table(text: &str) -> (Vec<String>, Vec<csv::StringRecord>) {
    let mut csv = csv::Reader::from_reader(text.as_bytes());
    let header = csv.headers().unwrap().iter().map(String::from).collect();
    (header, csv.records().map(Result::unwrap).collect())
}

fn col(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("{name}: {header:?}"))
}

#[test]
fn an_ida_brackets_first_exceedances_reports_resurrections_and_resumes_after_a_stop() {
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path());
    let full = dir.path().join("full");
    let o = crate::util::run_into(&study, &full);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));

    // Every probe scene, by (device, record): (IM, reached θmax/α ≥ ds for ds = 0.5, 1).
    let (sh, probes) = table(&read(&full, "stripes.csv"));
    let mut by_hunt: HashMap<(String, String), Vec<Probe>> = HashMap::new();
    for r in &probes {
        assert_eq!(&r[col(&sh, "status")], "ok", "{r:?}");
        let key = (
            r[col(&sh, "device")].to_string(),
            r[col(&sh, "record")].to_string(),
        );
        let im: f64 = r[col(&sh, "im")].parse().unwrap();
        let ratio = r[col(&sh, "peak_rotation_ratio")].parse().ok();
        let overturned = &r[col(&sh, "overturned")] == "true";
        by_hunt
            .entry(key)
            .or_default()
            .push((im, ratio, overturned));
    }
    assert_eq!(by_hunt.len(), HUNTS);
    let reaches = |p: &Probe, ds: f64| p.2 || p.1.unwrap() >= ds;

    let (h, rows) = table(&read(&full, "ida.csv"));
    assert_eq!(rows.len(), HUNTS * 2);
    let (mut censored, mut resurrections) = (0, 0);
    for r in &rows {
        assert_eq!(&r[col(&h, "status")], "done", "{r:?}");
        let key = (
            r[col(&h, "device")].to_string(),
            r[col(&h, "record")].to_string(),
        );
        let hunt = &by_hunt[&key];
        assert_eq!(r[col(&h, "probes")].parse::<usize>().unwrap(), hunt.len());
        let ds: f64 = r[col(&h, "damage_state")].parse().unwrap();
        let lo: f64 = r[col(&h, "bracket_lo")].parse().unwrap();
        let hi: f64 = r[col(&h, "bracket_hi")].parse().unwrap();
        let first = hunt
            .iter()
            .filter(|p| reaches(p, ds))
            .map(|p| p.0)
            .min_by(f64::total_cmp);
        if &r[col(&h, "censored")] == "true" {
            censored += 1;
            // Never reached: the hunt climbed to the top of the ladder.
            assert_eq!(first, None, "{r:?}");
            assert!(r[col(&h, "capacity")].is_empty() && hi == TOP, "{r:?}");
            assert!(hunt.iter().any(|p| (p.0 - TOP).abs() < 1e-9), "{r:?}");
            continue;
        }
        let capacity: f64 = r[col(&h, "capacity")].parse().unwrap();
        // The capacity is the first probe that reached the state, the bracket's low end the
        // highest probe below it (all of which held), no wider than the resolution.
        assert_eq!(Some(capacity), first, "{r:?}");
        assert_eq!(hi, capacity);
        let below = hunt.iter().filter(|p| p.0 < capacity);
        assert!(below.clone().all(|p| !reaches(p, ds)), "{r:?}");
        assert_eq!(lo, below.map(|p| p.0).fold(0.0, f64::max), "{r:?}");
        assert!(hi - lo <= RESOLUTION + 1e-12, "{r:?}");
        // Resurrections: every probe above the capacity that held.
        let held: Vec<f64> = hunt
            .iter()
            .filter(|p| p.0 > capacity && !reaches(p, ds))
            .map(|p| p.0)
            .collect();
        let n: usize = r[col(&h, "resurrections")].parse().unwrap();
        assert_eq!(n, held.len(), "{r:?}");
        resurrections += n;
    }
    eprintln!("{censored} censored, {resurrections} resurrections");

    // The fit: one ida curve per variant and state over the 8 components, censored counted.
    let report = read_fragility_json(&full.join("fragility.json")).unwrap();
    assert_eq!(report.curves.len(), 4);
    for c in &report.curves {
        assert_eq!(c.method, Method::Ida);
        assert_eq!(c.n_records, 8, "{c:?}");
        assert!(c.status == FitStatus::Fitted || c.median.is_none(), "{c:?}");
    }
    let n_censored: usize = report.curves.iter().map(|c| c.n_censored).sum();
    assert_eq!(n_censored, censored);
    let fragility_csv = read(&full, "fragility.csv");
    assert!(fragility_csv.lines().skip(1).all(|l| l.contains(",ida,")));
    // The summary says how many scenes the hunts took against the same ladder as stripes.
    let summary = read(&full, "summary.txt");
    let line = format!(
        "IDA: {} scenes (every probe of the hunts); as stripes, the same ladder takes {}",
        probes.len(),
        HUNTS * 7
    );
    assert!(summary.contains(&line), "{summary}");

    // Stopped by SIGTERM mid-hunt, then rerun: every journalled probe is reused, none runs
    // twice, and the files are the uninterrupted run's.
    let out = dir.path().join("stopped");
    let journal = out.join("results.journal");
    let mut child = spawn_run(&study, &out, &["--jobs", "1"]);
    wait_for_lines(&mut child, &journal, 1 + 20);
    signal(&child, "TERM");
    let (status, stderr) = finish(child);
    assert!(!status.success(), "{stderr}");
    let before = journalled(&journal);
    assert!((20..probes.len()).contains(&before), "{before} journalled");
    assert!(
        !out.join("fragility.csv").exists(),
        "no fit of part of the hunts"
    );
    let (status, stderr) = finish(spawn_run(&study, &out, &[]));
    assert!(status.success(), "{stderr}");
    assert_eq!(reused(&stderr), before);
    assert_eq!(lines(&journal), 1 + probes.len(), "no probe computed twice");
    for file in ["stripes.csv", "ida.csv", "fragility.csv", "fragility.json"] {
        assert_eq!(read(&out, file), read(&full, file), "{file}");
    }
}

#[test]
fn ida_sections_are_read_strictly() {
    let with = |fragility: &str, scale: &str| {
        STUDY
            .replace(
                "fragility: (method: ida(resolution: 0.2), damage_states: levels([0.5, 1.0]),",
                &format!("fragility: ({fragility}"),
            )
            .replace("scale: (from: 1.5, to: 12.0, steps: 7, log: true)", scale)
    };
    let ladder = "scale: (from: 1.5, to: 12.0, steps: 7, log: true)";
    for (fragility, scale, field, says) in [
        // A field of the method outside it, and one the method does not have.
        ("resolution: 0.2,", ladder, "resolution", ""),
        (
            "method: ida(resolution: 0.2, start: 1.0),",
            ladder,
            "start",
            "",
        ),
        (
            "method: ida(resolution: 0.0),",
            ladder,
            "fragility.method",
            "resolution",
        ),
        (
            "method: ida(resolution: 1e-9),",
            ladder,
            "fragility.method",
            "2^16",
        ),
        (
            "method: ida(resolution: 0.2),",
            "scale: [3.0, 1.5, 6.0]",
            "excitation.scale",
            "increasing",
        ),
        ("method: idaa(resolution: 0.2),", ladder, "idaa", ""),
    ] {
        let text = with(fragility, scale);
        let e = Study::from_ron_str(&text, "ida.ron").unwrap_err();
        assert!(e.line.is_some(), "{fragility}: {e}");
        let named = e.field.as_deref() == Some(field) || e.to_string().contains(field);
        assert!(named && e.to_string().contains(says), "{fragility}: {e}");
    }
    // The section as written reads, and says its method.
    let s = Study::from_ron_str(STUDY, "ida.ron").unwrap();
    let f = s.fragility.unwrap();
    assert_eq!(
        f.method,
        rocklab::study::fragility::Method::Ida { resolution: 0.2 }
    );
}
