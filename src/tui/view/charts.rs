//! The chart panels of the explorer: each reads the state it shows from the [`App`] and draws
//! it with the shared charts of [`crate::plot`] (the deflection here, the study charts there).

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::widgets::{Axis, Chart, Dataset, GraphType};

use crate::format::eng;
use crate::plot::{
    KeyEntry, PanelFrame, Theme, chart_with_key, curve_marker, eps_condition_chart,
    eps_error_chart, error_time_chart, linear_axis, marker_char, notice, point_marker, to_unit,
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
                    error_time_chart(frame, theme, panel, points, app.show_timings)
                }
                StudyView::Notice(text) => notice(frame, theme, panel, text),
            }
        }
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
    let (name, unit) = match app.diagram {
        Diagram::Deflection => ("Deflection u(x)", "m"),
        Diagram::Moment => ("Bending moment M = -EJu''", "N m"),
        Diagram::Shear => ("Shear force T = M'", "N"),
    };
    let outdated = if app.is_current() {
        ""
    } else {
        " · out of date"
    };
    let title = format!(" {name} [{unit}] (b: next){suffix}{outdated} ");
    let Some(shown) = &app.shown else {
        let panel = PanelFrame {
            area,
            title,
            focused,
        };
        let text = format!("solving n = {} …", app.wanted.elements);
        notice(frame, theme, panel, text);
        return;
    };
    let solution = match &shown.solution {
        Ok(s) => s,
        Err(e) => {
            let panel = PanelFrame {
                area,
                title,
                focused,
            };
            notice(frame, theme, panel, format!("no solution: {e}"));
            return;
        }
    };
    let l = shown.request.problem.length;
    let value = |x: f64| diagram_value(app, shown, solution, x);
    let (curve, y_axis) = sampled_curve(app, shown, solution, area);
    let Some((y_bounds, y_labels)) = y_axis else {
        let panel = PanelFrame {
            area,
            title,
            focused,
        };
        notice(
            frame,
            theme,
            panel,
            "no finite values to draw (see the warnings)".into(),
        );
        return;
    };
    // Drawn in the unit square (see `to_unit`), labelled in the real values.
    let x_bounds = [0.0, l];
    let unit = |(x, y): (f64, f64)| (to_unit(x, x_bounds), to_unit(y, y_bounds));
    let curve: Vec<(f64, f64)> = curve.into_iter().map(unit).collect();
    // The clamped ends as walls, and the obstacles by state.
    let walls = [vec![(0.0, 0.0), (0.0, 1.0)], vec![(1.0, 0.0), (1.0, 1.0)]];
    let mut states: [Vec<(f64, f64)>; 4] = Default::default();
    for o in &solution.obstacles {
        let state = usize::from(o.sliding) + 2 * usize::from(o.swivel);
        let y = value(o.x);
        if y.is_finite() {
            states[state].push(unit((o.x, y)));
        }
    }
    let state_names = ["stuck", "slides", "swivels", "slides+swivels"];
    let state_markers = [('●', 'o'), ('↕', 'S'), ('↻', 'W'), ('✱', 'X')];
    let wall = ('▒', '#');
    let mut key = vec![KeyEntry {
        marker: marker_char(theme, wall.0, wall.1),
        name: "clamped".into(),
        style: theme.dim(),
    }];
    let mut datasets = vec![
        Dataset::default()
            .marker(curve_marker(theme))
            .graph_type(GraphType::Line)
            .style(theme.series(0))
            .data(&curve),
    ];
    for wall_points in &walls {
        datasets.push(
            Dataset::default()
                .marker(point_marker(theme, wall.0, wall.1))
                .graph_type(GraphType::Line)
                .style(theme.dim())
                .data(wall_points),
        );
    }
    for (i, points) in states.iter().enumerate() {
        if !points.is_empty() {
            let (u, a) = state_markers[i];
            datasets.push(
                Dataset::default()
                    .marker(point_marker(theme, u, a))
                    .graph_type(GraphType::Scatter)
                    .style(theme.series(i + 1))
                    .data(points),
            );
            key.push(KeyEntry {
                marker: marker_char(theme, u, a),
                name: format!("obstacle {}", state_names[i]),
                style: theme.series(i + 1),
            });
        }
    }
    let chart = Chart::new(datasets)
        .x_axis(
            Axis::default()
                .title("x [m]")
                .bounds([0.0, 1.0])
                .labels(x_labels(l)),
        )
        .y_axis(Axis::default().bounds([0.0, 1.0]).labels(y_labels))
        .legend_position(None);
    let panel = PanelFrame {
        area,
        title,
        focused,
    };
    chart_with_key(frame, theme, panel, chart, &key);
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

/// The labels of the deflection chart's x axis.
fn x_labels(l: f64) -> Vec<String> {
    vec![eng(0.0), eng(0.5 * l), eng(l)]
}

/// The deflection panel's curve, sampled for a panel of `area`, and its y axis (bounds and
/// labels); no axis when no sample is finite.
#[allow(clippy::type_complexity)]
fn sampled_curve(
    app: &App,
    shown: &Shown,
    solution: &Solution,
    area: Rect,
) -> (Vec<(f64, f64)>, Option<([f64; 2], Vec<String>)>) {
    let l = shown.request.problem.length;
    let samples = (area.width as usize * 2).clamp(20, 400);
    let curve: Vec<(f64, f64)> = (0..samples)
        .map(|i| {
            let x = l * i as f64 / (samples - 1) as f64;
            (x, diagram_value(app, shown, solution, x))
        })
        .filter(|(_, y)| y.is_finite())
        .collect();
    if curve.is_empty() {
        return (curve, None);
    }
    let (min, max) = curve
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &(_, y)| {
            (a.min(y), b.max(y))
        });
    let axis = linear_axis(min, max);
    (curve, Some(axis))
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
    let shown = app.shown.as_ref()?;
    let solution = shown.solution.as_ref().ok()?;
    let (_, axis) = sampled_curve(app, shown, solution, area);
    let (_, y_labels) = axis?;
    let l = shown.request.problem.length;
    // Inside the borders; the key takes rows at the bottom only.
    let inner = Rect::new(
        area.x.saturating_add(1),
        area.y.saturating_add(1),
        area.width.saturating_sub(2),
        area.height.saturating_sub(2),
    );
    // As ratatui's `Chart` lays out: the widest y label (or the first x label, left aligned,
    // less the column under the axis), at most a third of the width, then the axis line.
    let width = |s: &String| ratatui::text::Line::from(s.as_str()).width() as u16;
    let widest_y = y_labels.iter().map(width).max().unwrap_or(0);
    let first_x = x_labels(l)
        .first()
        .map(width)
        .unwrap_or(0)
        .saturating_sub(1);
    let labels = widest_y.max(first_x).min(inner.width / 3);
    let mut left = inner.x + labels;
    if left + 1 < inner.right() {
        left += 1;
    }
    let last = inner.right().checked_sub(1)?;
    (last > left).then_some(DeflectionColumns {
        first: left,
        last,
        top: inner.y,
        bottom: inner.bottom(),
        length: l,
    })
}
