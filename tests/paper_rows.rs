//! Every row of `rocklab paper` recomputed here, independently of src/paper's check code: the
//! scenes are built from the presets and run through the library's public `sim` API (histories
//! resampled as `simulate --history` writes them), the closed forms are written out (Eq. 16,
//! Housner's r), and each fair check's definition is restated minimally below (the ratio
//! statistics, the immaterial share, the per-third trend and offset, envelope times, energy
//! flowing back). For each row the test asserts
//! - every number the row reports (all but the sensitivity reruns' verdict codes) equals the
//!   recomputation to 1e-9 relative (the same deterministic scenes: only summation order may
//!   differ), and no number of the row goes unchecked;
//! - the row's verdict is the one the restated thresholds give for those numbers.
//!
//! The recomputations live in paper_rows_rigid.rs, paper_rows_flexible.rs and
//! paper_rows_records.rs, one function per row, in the paper's order.

use rayon::prelude::*;
use rocklab::paper::{self, Agreement};
use rocklab::scene::{Excitation, Frequency, Scene};
use rocklab::sim::{self, History, HistoryColumn, SceneResult};
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

/// One value per axis point; None where the structure overturned.
pub type S = Vec<Option<f64>>;

/// What a row must report: its numbers by name and its verdict.
pub struct Expect {
    pub values: Vec<(String, f64)>,
    pub agreement: Agreement,
}

impl Expect {
    pub fn new(agreement: Agreement) -> Self {
        Expect {
            values: Vec::new(),
            agreement,
        }
    }

    pub fn with(mut self, name: impl Into<String>, x: f64) -> Self {
        self.values.push((name.into(), x));
        self
    }

    pub fn value(&self, name: &str) -> f64 {
        self.values
            .iter()
            .find(|(k, _)| k == name)
            .map_or(f64::NAN, |(_, x)| *x)
    }
}

pub fn rank(a: Agreement) -> usize {
    match a {
        Agreement::Agrees => 0,
        Agreement::Roughly => 1,
        Agreement::Disagrees => 2,
        Agreement::Untestable => 3,
    }
}

/// A claim about two responses holds as well as its weaker half; names gain the prefixes.
pub fn both(a: Expect, pa: &str, b: Expect, pb: &str) -> Expect {
    let agreement = if rank(a.agreement) >= rank(b.agreement) {
        a.agreement
    } else {
        b.agreement
    };
    let mut values: Vec<(String, f64)> = a
        .values
        .into_iter()
        .map(|(k, x)| (format!("{pa}: {k}"), x))
        .collect();
    values.extend(b.values.into_iter().map(|(k, x)| (format!("{pb}: {k}"), x)));
    Expect { values, agreement }
}

/// Agrees at most `agree`, roughly at most `roughly`.
pub fn ladder(distance: f64, agree: f64, roughly: f64) -> Agreement {
    if distance <= agree {
        Agreement::Agrees
    } else if distance <= roughly {
        Agreement::Roughly
    } else {
        Agreement::Disagrees
    }
}

fn pick(agree: bool, roughly: bool) -> Agreement {
    ladder(
        if agree {
            0.0
        } else if roughly {
            1.0
        } else {
            2.0
        },
        0.0,
        1.0,
    )
}

/// The claim words of the fair check's comparisons and their thresholds on (mean ratio, share
/// of points above 1, share below 1), restated.
#[derive(Clone, Copy)]
pub enum Claim {
    Larger,
    MarkedlyLarger,
    Lower,
    LowerEverywhere,
    MuchLower,
    SlightlyLower,
    Halved,
    SlightlyHigher,
    HigherSomewhere,
    LowerSomewhere,
}

/// The dead band: a ratio within ±1 % of 1 is no difference.
pub const BAND: f64 = 0.01;

impl Claim {
    fn judge(self, m: f64, above: f64, below: f64) -> Agreement {
        let (hi, lo) = (1.0 + BAND, 1.0 - BAND);
        match self {
            Claim::Larger => pick(m > hi && above >= 0.5, m > hi || above >= 0.5),
            Claim::MarkedlyLarger => pick(m >= 1.1 && above >= 0.8, m > hi),
            Claim::Lower => pick(m < lo && below >= 0.5, m < lo || below >= 0.5),
            Claim::LowerEverywhere => pick(below == 1.0, below >= 0.8),
            Claim::MuchLower => pick(m <= 0.8, m < 0.95),
            Claim::SlightlyLower => pick(
                (0.8..lo).contains(&m),
                (0.7..0.8).contains(&m) || (lo..1.03).contains(&m),
            ),
            Claim::Halved => pick(m < 0.5, m < 0.6),
            Claim::SlightlyHigher => pick(
                m > hi && m <= 1.2,
                (m > 1.2 && m <= 1.3) || (0.97..=hi).contains(&m),
            ),
            Claim::HigherSomewhere => pick(above > 0.0, false),
            Claim::LowerSomewhere => pick(below > 0.0, false),
        }
    }
}

