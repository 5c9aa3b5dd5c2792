//! The chart panels of the explorer: each reads the state it shows from the [`App`] and draws
//! it with the shared charts of [`crate::plot`] (the deflection here, the study charts there).
//! The deflection (or moment, or shear) is drawn with the reference solution (`condensed` on
//! the same mesh, solved on the worker) as a second curve under it, or, with `c`, the
//! difference from the reference on its own scale; nice linear ticks and a zero line.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::widgets::{Dataset, GraphType};

use crate::plot::{
    AxisKind, AxisSpec, CurrentRun, KeyEntry, PanelFrame, PlotArea, Theme, curve_key, curve_marker,
    eps_condition_chart, eps_error_chart, error_time_chart, key_layout, marker_char, notice,
    panel_with_key, point_marker,
};
use crate::scene::Panel;
use crate::solve::Solution;
use crate::study::{EpsPoint, MeshPoint};
use crate::tui::app::{App, Diagram, Shown};
use crate::tui::studies::StudyView;

/// The title's mark of a chart whose data belongs to the state before.
fn updating<T>(view: &StudyView<T>) -> &'static str {
    match view {
        StudyView::Outdated(_) => " · updating…",
        _ => "",
    }
}

/// Draws `panel` into `area`.
pub(super) fn draw_panel(
    frame: &mut Frame,
    app: &App,
    theme: &Theme,
    panel: Panel,
    area: Rect,
    title_suffix: &str,
    focused: bool,
) {
    let frame_of = |title: String| PanelFrame {
        area,
        title,
        focused,
    };
    match panel {
        Panel::Deflection => deflection(frame, app, theme, area, title_suffix, focused),
        Panel::EpsError => {
            let view = app.study_view::<Vec<EpsPoint>>(Panel::EpsError);
            let panel = frame_of(format!(
                " Error vs ε (regularised){title_suffix}{} ",
                updating(&view)
            ));
            match view {
                StudyView::Ready(points) | StudyView::Outdated(points) => {
                    let epsilon = Some(app.scene.solver.epsilon);
                    eps_error_chart(frame, theme, panel, points, epsilon)
                }
                StudyView::Notice(text) => notice(frame, theme, panel, text),
            }
        }
        Panel::EpsCond => {
            let view = app.study_view::<Vec<EpsPoint>>(Panel::EpsCond);
            let panel = frame_of(format!(
                " cond2 of the cases vs ε{title_suffix}{} ",
                updating(&view)
            ));
            match view {
                StudyView::Ready(points) | StudyView::Outdated(points) => {
                    let epsilon = Some(app.scene.solver.epsilon);
                    eps_condition_chart(frame, theme, panel, points, epsilon)
                }
                StudyView::Notice(text) => notice(frame, theme, panel, text),
            }
        }
        Panel::ErrorTime => {
            let view = app.study_view::<Vec<MeshPoint>>(Panel::ErrorTime);
            let panel = frame_of(if app.show_timings {
                format!(" Error vs run time{title_suffix}{} ", updating(&view))
            } else {
                format!(" Error vs n (t: time){title_suffix}{} ", updating(&view))
            });
            match view {
                StudyView::Ready(points) | StudyView::Outdated(points) => {
                    let current = CurrentRun {
                        elements: app.scene.mesh.elements,
                        method: app.scene.solver.method,
                    };
                    error_time_chart(frame, theme, panel, points, app.show_timings, Some(current))
                }
                StudyView::Notice(text) => notice(frame, theme, panel, text),
            }
        }
    }
}

/// The obstacles' states, in the words of the results panel ([`super::results::state_word`]),
/// and their markers (Unicode, ASCII).
const STATE_NAMES: [&str; 6] = ["stuck", "slides", "swivels", "both", "creeps", "unknown"];
const STATE_MARKERS: [(char, char); 6] = [
    ('●', 'o'),
    ('↕', 'S'),
    ('↻', 'W'),
    ('✱', 'X'),
    ('≈', '~'),
    ('?', '?'),
];

/// What the deflection panel draws, in real values: the curve (u, M or T, or its difference
/// from the reference), the reference curve, the obstacles by state, the key and the y range.
struct DeflectionData {
    length: f64,
    curve: Vec<(f64, f64)>,
    reference_curve: Vec<(f64, f64)>,
    states: [Vec<(f64, f64)>; 6],
    key: Vec<KeyEntry>,
    y_range: [f64; 2],
}

const REFERENCE_MARKER: (char, char) = ('·', ':');
const WALL: (char, char) = ('▒', '#');
/// Rows the deflection chart keeps before its key takes the rest.
const DEFLECTION_ROWS: u16 = 5;

