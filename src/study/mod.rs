//! Studies: a saved RON file that describes grids of scenes. A study expands into
//! [`ScenePoint`]s (a scene, its group label, its axis coordinates and a cache key); the sweep
//! runs them and the report aggregates them into spectra and overturning maps. No physics here:
//! every number that matters comes from `sim::run` on a scene.

// StudyError carries file, position, field and hint by value: errors are rare and built once,
// so their size does not matter.
#![allow(clippy::result_large_err)]

pub mod design;
mod error;
mod expand;
pub mod fields;
mod follow;
pub mod fragility;
mod param;
pub mod risk;
pub mod shapes;
mod strict;
pub(crate) mod suites;
pub mod uncertain;
mod values;
pub mod writer;

pub use crate::sim::{Quantity, QuantityInfo};
pub use error::StudyError;
pub use expand::{DeviceKind, Layout, MAX_SCENES, Parameter, Part, VariantLayout, device_label};
pub use param::{Param, ParamInfo};
pub use shapes::PulseShapes;
pub use strict::{ANGLE_FIELDS, parse_angle};
pub use values::Values;

use crate::excitation::KinkPolicy;
use crate::scene::{ClutchStiffness, Damping, Form, Impact, ResetRule, Scene};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::path::Path;

/// The schema version this build reads and writes.
pub const VERSION: u32 = 1;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Study {
    pub version: u32,
    pub name: String,
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub description: String,
    pub structure: StructureFamily,
    pub devices: Vec<DeviceVariant>,
    pub excitation: ExcitationFamily,
    /// Response quantities reported as spectra.
    #[serde(default = "default_quantities")]
    pub quantities: Vec<Quantity>,
    /// The x axis of the spectra (must vary in the study).
    #[serde(default = "default_spectrum_axis")]
    pub spectrum: Axis,
    /// An overturning map over two varying axes, e.g. (x: frequency, y: amplitude).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub map: Option<MapAxes>,
    #[serde(default)]
    pub impact: Impact,
    /// Simulated time per scene (s). Required, unless a record excitation's `tail` sets each
    /// scene's (then refused: it would be ignored).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration: Option<f64>,
    /// Integrator relative tolerance.
    #[serde(default = "crate::scene::default_rtol")]
    pub rtol: f64,
    /// End each scene once the ground has stopped and no peak can change any more (peaks are
    /// unchanged; end times and final energies differ). On by default: studies report peaks.
    #[serde(default = "yes")]
    pub stop_when_settled: bool,
    /// Advance full contact of a flexible structure with a linear device under a record in
    /// closed form (exact) instead of with the integrator; `false` forces the integrator.
    #[serde(
        default = "crate::scene::default_closed_form_contact",
        rename = "exact_contact"
    )]
    pub closed_form_contact: bool,
    /// Integrator method: `auto` (by rtol), `dp54` or `dop853`.
    #[serde(default, skip_serializing_if = "crate::scene::Method::is_auto")]
    pub method: crate::scene::Method,
    /// The inverse question: the least device parameter meeting a target (study/design.rs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub design: Option<design::Design>,
    /// Fragility analysis over the study's records and stripes (study/fragility.rs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fragility: Option<fragility::Fragility>,
    /// Seismic risk at a site from the fragility curves (study/risk.rs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub risk: Option<risk::Risk>,
    /// Uncertain parameters drawn per record × stripe of a fragility study
    /// (study/uncertain).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uncertain: Option<uncertain::Uncertain>,
}

pub(crate) fn yes() -> bool {
    true
}

pub(crate) fn default_quantities() -> Vec<Quantity> {
    vec![Quantity::PeakRotationRatio]
}

pub(crate) fn default_spectrum_axis() -> Axis {
    Axis::Frequency
}

pub(crate) fn unit_values() -> Values {
    Values::One(1.0)
}

pub(crate) fn zero_values() -> Values {
    Values::One(0.0)
}

pub(crate) fn default_eta_values() -> Values {
    Values::One(crate::scene::default_eta())
}

pub(crate) fn default_epsilon_values() -> Values {
    Values::One(crate::scene::default_epsilon())
}