/// variant / reference where both exist and the reference is positive.
pub fn ratios(reference: &S, variant: &S) -> Vec<f64> {
    let mut q = Vec::new();
    for (a, b) in reference.iter().zip(variant) {
        if let (Some(a), Some(b)) = (a, b)
            && *a > 0.0
        {
            q.push(b / a);
        }
    }
    q
}

pub fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// The pointwise comparison: mean ratio, shares above and below, points.
pub fn compare(claim: Claim, reference: &S, variant: &S) -> Expect {
    let q = ratios(reference, variant);
    let n = q.len() as f64;
    let m = mean(&q);
    let above = q.iter().filter(|r| **r > 1.0 + BAND).count() as f64 / n.max(1.0);
    let below = q.iter().filter(|r| **r < 1.0 - BAND).count() as f64 / n.max(1.0);
    let agreement = if q.is_empty() {
        Agreement::Untestable
    } else {
        claim.judge(m, above, below)
    };
    Expect::new(agreement)
        .with("mean ratio", m)
        .with("share above", above)
        .with("share below", below)
        .with("points", n)
}

pub fn one(x: f64) -> S {
    vec![Some(x)]
}

fn peak(s: &S) -> f64 {
    s.iter().flatten().fold(f64::NEG_INFINITY, |m, x| m.max(*x))
}

/// "Immaterial": the largest |difference| over the axis as a share of the reference's peak,
/// ≤ 10 % with no point where only one overturns (≤ 20 %, or above 10 % at one point only,
/// roughly). On three points or more the largest but one is reported too.
pub fn immaterial(reference: &S, variants: &[(&str, &S)]) -> Expect {
    let scale = peak(reference);
    let mut e = Expect::new(Agreement::Agrees).with("reference peak", scale);
    let (mut worst, mut second, mut flips) = (0.0f64, 0.0f64, 0usize);
    for (name, v) in variants {
        let (mut top, mut next, mut here) = (0.0f64, 0.0f64, 0usize);
        for (a, b) in reference.iter().zip(v.iter()) {
            match (a, b) {
                (Some(a), Some(b)) => {
                    let d = (a - b).abs() / scale;
                    if d > top {
                        next = top;
                        top = d;
                    } else if d > next {
                        next = d;
                    }
                }
                (None, None) => {}
                _ => here += 1,
            }
        }
        e = e
            .with(format!("{name}: largest difference / reference peak"), top)
            .with(format!("{name}: overturning flips"), here as f64);
        if reference.len() >= 3 {
            e = e.with(
                format!("{name}: largest difference but one / reference peak"),
                next,
            );
            second = second.max(next);
        } else {
            second = second.max(top);
        }
        worst = worst.max(top);
        flips += here;
    }
    let one_point = worst > 0.10 && second <= 0.10;
    e.agreement = if worst <= 0.10 && flips == 0 {
        Agreement::Agrees
    } else if worst <= 0.20 || (one_point && flips == 0) {
        Agreement::Roughly
    } else {
        Agreement::Disagrees
    };
    e
}

/// "Differences reduced": the mean |difference| per third over the reference's peak falls
/// (rises ≤ 0.01 allowed) and ends more than 0.01 below its start.
pub fn gap_shrinks(xs: &[f64], reference: &S, variant: &S) -> Expect {
    let scale = peak(reference);
    let mut d = Vec::new();
    let mut e = Expect::new(Agreement::Agrees);
    for (k, r) in thirds(xs.len()).iter().enumerate() {
        let gaps: Vec<f64> = r
            .clone()
            .filter_map(|i| Some((reference[i]? - variant[i]?).abs() / scale))
            .collect();
        d.push(mean(&gaps));
        e = e.with(
            format!(
                "mean |difference| / reference peak, third {} (x {:.2}–{:.2})",
                k + 1,
                xs[r.start],
                xs[r.end - 1]
            ),
            d[k],
        );
    }
    let lower = d[2] < d[0] - BAND;
    e.agreement = pick(lower && d[1] <= d[0] + BAND && d[2] <= d[1] + BAND, lower);
    e
}

