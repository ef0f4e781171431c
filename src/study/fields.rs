//! What each study field means, in one place next to the schema: one line of help per field,
//! the optional fields that serialisation leaves out when unset (so an editor can offer them),
//! and the fields that take a grid of values. The TUI reads these; a test below checks them
//! against the schema (every field of every shipped study has help, every optional field's
//! starting text parses where it belongs).

/// An optional field that is omitted from a saved study when unset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OptionalField {
    /// The struct or variant that has the field (`study` for the top level).
    pub owner: &'static str,
    pub field: &'static str,
    /// A valid value to start editing from.
    pub template: &'static str,
}

const fn optional(
    owner: &'static str,
    field: &'static str,
    template: &'static str,
) -> OptionalField {
    OptionalField {
        owner,
        field,
        template,
    }
}

pub const OPTIONAL_FIELDS: &[OptionalField] = &[
    optional("study", "description", "\"\""),
    optional("study", "map", "(x: frequency, y: amplitude)"),
    optional(
        "study",
        "fragility",
        "(damage_states: levels([0.2, 0.5, 1.0]))",
    ),
    optional(
        "study",
        "risk",
        "(hazard: \"hazards/illustrative_pga.csv\", years: 50.0)",
    ),
    optional("pulse", "vertical", "ratio(0.67)"),
    optional("record", "vertical", "ratio(0.67)"),
    optional(
        "study",
        "uncertain",
        "(seed: 1, alpha: normal(mean: 0.2, sd: 0.01))",
    ),
    optional("rigid", "size", "1.0"),
    optional("rigid", "p", "2.0"),
    optional("flexible", "omega_n", "10.0"),
    optional("flexible", "omega_ratio", "5.0"),
    optional("inerter", "label", "\"\""),
    optional("sequential", "label", "\"\""),
    optional("mechanistic", "k_theta", "[1000.0, 10000.0]"),
    optional("mechanistic", "clutch_frequency_ratio", "25.0"),
    optional("mechanistic", "cbar", "1.0"),
    optional("mechanistic", "xi_theta", "0.1"),
    optional("mechanistic", "label", "\"\""),
    optional("flywheel", "k_theta", "[1000.0, 10000.0]"),
    optional("flywheel", "clutch_frequency_ratio", "25.0"),
    optional("flywheel", "cbar", "1.0"),
    optional("flywheel", "xi_theta", "0.1"),
];

/// Pairs of fields of which a study sets one: the editor offers the other in their place.
pub const EXCLUSIVE_FIELDS: &[(&str, &str)] = &[
    ("p", "size"),
    ("omega_n", "omega_ratio"),
    ("k_theta", "clutch_frequency_ratio"),
    ("cbar", "xi_theta"),
];

/// The optional fields of a struct or variant (`study` for the top level).
pub fn optional_fields(owner: &str) -> impl Iterator<Item = &'static OptionalField> + '_ {
    OPTIONAL_FIELDS.iter().filter(move |f| f.owner == owner)
}

