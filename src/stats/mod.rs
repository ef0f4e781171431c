//! Fragility statistics: lognormal fragility curves per structure variant and damage state,
//! fitted by binomial maximum likelihood over stripes (multiple-stripe analysis; Baker 2015,
//! Earthquake Spectra 31(1)) or by censored maximum likelihood over IDA capacities, with
//! bootstrap confidence intervals over records and paired ratios of medians (protected
//! variant against the bare one). Pure statistics, below every other module but serde: the
//! observations come from the fragility engine (study → sweep → `report::stripes` /
//! `report::ida`) and from a design search's fragility target (`sweep::design`, which fits
//! every probe with the same functions); `report::fragility` writes the report to
//! fragility.csv / fragility.json and the figure, and re-exports this module.
//!
//! The contract with the engine is /work/notes/fragility-interface.md (copied into the types
//! below); degenerate fits are statuses, never numbers.

pub(crate) mod bootstrap;
mod fit;
pub(crate) mod normal;
#[cfg(test)]
pub(crate) mod tests;

pub use fit::{Lognormal, fit_binomial_mle, fit_censored, fit_moments, merge_stripes};

use bootstrap::Resampler;
pub use bootstrap::interval;
use serde::{Deserialize, Serialize};

/// The device of the bare structure: ratios are taken against the variant with this device.
pub const BARE_DEVICE: &str = "none";

/// One variant of the structure+device family: what a fragility curve is drawn for.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Variant {
    /// "none", "inerter", "sequential", "mechanistic" (or the variant's label).
    pub device: String,
    /// Every varying non-IM, non-record parameter, with the ASCII column names results.csv
    /// uses (e.g. ("alpha", 0.2), ("sigma", 0.5)).
    pub params: Vec<(String, f64)>,
}

impl Variant {
    /// "mechanistic sigma=0.5": the device and its parameters, for legends and readouts.
    pub fn label(&self) -> String {
        let mut s = self.device.clone();
        for (k, v) in &self.params {
            s.push_str(&format!(" {k}={v}"));
        }
        s
    }

    pub fn is_bare(&self) -> bool {
        self.device == BARE_DEVICE
    }
}

/// One scene of a multiple-stripe analysis.
#[derive(Clone, Debug, PartialEq)]
pub struct StripeObservation {
    pub variant: Variant,
    /// Record id, unique within the suite (e.g. "far_field/7a").
    pub record: String,
    /// The stripe's intensity-measure value.
    pub im: f64,
    /// The damage measure (e.g. θmax/α), compared against the damage-state thresholds.
    pub response: f64,
    /// Exceeds every damage state, whatever `response` says.
    pub overturned: bool,
}

impl StripeObservation {
    /// Whether the scene reached damage state `threshold` (None: no usable response).
    fn exceeds(&self, threshold: f64) -> Option<bool> {
        if self.overturned {
            Some(true)
        } else if self.response.is_finite() {
            Some(self.response >= threshold)
        } else {
            None
        }
    }
}

