//! The charts of the studies (paper Figure 5 and error against run time or n), drawn from the
//! studies' points on log–log axes whose labels are at their values: the explorer's panels and
//! the text charts of `beamfric report` are the same drawing. Each chart marks the current
//! point (the scene's ε, or its n and method) and prints its values under the chart.

use ratatui::Frame;
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::{Modifier, Style};
use ratatui::widgets::{Dataset, GraphType};

use super::chart::{
    KeyEntry, PanelFrame, Piece, bounds_of, curve_key, curve_marker, log_points, marker_char,
    notice, panel_with_key, point_marker,
};
use super::plot_area::{AxisKind, AxisSpec, Markers, PlotArea};
use super::{Look, MarkerSet, Palette, Theme, transliterate};
use crate::format::{duration, sci};
use crate::solve::{Method, Reference};
use crate::study::{EpsPoint, MeshPoint};

/// Rows a chart keeps for itself before the readout and the key take the rest.
const PLOT_ROWS: u16 = 5;

/// The marker line of the current ε or n.
pub(super) fn current_line(theme: &Theme) -> &'static str {
    if theme.look.ascii { ":" } else { "┆" }
}

/// Log axes over the points, with `x_title`.
fn log_axes(x: [f64; 2], y: [f64; 2], x_title: String) -> (AxisSpec, AxisSpec) {
    (
        AxisSpec {
            kind: AxisKind::Log,
            range: x,
            title: x_title,
        },
        AxisSpec {
            kind: AxisKind::Log,
            range: y,
            title: String::new(),
        },
    )
}

/// The plot area of an ε chart (log axes, ε below), with the current ε marked by a vertical
/// line; `None` when the panel is too small to plot in.
pub(super) fn epsilon_plot(
    frame: &mut Frame,
    theme: &Theme,
    plot: Rect,
    x: [f64; 2],
    y: [f64; 2],
    current_epsilon: Option<f64>,
) -> Option<PlotArea> {
    let (x_axis, y_axis) = log_axes(x, y, theme.text("ε").into_owned());
    let area = PlotArea::new(plot, &x_axis, &y_axis)?;
    if let Some(epsilon) = current_epsilon.filter(|e| *e > 0.0) {
        area.vertical_line(
            frame.buffer_mut(),
            epsilon.log10(),
            current_line(theme),
            theme.current(),
        );
    }
    Some(area)
}

/// The sweep point at exactly the current ε (the sweep includes it), if any.
pub(super) fn point_at(points: &[EpsPoint], epsilon: Option<f64>) -> Option<&EpsPoint> {
    let epsilon = epsilon?;
    points.iter().find(|p| p.epsilon == epsilon)
}

/// The readout's opening piece: the marker and the current ε.
fn epsilon_piece(theme: &Theme, epsilon: f64) -> Piece {
    (
        format!("{} ε = {}:", current_line(theme), sci(epsilon, 2)),
        theme.current(),
    )
}

