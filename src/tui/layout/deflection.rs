//! The deflection panel's chart, laid out: what it draws in real values (the curve — u, M or T,
//! or its difference from the reference — the reference curve, the obstacles by state, the key
//! and the y range) and where its plot sits in a panel. Drawing (`tui::view::charts`) and
//! mouse hit-testing (an obstacle under the pointer, a drag's position) both take it from
//! here, so a click lands on what is drawn.

use ratatui::layout::Rect;

use crate::plot::{
    AxisKind, AxisSpec, KeyEntry, PlotArea, Theme, curve_key, key_layout, marker_char,
};
use crate::scene::Panel;
use crate::solve::Solution;
use crate::tui::jobs::solve::Solved;
use crate::tui::jobs::sweeps::IterateField;
use crate::tui::state::motion::state_word;
use crate::tui::state::sweeps::SweepView;
use crate::tui::state::{App, Diagram};

/// The obstacles' states, in the words of the results panel ([`state_word`]),
/// and their markers (Unicode, ASCII).
pub const STATE_NAMES: [&str; 6] = ["stuck", "slides", "swivels", "both", "creeps", "unknown"];
pub const STATE_MARKERS: [(char, char); 6] = [
    ('●', 'o'),
    ('↕', 'S'),
    ('↻', 'W'),
    ('✱', 'X'),
    ('≈', '~'),
    ('?', '?'),
];

/// What the deflection panel draws, in real values: the curve (u, M or T, or its difference
/// from the reference), the reference curve, the obstacles by state, the key and the y range.
pub struct DeflectionData {
    pub length: f64,
    pub curve: Vec<(f64, f64)>,
    pub reference_curve: Vec<(f64, f64)>,
    /// The selected iterate's curve (the iterations panel's `<` `>`), when one other than the
    /// last is selected and its field has arrived.
    pub iterate_curve: Vec<(f64, f64)>,
    pub states: [Vec<(f64, f64)>; 6],
    pub key: Vec<KeyEntry>,
    pub y_range: [f64; 2],
    /// Stretches whose E·J differs from the beam's (the longest stretch's), with the glyph
    /// that marks each along the x axis.
    pub segments: Vec<Segment>,
    /// The position [m] of the obstacle whose parameter is selected, marked by a rule.
    pub selected_obstacle: Option<f64>,
    /// Every obstacle's point (x, value) in order, for its number beside its marker.
    pub obstacles: Vec<(f64, f64)>,
}

/// A stretch of the beam of its own stiffness, as the x axis marks it.
pub struct Segment {
    pub from: f64,
    pub to: f64,
    pub glyph: char,
}

/// The glyphs marking stiffer or softer stretches along the x axis (Unicode, ASCII), in turn.
pub const SEGMENT_GLYPHS: [(char, char); 3] = [('━', '='), ('═', '~'), ('▀', '^')];

pub const REFERENCE_MARKER: (char, char) = ('·', '.');
/// The selected iterate's curve.
pub const ITERATE_MARKER: (char, char) = ('∘', 'o');
pub const WALL: (char, char) = ('▒', '#');
/// Rows the deflection chart keeps before its key takes the rest.
pub const DEFLECTION_ROWS: u16 = 5;