/// One record of an incremental dynamic analysis, for one damage state.
#[derive(Clone, Debug, PartialEq)]
pub struct IdaObservation {
    pub variant: Variant,
    pub record: String,
    /// The damage state hunted for (1.0 = overturning for θmax/α).
    pub damage_state: f64,
    /// First IM at which the damage state was reached (bracket-bisected to the stated
    /// resolution); None = censored: not reached up to `top_im`.
    pub capacity_im: Option<f64>,
    pub top_im: f64,
    /// (survived_im, failed_below_im) pairs: survived at an IM above one that reached the state.
    pub resurrections: Vec<(f64, f64)>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct FragilityOptions {
    /// Thresholds of the damage measure (1.0 = overturning for θmax/α).
    pub damage_states: Vec<f64>,
    /// Resamples over records (0: no confidence intervals).
    pub bootstrap: usize,
    /// Bootstrap seed: reruns with the same seed agree bit for bit.
    pub seed: u64,
    /// Two-sided confidence level: 0.90 → 5th and 95th percentiles.
    pub confidence: f64,
}

impl Default for FragilityOptions {
    fn default() -> Self {
        FragilityOptions {
            damage_states: vec![0.2, 0.5, 1.0],
            bootstrap: 1000,
            seed: 1,
            confidence: 0.90,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    Stripes,
    Ida,
}

impl Method {
    pub fn name(self) -> &'static str {
        match self {
            Method::Stripes => "stripes",
            Method::Ida => "ida",
        }
    }
}

/// Whether a curve was fitted, and if not, why not.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FitStatus {
    Fitted,
    /// No observation at all.
    NoData,
    /// Nothing reached the damage state (IDA: every record censored).
    NoExceedance,
    /// Every observation reached the damage state.
    AllExceed,
    /// Observations at a single IM: two parameters cannot be fitted.
    OneStripe,
    /// Exceedances at a single stripe only.
    OneStripeExceeds,
    /// None exceed below one stripe and all above it: the likelihood peaks at β = 0.
    Separated,
    /// The best fit has exceedance falling with intensity.
    Decreasing,
    /// IDA: fewer than two distinct capacities.
    TooFewCapacities,
    /// The likelihood maximisation did not settle.
    NotConverged,
}

impl FitStatus {
    /// The name in fragility.csv (the serde name).
    pub fn name(self) -> &'static str {
        match self {
            FitStatus::Fitted => "fitted",
            FitStatus::NoData => "no_data",
            FitStatus::NoExceedance => "no_exceedance",
            FitStatus::AllExceed => "all_exceed",
            FitStatus::OneStripe => "one_stripe",
            FitStatus::OneStripeExceeds => "one_stripe_exceeds",
            FitStatus::Separated => "separated",
            FitStatus::Decreasing => "decreasing",
            FitStatus::TooFewCapacities => "too_few_capacities",
            FitStatus::NotConverged => "not_converged",
        }
    }

    /// A sentence for readouts and figure legends.
    pub fn explain(self) -> &'static str {
        match self {
            FitStatus::Fitted => "fitted",
            FitStatus::NoData => "no observations",
            FitStatus::NoExceedance => "no record reached the state",
            FitStatus::AllExceed => "every record reached the state",
            FitStatus::OneStripe => "a single stripe: two parameters cannot be fitted",
            FitStatus::OneStripeExceeds => "exceedances at a single stripe only",
            FitStatus::Separated => "perfectly separated stripes (β → 0)",
            FitStatus::Decreasing => "exceedance falls with intensity",
            FitStatus::TooFewCapacities => "fewer than two distinct capacities",
            FitStatus::NotConverged => "the fit did not converge",
        }
    }
}

/// Exceedances at one stripe.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StripePoint {
    pub im: f64,
    pub n: usize,
    pub exceed: usize,
}

impl StripePoint {
    pub fn fraction(&self) -> f64 {
        self.exceed as f64 / self.n as f64
    }
}

/// One fragility curve: a variant and a damage state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Curve {
    pub variant: Variant,
    pub damage_state: f64,
    pub method: Method,
    pub status: FitStatus,
    pub median: Option<f64>,
    pub beta: Option<f64>,
    pub median_lo: Option<f64>,
    pub median_hi: Option<f64>,
    pub beta_lo: Option<f64>,
    pub beta_hi: Option<f64>,
    pub n_records: usize,
    pub n_stripes: usize,
    /// Per-stripe exceedances (empty for IDA).
    pub stripes: Vec<StripePoint>,
    /// The IM range the data cover (lowest stripe or capacity, highest stripe or top IM);
    /// None without data.
    pub im_range: Option<[f64; 2]>,
    /// Bootstrap resamples whose fit was degenerate (left out of the intervals).
    pub bootstrap_degenerate: usize,
    /// IDA: records censored at their top IM.
    pub n_censored: usize,
    /// IDA: resurrections found (survived above an IM that reached the state).
    pub resurrections: usize,
    /// IDA: sorted capacities of the records that reached the state (empty for stripes).
    pub capacities: Vec<f64>,
    /// Each bootstrap resample's fit as [median, β], None where it was degenerate, in draw
    /// order (the same resample for every curve, so curves pair by index). Kept so that
    /// quantities derived from a fit (a seismic risk, `crate::risk`) get intervals from the
    /// same resamples. Empty without a fit or in files written before it was kept.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub resamples: Vec<Option<[f64; 2]>>,
    /// A study with uncertain parameters: the fit over its deterministic companion scenes
    /// (every uncertain parameter at its distribution's centre), the median and β from
    /// records alone beside this curve's total (report/stripes.rs). None otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub median_records: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beta_records: Option<f64>,
}

