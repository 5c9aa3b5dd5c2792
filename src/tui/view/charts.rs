//! The chart panels. Ratatui's chart has no log axis, so log–log charts plot log10 values and
//! the axes are labelled in decades, with bounds chosen so that the evenly spread labels fall
//! on decades.

use ratatui::Frame;
use ratatui::layout::{Alignment, Rect};
use ratatui::symbols::Marker;
use ratatui::text::Line;
use ratatui::widgets::{Axis, Chart, Dataset, GraphType, Paragraph, Wrap};

use super::Theme;
use crate::format::eng;
use crate::scene::Panel;
use crate::solve::{Method, Reference};
use crate::tui::app::{App, Diagram, StudyState};

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
    match panel {
        Panel::Deflection => deflection(frame, app, theme, area, title_suffix, focused),
        Panel::EpsError => eps_error(frame, app, theme, area, title_suffix, focused),
        Panel::EpsCond => eps_condition(frame, app, theme, area, title_suffix, focused),
        Panel::ErrorTime => error_time(frame, app, theme, area, title_suffix, focused),
    }
}

/// A message in place of a chart.
fn notice(
    frame: &mut Frame,
    theme: &Theme,
    area: Rect,
    title: String,
    focused: bool,
    text: String,
) {
    let block = theme.block(title, focused);
    frame.render_widget(
        Paragraph::new(text)
            .wrap(Wrap { trim: true })
            .alignment(Alignment::Center)
            .block(block),
        area,
    );
}

/// One entry of a chart's key: its marker and name.
struct KeyEntry {
    marker: char,
    name: String,
    style: ratatui::style::Style,
}

/// Draws `chart` in a bordered block with its key on the last lines inside the block (a
/// ratatui legend would hide itself in narrow panels).
fn chart_with_key(
    frame: &mut Frame,
    theme: &Theme,
    area: Rect,
    title: String,
    focused: bool,
    chart: Chart,
    key: &[KeyEntry],
) {
    use ratatui::text::Span;
    let block = theme.block(title, focused);
    let inner = block.inner(area);
    frame.render_widget(block, area);
    // Lay the entries out in lines no wider than the panel.
    let mut lines: Vec<Vec<Span>> = vec![Vec::new()];
    let mut width = 0usize;
    for entry in key {
        let text = format!("{} {}", entry.marker, entry.name);
        let len = text.chars().count() + 2;
        if width > 0 && width + len > inner.width as usize {
            lines.push(Vec::new());
            width = 0;
        }
        let line = lines.last_mut().expect("one line at least");
        line.push(Span::styled(text, entry.style));
        line.push(Span::raw("  "));
        width += len;
    }
    let key_height = if key.is_empty() {
        0
    } else {
        (lines.len() as u16).min(inner.height / 3)
    };
    let [plot, legend] = ratatui::layout::Layout::vertical([
        ratatui::layout::Constraint::Min(1),
        ratatui::layout::Constraint::Length(key_height),
    ])
    .areas(inner);
    frame.render_widget(chart, plot);
    let text: Vec<Line> = lines.into_iter().map(Line::from).collect();
    frame.render_widget(Paragraph::new(text), legend);
}

/// Bounds and labels of a log10 axis covering [min, max]: whole decades, as many labels as
/// `room` cells allow (two to five), the bounds a whole number of label steps apart.
fn decade_axis(min: f64, max: f64, room: u16) -> ([f64; 2], Vec<String>) {
    let low = min.floor();
    let mut high = max.ceil();
    if high <= low {
        high = low + 1.0;
    }
    let span = high - low;
    let intervals_wanted = (f64::from(room) / 7.0).floor().clamp(1.0, 4.0);
    let step = (span / intervals_wanted).ceil().max(1.0);
    let intervals = (span / step).ceil();
    let high = low + step * intervals;
    let labels = (0..=intervals as i64)
        .map(|i| format!("1e{}", (low + step * i as f64) as i64))
        .collect();
    ([low, high], labels)
}

