//! Which intensity measure predicts a damage state best (`rocklab ims RESULTS`, issue 40):
//! the IDA capacities of a study's results expressed in each IM and ranked by efficiency.
//!
//! A record scaled by λ has IM_k = λ^e · IM_k(unscaled), e = 1 for the amplitude measures
//! (PGA, PGV, PGD, CAV, Sa, Sa_avg, PGA*, PGV*, PGV/Tp), 2 for Arias intensity and 0 for the
//! significant duration (scaling does not change it). A hunt's capacity c (in the study's
//! scaling IM) is the scene factor λ(c) the study's `scale_to` gives the record (the same
//! function the scenes use), so the capacity in IM k is λ(c)^e · IM_k(unscaled): for linear
//! scalings, c × IM_k / IM_scale of the unscaled record.
//!
//! Per variant × damage state × IM, over the records whose hunt finished and reached the
//! state (censored and failed hunts left out):
//! - efficiency β = the sample standard deviation (n − 1) of ln capacity, with a percentile
//!   bootstrap interval over records (`stats::bootstrap`, the study's fragility seed, its
//!   number of resamples and confidence);
//! - sufficiency `p_magnitude` = the two-sided p-value of the least-squares slope of ln
//!   capacity against the record's moment magnitude (t test, n − 2 degrees of freedom);
//!   none when fewer than three records or the magnitudes are all equal.
//!
//! `pgv/tp` (PGV over the pulse period) is taken over the pulse-like components only (their
//! own n). A constant factor does not change β, so PGA* ranks with PGA and PGV* with PGV
//! within a variant (same α, p); both are listed because studies scale to them.

use super::stripes::variant_of;
use crate::error::{Context, Result};
use crate::excitation::ims::{self, Accelerogram, Ims};
use crate::excitation::library::{self, Library};
use crate::scene::{Excitation, RecordScale};
use crate::stats::Variant;
use crate::stats::bootstrap::{Resampler, interval};
use crate::study::{ExcitationFamily, RecordScaling, ScenePoint, Study};
use crate::sweep::SweepResults;
use crate::sweep::ida::replay;
use serde::Serialize;
use std::collections::BTreeMap;

/// Periods of the Sa columns (s), besides the one of the block's frequency parameter 2π/p.
pub const SA_PERIODS: [f64; 3] = [0.5, 1.0, 2.0];
/// The Sa_avg range (s).
pub const SA_AVG: (f64, f64) = (0.5, 2.0);

/// One row of the report.
#[derive(Clone, Debug, Serialize)]
pub struct ImRow {
    pub device: String,
    /// The variant's varying parameters (as in ida.csv).
    #[serde(flatten)]
    pub params: BTreeMap<String, f64>,
    pub damage_state: f64,
    /// The IM's name as in `scale_to` (`pga`, `sa(1.0)`, …; `d5_95`, `cav`, `pgd` and
    /// `pgv/tp` are not scalings).
    pub im: String,
    pub beta: f64,
    pub beta_lo: Option<f64>,
    pub beta_hi: Option<f64>,
    pub n: usize,
    pub p_magnitude: Option<f64>,
}

/// (IM name, its value for the unscaled record, its scaling exponent).
type Measure = (String, f64, i32);
/// (record, baseline, α bits, p bits).
type RecordKey = (String, bool, u64, u64);

/// One finished hunt that reached a damage state: its capacity in each IM and its magnitude.
struct Capacity {
    variant: Variant,
    damage_state: f64,
    /// (IM name, capacity in it); the pulse-only IM is absent for a non-pulse component.
    values: Vec<(String, f64)>,
    magnitude: Option<f64>,
}

