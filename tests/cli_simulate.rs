//! `rocklab simulate`: the JSON contract and the handling of bad input.

use crate::util::rocklab;

pub(crate) const BASE: &[&str] = &[
    "simulate",
    "--alpha",
    "0.17453292519943295",
    "--p",
    "2",
    "--amplitude-alpha",
    "1.5",
    "--frequency-ratio",
    "4",
    "--duration",
    "10",
];

pub(crate) fn with(extra: &[&str]) -> Vec<&'static str> {
    let mut v: Vec<&str> = BASE.to_vec();
    // Leak is fine in a test: the strings live for the process.
    v.extend(
        extra
            .iter()
            .map(|s| &*Box::leak(s.to_string().into_boxed_str())),
    );
    v
}

/// [`BASE`] with `flag`'s value replaced by `value` (clap refuses a flag given twice), then
/// `extra`.
pub(crate) fn with_value(flag: &str, value: &str, extra: &[&str]) -> Vec<&'static str> {
    let mut v = with(extra);
    let i = v.iter().position(|a| *a == flag).expect("a flag of BASE") + 1;
    v[i] = Box::leak(value.to_string().into_boxed_str());
    v
}

#[test]
fn the_text_summary_speaks_words_not_rust() {
    for device in [
        &["--device", "none"][..],
        &["--device", "mechanistic", "--sigma", "0.5"],
    ] {
        let out = rocklab(&with(device));
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = String::from_utf8(out.stdout).unwrap();
        let json = rocklab(&with(&[device, &["--json"][..]].concat()));
        let json: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
        // The end reason in the words the JSON uses, the structure and device by name.
        let first = text.lines().next().unwrap();
        let expected = format!(
            "structure rigid, device {}, end: {} at t = ",
            device[1],
            json["end_reason"].as_str().unwrap()
        );
        assert!(first.starts_with(&expected), "{first}\nnot {expected}");
        for rust in [
            "\"",
            "Some(",
            "None",
            "Duration",
            "Overturned",
            "Settled",
            "Rest",
        ] {
            assert!(!text.contains(rust), "{rust} in\n{text}");
        }
    }
}

#[test]
fn json_has_the_contract_keys_and_matches_the_library() {
    let out = rocklab(&with(&[
        "--device",
        "mechanistic",
        "--sigma",
        "0.5",
        "--json",
    ]));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert_eq!(stdout.trim().lines().count(), 1, "exactly one JSON object");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    for key in [
        "overturned",
        "peak_rotation",
        "peak_rotation_ratio",
        "peak_deformation",
        "peak_drift",
        "peak_abs_acceleration_g",
        "peak_angular_acceleration_p2",
        "impacts",
        "engagements",
        "energy_residual",
        "steps",
        "rhs_evals",
        "wall_seconds",
    ] {
        assert!(v.get(key).is_some(), "missing key {key}");
    }
    let ratio = v["peak_rotation"].as_f64().unwrap() / 0.17453292519943295;
    assert!((v["peak_rotation_ratio"].as_f64().unwrap() - ratio).abs() < 1e-12);
    assert_eq!(v["peak_deformation"].as_f64(), Some(0.0));
    assert!(v["engagements"].as_u64().unwrap() > 0);
    // The result records the modelling choices that produced it.
    assert_eq!(v["scene"]["device"]["mechanistic"]["reset"], "paper");
    assert_eq!(v["scene"]["structure"]["rigid"]["form"], "exact");
}

#[test]
fn history_csv_has_a_row_per_step_and_the_named_columns() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("h.csv");
    let p = path.to_str().unwrap();
    let out = rocklab(&with(&[
        "--device",
        "sequential",
        "--sigma",
        "0.5",
        "--history",
        p,
        "--json",
    ]));
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    for col in [
        "t",
        "theta",
        "theta_dot",
        "ground_accel",
        "device_force",
        "e_input",
    ] {
        assert!(header.split(',').any(|c| c == col), "{col} in {header}");
    }
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert!(rows.len() as u64 >= v["steps"].as_u64().unwrap());
    let peak = rows.iter().map(|r| r[1].abs()).fold(0.0, f64::max);
    // CSV values carry 11 significant digits.
    assert!(peak <= v["peak_rotation"].as_f64().unwrap() * (1.0 + 1e-9));
    assert!(peak > 0.95 * v["peak_rotation"].as_f64().unwrap());
}

