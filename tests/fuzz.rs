//! Property-based fuzzing (proptest) of the input surfaces: the record reader (AT2 and
//! column files, AT2 headers spelled every way), the study parser (the whole text, and the
//! design, fragility and IDA sections field by field), the records index (index.ron) and the
//! `simulate` flag set. The property: any input
//! gives a value or a clear error, never a panic (a panic fails the case and proptest shrinks
//! it to a minimal reproduction). Bounded: a fixed number of cases per target so `cargo test`
//! stays quick and deterministic (a fixed seed); raise PROPTEST_CASES (or multiply every
//! target's cases by ROCKLAB_FUZZ_SCALE) and set ROCKLAB_FUZZ_SEED to fuzz longer or
//! elsewhere. CI runs them again on a fresh seed, scaled and bounded in time (.ci/run).

use clap::Parser;
use proptest::prelude::*;
use rocklab::excitation::reader;
use rocklab::study::Study;
use std::time::Duration;

fn config(cases: u32) -> ProptestConfig {
    // CI's fuzz step (.ci/run) scales every target's cases with ROCKLAB_FUZZ_SCALE.
    let scale: u32 = std::env::var("ROCKLAB_FUZZ_SCALE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    ProptestConfig {
        cases: std::env::var("PROPTEST_CASES")
            .ok()
            .and_then(|c| c.parse().ok())
            .unwrap_or(cases.saturating_mul(scale)),
        failure_persistence: None,
        rng_seed: proptest::test_runner::RngSeed::Fixed(
            std::env::var("ROCKLAB_FUZZ_SEED")
                .ok()
                .and_then(|s| s.parse().ok())
                .unwrap_or(12),
        ),
        ..ProptestConfig::default()
    }
}

/// Numbers as record files write them, and as careless or hostile ones do.
fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        (-10.0f64..10.0).prop_map(|v| format!("{v:.6}")),
        (-10.0f64..10.0).prop_map(|v| format!("{v:.4E}")),
        (-10.0f64..10.0).prop_map(|v| format!("{v:.4}").replace('E', "D")),
        Just("1E12".to_string()),
        Just("1E20".to_string()),
        Just("1e-310".to_string()),
        Just("-0".to_string()),
        Just("NaN".to_string()),
        Just("inf".to_string()),
        Just("1e308".to_string()),
        Just("0.1-0.2".to_string()),
        Just("abc".to_string()),
        Just(String::new()),
    ]
}

/// AT2 header lines as writers, editors and hostile files spell them: keys in any order and
/// spacing, a key twice, units words, a huge field.
fn at2_header() -> impl Strategy<Value = String> {
    let key = prop_oneof![
        Just("NPTS"),
        Just("DT"),
        Just("npts"),
        Just("Dt"),
        Just("SEC"),
        Just("UNITS OF G"),
        Just("UNITS OF CM/S2"),
        Just("VELOCITY"),
    ];
    let sep = prop_oneof![Just("="), Just(" = "), Just("= "), Just(""), Just(",")];
    (
        proptest::collection::vec((key, sep, number()), 1..5),
        any::<bool>(),
    )
        .prop_map(|(parts, long)| {
            let mut line: String = parts
                .iter()
                .map(|(k, s, v)| format!("{k}{s}{v}"))
                .collect::<Vec<_>>()
                .join(", ");
            if long {
                line.push_str(&"9".repeat(5_000));
            }
            line
        })
}

/// Whether an AT2 header line gives `NPTS=` or `DT=` twice (the reader must refuse it).
fn gives_a_key_twice(text: &str) -> bool {
    let Some(line) = text
        .lines()
        .take(6)
        .find(|l| !l.trim_start().starts_with('#') && l.to_ascii_uppercase().contains("NPTS"))
    else {
        return false;
    };
    let upper = line.to_ascii_uppercase().replace(' ', "");
    ["NPTS=", "DT="].iter().any(|k| {
        upper
            .match_indices(k)
            .filter(|(at, _)| !upper[..*at].ends_with(|c: char| c.is_ascii_alphanumeric()))
            .count()
            > 1
    })
}

