//! Issue 43's twelve findings of an independent campaign, one reproducer each (each failed
//! before its fix):
//!
//! | finding | test |
//! |---|---|
//! | F1 a value nested in 10 000 brackets overflows the stack | `a_value_nested_ten_thousand_deep_is_refused_naming_the_line` |
//! | F2 a design resolution below f64's spacing loops at 100 % CPU | `a_design_resolution_f64_cannot_resolve_is_refused`, `a_design_at_the_resolution_floor_ends` (and sweep/design.rs `a_bracket_f64_cannot_split_ends_the_bisection`) |
//! | F3 `slurm`'s out dir from the raw study name | `a_study_name_that_leaves_out_is_refused_and_slashes_read_alike` |
//! | F4 `%` in `--out` reaches `#SBATCH --output=` raw | `a_percent_in_the_out_dir_is_escaped_in_slurm_directives` |
//! | F5 a 20 MB bad line quoted twice in its error | `a_huge_bad_line_is_quoted_as_a_bounded_excerpt` |
//! | F6 `--scene-time-limit 2e19` panics | `a_scene_time_limit_past_durations_is_a_usage_error` |
//! | F7 a figure's pixel buffer aborts when memory is short | `a_png_whose_pixels_do_not_fit_in_memory_is_a_clear_error` |
//! | F8 an AT2 header with two `DT=` | `an_at2_header_that_gives_a_key_twice_is_refused` |
//! | F9 record values of 1e300 g | `implausible_record_values_are_refused_naming_file_and_line` |
//! | F10 `records: []` selects every record | `an_empty_suite_filter_is_refused` |
//! | F11 an index `file:` outside the records folder | `an_index_file_outside_the_records_folder_is_refused_unread` |
//! | F12 raw parser messages, bootstrap: 2 | `parser_messages_name_the_field_with_a_hint`, `a_bootstrap_too_small_for_its_interval_is_refused` |

use crate::strict_inputs::AT2;
use crate::util::{rocklab, rocklab_command};
use rocklab::excitation::reader;
use rocklab::study::Study;
use std::path::Path;

const DEFAULT: &str = include_str!("../studies/default.ron");
const DESIGN: &str = include_str!("../studies/design_sigma_rigid.ron");
const FRAGILITY: &str = include_str!("../studies/fragility_far_field.ron");

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `text` with `from` replaced once (which must be there).
fn edited(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "{from:?} is not in the study");
    text.replacen(from, to, 1)
}

fn refused(text: &str) -> rocklab::study::StudyError {
    match Study::from_ron_str(text, "s.ron") {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e,
    }
}

#[test]
fn a_value_nested_ten_thousand_deep_is_refused_naming_the_line() {
    let dir = tempfile::tempdir().unwrap();
    for depth in [5_000, 10_000, 100_000] {
        let nested = format!("{}2.0{}", "[".repeat(depth), "]".repeat(depth));
        let path = dir.path().join("deep.ron");
        std::fs::write(
            &path,
            edited(DEFAULT, "rigid(p: 2.0", &format!("rigid(p: {nested}")),
        )
        .unwrap();
        let o = rocklab(&["run", path.to_str().unwrap(), "--dry-run"]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "depth {depth}: {e}");
        assert!(e.contains("deep.ron:") && e.contains("nested"), "{e}");
        assert!(e.len() < 2_000, "{} bytes of message", e.len());
    }
    // Nesting a study needs (a list in a range in a device) is far from the bound.
    assert!(Study::from_ron_str(DEFAULT, "default.ron").is_ok());
}

#[test]
fn a_design_resolution_f64_cannot_resolve_is_refused() {
    for tiny in ["1e-300", "1e-17", "1e-16", "4e-16"] {
        let e = refused(&edited(
            DESIGN,
            "resolution: 0.01",
            &format!("resolution: {tiny}"),
        ));
        assert_eq!(e.field.as_deref(), Some("design.resolution"), "{e}");
        assert!(e.line.is_some(), "{e}");
        let text = e.to_string();
        assert!(text.contains(tiny), "{text}");
        assert!(text.contains("hint:") && text.len() < 400, "{text}");
    }
    // The floor: 4 ulps of any value (f64's relative spacing is at most 2.2e-16).
    let floor = rocklab::study::design::MIN_RESOLUTION;
    assert_eq!(floor, 4.0 * f64::EPSILON);
    let ok = edited(
        DESIGN,
        "resolution: 0.01",
        &format!("resolution: {floor:e}"),
    );
    assert!(Study::from_ron_str(&ok, "s.ron").is_ok());
}