/// One line of help per study field, by field name.
const FIELD_HELP: &[(&str, &str)] = &[
    ("version", "schema version of the study file (1)"),
    ("name", "study name; `rocklab run` writes to out/<name>"),
    ("description", "free text"),
    (
        "structure",
        "rigid(p or size, alpha, mass, form) or flexible(r0, alpha, xi, omega_n or omega_ratio, mass)",
    ),
    ("form", "exact or slender (small-α) equations"),
    (
        "devices",
        "variants: none, inerter(sigma, coupling), sequential(sigma), mechanistic(sigma, …); a: duplicate",
    ),
    (
        "coupling",
        "how the single inerter is attached: rigid, or flywheel(cbar: 1.0, …), a flywheel \
         behind a spring (k_theta or clutch_frequency_ratio; cbar or xi_theta; rho)",
    ),
    (
        "reset",
        "re-engagement reset with play: paper or strict (never: no reset, the paper's §4 counterfactual)",
    ),
    ("label", "name of the variant in results"),
    (
        "excitation",
        "pulse(shape, amplitude, frequency) or record(names: [\"…\"], scale: …)",
    ),
    (
        "shape",
        "sine, cosine, ricker, …, or a list [sine, ricker]: each shape is an axis value (its own \
         spectra, selected by shape: ricker)",
    ),
    (
        "vertical",
        "vertical ground motion, positive up: ratio(r) (r × the scaled horizontal), \
         constant(c) (c·g), record(\"FILE\") (× the horizontal record's factor) or \
         pulse(shape, amplitude, frequency) (absolute)",
    ),
    (
        "amplitude",
        "alpha_ratio(A/(g·α)), tan_alpha_ratio(A/(g·tanα)) or g(A/g)",
    ),
    ("frequency", "ratio(ωg/p) or rad_per_sec(ωg)"),
    ("names", "ground-motion records"),
    (
        "suite",
        "a record suite: (name: far_field | near_field_pulse | near_field_no_pulse | near_field | table1, \
         optional component: a | b, records: [ids], pulse: true | false)",
    ),
    (
        "component",
        "only this component of every suite record: a or b",
    ),
    (
        "records",
        "only these record ids of the suite (1-based, as index.csv numbers them)",
    ),
    (
        "pulse",
        "only pulse-like (true) or no-pulse (false) near-field records",
    ),
    (
        "scale",
        "record scale factors, or the target intensities of scale_to",
    ),
    (
        "scale_to",
        "what scale means: factor, pga (g), pgv (m/s), pga_star (PGA/(g·tanα)), \
         pgv_star (PGV·p/(g·tanα)), fema (factor × FEMA P695 normalisation), \
         sa(period: T) (Sa(T) in g, ξ = 0.05 unless damping: is given), \
         sa_avg(from: T1, to: T2) (geometric mean of Sa, g) or arias (m/s)",
    ),
    ("baseline", "baseline-correct the records first"),
    (
        "fragility",
        "fragility analysis: the record `scale` values are the stripes of `scale_to`'s IM; \
         (damage_states, measure, bootstrap, seed, confidence)",
    ),
    (
        "damage_states",
        "levels([…]) or twelve (0.01 … 1): thresholds of the damage measure",
    ),
    (
        "risk",
        "seismic risk at a site from the fragility curves: (hazard: \"FILE\", years, mce, \
         beta_total); writes risk.csv, risk.json and risk.svg",
    ),
    (
        "hazard",
        "the site's hazard curve CSV (header pga,annual_rate or pgv,annual_rate), relative to \
         the study file's directory",
    ),
    (
        "years",
        "years of exposure for p_years = 1 − exp(−MAF · years)",
    ),
    (
        "mce",
        "FEMA P695 margins: the MCE intensity in the hazard's IM (with beta_total)",
    ),
    (
        "beta_total",
        "FEMA P695 margins: the total collapse uncertainty β_TOT (Table 7-2)",
    ),
    (
        "measure",
        "damage measure: peak_rotation_ratio (θmax/α), or for flexible structures peak_drift or peak_deformation",
    ),
    (
        "bootstrap",
        "bootstrap resamples over records for the confidence intervals: 0 (none) or at least 200",
    ),
    (
        "seed",
        "seed of the bootstrap (fragility) or of the draws (uncertain): reruns agree",
    ),
    (
        "uncertain",
        "uncertain parameters of a fragility study, drawn per record × stripe: (seed, sampling, \
         draws, then any of alpha, size, p, restitution, k_theta, clutch_frequency_ratio, cbar, \
         xi_theta: normal(mean, sd), lognormal(median, beta) or uniform(lo, hi))",
    ),
    (
        "sampling",
        "latin_hypercube (one draw in each of N equal-probability strata per parameter) or \
         monte_carlo (independent draws)",
    ),
    (
        "draws",
        "per_record_stripe: one draw per record × stripe, shared by the device variants (an \
         IDA: per record)",
    ),
    (
        "mean",
        "a normal distribution's mean, in the parameter's unit",
    ),
    (
        "sd",
        "a normal distribution's standard deviation (≥ 0), in the parameter's unit",
    ),
    ("median", "a lognormal distribution's median (> 0)"),
    (
        "beta",
        "a lognormal distribution's dispersion: the standard deviation of ln x (≥ 0)",
    ),
    ("lo", "a uniform distribution's lower end"),
    ("hi", "a uniform distribution's upper end"),
    (
        "confidence",
        "two-sided confidence level of the intervals (0.9: 5th–95th percentiles)",
    ),
    (
        "tail",
        "each scene lasts its record's length plus this many seconds (then no duration)",
    ),
    (
        "kinks",
        "whether the integrator stops at every record sample",
    ),
    (
        "spectrum",
        "x axis of the spectra: frequency, amplitude, scale, alpha, size, p, …",
    ),
    (
        "map",
        "overturning map over two axes: (x: frequency, y: amplitude)",
    ),
    (
        "impact",
        "housner() (Housner's r), housner(restitution: r) or dirac(width: n)",
    ),
    (
        "refine",
        "adaptive map: (levels: n) runs a coarse lattice every 2^n values, then refines only \
         where verdicts disagree; islands narrower than 2^n steps can be missed",
    ),
    (
        "levels",
        "refinement levels of an adaptive map (1–8): coarse lattice every 2^levels values",
    ),
    (
        "design",
        "the least device parameter meeting a target at every excitation point (rocklab design)",
    ),
    (
        "parameter",
        "parameter to size: sigma, cbar, xi_theta, friction, k_theta or clutch_frequency_ratio",
    ),
    (
        "bracket",
        "search bracket (low, high) of the sized parameter",
    ),
    (
        "resolution",
        "design: relative resolution of the answer (0.01: the bracket ends within 1 % of it); \
         fragility ida: the widest final bracket of a capacity, in IM units",
    ),
    (
        "target",
        "limit(quantity: q, max: v) (and no overturning) or no_overturning, at every excitation \
         point; in a fragility study fragility(state: d, median_at_least: x) or \
         fragility(state: d, at: x, exceedance_at_most: p), fitted over every record and stripe; \
         with a risk section risk(state: d, maf_at_most: x) or risk(state: d, p_years_at_most: p)",
    ),
    ("quantity", "the response quantity the target limits"),
    ("max", "the response limit of the target"),
    (
        "state",
        "fragility target: the damage state, by its threshold in fragility.damage_states",
    ),
    (
        "median_at_least",
        "fragility target: the fitted median intensity (scale_to's measure) must be at least this",
    ),
    (
        "at",
        "fragility target: the intensity the exceedance probability is read at",
    ),
    (
        "maf_at_most",
        "risk target: most mean annual frequency (1/yr) of reaching the state at the risk's site",
    ),
    (
        "p_years_at_most",
        "risk target: most probability of reaching the state in the risk section's years",
    ),
    (
        "exceedance_at_most",
        "fragility target: most probability of reaching the state at `at` (0 < p < 1)",
    ),
    (
        "over",
        "excitation axes the target holds over: frequency, amplitude, record, scale",
    ),
    (
        "verify",
        "values checked above the answer for a non-monotone failure (the bracket's top always)",
    ),
    ("x", "the map's x axis"),
    ("y", "the map's y axis"),
    ("from", "first value of a range"),
    ("to", "last value of a range (included)"),
    ("steps", "number of values in a range, both ends included"),
    ("log", "geometric instead of even spacing of a range"),
    (
        "restitution",
        "coefficient of restitution r (left out: Housner's r from the geometry; 1: elastic)",
    ),
    ("width", "width n of the Gaussian impact moment (rad)"),
    (
        "duration",
        "simulated time per scene (s); not with a record excitation's tail",
    ),
    ("rtol", "integrator relative tolerance"),
    (
        "method",
        "integrator: auto (by rtol), dp54 or dop853; in a fragility section: stripes (every \
         record at every scale value) or ida(resolution: r) (hunt up the scale values per \
         record, bisect each state's first exceedance to r, IM units)",
    ),
    (
        "stop_when_settled",
        "end a scene once the structure has settled after the motion",
    ),
    (
        "exact_contact",
        "advance full contact of a flexible structure with a linear device in closed form",
    ),
];