/// A share at most `limit` (twice roughly).
pub fn small(what: &str, share: f64, limit: f64) -> Expect {
    Expect::new(ladder(share, limit, 2.0 * limit)).with(what, share)
}

/// A share at least `limit` (half roughly).
pub fn at_least(what: &str, share: f64, limit: f64) -> Expect {
    Expect::new(pick(share >= limit, share >= 0.5 * limit)).with(what, share)
}

/// The three thirds of n points.
pub fn thirds(n: usize) -> [std::ops::Range<usize>; 3] {
    [0..n / 3, n / 3..2 * n / 3, 2 * n / 3..n]
}

/// The last time |y| is at least `f` of its peak.
pub fn envelope_time(t: &[f64], y: &[f64], f: f64) -> f64 {
    let top = y.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let mut last = f64::NAN;
    for (t, v) in t.iter().zip(y) {
        if v.abs() >= f * top {
            last = *t;
        }
    }
    last
}

/// "Faster decrease": the claimed-faster envelope reaches 50/20/10/5 % of its own peak first,
/// at all four (at two roughly).
pub fn faster(fast: &(Vec<f64>, Vec<f64>), slow: &(Vec<f64>, Vec<f64>)) -> Expect {
    let mut e = Expect::new(Agreement::Agrees);
    let mut earlier = 0;
    for (f, pct) in [(0.5, 50), (0.2, 20), (0.1, 10), (0.05, 5)] {
        let a = envelope_time(&fast.0, &fast.1, f);
        let b = envelope_time(&slow.0, &slow.1, f);
        earlier += usize::from(a < b);
        e = e
            .with(format!("claimed faster: time to {pct} % (s)"), a)
            .with(format!("other: time to {pct} % (s)"), b);
    }
    e.agreement = pick(earlier == 4, earlier >= 2);
    e
}

/// "Part of the energy back" (≥ 10 %, 2 % roughly) or "fully prevent" (≤ 1 %, 5 % roughly).
pub fn energy_back(returned: f64, claimed_back: bool) -> Expect {
    let agreement = if claimed_back {
        pick(returned >= 0.10, returned >= 0.02)
    } else {
        ladder(returned, 0.01, 0.05)
    };
    Expect::new(agreement).with("returned / taken", returned)
}

// Readings of a history, restated.

/// ∫|f| dt over the rows in [from, to), trapezoids.
pub fn impulse(t: &[f64], f: &[f64], from: f64, to: f64) -> f64 {
    let mut sum = 0.0;
    for i in 1..t.len() {
        if t[i - 1] >= from && t[i] < to {
            sum += (t[i] - t[i - 1]) * (f[i].abs() + f[i - 1].abs()) / 2.0;
        }
    }
    sum
}

/// A force a millionth of its largest is no contact.
pub fn floor(f: &[f64]) -> f64 {
    f.iter().map(|x| x.abs()).fold(0.0, f64::max) * 1e-6
}

/// The share of [from, to) with |f| above the floor at both ends of a row interval.
pub fn engaged(t: &[f64], f: &[f64], from: f64, to: f64) -> f64 {
    let fl = floor(f);
    let (mut on, mut all) = (0.0, 0.0);
    for i in 1..t.len() {
        if t[i - 1] >= from && t[i] < to {
            all += t[i] - t[i - 1];
            if f[i - 1].abs() > fl && f[i].abs() > fl {
                on += t[i] - t[i - 1];
            }
        }
    }
    if all > 0.0 { on / all } else { 0.0 }
}

/// Contacts: runs of two rows or more with |f| above the floor, as (first, last) rows.
pub fn contacts(f: &[f64]) -> Vec<(usize, usize)> {
    let fl = floor(f);
    let mut out = Vec::new();
    let mut i = 0;
    while i < f.len() {
        if f[i].abs() > fl {
            let mut j = i;
            while j + 1 < f.len() && f[j + 1].abs() > fl {
                j += 1;
            }
            if j > i {
                out.push((i, j));
            }
            i = j + 1;
        } else {
            i += 1;
        }
    }
    out
}

/// Sign changes of y, interpolated.
pub fn crossings(t: &[f64], y: &[f64]) -> Vec<f64> {
    let mut out = Vec::new();
    for i in 1..t.len() {
        if y[i - 1] * y[i] < 0.0 {
            let w = y[i - 1] / (y[i - 1] - y[i]);
            out.push(t[i - 1] + w * (t[i] - t[i - 1]));
        }
    }
    out
}