/// A one-point design at the finest resolution accepted: its bisection runs the ~50 halvings
/// f64 allows and ends, with a bracket no wider than the resolution asks.
#[test]
fn a_design_at_the_resolution_floor_ends() {
    let text = edited(
        DESIGN,
        "alpha: [deg(6), deg(8), deg(10), deg(12), deg(14)]",
        "alpha: deg(10)",
    );
    let text = edited(
        &text,
        "        mechanistic(sigma: 0.5, clutch_frequency_ratio: 25.0, cbar: 1.0),\n",
        "",
    );
    let text = edited(&text, "(from: 3.0, to: 10.0, steps: 15)", "3.0");
    let text = edited(&text, "resolution: 0.01", "resolution: 1e-15");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("fine.ron");
    std::fs::write(&path, &text).unwrap();
    let results = crate::util::run_study_file(&path);
    let study = results.study.clone().unwrap();
    let rows = rocklab::sweep::design::replay(&study, &results.outcomes).unwrap();
    let found: Vec<_> = rows
        .iter()
        .filter(|r| r.status == rocklab::sweep::design::DesignStatus::Found)
        .collect();
    assert!(!found.is_empty(), "{rows:?}");
    for row in found {
        assert!(
            row.lo < row.hi && row.hi - row.lo <= 1e-15 * row.hi,
            "{row:?}"
        );
        // About log2(3 / 1e-15) ≈ 52 halvings, the two ends and the verification probes.
        assert!((50..=80).contains(&row.probes), "{row:?}");
    }
}

#[test]
fn a_study_name_that_leaves_out_is_refused_and_slashes_read_alike() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["../../x", "..", "/abs/path", "a/../../b"] {
        let study = dir.path().join("named.ron");
        let text = edited(DEFAULT, "name: \"default\"", &format!("name: {name:?}"));
        std::fs::write(&study, text).unwrap();
        for command in ["slurm", "run"] {
            let o = rocklab_command(&[command, study.to_str().unwrap()])
                .current_dir(dir.path())
                .output()
                .unwrap();
            let e = stderr(&o);
            assert_eq!(o.status.code(), Some(2), "{command} {name}: {e}");
            assert!(e.contains("name") && e.contains("--out"), "{e}");
        }
    }
    assert!(!dir.path().join("x").exists() && !dir.path().join("out").exists());
    // `a/b` is one folder under out/ for `slurm` as for `run`.
    let study = dir.path().join("ab.ron");
    std::fs::write(
        &study,
        edited(DEFAULT, "name: \"default\"", "name: \"a/b\""),
    )
    .unwrap();
    let o = rocklab_command(&["slurm", study.to_str().unwrap(), "--tasks", "2"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("out/a_b/slurm/array.sh").is_file());
    assert!(!dir.path().join("out/a").exists());
    let out = rocklab::sweep::default_out_dir(Path::new("out"), "a/b").unwrap();
    assert_eq!(out, Path::new("out/a_b"));
}

