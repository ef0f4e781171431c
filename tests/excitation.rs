//! Ground motions: the shipped records, the file reader, sampled-record evaluation, scaling,
//! baseline correction and the analytic pulse families.

use rocklab::excitation::reader::parse;
use rocklab::excitation::{
    G, KinkPolicy, Library, Motion, Pulse, PulseShape, RecordMotion, Series, Source, StandIn,
};
use rocklab::scene::{Amplitude, Frequency, RecordScale};
use std::f64::consts::PI;
use std::path::PathBuf;
use std::sync::Arc;

fn records_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("records")
}

// ---------------------------------------------------------------- shipped records

#[test]
fn shipped_records_match_their_metadata() {
    for lib in [
        Library::open(Some(records_dir())).unwrap(),
        Library::open(None).unwrap(), // embedded only
    ] {
        assert_eq!(lib.index().len(), 6);
        for meta in lib.index() {
            let rec = lib.load(&meta.name, false).unwrap();
            let s = &rec.series;
            match (&rec.source, meta.stand_in) {
                (Source::StandIn(_), Some(si)) => {
                    // Fitted exactly to Table 1's PGV, and labelled as a stand-in.
                    assert!((s.pgv() - si.pgv).abs() < 1e-12, "{}", meta.name);
                    assert_eq!(Some(si.pgv), meta.pgv_table1);
                    assert!(meta.source.contains("stand-in"));
                }
                (Source::File(_) | Source::Embedded(_), _) => {
                    assert_eq!(Some(s.npts()), meta.npts, "{}", meta.name);
                    assert_eq!(Some(s.dt()), meta.dt, "{}", meta.name);
                    let pga_g = s.pga() / G;
                    assert!(
                        (pga_g / meta.pga_g.unwrap() - 1.0).abs() < 2e-4,
                        "{}",
                        meta.name
                    );
                    // Metadata PGV used g = 9.80665 and samples only; rocklab uses 9.81 and
                    // also the extrema inside segments: agreement to 0.2%.
                    let pgv = meta.pgv.unwrap();
                    assert!(
                        (s.pgv() / pgv - 1.0).abs() < 2e-3,
                        "{}: {}",
                        meta.name,
                        s.pgv()
                    );
                    if let Some(table) = meta.pgv_table1 {
                        assert!((s.pgv() / table - 1.0).abs() < 5e-3, "{}", meta.name);
                    }
                }
                (source, _) => panic!("{}: unexpected source {source:?}", meta.name),
            }
        }
    }
    // Records 3 and 5 are not available and stand in; 1, 2 and 4 are the real ones.
    let lib = Library::open(None).unwrap();
    for (name, stand_in) in [
        ("1", false),
        ("2", false),
        ("3", true),
        ("4", false),
        ("5", true),
    ] {
        let rec = lib.load(name, false).unwrap();
        assert_eq!(matches!(rec.source, Source::StandIn(_)), stand_in, "{name}");
    }
}

#[test]
fn embedded_and_directory_copies_are_identical_and_shared() {
    let dir = Library::open(Some(records_dir())).unwrap();
    let emb = Library::open(None).unwrap();
    for name in [
        "landers",
        "northridge",
        "superstition_hills",
        "northridge_228",
    ] {
        let a = dir.load(name, false).unwrap();
        let b = emb.load(name, false).unwrap();
        assert!(matches!(a.source, Source::File(_)));
        assert!(matches!(b.source, Source::Embedded(_)));
        assert_eq!(a.series, b.series);
        // Parsed once, then shared, whatever alias names it.
        assert!(Arc::ptr_eq(&a, &dir.load(name, false).unwrap()));
        let file = a.meta.as_ref().unwrap().file.clone();
        assert!(Arc::ptr_eq(&a, &dir.load(&file, false).unwrap()));
    }
}