/// Bounds and three labels of a linear axis covering [min, max], padded a little. Finite for
/// any finite input, the extremes of f64 included.
fn linear_axis(min: f64, max: f64) -> ([f64; 2], Vec<String>) {
    let label = |v: f64| crate::format::sci(v, 3);
    // Halves first, so that the span of ±1.7e308 does not overflow.
    let half_span = 0.5 * max - 0.5 * min;
    let pad = if half_span > 0.0 {
        0.16 * half_span
    } else if min == 0.0 {
        1.0
    } else {
        0.1 * min.abs()
    };
    let low = (min - pad).max(f64::MIN);
    let high = (max + pad).min(f64::MAX);
    (
        [low, high],
        vec![label(low), label(0.5 * low + 0.5 * high), label(high)],
    )
}

/// Maps `value` from `bounds` onto [0, 1], so that the chart widget only ever sees a unit
/// square: its own mapping to the character grid breaks down (and its line drawing can walk
/// billions of cells) when the bounds are extreme or subnormal. Values that land far outside
/// are clamped; the widget clips lines to the square.
fn to_unit(value: f64, [low, high]: [f64; 2]) -> f64 {
    let unit = (0.5 * value - 0.5 * low) / (0.5 * high - 0.5 * low);
    if unit.is_finite() {
        unit.clamp(-1.0, 2.0)
    } else {
        0.5
    }
}

fn curve_marker(theme: &Theme) -> Marker {
    if theme.look.ascii {
        Marker::Custom('.')
    } else {
        Marker::Braille
    }
}

fn point_marker(theme: &Theme, unicode: char, ascii: char) -> Marker {
    Marker::Custom(marker_char(theme, unicode, ascii))
}

fn marker_char(theme: &Theme, unicode: char, ascii: char) -> char {
    if theme.look.ascii { ascii } else { unicode }
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
    let title = format!(" {name} [{unit}] (b: next){suffix} ");
    let solution = match &app.solution {
        Ok(s) => s,
        Err(e) => {
            notice(
                frame,
                theme,
                area,
                title,
                focused,
                format!("no solution: {e}"),
            );
            return;
        }
    };
    let l = app.problem.length;
    let samples = (area.width as usize * 2).clamp(20, 400);
    let value = |x: f64| {
        let p = solution.field.at(&app.mesh, x);
        match app.diagram {
            Diagram::Deflection => p.deflection,
            Diagram::Moment => p.moment,
            Diagram::Shear => p.shear,
        }
    };
    let curve: Vec<(f64, f64)> = (0..samples)
        .map(|i| {
            let x = l * i as f64 / (samples - 1) as f64;
            (x, value(x))
        })
        .filter(|(_, y)| y.is_finite())
        .collect();
    if curve.is_empty() {
        notice(
            frame,
            theme,
            area,
            title,
            focused,
            "no finite values to draw (see the warnings)".into(),
        );
        return;
    }
    let (min, max) = curve
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &(_, y)| {
            (a.min(y), b.max(y))
        });
    let (y_bounds, y_labels) = linear_axis(min, max);
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
                .labels(vec![eng(0.0), eng(0.5 * l), eng(l)]),
        )
        .y_axis(Axis::default().bounds([0.0, 1.0]).labels(y_labels))
        .legend_position(None);
    chart_with_key(frame, theme, area, title, focused, chart, &key);
}

/// The ε-sweep's state as a chart input, or a notice.
fn eps_points(app: &App) -> Result<&[crate::study::EpsPoint], String> {
    match &app.eps_study.state {
        StudyState::Ready(points) => Ok(points),
        StudyState::Pending => Err("computing the ε sweep…".into()),
        StudyState::Failed(e) => Err(e.clone()),
        StudyState::Idle => Err("not computed".into()),
    }
}

fn log_points(pairs: impl Iterator<Item = (f64, Option<f64>)>) -> Vec<(f64, f64)> {
    pairs
        .filter_map(|(x, y)| {
            let y = y?;
            (x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite()).then(|| (x.log10(), y.log10()))
        })
        .collect()
}