/// The regularisation error against ε (paper Figure 5, left), the current ε marked with its
/// error printed.
pub fn eps_error_chart(
    frame: &mut Frame,
    theme: &Theme,
    panel: PanelFrame,
    points: &[EpsPoint],
    current_epsilon: Option<f64>,
) {
    let error = log_points(
        points
            .iter()
            .map(|p| (p.epsilon, p.error.and_then(|e| e.max_rel))),
    );
    let Some((x, y)) = bounds_of(&error) else {
        return notice(frame, theme, panel, "no error to plot".into());
    };
    let reference = points
        .iter()
        .find_map(|p| p.error.map(|e| e.reference.label()))
        .unwrap_or("the reference");
    let mut key = Vec::new();
    let mut readout = Vec::new();
    let current = point_at(points, current_epsilon);
    let series_style = theme.series(0);
    match current_epsilon {
        // The readout names the curve: no key needed.
        Some(epsilon) => {
            readout.push(epsilon_piece(theme, epsilon));
            let curve = curve_key(theme);
            readout.push(
                match current.and_then(|p| p.error.and_then(|e| e.max_rel)) {
                    Some(e) => (format!("{curve} error {}", sci(e, 2)), series_style),
                    None if current.is_none() => ("not in the sweep yet".into(), theme.dim()),
                    None => (format!("{curve} error n/a"), series_style),
                },
            );
            readout.push((format!("vs {reference}"), theme.dim()));
        }
        None => key.push(KeyEntry {
            marker: curve_key(theme),
            name: format!("max rel. error vs {reference}"),
            style: series_style,
            short: None,
        }),
    }
    let plot = panel_with_key(frame, theme, &panel, &readout, &[], &key, PLOT_ROWS);
    let Some(area) = epsilon_plot(frame, theme, plot, x, y, current_epsilon) else {
        return;
    };
    let buffer = frame.buffer_mut();
    let data: Vec<(f64, f64)> = error.iter().map(|p| area.unit(*p)).collect();
    area.draw_datasets(
        buffer,
        theme,
        vec![
            Dataset::default()
                .marker(curve_marker(theme))
                .graph_type(GraphType::Line)
                .style(theme.series(0))
                .data(&data),
        ],
    );
    area.draw_axes(buffer, theme);
    if let Some(e) = current.and_then(|p| Some((p.epsilon, p.error?.max_rel?))) {
        let [point] = log_points([(e.0, Some(e.1))].into_iter())[..] else {
            return;
        };
        area.scatter(
            buffer,
            &[Markers {
                symbol: marker_char(theme, '●', 'O'),
                points: vec![(point.0, point.1, theme.current())],
            }],
        );
    }
}

/// The largest condition number over the cases against ε (paper Figure 5, right), with the
/// Jacobi-scaled one: the scaled one as `+` markers under the cond₂ curve, so that cond₂'s
/// plateau is never hidden; the current ε marked with both values printed.
pub fn eps_condition_chart(
    frame: &mut Frame,
    theme: &Theme,
    panel: PanelFrame,
    points: &[EpsPoint],
    current_epsilon: Option<f64>,
) {
    let plain = log_points(
        points
            .iter()
            .map(|p| (p.epsilon, p.cond_max.map(|c| c.value))),
    );
    let scaled = log_points(
        points
            .iter()
            .map(|p| (p.epsilon, p.cond_scaled_max.map(|c| c.value))),
    );
    let Some((x, y)) = bounds_of(plain.iter().chain(&scaled)) else {
        let text = format!(
            "no condition numbers: they are computed for N ≤ {} unknowns",
            crate::study::CONDITION_LIMIT
        );
        return notice(frame, theme, panel, text);
    };
    let scaled_marker = ('+', '+');
    let plain_key = curve_key(theme);
    let scaled_key = marker_char(theme, scaled_marker.0, scaled_marker.1);
    let mut key = Vec::new();
    let mut readout = Vec::new();
    let current = point_at(points, current_epsilon);
    match (current_epsilon, current) {
        // The readout names both series with their values: it is the key.
        (Some(epsilon), Some(p)) => {
            let value = |c: Option<crate::linalg::condition::ConditionNumber>| {
                c.map_or("n/a".to_string(), |c| sci(c.value, 2))
            };
            readout.push(epsilon_piece(theme, epsilon));
            readout.push((
                format!("{plain_key} cond₂(Â) {}", value(p.cond_max)),
                theme.series(0),
            ));
            readout.push((
                format!("{scaled_key} scaled {}", value(p.cond_scaled_max)),
                theme.series(1),
            ));
        }
        _ => {
            if let Some(epsilon) = current_epsilon {
                readout.push(epsilon_piece(theme, epsilon));
                readout.push(("not in the sweep yet".into(), theme.dim()));
            }
            key.push(KeyEntry {
                marker: plain_key,
                name: "cond₂(Â)".into(),
                style: theme.series(0),
                short: None,
            });
            key.push(KeyEntry {
                marker: scaled_key,
                name: "Jacobi-scaled".into(),
                style: theme.series(1),
                short: None,
            });
        }
    }
    let plot = panel_with_key(frame, theme, &panel, &readout, &[], &key, PLOT_ROWS);
    let Some(area) = epsilon_plot(frame, theme, plot, x, y, current_epsilon) else {
        return;
    };
    let buffer = frame.buffer_mut();
    let scaled_unit: Vec<(f64, f64)> = scaled.iter().map(|p| area.unit(*p)).collect();
    let plain_unit: Vec<(f64, f64)> = plain.iter().map(|p| area.unit(*p)).collect();
    // The scaled markers first: the cond₂ curve is drawn over them.
    area.draw_datasets(
        buffer,
        theme,
        vec![
            Dataset::default()
                .marker(point_marker(theme, scaled_marker.0, scaled_marker.1))
                .graph_type(GraphType::Scatter)
                .style(theme.series(1))
                .data(&scaled_unit),
            Dataset::default()
                .marker(curve_marker(theme))
                .graph_type(GraphType::Line)
                .style(theme.series(0))
                .data(&plain_unit),
        ],
    );
    area.draw_axes(buffer, theme);
    if let Some(p) = current {
        let marks: Vec<(f64, f64, Style)> = log_points(
            [
                (p.epsilon, p.cond_max.map(|c| c.value)),
                (p.epsilon, p.cond_scaled_max.map(|c| c.value)),
            ]
            .into_iter(),
        )
        .into_iter()
        .map(|(x, y)| (x, y, theme.current()))
        .collect();
        area.scatter(
            buffer,
            &[Markers {
                symbol: marker_char(theme, '●', 'O'),
                points: marks,
            }],
        );
    }
}