#[test]
fn a_real_file_dropped_in_replaces_the_stand_in() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::copy(
        records_dir().join("index.ron"),
        tmp.path().join("index.ron"),
    )
    .unwrap();
    let lib = Library::open(Some(tmp.path().to_path_buf())).unwrap();
    let before = lib.load("imperial_valley", false).unwrap();
    assert!(matches!(before.source, Source::StandIn(_)));
    // A (fake) AT2 under the name the index expects.
    let file = &lib
        .index()
        .iter()
        .find(|m| m.name == "imperial_valley")
        .unwrap()
        .file;
    let at2 = "PEER NGA STRONG MOTION DATABASE RECORD\nImperial Valley-06, 10/15/1979, El Centro Differential Array, FN\nACCELERATION TIME HISTORY IN UNITS OF G\nNPTS=     4, DT=   .0050 SEC\n  .1000000E+00  -.2000000E+00   .3000000E+00   .0000000E+00\n";
    std::fs::write(tmp.path().join(file), at2).unwrap();
    let lib = Library::open(Some(tmp.path().to_path_buf())).unwrap();
    let after = lib.load("3", false).unwrap();
    assert!(matches!(after.source, Source::File(_)));
    assert_eq!(after.series.npts(), 4);
    // The data fingerprint (part of a study's cache key) changes with the data, and not with
    // the name used to reach it.
    assert_eq!(before.fingerprint.len(), 16);
    assert_ne!(before.fingerprint, after.fingerprint);
    assert_eq!(
        lib.load("imperial_valley", false).unwrap().fingerprint,
        after.fingerprint
    );
    assert!((after.series.pga() - 0.3 * G).abs() < 1e-12);
    // Any other data file dropped in is listed under its stem.
    std::fs::write(tmp.path().join("my_motion.txt"), "# dt: 0.02\n0\n0.1\n0\n").unwrap();
    assert!(lib.names().contains(&"my_motion".to_string()));
    assert_eq!(lib.load("my_motion", false).unwrap().series.npts(), 3);
}

#[test]
fn stand_in_has_the_table_period() {
    // MP velocity zeros are spaced Tp/2 (ν = 0: cos(2π t/Tp) inside the envelope).
    let si = StandIn {
        tp: 1.4,
        pgv: 0.67,
        gamma: 2.0,
        nu: 0.0,
        dt: 0.005,
    };
    let s = si.series();
    let (v, _) = s.velocity_extremes();
    // Interior crossings (the envelope's ends only graze zero: v ∝ (t − end)² there).
    let zeros: Vec<f64> = (1..v.len())
        .filter(|&k| v[k - 1] * v[k] < 0.0)
        .map(|k| s.dt() * ((k - 1) as f64 + v[k - 1] / (v[k - 1] - v[k])))
        .filter(|t| *t > 0.1 && *t < s.end() - 0.1)
        .collect();
    assert_eq!(zeros.len(), 4, "{zeros:?}");
    for w in zeros.windows(2) {
        assert!((w[1] - w[0] - 0.7).abs() < 2e-3, "{zeros:?}");
    }
}

#[test]
fn raw_at2_fixture_parses() {
    let text = std::fs::read_to_string(records_dir().join("NGA_no_1063_RRS228.AT2")).unwrap();
    let s = parse(&text, "NGA_no_1063_RRS228.AT2", None).unwrap();
    assert_eq!((s.npts(), s.dt()), (1991, 0.01));
    assert_eq!(s.samples()[0], -0.731461e-2 * G);
    assert_eq!(s.samples()[1990], 0.115999e-2 * G);
    // PROVENANCE.md: PGA 0.8252 g, PGV 1.601 m/s (with g = 9.80665).
    assert!((s.pga() / G - 0.8252).abs() < 1e-4);
    assert!((s.pgv() / 1.601 - 1.0).abs() < 2e-3);
}

// ---------------------------------------------------------------- reader

fn at2_west2(s: &Series) -> String {
    let mut out = String::from(
        "PEER NGA STRONG MOTION DATABASE RECORD\nTest, 1/1/2000, Station, 000\nACCELERATION TIME HISTORY IN UNITS OF G\n",
    );
    out.push_str(&format!("NPTS= {:>6}, DT= {:.4} SEC\n", s.npts(), s.dt()));
    for chunk in s.samples().chunks(5) {
        for a in chunk {
            out.push_str(&format!(" {:e}", a / G));
        }
        out.push('\n');
    }
    out
}

