//! Scene files: the TOML model of a problem and how to solve and show it, its validation into
//! a [`Problem`], loading (file or preset name) and atomic saving.
//!
//! Every rejection is a [`SceneError`] that names the source (file or preset), the field and
//! the rule it broke, e.g. `beam.toml: obstacle[2].x = 1.2: must lie strictly inside (0, l) =
//! (0, 1) m`. Unknown fields are errors, not silently ignored.

mod presets;
mod save;

use std::fmt;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::model::{LinearLoad, Obstacle, Problem, StiffnessPiece};
use crate::solve::Method;

pub use presets::{PRESETS, Preset, preset};
pub use save::{SaveError, save_atomic};

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
}

impl Panel {
    /// Every panel, in display order.
    pub const ALL: [Panel; 4] = [
        Panel::Deflection,
        Panel::EpsError,
        Panel::EpsCond,
        Panel::ErrorTime,
    ];
}

/// `[view]`: the panels the scene needs; panels not listed are neither drawn nor computed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViewSpec {
    #[serde(default = "all_panels")]
    pub panels: Vec<Panel>,
}

fn all_panels() -> Vec<Panel> {
    Panel::ALL.to_vec()
}

impl Default for ViewSpec {
    fn default() -> Self {
        ViewSpec {
            panels: all_panels(),
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

    /// The scene as TOML text; large and tiny numbers in exponent form (2.15e11, not
    /// 215000000000.0), still exact.
    pub fn to_toml(&self) -> String {
        let text = toml::to_string(self).expect("a scene always serializes");
        text.lines()
            .map(|line| {
                let Some((key, value)) = line.split_once(" = ") else {
                    return line.to_string();
                };
                // Floats only (TOML writes them with a point or an exponent); integers stay.
                let is_float = value.contains(['.', 'e', 'E']) && !value.starts_with('"');
                match value.parse::<f64>() {
                    Ok(v) if is_float && v != 0.0 && (v.abs() >= 1e5 || v.abs() < 1e-3) => {
                        format!("{key} = {v:e}")
                    }
                    _ => line.to_string(),
                }
            })
            .collect::<Vec<_>>()
            .join("\n")
            + "\n"
    }

    /// Checks every rule and builds the problem the numerics solve.
    pub fn validate(&self, source: &str) -> Result<(Problem, Settings), SceneError> {
        Validator { source }.run(self)
    }

    /// The physical problem, when the scene is known to be valid.
    pub fn problem(&self) -> Result<Problem, SceneError> {
        self.validate("scene").map(|(problem, _)| problem)
    }

    /// Settings from the scene.
    pub fn settings(&self) -> Settings {
        Settings {
            elements: self.mesh.elements,
            method: self.solver.method,
            epsilon: self.solver.epsilon,
        }
    }
}

/// Loads a scene by preset name or file path. A path that exists wins over a preset name.
/// Returns the scene and its source name for messages.
pub fn load(name_or_path: &str) -> Result<(Scene, String), SceneError> {
    let path = Path::new(name_or_path);
    if path.exists() {
        let source = name_or_path.to_string();
        let text = std::fs::read_to_string(path).map_err(|e| SceneError {
            source: source.clone(),
            field: String::new(),
            rule: format!("cannot read the file: {e}"),
        })?;
        let scene = Scene::from_toml(&text, &source)?;
        scene.validate(&source)?;
        return Ok((scene, source));
    }
    if let Some(preset) = preset(name_or_path) {
        let source = format!("preset {}", preset.name);
        let scene = Scene::from_toml(preset.text, &source)?;
        scene.validate(&source)?;
        return Ok((scene, source));
    }
    let names: Vec<&str> = PRESETS.iter().map(|p| p.name).collect();
    Err(SceneError {
        source: name_or_path.to_string(),
        field: String::new(),
        rule: format!(
            "no such file, and not a preset name (presets: {})",
            names.join(", ")
        ),
    })
}

fn parse_error(text: &str, source: &str, error: &toml::de::Error) -> SceneError {
    let message = error.message().trim().to_string();
    let Some(span) = error.span() else {
        return SceneError {
            source: source.to_string(),
            field: String::new(),
            rule: message,
        };
    };
    let before = &text[..span.start.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
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

/// The rule for ε: finite and greater than zero.
pub fn check_epsilon(epsilon: f64) -> Result<(), String> {
    if epsilon.is_finite() && epsilon > 0.0 {
        Ok(())
    } else {
        Err(format!(
            "= {epsilon}: ε must be a finite number greater than zero"
        ))
    }
}

struct Validator<'a> {
    source: &'a str,
}

/// A number as a person would write it: 0.8, 2.15e11, -1e-8.
fn show(value: f64) -> String {
    let magnitude = value.abs();
    if value == 0.0 || !value.is_finite() || (1e-3..1e6).contains(&magnitude) {
        format!("{value}")
    } else {
        format!("{value:e}")
    }
}

impl Validator<'_> {
    fn error(&self, field: impl Into<String>, rule: impl Into<String>) -> SceneError {
        SceneError {
            source: self.source.to_string(),
            field: field.into(),
            rule: rule.into(),
        }
    }

    fn finite(&self, field: &str, value: f64) -> Result<f64, SceneError> {
        if value.is_finite() {
            Ok(value)
        } else {
            Err(self.error(field, format!("= {}: must be a finite number", show(value))))
        }
    }

    fn positive(&self, field: &str, value: f64, unit: &str) -> Result<f64, SceneError> {
        self.finite(field, value)?;
        if value > 0.0 {
            Ok(value)
        } else {
            let unit = if unit.is_empty() {
                String::new()
            } else {
                format!(" {unit}")
            };
            Err(self.error(
                field,
                format!("= {}{unit}: must be greater than zero", show(value)),
            ))
        }
    }

    fn section(&self, field: &str, section: &Section) -> Result<f64, SceneError> {
        for (name, value) in section.dimensions() {
            let unit = if name == "inertia" { "m^4" } else { "m" };
            self.positive(&format!("{field}.{name}"), value, unit)?;
        }
        let inertia = section.inertia();
        if inertia > 0.0 && inertia.is_finite() {
            Ok(inertia)
        } else {
            Err(self.error(
                field,
                format!("second moment J = {inertia:e} m^4 is out of floating-point range"),
            ))
        }
    }

    fn bending_stiffness(&self, field: &str, young: f64, inertia: f64) -> Result<f64, SceneError> {
        let ej = young * inertia;
        if ej > 0.0 && ej.is_finite() {
            Ok(ej)
        } else {
            Err(self.error(
                field,
                format!("E·J = {ej:e} N m^2 is out of floating-point range"),
            ))
        }
    }

    fn run(&self, scene: &Scene) -> Result<(Problem, Settings), SceneError> {
        let beam = &scene.beam;
        let length = self.positive("beam.length", beam.length, "m")?;
        let young = self.positive("beam.young", beam.young, "Pa")?;
        let inertia = self.section("beam.section", &beam.section)?;
        let base = self.bending_stiffness("beam", young, inertia)?;

        // Stretches of their own, then fill the gaps with the beam's E·J.
        let mut segments = Vec::with_capacity(beam.segments.len());
        for (i, segment) in beam.segments.iter().enumerate() {
            let field = format!("beam.segment[{}]", i + 1);
            let from = self.finite(&format!("{field}.from"), segment.from)?;
            let to = self.finite(&format!("{field}.to"), segment.to)?;
            if !(0.0..length).contains(&from) {
                return Err(self.error(
                    format!("{field}.from"),
                    format!(
                        "= {} m: must lie in [0, l) = [0, {}) m",
                        show(from),
                        show(length)
                    ),
                ));
            }
            if !(to > from && to <= length) {
                return Err(self.error(
                    format!("{field}.to"),
                    format!(
                        "= {} m: must lie in (from, l] = ({}, {}] m",
                        show(to),
                        show(from),
                        show(length)
                    ),
                ));
            }
            let young = match segment.young {
                Some(e) => self.positive(&format!("{field}.young"), e, "Pa")?,
                None => young,
            };
            let inertia = match &segment.section {
                Some(s) => self.section(&format!("{field}.section"), s)?,
                None => inertia,
            };
            let ej = self.bending_stiffness(&field, young, inertia)?;
            segments.push((i, from, to, ej));
        }
        segments.sort_by(|a, b| a.1.total_cmp(&b.1));
        for pair in segments.windows(2) {
            let (i, _, to, _) = pair[0];
            let (j, from, _, _) = pair[1];
            if from < to {
                return Err(self.error(
                    format!("beam.segment[{}]", j + 1),
                    format!(
                        "overlaps beam.segment[{}] (from = {from} m < its end {to} m); \
                         segments must not overlap",
                        i + 1
                    ),
                ));
            }
        }
        let mut stiffness = Vec::new();
        let mut cursor = 0.0;
        for &(_, from, to, ej) in &segments {
            if from > cursor {
                stiffness.push(StiffnessPiece {
                    from: cursor,
                    to: from,
                    bending_stiffness: base,
                });
            }
            stiffness.push(StiffnessPiece {
                from,
                to,
                bending_stiffness: ej,
            });
            cursor = to;
        }
        if cursor < length {
            stiffness.push(StiffnessPiece {
                from: cursor,
                to: length,
                bending_stiffness: base,
            });
        }

        let f0 = self.finite("load.f0", scene.load.f0)?;
        let f1 = self.finite("load.f1", scene.load.f1())?;

        if scene.obstacles.len() > MAX_OBSTACLES {
            return Err(self.error(
                "obstacle",
                format!(
                    "{} obstacles: at most {MAX_OBSTACLES} are supported",
                    scene.obstacles.len()
                ),
            ));
        }
        let mut obstacles = Vec::with_capacity(scene.obstacles.len());
        for (i, o) in scene.obstacles.iter().enumerate() {
            let field = format!("obstacle[{}]", i + 1);
            let x = self.finite(&format!("{field}.x"), o.x)?;
            if !(x > 0.0 && x < length) {
                return Err(self.error(
                    format!("{field}.x"),
                    format!(
                        "= {} m: must lie strictly inside (0, l) = (0, {}) m",
                        show(x),
                        show(length)
                    ),
                ));
            }
            for (name, value, unit) in [("sliding", o.sliding, "N"), ("swivel", o.swivel, "N m")] {
                let value = self.finite(&format!("{field}.{name}"), value)?;
                if value < 0.0 {
                    return Err(self.error(
                        format!("{field}.{name}"),
                        format!(
                            "= {} {unit}: a friction threshold must be zero or positive",
                            show(value)
                        ),
                    ));
                }
            }
            obstacles.push((
                i,
                Obstacle {
                    x,
                    sliding_threshold: o.sliding,
                    swivel_threshold: o.swivel,
                },
            ));
        }
        obstacles.sort_by(|a, b| a.1.x.total_cmp(&b.1.x));
        let gap = MIN_SEPARATION * length;
        for pair in obstacles.windows(2) {
            let ((i, a), (j, b)) = (pair[0], pair[1]);
            if b.x - a.x < gap {
                let (first, second) = if i < j { (i, j) } else { (j, i) };
                let rule = if a.x == b.x {
                    format!(
                        "= {} m: same position as obstacle[{}]; obstacles must be at distinct points",
                        b.x,
                        first + 1
                    )
                } else {
                    format!(
                        "= {} m: closer than {gap:e} m (1e-9 l) to obstacle[{}]; obstacles must be apart",
                        if second == j { b.x } else { a.x },
                        first + 1
                    )
                };
                return Err(self.error(format!("obstacle[{}].x", second + 1), rule));
            }
        }
        for &(i, o) in &obstacles {
            let nearest_support = o.x.min(length - o.x);
            if nearest_support < gap {
                return Err(self.error(
                    format!("obstacle[{}].x", i + 1),
                    format!("= {} m: closer than {gap:e} m (1e-9 l) to a support", o.x),
                ));
            }
            for piece in &stiffness {
                for end in [piece.from, piece.to] {
                    if end != o.x && (end - o.x).abs() < gap {
                        return Err(self.error(
                            format!("obstacle[{}].x", i + 1),
                            format!(
                                "= {} m: closer than {gap:e} m (1e-9 l) to a segment end at {end} m; \
                                 put it exactly on the end or apart from it",
                                o.x
                            ),
                        ));
                    }
                }
            }
        }
        for piece in &stiffness {
            if piece.to - piece.from < gap {
                return Err(self.error(
                    "beam.segment",
                    format!(
                        "a stretch [{}, {}] m is shorter than {gap:e} m (1e-9 l)",
                        piece.from, piece.to
                    ),
                ));
            }
        }

        let elements = scene.mesh.elements;
        check_elements(elements).map_err(|rule| self.error("mesh.elements", rule))?;
        let epsilon = scene.solver.epsilon;
        check_epsilon(epsilon).map_err(|rule| self.error("solver.epsilon", rule))?;
        if scene.view.panels.is_empty() {
            return Err(self.error(
                "view.panels",
                "is empty: list at least one of \"deflection\", \"eps-error\", \"eps-cond\", \"error-time\"",
            ));
        }

        let problem = Problem {
            length,
            stiffness,
            load: LinearLoad { f0, f1 },
            obstacles: obstacles.into_iter().map(|(_, o)| o).collect(),
        };
        let settings = Settings {
            elements,
            method: scene.solver.method,
            epsilon,
        };
        Ok((problem, settings))
    }
}
