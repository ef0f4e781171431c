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
    ("p", "frequency parameter p (rad/s), instead of size"),
    ("size", "half-diagonal R (m), instead of p"),
    ("alpha", "slenderness α (rad), or in degrees as deg(10)"),
    ("mass", "structure mass (kg)"),
    ("form", "exact or slender (small-α) equations"),
    ("r0", "R0 = √(B² + H²) (m)"),
    ("xi", "column damping ratio ξ"),
    ("omega_n", "column natural frequency ωn (rad/s)"),
    ("omega_ratio", "column frequency as ωn/p"),
    (
        "devices",
        "variants: none, inerter(sigma, coupling), sequential(sigma), mechanistic(sigma, …); a: duplicate",
    ),
    ("sigma", "inerter mass ratio σ = mr/m"),
    ("coupling", "how the single inerter is attached"),
    (
        "k_theta",
        "clutch stiffness kθ (N·m/rad), instead of clutch_frequency_ratio",
    ),
    (
        "clutch_frequency_ratio",
        "clutch frequency √(k/mr) as a multiple of p (default 25)",
    ),
    (
        "cbar",
        "flywheel damping c̄ = c/J (1/s), instead of xi_theta (default 1)",
    ),
    ("xi_theta", "flywheel damping ratio ξθ, instead of cbar"),
    ("friction", "dry friction fμ / (mr·g)"),
    ("eta", "friction transition η (s/rad)"),
    ("play", "gear play up (m)"),
    ("epsilon", "clutch tanh smoothing ε (per rad)"),
    ("rho", "pinion radius ρ (m)"),
    ("reset", "re-engagement reset with play: paper or strict"),
    ("label", "name of the variant in results"),
    (
        "excitation",
        "pulse(shape, amplitude, frequency) or record(names: [\"…\"], scale: …)",
    ),
    ("shape", "sine, cosine, ricker, …"),
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
         pgv_star (PGV·p/(g·tanα)) or fema (factor × FEMA P695 normalisation)",
    ),
    ("baseline", "baseline-correct the records first"),
    (
        "fragility",
        "fragility analysis: the record `scale` values are the stripes of `scale_to`'s IM; \
         (damage_states, measure, bootstrap, seed, confidence)",
    ),
    (
        "damage_states",
        "levels([0.2, 0.5, 1.0]) (default) or twelve (0.01 … 1): thresholds of the damage measure",
    ),
    (
        "measure",
        "damage measure: peak_rotation_ratio (θmax/α), or for flexible structures peak_drift or peak_deformation",
    ),
    (
        "bootstrap",
        "bootstrap resamples over records for the confidence intervals (default 1000)",
    ),
    ("seed", "bootstrap seed (reruns agree)"),
    (
        "confidence",
        "confidence level of the intervals (default 0.9: 5th–95th percentiles)",
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
        "housner(restitution: None or r) or dirac(width: n)",
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
        "limit(quantity: q, max: v) (and no overturning) or no_overturning, at every excitation point",
    ),
    ("quantity", "the response quantity the target limits"),
    ("max", "the response limit of the target"),
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
        "coefficient of restitution r (None: Housner's r from the geometry; 1: elastic)",
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

/// Help for a study field, by name (list elements have none).
pub fn field_help(field: &str) -> Option<&'static str> {
    if field == "quantities" {
        return Some(QUANTITIES_HELP.as_str());
    }
    FIELD_HELP
        .iter()
        .find(|(f, _)| *f == field)
        .map(|(_, h)| *h)
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
                device => ("", rigid, format!("{device}(sigma: 1.0, {set})")),
            };
            format!(
                "(version: 1, name: \"t\", structure: {structure}, devices: [{device}], \
                 excitation: pulse(shape: sine, amplitude: alpha_ratio(1.5), \
                 frequency: ratio(2.0)), duration: 1.0, {top})"
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
