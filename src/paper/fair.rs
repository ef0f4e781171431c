//! One fair check per kind of claim, defined once: every row whose claim is of a kind judges it
//! with that kind's function and thresholds, so no row picks its own window or margin.
//!
//! A spectrum is a [`Series`]: one value per point of the figure's axis, None where the scene
//! overturned (the paper discontinues its curves there).

use super::Agreement;

/// One value per axis point; None where the structure overturned.
pub type Series = Vec<Option<f64>>;

/// A fair check's outcome: what was checked, the numbers, the verdict and, short of agreeing,
/// the gap.
#[derive(Clone, Debug)]
pub struct Judgement {
    pub check: String,
    pub values: Vec<(String, f64)>,
    pub verdict: Agreement,
    pub gap: String,
}

impl Judgement {
    /// Add a value reported beside the check's own (it does not change the verdict).
    pub fn with(mut self, name: impl Into<String>, x: f64) -> Self {
        self.values.push((name.into(), x));
        self
    }

    /// Add a sentence to the check's description (the scenes it ran).
    pub fn on(mut self, scenes: &str) -> Self {
        self.check = format!("{} — {scenes}", self.check);
        self
    }

    /// The value the check reported as `name`; a name it did not report is an error (a
    /// misspelt name must not read as NaN, which `f64::max` would silently drop).
    pub fn value(&self, name: &str) -> Result<f64, MissingValue> {
        self.values
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, x)| *x)
            .ok_or_else(|| MissingValue {
                name: name.to_string(),
                check: self.check.clone(),
            })
    }
}

/// A row asked a judgement for a value it did not report.
#[derive(Debug, thiserror::Error)]
#[error("internal: the check \"{check}\" reports no value named \"{name}\"")]
pub struct MissingValue {
    pub name: String,
    pub check: String,
}

impl From<MissingValue> for crate::error::Error {
    fn from(e: MissingValue) -> Self {
        crate::error::Error::Other(Box::new(e))
    }
}

/// "Immaterial / not determinant / negligible / comparable / almost unnoticeable": the largest
/// difference from the reference, over the figure's whole axis, as a share of the reference
/// spectrum's peak, at most this...
pub const IMMATERIAL_SHARE: f64 = 0.10;
/// ...and at most this for "roughly".
pub const IMMATERIAL_ROUGHLY: f64 = 0.20;

/// The dead band of the immaterial share: within a point of [`IMMATERIAL_SHARE`] the row says
/// the verdict sits at the threshold.
pub const IMMATERIAL_MARGIN: f64 = 0.01;

/// "Immaterial" and its synonyms: every variant against the reference. A point where exactly
/// one of the two overturned (a curve discontinued where the other goes on) is a visible
/// difference: it caps the verdict at roughly. On a spectrum (three points or more) the
/// largest difference but one is reported too: a share above the threshold at a single point
/// only is roughly, and the gap says the verdict rests on that point.
pub fn immaterial(reference: &Series, variants: &[(&str, &Series)]) -> Judgement {
    let scale = peak(reference).unwrap_or(0.0);
    let mut values = vec![("reference peak".to_string(), scale)];
    let (mut worst, mut worst_but_one, mut flips) = (0.0f64, 0.0f64, 0usize);
    for (name, v) in variants {
        let mut d: Vec<f64> = reference
            .iter()
            .zip(v.iter())
            .filter_map(|(a, b)| Some((a.as_ref()? - b.as_ref()?).abs()))
            .map(|d| if scale > 0.0 { d / scale } else { d })
            .collect();
        d.sort_by(|a, b| b.total_cmp(a));
        let share = d.first().copied().unwrap_or(0.0);
        let flipped = reference
            .iter()
            .zip(v.iter())
            .filter(|(a, b)| a.is_some() != b.is_some())
            .count();
        values.push((
            format!("{name}: largest difference / reference peak"),
            share,
        ));
        values.push((format!("{name}: overturning flips"), flipped as f64));
        if reference.len() >= 3 {
            let but_one = d.get(1).copied().unwrap_or(0.0);
            values.push((
                format!("{name}: largest difference but one / reference peak"),
                but_one,
            ));
            worst_but_one = worst_but_one.max(but_one);
        } else {
            worst_but_one = worst_but_one.max(share);
        }
        worst = worst.max(share);
        flips += flipped;
    }
    let one_point = worst > IMMATERIAL_SHARE && worst_but_one <= IMMATERIAL_SHARE;
    let verdict = if worst <= IMMATERIAL_SHARE && flips == 0 {
        Agreement::Agrees
    } else if worst <= IMMATERIAL_ROUGHLY || (one_point && flips == 0) {
        Agreement::Roughly
    } else {
        Agreement::Disagrees
    };
    let pct = |x: f64| 100.0 * x;
    let gap = match verdict {
        Agreement::Agrees if worst > IMMATERIAL_SHARE - IMMATERIAL_MARGIN => format!(
            "largest difference {:.1} % of the reference peak, within a point of the {:.0} % threshold",
            pct(worst),
            pct(IMMATERIAL_SHARE)
        ),
        Agreement::Agrees => String::new(),
        _ if flips > 0 && worst <= IMMATERIAL_ROUGHLY => format!(
            "largest difference {:.1} % of the peak, but {flips} point(s) where only one curve overturns",
            pct(worst)
        ),
        _ if one_point => format!(
            "largest difference {:.1} % of the reference peak at one point only: without it {:.1} % (immaterial: ≤ {:.0} %), so the verdict rests on that point",
            pct(worst),
            pct(worst_but_one),
            pct(IMMATERIAL_SHARE)
        ),
        _ => format!(
            "largest difference {:.1} % of the reference peak (immaterial: ≤ {:.0} %)",
            pct(worst),
            pct(IMMATERIAL_SHARE)
        ),
    };
    Judgement {
        check: format!(
            "immaterial: largest |difference| over the whole axis ≤ {:.0} % of the reference spectrum's peak (≤ {:.0} %, or above it at one point only, roughly), no overturning flips",
            pct(IMMATERIAL_SHARE),
            pct(IMMATERIAL_ROUGHLY)
        ),
        values,
        verdict,
        gap,
    }
}

