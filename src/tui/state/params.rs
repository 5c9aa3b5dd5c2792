//! The explorer's parameter list: which rows a scene has, how each is labelled and shown (with
//! its unit, in engineering form), and how a keystroke or typed text changes it. Changes return
//! a candidate scene; the update function validates it with the scene rules before keeping it,
//! so the explorer accepts exactly what a scene file would.
//!
//! Steps: loads, modulus, section dimensions, thresholds and ε move on a log scale (×10^0.1
//! fine, ×10 coarse; zero steps to ±1 unit), obstacle positions linearly (l/200 fine, l/20
//! coarse, never past a neighbour or a support), elements by 10 % (at least one) or ×10, and
//! the method cycles.

use crate::format::eng;
use crate::scene::{MAX_ELEMENTS, Scene, Section};
use crate::solve::Method;

/// A dimension of the cross-section.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dimension {
    Width,
    Height,
    Radius,
    Inertia,
}

/// One editable row.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Row {
    LoadStart,
    LoadEnd,
    Young,
    Section(Dimension),
    ObstacleX(usize),
    Sliding(usize),
    Swivel(usize),
    Epsilon,
    Elements,
    Method,
}

/// The rows of `scene`, in display order.
pub fn rows(scene: &Scene) -> Vec<Row> {
    let mut rows = vec![Row::LoadStart, Row::LoadEnd, Row::Young];
    match scene.beam.section {
        Section::Rectangle { .. } => {
            rows.push(Row::Section(Dimension::Width));
            rows.push(Row::Section(Dimension::Height));
        }
        Section::Circle { .. } => rows.push(Row::Section(Dimension::Radius)),
        Section::Custom { .. } => rows.push(Row::Section(Dimension::Inertia)),
    }
    for i in 0..scene.obstacles.len() {
        rows.extend([Row::ObstacleX(i), Row::Sliding(i), Row::Swivel(i)]);
    }
    rows.extend([Row::Epsilon, Row::Elements, Row::Method]);
    rows
}

impl Row {
    /// The label, e.g. `load f0 (x = 0)`.
    pub fn label(self) -> String {
        match self {
            Row::LoadStart => "load f0 (x=0)".into(),
            Row::LoadEnd => "load f1 (x=l)".into(),
            Row::Young => "modulus E".into(),
            Row::Section(Dimension::Width) => "width".into(),
            Row::Section(Dimension::Height) => "height".into(),
            Row::Section(Dimension::Radius) => "radius".into(),
            Row::Section(Dimension::Inertia) => "inertia J".into(),
            Row::ObstacleX(i) => format!("obstacle {} x", i + 1),
            Row::Sliding(_) => "  sliding g1".into(),
            Row::Swivel(_) => "  swivel g2".into(),
            Row::Epsilon => "epsilon ε".into(),
            Row::Elements => "elements n".into(),
            Row::Method => "method".into(),
        }
    }

    /// The scene file's name of the value, as the scene's rules name it (`mesh.elements`,
    /// `obstacle[2].x`).
    pub fn field(self) -> String {
        match self {
            Row::LoadStart => "load.f0".into(),
            Row::LoadEnd => "load.f1".into(),
            Row::Young => "beam.young".into(),
            Row::Section(Dimension::Width) => "beam.section.width".into(),
            Row::Section(Dimension::Height) => "beam.section.height".into(),
            Row::Section(Dimension::Radius) => "beam.section.radius".into(),
            Row::Section(Dimension::Inertia) => "beam.section.inertia".into(),
            Row::ObstacleX(i) => format!("obstacle[{}].x", i + 1),
            Row::Sliding(i) => format!("obstacle[{}].sliding", i + 1),
            Row::Swivel(i) => format!("obstacle[{}].swivel", i + 1),
            Row::Epsilon => "solver.epsilon".into(),
            Row::Elements => "mesh.elements".into(),
            Row::Method => "solver.method".into(),
        }
    }