/// A record file: an optional AT2 header (both styles) or comment lines, then data rows.
fn record_text() -> impl Strategy<Value = String> {
    let header = prop_oneof![
        (number(), number()).prop_map(|(n, dt)| format!("NPTS= {n}, DT= {dt} SEC")),
        (number(), number()).prop_map(|(n, dt)| format!("{n} {dt} NPTS, DT")),
        at2_header(),
        number().prop_map(|dt| format!("# dt: {dt}")),
        Just("# units: cm/s2".to_string()),
        Just(String::new()),
    ];
    (
        proptest::collection::vec(header, 0..3),
        0usize..4,
        proptest::collection::vec(proptest::collection::vec(number(), 0..4), 0..12),
    )
        .prop_map(|(headers, free_lines, rows)| {
            let mut text = String::new();
            for _ in 0..free_lines {
                text.push_str("PEER STRONG MOTION DATABASE RECORD\n");
            }
            for h in headers {
                text.push_str(&h);
                text.push('\n');
            }
            for r in rows {
                text.push_str(&r.join("  "));
                text.push('\n');
            }
            text
        })
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn the_record_reader_never_panics(text in record_text(), dt in proptest::option::of(number())) {
        let dt = dt.and_then(|d| d.parse::<f64>().ok());
        match reader::parse(&text, "fuzz.at2", dt) {
            Ok(series) => {
                prop_assert!(series.dt() >= reader::MIN_DT && series.dt().is_finite());
                prop_assert!(series.npts() >= 1);
                // Every sample is a plausible ground acceleration (issue 43, F9).
                let worst = series.samples().iter().fold(0.0f64, |m, a| m.max(a.abs()));
                prop_assert!(worst <= reader::MAX_ACCELERATION, "{}", worst);
                // A header that gives a key twice is refused, never read at its first (F8).
                prop_assert!(!gives_a_key_twice(&text), "accepted:\n{}", text);
            }
            // A message is a line or two, whatever the file holds (F5).
            Err(e) => prop_assert!(e.to_string().len() < 1_000, "{} bytes", e.to_string().len()),
        }
    }

    #[test]
    fn the_record_reader_never_panics_on_arbitrary_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        let text = String::from_utf8_lossy(&bytes);
        let _ = reader::parse(&text, "fuzz.txt", None);
        let _ = reader::parse(&text, "fuzz.txt", Some(0.01));
    }
}

const BASE_STUDY: &str = include_str!("../studies/default.ron");

/// `base` with each edit applied in turn: at a fraction of the text, `cut` bytes replaced by
/// the token (both ends moved to character boundaries). The study and index targets share it.
fn spliced(base: &str, edits: Vec<(f64, usize, String)>) -> String {
    let mut text = base.to_string();
    for (at, cut, token) in edits {
        let mut i = ((text.len() as f64) * at) as usize;
        while !text.is_char_boundary(i) {
            i -= 1;
        }
        let mut j = (i + cut).min(text.len());
        while !text.is_char_boundary(j) {
            j += 1;
        }
        text.replace_range(i..j, &token);
    }
    text
}