pub(crate) fn default_rho_values() -> Values {
    Values::One(crate::scene::default_rho())
}

/// A family of structures; every parameter is a value, a list or a range.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum StructureFamily {
    /// Rectangular block: give `size` (R, m) or `p` (rad/s), and α (rad).
    Rigid {
        #[serde(default, skip_serializing_if = "Option::is_none")]
        size: Option<Values>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        p: Option<Values>,
        alpha: Values,
        #[serde(default = "unit_values")]
        mass: Values,
        #[serde(default)]
        form: Form,
    },
    /// Flexible rocking structure: R0 (m), α (rad), ξ, and ωn (rad/s) or ωn/p.
    Flexible {
        r0: Values,
        alpha: Values,
        xi: Values,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        omega_n: Option<Values>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        omega_ratio: Option<Values>,
        #[serde(default = "unit_values")]
        mass: Values,
    },
}

/// A device variant; a mechanistic clutch takes grids of its parameters (cartesian product).
/// (A handful per study: the size difference between variants does not matter.)
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum DeviceVariant {
    /// The bare structure: `none`, or `bare` as results, labels and selectors name it.
    #[serde(alias = "bare")]
    None,
    /// A single inerter without clutch, attached rigidly or through a flywheel.
    Inerter {
        sigma: Values,
        #[serde(default = "rigid_coupling")]
        coupling: CouplingFamily,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        label: Option<String>,
    },
    /// Twin clutched inerters, Makris–Kampas sequential law.
    Sequential {
        sigma: Values,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        label: Option<String>,
    },
    /// Twin clutched inerters with the paper's mechanistic clutch. Stiffness: `k_theta` or
    /// `clutch_frequency_ratio` (default ratio 25: ξθ = 0.02 ⇔ c̄ ≈ 1 s⁻¹ on the §6 structure); damping: `cbar` (default 1 s⁻¹) or `xi_theta`.
    Mechanistic {
        sigma: Values,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        k_theta: Option<Values>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        clutch_frequency_ratio: Option<Values>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        cbar: Option<Values>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        xi_theta: Option<Values>,
        /// Dry friction fμ / (mr·g).
        #[serde(default = "zero_values")]
        friction: Values,
        #[serde(default = "default_eta_values")]
        eta: Values,
        /// Gear play up (m).
        #[serde(default = "zero_values")]
        play: Values,
        #[serde(default = "default_epsilon_values")]
        epsilon: Values,
        #[serde(default = "default_rho_values")]
        rho: Values,
        #[serde(default)]
        reset: ResetRule,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        label: Option<String>,
    },
}

/// How a study's single inerter is attached: rigidly, or through an explicit flywheel behind
/// a spring, with the clutch's spring and damping named as a mechanistic device names them
/// (and as `rocklab simulate --coupling flywheel` takes them): stiffness `k_theta` or
/// `clutch_frequency_ratio` (default the clutch's), damping `cbar` (default the clutch's) or
/// `xi_theta`, pinion radius `rho`. Each takes a value, a list or a range.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum CouplingFamily {
    Rigid,
    Flywheel {
        #[serde(default, skip_serializing_if = "Option::is_none")]
        k_theta: Option<Values>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        clutch_frequency_ratio: Option<Values>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        cbar: Option<Values>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        xi_theta: Option<Values>,
        #[serde(default = "default_rho_values")]
        rho: Values,
    },
}

pub(crate) fn rigid_coupling() -> CouplingFamily {
    CouplingFamily::Rigid
}

/// The clutch frequency ratio √(k/mr)/p of a device that gives neither it nor `k_theta`.
pub(crate) fn default_clutch_frequency_ratio() -> Values {
    Values::One(match ClutchStiffness::default() {
        ClutchStiffness::FrequencyRatio(r) | ClutchStiffness::KTheta(r) => r,
    })
}