/// The share of e's falls that happen between two rows of one time.
pub fn sudden(t: &[f64], e: &[f64]) -> f64 {
    let (mut jump, mut total) = (0.0, 0.0);
    for i in 1..t.len() {
        let d = e[i - 1] - e[i];
        if d > 0.0 {
            total += d;
            if t[i] - t[i - 1] <= 1e-12 {
                jump += d;
            }
        }
    }
    if total > 0.0 { jump / total } else { 0.0 }
}

/// The row where |f| is largest in rows a..=b (the first of equals).
pub fn peak_row(f: &[f64], a: usize, b: usize) -> usize {
    let mut k = a;
    for i in a..=b {
        if f[i].abs() > f[k].abs() {
            k = i;
        }
    }
    k
}

/// Device dissipation over the input at the end (None if overturned).
pub fn device_share(r: &SceneResult) -> Option<f64> {
    let e = &r.energy;
    if r.overturned {
        None
    } else {
        Some((e.device_damping + e.friction + e.disengagement + e.reset) / e.input)
    }
}

// Scenes, run once per test process.

type Cache<T> = OnceLock<Mutex<HashMap<String, Arc<T>>>>;

fn library() -> &'static rocklab::excitation::Library {
    rocklab::excitation::library::global().expect("the record library")
}

/// Run scenes in parallel (each at most once per process).
pub fn results(scenes: &[Scene]) -> Vec<Arc<SceneResult>> {
    static CACHE: Cache<SceneResult> = OnceLock::new();
    let map = CACHE.get_or_init(Default::default);
    scenes
        .par_iter()
        .map(|s| {
            let k = format!("{s:?}");
            if let Some(r) = map.lock().unwrap().get(&k) {
                return Arc::clone(r);
            }
            let r = Arc::new(sim::run(s, library()).expect("a paper scene runs"));
            map.lock().unwrap().insert(k, Arc::clone(&r));
            r
        })
        .collect()
}

pub fn result(scene: &Scene) -> Arc<SceneResult> {
    results(std::slice::from_ref(scene)).remove(0)
}

/// The scene's history as `rocklab simulate --history` writes it.
pub fn history(scene: &Scene) -> Arc<History> {
    static CACHE: Cache<History> = OnceLock::new();
    let map = CACHE.get_or_init(Default::default);
    let k = format!("{scene:?}");
    if let Some(h) = map.lock().unwrap().get(&k) {
        return Arc::clone(h);
    }
    let (_, h) = sim::run_history(&sim::history_scene(scene), library(), &sim::Sampling::Auto)
        .expect("a paper history runs");
    let h = Arc::new(h);
    map.lock().unwrap().insert(k, Arc::clone(&h));
    h
}

pub fn column(h: &History, name: HistoryColumn) -> Vec<f64> {
    h.column(name)
        .unwrap_or_else(|| panic!("no history column {name}"))
}

/// Energy the device hands back over what it took: the drops of the device-side energy
/// (flywheels + clutch spring + everything the device dissipates) over its rises.
pub fn returned(scene: &Scene) -> f64 {
    let h = history(scene);
    let parts: Vec<Vec<f64>> = paper::runs::col::DEVICE_ENERGY
        .iter()
        .map(|c| column(&h, *c))
        .collect();
    let d: Vec<f64> = (0..parts[0].len())
        .map(|i| parts.iter().map(|p| p[i]).sum())
        .collect();
    let (mut up, mut down) = (0.0, 0.0);
    for w in d.windows(2) {
        if w[1] > w[0] {
            up += w[1] - w[0];
        } else {
            down += w[0] - w[1];
        }
    }
    if up > 0.0 { down / up } else { 0.0 }
}

// Measures (None where the structure overturned).

pub fn rot(r: &SceneResult) -> Option<f64> {
    (!r.overturned).then_some(r.peak_rotation_ratio)
}

pub fn deformation(r: &SceneResult) -> Option<f64> {
    (!r.overturned).then_some(r.peaks.deformation)
}

pub fn drift(r: &SceneResult) -> Option<f64> {
    (!r.overturned).then_some(r.peaks.drift)
}

/// A rigid block's acceleration as the paper measures it: |θ̈|max/p² between impacts.
pub fn angular(r: &SceneResult) -> Option<f64> {
    (!r.overturned).then(|| r.peaks.angular_acceleration_p2.expect("a rigid block"))
}

/// The absolute horizontal acceleration |ẍ + a_g|max/g (a flexible structure's measure).
pub fn horizontal(r: &SceneResult) -> Option<f64> {
    (!r.overturned).then_some(r.peaks.abs_acceleration_g)
}