#[test]
fn a_percent_in_the_out_dir_is_escaped_in_slurm_directives() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run%j_%x%%");
    let o = rocklab(&[
        "slurm",
        "default",
        "--tasks",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let script = std::fs::read_to_string(out.join("slurm/array.sh")).unwrap();
    let output = script
        .lines()
        .find_map(|l| l.strip_prefix("#SBATCH --output="))
        .unwrap();
    // sbatch reads `%%` as `%` and `%A`/`%a` as the job and task: the folder is the one
    // rocklab made, the file name keeps its own patterns.
    let logs = output.strip_suffix("/array-%A_%a.log").unwrap();
    assert_eq!(
        logs.replace("%%", "%"),
        out.join("slurm/logs").display().to_string()
    );
    assert!(out.join("slurm/logs").is_dir());
}

#[test]
fn a_huge_bad_line_is_quoted_as_a_bounded_excerpt() {
    let garbage = "x".repeat(2_000_000);
    for text in [
        format!("PEER\nX\nACCELERATION IN UNITS OF G\nNPTS= 2, DT= 0.01 SEC\n0.1 {garbage}\n"),
        format!("# dt: 0.01\n0.1\n{garbage}\n"),
        format!("# dt: 0.01\n0.1\n1{garbage}\n"),
        format!("PEER\nX\nY\nNPTS= {garbage}, DT= 0.01 SEC\n0.1\n"),
    ] {
        let e = reader::parse(&text, "big.AT2", None).unwrap_err();
        assert!(e.line >= 3, "{e}");
        assert!(e.to_string().len() < 600, "{} bytes", e.to_string().len());
        assert!(e.to_string().contains("xxxx…"), "{e}");
    }
}

#[test]
fn a_scene_time_limit_past_durations_is_a_usage_error() {
    use clap::Parser;
    for command in ["run", "check"] {
        for limit in ["2e19", "1e300", "18446744073709551616"] {
            let args = ["rocklab", command, "default", "--scene-time-limit", limit];
            let e = rocklab::cli::Cli::try_parse_from(args).err();
            let e = e.unwrap_or_else(|| panic!("{command} --scene-time-limit {limit} accepted"));
            assert!(e.to_string().contains("--scene-time-limit"), "{e}");
        }
        let args = ["rocklab", command, "default", "--scene-time-limit", "1e9"];
        assert!(rocklab::cli::Cli::try_parse_from(args).is_ok());
    }
}

/// Under an address-space limit well below the PNG's 5.8 GB of pixels, the figure is refused
/// with a message naming the size, not an abort.
#[cfg(target_os = "linux")]
#[test]
fn a_png_whose_pixels_do_not_fit_in_memory_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = crate::util::run_into("default", &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let png = dir.path().join("big.png");
    let script = format!(
        "ulimit -v 3000000 && exec {} plot {} --png {} --size 2000x2000mm --dpi 560 \
         --max-megapixels 2000",
        env!("CARGO_BIN_EXE_rocklab"),
        out.join("results.json").display(),
        png.display()
    );
    let o = std::process::Command::new("sh")
        .args(["-c", &script])
        .output()
        .unwrap();
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("memory") && e.contains("--dpi"), "{e}");
    // `--png` names a folder: no figure was left in it.
    let left = std::fs::read_dir(&png).map_or(0, |d| d.count());
    assert_eq!(left, 0, "{e}");
}

#[test]
fn an_at2_header_that_gives_a_key_twice_is_refused() {
    assert_eq!(reader::parse(AT2, "r.AT2", None).unwrap().dt(), 0.01);
    for header in [
        "NPTS=    6, DT=   .0100 SEC, DT= .0200 SEC",
        "NPTS=    6, DT=   .0100 SEC DT=.0200",
        "NPTS=    6, NPTS= 6, DT=   .0100 SEC",
    ] {
        let text = AT2.replace("NPTS=    6, DT=   .0100 SEC", header);
        let e = reader::parse(&text, "r.AT2", None).unwrap_err();
        assert_eq!(e.line, 4, "{e}");
        assert!(e.message.contains("more than once"), "{e}");
    }
}

#[test]
fn implausible_record_values_are_refused_naming_file_and_line() {
    for (value, units) in [("1e300", "G"), ("-250", "G"), ("200000", "CM/S2")] {
        let text = AT2
            .replace("0.5", value)
            .replace("UNITS OF G", &format!("UNITS OF {units}"));
        let e = reader::parse(&text, "r.AT2", None).unwrap_err();
        assert_eq!((e.origin.as_str(), e.line), ("r.AT2", 6), "{e}");
        assert!(e.message.contains(value), "{e}");
    }
    // The strongest motions recorded (~4 g) and a cm/s² record of them read.
    let strong = AT2.replace("0.5", "4.4");
    assert!(reader::parse(&strong, "r.AT2", None).is_ok());
    let gal = AT2
        .replace("0.5", "-4300")
        .replace("UNITS OF G", "UNITS OF CM/S2");
    assert!(reader::parse(&gal, "r.AT2", None).is_ok());
    // One-column files too.
    let e = reader::parse("# dt: 0.01\n0.1\n1e300\n", "c.txt", None).unwrap_err();
    assert_eq!(e.line, 3, "{e}");
}