/// The deflection panel's data for a panel of `area`, or the notice to show instead.
pub fn deflection_data(app: &App, theme: &Theme, area: Rect) -> Result<DeflectionData, String> {
    let Some(shown) = &app.exploration.shown else {
        return Err(format!("solving n = {} …", app.exploration.wanted.elements));
    };
    let solution = match &shown.solution {
        Ok(s) => s,
        Err(e) => return Err(format!("no solution: {e}")),
    };
    let difference = app.show_difference;
    let reference = shown.reference.as_ref();
    if difference && reference.is_none() {
        return Err(if solution.method == crate::solve::Method::Condensed {
            "this is the reference method (condensed): nothing to compare with; c goes back"
        } else {
            "no reference: the condensed method gave no solution on this mesh; c goes back"
        }
        .into());
    }
    let l = shown.request.problem.length;
    let samples = (area.width as usize * 2).clamp(20, 400);
    let value_of = |s: &Solution, x: f64| diagram_value(app, shown, s, x);
    let value = |x: f64| match (difference, reference) {
        (true, Some(r)) => value_of(solution, x) - value_of(r, x),
        _ => value_of(solution, x),
    };
    let xs: Vec<f64> = (0..samples)
        .map(|i| l * i as f64 / (samples - 1) as f64)
        .collect();
    let finite = |points: Vec<(f64, f64)>| -> Vec<(f64, f64)> {
        points.into_iter().filter(|(_, y)| y.is_finite()).collect()
    };
    let curve = finite(xs.iter().map(|&x| (x, value(x))).collect());
    let reference_curve = match (difference, reference) {
        (false, Some(r)) => finite(xs.iter().map(|&x| (x, value_of(r, x))).collect()),
        _ => Vec::new(),
    };
    let (iterate_curve, iterate_key) = iterate_curve(app, theme, &xs);
    if curve.is_empty() {
        return Err("no finite values to draw (see the warnings)".into());
    }
    // The range covers both curves and zero (the clamped ends, and the u = 0 line).
    let (min, max) = curve
        .iter()
        .chain(&reference_curve)
        .chain(&iterate_curve)
        .fold((0.0f64, 0.0f64), |(a, b), &(_, y)| (a.min(y), b.max(y)));
    let method = solution.method;
    let mut key = vec![KeyEntry {
        marker: curve_key(theme),
        name: if difference {
            format!("{method} − condensed")
        } else {
            method.name().to_string()
        },
        style: theme.series(0),
        short: None,
    }];
    if !reference_curve.is_empty() {
        key.push(KeyEntry {
            marker: marker_char(theme, REFERENCE_MARKER.0, REFERENCE_MARKER.1),
            name: "condensed = reference (c: difference)".into(),
            style: theme.series(6),
            short: None,
        });
    }
    key.extend(iterate_key);
    key.push(KeyEntry {
        marker: marker_char(theme, WALL.0, WALL.1),
        name: "clamped".into(),
        // Text is never dark grey (the theme's rule): the key in the secondary style.
        style: theme.dim(),
        short: None,
    });
    let beam = &app.scene().beam;
    let beam_stiffness = beam.young * beam.section.inertia();
    let segments = segments(&shown.request.problem, beam_stiffness, theme, &mut key);
    let selected_obstacle = app
        .exploration
        .selected_row()
        .obstacle()
        .and_then(|i| solution.obstacles.get(i))
        .map(|o| o.x);
    let mut states: [Vec<(f64, f64)>; 6] = Default::default();
    let mut obstacles = Vec::new();
    let regularized = method.is_regularized();
    for o in &solution.obstacles {
        let word = state_word(o, regularized, shown.max_deflection);
        let state = STATE_NAMES.iter().position(|n| *n == word).unwrap_or(5);
        let y = value(o.x);
        if y.is_finite() {
            states[state].push((o.x, y));
        }
        obstacles.push((o.x, y));
    }
    for (i, points) in states.iter().enumerate() {
        if !points.is_empty() {
            let (u, a) = STATE_MARKERS[i];
            key.push(KeyEntry {
                marker: marker_char(theme, u, a),
                name: format!("obstacle {}", STATE_NAMES[i]),
                style: theme.series(i + 1),
                short: None,
            });
        }
    }
    Ok(DeflectionData {
        length: l,
        curve,
        reference_curve,
        iterate_curve,
        states,
        key,
        y_range: [min, max],
        segments,
        selected_obstacle,
        obstacles,
    })
}

/// The stretches whose E·J is not the beam's own (`[beam]`'s E times its section's J), each
/// with its glyph and an entry in the key: `━ EJ 2.9e9 N m² on 0.3–0.6 m (beam 2.9e3)`.
fn segments(
    problem: &crate::model::Problem,
    beam: f64,
    theme: &Theme,
    key: &mut Vec<KeyEntry>,
) -> Vec<Segment> {
    let pieces = &problem.stiffness;
    // Equal up to rounding of the product E·J.
    let is_beam = |ej: f64| (ej - beam).abs() <= 1e-12 * beam.abs();
    let mut segments = Vec::new();
    for piece in pieces.iter().filter(|p| !is_beam(p.bending_stiffness)) {
        let (u, a) = SEGMENT_GLYPHS[segments.len() % SEGMENT_GLYPHS.len()];
        let glyph = marker_char(theme, u, a);
        key.push(KeyEntry {
            marker: glyph,
            name: format!(
                "EJ {} N m² on {}–{} m (beam {})",
                crate::format::sci(piece.bending_stiffness, 2),
                crate::format::eng(piece.from),
                crate::format::eng(piece.to),
                crate::format::sci(beam, 2),
            ),
            style: theme.plain(),
            short: Some(format!(
                "EJ {} on {}–{} m",
                crate::format::sci(piece.bending_stiffness, 1),
                crate::format::eng(piece.from),
                crate::format::eng(piece.to),
            )),
        });
        segments.push(Segment {
            from: piece.from,
            to: piece.to,
            glyph,
        });
    }
    // More than two: one entry for them all, so that the key leaves the chart its rows.
    if segments.len() > 2 {
        let own: Vec<f64> = pieces
            .iter()
            .map(|p| p.bending_stiffness)
            .filter(|ej| !is_beam(*ej))
            .collect();
        let low = own.iter().copied().fold(f64::INFINITY, f64::min);
        let high = own.iter().copied().fold(0.0, f64::max);
        key.truncate(key.len() - segments.len());
        key.push(KeyEntry {
            marker: segments[0].glyph,
            name: format!(
                "{} stretches, EJ {} … {} N m²",
                segments.len(),
                crate::format::sci(low, 2),
                crate::format::sci(high, 2),
            ),
            style: theme.plain(),
            short: Some(format!("{} stretches of their own EJ", segments.len())),
        });
    }
    segments
}