pub fn series(rs: &[Arc<SceneResult>], m: fn(&SceneResult) -> Option<f64>) -> S {
    rs.iter().map(|r| m(r)).collect()
}

/// `from, from + step, …, to`.
pub fn axis(from: f64, to: f64, step: f64) -> Vec<f64> {
    let n = ((to - from) / step).round() as usize;
    (0..=n).map(|i| from + i as f64 * step).collect()
}

/// The scene at each ωg/p of `xs`.
pub fn sweep(scene: &Scene, xs: &[f64]) -> Vec<Arc<SceneResult>> {
    let scenes: Vec<Scene> = xs
        .iter()
        .map(|&x| {
            let mut s = scene.clone();
            match &mut s.excitation {
                Excitation::Pulse { frequency, .. } => *frequency = Frequency::Ratio(x),
                e => panic!("not a pulse: {e:?}"),
            }
            s
        })
        .collect();
    results(&scenes)
}

// The table: every claim's recomputation, in the paper's order.

/// A claim's id and its recomputation.
pub type Entry = (&'static str, fn() -> Expect);

fn table() -> Vec<Entry> {
    let mut t = crate::paper_rows_rigid::TABLE.to_vec();
    t.extend(crate::paper_rows_mechanisms::TABLE);
    t.extend(crate::paper_rows_flexible::TABLE);
    t.extend(crate::paper_rows_clutch_settings::TABLE);
    t.extend(crate::paper_rows_records::TABLE);
    t
}

fn close(a: f64, b: f64) -> bool {
    (a.is_nan() && b.is_nan()) || a == b || (a - b).abs() <= 1e-9 * a.abs().max(b.abs()) + 1e-12
}

/// What is wrong with `row` against its recomputation.
fn problems(row: &paper::Row, e: &Expect) -> Vec<String> {
    let mut out = Vec::new();
    for (k, x) in &e.values {
        match row.value(k) {
            None => out.push(format!("{}: no value '{k}' (recomputed {x})", row.id)),
            Some(y) if !close(*x, y) => {
                out.push(format!("{}: '{k}' = {y}, recomputed {x}", row.id))
            }
            _ => {}
        }
    }
    for (k, y) in &row.values {
        if !k.starts_with("sensitivity") && !e.values.iter().any(|(n, _)| n == k) {
            out.push(format!("{}: '{k}' = {y} is not recomputed", row.id));
        }
    }
    if row.verdict != e.agreement {
        out.push(format!(
            "{}: verdict {:?}, the thresholds give {:?}",
            row.id, row.verdict, e.agreement
        ));
    }
    out
}

#[test]
fn the_table_recomputes_every_claim() {
    let ids: Vec<&str> = table().iter().map(|(id, _)| *id).collect();
    assert_eq!(ids, paper::claim_ids());
}

#[test]
fn every_rows_numbers_and_verdict_are_recomputed() {
    let rows = paper::rows(None).expect("the paper's rows run");
    let t = table();
    assert_eq!(rows.len(), t.len());
    let mut all = Vec::new();
    for (row, (id, recompute)) in rows.iter().zip(&t) {
        assert_eq!(row.id, *id);
        all.extend(problems(row, &recompute()));
    }
    assert!(all.is_empty(), "{}", all.join("\n"));
}

/// Three of the reruns behind disagreements (one unstated setting changed), their verdict
/// codes (0 agrees, 1 roughly, 2 disagrees) recomputed: the reasons quote measured runs.
#[test]
fn sensitivity_reruns_are_recomputed() {
    let cases = [
        (
            "fig8-faster-decrease",
            "c̄ = 0.5 s⁻¹",
            crate::paper_rows_rigid::decay_with_cbar(0.5),
        ),
        (
            "fig19-operational-immaterial",
            "√(kθ/J) = 10 p",
            crate::paper_rows_flexible::xi_immaterial_at_stiffness(10.0),
        ),
        (
            "fig21-operational-negligible",
            "fμ = 0.02 mr g",
            crate::paper_rows_flexible::friction_negligible(0.02),
        ),
    ];
    for (id, name, agreement) in cases {
        let row = paper::row(id).expect("the row runs");
        let code = row
            .value(&format!(
                "sensitivity (0 agrees, 1 roughly, 2 disagrees): {name}"
            ))
            .unwrap_or_else(|| panic!("{id}: no sensitivity value for {name}"));
        assert_eq!(code, rank(agreement) as f64, "{id}: {name}");
    }
}