/// The IMs of an unscaled record, with their scaling exponents, for a block of parameters
/// `alpha`, `p` (PGA*, PGV* and the Sa at 2π/p depend on them).
fn measures(
    record: &crate::excitation::library::Record,
    alpha: f64,
    p: f64,
) -> Result<Vec<Measure>> {
    let acc = Accelerogram::from_series(&record.series).context("intensity measures")?;
    let block_period = 2.0 * std::f64::consts::PI / p;
    let mut periods = SA_PERIODS.to_vec();
    periods.push(block_period);
    let m = Ims::of(&acc, &periods, ims::DEFAULT_DAMPING).context("intensity measures")?;
    let sa_avg = ims::spectrum::sa_avg(&acc, SA_AVG.0, SA_AVG.1, ims::DEFAULT_DAMPING)
        .context("Sa_avg")?
        / ims::STANDARD_GRAVITY;
    let (pga, pgv) = (record.series.pga(), record.series.pgv());
    // The scenes' own definitions of PGA* and PGV*: the factor that takes the record to 1.
    let pga_star = 1.0 / RecordScale::PgaStar(1.0).factor(pga, pgv, alpha, p);
    let pgv_star = 1.0 / RecordScale::PgvStar(1.0).factor(pga, pgv, alpha, p);
    let mut out = vec![
        ("pga".to_string(), m.pga_g, 1),
        ("pgv".to_string(), m.pgv_m_s, 1),
        ("pgd".to_string(), m.pgd_m, 1),
        ("arias".to_string(), m.arias_m_s, 2),
        ("cav".to_string(), m.cav_m_s, 1),
        ("d5_95".to_string(), m.d5_95_s, 0),
    ];
    for (t, sa) in periods.iter().zip(&m.sa_g) {
        out.push((format!("sa({})", fmt_period(*t)), *sa, 1));
    }
    out.push((
        format!("sa_avg({}, {})", fmt_period(SA_AVG.0), fmt_period(SA_AVG.1)),
        sa_avg,
        1,
    ));
    out.push(("pga_star".to_string(), pga_star, 1));
    out.push(("pgv_star".to_string(), pgv_star, 1));
    if let Some(tp) = m.tp_s {
        out.push(("pgv/tp".to_string(), m.pgv_m_s / tp, 1));
    }
    Ok(out)
}

/// A period as `scale_to` writes it: 1.0, 0.5, 3.14.
fn fmt_period(t: f64) -> String {
    let r = (t * 100.0).round() / 100.0;
    if r.fract() == 0.0 {
        format!("{r:.1}")
    } else {
        format!("{r}")
    }
}

/// The record's moment magnitude: its suite row's, else its library entry's.
fn magnitude(library: &Library, name: &str) -> Option<f64> {
    library
        .suite_entry(name)
        .map(|e| e.row.magnitude)
        .or_else(|| {
            library
                .index()
                .iter()
                .find(|m| m.name == name)
                .map(|m| m.mw)
        })
}

