//! Scene files: the TOML model of a problem and how to solve and show it, its validation into
//! a [`Problem`], loading (file or preset name) and atomic saving.
//!
//! Every rejection is a [`SceneError`] that names the source (file or preset), the field and
//! the rule it broke, e.g. `beam.toml: obstacle[2].x = 1.2: must lie strictly inside (0, l) =
//! (0, 1) m`. Unknown fields are errors, not silently ignored.

mod loaded;
mod presets;
mod read;
mod save;
mod serialize;
mod validate;

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::model::{Method, Problem};
use validate::Validator;

pub use loaded::{LoadedScene, SceneSource, load};
pub use presets::{PRESETS, Preset, preset};
pub use read::{MAX_SCENE_BYTES, read_scene_text};
pub(crate) use read::{Refusal, read_regular_file};
pub use save::{SaveError, SaveOutcome, save_atomic, save_scene, write_atomic};
pub use serialize::{SAVED_HEADER, float_text};

/// Most elements a scene may ask for (memory stays under a few hundred MB).
pub const MAX_ELEMENTS: usize = 10_000_000;
/// Most obstacles a scene may have. `condensed` is O(n + k·solves); the dual methods build a
/// dense 2k × 2k matrix (512 MB at this limit) and are slow well before it.
pub const MAX_OBSTACLES: usize = 4096;
/// Two distinct special points (obstacles, supports, ends of stretches) closer than this
/// fraction of the length are rejected: the element between them would be degenerate.
pub const MIN_SEPARATION: f64 = 1e-9;

/// A scene as written in a TOML file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Shown in the title bar.
    #[serde(default)]
    pub title: String,
    /// What the scene teaches, shown in the help overlay.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub description: String,
    pub beam: BeamSpec,
    pub load: LoadSpec,
    #[serde(default, rename = "obstacle", skip_serializing_if = "Vec::is_empty")]
    pub obstacles: Vec<ObstacleSpec>,
    #[serde(default)]
    pub mesh: MeshSpec,
    #[serde(default)]
    pub solver: SolverSpec,
    #[serde(default)]
    pub view: ViewSpec,
}

/// `[beam]`: length, material and cross-section, with optional stretches of their own.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BeamSpec {
    /// l [m].
    pub length: f64,
    /// Young's modulus E [Pa].
    pub young: f64,
    pub section: Section,
    #[serde(default, rename = "segment", skip_serializing_if = "Vec::is_empty")]
    pub segments: Vec<SegmentSpec>,
}

/// A cross-section; its second moment J [m⁴] about the bending axis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "lowercase", deny_unknown_fields)]
pub enum Section {
    /// J = width·height³/12 (height in the direction of the deflection) [m].
    Rectangle { width: f64, height: f64 },
    /// J = π r⁴/4 [m].
    Circle { radius: f64 },
    /// J given directly [m⁴].
    Custom { inertia: f64 },
}

impl Section {
    /// Second moment of area J [m⁴].
    pub fn inertia(&self) -> f64 {
        match *self {
            Section::Rectangle { width, height } => width * height.powi(3) / 12.0,
            Section::Circle { radius } => std::f64::consts::PI * radius.powi(4) / 4.0,
            Section::Custom { inertia } => inertia,
        }
    }

    /// The dimensions as (field name, value) pairs, for validation and display.
    pub fn dimensions(&self) -> Vec<(&'static str, f64)> {
        match *self {
            Section::Rectangle { width, height } => vec![("width", width), ("height", height)],
            Section::Circle { radius } => vec![("radius", radius)],
            Section::Custom { inertia } => vec![("inertia", inertia)],
        }
    }
}

/// `[[beam.segment]]`: a stretch [from, to] with its own modulus and/or section.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentSpec {
    /// Start [m].
    pub from: f64,
    /// End [m].
    pub to: f64,
    /// E on the stretch [Pa]; the beam's if left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub young: Option<f64>,
    /// Section on the stretch; the beam's if left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub section: Option<Section>,
}

/// `[load]`: f(x) = f0 + (f1 − f0) x / l [N/m]; f1 defaults to f0 (constant load).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    pub f0: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub f1: Option<f64>,
}

impl LoadSpec {
    /// f at x = l [N/m].
    pub fn f1(&self) -> f64 {
        self.f1.unwrap_or(self.f0)
    }
}

/// `[[obstacle]]`: a point obstacle with given sliding and swivel friction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleSpec {
    /// Position x̂ [m].
    pub x: f64,
    /// Sliding threshold g1 [N].
    pub sliding: f64,
    /// Swivel threshold g2 [N m].
    pub swivel: f64,
}