/// "Converge / within": |a − b| / |b| at most `tol` (the tolerance is the claim's own word:
/// "converge" 1 %).
pub const CONVERGE: f64 = 0.01;

pub fn converges(value: f64, limit: f64) -> Judgement {
    let err = (value - limit).abs() / limit.abs();
    let verdict = ladder(err, CONVERGE, 5.0 * CONVERGE);
    Judgement {
        check: format!(
            "converges: |value − limit| / limit ≤ {:.0} % ({:.0} % roughly)",
            100.0 * CONVERGE,
            500.0 * CONVERGE
        ),
        values: vec![
            ("value".into(), value),
            ("limit".into(), limit),
            ("relative difference".into(), err),
        ],
        verdict,
        gap: gap_unless_agrees(verdict, || format!("{:.2} % apart", 100.0 * err)),
    }
}

/// A measure of distance from the claim judged on two thresholds: agrees at most `agree`,
/// roughly at most `roughly`, else disagrees.
fn ladder(distance: f64, agree: f64, roughly: f64) -> Agreement {
    if distance <= agree {
        Agreement::Agrees
    } else if distance <= roughly {
        Agreement::Roughly
    } else {
        Agreement::Disagrees
    }
}

/// The gap a row states: none when it agrees.
fn gap_unless_agrees(verdict: Agreement, gap: impl FnOnce() -> String) -> String {
    if verdict == Agreement::Agrees {
        String::new()
    } else {
        gap()
    }
}

/// The dead band of every ratio check: a ratio within ±1 % of 1 is "no difference", so a
/// verdict never flips on the fifth digit (a mean of 0.9999992 is not "slightly lower", a
/// point at 1.000001 is not "above").
pub const DEAD_BAND: f64 = 0.01;

/// How strongly a claim says one response is above or below another; thresholds on the mean
/// of the pointwise ratio (variant / reference) and the share of points on the claimed side,
/// each clear of [`DEAD_BAND`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Relation {
    /// "larger / higher / increased": mean ratio > 1 and at least half the points above.
    Larger,
    /// "markedly / significantly larger": mean ratio ≥ 1.10 and ≥ 80 % of the points above.
    MarkedlyLarger,
    /// "lower / smaller / reduce": mean ratio < 1 and at least half the points below.
    Lower,
    /// "in all cases smaller": every point below (≥ 80 % roughly).
    LowerEverywhere,
    /// "significantly / greatly / important reductions": mean ratio ≤ 0.80 (< 0.95 roughly).
    MuchLower,
    /// "slightly / marginally / mild / small / less dramatic" lower: mean ratio in [0.80, 1)
    /// (0.70 – 0.80 or 1 – 1.03 roughly).
    SlightlyLower,
    /// "more than halving": mean ratio < 0.5 (< 0.6 roughly).
    Halved,
    /// "slightly higher": mean ratio in (1, 1.20] ((1.20, 1.30] or [0.97, 1] roughly).
    SlightlyHigher,
    /// "can / possible / in some cases" higher: at least one point above.
    HigherSomewhere,
    /// "can" lower: at least one point below.
    LowerSomewhere,
}

