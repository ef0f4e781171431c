//! `rocklab records` and `rocklab simulate --record`.

use crate::util::rocklab_command;

/// Run `rocklab args` in `dir` without ROCKLAB_RECORDS: (exit code, stdout, stderr).
fn run_in(args: &[&str], dir: &std::path::Path) -> (i32, String, String) {
    let out = rocklab_command(args)
        .current_dir(dir)
        .env_remove("ROCKLAB_RECORDS")
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

fn crate_dir() -> std::path::PathBuf {
    env!("CARGO_MANIFEST_DIR").into()
}

#[test]
fn records_json_lists_every_record_with_its_source() {
    // From the crate (./records) and from anywhere else (embedded in the binary).
    let elsewhere = tempfile::tempdir().unwrap();
    for (dir, source) in [
        (crate_dir(), "file"),
        (elsewhere.path().to_path_buf(), "embedded"),
    ] {
        let (code, out, err) = run_in(&["records", "--json"], &dir);
        assert_eq!(code, 0, "{err}");
        let list: Vec<serde_json::Value> = serde_json::from_str(&out).unwrap();
        assert_eq!(list.len(), 6);
        for r in &list {
            let expect = if r["table1"] == 3 || r["table1"] == 5 {
                "stand-in"
            } else {
                source
            };
            assert_eq!(r["source"], expect, "{r}");
            if let Some(table) = r["pgv_table1"].as_f64() {
                let pgv = r["pgv"].as_f64().unwrap();
                assert!((pgv / table - 1.0).abs() < 5e-3, "{r}");
            }
        }
    }
    let (code, out, _) = run_in(&["records"], &crate_dir());
    assert_eq!(code, 0);
    assert!(out.contains("stand-in: MP pulse Tp 5.9 s, PGV 0.6 m/s"));
    assert!(out.contains("landers") && out.contains('█'));
}

#[test]
fn simulate_runs_a_record_by_name_number_or_path() {
    let base = ["simulate", "--size", "2", "--alpha", "0.2", "--json"];
    let dir = crate_dir();
    let path = dir.join("records/RSN1063_NORTHR_RRS032_FN.txt");
    let mut peaks = vec![];
    for record in ["northridge", "2", path.to_str().unwrap()] {
        let mut args = base.to_vec();
        args.extend(["--record", record, "--scale", "0.5"]);
        let (code, out, err) = run_in(&args, &dir);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        // Default duration: the record's 19.9 s plus 10 s of free rocking (or less, at rest).
        assert!((v["scene"]["duration"].as_f64().unwrap() - 29.9).abs() < 1e-9);
        peaks.push(v["peak_rotation"].as_f64().unwrap());
    }
    assert!(
        peaks[0] > 0.0 && peaks.iter().all(|p| *p == peaks[0]),
        "{peaks:?}"
    );
}

#[test]
fn simulate_record_usage_errors_exit_2() {
    let dir = crate_dir();
    let base = ["simulate", "--size", "2", "--alpha", "0.2"];
    for (extra, message) in [
        (vec!["--record", "nowhere"], "unknown record 'nowhere'"),
        (
            vec!["--record", "1", "--amplitude-g", "0.3"],
            "--amplitude-g only applies to pulses",
        ),
        (
            vec!["--record", "1", "--pulse", "ricker"],
            "--pulse and --record",
        ),
        (
            vec!["--amplitude-g", "0.3", "--frequency", "4", "--scale", "2"],
            "--scale only applies with --record",
        ),
        (
            vec!["--pulse", "mp", "--amplitude-g", "0.3", "--frequency", "4"],
            "--gamma is required",
        ),
        (
            vec![
                "--pulse", "mp", "--gamma", "0.5", "--tp", "1", "--pgv", "0.5",
            ],
            "--gamma",
        ),
    ] {
        let mut args = base.to_vec();
        args.extend(extra);
        let (code, _, err) = run_in(&args, &dir);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(message), "{args:?}: {err}");
    }
}