/// The flywheel damping c̄ of a device that gives neither it nor `xi_theta`.
pub(crate) fn default_cbar() -> Values {
    Values::One(match Damping::default() {
        Damping::CBar(c) | Damping::XiTheta(c) => c,
    })
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ExcitationFamily {
    /// Analytic pulses: amplitude and frequency axes; one shape or a list of them (an axis
    /// of the study, shapes.rs).
    Pulse {
        shape: PulseShapes,
        amplitude: AmplitudeAxis,
        frequency: FrequencyAxis,
        /// The vertical ground motion of every scene (absent: none).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        vertical: Option<crate::scene::VerticalMotion>,
    },
    /// Recorded ground motions from the record library (`rocklab records` lists them), each
    /// scaled by `scale`: a factor (default), or a target PGA (g), PGV (m/s), PGA* or PGV*
    /// per `scale_to`. The records are `names`, then the members of `suite` (a whole FEMA P695
    /// set or a filter of one; `rocklab records --suite NAME` lists them).
    Record {
        #[serde(default)]
        names: Vec<String>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        suite: Option<crate::excitation::suite::SuiteSelect>,
        #[serde(default = "unit_values")]
        scale: Values,
        #[serde(default)]
        scale_to: RecordScaling,
        /// Baseline-correct the records first.
        #[serde(default)]
        baseline: bool,
        /// Whether the integrator stops at every sample (default) or steps over the kinks.
        #[serde(default)]
        kinks: KinkPolicy,
        /// Each scene lasts its record's length plus `tail` seconds (the study then gives no
        /// `duration`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        tail: Option<f64>,
        /// The vertical ground motion of every scene (absent: none): `ratio(r)` follows each
        /// record's scaling, a `record("FILE")` is multiplied by the same factor.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        vertical: Option<crate::scene::VerticalMotion>,
    },
}

impl ExcitationFamily {
    /// The vertical ground motion every scene of the study has.
    pub fn vertical(&self) -> Option<&crate::scene::VerticalMotion> {
        match self {
            ExcitationFamily::Pulse { vertical, .. }
            | ExcitationFamily::Record { vertical, .. } => vertical.as_ref(),
        }
    }
}

/// What a record's `scale` value means.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RecordScaling {
    /// a_g = scale · record.
    #[default]
    Factor,
    /// Scaled to a peak ground acceleration of `scale` g.
    Pga,
    /// Scaled to a peak ground velocity of `scale` m/s.
    Pgv,
    /// Scaled to PGA* = PGA/(g·tan α) = `scale` for each structure of the family.
    PgaStar,
    /// Scaled to PGV* = PGV·p/(g·tan α) = `scale` for each structure of the family.
    PgvStar,
    /// FEMA P695 normalisation: a_g = `scale` · (the record's normalisation factor) · record
    /// (suite records only; the factor is in their `index.csv`).
    Fema,
    /// Scaled to Sa(T, ξ) = `scale` g: the record's pseudo-spectral acceleration at `period`
    /// (s), damping ratio `damping` (default 0.05), as `excitation::ims` computes it.
    Sa {
        period: f64,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        damping: Option<f64>,
    },
    /// Scaled to Sa_avg = `scale` g: the geometric mean of Sa (ξ = 0.05) at ten log-spaced
    /// periods from `from` to `to` (s).
    SaAvg { from: f64, to: f64 },
    /// Scaled to an Arias intensity of `scale` m/s (it grows with the factor squared).
    Arias,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AmplitudeAxis {
    /// A/g.
    G(Values),
    /// A/(g·tan α).
    TanAlphaRatio(Values),
    /// A/(g·α).
    AlphaRatio(Values),
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrequencyAxis {
    /// ωg (rad/s).
    RadPerSec(Values),
    /// ωg/p.
    Ratio(Values),
}

impl AmplitudeAxis {
    /// The parameter its values are.
    pub fn param(&self) -> Param {
        match self {
            AmplitudeAxis::G(_) => Param::AmplitudeG,
            AmplitudeAxis::TanAlphaRatio(_) => Param::AmplitudeTanAlphaRatio,
            AmplitudeAxis::AlphaRatio(_) => Param::AmplitudeAlphaRatio,
        }
    }

    pub fn values(&self) -> &Values {
        match self {
            AmplitudeAxis::G(v)
            | AmplitudeAxis::TanAlphaRatio(v)
            | AmplitudeAxis::AlphaRatio(v) => v,
        }
    }
}

impl FrequencyAxis {
    /// The parameter its values are.
    pub fn param(&self) -> Param {
        match self {
            FrequencyAxis::RadPerSec(_) => Param::Frequency,
            FrequencyAxis::Ratio(_) => Param::FrequencyRatio,
        }
    }

    pub fn values(&self) -> &Values {
        match self {
            FrequencyAxis::RadPerSec(v) | FrequencyAxis::Ratio(v) => v,
        }
    }
}

/// A study parameter that can serve as a spectrum or map axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    /// The pulse frequency (ωg or ωg/p, as the study gives it).
    Frequency,
    /// The pulse amplitude (A/g, A/(g·α) or A/(g·tanα)).
    Amplitude,
    /// The record scale factor.
    Scale,
    Alpha,
    Size,
    P,
    R0,
    Xi,
    OmegaN,
    OmegaRatio,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MapAxes {
    pub x: Axis,
    pub y: Axis,
    /// Compute the map by boundary refinement instead of running every cell (sweep/adaptive.rs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refine: Option<Refine>,
}

/// Adaptive overturning map: run a coarse lattice of the map's grid (every 2^levels-th value
/// of both axes, the last values always included), then split only the cells whose known
/// points disagree (overturned vs survived, or a failed scene), down to the study's grid.
/// Cells whose known points all agree are filled with that verdict and marked inferred. A
/// survival island or overturning tongue narrower than a coarse cell (2^levels grid steps)
/// can be missed; anything that touches a coarse lattice point is found.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Refine {
    /// Refinement levels: the coarse lattice steps 2^levels grid values (1 ≤ levels ≤ 8).
    pub levels: u32,
}

impl MapAxes {
    /// The refinement levels of an adaptive map (None: every cell runs).
    pub fn refine_levels(&self) -> Option<u32> {
        self.refine.map(|r| r.levels)
    }
}

/// One scene of an expanded study.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ScenePoint {
    /// Position in the study's expansion order.
    pub index: usize,
    pub scene: Scene,
    /// Display label of the scene's group: the device, every parameter that varies in the
    /// study and is not an axis, and the record. Never parse it: [`Layout::locate`] gives the
    /// exact parameter values of a point from its index.
    pub group: String,
    /// Axis name → value; the spectrum axis first, then the map's y axis if any, then the
    /// other varying parameters.
    pub coords: Vec<(String, f64)>,
    /// Hash of the scene and solver settings: the cache key for reruns.
    pub key: String,
    /// In a study with uncertain parameters: the values drawn for this scene, or that it is
    /// a drawn scene's deterministic companion (study/uncertain).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uncertain: Option<uncertain::Sample>,
}

