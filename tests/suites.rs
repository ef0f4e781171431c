//! Record suites (FEMA P695 sets in records/fema-p695/): every component's data against its
//! index.csv, suite selection and filters, and IM scaling of suite records.

use rocklab::excitation::suite::{Component, SUITES, Set, SuiteSelect};
use rocklab::excitation::{G, Library, Source};
use rocklab::scene::{Excitation, RecordScale};
use rocklab::study::Study;
use sha2::{Digest, Sha256};
use std::path::PathBuf;

fn records_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("records")
}

/// g of index.csv's PGV (trapezoidal integration of a·9.80665 sampled at the samples).
const G_INDEX: f64 = 9.80665;

#[test]
fn every_component_matches_its_index_row() {
    let dir = Library::open(Some(records_dir())).unwrap();
    let embedded = Library::open(None).unwrap();
    let counts: Vec<usize> = Set::ALL
        .iter()
        .map(|s| dir.suite_records().iter().filter(|r| r.set == *s).count())
        .collect();
    assert_eq!(counts, [44, 28, 28]);
    for e in dir.suite_records() {
        let id = e.id();
        let m = &e.row;
        // The shipped file is the one the index describes, byte for byte.
        let bytes = std::fs::read(records_dir().join(e.path())).unwrap();
        let hash: String = Sha256::digest(&bytes)
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        assert_eq!(hash, m.sha256, "{id}");
        for lib in [&dir, &embedded] {
            let r = lib.load(&id, false).unwrap();
            assert!(
                matches!(
                    (&r.source, std::ptr::eq(lib, &dir)),
                    (Source::File(_), true) | (Source::Embedded(_), false)
                ),
                "{id}: {:?}",
                r.source
            );
            let s = &r.series;
            assert_eq!(s.npts(), m.npts, "{id}");
            assert_eq!(s.dt(), m.dt, "{id}");
            // PGA: index.csv gives max |a| in g to 6–7 significant digits.
            assert!(
                (s.pga() / G / m.pga_g - 1.0).abs() < 2e-6,
                "{id}: PGA {}",
                s.pga() / G
            );
            // PGV as index.csv computes it, from the samples rocklab read …
            let mut v = 0.0_f64;
            let mut peak = 0.0_f64;
            for w in s.samples().windows(2) {
                v += 0.5 * s.dt() * (w[0] + w[1]) / G * G_INDEX;
                peak = peak.max(v.abs());
            }
            assert!((peak / m.pgv_m_s - 1.0).abs() < 1e-6, "{id}: PGV {peak}");
            // … and rocklab's own (g = 9.81, and the extrema of v inside segments where a
            // changes sign, each at most |a|·dt/2 beyond the samples' v): never below, never
            // more than PGA·dt/2 above.
            let excess = s.pgv() - m.pgv_m_s * G / G_INDEX;
            assert!(
                (-1e-12..=0.5 * s.pga() * s.dt()).contains(&excess),
                "{id}: {excess}"
            );
        }
    }
}