/// The marker of each method, by its place in [`Method::ALL`]: (Unicode, ASCII).
pub(crate) const METHOD_MARKERS: [(char, char); 7] = [
    ('●', 'o'),
    ('■', '#'),
    ('▲', '^'),
    ('◆', '%'),
    ('✚', '+'),
    ('✖', 'x'),
    ('★', '@'),
];

/// A method's series: its index in [`Method::ALL`], the method, and its log10 points, each
/// with whether it is at the current n.
type MethodSeries = (usize, Method, Vec<(f64, f64, bool)>);

/// A method's name where the key has little room.
fn short_name(method: Method) -> &'static str {
    match method {
        Method::Dual => "dual",
        Method::Condensed => "cond.",
        Method::Flexibility => "flex.",
        Method::Regularized => "reg.",
        Method::RegularizedNewton => "reg.N",
        Method::DualInverse => "dual-inv",
        Method::ClosedForm => "closed",
    }
}

/// The scene's own run in the mesh sweep: its n and the method it uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CurrentRun {
    pub elements: usize,
    pub method: Method,
}

/// Every method's error against its run time (or against n when `by_time` is false): one
/// marker per method, the selected method placed first so that it sits at its exact cells and
/// the others move aside (at most three columns) rather than hide it; the current run marked
/// by a rule (at its n, or at its run time when the x axis is time) and the selected method's
/// error (and run time) there printed.
pub fn error_time_chart(
    frame: &mut Frame,
    theme: &Theme,
    panel: PanelFrame,
    points: &[MeshPoint],
    by_time: bool,
    current: Option<CurrentRun>,
) {
    let series = method_series(points, by_time, current);
    let all: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|(_, _, d)| d.iter().map(|p| (p.0, p.1)))
        .collect();
    let Some((x, y)) = bounds_of(&all) else {
        return notice(frame, theme, panel, "no error to plot".into());
    };
    let selected = current.map(|c| c.method);
    let key = method_key(theme, &series, selected);
    let (readout, optional) = match current {
        Some(run) => current_readout(theme, points, by_time, run),
        None => (Vec::new(), Vec::new()),
    };
    let plot = panel_with_key(frame, theme, &panel, &readout, &optional, &key, PLOT_ROWS);
    let x_title = if by_time { "t [s]" } else { "n" };
    let (x_axis, y_axis) = log_axes(x, y, x_title.into());
    let Some(area) = PlotArea::new(plot, &x_axis, &y_axis) else {
        return;
    };
    let buffer = frame.buffer_mut();
    // The current run's rule: at its n, or against time at the selected method's run time
    // there (a mark a plain-text frame shows too, not only reverse video: issue 25).
    let rule = match current {
        Some(run) if !by_time => Some((run.elements as f64).log10()),
        Some(run) => series
            .iter()
            .filter(|(_, method, _)| *method == run.method)
            .flat_map(|(_, _, data)| data.iter())
            .find(|(_, _, is_current)| *is_current)
            .map(|(x, _, _)| *x),
        None => None,
    };
    if let Some(x) = rule {
        area.vertical_line(buffer, x, current_line(theme), theme.current());
    }
    // The selected method's points joined in the order of n, in the theme's curve markers,
    // under every method's markers.
    let path: Vec<(f64, f64)> = series
        .iter()
        .filter(|(_, method, _)| Some(*method) == selected)
        .flat_map(|(_, _, data)| data.iter().map(|&(x, y, _)| area.unit((x, y))))
        .collect();
    if path.len() > 1 {
        let style = series
            .iter()
            .find(|(_, method, _)| Some(*method) == selected)
            .map_or(theme.plain(), |(i, _, _)| theme.series(*i));
        let line = Dataset::default()
            .marker(curve_marker(theme))
            .graph_type(GraphType::Line)
            .style(style)
            .data(&path);
        area.draw_datasets(buffer, theme, vec![line]);
    }
    area.scatter(buffer, &method_markers(theme, &series, selected));
    area.draw_axes(buffer, theme);
}