#[test]
fn parsing_round_trips_in_every_format() {
    let values: Vec<f64> = (0..23)
        .map(|k| ((k * 7 % 11) as f64 - 5.0) * 0.0123 * G)
        .collect();
    let s = Series::new(0.0, 0.01, values);
    let back = parse(&at2_west2(&s), "west2.AT2", None).unwrap();
    assert_eq!(back.npts(), s.npts());
    assert_eq!(back.dt(), s.dt());
    for (a, b) in s.samples().iter().zip(back.samples()) {
        assert!((a - b).abs() <= 1e-15 * G, "{a} {b}");
    }
    // NGA-West1 header style, values run together, zeros padding the last line past NPTS
    // (data past NPTS are refused: tests/strict_inputs.rs).
    let west1 = "NORTHRIDGE, 1/17/94 12:31, RINALDI RECEIVING STA, 228\nsecond line\nACCELERATION TIME HISTORY IN UNITS OF G\n5    0.0200    NPTS, DT\n1.5E-01-2.5E-01 3.0E-01\n-4.0E-01  5.0D-01  0.0E+00\n";
    let w1 = parse(west1, "west1.AT2", None).unwrap();
    assert!(parse(&west1.replace("0.0E+00", "9.9E+00"), "west1.AT2", None).is_err());
    assert_eq!(w1.dt(), 0.02);
    let want = [0.15, -0.25, 0.3, -0.4, 0.5];
    assert_eq!(w1.npts(), 5);
    for (a, w) in w1.samples().iter().zip(want) {
        assert!((a - w * G).abs() < 1e-14);
    }
    // Two columns (t, a) in cm/s², starting at t0 = 0.5.
    let two = "# units: cm/s2\n0.50 10\n0.52 -20\n0.54 30\n";
    let t2 = parse(two, "two.csv", None).unwrap();
    assert_eq!(t2.t0(), 0.5);
    assert!((t2.dt() - 0.02).abs() < 1e-15);
    assert!((t2.accel(0.52) + 0.2).abs() < 1e-12);
    assert_eq!(t2.accel(0.49), 0.0);
    // One column with the dt given by the caller (Windows line ends and a BOM are fine).
    let one = parse("\u{feff}0.1\r\n-0.2\r\n", "one.txt", Some(0.05)).unwrap();
    assert_eq!((one.npts(), one.dt()), (2, 0.05));
    assert!((one.samples()[1] + 0.2 * G).abs() < 1e-15);
}

#[test]
fn malformed_files_give_clear_errors() {
    let cases = [
        ("", "empty.AT2:", "the file is empty"),
        (
            "PEER\nEvent\nACCELERATION TIME HISTORY IN UNITS OF G\nNPTS= abc, DT= .01 SEC\n0.1\n",
            "bad.AT2:4:",
            "bad AT2 header",
        ),
        (
            "PEER\nEvent\nACCELERATION TIME HISTORY IN UNITS OF G\nNPTS=  6, DT= .01 SEC\n0.1 0.2 0.3\n0.4\n",
            "short.AT2:4:",
            "NPTS = 6 but the data hold only 4 values (last data on line 6)",
        ),
        (
            "PEER\nEvent\nACCELERATION TIME HISTORY IN UNITS OF G\nNPTS=  3, DT= .01 SEC\n0.1 0.2\n0.3x\n",
            "nan.AT2:6:",
            "'0.3x' is not a number",
        ),
        (
            "PEER\nEvent\nUNITS OF G\n100 0.0 NPTS, DT\n",
            "dt.AT2:4:",
            "DT = 0 must be > 0",
        ),
        ("0.1\n0.2\n", "nodt.txt:", "needs a time step > 0"),
        (
            "0 0.1\n0.01 0.2\n0.05 0.3\n",
            "gap.txt:3:",
            "breaks the uniform step",
        ),
        ("1 2 3\n", "three.txt:1:", "expected one column"),
    ];
    for (text, origin_line, message) in cases {
        let origin = origin_line.split(':').next().unwrap();
        let e = parse(text, origin, None).unwrap_err().to_string();
        assert!(e.starts_with(origin_line), "{e}");
        assert!(e.contains(message), "{e}");
    }
}

// ---------------------------------------------------------------- sampled motion

fn motion(samples: &[f64], dt: f64, factor: f64) -> RecordMotion {
    RecordMotion {
        series: Arc::new(Series::new(0.0, dt, samples.to_vec())),
        factor,
        kinks: KinkPolicy::StopAtSamples,
    }
}