/// The quantities' names from their table, with the one that needs a rigid block.
static QUANTITIES_HELP: std::sync::LazyLock<String> = std::sync::LazyLock::new(|| {
    let names: Vec<&str> = super::Quantity::ALL.iter().map(|q| q.name()).collect();
    let angular = super::Quantity::PeakAngularAcceleration.info();
    format!("{} ({}: {})", names.join(", "), angular.name, angular.help)
});

/// A field the study reader fills in when a study leaves it out, and with what, as study
/// text. The text comes from the reader's own defaults (the functions its `serde(default)`
/// attributes name, `ClutchStiffness::default()`, …), so the help cannot name another value.
pub struct FieldDefault {
    /// The struct or variant that has the field (`study` for the top level).
    pub owner: &'static str,
    pub field: &'static str,
    pub text: fn() -> String,
}

/// A value as compact study text.
fn ron_text<T: serde::Serialize>(value: T) -> String {
    ron::to_string(&value).expect("defaults serialise")
}

const fn default(owner: &'static str, field: &'static str, text: fn() -> String) -> FieldDefault {
    FieldDefault { owner, field, text }
}

pub const FIELD_DEFAULTS: &[FieldDefault] = &[
    default("study", "quantities", || {
        ron_text(super::default_quantities())
    }),
    default("study", "spectrum", || {
        ron_text(super::default_spectrum_axis())
    }),
    default("study", "impact", || {
        match crate::scene::Impact::default() {
            // An option left out reads as None: the study text leaves it out too.
            crate::scene::Impact::Housner { restitution: None } => "housner()".into(),
            other => ron_text(other),
        }
    }),
    default("study", "rtol", || ron_text(crate::scene::default_rtol())),
    default("study", "stop_when_settled", || ron_text(super::yes())),
    default("study", "exact_contact", || {
        ron_text(crate::scene::default_closed_form_contact())
    }),
    default("study", "method", || {
        ron_text(crate::scene::Method::default())
    }),
    default("rigid", "mass", || ron_text(super::unit_values())),
    default("rigid", "form", || ron_text(crate::scene::Form::default())),
    default("flexible", "mass", || ron_text(super::unit_values())),
    default("inerter", "coupling", || ron_text(super::rigid_coupling())),
    default("mechanistic", "clutch_frequency_ratio", || {
        ron_text(super::default_clutch_frequency_ratio())
    }),
    default("mechanistic", "cbar", || ron_text(super::default_cbar())),
    default("mechanistic", "friction", || ron_text(super::zero_values())),
    default("mechanistic", "eta", || {
        ron_text(super::default_eta_values())
    }),
    default("mechanistic", "play", || ron_text(super::zero_values())),
    default("mechanistic", "epsilon", || {
        ron_text(super::default_epsilon_values())
    }),
    default("mechanistic", "rho", || {
        ron_text(super::default_rho_values())
    }),
    default("mechanistic", "reset", || {
        ron_text(crate::scene::ResetRule::default())
    }),
    default("flywheel", "clutch_frequency_ratio", || {
        ron_text(super::default_clutch_frequency_ratio())
    }),
    default("flywheel", "cbar", || ron_text(super::default_cbar())),
    default("flywheel", "rho", || ron_text(super::default_rho_values())),
    default("record", "scale", || ron_text(super::unit_values())),
    default("record", "scale_to", || {
        ron_text(super::RecordScaling::default())
    }),
    default("record", "baseline", || ron_text(bool::default())),
    default("record", "kinks", || {
        ron_text(crate::excitation::KinkPolicy::default())
    }),
    default("design", "resolution", || {
        ron_text(super::design::default_resolution())
    }),
    default("design", "verify", || {
        ron_text(super::design::default_verify())
    }),
    default("fragility", "method", || {
        ron_text(super::fragility::Method::default())
    }),
    default("fragility", "damage_states", || {
        ron_text(super::fragility::DamageStates::default())
    }),
    default("fragility", "measure", || {
        ron_text(super::fragility::default_measure())
    }),
    default("fragility", "bootstrap", || {
        ron_text(super::fragility::default_bootstrap())
    }),
    default("fragility", "seed", || {
        ron_text(super::fragility::default_seed())
    }),
    default("fragility", "confidence", || {
        ron_text(super::fragility::default_confidence())
    }),
];