/// The deflection panel's data for a panel of `area`, or the notice to show instead.
fn deflection_data(app: &App, theme: &Theme, area: Rect) -> Result<DeflectionData, String> {
    let Some(shown) = &app.shown else {
        return Err(format!("solving n = {} …", app.wanted.elements));
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
    if curve.is_empty() {
        return Err("no finite values to draw (see the warnings)".into());
    }
    // The range covers both curves and zero (the clamped ends, and the u = 0 line).
    let (min, max) = curve
        .iter()
        .chain(&reference_curve)
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
    key.push(KeyEntry {
        marker: marker_char(theme, WALL.0, WALL.1),
        name: "clamped".into(),
        // Text is never dark grey (the theme's rule): the key in the secondary style.
        style: theme.dim(),
        short: None,
    });
    let mut states: [Vec<(f64, f64)>; 6] = Default::default();
    let regularized = method.is_regularized();
    for o in &solution.obstacles {
        let word = super::results::state_word(o, regularized, shown.max_deflection);
        let state = STATE_NAMES.iter().position(|n| *n == word).unwrap_or(5);
        let y = value(o.x);
        if y.is_finite() {
            states[state].push((o.x, y));
        }
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
        states,
        key,
        y_range: [min, max],
    })
}

/// The deflection chart's axes in `plot` (the panel inside its borders, above its key).
fn deflection_plot(data: &DeflectionData, plot: Rect) -> Option<PlotArea> {
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

/// The value the deflection panel shows at `x`: u, M or T.
fn diagram_value(app: &App, shown: &Shown, solution: &Solution, x: f64) -> f64 {
    let p = solution.field.at(&shown.mesh, x);
    match app.diagram {
        Diagram::Deflection => p.deflection,
        Diagram::Moment => p.moment,
        Diagram::Shear => p.shear,
    }
}

fn deflection(
    frame: &mut Frame,
    app: &App,
    theme: &Theme,
    area: Rect,
    suffix: &str,
    focused: bool,
) {
    let (name, symbol, unit) = match app.diagram {
        Diagram::Deflection => ("Deflection u(x)", "u", "m"),
        Diagram::Moment => ("Bending moment M = -EJu''", "M", "N m"),
        Diagram::Shear => ("Shear force T = M'", "T", "N"),
    };
    let outdated = if app.is_current() {
        ""
    } else {
        " · out of date"
    };
    let title = if app.show_difference {
        format!(" {symbol} − {symbol}_ref [{unit}] (c: back, b: next){suffix}{outdated} ")
    } else {
        format!(" {name} [{unit}] (b: next){suffix}{outdated} ")
    };
    let panel = PanelFrame {
        area,
        title,
        focused,
    };
    let data = match deflection_data(app, theme, area) {
        Ok(data) => data,
        Err(text) => return notice(frame, theme, panel, text),
    };
    let plot = panel_with_key(frame, theme, &panel, &[], &[], &data.key, DEFLECTION_ROWS);
    let Some(plot) = deflection_plot(&data, plot) else {
        return;
    };
    let buffer = frame.buffer_mut();
    let zero = marker_char(theme, '─', '-').to_string();
    plot.horizontal_line(buffer, 0.0, &zero, theme.faint());
    let unit = |points: &[(f64, f64)]| -> Vec<(f64, f64)> {
        points.iter().map(|p| plot.unit(*p)).collect()
    };
    let walls = [vec![(0.0, 0.0), (0.0, 1.0)], vec![(1.0, 0.0), (1.0, 1.0)]];
    let curve = unit(&data.curve);
    let reference_curve = unit(&data.reference_curve);
    let states: Vec<Vec<(f64, f64)>> = data.states.iter().map(|s| unit(s)).collect();
    let mut datasets = Vec::new();
    for wall_points in &walls {
        datasets.push(
            Dataset::default()
                .marker(point_marker(theme, WALL.0, WALL.1))
                .graph_type(GraphType::Line)
                .style(theme.faint())
                .data(wall_points),
        );
    }
    // The reference under the current method's curve.
    datasets.push(
        Dataset::default()
            .marker(point_marker(theme, REFERENCE_MARKER.0, REFERENCE_MARKER.1))
            .graph_type(GraphType::Line)
            .style(theme.series(6))
            .data(&reference_curve),
    );
    datasets.push(
        Dataset::default()
            .marker(curve_marker(theme))
            .graph_type(GraphType::Line)
            .style(theme.series(0))
            .data(&curve),
    );
    for (i, points) in states.iter().enumerate() {
        let (u, a) = STATE_MARKERS[i];
        datasets.push(
            Dataset::default()
                .marker(point_marker(theme, u, a))
                .graph_type(GraphType::Scatter)
                .style(theme.series(i + 1))
                .data(points),
        );
    }
    plot.draw_datasets(buffer, theme, datasets);
    plot.draw_axes(buffer, theme);
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
    let theme = Theme::new(app.look, app.palette);
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