impl Relation {
    fn words(self) -> &'static str {
        match self {
            Relation::Larger => {
                "larger: mean ratio > 1.01 and ≥ 50 % of points above 1.01 (one of the two roughly)"
            }
            Relation::MarkedlyLarger => {
                "markedly larger: mean ratio ≥ 1.10 and ≥ 80 % of points above 1.01 (mean > 1.01 roughly)"
            }
            Relation::Lower => {
                "lower: mean ratio < 0.99 and ≥ 50 % of points below 0.99 (one of the two roughly)"
            }
            Relation::LowerEverywhere => {
                "lower in all cases: every point below 0.99 (≥ 80 % roughly)"
            }
            Relation::MuchLower => "significantly lower: mean ratio ≤ 0.80 (< 0.95 roughly)",
            Relation::SlightlyLower => {
                "slightly lower: mean ratio in [0.80, 0.99) (0.70–0.80 or 0.99–1.03 roughly)"
            }
            Relation::Halved => "more than halved: mean ratio < 0.5 (< 0.6 roughly)",
            Relation::SlightlyHigher => {
                "slightly higher: mean ratio in (1.01, 1.20] ((1.20, 1.30] or [0.97, 1.01] roughly)"
            }
            Relation::HigherSomewhere => "can be higher: at least one point above 1.01",
            Relation::LowerSomewhere => "can be lower: at least one point below 0.99",
        }
    }

    fn judge(self, mean: f64, above: f64, below: f64) -> Agreement {
        use Agreement::*;
        let pick = |agree: bool, rough: bool| {
            if agree {
                Agrees
            } else if rough {
                Roughly
            } else {
                Disagrees
            }
        };
        let (hi, lo) = (1.0 + DEAD_BAND, 1.0 - DEAD_BAND);
        match self {
            Relation::Larger => pick(mean > hi && above >= 0.5, mean > hi || above >= 0.5),
            Relation::MarkedlyLarger => pick(mean >= 1.10 && above >= 0.8, mean > hi),
            Relation::Lower => pick(mean < lo && below >= 0.5, mean < lo || below >= 0.5),
            Relation::LowerEverywhere => pick(below >= 1.0, below >= 0.8),
            Relation::MuchLower => pick(mean <= 0.80, mean < 0.95),
            Relation::SlightlyLower => pick(
                (0.80..lo).contains(&mean),
                (0.70..0.80).contains(&mean) || (lo..1.03).contains(&mean),
            ),
            Relation::Halved => pick(mean < 0.5, mean < 0.6),
            Relation::SlightlyHigher => pick(
                mean > hi && mean <= 1.20,
                (1.20..=1.30).contains(&mean) || (0.97..=hi).contains(&mean),
            ),
            Relation::HigherSomewhere => pick(above > 0.0, false),
            Relation::LowerSomewhere => pick(below > 0.0, false),
        }
    }
}

/// The pointwise ratio variant / reference where both exist and the reference is positive.
pub fn ratios(reference: &Series, variant: &Series) -> Vec<f64> {
    reference
        .iter()
        .zip(variant)
        .filter_map(|(a, b)| match (a, b) {
            (Some(a), Some(b)) if *a > 0.0 => Some(b / a),
            _ => None,
        })
        .collect()
}

/// A claimed relation of `variant` to `reference`, pointwise over the figure's whole axis (a
/// single scene is a one-point axis).
pub fn compare(relation: Relation, reference: &Series, variant: &Series) -> Judgement {
    let q = ratios(reference, variant);
    let n = q.len().max(1) as f64;
    let m = mean(&q);
    let above = q.iter().filter(|r| **r > 1.0 + DEAD_BAND).count() as f64 / n;
    let below = q.iter().filter(|r| **r < 1.0 - DEAD_BAND).count() as f64 / n;
    let verdict = if q.is_empty() {
        Agreement::Untestable
    } else {
        relation.judge(m, above, below)
    };
    Judgement {
        check: relation.words().to_string(),
        values: vec![
            ("mean ratio".into(), m),
            ("share above".into(), above),
            ("share below".into(), below),
            ("points".into(), q.len() as f64),
        ],
        verdict,
        gap: match verdict {
            Agreement::Agrees => String::new(),
            Agreement::Untestable => "no point where both responses exist".into(),
            _ => format!(
                "mean ratio {m:.3}, {:.0} % of {} points above 1.01, {:.0} % below 0.99",
                100.0 * above,
                q.len(),
                100.0 * below
            ),
        },
    }
}