#[test]
fn record_is_exact_at_samples_and_linear_between() {
    let m = motion(&[0.0, 1.0, -2.0, 0.5], 0.1, 2.0);
    for (k, a) in [0.0, 1.0, -2.0, 0.5].iter().enumerate() {
        assert!((m.accel(k as f64 * 0.1) - 2.0 * a).abs() < 1e-12);
    }
    assert!((m.accel(0.125) - 2.0 * (1.0 - 0.75)).abs() < 1e-12);
    assert_eq!(m.accel(-0.01), 0.0);
    assert_eq!(m.accel(0.31), 0.0);
    // Breakpoints are the samples, strictly increasing, then the end.
    let mut t = 0.0;
    let mut stops = vec![];
    while let Some(b) = m.next_breakpoint(t) {
        assert!(b > t);
        stops.push(b);
        t = b;
    }
    assert_eq!(stops.len(), 3);
    assert!((stops[2] - 0.3).abs() < 1e-15);
    // Ends on a nonzero sample: a jump there only.
    assert!(m.jumps_at(stops[2]) && !m.jumps_at(stops[1]));
    let over = RecordMotion {
        kinks: KinkPolicy::StepOver,
        ..m.clone()
    };
    assert_eq!(over.next_breakpoint(0.0), Some(m.end()));
}

#[test]
fn first_exceedance_and_peak_are_exact() {
    let m = motion(&[0.0, 1.0, -2.0, 0.5], 0.1, 2.0);
    // |2 a| reaches 1 on the first segment at t = 0.05.
    assert!((m.first_exceedance(0.0, 1.0).unwrap() - 0.05).abs() < 1e-15);
    // Level 3 from t = 0.1 (a = 2): crossed downward to −3 on [0.1, 0.2]: 2 − 6u = −3.
    assert!((m.first_exceedance(0.1, 3.0).unwrap() - (0.1 + 0.1 * 5.0 / 6.0)).abs() < 1e-15);
    assert_eq!(m.first_exceedance(0.0, 4.0), None);
    // The returned time is where the excess is strict (callers test |a_g| > level there).
    for (t0, level) in [(0.0, 1.0), (0.1, 3.0), (0.0, 0.3), (0.21, 1.7)] {
        let t = m.first_exceedance(t0, level).unwrap();
        assert!(m.accel(t).abs() > level && t >= t0, "{t0} {level} {t}");
    }
    assert_eq!(m.first_exceedance(0.25, 1.5), None);
    assert!((m.peak_abs(0.0, 0.3) - 4.0).abs() < 1e-15);
    assert!((m.peak_abs(0.0, 0.15) - 2.0).abs() < 1e-15);
    // Inside one segment: a(0.12) = 0.4, a(0.14) = −0.2.
    assert!((m.peak_abs(0.12, 0.14) - 2.0 * 0.4).abs() < 1e-12);
    // Through the Motion enum too.
    let motion = Motion::record(m);
    assert!((motion.first_exceedance(0.0, 1.0).unwrap() - 0.05).abs() < 1e-15);
    assert!((motion.peak_abs(0.0, 1.0) - 4.0).abs() < 1e-15);
}

#[test]
fn pgv_is_the_exact_integral_of_the_linear_history() {
    // a = 1, −1 over one step: v peaks mid-segment at dt/4... check against closed form.
    let s = Series::new(0.0, 0.2, vec![1.0, -1.0]);
    assert!((s.pgv() - 0.05).abs() < 1e-15);
    // A sampled sine: PGV → 2A/ω as dt → 0.
    let (a, w) = (3.0, 2.0 * PI);
    let n = 2001;
    let dt = 1.0 / (n - 1) as f64;
    let s = Series::new(
        0.0,
        dt,
        (0..n).map(|k| a * (w * k as f64 * dt).sin()).collect(),
    );
    assert!((s.pgv() / (2.0 * a / w) - 1.0).abs() < 1e-6);
}

#[test]
fn scaling_hits_its_target() {
    let s = Arc::new(Series::new(0.0, 0.01, vec![0.0, 2.0, -3.0, 1.0, 0.0]));
    for scale in [
        RecordScale::Factor(-1.5),
        RecordScale::Pga(0.5),
        RecordScale::Pgv(0.2),
        RecordScale::PgaStar(1.5),
        RecordScale::PgvStar(0.7),
    ] {
        let factor = scale.factor(s.pga(), s.pgv(), 0.2, 2.0);
        let m = RecordMotion {
            series: s.clone(),
            factor,
            kinks: KinkPolicy::default(),
        };
        let scaled = Series::new(
            0.0,
            0.01,
            (0..5).map(|k| m.accel(k as f64 * 0.01)).collect(),
        );
        match scale {
            RecordScale::Factor(k) => assert!((m.accel(0.02) - 3.0 * 1.5).abs() < 1e-12 && k < 0.0),
            RecordScale::Pga(g) => assert!((scaled.pga() - g * G).abs() < 1e-12),
            RecordScale::Pgv(v) => assert!((scaled.pgv() - v).abs() < 1e-12),
            // α = 0.2, p = 2 rad/s.
            RecordScale::PgaStar(x) => {
                assert!((scaled.pga() / (G * 0.2_f64.tan()) - x).abs() < 1e-12)
            }
            RecordScale::PgvStar(x) => {
                assert!((scaled.pgv() * 2.0 / (G * 0.2_f64.tan()) - x).abs() < 1e-12)
            }
        }
    }
}