/// The defaults of a field, by name: `X`, or `X in owner, Y in other` where its owners differ.
pub(super) fn default_note(field: &str) -> Option<String> {
    let found: Vec<(&str, String)> = FIELD_DEFAULTS
        .iter()
        .filter(|d| d.field == field)
        .map(|d| (d.owner, (d.text)()))
        .collect();
    let first = &found.first()?.1;
    if found.iter().all(|(_, text)| text == first) {
        return Some(first.clone());
    }
    let each: Vec<String> = found.iter().map(|(o, t)| format!("{t} in {o}")).collect();
    Some(each.join(", "))
}

/// Help for a study field, by name (list elements have none), with the default the reader
/// applies when the field is left out.
pub fn field_help(field: &str) -> Option<String> {
    let help = if field == "quantities" {
        QUANTITIES_HELP.as_str()
    } else {
        // A grid parameter's help is its row of the parameter table.
        FIELD_HELP
            .iter()
            .find(|(f, _)| *f == field)
            .map(|(_, h)| *h)
            .or_else(|| super::Param::from_field(field).map(|p| p.info().help))
            .filter(|h| !h.is_empty())?
    };
    Some(match default_note(field) {
        Some(note) => format!("{help} (default {note})"),
        None => help.to_string(),
    })
}

/// Fields that take a value, a list or a range ([`super::Values`] or an axis of them).
const GRID_FIELDS: &[&str] = &[
    "p",
    "size",
    "alpha",
    "mass",
    "r0",
    "xi",
    "omega_n",
    "omega_ratio",
    "sigma",
    "k_theta",
    "clutch_frequency_ratio",
    "cbar",
    "xi_theta",
    "friction",
    "eta",
    "play",
    "epsilon",
    "rho",
    "amplitude",
    "frequency",
    "scale",
];