impl Curve {
    /// The dispersion the uncertain parameters add, by the square-root-of-sum-of-squares rule
    /// β_total² = β_records² + β_parameters² (FEMA P695 §7.3): None without both fits, or
    /// where β_total < β_records (the draws' sampling noise is larger than their share).
    pub fn beta_parameters(&self) -> Option<f64> {
        let (total, records) = (self.beta?, self.beta_records?);
        (total >= records).then(|| (total * total - records * records).sqrt())
    }

    /// Why a fitted curve should not be trusted as it stands (empty: nothing found): a median
    /// outside the data's intensity range, a median interval wider (as a ratio) than the
    /// data's span, bootstrap resamples that could not be fitted (with their count).
    pub fn warnings(&self) -> Vec<String> {
        let mut flags = Vec::new();
        let (Some(_), Some([lo, hi])) = (self.median, self.im_range) else {
            return flags;
        };
        if let Some(e) = self.extrapolation() {
            flags.push(format!("median_{}", e.name()));
        }
        if let (Some(mlo), Some(mhi)) = (self.median_lo, self.median_hi)
            && mhi / mlo > hi / lo
        {
            flags.push("interval_wider_than_data".to_string());
        }
        if self.bootstrap_degenerate > 0 {
            flags.push(format!(
                "degenerate_resamples={}",
                self.bootstrap_degenerate
            ));
        }
        flags
    }

    /// P(reach the state | IM = x) of the fitted curve.
    pub fn probability(&self, x: f64) -> Option<f64> {
        let (m, b) = (self.median?, self.beta?);
        Some(normal::cdf((x / m).ln() / b))
    }

    /// Whether the fitted median lies outside the IM range the data cover: then it is the
    /// lognormal's extrapolation, not a value the stripes (or capacities) bracket.
    pub fn extrapolation(&self) -> Option<Extrapolation> {
        let (median, [lo, hi]) = (self.median?, self.im_range?);
        match () {
            _ if median < lo => Some(Extrapolation::BelowData),
            _ if median > hi => Some(Extrapolation::AboveData),
            _ => None,
        }
    }
}

/// A fitted median outside the data's IM range (see [`Curve::extrapolation`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Extrapolation {
    BelowData,
    AboveData,
}

impl Extrapolation {
    /// The word in fragility.csv's `warnings` column, after `median_` (`median_below_data`).
    pub fn name(self) -> &'static str {
        match self {
            Extrapolation::BelowData => "below_data",
            Extrapolation::AboveData => "above_data",
        }
    }

    /// A sentence for summaries and readouts.
    pub fn explain(self) -> &'static str {
        match self {
            Extrapolation::BelowData => "median below the lowest IM of the data: extrapolated",
            Extrapolation::AboveData => "median above the highest IM of the data: extrapolated",
        }
    }
}

/// Median of variant `a` over that of variant `b` (the bare one) for one damage state, with a
/// paired bootstrap interval, and whether the fitted curves cross inside the IM range.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MedianRatio {
    pub a: Variant,
    pub b: Variant,
    pub damage_state: f64,
    pub ratio: Option<f64>,
    pub lo: Option<f64>,
    pub hi: Option<f64>,
    pub curves_cross: bool,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FragilityReport {
    /// The intensity measure's label for axes and tables, e.g. "PGA*" (set by the engine).
    #[serde(default)]
    pub im: String,
    /// The damage measure's label, e.g. "θmax/α" (set by the engine).
    #[serde(default)]
    pub damage_measure: String,
    pub curves: Vec<Curve>,
    pub ratios: Vec<MedianRatio>,
    /// Bootstrap resamples and the confidence level of the intervals.
    pub bootstrap: usize,
    pub confidence: f64,
    pub seed: u64,
    /// A study with uncertain parameters: what was drawn and how, one line (set by the
    /// engine, report/stripes.rs); empty otherwise.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub uncertainty: String,
}