#[test]
fn baseline_correction_removes_drift() {
    // A constant offset plus a linear trend integrates to an exact quadratic velocity, which
    // the correction removes entirely.
    let s = Series::new(
        0.0,
        0.01,
        (0..500).map(|k| 0.3 - 0.02 * k as f64 * 0.01).collect(),
    );
    let c = s.baseline_corrected();
    assert!(c.pga() < 1e-10, "{}", c.pga());
    // On a real record it is opt-in; the corrected velocity satisfies the normal equations
    // (orthogonal to τ and τ²), so its mean square is the least possible.
    let lib = Library::open(None).unwrap();
    let raw = lib.load("landers", false).unwrap();
    let corr = lib.load("landers", true).unwrap();
    assert_ne!(raw.series.samples(), corr.series.samples());
    let (v_raw, _) = raw.series.velocity_extremes();
    let (v, _) = corr.series.velocity_extremes();
    let dt = corr.series.dt();
    let dot = |f: &dyn Fn(f64) -> f64, v: &[f64]| -> f64 {
        v.iter()
            .enumerate()
            .map(|(k, x)| x * f(k as f64 * dt))
            .sum()
    };
    let norm = dot(
        &|t| t * t,
        &v_raw.iter().map(|x| x.abs()).collect::<Vec<_>>(),
    );
    assert!(dot(&|t| t, &v).abs() < 1e-9 * norm);
    assert!(dot(&|t| t * t, &v).abs() < 1e-9 * norm * 48.0);
    assert!(
        dot(&|_| 1.0, &v.iter().map(|x| x * x).collect::<Vec<_>>())
            < dot(&|_| 1.0, &v_raw.iter().map(|x| x * x).collect::<Vec<_>>())
    );
}

// ---------------------------------------------------------------- pulses

/// Simpson integrals of a over [0, end]: (∫a dt, the velocity history at n + 1 points).
fn integrate(p: &Pulse, n: usize) -> (f64, Vec<(f64, f64)>) {
    let h = p.end() / n as f64;
    let mut v = vec![(0.0, 0.0)];
    let mut total = 0.0;
    for k in 0..n {
        let t = k as f64 * h;
        total += h / 6.0 * (p.accel(t) + 4.0 * p.accel(t + 0.5 * h) + p.accel(t + h));
        v.push((t + h, total));
    }
    (total, v)
}

fn peak(p: &Pulse) -> f64 {
    let n = 200_000;
    (0..=n)
        .map(|k| p.accel(p.end() * k as f64 / n as f64).abs())
        .fold(0.0, f64::max)
}

fn families() -> Vec<PulseShape> {
    vec![
        PulseShape::Sine,
        PulseShape::Cosine,
        PulseShape::Ricker,
        PulseShape::AntisymmetricRicker,
        PulseShape::MavroeidisPapageorgiou {
            gamma: 2.5,
            nu: 0.7,
        },
        PulseShape::MavroeidisPapageorgiou {
            gamma: 1.5,
            nu: 0.0,
        },
    ]
}