/// "Differences reduced as X increases", read off the plot: the mean |difference| per third of
/// the axis, on the plotted quantity, as a share of the reference's peak (the plot's scale),
/// falls from third to third (a rise of at most [`DEAD_BAND`] of the peak between neighbours
/// is allowed) and ends more than [`DEAD_BAND`] below where it started. Ends lower but not
/// monotone: roughly.
pub fn gap_shrinks(xs: &[f64], reference: &Series, variant: &Series) -> Judgement {
    let scale = peak(reference).unwrap_or(1.0);
    let d: Vec<f64> = thirds(xs.len())
        .iter()
        .map(|r| {
            let gaps: Vec<f64> = r
                .clone()
                .filter_map(|i| Some((reference[i]? - variant[i]?).abs() / scale))
                .collect();
            mean(&gaps)
        })
        .collect();
    let monotone = d.windows(2).all(|w| w[1] <= w[0] + DEAD_BAND);
    let ends_lower = d[2] < d[0] - DEAD_BAND;
    let verdict = if monotone && ends_lower {
        Agreement::Agrees
    } else if ends_lower {
        Agreement::Roughly
    } else {
        Agreement::Disagrees
    };
    let values = thirds(xs.len())
        .iter()
        .enumerate()
        .map(|(k, r)| {
            (
                format!(
                    "mean |difference| / reference peak, third {} (x {:.2}–{:.2})",
                    k + 1,
                    xs[r.start],
                    xs[r.end - 1]
                ),
                d[k],
            )
        })
        .collect();
    Judgement {
        check: format!(
            "differences reduced as x increases: mean |difference| per third of the axis over the reference's peak (the plotted gap) falls third to third (rises ≤ {DEAD_BAND} allowed) and ends more than {DEAD_BAND} below its start"
        ),
        values,
        verdict,
        gap: gap_unless_agrees(verdict, || {
            format!(
                "plotted gap by third {:.3} → {:.3} → {:.3}",
                d[0], d[1], d[2]
            )
        }),
    }
}

/// "Around X % lower, fairly constant": the pointwise ratio's mean in each third of the axis
/// within `offset_band` of 1 − X (twice that roughly).
pub const OFFSET_BAND: f64 = 0.04;

/// `pairs`: (reference, variant) series over `xs`, one pair per record.
pub fn constant_offset(xs: &[f64], pairs: &[(&Series, &Series)], lower_by: f64) -> Judgement {
    let target = 1.0 - lower_by;
    let thirds = thirds(xs.len());
    let means: Vec<f64> = thirds
        .iter()
        .map(|r| {
            let q: Vec<f64> = pairs
                .iter()
                .flat_map(|(a, b)| ratios(&a[r.clone()].to_vec(), &b[r.clone()].to_vec()))
                .collect();
            mean(&q)
        })
        .collect();
    let worst = means.iter().map(|m| (m - target).abs()).fold(0.0, f64::max);
    let verdict = ladder(worst, OFFSET_BAND, 2.0 * OFFSET_BAND);
    let mut values = Vec::new();
    for (k, r) in thirds.iter().enumerate() {
        values.push((
            format!(
                "mean ratio, third {} (x {:.0}–{:.0})",
                k + 1,
                xs[r.start],
                xs[r.end - 1]
            ),
            means[k],
        ));
    }
    Judgement {
        check: format!(
            "around {:.0} % lower, fairly constant: pointwise ratio's mean in each third of the axis within ±{:.0} points of {target:.2} (±{:.0} roughly)",
            100.0 * lower_by,
            100.0 * OFFSET_BAND,
            200.0 * OFFSET_BAND
        ),
        values,
        verdict,
        gap: gap_unless_agrees(verdict, || {
            format!(
                "by third {:.3}, {:.3}, {:.3} against {target:.2}",
                means[0], means[1], means[2]
            )
        }),
    }
}