#[test]
fn simulate_accepts_the_new_pulse_families() {
    let dir = crate_dir();
    let base = ["simulate", "--size", "2", "--alpha", "0.2", "--json"];
    for extra in [
        vec![
            "--pulse",
            "ricker",
            "--amplitude-ratio",
            "1.5",
            "--frequency-ratio",
            "3",
        ],
        vec![
            "--pulse",
            "antisymmetric-ricker",
            "--amplitude-ratio",
            "1.5",
            "--frequency-ratio",
            "3",
        ],
        vec![
            "--pulse",
            "mp",
            "--gamma",
            "2",
            "--nu",
            "0.5",
            "--amplitude-ratio",
            "1.5",
            "--frequency-ratio",
            "3",
        ],
        vec![
            "--pulse", "mp", "--gamma", "2", "--tp", "1.2", "--pgv", "0.5",
        ],
    ] {
        let mut args = base.to_vec();
        args.extend(extra);
        let (code, out, err) = run_in(&args, &dir);
        assert_eq!(code, 0, "{args:?}: {err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert!(v["peak_rotation"].as_f64().unwrap() > 0.0, "{args:?}");
    }
}

#[test]
fn a_records_directory_from_the_environment_or_flag_replaces_a_stand_in() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::copy(
        crate_dir().join("records/index.ron"),
        tmp.path().join("index.ron"),
    )
    .unwrap();
    std::fs::write(
        tmp.path().join("RSN529_PALMSPR_NPS_FN.AT2"),
        "PEER NGA STRONG MOTION DATABASE RECORD\nN. Palm Springs\nACCELERATION TIME HISTORY IN UNITS OF G\n3    0.0050    NPTS, DT\n 0.1 -0.4 0.2\n",
    )
    .unwrap();
    let elsewhere = tempfile::tempdir().unwrap();
    let by_env = rocklab_command(&["records", "--json"])
        .current_dir(elsewhere.path())
        .env("ROCKLAB_RECORDS", tmp.path())
        .output()
        .unwrap();
    let dir = tmp.path().to_str().unwrap();
    let (code, by_flag, err) = run_in(
        &["records", "--json", "--records-dir", dir],
        elsewhere.path(),
    );
    assert_eq!(code, 0, "{err}");
    for out in [String::from_utf8(by_env.stdout).unwrap(), by_flag] {
        let list: Vec<serde_json::Value> = serde_json::from_str(&out).unwrap();
        let palm = list.iter().find(|r| r["name"] == "palm_springs").unwrap();
        assert_eq!(palm["source"], "file");
        assert_eq!(palm["npts"], 3);
        assert!((palm["pga_g"].as_f64().unwrap() - 0.4).abs() < 1e-12);
        // The others still come from the binary.
        let landers = list.iter().find(|r| r["name"] == "landers").unwrap();
        assert_eq!(landers["source"], "embedded");
    }
}

/// The stand-in records (Imperial Valley and N. Palm Springs here) are flagged in every
/// output: summary.txt, results.csv (`record_source`), results.json (`stand_in_records`),
/// `compare` (text and JSON) and `simulate --json`; a real record is not.
#[test]
fn stand_in_records_are_flagged_in_every_output() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("standin.ron");
    std::fs::write(
        &study,
        r#"(version: 1, name: "standin",
            structure: flexible(r0: 10.0, alpha: 0.2, xi: 0.02, omega_n: [5.0, 10.0]),
            devices: [none, sequential(sigma: 0.5)],
            excitation: record(names: ["landers", "imperial_valley"], scale: 1.0),
            quantities: [peak_rotation_ratio], spectrum: omega_n, duration: 3.0)"#,
    )
    .unwrap();
    let out = dir.path().join("out");
    let o = crate::util::run_into(study.to_str().unwrap(), &out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let note = rocklab::excitation::library::STAND_IN_NOTE;
    let summary = std::fs::read_to_string(out.join("summary.txt")).unwrap();
    assert!(
        summary.contains(&format!("{note}: imperial_valley\n")),
        "{summary}"
    );

    let mut csv = csv::Reader::from_path(out.join("results.csv")).unwrap();
    let headers = csv.headers().unwrap().clone();
    let col = |name: &str| headers.iter().position(|h| h == name).unwrap();
    let (excitation, source) = (col("excitation"), col("record_source"));
    let rows: Vec<csv::StringRecord> = csv.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), 8);
    for row in &rows {
        let stand_in = &row[excitation] == "imperial_valley";
        assert_eq!(&row[source] == "stand-in", stand_in, "{row:?}");
    }
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("results.json")).unwrap()).unwrap();
    assert_eq!(
        json["stand_in_records"],
        serde_json::json!(["imperial_valley"])
    );

    let o = crate::util::rocklab(&["compare", out.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains(&format!("{note}: imperial_valley")), "{text}");
    let json = crate::util::rocklab_json(&["compare", out.to_str().unwrap(), "--json"]);
    assert_eq!(
        json["stand_in_records"],
        serde_json::json!(["imperial_valley"])
    );

    let sim = |record: &str| {
        crate::util::rocklab_json(&[
            "simulate",
            "--structure",
            "flexible",
            "--size",
            "10",
            "--alpha",
            "0.2",
            "--xi",
            "0.02",
            "--omega-n",
            "10",
            "--record",
            record,
            "--duration",
            "2",
            "--json",
        ])
    };
    assert_eq!(sim("imperial_valley")["record_source"], "stand-in");
    assert_ne!(sim("landers")["record_source"], "stand-in");
}