/// `Pulse::accel_bound` bounds |a_g| on any interval (the acceleration peak searches skip
/// steps on it), and is tight to first order: on short intervals it is the larger end value
/// plus at most the slope times the length, and the slope is within 3 % of the steepest.
#[test]
fn pulse_bound_holds_on_every_interval_and_is_tight_on_short_ones() {
    let (a, w) = (-2.3, 5.0);
    for shape in families() {
        let p = Pulse::new(shape, a, w);
        let n: usize = 20_000;
        let dt = p.end() / n as f64;
        let steepest = (0..n)
            .map(|k| (p.accel((k + 1) as f64 * dt) - p.accel(k as f64 * dt)).abs() / dt)
            .fold(0.0, f64::max);
        for width in [1, 7, 50, 400, n] {
            for k in (0..=n - width).step_by(97) {
                let (t0, t1) = (k as f64 * dt, (k + width) as f64 * dt);
                let bound = p.accel_bound(t0, t1);
                let fine = (0..=64)
                    .map(|j| p.accel(t0 + (t1 - t0) * j as f64 / 64.0).abs())
                    .fold(0.0, f64::max);
                assert!(bound >= fine, "{shape:?} on [{t0}, {t1}]: {bound} < {fine}");
                let ends = p.accel(t0).abs().max(p.accel(t1).abs());
                assert!(
                    bound <= ends + 1.03 * steepest * (t1 - t0) / 2.0 + 1e-12,
                    "{shape:?}"
                );
            }
        }
        assert!(
            p.accel_bound(-2.0, -1.0) == 0.0 && p.accel_bound(p.end() + 1.0, p.end() + 2.0) == 0.0
        );
    }
    // Across the cosine's jumps at 0 and at its end (where the phase may round past 2π and
    // a_g read 0), for frequencies where it does and does not.
    for w in [3.1, 5.0, 7.3] {
        let p = Pulse::new(PulseShape::Cosine, a, w);
        let (end, h) = (p.end(), 1e-3 / w);
        for (t0, t1) in [(-h, h), (0.0, h), (end - h, end), (end - h, end + h)] {
            assert!(p.accel_bound(t0, t1) >= a.abs(), "ω {w} on [{t0}, {t1}]");
        }
    }
}

#[test]
fn every_family_has_zero_mean_and_the_requested_peak() {
    let (a, w) = (-2.3, 5.0);
    for shape in families() {
        let p = Pulse::new(shape, a, w);
        let (mean, _) = integrate(&p, 20_000);
        assert!(mean.abs() < 1e-9 * a.abs() * p.end(), "{shape:?}: {mean}");
        assert!(
            (peak(&p) / a.abs() - 1.0).abs() < 1e-6,
            "{shape:?}: {}",
            peak(&p)
        );
    }
}

/// Times where the velocity changes sign or has a local extremum.
fn velocity_features(p: &Pulse) -> (Vec<f64>, Vec<f64>) {
    let (_, v) = integrate(p, 40_000);
    // Ignore the flat tails, where roundoff alone changes signs.
    let vmax = v.iter().fold(0.0_f64, |m, x| m.max(x.1.abs()));
    let significant = |k: usize| (v[k + 1].1 - v[k].1).abs() > 1e-7 * vmax;
    let zeros = (1..v.len() - 1)
        .filter(|&k| v[k].1 * v[k + 1].1 < 0.0 && significant(k))
        .map(|k| v[k].0 + (v[k + 1].0 - v[k].0) * v[k].1 / (v[k].1 - v[k + 1].1))
        .collect();
    let extrema = (1..v.len() - 1)
        .filter(|&k| {
            (v[k].1 - v[k - 1].1) * (v[k + 1].1 - v[k].1) < 0.0 && v[k].1.abs() > 1e-3 * vmax
        })
        .map(|k| v[k].0)
        .collect();
    (zeros, extrema)
}

#[test]
fn velocity_pulses_have_the_right_period() {
    let w = 4.0;
    let tp = 2.0 * PI / w;
    let close = |a: f64, b: f64| (a - b).abs() < 1e-3 * tp;
    // Sine: a one-sided velocity pulse 2A/ω high, peaking at Tp/2, back to zero at Tp.
    let (_, v) = integrate(&Pulse::new(PulseShape::Sine, 1.0, w), 40_000);
    let top = v
        .iter()
        .fold((0.0, 0.0), |m, x| if x.1 > m.1 { *x } else { m });
    assert!(close(top.0, tp / 2.0) && (top.1 - 2.0 / w).abs() < 1e-9);
    assert!(v.last().unwrap().1.abs() < 1e-12);
    // Cosine: v = (A/ω) sin ωt, one full cycle: zero at Tp/2.
    let (zeros, _) = velocity_features(&Pulse::new(PulseShape::Cosine, 1.0, w));
    assert!(zeros.len() == 1 && close(zeros[0], tp / 2.0), "{zeros:?}");
    // Ricker (σ = √2/ω): velocity is a Gaussian derivative, extrema 2σ apart.
    let (_, ext) = velocity_features(&Pulse::new(PulseShape::Ricker, 1.0, w));
    assert_eq!(ext.len(), 2);
    assert!(close(ext[1] - ext[0], 2.0 * 2f64.sqrt() / w));
    // Antisymmetric Ricker (σ = √3/ω): velocity ∝ (x² − 1) e^{−x²/2}, zeros 2σ apart.
    let (zeros, _) = velocity_features(&Pulse::new(PulseShape::AntisymmetricRicker, 1.0, w));
    assert_eq!(zeros.len(), 2);
    assert!(close(zeros[1] - zeros[0], 2.0 * 3f64.sqrt() / w));
    // MP: velocity zeros Tp/2 apart whatever ν.
    let mp = PulseShape::MavroeidisPapageorgiou {
        gamma: 3.0,
        nu: 0.4,
    };
    let (zeros, _) = velocity_features(&Pulse::new(mp, 1.0, w));
    assert!(zeros.len() >= 4, "{zeros:?}");
    for z in zeros.windows(2) {
        assert!(close(z[1] - z[0], tp / 2.0), "{zeros:?}");
    }
}