/// The deflection chart's axes in `plot` (the panel inside its borders, above its key).
pub fn deflection_plot(data: &DeflectionData, plot: Rect) -> Option<PlotArea> {
    let x_axis = AxisSpec {
        kind: AxisKind::Linear,
        range: [0.0, data.length],
        title: "x [m]".into(),
    };
    let y_axis = AxisSpec {
        kind: AxisKind::Linear,
        range: data.y_range,
        title: String::new(),
    };
    PlotArea::new(plot, &x_axis, &y_axis)
}

/// The selected iterate's curve at `xs` and its key entry, when the iterations panel selects
/// one other than the last and its field has arrived (not with the difference u − u_ref).
fn iterate_curve(app: &App, theme: &Theme, xs: &[f64]) -> (Vec<(f64, f64)>, Option<KeyEntry>) {
    let Some(iterate) = iterate_field(app).filter(|_| !app.show_difference) else {
        return (Vec::new(), None);
    };
    let curve: Vec<(f64, f64)> = xs
        .iter()
        .map(|&x| (x, diagram_point(app, iterate.field.at(&iterate.mesh, x))))
        .filter(|(_, y)| y.is_finite())
        .collect();
    let key = (!curve.is_empty()).then(|| KeyEntry {
        marker: marker_char(theme, ITERATE_MARKER.0, ITERATE_MARKER.1),
        name: format!("iterate {} (< >)", iterate.iteration),
        style: theme.series(3),
        short: None,
    });
    (curve, key)
}

/// The selected iterate's field, when the iterations panel has one other than the last.
fn iterate_field(app: &App) -> Option<&IterateField> {
    match app
        .exploration
        .sweep_view::<IterateField>(Panel::Iterations)
    {
        SweepView::Ready(field) => Some(field),
        _ => None,
    }
}

/// The value the deflection panel shows at `x`: u, M or T.
fn diagram_value(app: &App, shown: &Solved, solution: &Solution, x: f64) -> f64 {
    diagram_point(app, solution.field.at(&shown.mesh, x))
}

/// What the deflection panel shows of a point of a field: u, M or T.
fn diagram_point(app: &App, p: crate::fem::PointValues) -> f64 {
    match app.exploration.diagram {
        Diagram::Deflection => p.deflection,
        Diagram::Moment => p.moment,
        Diagram::Shear => p.shear,
    }
}

/// Where the deflection chart puts x = 0 … l on screen: the first and last column of its plot
/// (x = 0 and x = l), as ratatui's chart lays out the plot right of the y labels and its axis
/// line, inside the panel's borders. Mouse hit-testing maps columns to positions with it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeflectionColumns {
    pub first: u16,
    pub last: u16,
    /// The rows of the plot (the panel inside its borders).
    pub top: u16,
    pub bottom: u16,
    /// The beam's length l [m].
    pub length: f64,
}

impl DeflectionColumns {
    /// The column a point at `x` [m] is drawn in (the chart rounds to the nearest cell).
    pub fn column_of(&self, x: f64) -> u16 {
        let span = f64::from(self.last - self.first);
        let unit = (x / self.length).clamp(0.0, 1.0);
        self.first + (unit * span).round() as u16
    }

    /// The position [m] drawn at `column` (clamped to the plot).
    pub fn x_at(&self, column: u16) -> f64 {
        let span = f64::from(self.last - self.first).max(1.0);
        let column = column.clamp(self.first, self.last);
        self.length * f64::from(column - self.first) / span
    }

    /// Is the cell at `x`, `y` inside the plot?
    pub fn contains(&self, x: u16, y: u16) -> bool {
        (self.first..=self.last).contains(&x) && (self.top..self.bottom).contains(&y)
    }
}

/// The deflection chart's columns in a panel of `area`, when it draws a chart (a solution with
/// finite values, and room for a plot at least two columns wide).
pub fn deflection_columns(app: &App, area: Rect) -> Option<DeflectionColumns> {
    // The same data, key and axes as the drawing (see `deflection`).
    let theme = Theme::new(app.look, app.palette, app.markers);
    let data = deflection_data(app, &theme, area).ok()?;
    let inner = theme.block("", false).inner(area);
    let plot = key_layout(&theme, inner, &[], &[], &data.key, DEFLECTION_ROWS).0;
    let plot = deflection_plot(&data, plot)?;
    let graph = plot.graph;
    (graph.width > 1).then_some(DeflectionColumns {
        first: graph.left(),
        last: graph.right() - 1,
        top: graph.top(),
        bottom: graph.bottom(),
        length: data.length,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_marker_reads_in_ascii_text_as_its_ascii_legend_shows_it() {
        use crate::plot::ascii_char;
        for (unicode, ascii) in STATE_MARKERS.into_iter().chain([ITERATE_MARKER, WALL]) {
            assert_eq!(ascii_char(unicode), ascii, "{unicode}");
        }
    }
}