/// Whether a field takes a grid: a value, a list or a range.
pub fn takes_grid(field: &str) -> bool {
    GRID_FIELDS.contains(&field)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::Study;

    /// Field names of a RON document (struct fields at any depth).
    fn field_names(value: &ron::Value, out: &mut Vec<String>) {
        match value {
            ron::Value::Map(map) => {
                for (k, v) in map.iter() {
                    if let ron::Value::String(name) = k {
                        out.push(name.clone());
                    }
                    field_names(v, out);
                }
            }
            ron::Value::Seq(items) => items.iter().for_each(|v| field_names(v, out)),
            ron::Value::Option(Some(v)) => field_names(v, out),
            _ => {}
        }
    }

    #[test]
    fn every_field_of_every_shipped_study_has_help() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/studies");
        let (mut checked, mut missing) = (0, Vec::new());
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_none_or(|e| e != "ron") {
                continue;
            }
            // Saved as the workbench saves it, so that defaulted fields appear too.
            let study = Study::load(&path).unwrap();
            let value: ron::Value = ron::from_str(&study.to_ron_string()).unwrap();
            let mut names = Vec::new();
            field_names(&value, &mut names);
            for name in names {
                if field_help(&name).is_none() && !missing.contains(&name) {
                    missing.push(name);
                }
                checked += 1;
            }
        }
        assert!(missing.is_empty(), "fields without help: {missing:?}");
        assert!(checked > 50, "only {checked} fields checked");
    }

    #[test]
    fn every_optional_field_is_omitted_when_unset_and_accepts_its_template() {
        // A small study with one occurrence of the owner, `set` inside it.
        let doc = |owner: &str, set: &str| -> String {
            let rigid = "rigid(alpha: 0.2)".to_string();
            let (top, structure, device) = match owner {
                "study" => (set, rigid, "none".to_string()),
                "rigid" => ("", format!("rigid(alpha: 0.2, {set})"), "none".into()),
                "flexible" => (
                    "",
                    format!("flexible(r0: 1.0, alpha: 0.2, xi: 0.05, {set})"),
                    "none".into(),
                ),
                "flywheel" => (
                    "",
                    rigid,
                    format!("inerter(sigma: 1.0, coupling: flywheel({set}))"),
                ),
                "pulse" | "record" => ("", rigid, "none".to_string()),
                device => ("", rigid, format!("{device}(sigma: 1.0, {set})")),
            };
            let excitation = match owner {
                "pulse" => format!(
                    "pulse(shape: sine, amplitude: alpha_ratio(1.5), frequency: ratio(2.0), {set})"
                ),
                "record" => format!("record(names: [\"x\"], {set})"),
                _ => "pulse(shape: sine, amplitude: alpha_ratio(1.5), frequency: ratio(2.0))"
                    .to_string(),
            };
            format!(
                "(version: 1, name: \"t\", structure: {structure}, devices: [{device}], \
                 excitation: {excitation}, duration: 1.0, {top})"
            )
        };
        let saved = |doc: &str| -> String {
            Study::parse_ron(doc, "test")
                .unwrap_or_else(|e| panic!("does not parse: {e}\n{doc}"))
                .to_ron_string()
        };
        for f in OPTIONAL_FIELDS {
            assert!(field_help(f.field).is_some(), "{f:?} has no help");
            let unset = saved(&doc(f.owner, ""));
            assert!(!has_key(&unset, f.field), "{f:?} is saved unset:\n{unset}");
            // An empty text is left out like an unset one: set a non-empty one.
            let value = if f.template == "\"\"" {
                "\"x\""
            } else {
                f.template
            };
            let set = saved(&doc(f.owner, &format!("{}: {value}", f.field)));
            assert!(
                has_key(&set, f.field),
                "{f:?} is not saved when set:\n{set}"
            );
        }
    }

    /// A small study with one occurrence of `owner`, `set` (a `field: value` or nothing)
    /// inside it; `field` is the field set, which the template does not write itself.
    fn study_with(owner: &str, field: &str, set: &str) -> String {
        let mut top = String::new();
        let mut structure = "rigid(alpha: 0.2, size: 1.0)".to_string();
        let mut device = "none".to_string();
        let mut excitation =
            "pulse(shape: sine, amplitude: alpha_ratio(1.5), frequency: ratio(2.0))".to_string();
        match owner {
            "study" => top = set.to_string(),
            "rigid" => structure = format!("rigid(alpha: 0.2, size: 1.0, {set})"),
            "flexible" => {
                structure =
                    format!("flexible(r0: 1.0, alpha: 0.2, xi: 0.05, omega_ratio: 5.0, {set})")
            }
            "inerter" | "mechanistic" => device = format!("{owner}(sigma: 0.5, {set})"),
            "flywheel" => device = format!("inerter(sigma: 0.5, coupling: flywheel({set}))"),
            "record" => excitation = format!("record(names: [\"x\"], {set})"),
            "design" => {
                top = format!(
                    "design: (parameter: sigma, bracket: (0.1, 2.0), target: no_overturning, {set})"
                )
            }
            "fragility" => {
                // A field of its own, so that the section is a struct, not `()`.
                let own = if field == "seed" {
                    "bootstrap: 10"
                } else {
                    "seed: 7"
                };
                top = format!("fragility: ({own}, {set})")
            }
            other => panic!("no study template for {other}"),
        }
        format!(
            "(version: 1, name: \"t\", structure: {structure}, devices: [{device}], \
             excitation: {excitation}, duration: 1.0, {top})"
        )
    }

    #[test]
    fn every_default_in_the_help_is_the_one_the_reader_applies() {
        let read = |doc: &str| {
            Study::parse_ron(doc, "test").unwrap_or_else(|e| panic!("does not parse: {e}\n{doc}"))
        };
        let scenes = |s: &Study| s.expand().map_err(|e| e.to_string());
        for d in FIELD_DEFAULTS {
            let text = (d.text)();
            let help = field_help(d.field).unwrap_or_else(|| panic!("{} has no help", d.field));
            assert!(
                help.contains(&format!("default {text}"))
                    || help.contains(&format!("{text} in {}", d.owner)),
                "{}: the help does not name the default {text}: {help}",
                d.field
            );
            // Left out, and written with the default the help names: the same study.
            let left_out = read(&study_with(d.owner, d.field, ""));
            let written = read(&study_with(
                d.owner,
                d.field,
                &format!("{}: {text}", d.field),
            ));
            assert_eq!(
                scenes(&left_out),
                scenes(&written),
                "{}.{}",
                d.owner,
                d.field
            );
            let optional = OPTIONAL_FIELDS
                .iter()
                .any(|o| o.owner == d.owner && o.field == d.field);
            if !optional {
                assert_eq!(left_out, written, "{}.{} = {text}", d.owner, d.field);
            }
        }
        // The check can fail: a clutch ratio other than the reader's is another study.
        let other = read(&study_with(
            "mechanistic",
            "",
            "clutch_frequency_ratio: 50.0",
        ));
        assert_ne!(
            scenes(&read(&study_with("mechanistic", "", ""))),
            scenes(&other)
        );
    }

    #[test]
    fn no_help_names_a_default_by_hand_or_speaks_rust() {
        for (field, help) in FIELD_HELP {
            assert!(
                !help.contains("default"),
                "{field}: a default written by hand: {help}"
            );
        }
        for (field, _) in FIELD_HELP {
            let help = field_help(field).unwrap();
            for rust in ["None", "Some(", "\"\""] {
                assert!(!help.contains(rust), "{field}: {help}");
            }
        }
        assert_eq!(
            field_help("clutch_frequency_ratio").unwrap(),
            "clutch frequency √(k/mr) as a multiple of p (default 25.0)"
        );
    }

    /// Whether `field` is used as a key (`field:`) in a RON text.
    fn has_key(text: &str, field: &str) -> bool {
        text.match_indices(&format!("{field}:")).any(|(i, _)| {
            !text[..i]
                .chars()
                .next_back()
                .is_some_and(|c| c.is_alphanumeric() || c == '_')
        })
    }
}