    /// The unit of the value.
    pub fn unit(self) -> &'static str {
        match self {
            Row::LoadStart | Row::LoadEnd => "N/m",
            Row::Young => "Pa",
            Row::Section(Dimension::Inertia) => "m^4",
            Row::Section(_) | Row::ObstacleX(_) => "m",
            Row::Sliding(_) => "N",
            Row::Swivel(_) => "N m",
            Row::Epsilon | Row::Elements | Row::Method => "",
        }
    }

    /// The obstacle a row belongs to.
    /// The same kind of row for obstacle `index` (other rows unchanged).
    pub fn for_obstacle(self, index: usize) -> Row {
        match self {
            Row::ObstacleX(_) => Row::ObstacleX(index),
            Row::Sliding(_) => Row::Sliding(index),
            Row::Swivel(_) => Row::Swivel(index),
            other => other,
        }
    }

    pub fn obstacle(self) -> Option<usize> {
        match self {
            Row::ObstacleX(i) | Row::Sliding(i) | Row::Swivel(i) => Some(i),
            _ => None,
        }
    }

    /// The value as a number, for rows that have one.
    pub fn number(self, scene: &Scene) -> Option<f64> {
        Some(match self {
            Row::LoadStart => scene.load.f0,
            Row::LoadEnd => scene.load.f1(),
            Row::Young => scene.beam.young,
            Row::Section(d) => section_value(&scene.beam.section, d)?,
            Row::ObstacleX(i) => scene.obstacles.get(i)?.x,
            Row::Sliding(i) => scene.obstacles.get(i)?.sliding,
            Row::Swivel(i) => scene.obstacles.get(i)?.swivel,
            Row::Epsilon => scene.solver.epsilon,
            Row::Elements => scene.mesh.elements as f64,
            Row::Method => return None,
        })
    }

    /// The value as shown: engineering form and unit.
    pub fn value(self, scene: &Scene) -> String {
        match self {
            Row::Method => scene.solver.method.name().to_string(),
            Row::Elements => scene.mesh.elements.to_string(),
            _ => {
                let number = self.number(scene).map_or("?".into(), eng);
                if self.unit().is_empty() {
                    number
                } else {
                    format!("{number} {}", self.unit())
                }
            }
        }
    }
}

fn section_value(section: &Section, d: Dimension) -> Option<f64> {
    match (*section, d) {
        (Section::Rectangle { width, .. }, Dimension::Width) => Some(width),
        (Section::Rectangle { height, .. }, Dimension::Height) => Some(height),
        (Section::Circle { radius }, Dimension::Radius) => Some(radius),
        (Section::Custom { inertia }, Dimension::Inertia) => Some(inertia),
        _ => None,
    }
}

fn set_number(scene: &mut Scene, row: Row, value: f64) {
    match row {
        Row::LoadStart => {
            // Keep a constant load constant: f1 follows f0 when it was not given.
            scene.load.f0 = value;
        }
        Row::LoadEnd => scene.load.f1 = Some(value),
        Row::Young => scene.beam.young = value,
        Row::Section(d) => {
            let s = &mut scene.beam.section;
            match (s, d) {
                (Section::Rectangle { width, .. }, Dimension::Width) => *width = value,
                (Section::Rectangle { height, .. }, Dimension::Height) => *height = value,
                (Section::Circle { radius }, Dimension::Radius) => *radius = value,
                (Section::Custom { inertia }, Dimension::Inertia) => *inertia = value,
                _ => {}
            }
        }
        Row::ObstacleX(i) => scene.obstacles[i].x = value,
        Row::Sliding(i) => scene.obstacles[i].sliding = value,
        Row::Swivel(i) => scene.obstacles[i].swivel = value,
        Row::Epsilon => scene.solver.epsilon = value,
        Row::Elements => {
            // Out-of-range counts are left for validation to reject with its message.
            scene.mesh.elements = if value.is_finite() && value >= 0.0 {
                value.round().min(usize::MAX as f64) as usize
            } else {
                0
            }
        }
        Row::Method => {}
    }
}

/// A log-scale step of `value` up (direction +1) or down (−1) in magnitude, fine (×10^0.1) or
/// coarse (×10); zero steps to ±1. A coarse step shifts the decimal exponent of the value as
/// written (5e4 → 5e5, 1e-16 → 1e-15), so it lands on the number a user would type and never
/// drifts (sixteen steps from 1e-16 reach exactly 1). A fine step from a point of the grid
/// 10^(j/10) moves to the next point of that grid (ten of them make exactly one decade); from
/// any other value it multiplies by 10^0.1.
fn log_step(value: f64, direction: i32, coarse: bool) -> f64 {
    if value == 0.0 {
        return f64::from(direction.signum());
    }
    let up = (direction > 0) == (value > 0.0);
    let magnitude = value.abs();
    let stepped = if coarse {
        decade_shift(magnitude, if up { 1 } else { -1 })
    } else {
        tenth_decade_step(magnitude, up)
    };
    stepped.copysign(value)
}

