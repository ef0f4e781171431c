//! Issue 29's cases: silently different inputs, each now refused where it is written (record
//! files whose counts, headers, units or repeated lines disagree with their data, a records
//! index with a name or Table 1 row given twice or units that are not an acceleration's or
//! not the file's, a `$ROCKLAB_RECORDS` that names no directory), and bounded resources (a
//! history capped before it fills memory, shard counts and figure sizes bounded).
//!
//! Every case of the issue and the test that covers it:
//!
//! | issue 29 case | test |
//! |---|---|
//! | `sigma: xi(0.5)`, `alpha_ratio(g(1.5))`, `play: sine(0.001)`, `alpha: p(0.2)`, `ratio(ratio(4.0))` | study.rs `a_wrapper_or_key_that_means_nothing_is_refused_where_it_is_written` |
//! | raw string with a quote desyncs the name scanner | same test (the `r#"tricky " quote"#` part) |
//! | duplicate key inside a range | same test (`from` twice) |
//! | selectors skip the strict reading (`compare --a 'mechanistic(friction: foo(0.0))'`) | src/report/select.rs `selectors_parse_in_study_syntax` |
//! | the TUI editor takes `xi(0.5)` for `mass` | `the_editors_parser_refuses_a_wrapper_on_mass` (below; the editor parses with `Study::parse_ron`) |
//! | AT2 NPTS smaller than its data; an extra value on a line; `VELOCITY` header; two `# dt:`; `# npts: 10` with 3 values | `record_files_that_disagree_with_themselves_are_refused` |
//! | AT2 of 1e300 with `--scale-pga` "is all zeros" | messages.rs `a_huge_record_is_refused_naming_its_line_even_scaled_to_a_pga` (issue 43 refuses the file) |
//! | index.ron: `landers` twice, `units: "furlongs"`, `"cm/s2"` against `# units: g`, `table1` twice | `a_records_index_that_names_twice_or_mislabels_units_is_refused` |
//! | `ROCKLAB_RECORDS=/nonexist` ignored (records, simulate, the workbench) | `a_records_variable_that_names_no_directory_is_an_error` |
//! | a journal line edited on disk is reused | checkpoint.rs `an_edited_journal_line_is_recomputed_not_reused` |
//! | `run --force` three times overwrites `results.json.previous` | checkpoint.rs `forced_runs_never_overwrite_set_aside_results` |
//! | `simulate … --duration 1e300 --history` grows to 8.4 GB | `a_history_stops_at_its_row_cap` |
//! | `plot --size 5x5mm` / `100x5mm` / PNG: minutes, gigabytes | `figures_too_small_for_their_panels_are_refused` (below), figure.rs `sizes_below_half_the_panels_and_pngs_over_the_pixel_cap_are_refused` |
//! | `plot --png --size 2000x2000mm --dpi 2400` panics | `a_figure_over_the_pixel_cap_is_refused_before_drawing`, figure.rs (the 2000-megapixel ceiling) |
//! | `status` quadratic in the shard count | BENCHMARKS.md "Post-processing and status at scale"; status.rs `set_names_parse` (no shard count above the scene cap) |
//! | `run --shard 0/1000000` on a 36-scene study | `a_shard_count_above_the_scene_count_is_refused` |
//! | 400 000-scene post-processing quadratic | BENCHMARKS.md "Post-processing and status at scale" (no timing assertions) |
//! | SIGTERM ignored during post-processing | finalise.rs `a_signal_while_the_results_are_written_stops_at_once_and_loses_no_scene` |
//! | `slurm --partition $'p\n#SBATCH …'`, `--account 'a b;id'` | slurm.rs `hostile_values_never_reach_a_script_as_code` |
//! | `simulate --p 1e300` / `--p 1e-300` name `--size` | messages.rs `a_p_that_gives_no_usable_size_names_p` |
//! | AT2 1e300 under `--scale-pga 0.5 --baseline` "is all zeros" | messages.rs `a_huge_record_is_refused_naming_its_line_even_scaled_to_a_pga` (issue 43 refuses the file) |
//! | `--scene-time-limit 0.0001` prints "limit of 0 s" | messages.rs `a_tiny_scene_time_limit_is_reported_as_given` |
//! | `table … \| head -1` prints "Broken pipe", exits 1 | messages.rs `table_into_a_pipe_closed_after_one_line_exits_quietly` |
//! | `nan` in a study: "found a unit value" | messages.rs `nan_and_infinities_in_a_study_name_the_field` |
//! | 1e308 printed as a 309-digit number | messages.rs `huge_numbers_in_messages_read_in_scientific_notation` |
//! | fuzz targets: study parser, record reader, index (bounded, in `cargo test`) | fuzz.rs `the_study_parser_never_panics*`, `the_record_reader_never_panics*`, `the_records_index_never_panics` |