#[test]
fn suites_select_by_name_component_record_and_pulse() {
    let lib = Library::open(Some(records_dir())).unwrap();
    let sel = |name: &str| SuiteSelect {
        name: name.into(),
        ..SuiteSelect::default()
    };
    let count = |s: SuiteSelect| lib.suite(&s).unwrap().len();
    assert_eq!(count(sel("far_field")), 44);
    assert_eq!(count(sel("near_field_pulse")), 28);
    assert_eq!(count(sel("near_field_no_pulse")), 28);
    assert_eq!(count(sel("near_field")), 56);
    let table1 = lib.suite(&sel("table1")).unwrap();
    assert_eq!(
        table1,
        [
            "landers",
            "northridge",
            "imperial_valley",
            "superstition_hills",
            "palm_springs"
        ]
    );
    let fn_only = lib
        .suite(&SuiteSelect {
            component: Some(Component::A),
            pulse: Some(true),
            ..sel("near_field")
        })
        .unwrap();
    assert_eq!(fn_only.len(), 14);
    assert!(
        fn_only
            .iter()
            .all(|n| n.starts_with("near_field_pulse/") && n.ends_with('a'))
    );
    let some = lib
        .suite(&SuiteSelect {
            records: vec![7, 1],
            ..sel("far_field")
        })
        .unwrap();
    assert_eq!(
        some,
        [
            "far_field/1a",
            "far_field/1b",
            "far_field/7a",
            "far_field/7b"
        ]
    );
    // Far-field records are not classified by pulse; unknown suites and ids are errors.
    assert!(
        lib.suite(&SuiteSelect {
            pulse: Some(true),
            ..sel("far_field")
        })
        .is_err()
    );
    let err = lib.suite(&sel("farfield")).unwrap_err().to_string();
    assert!(
        err.contains("unknown suite") && SUITES.iter().all(|s| err.contains(s)),
        "{err}"
    );
    let err = lib
        .suite(&SuiteSelect {
            records: vec![23],
            ..sel("far_field")
        })
        .unwrap_err()
        .to_string();
    assert!(err.contains("no record 23"), "{err}");
    // The near-field pulse set holds the paper's Rinaldi FN record, value for value.
    let rinaldi = lib.load("near_field_pulse/9a", false).unwrap();
    let table = lib.load("northridge", false).unwrap();
    assert_eq!(rinaldi.series.samples(), table.series.samples());
}

#[test]
fn dimensionless_scaling_means_the_same_for_every_structure() {
    let lib = Library::open(Some(records_dir())).unwrap();
    let r = lib.load("far_field/7a", false).unwrap();
    let (pga, pgv) = (r.series.pga(), r.series.pgv());
    for (alpha, p) in [(0.2_f64, 2.0_f64), (0.1, 3.0), (0.25, 1.0)] {
        // PGA* = PGA/(g tan α) after scaling equals the target …
        let k = RecordScale::PgaStar(2.5).factor(pga, pgv, alpha, p);
        assert!(((k * pga) / (G * alpha.tan()) / 2.5 - 1.0).abs() < 1e-14);
        // … and PGV* = PGV·p/(g tan α).
        let k = RecordScale::PgvStar(0.8).factor(pga, pgv, alpha, p);
        assert!(((k * pgv) * p / (G * alpha.tan()) / 0.8 - 1.0).abs() < 1e-14);
    }
    let k = RecordScale::Pga(0.5).factor(pga, pgv, 0.2, 2.0);
    assert!((k * pga / G - 0.5).abs() < 1e-14);
}

// StudyError is large by design (study/mod.rs): built once per failing study.
#[allow(clippy::result_large_err)]
fn study(excitation: &str) -> Result<rocklab::study::Study, rocklab::study::StudyError> {
    rocklab::study::Study::from_ron_str(
        &format!(
            "(version: 1, name: \"s\", structure: rigid(p: 2.0, alpha: [0.1, 0.2]), \
             devices: [none], excitation: {excitation}, spectrum: scale{duration})",
            // A record's `tail` sets each scene's duration: the study then gives none.
            duration = if excitation.contains("tail:") {
                ""
            } else {
                ", duration: 30.0"
            }
        ),
        "s.ron",
    )
}