/// The fractions of its own peak an envelope is timed to.
pub const DECAY_FRACTIONS: [f64; 4] = [0.5, 0.2, 0.1, 0.05];

/// The last time |y| reaches `f` × its peak: when the envelope (the largest |y| still to come)
/// falls below that fraction.
pub fn envelope_time(t: &[f64], y: &[f64], f: f64) -> f64 {
    let peak = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    t.iter()
        .zip(y)
        .filter(|(_, v)| v.abs() >= f * peak)
        .map(|(t, _)| *t)
        .fold(f64::NAN, f64::max)
}

/// "Faster decrease / quickly reach rest": the claimed-faster history's envelope falls to each
/// of [`DECAY_FRACTIONS`] of its own peak earlier than the other's (at half of them roughly).
pub fn faster_decrease(faster: (&[f64], &[f64]), slower: (&[f64], &[f64])) -> Judgement {
    let mut values = Vec::new();
    let mut earlier = 0;
    for f in DECAY_FRACTIONS {
        let a = envelope_time(faster.0, faster.1, f);
        let b = envelope_time(slower.0, slower.1, f);
        values.push((format!("claimed faster: time to {:.0} % (s)", 100.0 * f), a));
        values.push((format!("other: time to {:.0} % (s)", 100.0 * f), b));
        earlier += usize::from(a < b);
    }
    let verdict = if earlier == DECAY_FRACTIONS.len() {
        Agreement::Agrees
    } else if 2 * earlier >= DECAY_FRACTIONS.len() {
        Agreement::Roughly
    } else {
        Agreement::Disagrees
    };
    Judgement {
        check: "faster decrease: times for each envelope (largest |θ| still to come) to fall below 50/20/10/5 % of its own peak, the claimed-faster one earlier at all four (at two roughly)".into(),
        values,
        verdict,
        gap: gap_unless_agrees(verdict, || {
            format!("earlier at {earlier} of {} fractions", DECAY_FRACTIONS.len())
        }),
    }
}

/// "Increases with x": strictly increasing on the grid.
pub fn increasing(name: &str, curves: &[Vec<f64>]) -> Judgement {
    let rises: usize = curves
        .iter()
        .map(|ys| ys.windows(2).filter(|w| w[1] > w[0]).count())
        .sum();
    let steps: usize = curves.iter().map(|ys| ys.len().saturating_sub(1)).sum();
    let verdict = if rises == steps {
        Agreement::Agrees
    } else if 2 * rises >= steps {
        Agreement::Roughly
    } else {
        Agreement::Disagrees
    };
    Judgement {
        check: format!(
            "increasing: {name} rises at every step of the grid (at half of them roughly)"
        ),
        values: vec![
            ("rising steps".into(), rises as f64),
            ("steps".into(), steps as f64),
        ],
        verdict,
        gap: gap_unless_agrees(verdict, || format!("rises at {rises} of {steps} steps")),
    }
}

/// "Approximately X": within `APPROX` of X, relative (twice that roughly).
pub const APPROX: f64 = 0.15;

pub fn approximately(value: f64, stated: f64) -> Judgement {
    let err = (value - stated).abs() / stated.abs();
    let verdict = ladder(err, APPROX, 2.0 * APPROX);
    Judgement {
        check: format!(
            "approximately: within {:.0} % of the stated value ({:.0} % roughly)",
            100.0 * APPROX,
            200.0 * APPROX
        ),
        values: vec![("measured".into(), value), ("stated".into(), stated)],
        verdict,
        gap: gap_unless_agrees(verdict, || format!("{value:.3} against {stated}")),
    }
}

/// "Coincide / conserve / equivalent": a measured share (a mismatch, a residual, a relative
/// difference) at most `limit` (twice that roughly).
pub fn small(what: &str, share: f64, limit: f64) -> Judgement {
    let verdict = ladder(share, limit, 2.0 * limit);
    Judgement {
        check: format!("small: {what} ≤ {} ({} roughly)", limit, 2.0 * limit),
        values: vec![(what.to_string(), share)],
        verdict,
        gap: gap_unless_agrees(verdict, || format!("{what} = {share:.4} against ≤ {limit}")),
    }
}