fn bounds_of(series: &[&[(f64, f64)]]) -> Option<([f64; 2], [f64; 2])> {
    let mut iter = series.iter().flat_map(|s| s.iter());
    let first = iter.next()?;
    let (mut x, mut y) = ([first.0, first.0], [first.1, first.1]);
    for p in iter {
        x = [x[0].min(p.0), x[1].max(p.0)];
        y = [y[0].min(p.1), y[1].max(p.1)];
    }
    Some((x, y))
}

/// A series of a log–log chart: markers (Unicode, ASCII), name, log10 points, how drawn.
type Series = ((char, char), String, Vec<(f64, f64)>, GraphType);

/// A log–log chart of `series` with the current ε marked when given.
#[allow(clippy::too_many_arguments)]
fn log_log(
    frame: &mut Frame,
    theme: &Theme,
    area: Rect,
    title: String,
    focused: bool,
    x_title: &str,
    series: &[Series],
    current_epsilon: Option<f64>,
    empty: String,
) {
    let all: Vec<&[(f64, f64)]> = series.iter().map(|(_, _, d, _)| d.as_slice()).collect();
    let Some((x, y)) = bounds_of(&all) else {
        return notice(frame, theme, area, title, focused, empty);
    };
    let (x_bounds, x_labels) = decade_axis(x[0], x[1], area.width.saturating_sub(10));
    let (y_bounds, y_labels) = decade_axis(y[0], y[1], area.height.saturating_sub(6) * 3);
    let marker: Vec<(f64, f64)> = current_epsilon
        .map(|e| vec![(e.log10(), y_bounds[0]), (e.log10(), y_bounds[1])])
        .unwrap_or_default();
    let mut key = Vec::new();
    let mut datasets = Vec::new();
    for (i, ((u, a), name, data, kind)) in series.iter().enumerate() {
        let marker = if *kind == GraphType::Line && !theme.look.ascii {
            Marker::Braille
        } else {
            point_marker(theme, *u, *a)
        };
        datasets.push(
            Dataset::default()
                .marker(marker)
                .graph_type(*kind)
                .style(theme.series(i))
                .data(data),
        );
        key.push(KeyEntry {
            marker: marker_char(theme, *u, *a),
            name: name.clone(),
            style: theme.series(i),
        });
    }
    if let Some(epsilon) = current_epsilon {
        datasets.push(
            Dataset::default()
                .marker(point_marker(theme, '│', '|'))
                .graph_type(GraphType::Line)
                .style(theme.dim())
                .data(&marker),
        );
        key.push(KeyEntry {
            marker: marker_char(theme, '│', '|'),
            name: format!("ε = {}", crate::format::sci(epsilon, 2)),
            style: theme.dim(),
        });
    }
    let chart = Chart::new(datasets)
        .x_axis(
            Axis::default()
                .title(x_title)
                .bounds(x_bounds)
                .labels(x_labels),
        )
        .y_axis(Axis::default().bounds(y_bounds).labels(y_labels))
        .legend_position(None);
    chart_with_key(frame, theme, area, title, focused, chart, &key);
}

fn eps_error(frame: &mut Frame, app: &App, theme: &Theme, area: Rect, suffix: &str, focused: bool) {
    let title = format!(" Error vs ε (regularised){suffix} ");
    match eps_points(app) {
        Ok(points) => eps_error_chart(
            frame,
            theme,
            area,
            title,
            focused,
            points,
            Some(app.scene.solver.epsilon),
        ),
        Err(text) => notice(frame, theme, area, title, focused, text),
    }
}

/// The regularisation error against ε (paper Figure 5, left).
pub(crate) fn eps_error_chart(
    frame: &mut Frame,
    theme: &Theme,
    area: Rect,
    title: String,
    focused: bool,
    points: &[crate::study::EpsPoint],
    current_epsilon: Option<f64>,
) {
    let error = log_points(
        points
            .iter()
            .map(|p| (p.epsilon, p.error.and_then(|e| e.max_rel))),
    );
    let series = [(
        ('•', '*'),
        "max rel. error".to_string(),
        error,
        GraphType::Line,
    )];
    log_log(
        frame,
        theme,
        area,
        title,
        focused,
        "ε",
        &series,
        current_epsilon,
        "no error to plot".into(),
    );
}