use crate::util::rocklab_command;
use rocklab::excitation::library::{Library, RecordError};
use rocklab::excitation::reader;
use std::path::Path;

/// The error of a record text that must be refused: (line, message).
fn refused(text: &str) -> (usize, String) {
    match reader::parse(text, "r.AT2", None) {
        Ok(s) => panic!("accepted ({} samples):\n{text}", s.npts()),
        Err(e) => {
            assert_eq!(e.origin, "r.AT2");
            (e.line, e.message)
        }
    }
}

/// A well-formed six-sample AT2 file (also the base of tests/campaign.rs's header mutants).
pub(crate) const AT2: &str = "PEER NGA STRONG MOTION DATABASE RECORD\nLANDERS\n\
                   ACCELERATION TIME HISTORY IN UNITS OF G\n\
                   NPTS=    6, DT=   .0100 SEC\n\
                   0.1 0.2 0.3\n0.4 0.5 0.6\n";

#[test]
fn record_files_that_disagree_with_themselves_are_refused() {
    let ok = reader::parse(AT2, "r.AT2", None).unwrap();
    assert_eq!(ok.samples().len(), 6);
    assert!((ok.samples()[5] - 0.6 * rocklab::excitation::G).abs() < 1e-12);
    // Zeros filling the line that completes NPTS are padding, not data.
    let padded = AT2
        .replace("NPTS=    6", "NPTS=    5")
        .replace("0.5 0.6", "0.5 0.0");
    assert_eq!(reader::parse(&padded, "r", None).unwrap().npts(), 5);

    // NPTS smaller than the data: not truncated.
    let (line, m) = refused(&AT2.replace("NPTS=    6", "NPTS=    4"));
    assert_eq!(line, 6, "{m}");
    assert!(m.contains("NPTS = 4"), "{m}");
    // An extra value on a line would shift every later sample.
    let (line, m) = refused(&AT2.replace("0.4 0.5 0.6", "0.4 0.5 0.6 0.7"));
    assert_eq!(line, 6, "{m}");
    let (line, m) = refused(&AT2.replace("0.4 0.5 0.6\n", "0.4 0.5\n0.6\n"));
    assert!(
        line == 6 && m.contains("2 values on this line but 3"),
        "{line}: {m}"
    );
    // A velocity record is not an acceleration.
    let (line, m) = refused(&AT2.replace(
        "ACCELERATION TIME HISTORY IN UNITS OF G",
        "VELOCITY TIME HISTORY IN UNITS OF CM/S",
    ));
    assert_eq!(line, 3, "{m}");
    assert!(m.contains("velocity"), "{m}");
    let (line, m) = refused(&AT2.replace("UNITS OF G", "UNITS OF FURLONGS"));
    assert!(line == 3 && m.contains("furlongs"), "{line}: {m}");

    // Column files: a header line given twice, a count that disagrees, velocity units.
    let col = "# dt: 0.01\n# units: g\n# npts: 3\n0.1\n0.2\n0.3\n";
    assert_eq!(reader::parse(col, "c", None).unwrap().npts(), 3);
    for (from, to, line, word) in [
        ("# dt: 0.01\n", "# dt: 0.01\n# dt: 0.02\n", 2, "dt"),
        ("# units: g\n", "# units: g\n# units: g\n", 3, "units"),
        ("# npts: 3", "# npts: 10", 3, "npts: 10"),
        ("# units: g", "# units: cm/s", 2, "velocity"),
        ("# units: g", "# units: furlongs", 2, "furlongs"),
    ] {
        let text = col.replace(from, to);
        let e = reader::parse(&text, "c.txt", None).expect_err(&text);
        assert_eq!(e.line, line, "{e}");
        assert!(e.message.contains(word), "{e}");
    }
    let e = reader::parse(&col.replace("0.2\n", "0.2 0.25\n"), "c", None).unwrap_err();
    assert_eq!(e.line, 5, "{e}");
}