impl FragilityReport {
    /// What the median is a value of: the intensity measure's short name ("PGA*" of
    /// "PGA* = PGA/(g·tanα)", "PGA" of "PGA (g)"), "IM" when the report names none.
    pub fn im_name(&self) -> &str {
        let short = self.im.split([' ', '=']).next().unwrap_or("");
        if short.is_empty() { "IM" } else { short }
    }

    /// The ratio for a curve's variant and damage state against the bare variant, if any.
    pub fn ratio_of(&self, curve: &Curve) -> Option<&MedianRatio> {
        self.ratios
            .iter()
            .find(|r| r.a == curve.variant && r.damage_state == curve.damage_state)
    }
}

/// Variants in order of first appearance, and each observation's variant index.
fn index_variants<'a>(variants: impl Iterator<Item = &'a Variant>) -> (Vec<Variant>, Vec<usize>) {
    let mut list: Vec<Variant> = Vec::new();
    let mut index = Vec::new();
    for v in variants {
        let i = match list.iter().position(|u| u == v) {
            Some(i) => i,
            None => {
                list.push(v.clone());
                list.len() - 1
            }
        };
        index.push(i);
    }
    (list, index)
}

/// Records in sorted order, and each observation's record index.
fn index_records<'a>(records: impl Iterator<Item = &'a str> + Clone) -> (Vec<String>, Vec<usize>) {
    let mut list: Vec<String> = records.clone().map(str::to_string).collect();
    list.sort();
    list.dedup();
    let index = records
        .map(|r| list.binary_search_by(|x| x.as_str().cmp(r)).unwrap_or(0))
        .collect();
    (list, index)
}

fn range(values: impl Iterator<Item = f64>) -> Option<[f64; 2]> {
    values.fold(None, |r, v| {
        let [lo, hi] = r.unwrap_or([v, v]);
        Some([lo.min(v), hi.max(v)])
    })
}

/// The fitted quantities a bootstrap replicate yields for one curve.
type Fit = Result<Lognormal, FitStatus>;

/// One curve's data as a function of record weights (how often each record is drawn).
trait CurveData {
    fn fit(&self, weights: &[usize]) -> Fit;
}

/// Stripe data of one variant and damage state: per record, (stripe index, exceeded).
struct StripeData {
    ims: Vec<f64>,
    by_record: Vec<Vec<(usize, bool)>>,
}

impl StripeData {
    fn points(&self, weights: &[usize]) -> Vec<StripePoint> {
        let mut points: Vec<StripePoint> = self
            .ims
            .iter()
            .map(|&im| StripePoint {
                im,
                n: 0,
                exceed: 0,
            })
            .collect();
        for (obs, &w) in self.by_record.iter().zip(weights) {
            for &(j, exceeded) in obs {
                points[j].n += w;
                points[j].exceed += w * usize::from(exceeded);
            }
        }
        points
    }
}

impl CurveData for StripeData {
    fn fit(&self, weights: &[usize]) -> Fit {
        fit_binomial_mle(&self.points(weights))
    }
}

/// IDA data of one variant and damage state: per record, capacity (Ok) or top IM (Err).
struct IdaData {
    by_record: Vec<Option<Result<f64, f64>>>,
}

impl CurveData for IdaData {
    fn fit(&self, weights: &[usize]) -> Fit {
        let (mut caps, mut tops) = (Vec::new(), Vec::new());
        for (obs, &w) in self.by_record.iter().zip(weights) {
            for _ in 0..w {
                match obs {
                    Some(Ok(c)) => caps.push(*c),
                    Some(Err(t)) => tops.push(*t),
                    None => {}
                }
            }
        }
        fit_censored(&caps, &tops)
    }
}

/// A curve before fitting: what it is and its data.
struct Pending {
    curve: Curve,
    data: Box<dyn CurveData>,
}