/// `magnitude` (> 0) with its decimal exponent moved by `decades`, digits kept.
fn decade_shift(magnitude: f64, decades: i32) -> f64 {
    let written = format!("{magnitude:e}");
    let shifted = written.split_once('e').and_then(|(digits, exponent)| {
        let exponent: i32 = exponent.parse().ok()?;
        format!("{digits}e{}", exponent + decades)
            .parse::<f64>()
            .ok()
    });
    shifted.unwrap_or(magnitude * 10f64.powi(decades))
}

/// One fine step of `magnitude` (> 0): along the grid 10^(j/10) when it lies on it.
fn tenth_decade_step(magnitude: f64, up: bool) -> f64 {
    let tenths = magnitude.log10() * 10.0;
    let nearest = tenths.round();
    let on_grid = tenths.is_finite()
        && nearest.abs() < 1e4
        && (grid_point(nearest as i32) / magnitude - 1.0).abs() < 1e-12;
    if on_grid {
        grid_point(nearest as i32 + if up { 1 } else { -1 })
    } else {
        let factor = 10f64.powf(0.1);
        if up {
            magnitude * factor
        } else {
            magnitude / factor
        }
    }
}

/// 10^(j/10), as the decimal number written with the shortest digits of 10^((j mod 10)/10):
/// the same double however it is reached, and exactly 10^(j/10) at every decade.
fn grid_point(tenths: i32) -> f64 {
    let decade = tenths.div_euclid(10);
    let within = tenths.rem_euclid(10);
    let digits = 10f64.powf(f64::from(within) / 10.0);
    format!("{digits}e{decade}")
        .parse()
        .unwrap_or(f64::INFINITY)
}

/// The scene after one step of `row` (fine or coarse) in `direction` (+1 or −1). Not yet
/// validated.
pub fn step(scene: &Scene, row: Row, direction: i32, coarse: bool) -> Scene {
    let mut next = scene.clone();
    match row {
        Row::Method => {
            let all = Method::ALL;
            let i = all
                .iter()
                .position(|m| *m == scene.solver.method)
                .unwrap_or(0);
            let j = (i as i32 + direction).rem_euclid(all.len() as i32) as usize;
            next.solver.method = all[j];
        }
        Row::Elements => {
            let n = scene.mesh.elements as f64;
            let target = if coarse {
                if direction > 0 { n * 10.0 } else { n / 10.0 }
            } else {
                let change = (n * 0.1).round().max(1.0);
                n + f64::from(direction) * change
            };
            next.mesh.elements = target.round().clamp(1.0, MAX_ELEMENTS as f64) as usize;
        }
        Row::ObstacleX(i) => {
            let l = scene.beam.length;
            let step = if coarse { l / 20.0 } else { l / 200.0 };
            let x = scene.obstacles[i].x + f64::from(direction) * step;
            // Never past a neighbour or a support: stop a thousandth of l before it.
            let gap = l / 1000.0;
            let lower = if i == 0 {
                0.0
            } else {
                scene.obstacles[i - 1].x
            } + gap;
            let upper = scene.obstacles.get(i + 1).map_or(l, |o| o.x) - gap;
            next.obstacles[i].x = x.clamp(lower, upper.max(lower));
        }
        _ => {
            if let Some(value) = row.number(scene) {
                set_number(&mut next, row, log_step(value, direction, coarse));
            }
        }
    }
    next
}

/// The scene with `row` set from typed text. Errors say what would be accepted.
pub fn set_from_text(scene: &Scene, row: Row, text: &str) -> Result<Scene, String> {
    let text = text.trim();
    let mut next = scene.clone();
    if row == Row::Method {
        let method = Method::ALL
            .into_iter()
            .find(|m| m.name() == text)
            .ok_or_else(|| {
                let names: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
                format!("'{text}' is not a method; one of {}", names.join(", "))
            })?;
        next.solver.method = method;
        return Ok(next);
    }
    let value: f64 = text
        .parse()
        .map_err(|_| format!("'{text}' is not a number (write e.g. 5e4 or 0.8)"))?;
    // Quoted as typed: the number it reads as may not say it (1e400 is infinity, and a count
    // of 1e300 elements is none the machine can hold).
    if !value.is_finite() {
        return Err(format!(
            "{} = {text}: must be a finite number (at most 1.8e308 in size)",
            row.field()
        ));
    }
    if row == Row::Elements
        && (value.fract() != 0.0 || !(1.0..=MAX_ELEMENTS as f64).contains(&value))
    {
        return Err(format!(
            "{} = {text}: must be a whole number from 1 to {MAX_ELEMENTS}",
            row.field()
        ));
    }
    set_number(&mut next, row, value);
    Ok(next)
}