/// A copy of the shipped records directory with `index.ron` edited by `edit`.
fn records_with(edit: impl Fn(&str) -> String) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let from = Path::new(env!("CARGO_MANIFEST_DIR")).join("records");
    for entry in std::fs::read_dir(&from).unwrap() {
        let path = entry.unwrap().path();
        if !path.is_file() {
            continue;
        }
        std::fs::copy(&path, dir.path().join(path.file_name().unwrap())).unwrap();
    }
    let index = std::fs::read_to_string(from.join("index.ron")).unwrap();
    let edited = edit(&index);
    assert_ne!(edited, index, "the edit changed nothing");
    std::fs::write(dir.path().join("index.ron"), edited).unwrap();
    dir
}

fn open_error(dir: &Path) -> (usize, String) {
    match Library::open(Some(dir.to_path_buf())) {
        Ok(_) => panic!("index accepted"),
        Err(RecordError::Parse(e)) => {
            assert!(e.origin.ends_with("index.ron"), "{e}");
            (e.line, e.message)
        }
        Err(e) => panic!("{e}"),
    }
}

#[test]
fn a_records_index_that_names_twice_or_mislabels_units_is_refused() {
    let lib = Library::open(Some(Path::new(env!("CARGO_MANIFEST_DIR")).join("records"))).unwrap();
    assert!(lib.load("landers", false).is_ok());

    let twice = records_with(|t| t.replacen("name: \"northridge\"", "name: \"landers\"", 1));
    let (line, m) = open_error(twice.path());
    assert_eq!(line, 33, "{m}");
    assert!(m.contains("landers") && m.contains("line 14"), "{m}");

    let row = records_with(|t| t.replacen("table1: Some(2)", "table1: Some(1)", 1));
    let (line, m) = open_error(row.path());
    assert_eq!(line, 34, "{m}");
    assert!(m.contains("table1: 1"), "{m}");

    let furlongs = records_with(|t| t.replacen("units: \"g\"", "units: \"furlongs\"", 1));
    let (line, m) = open_error(furlongs.path());
    assert!(line == 29 && m.contains("furlongs"), "{line}: {m}");

    // Units the file itself contradicts (it says `# units: g`).
    let cms2 = records_with(|t| t.replacen("units: \"g\"", "units: \"cm/s2\"", 1));
    let lib = Library::open(Some(cms2.path().to_path_buf())).unwrap();
    let e = lib.load("landers", false).unwrap_err().to_string();
    assert!(e.contains("cm/s2") && e.contains("RSN879"), "{e}");
    // A sample count the file contradicts.
    let npts = records_with(|t| t.replacen("npts: Some(9625)", "npts: Some(9626)", 1));
    let lib = Library::open(Some(npts.path().to_path_buf())).unwrap();
    let e = lib.load("landers", false).unwrap_err().to_string();
    assert!(e.contains("9626") && e.contains("9625"), "{e}");
}

#[test]
fn a_records_variable_that_names_no_directory_is_an_error() {
    for args in [
        &["records"][..],
        &[
            "simulate", "--record", "landers", "--alpha", "0.2", "--p", "2",
        ][..],
        // The workbench refuses it before taking the terminal (no TTY here: without the
        // check it would fail on the terminal instead, with no word of the variable).
        &["tui"][..],
    ] {
        let o = rocklab_command(args)
            .env("ROCKLAB_RECORDS", "/nonexistent/records")
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?}: {stderr}");
        assert!(
            stderr.contains("ROCKLAB_RECORDS") && stderr.contains("/nonexistent/records"),
            "{args:?}: {stderr}"
        );
    }
}

