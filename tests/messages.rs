//! Issue 29's "Messages": every error names the input the user gave, in numbers as they
//! read (never 1e308 as 309 digits), and output cut short by a closed pipe ends quietly.

use crate::util::{default_run_with_scene_time_limit, rocklab, rocklab_command};
use std::io::BufRead;
use std::process::Stdio;

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A study line changed in the default study: the error of loading it.
fn study_error(from: &str, to: &str) -> String {
    let text = include_str!("../studies/default.ron");
    assert!(text.contains(from), "{from}");
    let text = text.replacen(from, to, 1);
    match rocklab::study::Study::from_ron_str(&text, "edited.ron") {
        Ok(_) => panic!("accepted: {to}"),
        Err(e) => e.to_string(),
    }
}

/// No number printed with more than 20 digits in a row.
fn no_long_numbers(text: &str) {
    let longest = text
        .split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0);
    assert!(longest <= 20, "a {longest}-digit number in: {text}");
}

#[test]
fn nan_and_infinities_in_a_study_name_the_field() {
    for word in ["nan", "NaN", "inf", "-inf", "Infinity"] {
        let e = study_error("alpha: 0.17453292519943295", &format!("alpha: {word}"));
        assert!(
            e.contains("structure.alpha") && e.contains(&format!("`{word}` is not a number")),
            "{word}: {e}"
        );
        assert!(!e.contains("unit value"), "{e}");
        // Inside a list too, with the item's place.
        let e = study_error("sigma: 0.5", &format!("sigma: [0.5, {word}]"));
        assert!(
            e.contains("sigma[1]") && e.contains("not a number"),
            "{word}: {e}"
        );
    }
}

#[test]
fn huge_numbers_in_messages_read_in_scientific_notation() {
    // A value given twice.
    let e = study_error("sigma: 0.5", "sigma: [1e308, 1e308]");
    assert!(e.contains("the value 1e308 is given twice"), "{e}");
    no_long_numbers(&e);
    // p gives the size: the message speaks of p.
    let e = study_error("p: 2.0", "p: 1e308");
    assert!(e.contains("structure.p: gives a size R = 0 m"), "{e}");
    // A record header's DT.
    let dir = tempfile::tempdir().unwrap();
    for (dt, expected) in [
        ("-1e308", "DT = -1e308 must be > 0"),
        ("1e308", "DT 1e308 s is not a usable time step"),
    ] {
        let path = dir.path().join("r.AT2");
        std::fs::write(
            &path,
            format!(
                "PEER\nX\nACCELERATION TIME HISTORY IN UNITS OF G\nNPTS=    3, DT=   {dt} \
                 SEC\n0.1 0.2 0.3\n"
            ),
        )
        .unwrap();
        let o = rocklab(&[
            "simulate",
            "--alpha",
            "10deg",
            "--p",
            "2",
            "--record",
            path.to_str().unwrap(),
        ]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{e}");
        assert!(e.contains(expected) && e.contains("r.AT2:4"), "{e}");
        // Not a flag the user never gave (the record's length was infinite).
        assert!(!e.contains("--duration"), "{e}");
        no_long_numbers(&e);
    }
    assert_eq!(rocklab::numfmt::fmt_num(1e308), "1e308");
    assert_eq!(rocklab::numfmt::fmt_exact(-1e308), "-1e308");
    assert_eq!(rocklab::numfmt::fmt_exact(0.25), "0.25");
    assert_eq!(rocklab::numfmt::fmt_exact(1e-300), "1e-300");
}

#[test]
fn a_p_that_gives_no_usable_size_names_p() {
    for (p, size) in [("1e300", "R = 0e0 m"), ("1e-300", "R = inf m")] {
        let o = rocklab(&[
            "simulate",
            "--alpha",
            "10deg",
            "--p",
            p,
            "--amplitude-g",
            "0.3",
            "--frequency",
            "1",
        ]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{e}");
        assert!(
            e.contains(&format!("invalid value {p} for --p: gives a size {size}")),
            "{e}"
        );
        assert!(!e.contains("for --size"), "{e}");
    }
}

/// Values of 1e300 g, even scaled to a PGA of 0.5 g and baseline corrected: no record holds
/// them, so the reader refuses the file naming its line and value (issue 43, F9), never
/// "is all zeros" (issue 29) nor a "step size underflow" naming nothing.
#[test]
fn a_huge_record_is_refused_naming_its_line_even_scaled_to_a_pga() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("huge.AT2");
    std::fs::write(
        &path,
        "PEER\nX\nACCELERATION TIME HISTORY IN UNITS OF G\nNPTS=    4, DT=   0.01 SEC\n\
         1e300 -1e300 1e300 -1e300\n",
    )
    .unwrap();
    let o = rocklab(&[
        "simulate",
        "--alpha",
        "10deg",
        "--p",
        "2",
        "--record",
        path.to_str().unwrap(),
        "--scale-pga",
        "0.5",
        "--baseline",
        "--json",
    ]);
    let e = stderr(&o);
    assert!(!o.status.success(), "{e}");
    assert!(e.contains("huge.AT2:5: 1e300 g is not a plausible"), "{e}");
    assert!(!e.contains("all zeros"), "{e}");
}

#[test]
fn a_tiny_scene_time_limit_is_reported_as_given() {
    let reasons: Vec<String> = default_run_with_scene_time_limit("0.0001")
        .into_iter()
        .flatten()
        .collect();
    // Every default scene takes milliseconds: the limit stops some of them.
    assert!(!reasons.is_empty());
    for r in reasons {
        assert!(r.contains("limit of 0.0001 s per scene"), "{r}");
    }
}

/// `rocklab table DIR | head -1`: the reader goes away after one line; the command ends
/// quietly, as Unix tools do.
#[test]
fn table_into_a_pipe_closed_after_one_line_exits_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let study = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/overturning_map_rigid.ron"
    );
    let o = crate::util::run_into(study, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut child = rocklab_command(&["table", out.to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    std::io::BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    assert!(first.starts_with("scene,"), "{first}");
    // The reader is dropped here, with hundreds of kilobytes still to come.
    let o = child.wait_with_output().unwrap();
    // Ended as `seq … | head -1` ends: by SIGPIPE's default action (as every print-only
    // command, src/cli/mod.rs), or with status 0 if it had written all before; never 1.
    use std::os::unix::process::ExitStatusExt;
    assert!(
        o.status.success() || o.status.signal() == Some(libc::SIGPIPE),
        "{:?}: {}",
        o.status,
        stderr(&o)
    );
    assert_eq!(stderr(&o), "");
}