/// Tokens a study edit may splice in: names, numbers, punctuation, as typos and hostile edits.
fn study_token() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("(".to_string()),
        Just(")".to_string()),
        Just("[".to_string()),
        Just("]".to_string()),
        Just(",".to_string()),
        Just(":".to_string()),
        Just("\"".to_string()),
        Just("linspace(".to_string()),
        Just("xi(".to_string()),
        Just("ratio(".to_string()),
        Just("r#\"a \" b\"#".to_string()),
        Just("from: 2.0, ".to_string()),
        Just("(from: 1e-300, to: 1e300, steps: 3, log: true)".to_string()),
        Just("(from: 0.0, to: 1.0, steps: 1000001)".to_string()),
        Just("mavroeidis_papageorgiou(gamma: 1e308, nu: 0.0)".to_string()),
        Just("-1".to_string()),
        Just("0".to_string()),
        Just("1e308".to_string()),
        Just("NaN".to_string()),
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("-inf".to_string()),
        Just("\u{feff}".to_string()),
        Just("/*".to_string()),
        Just("//".to_string()),
        "[a-z_]{1,8}".prop_map(|s| s),
        (-1e3f64..1e3).prop_map(|v| format!("{v}")),
    ]
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn the_study_parser_never_panics(
        edits in proptest::collection::vec((0.0f64..1.0, 0usize..6, study_token()), 1..4)
    ) {
        let text = spliced(BASE_STUDY, edits);
        if let Ok(study) = Study::from_ron_str(&text, "fuzz.ron") {
            // A valid study round-trips to the same study.
            let back = Study::from_ron_str(&study.to_ron_string(), "back.ron");
            prop_assert_eq!(back.ok(), Some(study));
        }
    }

    #[test]
    fn the_study_parser_never_panics_on_arbitrary_text(text in "\\PC{0,200}") {
        let _ = Study::from_ron_str(&text, "fuzz.ron");
    }
}

/// The shipped studies with a design, fragility or IDA section: the section fuzz edits them.
const SECTION_STUDIES: [&str; 4] = [
    include_str!("../studies/design_sigma_rigid.ron"),
    include_str!("../studies/design_fragility_rigid.ron"),
    include_str!("../studies/fragility_ida_far_field.ron"),
    include_str!("../studies/fragility_far_field.ron"),
];

/// A field of the design, fragility or IDA sections (or the suite filter they read) and a
/// value for it, from typical to hostile: what the campaign of issue 43 mutated.
fn section_edit() -> impl Strategy<Value = (&'static str, String)> {
    let field = prop_oneof![
        Just("resolution"),
        Just("bracket"),
        Just("verify"),
        Just("target"),
        Just("parameter"),
        Just("bootstrap"),
        Just("seed"),
        Just("confidence"),
        Just("method"),
        Just("damage_states"),
        Just("measure"),
        Just("suite"),
        Just("scale"),
        Just("tail"),
    ];
    let value = prop_oneof![
        (-3.0f64..3.0).prop_map(|v| format!("{v}")),
        (-400i64..400).prop_map(|v| format!("{v}")),
        prop_oneof![
            Just(1e-300),
            Just(1e-17),
            Just(2.2e-16),
            Just(8.9e-16),
            Just(1e308)
        ]
        .prop_map(|v| format!("{v:e}")),
        Just("1.5".to_string()),
        Just("-1".to_string()),
        Just("2".to_string()),
        Just("18446744073709551616".to_string()),
        Just("nan".to_string()),
        Just("\"x\"".to_string()),
        Just("(3.0, 0.0)".to_string()),
        Just("(0.0, 1e-300)".to_string()),
        Just("(1e300, 1e308)".to_string()),
        Just("ida(resolution: 1e-300)".to_string()),
        Just("ida(resolution: 0.5)".to_string()),
        Just("stripes".to_string()),
        Just("levels([])".to_string()),
        Just("levels([1.0, 0.5])".to_string()),
        Just("fragility(state: 1.0, median_at_least: 1e-300)".to_string()),
        Just("limit(quantity: peak_rotation_ratio, max: 0.0)".to_string()),
        Just("no_overturning".to_string()),
        Just("(name: \"far_field\", records: [])".to_string()),
        Just("(name: \"far_field\", records: [0, 99])".to_string()),
        Just("(name: \"far_field\", component: c)".to_string()),
        Just("(from: 1.0, to: 1e300, steps: 3, log: true)".to_string()),
        Just(format!("{}1.0{}", "[".repeat(100), "]".repeat(100))),
    ];
    (field, value)
}