/// Fits every curve on all records, bootstraps over records (the same resample for every
/// curve, so ratios are paired) and assembles the report.
fn finish(mut pending: Vec<Pending>, n_records: usize, opts: &FragilityOptions) -> FragilityReport {
    let all = vec![1; n_records];
    let full: Vec<Fit> = pending.iter().map(|p| p.data.fit(&all)).collect();
    let mut resampler = Resampler::new(opts.seed, n_records);
    let mut replicates: Vec<Vec<Fit>> = vec![Vec::with_capacity(opts.bootstrap); pending.len()];
    for _ in 0..opts.bootstrap {
        let weights = resampler.draw();
        for (p, reps) in pending.iter().zip(&mut replicates) {
            reps.push(p.data.fit(&weights));
        }
    }
    for ((p, fit), reps) in pending.iter_mut().zip(&full).zip(&replicates) {
        let c = &mut p.curve;
        match fit {
            Ok(f) => {
                c.status = FitStatus::Fitted;
                c.median = Some(f.median);
                c.beta = Some(f.beta);
                let ok: Vec<&Lognormal> = reps.iter().filter_map(|r| r.as_ref().ok()).collect();
                c.bootstrap_degenerate = reps.len() - ok.len();
                let medians: Vec<f64> = ok.iter().map(|f| f.median).collect();
                let betas: Vec<f64> = ok.iter().map(|f| f.beta).collect();
                [c.median_lo, c.median_hi] = interval(&medians, opts.confidence);
                [c.beta_lo, c.beta_hi] = interval(&betas, opts.confidence);
                c.resamples = reps
                    .iter()
                    .map(|r| r.as_ref().ok().map(|f| [f.median, f.beta]))
                    .collect();
            }
            Err(status) => c.status = *status,
        }
    }
    let ratios = ratios(&pending, &full, &replicates, opts.confidence);
    FragilityReport {
        im: String::new(),
        damage_measure: String::new(),
        curves: pending.into_iter().map(|p| p.curve).collect(),
        ratios,
        bootstrap: opts.bootstrap,
        confidence: opts.confidence,
        seed: opts.seed,
        uncertainty: String::new(),
    }
}

/// Each protected variant's median over the bare variant's with the same parameters, per
/// damage state; the interval from the paired replicates where both fits exist.
fn ratios(
    pending: &[Pending],
    full: &[Fit],
    replicates: &[Vec<Fit>],
    confidence: f64,
) -> Vec<MedianRatio> {
    let mut out = Vec::new();
    for (i, p) in pending.iter().enumerate() {
        let c = &p.curve;
        if c.variant.is_bare() {
            continue;
        }
        let bare = pending.iter().position(|q| {
            q.curve.variant.is_bare()
                && q.curve.variant.params == c.variant.params
                && q.curve.damage_state == c.damage_state
                && q.curve.method == c.method
        });
        let Some(j) = bare else { continue };
        let paired: Vec<f64> = replicates[i]
            .iter()
            .zip(&replicates[j])
            .filter_map(|(a, b)| Some(a.as_ref().ok()?.median / b.as_ref().ok()?.median))
            .collect();
        let (fa, fb) = (full[i].as_ref().ok(), full[j].as_ref().ok());
        let [lo, hi] = match (fa, fb) {
            (Some(_), Some(_)) => interval(&paired, confidence),
            _ => [None, None],
        };
        let span = range(
            c.im_range
                .into_iter()
                .chain(pending[j].curve.im_range)
                .flatten(),
        );
        out.push(MedianRatio {
            a: c.variant.clone(),
            b: pending[j].curve.variant.clone(),
            damage_state: c.damage_state,
            ratio: fa.zip(fb).map(|(a, b)| a.median / b.median),
            lo,
            hi,
            curves_cross: fa
                .zip(fb)
                .zip(span)
                .is_some_and(|((a, b), span)| curves_cross(a, b, span)),
        });
    }
    out
}

/// Whether two lognormal curves cross strictly inside the IM range: Φ(ln(x/θa)/βa) and
/// Φ(ln(x/θb)/βb) are equal where ln x = (βb ln θa − βa ln θb)/(βb − βa).
pub fn curves_cross(a: &Lognormal, b: &Lognormal, [lo, hi]: [f64; 2]) -> bool {
    if a.beta == b.beta {
        return false;
    }
    let ln_x = (b.beta * a.median.ln() - a.beta * b.median.ln()) / (b.beta - a.beta);
    lo.ln() < ln_x && ln_x < hi.ln()
}