/// One series per method that has a point to draw, in [`Method::ALL`] order: log10 of the run
/// time (or of n) and of the error against the reference, each point with whether it is at
/// the current n.
fn method_series(
    points: &[MeshPoint],
    by_time: bool,
    current: Option<CurrentRun>,
) -> Vec<MethodSeries> {
    let x_of = |p: &MeshPoint| {
        if by_time {
            p.run_time.as_secs_f64()
        } else {
            p.elements as f64
        }
    };
    let error_of = |p: &MeshPoint| {
        p.error
            .filter(|e| e.reference != Reference::ThisSolution)
            .and_then(|e| e.max_rel)
    };
    let mut series: Vec<MethodSeries> = Vec::new();
    for (i, method) in Method::ALL.into_iter().enumerate() {
        let data: Vec<(f64, f64, bool)> = points
            .iter()
            .filter(|p| p.method == method && p.refused.is_none())
            .filter_map(|p| {
                let [(x, y)] = log_points([(x_of(p), error_of(p))].into_iter())[..] else {
                    return None;
                };
                let is_current = current.is_some_and(|c| c.elements == p.elements);
                Some((x, y, is_current))
            })
            .collect();
        if !data.is_empty() {
            series.push((i, method, data));
        }
    }
    series
}

/// The key: each method's marker and name, the selected method's in bold.
fn method_key(theme: &Theme, series: &[MethodSeries], selected: Option<Method>) -> Vec<KeyEntry> {
    series
        .iter()
        .map(|(i, method, _)| {
            let (u, a) = METHOD_MARKERS[i % METHOD_MARKERS.len()];
            let mut style = theme.series(*i);
            if Some(*method) == selected {
                style = style.add_modifier(Modifier::BOLD);
            }
            KeyEntry {
                marker: marker_char(theme, u, a),
                name: method.name().to_string(),
                style,
                short: Some(short_name(*method).to_string()),
            }
        })
        .collect()
}

/// Lines of styled text over the key: those always shown, and those shown where there is
/// room.
type Readout = (Vec<(String, Style)>, Vec<(String, Style)>);