/// `text` with the value of the first `field:` replaced by `value` (the text unchanged if the
/// field is not written there).
fn with_field(text: &str, field: &str, value: &str) -> String {
    let key = format!("{field}:");
    let Some(at) = text.find(&key) else {
        return text.to_string();
    };
    let start = at + key.len();
    let mut depth = 0i32;
    let mut end = text.len();
    for (i, c) in text[start..].char_indices() {
        match c {
            '(' | '[' => depth += 1,
            ')' | ']' if depth == 0 => {
                end = start + i;
                break;
            }
            ')' | ']' => depth -= 1,
            ',' | '\n' if depth == 0 => {
                end = start + i;
                break;
            }
            _ => {}
        }
    }
    format!("{} {value}{}", &text[..start], &text[end..])
}

proptest! {
    #![proptest_config(config(256))]

    /// The design, fragility and IDA sections, field by field: a study reads or is refused
    /// with a bounded message (no megabytes quoted, no 300-digit number), and what reads keeps
    /// the bounds the campaign found missing (a resolution f64 can reach, a bootstrap that
    /// gives an interval, a suite filter that selects).
    #[test]
    fn the_design_fragility_and_ida_sections_never_panic(
        base in 0usize..SECTION_STUDIES.len(),
        edits in proptest::collection::vec(section_edit(), 1..4),
        splices in proptest::collection::vec((0.0f64..1.0, 0usize..6, study_token()), 0..2),
    ) {
        let mut text = SECTION_STUDIES[base].to_string();
        for (field, value) in &edits {
            text = with_field(&text, field, value);
        }
        let text = spliced(&text, splices);
        match Study::from_ron_str(&text, "fuzz.ron") {
            Ok(study) => {
                if let Some(design) = &study.design {
                    prop_assert!(design.resolution >= rocklab::study::design::MIN_RESOLUTION);
                }
                if let Some(f) = &study.fragility {
                    let floor = rocklab::study::fragility::MIN_BOOTSTRAP;
                    prop_assert!(f.bootstrap == 0 || f.bootstrap >= floor, "{}", f.bootstrap);
                }
                let back = Study::from_ron_str(&study.to_ron_string(), "back.ron");
                prop_assert_eq!(back.ok(), Some(study));
            }
            Err(e) => {
                let shown = e.to_string();
                prop_assert!(shown.len() < 2_000, "{} bytes: {}", shown.len(), &shown[..200]);
                let digits = shown
                    .split(|c: char| !c.is_ascii_digit())
                    .map(str::len)
                    .max()
                    .unwrap_or(0);
                prop_assert!(digits < 30, "{}", shown);
                prop_assert!(e.line.is_some(), "no line: {}", shown);
            }
        }
    }
}

/// `simulate` flags with values from typical to absurd.
fn simulate_flags() -> impl Strategy<Value = Vec<String>> {
    let value = prop_oneof![
        (0.01f64..10.0).prop_map(|v| format!("{v}")),
        Just("1e-300".to_string()),
        Just("1e308".to_string()),
        Just("-1".to_string()),
        Just("0".to_string()),
        Just("NaN".to_string()),
        Just("inf".to_string()),
    ];
    let flag = prop_oneof![
        Just("--size"),
        Just("--p"),
        Just("--mass"),
        Just("--sigma"),
        Just("--k-theta"),
        Just("--rho"),
        Just("--epsilon"),
        Just("--xi-theta"),
        Just("--friction"),
        Just("--eta"),
        Just("--play"),
        Just("--amplitude-ratio"),
        Just("--amplitude-g"),
        Just("--frequency"),
        Just("--frequency-ratio"),
        Just("--gamma"),
        Just("--nu"),
        Just("--tp"),
        Just("--pgv"),
        Just("--duration"),
        Just("--rtol"),
        Just("--theta0"),
        Just("--xi"),
        Just("--omega-n"),
        Just("--scale"),
    ];
    let choice = prop_oneof![
        Just(vec!["--device".to_string(), "mechanistic".to_string()]),
        Just(vec!["--device".to_string(), "sequential".to_string()]),
        Just(vec!["--structure".to_string(), "flexible".to_string()]),
        Just(vec!["--pulse".to_string(), "mp".to_string()]),
        Just(vec!["--record".to_string(), "landers".to_string()]),
    ];
    (
        proptest::collection::vec((flag, value), 0..6),
        proptest::collection::vec(choice, 0..3),
        0.01f64..1.5,
    )
        .prop_map(|(pairs, choices, alpha)| {
            let mut args = vec![
                "rocklab".to_string(),
                "simulate".to_string(),
                "--alpha".to_string(),
                format!("{alpha}"),
            ];
            for (f, v) in pairs {
                args.push(f.to_string());
                args.push(v);
            }
            args.extend(choices.into_iter().flatten());
            args
        })
}