impl ScenePoint {
    /// The coordinate labelled `name` (a parameter's label, or an axis label from a file).
    pub fn coord(&self, name: &str) -> Option<f64> {
        self.coords.iter().find(|(n, _)| n == name).map(|(_, v)| *v)
    }

    /// The value of parameter `param`, if it is one of the point's coordinates.
    pub fn param(&self, param: Param) -> Option<f64> {
        self.coord(param.label())
    }
}

/// Cache key of a scene: the scene (solver settings included) and the crate version, hashed.
pub fn scene_key(scene: &Scene) -> String {
    let json = serde_json::to_string(scene).expect("scenes serialise");
    // A record is named in the scene, but its data can change under the same name (dropping
    // the real AT2 into records/ replaces a stand-in): key on the data too.
    let data = match &scene.excitation {
        crate::scene::Excitation::Record { name, baseline, .. } => {
            crate::excitation::library::global()
                .and_then(|lib| lib.load(name, *baseline))
                .map(|r| r.fingerprint.clone())
                .unwrap_or_else(|e| format!("unavailable: {e}"))
        }
        _ => String::new(),
    };
    short_hash(&format!(
        "rocklab {} {json} {data}",
        env!("CARGO_PKG_VERSION")
    ))
}

fn short_hash(text: &str) -> String {
    let digest = Sha256::digest(text.as_bytes());
    digest[..8].iter().map(|b| format!("{b:02x}")).collect()
}