/// `[mesh]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// Number of Hermite cubic elements n.
    pub elements: usize,
}

impl Default for MeshSpec {
    fn default() -> Self {
        MeshSpec { elements: 20 }
    }
}

/// `[solver]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    #[serde(default)]
    pub method: Method,
    /// Regularisation parameter ε of (40) (only the regularised methods use it).
    #[serde(default = "default_epsilon")]
    pub epsilon: f64,
}

fn default_epsilon() -> f64 {
    1e-6
}

impl Default for SolverSpec {
    fn default() -> Self {
        SolverSpec {
            method: Method::default(),
            epsilon: default_epsilon(),
        }
    }
}

/// The explorer's panels a scene can ask for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Panel {
    /// u(x) (or moment and shear) over the beam.
    Deflection,
    /// Regularisation error against ε (paper Figure 5, left).
    EpsError,
    /// Largest condition number over the enumerated cases against ε (Figure 5, right).
    EpsCond,
    /// Error against run time for every method over mesh sizes.
    ErrorTime,
    /// Figure 5 as one panel: the regularisation error and cond₂ of the case matrices against
    /// ε on one shared ε axis.
    #[serde(rename = "figure-5")]
    Figure5,
    /// The method's convergence history, iteration by iteration.
    Iterations,
    /// The dual (49) restricted to the selected obstacle: the box, level curves, iterates.
    DualBox,
    /// The regularised method's cases of Table 1.
    Cases,
    /// The structure of the matrices: A, S = B A⁻¹ Bᵀ and the condensed system.
    Matrices,
}

impl Panel {
    /// Every panel, in display order.
    pub const ALL: [Panel; 9] = [
        Panel::Deflection,
        Panel::EpsError,
        Panel::EpsCond,
        Panel::ErrorTime,
        Panel::Figure5,
        Panel::Iterations,
        Panel::DualBox,
        Panel::Cases,
        Panel::Matrices,
    ];

    /// The panels of a scene that does not list its own: the overview of the answer and its
    /// trade-offs. The others (how the method works) are a key away (`v`).
    pub const DEFAULT: [Panel; 4] = [
        Panel::Deflection,
        Panel::EpsError,
        Panel::EpsCond,
        Panel::ErrorTime,
    ];

    /// The name in scene files, e.g. `eps-error`.
    pub fn name(self) -> &'static str {
        match self {
            Panel::Deflection => "deflection",
            Panel::EpsError => "eps-error",
            Panel::EpsCond => "eps-cond",
            Panel::ErrorTime => "error-time",
            Panel::Figure5 => "figure-5",
            Panel::Iterations => "iterations",
            Panel::DualBox => "dual-box",
            Panel::Cases => "cases",
            Panel::Matrices => "matrices",
        }
    }
}

/// `[view]`: the panels the scene needs; panels not listed are neither drawn nor computed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViewSpec {
    #[serde(default = "default_panels")]
    pub panels: Vec<Panel>,
    /// The parameter selected when the scene opens, by its field name (`solver.epsilon`,
    /// `obstacle[1].sliding`, … one of [`Scene::parameter_fields`]); the first one if absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub select: Option<String>,
}

impl Scene {
    /// The fields the explorer lists as parameters, in its order: loads, modulus, the
    /// section's dimensions, each obstacle's position and thresholds, ε, elements, method.
    pub fn parameter_fields(&self) -> Vec<String> {
        let mut fields: Vec<String> = vec!["load.f0".into(), "load.f1".into(), "beam.young".into()];
        for (name, _) in self.beam.section.dimensions() {
            fields.push(format!("beam.section.{name}"));
        }
        for i in 1..=self.obstacles.len() {
            for what in ["x", "sliding", "swivel"] {
                fields.push(format!("obstacle[{i}].{what}"));
            }
        }
        fields.extend(["solver.epsilon", "mesh.elements", "solver.method"].map(String::from));
        fields
    }
}

fn default_panels() -> Vec<Panel> {
    Panel::DEFAULT.to_vec()
}

impl Default for ViewSpec {
    fn default() -> Self {
        ViewSpec {
            panels: default_panels(),
            select: None,
        }
    }
}

/// A rejected scene: where it came from, which field, and the rule it broke.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneError {
    /// File path or `preset <name>`.
    pub source: String,
    /// Dotted path of the field, e.g. `obstacle[2].x`; a location for syntax errors.
    pub field: String,
    /// The rule, with what would be accepted.
    pub rule: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.field.is_empty() {
            write!(f, "{}: {}", self.source, self.rule)
        } else {
            write!(f, "{}: {}: {}", self.source, self.field, self.rule)
        }
    }
}