/// The report of a study's IDA results.
pub fn report(study: &Study, results: &SweepResults) -> Result<Vec<ImRow>> {
    let Some(f) = &study.fragility else {
        crate::error::bail!("study `{}` has no fragility section", study.name);
    };
    let ExcitationFamily::Record { scale_to, .. } = &study.excitation else {
        crate::error::bail!(
            "study `{}` does not scale records: `rocklab ims` needs an IDA over records",
            study.name
        );
    };
    let scale_to: RecordScaling = *scale_to;
    let search = replay(study, &results.outcomes).context("replaying the IDA hunts")?;
    let layout = study.layout()?;
    let library = library::global().context("the record library")?;
    let on_grid: Vec<&ScenePoint> = Vec::new();
    let mut caps: Vec<Capacity> = Vec::new();
    let mut cache: BTreeMap<RecordKey, Vec<Measure>> = BTreeMap::new();
    for r in search.records() {
        if !r.done || r.failed {
            continue;
        }
        let scene = &r.nominal.scene;
        let Excitation::Record { name, baseline, .. } = &scene.excitation else {
            continue;
        };
        let (alpha, p) = (scene.structure.alpha(), scene.structure.p());
        let record = library
            .load(name, *baseline)
            .with_context(|| format!("record `{name}`"))?;
        let key = (name.clone(), *baseline, alpha.to_bits(), p.to_bits());
        if !cache.contains_key(&key) {
            let m = measures(&record, alpha, p).with_context(|| format!("record `{name}`"))?;
            cache.insert(key.clone(), m);
        }
        let ims = &cache[&key];
        let variant = variant_of(&layout, &r.nominal, &on_grid);
        for (ds, result) in &r.states {
            let Some(c) = result.capacity.filter(|_| !result.censored) else {
                continue;
            };
            let lambda = crate::study::suites::scene_scale(scale_to, c, name, *baseline)?.factor(
                record.series.pga(),
                record.series.pgv(),
                alpha,
                p,
            );
            caps.push(Capacity {
                variant: variant.clone(),
                damage_state: *ds,
                values: ims
                    .iter()
                    .map(|(im, v, e)| (im.clone(), lambda.abs().powi(*e) * v))
                    .collect(),
                magnitude: magnitude(library, name),
            });
        }
    }
    let mut rows = Vec::new();
    let mut groups: Vec<(Variant, f64)> = Vec::new();
    for c in &caps {
        if !groups.contains(&(c.variant.clone(), c.damage_state)) {
            groups.push((c.variant.clone(), c.damage_state));
        }
    }
    let names: Vec<String> = cache
        .values()
        .flat_map(|m| m.iter().map(|(n, _, _)| n.clone()))
        .fold(Vec::new(), |mut v, n| {
            if !v.contains(&n) {
                v.push(n);
            }
            v
        });
    for (variant, ds) in groups {
        let first = rows.len();
        let group: Vec<&Capacity> = caps
            .iter()
            .filter(|c| c.variant == variant && c.damage_state == ds)
            .collect();
        for im in &names {
            let pairs: Vec<(f64, Option<f64>)> = group
                .iter()
                .filter_map(|c| {
                    let v = c.values.iter().find(|(n, _)| n == im)?.1;
                    (v > 0.0 && v.is_finite()).then(|| (v.ln(), c.magnitude))
                })
                .collect();
            if pairs.len() < 2 {
                continue;
            }
            let logs: Vec<f64> = pairs.iter().map(|(l, _)| *l).collect();
            let [beta_lo, beta_hi] = bootstrap_beta(&logs, f.bootstrap, f.seed, f.confidence);
            let mags: Option<Vec<f64>> = pairs.iter().map(|(_, m)| *m).collect();
            rows.push(ImRow {
                device: variant.device.clone(),
                params: variant.params.iter().cloned().collect(),
                damage_state: ds,
                im: im.clone(),
                beta: sample_std(&logs),
                beta_lo,
                beta_hi,
                n: logs.len(),
                p_magnitude: mags.and_then(|m| slope_p_value(&m, &logs)),
            });
        }
        // Ranked within the variant and damage state (groups in the order met).
        rows[first..].sort_by(|a, b| a.beta.total_cmp(&b.beta));
    }
    Ok(rows)
}