proptest! {
    #![proptest_config(config(64))]

    #[test]
    fn the_simulate_flag_set_never_panics(args in simulate_flags()) {
        let Ok(cli) = rocklab::cli::Cli::try_parse_from(&args) else {
            return Ok(());
        };
        let Some(rocklab::cli::Command::Simulate(sim_args)) = cli.command else {
            panic!("not a simulate command");
        };
        if let Ok(scene) = sim_args.scene() {
            // Bounded: a case runs at most a fraction of a second.
            let bounds = rocklab::sim::Bounds {
                cancel: None,
                time_limit: Some(Duration::from_millis(200)),
                ..Default::default()
            };
            let run = rocklab::sweep::guarded(|| {
                let records = rocklab::excitation::library::global().unwrap();
                rocklab::sim::run_bounded(&scene, records, bounds)
            });
            prop_assert!(
                !matches!(run, Err(rocklab::sweep::Guarded::Panic(_))),
                "{:?}: {:?}", args, run
            );
        }
    }
}

const BASE_INDEX: &str = include_str!("../records/index.ron");

/// Tokens an index edit may splice in: duplicate names and rows, units, counts, hostile text.
fn index_token() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("name: \"landers\", ".to_string()),
        Just("table1: Some(1), ".to_string()),
        Just("\"furlongs\"".to_string()),
        Just("\"cm/s\"".to_string()),
        Just("\"cm/s2\"".to_string()),
        Just("npts: Some(1), ".to_string()),
        Just("Some(1e308)".to_string()),
        Just("(".to_string()),
        Just(")".to_string()),
        Just(",".to_string()),
        Just("\"".to_string()),
        Just("/*".to_string()),
        "[a-z_]{1,8}".prop_map(|s| s),
        (-1e3f64..1e3).prop_map(|v| format!("{v}")),
    ]
}

proptest! {
    #![proptest_config(config(64))]

    /// The records index: any edit gives a library whose every record loads or fails with
    /// an error, never a panic; names stay unique (a name picks one record).
    #[test]
    fn the_records_index_never_panics(
        edits in proptest::collection::vec((0.0f64..1.0, 0usize..8, index_token()), 1..3)
    ) {
        let text = spliced(BASE_INDEX, edits);
        let dir = tempfile::tempdir().unwrap();
        let records = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("records");
        for entry in std::fs::read_dir(&records).unwrap() {
            let path = entry.unwrap().path();
            if !path.is_file() {
                continue;
            }
            std::fs::copy(&path, dir.path().join(path.file_name().unwrap())).unwrap();
        }
        std::fs::write(dir.path().join("index.ron"), &text).unwrap();
        if let Ok(lib) = rocklab::excitation::library::Library::open(Some(dir.path().to_path_buf())) {
            let mut names: Vec<String> =
                lib.index().iter().map(|m| m.name.to_ascii_lowercase()).collect();
            let n = names.len();
            names.sort();
            names.dedup();
            prop_assert_eq!(names.len(), n);
            for meta in lib.index() {
                let _ = lib.load(&meta.name, false);
            }
        }
    }
}
