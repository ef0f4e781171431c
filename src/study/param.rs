//! Study parameters: the one table of their identities (study field, display label, CSV/JSON
//! name, unit, help), beside [`crate::sim::Quantity`] and [`crate::sim::HistoryColumn`].
//! Coordinates, axis labels, group labels, CSV headers, design and IDA labels and the paper's
//! rows read a parameter's label from here: a misspelt parameter is a compile error
//! (`Param::Sigma`), and a label read back from a file that names none is `None` from
//! [`Param::from_label`], which its callers report.

/// Declares [`Param`], its [`Param::ALL`] list and [`Param::info`] from one table, so a
/// parameter is added in one line and the list cannot miss it.
macro_rules! params {
    ($($(#[$doc:meta])* $param:ident => ($field:literal, $label:literal, $name:literal, $unit:literal, $help:literal),)*) => {
        /// A parameter of a study's grid: its identity, whatever text shows it.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum Param {
            $($(#[$doc])* $param,)*
        }

        impl Param {
            /// Every parameter, in the table's order.
            pub const ALL: [Param; [$($label),*].len()] = [$(Param::$param),*];

            /// Everything the program says about this parameter: its row of the table.
            pub fn info(self) -> &'static ParamInfo {
                match self {
                    $(Param::$param => &ParamInfo {
                        field: $field,
                        label: $label,
                        name: $name,
                        unit: $unit,
                        help: $help,
                    },)*
                }
            }
        }
    };
}

/// What the program says about a parameter (one row of [`Param::info`]).
#[derive(Debug, PartialEq, Eq)]
pub struct ParamInfo {
    /// The study file's field (also the expansion's parameter id), e.g. `k_theta`.
    pub field: &'static str,
    /// Paper notation: coordinates, axes, group labels, e.g. `kθ`.
    pub label: &'static str,
    /// ASCII identifier in CSV headers and JSON (valid in MATLAB, pandas and R), e.g.
    /// `omega_c_over_p`.
    pub name: &'static str,
    /// Unit (empty for a ratio).
    pub unit: &'static str,
    /// One line on what it is, for help texts (empty where the field's help says it).
    pub help: &'static str,
}

params! {
    /// The pulse frequency as a multiple of p (`frequency: ratio(…)`).
    FrequencyRatio => ("frequency", "ωg/p", "omega_g_over_p", "", ""),
    /// The pulse frequency in rad/s (`frequency: rad_per_sec(…)`).
    Frequency => ("frequency", "ωg", "omega_g", "rad/s", ""),
    /// The pulse amplitude in g (`amplitude: g(…)`).
    AmplitudeG => ("amplitude", "A/g", "a_over_g", "", ""),
    /// The pulse amplitude as a multiple of g tan α.
    AmplitudeTanAlphaRatio => ("amplitude", "A/(g·tanα)", "a_over_g_tan_alpha", "", ""),
    /// The pulse amplitude as a multiple of g α.
    AmplitudeAlphaRatio => ("amplitude", "A/(g·α)", "a_over_g_alpha", "", ""),
    /// A record's scale factor.
    Scale => ("scale", "scale", "scale", "", ""),
    /// A record, by its index in the study's list of names.
    Record => ("record", "record", "record", "", ""),
    /// A pulse shape, by its index in the study's list of shapes.
    Shape => ("shape", "shape", "shape", "", ""),
    Size => ("size", "R", "size", "m", "half-diagonal R (m), instead of p"),
    P => ("p", "p", "p", "rad/s", "frequency parameter p (rad/s), instead of size"),
    Alpha => ("alpha", "α", "alpha", "rad", "slenderness α (rad), or in degrees as deg(10)"),
    Mass => ("mass", "m", "mass", "kg", "structure mass (kg)"),
    R0 => ("r0", "R0", "r0", "m", "R0 = √(B² + H²) (m)"),
    Xi => ("xi", "ξ", "xi", "", "column damping ratio ξ"),
    OmegaN => ("omega_n", "ωn", "omega_n", "rad/s", "column natural frequency ωn (rad/s)"),
    OmegaRatio => ("omega_ratio", "ωn/p", "omega_n_over_p", "", "column frequency as ωn/p"),
    Sigma => ("sigma", "σ", "sigma", "", "inerter mass ratio σ = mr/m"),
    KTheta => ("k_theta", "kθ", "k_theta", "N·m/rad", "clutch stiffness kθ (N·m/rad), instead of clutch_frequency_ratio"),
    ClutchFrequencyRatio => ("clutch_frequency_ratio", "ωc/p", "omega_c_over_p", "", "clutch frequency √(k/mr) as a multiple of p"),
    XiTheta => ("xi_theta", "ξθ", "xi_theta", "", "flywheel damping ratio ξθ, instead of cbar"),
    Cbar => ("cbar", "c̄", "cbar", "1/s", "flywheel damping c̄ = c/J (1/s), instead of xi_theta"),
    Friction => ("friction", "fμ", "f_mu", "mr·g", "dry friction fμ / (mr·g)"),
    Eta => ("eta", "η", "eta", "s/rad", "friction transition η (s/rad)"),
    Play => ("play", "up", "play", "m", "gear play up (m)"),
    Epsilon => ("epsilon", "ε", "epsilon", "", "clutch tanh smoothing ε (per rad)"),
    Rho => ("rho", "ρ", "rho", "m", "pinion radius ρ (m)"),
    /// The coefficient of restitution of a rigid block's impacts (`impact: housner(restitution: r)`);
    /// a grid parameter only as an uncertain one (study/uncertain).
    Restitution => ("restitution", "r", "restitution", "", "coefficient of restitution r"),
}

impl Param {
    /// Paper notation, as coordinates and group labels show it.
    pub fn label(self) -> &'static str {
        self.info().label
    }

    /// The study field it is read from.
    pub fn field(self) -> &'static str {
        self.info().field
    }

    /// The parameter a coordinate label names, or None for a label no parameter has.
    pub fn from_label(label: &str) -> Option<Param> {
        Param::ALL.into_iter().find(|p| p.label() == label)
    }

    /// The parameter whose help a study field shows (the first with that field).
    pub fn from_field(field: &str) -> Option<Param> {
        Param::ALL.into_iter().find(|p| p.field() == field)
    }

    /// What the reader puts in its field when the study leaves it out, if anything (from
    /// the one table of defaults, `study::fields`).
    pub fn default_note(self) -> Option<String> {
        super::fields::default_note(self.field())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    /// Labels and CSV names identify a parameter: no two share one (a coordinate read back
    /// from a file must name exactly one parameter).
    #[test]
    fn labels_and_names_are_unique() {
        let labels: HashSet<_> = Param::ALL.iter().map(|p| p.label()).collect();
        let names: HashSet<_> = Param::ALL.iter().map(|p| p.info().name).collect();
        assert_eq!(labels.len(), Param::ALL.len());
        assert_eq!(names.len(), Param::ALL.len());
        for p in Param::ALL {
            assert_eq!(Param::from_label(p.label()), Some(p));
            let name = p.info().name;
            assert!(
                name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'),
                "{name}"
            );
        }
        assert_eq!(Param::from_label("sigma"), None);
    }
}