fn eps_condition(
    frame: &mut Frame,
    app: &App,
    theme: &Theme,
    area: Rect,
    suffix: &str,
    focused: bool,
) {
    let title = format!(" cond2 of the cases vs ε{suffix} ");
    match eps_points(app) {
        Ok(points) => eps_condition_chart(
            frame,
            theme,
            area,
            title,
            focused,
            points,
            Some(app.scene.solver.epsilon),
        ),
        Err(text) => notice(frame, theme, area, title, focused, text),
    }
}

/// The largest condition number over the cases against ε (paper Figure 5, right), with the
/// Jacobi-scaled one.
pub(crate) fn eps_condition_chart(
    frame: &mut Frame,
    theme: &Theme,
    area: Rect,
    title: String,
    focused: bool,
    points: &[crate::study::EpsPoint],
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
    let series = [
        (('•', '*'), "cond2(Â)".to_string(), plain, GraphType::Line),
        (
            ('+', '+'),
            "Jacobi-scaled".to_string(),
            scaled,
            GraphType::Scatter,
        ),
    ];
    let empty = format!(
        "no condition numbers: they are computed for N ≤ {} unknowns",
        crate::study::CONDITION_LIMIT
    );
    log_log(
        frame,
        theme,
        area,
        title,
        focused,
        "ε",
        &series,
        current_epsilon,
        empty,
    );
}

fn error_time(
    frame: &mut Frame,
    app: &App,
    theme: &Theme,
    area: Rect,
    suffix: &str,
    focused: bool,
) {
    let title = if app.show_timings {
        format!(" Error vs run time{suffix} ")
    } else {
        format!(" Error vs n (t: time){suffix} ")
    };
    match &app.mesh_study.state {
        StudyState::Ready(points) => {
            error_time_chart(frame, theme, area, title, focused, points, app.show_timings)
        }
        StudyState::Pending => notice(
            frame,
            theme,
            area,
            title,
            focused,
            "computing the mesh sweep…".into(),
        ),
        StudyState::Failed(e) => notice(frame, theme, area, title, focused, e.clone()),
        StudyState::Idle => notice(frame, theme, area, title, focused, "not computed".into()),
    }
}

/// Every method's error against its run time (or against n when `by_time` is false).
pub(crate) fn error_time_chart(
    frame: &mut Frame,
    theme: &Theme,
    area: Rect,
    title: String,
    focused: bool,
    points: &[crate::study::MeshPoint],
    by_time: bool,
) {
    let markers = [
        ('●', 'o'),
        ('■', '#'),
        ('▲', '^'),
        ('◆', '%'),
        ('✚', '+'),
        ('✖', 'x'),
    ];
    let mut series = Vec::new();
    for (i, method) in Method::ALL.into_iter().enumerate() {
        let of_method: Vec<_> = points.iter().filter(|p| p.method == method).collect();
        if of_method.is_empty() || of_method.iter().all(|p| p.refused.is_some()) {
            continue;
        }
        let is_reference = of_method.iter().any(|p| p.is_reference());
        let data = log_points(of_method.iter().filter(|p| p.refused.is_none()).map(|p| {
            let x = if by_time {
                p.run_time.as_secs_f64()
            } else {
                p.elements as f64
            };
            (
                x,
                p.error
                    .filter(|e| e.reference != Reference::ThisSolution)
                    .and_then(|e| e.max_rel),
            )
        }));
        let name = if is_reference {
            format!("{method} = reference")
        } else {
            method.name().to_string()
        };
        series.push((markers[i % markers.len()], name, data, GraphType::Scatter));
    }
    let x_title = if by_time {
        "run time [s]"
    } else {
        "elements n"
    };
    log_log(
        frame,
        theme,
        area,
        title,
        focused,
        x_title,
        &series,
        None,
        "no error to plot".into(),
    );
}