fn assert_usage_error(args: &[&str], flag: &str) {
    let out = rocklab(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "args {args:?}: {stderr}");
    assert!(
        stderr.contains(flag),
        "message should name {flag}: {stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(out.stdout.is_empty());
}

#[test]
fn bad_values_name_the_flag_and_the_valid_range() {
    let cases: &[(&[&str], &str)] = &[
        (&["--alpha", "0"], "--alpha"),
        (&["--alpha", "-0.1"], "--alpha"),
        (&["--alpha", "1.6"], "--alpha"),
        (&["--alpha", "NaN"], "--alpha"),
        (&["--duration", "inf"], "--duration"),
        (&["--device", "inerter", "--sigma", "-0.5"], "--sigma"),
        (
            &[
                "--device",
                "mechanistic",
                "--sigma",
                "0.5",
                "--k-theta",
                "-1",
            ],
            "--k-theta",
        ),
        (
            &["--device", "mechanistic", "--sigma", "0.5", "--cbar", "-1"],
            "--cbar",
        ),
        (
            &[
                "--device",
                "mechanistic",
                "--sigma",
                "0.5",
                "--xi-theta",
                "-0.1",
            ],
            "--xi-theta",
        ),
        (
            &[
                "--device",
                "mechanistic",
                "--sigma",
                "0.5",
                "--epsilon",
                "0",
            ],
            "--epsilon",
        ),
        (
            &[
                "--device",
                "mechanistic",
                "--sigma",
                "0.5",
                "--play",
                "-0.001",
            ],
            "--play",
        ),
        (
            &[
                "--device",
                "mechanistic",
                "--sigma",
                "0.5",
                "--friction",
                "-0.1",
            ],
            "--friction",
        ),
        (&["--rtol", "0"], "--rtol"),
        (&["--impact", "dirac", "--width", "0"], "--width"),
    ];
    for (extra, flag) in cases {
        // Later flags override nothing: put the bad value in place of the base one.
        let mut args: Vec<&str> = BASE
            .iter()
            .copied()
            .filter(|a| !extra.contains(a))
            .collect();
        if extra.contains(&"--alpha") {
            let i = args
                .iter()
                .position(|a| *a == "0.17453292519943295")
                .unwrap();
            args.remove(i);
        }
        if extra.contains(&"--duration") {
            let i = args.iter().position(|a| *a == "10").unwrap();
            args.remove(i);
        }
        args.extend_from_slice(extra);
        assert_usage_error(&args, flag);
    }
}

#[test]
fn missing_and_contradictory_flags_are_usage_errors() {
    assert_usage_error(
        &[
            "simulate",
            "--p",
            "2",
            "--amplitude-g",
            "0.3",
            "--frequency",
            "8",
        ],
        "--alpha",
    );
    assert_usage_error(&with(&["--size", "1.8"]), "--size");
    assert_usage_error(&with(&["--device", "mechanistic"]), "--sigma");
    assert_usage_error(&with(&["--play", "0.001"]), "--play");
    assert_usage_error(&with(&["--frequency", "8"]), "--frequency");
    assert_usage_error(&with(&["--amplitude-g", "0.3"]), "--amplitude");
    assert_usage_error(&with(&["--impact", "dirac"]), "--width");
    assert_usage_error(
        &with(&[
            "--device",
            "mechanistic",
            "--sigma",
            "0.5",
            "--cbar",
            "1",
            "--xi-theta",
            "0.02",
        ]),
        "--cbar",
    );
}

/// `--repeat N` runs the scene N times in-process: the result is the single run's (the runs
/// are checked to agree), wall_seconds is the fastest run and never above the median.
#[test]
fn repeat_reports_the_fastest_run_beside_the_median_and_the_same_result() {
    let json = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec!["--json"];
        args.extend_from_slice(extra);
        let out = rocklab(&with(&args));
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let once = json(&[]);
    let five = json(&["--repeat", "5"]);
    assert_eq!(once["repeats"], 1);
    assert_eq!(five["repeats"], 5);
    assert_eq!(once["wall_seconds"], once["wall_seconds_median"]);
    let (fastest, median) = (
        five["wall_seconds"].as_f64().unwrap(),
        five["wall_seconds_median"].as_f64().unwrap(),
    );
    assert!(fastest > 0.0 && fastest <= median, "{fastest} {median}");
    for key in ["peak_rotation", "rhs_evals", "steps", "impacts", "end_time"] {
        assert_eq!(once[key], five[key], "{key}");
    }
    let zero = rocklab(&with(&["--repeat", "0"]));
    assert_eq!(zero.status.code(), Some(2), "--repeat 0 is a usage error");
}