/// "Cause shifts / is prevented": a measured share at least `limit` (half that roughly).
pub fn at_least(what: &str, share: f64, limit: f64) -> Judgement {
    let verdict = if share >= limit {
        Agreement::Agrees
    } else if share >= 0.5 * limit {
        Agreement::Roughly
    } else {
        Agreement::Disagrees
    };
    Judgement {
        check: format!("at least: {what} ≥ {limit} ({} roughly)", 0.5 * limit),
        values: vec![(what.to_string(), share)],
        verdict,
        gap: gap_unless_agrees(verdict, || format!("{what} = {share:.4} against ≥ {limit}")),
    }
}

/// Energy flowing back from the device: "part of the energy transferred back" = at least 10 %
/// of what the device took (2 % roughly); "fully prevent" = at most 1 % (5 % roughly).
pub fn energy_back(returned: f64, claimed_back: bool) -> Judgement {
    let verdict = match claimed_back {
        true if returned >= 0.10 => Agreement::Agrees,
        true if returned >= 0.02 => Agreement::Roughly,
        false if returned <= 0.01 => Agreement::Agrees,
        false if returned <= 0.05 => Agreement::Roughly,
        _ => Agreement::Disagrees,
    };
    Judgement {
        check: "energy back: the device-side energy's drops over its rises (flywheels + clutch spring + device dissipation): a part ≥ 10 % (2 % roughly), none ≤ 1 % (5 % roughly)".into(),
        values: vec![("returned / taken".into(), returned)],
        verdict,
        gap: gap_unless_agrees(verdict, || {
            format!("{:.1} % returned", 100.0 * returned)
        }),
    }
}

/// The verdict of a check over plausible values of what the paper leaves unstated: "agrees
/// for …; not for …", and each variant's verdict as a value (0 agrees, 1 roughly, 2 disagrees).
pub fn sensitivity(over: &str, variants: &[(String, Judgement)]) -> (String, Vec<(String, f64)>) {
    let rank = |v: Agreement| Agreement::ALL.iter().position(|x| *x == v).unwrap_or(3) as f64;
    let names = |want: Agreement| {
        variants
            .iter()
            .filter(|(_, j)| j.verdict == want)
            .map(|(n, _)| n.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut parts = Vec::new();
    for v in [Agreement::Agrees, Agreement::Roughly, Agreement::Disagrees] {
        let n = names(v);
        if !n.is_empty() {
            parts.push(format!("{} for {n}", v.label()));
        }
    }
    let values = variants
        .iter()
        .map(|(n, j)| {
            (
                format!("sensitivity (0 agrees, 1 roughly, 2 disagrees): {n}"),
                rank(j.verdict),
            )
        })
        .collect();
    (
        format!("sensitivity over the {over}: {}", parts.join("; ")),
        values,
    )
}

/// A claim that cannot be checked here, and why.
pub fn untestable(why: &str) -> Judgement {
    Judgement {
        check: "none".into(),
        values: Vec::new(),
        verdict: Agreement::Untestable,
        gap: why.into(),
    }
}

/// The worse of two judgements (a claim about two responses holds as well as its weaker half);
/// values of both are kept, the second's prefixed.
pub fn both(a: Judgement, prefix_a: &str, b: Judgement, prefix_b: &str) -> Judgement {
    let rank = |v: Agreement| Agreement::ALL.iter().position(|x| *x == v).unwrap_or(0);
    let verdict = if rank(a.verdict) >= rank(b.verdict) {
        a.verdict
    } else {
        b.verdict
    };
    let gap = [(prefix_a, &a.gap), (prefix_b, &b.gap)]
        .iter()
        .filter(|(_, g)| !g.is_empty())
        .map(|(p, g)| format!("{p}: {g}"))
        .collect::<Vec<_>>()
        .join("; ");
    let check = if a.check == b.check {
        format!("{} (for {prefix_a} and {prefix_b})", a.check)
    } else {
        format!("{prefix_a}: {}; {prefix_b}: {}", a.check, b.check)
    };
    let values = a
        .values
        .into_iter()
        .map(|(k, x)| (format!("{prefix_a}: {k}"), x))
        .chain(
            b.values
                .into_iter()
                .map(|(k, x)| (format!("{prefix_b}: {k}"), x)),
        )
        .collect();
    Judgement {
        check,
        values,
        verdict,
        gap,
    }
}

pub fn mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        f64::NAN
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

pub fn peak(v: &Series) -> Option<f64> {
    v.iter().flatten().copied().reduce(f64::max)
}

/// The three thirds of an axis of n points (index ranges).
pub fn thirds(n: usize) -> [std::ops::Range<usize>; 3] {
    [0..n / 3, n / 3..2 * n / 3, 2 * n / 3..n]
}