impl Study {
    /// The built-in default: a small rigid-block spectrum (bare, sequential, mechanistic) that
    /// runs in a few seconds.
    pub fn builtin_default() -> Study {
        Study::from_ron_str(include_str!("../../studies/default.ron"), "default.ron")
            .expect("the built-in default study parses")
    }

    /// Parse and validate.
    pub fn from_ron_str(text: &str, origin: &str) -> Result<Study, StudyError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let study = Study::parse_ron(text, origin)?;
        study.validate().map_err(|e| e.located(text, origin))?;
        Ok(study)
    }

    /// Parse only (schema errors), without the physical validation of [`Study::validate`].
    pub fn parse_ron(text: &str, origin: &str) -> Result<Study, StudyError> {
        // A byte-order mark (some Windows editors write one) is no part of the study.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        strict::check_nesting(text, origin)?;
        strict::check_names(text, origin)?;
        strict::check_shapes(text, origin)?;
        strict::check_not_numbers(text, origin)?;
        let resolved = strict::resolve_degrees(text, origin)?;
        let study = ron_options()
            .from_str(&resolved)
            .map_err(|e| StudyError::from_ron(e, &resolved, origin))?;
        strict::check_meaning(text, &study, origin)?;
        Ok(study)
    }

    pub fn load(path: &Path) -> Result<Study, StudyError> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| StudyError {
            origin: origin.clone(),
            line: None,
            column: None,
            field: None,
            message: format!("cannot read the study file: {e}"),
            hint: Some("check the path; `rocklab run default` runs the built-in study".into()),
        })?;
        let mut study = Study::from_ron_str(&text, &origin)?;
        risk::resolve(&mut study, path).map_err(|e| e.located(&text, &origin))?;
        Ok(study)
    }

    /// Pretty RON that parses back to the same study.
    pub fn to_ron_string(&self) -> String {
        let config = ron::ser::PrettyConfig::new()
            .extensions(ron::extensions::Extensions::IMPLICIT_SOME)
            .struct_names(false);
        ron_options()
            .to_string_pretty(self, config)
            .expect("studies serialise")
    }

    /// Write the study laid out for reading (lists on one line where they fit), every field
    /// spelled out: what `rocklab run` keeps beside its results.
    pub fn save(&self, path: &Path) -> Result<(), crate::fsutil::FsError> {
        crate::fsutil::write_atomic(path, writer::write(self, None).text.as_bytes())
    }

    /// The study as text that keeps what the user wrote in `original` (the file it was
    /// opened from): comments, spelling, defaults left out; see [`writer`].
    pub fn to_ron_keeping(&self, original: Option<&str>) -> writer::Written {
        writer::write(self, original)
    }

    /// Physical and structural validity. Errors name the field (as a path) with a hint; the
    /// file position is filled in by [`Study::from_ron_str`].
    pub fn validate(&self) -> Result<(), StudyError> {
        expand::validate(self)?;
        design::validate(self)?;
        fragility::validate(self)?;
        uncertain::validate(self)?;
        risk::validate(self)
    }

    pub fn expand(&self) -> Result<Vec<ScenePoint>, StudyError> {
        expand::expand(self)
    }

    /// The parameters of each device variant and where its scenes sit in the expansion.
    pub fn layout(&self) -> Result<Layout, StudyError> {
        Layout::of(self)
    }

    /// Hash of the canonical RON: identifies the study a results file came from.
    pub fn hash(&self) -> String {
        short_hash(&self.to_ron_string())
    }
}

fn ron_options() -> ron::Options {
    ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
}

/// What a study computes, decided once from its sections ([`Study::kind`]); the sweep picks
/// its run by it, so no caller re-derives it from the sections.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StudyKind {
    /// Response spectra over the spectrum axis: every scene of the grid.
    Spectra,
    /// An overturning map over two axes, every cell run.
    Map,
    /// An overturning map by boundary refinement (`map.refine`): rounds of scenes.
    RefinedMap,
    /// A fragility study on stripes: every scene of the grid, fitted per damage state.
    Stripes,
    /// An incremental dynamic analysis (`fragility.method: ida`): a hunt per record.
    Ida,
    /// A design search (`design`): a bisection per design point.
    Design,
}

