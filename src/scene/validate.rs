//! The rules a scene must satisfy, checked in one pass that builds the [`Problem`]: each
//! broken rule is a [`SceneError`] naming the field and what would be accepted.

use super::{
    BeamSpec, MAX_OBSTACLES, MIN_SEPARATION, ObstacleSpec, Panel, Scene, SceneError, Section,
    SegmentSpec, Settings, check_elements, check_epsilon, check_positive,
};
use crate::model::{LinearLoad, Obstacle, Problem, StiffnessPiece};

pub(super) struct Validator<'a> {
    pub(super) source: &'a str,
}

/// A number as a person would write it: 0.8, 2.15e11, -1e-8.
pub(super) fn show(value: f64) -> String {
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
            Err(self.not_finite(field, value))
        }
    }

    /// The error of a `field` that is not a finite number.
    fn not_finite(&self, field: impl Into<String>, value: f64) -> SceneError {
        self.error(field, format!("= {}: must be a finite number", show(value)))
    }

    fn positive(&self, field: &str, value: f64, unit: &str) -> Result<f64, SceneError> {
        self.finite(field, value)?;
        check_positive(value, unit).map_err(|rule| self.error(field, rule))?;
        Ok(value)
    }

    fn section(&self, field: &str, section: &Section) -> Result<f64, SceneError> {
        for (name, value) in section.dimensions() {
            let unit = if name == "inertia" { "m^4" } else { "m" };
            self.positive(&format!("{field}.{name}"), value, unit)?;
        }
        let inertia = section.inertia();
        if inertia.is_normal() && inertia > 0.0 {
            Ok(inertia)
        } else {
            Err(self.error(
                field,
                format!(
                    "second moment J = {inertia:e} m^4 is out of floating-point range (must be \
                     a normal number, 2.2251e-308 to 1.8e308)"
                ),
            ))
        }
    }

    fn bending_stiffness(&self, field: &str, young: f64, inertia: f64) -> Result<f64, SceneError> {
        let ej = young * inertia;
        if ej.is_normal() && ej > 0.0 {
            Ok(ej)
        } else {
            Err(self.error(
                field,
                format!(
                    "E·J = {ej:e} N m^2 is out of floating-point range (must be a normal \
                     number, 2.2251e-308 to 1.8e308)"
                ),
            ))
        }
    }

    /// Every rule, in the order the messages report them: the beam and its stretches, the
    /// load, the obstacles, then the solver and view settings.
    pub(super) fn check_all(&self, scene: &Scene) -> Result<(Problem, Settings), SceneError> {
        let (length, stiffness) = self.beam(&scene.beam)?;
        let f0 = self.finite("load.f0", scene.load.f0)?;
        let f1 = self.finite("load.f1", scene.load.f1())?;
        let obstacles = self.obstacles(&scene.obstacles, length)?;
        let gap = MIN_SEPARATION * length;
        self.obstacles_apart(&obstacles, gap)?;
        self.obstacles_clear(&obstacles, &stiffness, length, gap)?;
        self.stretches_long_enough(&stiffness, gap)?;
        let settings = self.settings(scene)?;
        let problem = Problem {
            length,
            stiffness,
            load: LinearLoad { f0, f1 },
            obstacles: obstacles.into_iter().map(|(_, o)| o).collect(),
        };
        Ok((problem, settings))
    }

    /// The length and E·J along the beam: the stretches of their own, the gaps filled with
    /// the beam's E·J.
    fn beam(&self, beam: &BeamSpec) -> Result<(f64, Vec<StiffnessPiece>), SceneError> {
        let length = self.positive("beam.length", beam.length, "m")?;
        let young = self.positive("beam.young", beam.young, "Pa")?;
        let inertia = self.section("beam.section", &beam.section)?;
        let base = self.bending_stiffness("beam", young, inertia)?;
        let mut segments = Vec::with_capacity(beam.segments.len());
        for (i, segment) in beam.segments.iter().enumerate() {
            segments.push(self.segment(i, segment, length, young, inertia)?);
        }
        segments.sort_by(|a, b| a.1.total_cmp(&b.1));
        self.segments_apart(&segments)?;
        Ok((length, fill_stiffness(&segments, base, length)))
    }

    /// One `[[beam.segment]]` as (index, from, to, E·J).
    fn segment(
        &self,
        i: usize,
        segment: &SegmentSpec,
        length: f64,
        young: f64,
        inertia: f64,
    ) -> Result<Segment, SceneError> {
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
        Ok((i, from, to, ej))
    }

    /// Segments sorted by start must not overlap.
    fn segments_apart(&self, segments: &[Segment]) -> Result<(), SceneError> {
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
        Ok(())
    }

    /// The obstacles with their index in the file, sorted by position.
    fn obstacles(
        &self,
        specs: &[ObstacleSpec],
        length: f64,
    ) -> Result<Vec<(usize, Obstacle)>, SceneError> {
        if specs.len() > MAX_OBSTACLES {
            return Err(self.error(
                "obstacle",
                format!(
                    "{} obstacles: at most {MAX_OBSTACLES} are supported",
                    specs.len()
                ),
            ));
        }
        let mut obstacles = Vec::with_capacity(specs.len());
        for (i, o) in specs.iter().enumerate() {
            obstacles.push((i, self.obstacle(i, o, length)?));
        }
        obstacles.sort_by(|a, b| a.1.x.total_cmp(&b.1.x));
        Ok(obstacles)
    }

    /// One `[[obstacle]]`: strictly inside the beam, thresholds zero or positive. Field names
    /// are written only for an error: a scene of thousands of obstacles is checked on every
    /// key of the explorer.
    fn obstacle(&self, i: usize, o: &ObstacleSpec, length: f64) -> Result<Obstacle, SceneError> {
        let field = |name: &str| format!("obstacle[{}].{name}", i + 1);
        let x = o.x;
        if !x.is_finite() {
            return Err(self.not_finite(field("x"), x));
        }
        if !(x > 0.0 && x < length) {
            return Err(self.error(
                field("x"),
                format!(
                    "= {} m: must lie strictly inside (0, l) = (0, {}) m",
                    show(x),
                    show(length)
                ),
            ));
        }
        for (name, value, unit) in [("sliding", o.sliding, "N"), ("swivel", o.swivel, "N m")] {
            if !value.is_finite() {
                return Err(self.not_finite(field(name), value));
            }
            if value < 0.0 {
                return Err(self.error(
                    field(name),
                    format!(
                        "= {} {unit}: a friction threshold must be zero or positive",
                        show(value)
                    ),
                ));
            }
        }
        Ok(Obstacle {
            x,
            sliding_threshold: o.sliding,
            swivel_threshold: o.swivel,
        })
    }

    /// Obstacles sorted by position must be at distinct points, `gap` apart.
    fn obstacles_apart(&self, obstacles: &[(usize, Obstacle)], gap: f64) -> Result<(), SceneError> {
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
        Ok(())
    }

    /// No obstacle within `gap` of a support or of a segment end (unless exactly on it).
    fn obstacles_clear(
        &self,
        obstacles: &[(usize, Obstacle)],
        stiffness: &[StiffnessPiece],
        length: f64,
        gap: f64,
    ) -> Result<(), SceneError> {
        for &(i, o) in obstacles {
            let nearest_support = o.x.min(length - o.x);
            if nearest_support < gap {
                return Err(self.error(
                    format!("obstacle[{}].x", i + 1),
                    format!("= {} m: closer than {gap:e} m (1e-9 l) to a support", o.x),
                ));
            }
            for piece in stiffness {
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
        Ok(())
    }

    /// Every stretch of constant E·J at least `gap` long.
    fn stretches_long_enough(
        &self,
        stiffness: &[StiffnessPiece],
        gap: f64,
    ) -> Result<(), SceneError> {
        for piece in stiffness {
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
        Ok(())
    }

    /// Mesh size, ε and the panels.
    fn settings(&self, scene: &Scene) -> Result<Settings, SceneError> {
        let elements = scene.mesh.elements;
        check_elements(elements).map_err(|rule| self.error("mesh.elements", rule))?;
        let epsilon = scene.solver.epsilon;
        check_epsilon(epsilon).map_err(|rule| self.error("solver.epsilon", rule))?;
        if scene.view.panels.is_empty() {
            let names: Vec<String> = Panel::ALL
                .iter()
                .map(|p| format!("\"{}\"", p.name()))
                .collect();
            return Err(self.error(
                "view.panels",
                format!("is empty: list at least one of {}", names.join(", ")),
            ));
        }
        if let Some(select) = &scene.view.select {
            let fields = scene.parameter_fields();
            if !fields.contains(select) {
                return Err(self.error(
                    "view.select",
                    format!(
                        "= \"{}\": must name a parameter of this scene, one of {}",
                        crate::format::printable(select),
                        fields.join(", ")
                    ),
                ));
            }
        }
        Ok(Settings {
            elements,
            method: scene.solver.method,
            epsilon,
        })
    }
}

/// A `[[beam.segment]]` after validation: (index in the file, from, to, E·J).
type Segment = (usize, f64, f64, f64);

/// The stretches of constant E·J covering [0, l]: the segments (sorted, apart), the gaps
/// between them with the beam's `base` E·J.
fn fill_stiffness(segments: &[Segment], base: f64, length: f64) -> Vec<StiffnessPiece> {
    let mut stiffness = Vec::new();
    let mut cursor = 0.0;
    for &(_, from, to, ej) in segments {
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
    stiffness
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panel_name_is_its_serialized_form() {
        for panel in Panel::ALL {
            let json = serde_json::to_value(panel).unwrap();
            assert_eq!(json.as_str(), Some(panel.name()));
        }
    }
}