#[test]
fn a_study_takes_a_suite_scaled_to_an_intensity_measure() {
    let lib = Library::open(Some(records_dir())).unwrap();
    let s = study(
        "record(names: [\"landers\"], suite: (name: \"far_field\", component: b, records: [3]), \
         scale: [1.5, 3.0], scale_to: pga_star, tail: 10.0)",
    )
    .unwrap();
    let points = s.expand().unwrap();
    // 2 α × (landers + far_field/3b) × 2 stripes.
    assert_eq!(points.len(), 8);
    for p in &points {
        let Excitation::Record { name, scale, .. } = &p.scene.excitation else {
            panic!("{p:?}")
        };
        assert!(
            ["landers", "far_field/3b"].contains(&name.as_str()),
            "{name}"
        );
        assert!(matches!(scale, RecordScale::PgaStar(v) if *v == 1.5 || *v == 3.0));
        // Each scene lasts its record's length plus the tail.
        let end = lib.load(name, false).unwrap().series.end();
        assert_eq!(p.scene.duration, end + 10.0, "{name}");
    }
    // FEMA normalisation: scale × the record's factor from index.csv.
    let s = study("record(suite: (name: \"far_field\", records: [7]), scale: 2.0, scale_to: fema)")
        .unwrap();
    let nf = lib
        .suite_entry("far_field/7a")
        .unwrap()
        .row
        .normalization_factor;
    let Excitation::Record { scale, .. } = &s.expand().unwrap()[0].scene.excitation else {
        panic!()
    };
    assert_eq!(*scale, RecordScale::Factor(2.0 * nf));
}

#[test]
fn bad_suites_are_errors_that_name_the_field() {
    for (excitation, field, says) in [
        (
            "record(suite: (name: \"farfield\"))",
            "excitation.suite",
            "unknown suite",
        ),
        (
            "record(suite: (name: \"far_field\", records: [40]))",
            "excitation.suite",
            "no record 40",
        ),
        (
            "record(names: [\"landers\"], scale_to: fema)",
            "excitation.scale_to",
            "normalisation",
        ),
        (
            "record(names: [\"far_field/1a\"], suite: (name: \"far_field\", records: [1]))",
            "excitation.suite",
            "both in `names` and in the suite",
        ),
        ("record(names: [])", "excitation.names", "no records"),
        (
            "record(names: [\"landers\"], tail: -1.0)",
            "excitation.tail",
            "not a duration",
        ),
    ] {
        let e = study(excitation).unwrap_err();
        assert_eq!(e.field.as_deref(), Some(field), "{excitation}: {e}");
        assert!(e.to_string().contains(says), "{excitation}: {e}");
        assert!(e.line.is_some(), "{excitation}: {e}");
    }
}

/// A study with a record `tail` gives no `duration` (it would be silently unused): both are
/// refused at the duration's line with a hint, and a study with neither names what is missing.
#[test]
fn duration_and_tail_are_one_or_the_other() {
    let text = |excitation: &str, duration: &str| {
        format!(
            "(\n    version: 1,\n    name: \"s\",\n    structure: rigid(p: 2.0, alpha: 0.2),\n    \
             devices: [none],\n    excitation: {excitation},\n    spectrum: scale,\n{duration})"
        )
    };
    let tail = "record(names: [\"landers\"], scale: [1.0, 2.0], tail: 10.0)";
    let e = Study::from_ron_str(&text(tail, "    duration: 10.0,\n"), "s.ron").unwrap_err();
    assert_eq!(
        (e.origin.as_str(), e.line, e.field.as_deref()),
        ("s.ron", Some(8), Some("duration")),
        "{e}"
    );
    assert!(e.to_string().contains("unused") && e.to_string().contains("remove `duration`"));
    let no_tail = "record(names: [\"landers\"], scale: [1.0, 2.0])";
    let e = Study::from_ron_str(&text(no_tail, ""), "s.ron").unwrap_err();
    assert_eq!(e.field.as_deref(), Some("duration"), "{e}");
    assert!(
        e.to_string().contains("missing") && e.to_string().contains("tail: 10.0"),
        "{e}"
    );
    // Either alone is a study; the tail sets each scene's duration from its record.
    let s = Study::from_ron_str(&text(tail, ""), "s.ron").unwrap();
    assert_eq!(s.duration, None);
    let end = s.expand().unwrap()[0].scene.duration;
    assert!(end > 10.0, "{end}");
    let s = Study::from_ron_str(&text(no_tail, "    duration: 7.0,\n"), "s.ron").unwrap();
    assert!(s.expand().unwrap().iter().all(|p| p.scene.duration == 7.0));
}