fn empty_curve(variant: &Variant, damage_state: f64, method: Method) -> Curve {
    Curve {
        variant: variant.clone(),
        damage_state,
        method,
        status: FitStatus::NoData,
        median: None,
        beta: None,
        median_lo: None,
        median_hi: None,
        beta_lo: None,
        beta_hi: None,
        n_records: 0,
        n_stripes: 0,
        stripes: Vec::new(),
        im_range: None,
        bootstrap_degenerate: 0,
        n_censored: 0,
        resurrections: 0,
        capacities: Vec::new(),
        resamples: Vec::new(),
        median_records: None,
        beta_records: None,
    }
}

/// Multiple-stripe analysis: one curve per variant (in order of appearance) and damage state
/// (in the options' order). Observations with a non-finite response that did not overturn are
/// left out.
pub fn analyse_stripes(obs: &[StripeObservation], opts: &FragilityOptions) -> FragilityReport {
    let (variants, vix) = index_variants(obs.iter().map(|o| &o.variant));
    let (records, rix) = index_records(obs.iter().map(|o| o.record.as_str()));
    let mut pending = Vec::new();
    for (v, variant) in variants.iter().enumerate() {
        let mine: Vec<usize> = (0..obs.len()).filter(|&i| vix[i] == v).collect();
        let mut ims: Vec<f64> = mine.iter().map(|&i| obs[i].im).collect();
        ims.sort_by(f64::total_cmp);
        ims.dedup();
        for &ds in &opts.damage_states {
            let mut by_record = vec![Vec::new(); records.len()];
            for &i in &mine {
                if let Some(exceeded) = obs[i].exceeds(ds) {
                    let j = ims.partition_point(|&x| x < obs[i].im);
                    by_record[rix[i]].push((j, exceeded));
                }
            }
            let data = StripeData {
                ims: ims.clone(),
                by_record,
            };
            let mut curve = empty_curve(variant, ds, Method::Stripes);
            curve.stripes = merge_stripes(&data.points(&vec![1; records.len()]));
            curve.n_stripes = curve.stripes.len();
            curve.n_records = data.by_record.iter().filter(|o| !o.is_empty()).count();
            curve.im_range = range(curve.stripes.iter().map(|p| p.im));
            pending.push(Pending {
                curve,
                data: Box::new(data),
            });
        }
    }
    finish(pending, records.len(), opts)
}

/// Incremental dynamic analysis: one curve per variant and damage state found in the
/// observations, fitted to first-capacity IMs with records that never reached the state
/// censored at their top IM. `opts.damage_states` orders the curves (states not listed there
/// follow in order of appearance).
pub fn analyse_ida(obs: &[IdaObservation], opts: &FragilityOptions) -> FragilityReport {
    let (variants, vix) = index_variants(obs.iter().map(|o| &o.variant));
    let (records, rix) = index_records(obs.iter().map(|o| o.record.as_str()));
    let mut states: Vec<f64> = opts.damage_states.clone();
    for o in obs {
        if !states.contains(&o.damage_state) {
            states.push(o.damage_state);
        }
    }
    let mut pending = Vec::new();
    for (v, variant) in variants.iter().enumerate() {
        for &ds in &states {
            let mine: Vec<usize> = (0..obs.len())
                .filter(|&i| vix[i] == v && obs[i].damage_state == ds)
                .collect();
            if mine.is_empty() {
                continue;
            }
            let mut by_record = vec![None; records.len()];
            let mut curve = empty_curve(variant, ds, Method::Ida);
            for &i in &mine {
                let o = &obs[i];
                by_record[rix[i]] = Some(o.capacity_im.ok_or(o.top_im));
                curve.resurrections += o.resurrections.len();
            }
            curve.n_records = by_record.iter().flatten().count();
            curve.n_censored = by_record.iter().flatten().filter(|c| c.is_err()).count();
            let mut caps: Vec<f64> = by_record.iter().flatten().filter_map(|c| c.ok()).collect();
            caps.sort_by(f64::total_cmp);
            curve.im_range = range(by_record.iter().flatten().map(|c| c.unwrap_or_else(|t| t)));
            curve.capacities = caps;
            pending.push(Pending {
                curve,
                data: Box::new(IdaData { by_record }),
            });
        }
    }
    finish(pending, records.len(), opts)
}