/// The sample standard deviation (n − 1) of `x` (n ≥ 2).
pub fn sample_std(x: &[f64]) -> f64 {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    (x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
}

/// The percentile interval of β over `resamples` bootstrap resamples of the records.
fn bootstrap_beta(logs: &[f64], resamples: usize, seed: u64, confidence: f64) -> [Option<f64>; 2] {
    let mut draw = Resampler::new(seed, logs.len());
    let betas: Vec<f64> = (0..resamples)
        .map(|_| {
            let sample: Vec<f64> = draw
                .draw()
                .iter()
                .zip(logs)
                .flat_map(|(w, l)| std::iter::repeat_n(*l, *w))
                .collect();
            sample_std(&sample)
        })
        .collect();
    interval(&betas, confidence)
}

/// The two-sided p-value of the least-squares slope of y on x (t test with n − 2 degrees of
/// freedom); None for fewer than three points or a constant x.
pub fn slope_p_value(x: &[f64], y: &[f64]) -> Option<f64> {
    let n = x.len();
    if n < 3 {
        return None;
    }
    let nf = n as f64;
    let (mx, my) = (x.iter().sum::<f64>() / nf, y.iter().sum::<f64>() / nf);
    let sxx: f64 = x.iter().map(|v| (v - mx).powi(2)).sum();
    if sxx <= 1e-12 * (1.0 + mx * mx) {
        return None;
    }
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let slope = sxy / sxx;
    let sse: f64 = x
        .iter()
        .zip(y)
        .map(|(a, b)| (b - my - slope * (a - mx)).powi(2))
        .sum();
    let dof = nf - 2.0;
    let se = (sse / dof / sxx).sqrt();
    if se == 0.0 {
        return Some(if slope == 0.0 { 1.0 } else { 0.0 });
    }
    let t = slope / se;
    // P(|T| > t) = I_{ν/(ν+t²)}(ν/2, 1/2).
    Some(incomplete_beta(dof / 2.0, 0.5, dof / (dof + t * t)))
}

/// The regularised incomplete beta function I_x(a, b), by its continued fraction (Lentz's
/// method), on the side of x where it converges fast.
pub fn incomplete_beta(a: f64, b: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let ln_front =
        libm::lgamma(a + b) - libm::lgamma(a) - libm::lgamma(b) + a * x.ln() + b * (1.0 - x).ln();
    if x < (a + 1.0) / (a + b + 2.0) {
        ln_front.exp() * beta_fraction(a, b, x) / a
    } else {
        1.0 - ln_front.exp() * beta_fraction(b, a, 1.0 - x) / b
    }
}

fn beta_fraction(a: f64, b: f64, x: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
    let mut c = 1.0;
    let mut d = 1.0 - qab * x / qap;
    if d.abs() < TINY {
        d = TINY;
    }
    d = 1.0 / d;
    let mut h = d;
    for m in 1..300 {
        let m = m as f64;
        let m2 = 2.0 * m;
        let aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1.0 + aa * d;
        d = if d.abs() < TINY { TINY } else { d };
        c = 1.0 + aa / c;
        c = if c.abs() < TINY { TINY } else { c };
        d = 1.0 / d;
        h *= d * c;
        let aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1.0 + aa * d;
        d = if d.abs() < TINY { TINY } else { d };
        c = 1.0 + aa / c;
        c = if c.abs() < TINY { TINY } else { c };
        d = 1.0 / d;
        let step = d * c;
        h *= step;
        if (step - 1.0).abs() < 1e-15 {
            break;
        }
    }
    h
}

/// The ranked text table: per variant and damage state, the IMs from the most efficient.
pub fn table(rows: &[ImRow]) -> String {
    let mut out = String::from(
        "IM efficiency: β = std of ln IDA capacity in the IM over the records reaching the state (n); \
         interval: bootstrap over records; p(Mw): slope of ln capacity on magnitude\n",
    );
    let mut last: Option<(String, String, f64)> = None;
    for r in rows {
        let params: String = r.params.iter().map(|(k, v)| format!(" {k}={v}")).collect();
        let key = (r.device.clone(), params.clone(), r.damage_state);
        if last.as_ref() != Some(&key) {
            out.push_str(&format!(
                "\n{}{} damage state {}\n{:<18} {:>6} {:>15} {:>3} {:>7}\n",
                r.device, params, r.damage_state, "im", "β", "interval", "n", "p(Mw)"
            ));
            last = Some(key);
        }
        let ci = match (r.beta_lo, r.beta_hi) {
            (Some(lo), Some(hi)) => format!("{lo:.3}–{hi:.3}"),
            _ => "-".into(),
        };
        let p = r.p_magnitude.map_or("-".into(), |p| format!("{p:.3}"));
        out.push_str(&format!(
            "{:<18} {:>6.3} {:>15} {:>3} {:>7}\n",
            r.im, r.beta, ci, r.n, p
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_std_uses_n_minus_one() {
        assert!((sample_std(&[1.0, 2.0, 3.0, 4.0]) - (5.0f64 / 3.0).sqrt()).abs() < 1e-15);
        assert_eq!(sample_std(&[2.5, 2.5, 2.5]), 0.0);
    }

    /// I_x(a, b) against closed forms: I_x(1, 1) = x, I_x(a, 1) = x^a, I_x(1, b) = 1 − (1−x)^b,
    /// and the t distribution with 1 degree of freedom (Cauchy): P(|T| > t) = 1 − 2 atan(t)/π.
    #[test]
    fn incomplete_beta_closed_forms() {
        for x in [0.01, 0.3, 0.5, 0.77, 0.99] {
            assert!((incomplete_beta(1.0, 1.0, x) - x).abs() < 1e-13);
            assert!((incomplete_beta(2.5, 1.0, x) - x.powf(2.5)).abs() < 1e-13);
            assert!((incomplete_beta(1.0, 3.0, x) - (1.0 - (1.0 - x).powi(3))).abs() < 1e-13);
        }
        for t in [0.2f64, 1.0, 3.0, 12.0] {
            let p = incomplete_beta(0.5, 0.5, 1.0 / (1.0 + t * t));
            let cauchy = 1.0 - 2.0 * t.atan() / std::f64::consts::PI;
            assert!((p - cauchy).abs() < 1e-12, "{t}: {p} {cauchy}");
        }
    }

    /// A slope against known t statistics: y = x exactly plus alternating ±e has the slope's
    /// p-value of a t test; with n = 3 (1 dof) it is the Cauchy tail; no slope gives p = 1.
    #[test]
    fn slope_p_values() {
        // x = 0, 1, 2; y = 0, 1 + e, 2 → slope 1, residuals (−e/3, 2e/3, −e/3).
        let e = 0.3;
        let p = slope_p_value(&[0.0, 1.0, 2.0], &[0.0, 1.0 + e, 2.0]).unwrap();
        let sse = 6.0 * e * e / 9.0;
        let t = 1.0 / (sse / 1.0 / 2.0).sqrt();
        let cauchy = 1.0 - 2.0 * t.atan() / std::f64::consts::PI;
        assert!((p - cauchy).abs() < 1e-12, "{p} {cauchy}");
        let flat = slope_p_value(&[0.0, 1.0, 2.0, 3.0], &[1.0, 2.0, 2.0, 1.0]).unwrap();
        assert!((flat - 1.0).abs() < 1e-12, "{flat}");
        assert_eq!(slope_p_value(&[6.7, 6.7, 6.7], &[1.0, 2.0, 3.0]), None);
        assert_eq!(slope_p_value(&[6.0, 7.0], &[1.0, 2.0]), None);
    }

    #[test]
    fn bootstrap_interval_brackets_beta_and_is_zero_for_equal_capacities() {
        let logs = [0.1, 0.5, -0.2, 0.9, 0.3, -0.4, 0.2];
        let [lo, hi] = bootstrap_beta(&logs, 500, 7, 0.9);
        let beta = sample_std(&logs);
        assert!(
            lo.unwrap() < beta && beta < hi.unwrap(),
            "{lo:?} {beta} {hi:?}"
        );
        let [lo, hi] = bootstrap_beta(&[0.4; 5], 100, 7, 0.9);
        assert_eq!((lo, hi), (Some(0.0), Some(0.0)));
    }

    #[test]
    fn periods_are_named_as_in_scale_to() {
        assert_eq!(fmt_period(1.0), "1.0");
        assert_eq!(fmt_period(0.5), "0.5");
        assert_eq!(fmt_period(std::f64::consts::PI), "3.14");
    }
}