impl StudyKind {
    /// Whether its scenes come from a search in rounds (each round needs the verdicts of the
    /// one before), which cannot be split into shards.
    pub fn searches(self) -> bool {
        match self {
            StudyKind::RefinedMap | StudyKind::Ida | StudyKind::Design => true,
            StudyKind::Spectra | StudyKind::Map | StudyKind::Stripes => false,
        }
    }
}

impl Study {
    /// What the study computes. A refined map, a design and an IDA are searches and exclude
    /// one another (validation refuses a design with a map; a design's fragility target
    /// needs stripes); a map beside a fragility section is a map.
    pub fn kind(&self) -> StudyKind {
        let ida = self
            .fragility
            .as_ref()
            .is_some_and(|f| f.method.ida_resolution().is_some());
        match (&self.map, &self.design, &self.fragility) {
            (Some(m), ..) if m.refine.is_some() => StudyKind::RefinedMap,
            (_, Some(_), _) => StudyKind::Design,
            _ if ida => StudyKind::Ida,
            (Some(_), ..) => StudyKind::Map,
            (None, None, Some(_)) => StudyKind::Stripes,
            (None, None, None) => StudyKind::Spectra,
        }
    }

    /// The coordinate label of an axis in this study (e.g. `ωg/p`, `A/(g·α)`, `ωn`).
    pub fn axis_label(&self, axis: Axis) -> String {
        self.axis_param(axis).label().to_string()
    }

    /// The parameter an axis is in this study (the pulse's frequency and amplitude as the
    /// study gives them).
    pub fn axis_param(&self, axis: Axis) -> Param {
        match (axis, &self.excitation) {
            (Axis::Frequency, ExcitationFamily::Pulse { frequency, .. }) => frequency.param(),
            (Axis::Amplitude, ExcitationFamily::Pulse { amplitude, .. }) => amplitude.param(),
            (Axis::Frequency, _) => Param::Frequency,
            (Axis::Amplitude, _) => Param::AmplitudeG,
            (Axis::Scale, _) => Param::Scale,
            (Axis::Alpha, _) => Param::Alpha,
            (Axis::Size, _) => Param::Size,
            (Axis::P, _) => Param::P,
            (Axis::R0, _) => Param::R0,
            (Axis::Xi, _) => Param::Xi,
            (Axis::OmegaN, _) => Param::OmegaN,
            (Axis::OmegaRatio, _) => Param::OmegaRatio,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_default_round_trips_and_expands() {
        let study = Study::builtin_default();
        let text = study.to_ron_string();
        let back = Study::from_ron_str(&text, "round-trip").unwrap();
        assert_eq!(back, study, "{text}");
        let points = study.expand().unwrap();
        assert_eq!(points.len(), 3 * 12);
        assert_eq!(points[0].coords[0].0, Param::FrequencyRatio.label());
        assert_eq!(points[0].group, "bare");
        assert_eq!(points[12].group, "sequential");
        assert_eq!(study.kind(), StudyKind::Spectra);
        // The frequency axis varies fastest.
        assert_eq!(points[1].coords[0].1, 2.0);
    }

    /// The kind follows the sections: a map, refined or not, and a fragility section beside
    /// it (the map wins: it is what the run computes).
    #[test]
    fn the_kind_is_decided_by_the_sections() {
        let mut study = Study::builtin_default();
        let mut axes = MapAxes {
            x: Axis::Frequency,
            y: Axis::Amplitude,
            refine: None,
        };
        study.map = Some(axes);
        assert_eq!(study.kind(), StudyKind::Map);
        assert!(!study.kind().searches());
        axes.refine = Some(Refine { levels: 2 });
        study.map = Some(axes);
        assert_eq!(study.kind(), StudyKind::RefinedMap);
        assert!(study.kind().searches());
    }
}