impl std::error::Error for SceneError {}

/// What a scene asks of the solver besides the physics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    pub elements: usize,
    pub method: Method,
    pub epsilon: f64,
}

impl Scene {
    /// Parses TOML text; `source` names it in errors (a path or `preset <name>`).
    pub fn from_toml(text: &str, source: &str) -> Result<Scene, SceneError> {
        toml::from_str(text).map_err(|e| parse_error(text, source, &e))
    }

    /// The scene as TOML text, serialized by serde and `toml`: every string and every f64
    /// reads back exactly; numbers outside [1e-3, 1e5) in exponent form (2.15e11), fields in
    /// the order of README's example. No comments.
    pub fn to_toml(&self) -> String {
        serialize::scene_to_toml(self)
    }

    /// Checks every rule and builds the problem the numerics solve.
    pub fn validate(&self, source: &str) -> Result<(Problem, Settings), SceneError> {
        Validator { source }.check_all(self)
    }

    /// The physical problem, when the scene is known to be valid.
    pub fn problem(&self) -> Result<Problem, SceneError> {
        self.validate("scene").map(|(problem, _)| problem)
    }
}

fn parse_error(text: &str, source: &str, error: &toml::de::Error) -> SceneError {
    // Quoted names from the file may hold control characters: escaped, one line.
    let message = crate::format::printable(error.message().trim()).into_owned();
    let Some(span) = error.span() else {
        return SceneError {
            source: source.to_string(),
            field: String::new(),
            rule: message,
        };
    };
    let before = &text[..span.start.min(text.len())];
    let (line, column) = text_position(text, span.start);
    // The table the error sits in, so the message names the field's place, not just a line.
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let on_header = text[line_start..].trim_start().starts_with('[');
    let table = if on_header {
        String::new()
    } else {
        text[..line_start]
            .lines()
            .rev()
            .map(str::trim)
            .find(|l| l.starts_with('['))
            .map(|header| format!(" in {header}"))
            .unwrap_or_default()
    };
    let key = text[span.start.min(text.len())..span.end.min(text.len())]
        .lines()
        .next()
        .unwrap_or("")
        .trim();
    let key = if key.is_empty() || key.len() > 40 {
        String::new()
    } else {
        format!(" at `{key}`")
    };
    SceneError {
        source: source.to_string(),
        field: format!("line {line}, column {column}{table}{key}"),
        rule: message,
    }
}

/// Line and column (from 1) of byte `offset` in `text`, as an editor shows them: columns
/// count characters, not bytes (ε is two bytes). Scene and lesson errors say where with it.
pub fn text_position(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    (
        before.matches('\n').count() + 1,
        before[line_start..].chars().count() + 1,
    )
}

/// The rule for the number of elements, shared by scene files, the command line and the
/// explorer: the message says what would be accepted.
pub fn check_elements(elements: usize) -> Result<(), String> {
    if (1..=MAX_ELEMENTS).contains(&elements) {
        Ok(())
    } else {
        Err(format!(
            "= {elements}: must be between 1 and {MAX_ELEMENTS}"
        ))
    }
}

/// The rule for ε: finite, greater than zero and not subnormal (see [`check_positive`]).
pub fn check_epsilon(epsilon: f64) -> Result<(), String> {
    if epsilon.is_finite() && epsilon > 0.0 {
        check_positive(epsilon, "").map_err(|rule| rule.replacen(": must", ": ε must", 1))
    } else {
        Err(format!(
            "= {epsilon}: ε must be a finite number greater than zero"
        ))
    }
}

/// The rule for every positive parameter (ε, length, modulus, section sizes, J, E·J): a
/// normal f64 greater than zero. Subnormal values (below 2.2251e-308) carry fewer
/// significant digits and overflow when inverted, so the methods cannot honour them.
pub fn check_positive(value: f64, unit: &str) -> Result<(), String> {
    use validate::show;
    let unit = if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    };
    if value.is_normal() && value > 0.0 {
        Ok(())
    } else if value > 0.0 && value.is_finite() {
        Err(format!(
            "= {value:e}{unit}: must be a normal positive number ≥ 2.2251e-308 \
             (f64::MIN_POSITIVE); subnormal values are not supported"
        ))
    } else {
        Err(format!(
            "= {}{unit}: must be greater than zero",
            show(value)
        ))
    }
}