/// What the chart prints of the scene's own run: its n, its method's error there (or why
/// there is none), its run time when the x axis is time, and what the error is measured
/// against (where there is room).
fn current_readout(theme: &Theme, points: &[MeshPoint], by_time: bool, run: CurrentRun) -> Readout {
    let reference = points
        .iter()
        .find_map(|p| p.error.map(|e| e.reference))
        .filter(|r| *r != Reference::ThisSolution);
    let mut readout = vec![(
        format!("{} n = {}:", current_line(theme), run.elements),
        theme.current(),
    )];
    let mut optional = Vec::new();
    let i = Method::ALL
        .iter()
        .position(|m| *m == run.method)
        .unwrap_or(0);
    let (u, a) = METHOD_MARKERS[i % METHOD_MARKERS.len()];
    let marker = marker_char(theme, u, a);
    let style = theme.series(i);
    let at = points
        .iter()
        .find(|p| p.method == run.method && p.elements == run.elements);
    let text = match at {
        None => format!("{marker} {} not in the sweep", run.method),
        Some(p) if p.refused.is_some() => format!("{marker} {} gives no result", run.method),
        Some(p) => match p.error {
            Some(e) if e.reference == Reference::ThisSolution => {
                format!("{marker} {} is the reference", run.method)
            }
            Some(e) => format!(
                "{marker} {}",
                e.max_rel.map_or("error n/a".to_string(), |r| sci(r, 2))
            ),
            None => format!("{marker} error n/a"),
        },
    };
    readout.push((text, style));
    if by_time && let Some(p) = at.filter(|p| p.refused.is_none()) {
        readout.push((format!("in {}", duration(p.run_time)), style));
    }
    if let Some(r) = reference {
        optional.push((format!("(error vs {})", r.label()), theme.dim()));
    }
    (readout, optional)
}

/// The series as scatter markers, the selected method first (it keeps its exact cells), the
/// points at the current n in reverse video.
fn method_markers(
    theme: &Theme,
    series: &[MethodSeries],
    selected: Option<Method>,
) -> Vec<Markers> {
    let mut order: Vec<&MethodSeries> = series.iter().collect();
    order.sort_by_key(|(_, m, _)| Some(*m) != selected);
    order
        .iter()
        .map(|(i, _, data)| {
            let (u, a) = METHOD_MARKERS[i % METHOD_MARKERS.len()];
            let style = theme.series(*i);
            Markers {
                symbol: marker_char(theme, u, a),
                points: data
                    .iter()
                    .map(|&(x, y, is_current)| {
                        let style = if is_current {
                            style.add_modifier(Modifier::REVERSED | Modifier::BOLD)
                        } else {
                            style
                        };
                        (x, y, style)
                    })
                    .collect(),
            }
        })
        .collect()
}

/// A chart of study data drawn on its own, for reports.
#[derive(Debug, Clone, Copy)]
pub enum StudyChart<'a> {
    /// Regularisation error against ε.
    EpsError(&'a [EpsPoint]),
    /// Largest condition numbers of the cases against ε.
    EpsCondition(&'a [EpsPoint]),
    /// Error against run time (`by_time`) or against n.
    ErrorTime {
        points: &'a [MeshPoint],
        by_time: bool,
    },
}

/// Draws one study chart, with its title, into a fresh buffer of the given size: the same
/// drawing as the explorer's panel.
pub fn chart_buffer(chart: StudyChart, title: &str, width: u16, height: u16, look: Look) -> Buffer {
    let theme = Theme::new(look, Palette::Dark, MarkerSet::default());
    let mut terminal = ratatui::Terminal::new(ratatui::backend::TestBackend::new(width, height))
        .expect("an in-memory terminal");
    terminal
        .draw(|frame| {
            let panel = PanelFrame {
                area: frame.area(),
                title: format!(" {title} "),
                focused: false,
            };
            match chart {
                StudyChart::EpsError(points) => eps_error_chart(frame, &theme, panel, points, None),
                StudyChart::EpsCondition(points) => {
                    eps_condition_chart(frame, &theme, panel, points, None)
                }
                StudyChart::ErrorTime { points, by_time } => {
                    error_time_chart(frame, &theme, panel, points, by_time, None)
                }
            }
            if look.ascii {
                transliterate(frame.buffer_mut());
            }
        })
        .expect("drawing into memory does not fail");
    terminal.backend().buffer().clone()
}