#[test]
fn an_empty_suite_filter_is_refused() {
    let text = edited(
        FRAGILITY,
        "suite: (name: \"far_field\")",
        "suite: (name: \"far_field\", records: [])",
    );
    let e = refused(&text);
    assert_eq!(e.field.as_deref(), Some("excitation.suite.records"), "{e}");
    assert!(e.line.is_some() && e.hint.is_some(), "{e}");
}

#[test]
fn an_index_file_outside_the_records_folder_is_refused_unread() {
    let index = include_str!("../records/index.ron");
    let file = index
        .lines()
        .find_map(|l| l.trim().strip_prefix("file: "))
        .unwrap()
        .trim_end_matches(',');
    let dir = tempfile::tempdir().unwrap();
    let secret = dir.path().join("secret.AT2");
    std::fs::write(&secret, "TOP SECRET FIRST LINE\n").unwrap();
    let records = dir.path().join("records");
    std::fs::create_dir(&records).unwrap();
    for outside in [secret.display().to_string(), "../secret.AT2".to_string()] {
        std::fs::write(
            records.join("index.ron"),
            index.replacen(file, &format!("{outside:?}"), 1),
        )
        .unwrap();
        let e = match rocklab::excitation::library::Library::open(Some(records.clone())) {
            Ok(_) => panic!("{outside} accepted"),
            Err(e) => e.to_string(),
        };
        assert!(e.contains("index.ron:") && e.contains("file"), "{e}");
        assert!(!e.contains("TOP SECRET"), "{e}");
    }
}

#[test]
fn parser_messages_name_the_field_with_a_hint() {
    let fragility = "fragility: (damage_states: levels([0.2, 0.5, 1.0]))";
    for (from, to, field) in [
        (
            fragility,
            "fragility: (damage_states: levels([0.2, 0.5, 1.0]), seed: 1.5)",
            "fragility.seed",
        ),
        (
            fragility,
            "fragility: (damage_states: levels([0.2, 0.5, 1.0]), bootstrap: -1)",
            "fragility.bootstrap",
        ),
        (
            fragility,
            "fragility: (damage_states: levels([0.2, 0.5, 1.0]), bootstrap: \"x\")",
            "fragility.bootstrap",
        ),
        ("tail: 10.0", "tail: 10.0.0", "excitation.tail"),
        ("name: \"fragility_far_field\"", "name: 5", "name"),
        ("version: 1", "version: 1.5", "version"),
    ] {
        let e = refused(&edited(FRAGILITY, from, to));
        assert_eq!(e.field.as_deref(), Some(field), "{to}: {e}");
        assert!(e.line.is_some() && e.hint.is_some(), "{e}");
        assert!(!e.to_string().contains("Expected comma"), "{e}");
    }
    let e = refused(&edited(
        FRAGILITY,
        fragility,
        "fragility: (damage_states: levels([0.2, 0.5, 1.0]), seed: 1.5)",
    ));
    assert!(e.message.contains("whole number"), "{e}");
    let e = refused(&edited(
        FRAGILITY,
        fragility,
        "fragility: (damage_states: levels([0.2, 0.5, 1.0]), bootstrap: -1)",
    ));
    assert!(e.message.contains("-1"), "{e}");
}

#[test]
fn a_bootstrap_too_small_for_its_interval_is_refused() {
    let fragility = "fragility: (damage_states: levels([0.2, 0.5, 1.0]))";
    for n in [1, 2, 199] {
        let to = format!("fragility: (damage_states: levels([0.2, 0.5, 1.0]), bootstrap: {n})");
        let e = refused(&edited(FRAGILITY, fragility, &to));
        assert_eq!(e.field.as_deref(), Some("fragility.bootstrap"), "{e}");
        assert!(e.to_string().contains("200"), "{e}");
    }
    for n in [0, 200, 1000] {
        let to = format!("fragility: (damage_states: levels([0.2, 0.5, 1.0]), bootstrap: {n})");
        assert!(Study::from_ron_str(&edited(FRAGILITY, fragility, &to), "s.ron").is_ok());
    }
}