#[test]
fn ricker_spectra_peak_at_the_requested_frequency() {
    let w = 3.0;
    for shape in [PulseShape::Ricker, PulseShape::AntisymmetricRicker] {
        let p = Pulse::new(shape, 1.0, w);
        let n = 20_000;
        let h = p.end() / n as f64;
        let amp = |om: f64| {
            let (mut re, mut im) = (0.0, 0.0);
            for k in 0..=n {
                let t = k as f64 * h;
                re += p.accel(t) * (om * t).cos() * h;
                im += p.accel(t) * (om * t).sin() * h;
            }
            re.hypot(im)
        };
        assert!(
            amp(w) > amp(0.98 * w) && amp(w) > amp(1.02 * w),
            "{shape:?}"
        );
    }
}

#[test]
fn mp_by_period_and_pgv() {
    for (gamma, nu) in [(2.0, 0.0), (2.5, 1.0), (1.2, -0.5)] {
        let p = Pulse::mavroeidis_papageorgiou(1.4, 0.67, gamma, nu);
        let (end_v, v) = integrate(&p, 40_000);
        let pgv = v.iter().fold(0.0_f64, |m, x| m.max(x.1.abs()));
        assert!((pgv / 0.67 - 1.0).abs() < 1e-6, "γ {gamma} ν {nu}: {pgv}");
        assert!(end_v.abs() < 1e-9);
        assert!((p.end() - gamma * 1.4).abs() < 1e-12);
    }
}

#[test]
fn paper_scalings_apply_to_every_family() {
    // A/(g tan α) and ωg/p mean peak acceleration and ω for every family.
    let (alpha, p) = (0.2_f64, 2.0);
    let a = Amplitude::TanAlphaRatio(1.5).absolute(alpha);
    let w = Frequency::Ratio(4.0).absolute(p);
    for shape in families() {
        let pulse = Pulse::new(shape, a, w);
        assert!((peak(&pulse) / (1.5 * G * alpha.tan()) - 1.0).abs() < 1e-6);
        assert_eq!(pulse.omega, 8.0);
    }
}

#[test]
fn a_broken_index_or_stand_in_is_a_clear_error() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(
        tmp.path().join("index.ron"),
        "[\n  (name: \"x\",\n  oops\n]\n",
    )
    .unwrap();
    let e = Library::open(Some(tmp.path().to_path_buf()))
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("index.ron:3:"), "{e}");
    let index = std::fs::read_to_string(records_dir().join("index.ron"))
        .unwrap()
        .replace(
            "gamma: 2.0, nu: 0.0, dt: 0.005",
            "gamma: 0.5, nu: 0.0, dt: 0.005",
        );
    std::fs::write(tmp.path().join("index.ron"), index).unwrap();
    let lib = Library::open(Some(tmp.path().to_path_buf())).unwrap();
    let e = lib.load("palm_springs", false).unwrap_err().to_string();
    assert!(
        e.contains("stand-in needs") && e.contains("palm_springs"),
        "{e}"
    );
    // A dt given for a file that states its own, differently.
    let e = parse("# dt: 0.01\n0.1\n", "x.txt", Some(0.02)).unwrap_err();
    assert!(
        e.to_string()
            .contains("differs from its '# dt: 0.01' header")
    );
}