/// More shards than scenes is refused (a shard of no scene would write an empty results set).
#[test]
fn a_shard_count_above_the_scene_count_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let o = crate::util::rocklab(&[
        "run",
        "default",
        "--shard",
        "0/1000000",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("--shard 0/1000000") && stderr.contains("36 scenes"),
        "{stderr}"
    );
    assert!(!out.join("results.shard-0-of-1000000.json").exists());
}

/// The issue's endless-impact scene with a 1e300 s duration: the history stops at its cap
/// (named in the message with the flag that raises it) instead of growing to gigabytes.
#[test]
fn a_history_stops_at_its_row_cap() {
    let dir = tempfile::tempdir().unwrap();
    let h = dir.path().join("h.csv");
    let o = crate::util::rocklab(&[
        "simulate",
        "--alpha",
        "10deg",
        "--p",
        "2",
        "--theta0",
        "0.1",
        "--restitution",
        "1",
        "--amplitude-g",
        "0",
        "--frequency",
        "1",
        "--duration",
        "1e300",
        "--history",
        h.to_str().unwrap(),
        "--max-history-rows",
        "5000",
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{stderr}");
    assert!(
        stderr.contains("cap of 5000 rows") && stderr.contains("--max-history-rows"),
        "{stderr}"
    );
    assert!(!h.exists());
}

/// A PNG of --size at --dpi over the pixel cap is refused before anything is drawn.
#[test]
fn a_figure_over_the_pixel_cap_is_refused_before_drawing() {
    let dir = tempfile::tempdir().unwrap();
    let o = crate::util::rocklab(&[
        "plot",
        "/nonexistent/results.json",
        "--png",
        dir.path().to_str().unwrap(),
        "--size",
        "2000x2000mm",
        "--dpi",
        "2400",
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("--max-megapixels") && stderr.contains("100 megapixels"),
        "{stderr}"
    );
}

/// The workbench's editor reads an edited study with `Study::parse_ron`: a wrapper that means
/// nothing on `mass` is refused there too, naming it.
#[test]
fn the_editors_parser_refuses_a_wrapper_on_mass() {
    let text = include_str!("../studies/default.ron");
    let from = "rigid(p: 2.0,";
    assert!(text.contains(from));
    let edited = text.replacen(from, "rigid(mass: xi(0.5), p: 2.0,", 1);
    let e = rocklab::study::Study::parse_ron(&edited, "edit").unwrap_err();
    assert!(e.to_string().contains("`xi(…)` means nothing here"), "{e}");
    assert_eq!(e.field.as_deref(), Some("structure.mass"), "{e}");
}

/// `plot --size` below what a figure's panels and labels need is refused with the size it
/// needs, for SVG and PNG, before plotters gets a panel of no size (it spent minutes and
/// gigabytes on 5x5mm); at that size the figure is drawn.
#[test]
fn figures_too_small_for_their_panels_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = crate::util::run_into("default", &out);
    assert!(o.status.success());
    let figs = dir.path().join("figs");
    let plot = |format: &str, size: &str| {
        crate::util::rocklab(&[
            "plot",
            out.to_str().unwrap(),
            format,
            figs.to_str().unwrap(),
            "--scene",
            "0",
            "--size",
            size,
        ])
    };
    for (format, size) in [
        ("--svg", "5x5mm"),
        ("--svg", "100x5mm"),
        ("--png", "5x5mm"),
        ("--png", "100x5mm"),
    ] {
        let o = plot(format, size);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{format} {size}: {stderr}");
        assert!(
            stderr.contains(&format!("--size {size} is too small for the"))
                && stderr.contains("at least"),
            "{format} {size}: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
    // At 80x91mm every figure of the default study fits (the scene figure needs 80x75mm).
    let o = plot("--png", "80x91mm");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    assert!(figs.join("scene-0.png").exists());
    // No temporary file is left behind by a refused figure.
    for entry in std::fs::read_dir(&figs).unwrap() {
        let name = entry.unwrap().file_name();
        assert!(!name.to_string_lossy().starts_with(".tmp"), "{name:?}");
    }
}
