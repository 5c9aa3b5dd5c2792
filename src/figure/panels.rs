//! The figures of the sweep panels, from the data the explorer's panels draw: the
//! regularisation error and the largest condition numbers against ε (paper Figure 5), and
//! every method's error against its run time or against n; each with the current point
//! (the scene's ε, or its n and method) marked by a dashed rule and a ring.

use super::axes::{Axes, Axis, PLOT, current_rule};
use super::series::{
    LegendEntry, Sample, Series, SeriesStyle, current_ring, draw_legend, draw_notice, draw_series,
    page,
};
use crate::format::{duration, sci};
use crate::plot::CurrentRun;
use crate::solve::{Method, Reference};
use crate::study::{CONDITION_LIMIT, EpsPoint, MeshPoint};

/// The name of the ε axis: ε compares with the friction unknowns, displacements [m] and
/// rotations [rad].
const EPSILON_AXIS: &str = "ε [m, rad]";
/// The name of the error axis.
const ERROR_AXIS: &str = "max relative nodal error [1]";

/// Positive, finite (x, y) pairs only: what a log–log plot can show.
fn plottable(points: impl IntoIterator<Item = (f64, Option<f64>)>) -> Vec<(f64, f64)> {
    points
        .into_iter()
        .filter_map(|(x, y)| Some((x, y?)))
        .filter(|(x, y)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0)
        .collect()
}

/// Log axes over every point of every series; `None` when there is none.
fn log_axes(series: &[Series]) -> Option<Axes> {
    let all = || series.iter().flat_map(|s| s.points.iter());
    Some(Axes::new(
        Axis::log_over(all().map(|p| p.0))?,
        Axis::log_over(all().map(|p| p.1))?,
    ))
}

/// The legend entry of the current ε: its value and the lines after it.
fn epsilon_entry(epsilon: f64, mut lines: Vec<String>) -> LegendEntry {
    lines.insert(0, format!("current ε = {}", sci(epsilon, 2)));
    LegendEntry::new(Sample::Current, lines)
}

/// The regularisation error against ε (paper Figure 5, left); the current ε marked with its
/// error in the legend.
pub fn eps_error_figure(points: &[EpsPoint], current_epsilon: Option<f64>, title: &str) -> String {
    let reference = points
        .iter()
        .find_map(|p| p.error.map(|e| e.reference.label()))
        .unwrap_or("the reference");
    let note = format!("max |u − u_ref| / max |u_ref| over the nodes, u_ref: {reference}");
    let mut svg = page(
        title,
        "Regularisation error against ε (paper Figure 5, left)",
        (EPSILON_AXIS, ERROR_AXIS),
        &note,
    );
    let error = |p: &EpsPoint| p.error.and_then(|e| e.max_rel);
    let series = [Series {
        name: "max rel. error".into(),
        style: SeriesStyle::indexed(0),
        points: plottable(points.iter().map(|p| (p.epsilon, error(p)))),
    }];
    let Some(axes) = log_axes(&series) else {
        draw_notice(
            &mut svg,
            "no error to plot: no ε gave a positive finite error",
        );
        return svg.finish();
    };
    axes.draw(&mut svg, 34.0);
    let mut legend = vec![LegendEntry::new(
        Sample::Series(series[0].style),
        vec![series[0].name.clone()],
    )];
    if let Some(epsilon) = current_epsilon.filter(|e| *e > 0.0) {
        let current = points.iter().find(|p| p.epsilon == epsilon);
        let value = match current.map(error) {
            None => "not in the sweep".to_string(),
            Some(e) => format!("error {}", e.map_or("n/a".into(), |e| sci(e, 3))),
        };
        legend.push(epsilon_entry(epsilon, vec![value]));
        current_rule(&mut svg, PLOT, axes.x_px(epsilon));
    }
    draw_series(&mut svg, &axes, &series[0]);
    if let Some((x, y)) = current_epsilon.and_then(|e| {
        let p = points.iter().find(|p| p.epsilon == e)?;
        plottable([(p.epsilon, error(p))]).first().copied()
    }) {
        current_ring(&mut svg, &axes, x, y);
    }
    draw_legend(&mut svg, PLOT, &legend);
    svg.finish()
}

/// The largest 2-norm condition number over the enumerated cases against ε (paper Figure 5,
/// right), with the Jacobi-scaled one; the current ε marked with both values in the legend.
pub fn eps_cond_figure(points: &[EpsPoint], current_epsilon: Option<f64>, title: &str) -> String {
    let mut svg = page(
        title,
        "Largest condition number of the case matrices against ε (paper Figure 5, right)",
        (EPSILON_AXIS, "largest cond₂ over the cases [1]"),
        "cond₂ of the case matrices Â of (43), and of their Jacobi scaling",
    );
    type Value = fn(&EpsPoint) -> Option<f64>;
    let plain: Value = |p| p.cond_max.map(|c| c.value);
    let scaled: Value = |p| p.cond_scaled_max.map(|c| c.value);
    let series: Vec<Series> = [("cond₂(Â)", plain), ("Jacobi-scaled", scaled)]
        .into_iter()
        .enumerate()
        .map(|(i, (name, value))| Series {
            name: name.into(),
            style: SeriesStyle::indexed(i),
            points: plottable(points.iter().map(|p| (p.epsilon, value(p)))),
        })
        .filter(|s| !s.points.is_empty())
        .collect();
    let Some(axes) = log_axes(&series) else {
        let text = format!(
            "no condition numbers to plot: they are computed for N ≤ {CONDITION_LIMIT} unknowns, \
             by the enumerating method"
        );
        draw_notice(&mut svg, &text);
        return svg.finish();
    };
    axes.draw(&mut svg, 34.0);
    let mut legend: Vec<LegendEntry> = series
        .iter()
        .map(|s| LegendEntry::new(Sample::Series(s.style), vec![s.name.clone()]))
        .collect();
    let current = current_epsilon.and_then(|e| points.iter().find(|p| p.epsilon == e));
    if let Some(epsilon) = current_epsilon.filter(|e| *e > 0.0) {
        let lines = match current {
            None => vec!["not in the sweep".to_string()],
            Some(p) => vec![
                format!("cond₂ {}", plain(p).map_or("n/a".into(), |c| sci(c, 3))),
                format!("scaled {}", scaled(p).map_or("n/a".into(), |c| sci(c, 3))),
            ],
        };
        legend.push(epsilon_entry(epsilon, lines));
        current_rule(&mut svg, PLOT, axes.x_px(epsilon));
    }
    for s in &series {
        draw_series(&mut svg, &axes, s);
    }
    if let Some(p) = current {
        for (x, y) in plottable([(p.epsilon, plain(p)), (p.epsilon, scaled(p))]) {
            current_ring(&mut svg, &axes, x, y);
        }
    }
    draw_legend(&mut svg, PLOT, &legend);
    svg.finish()
}

/// What the error-against-run-time figure puts on its x axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorAxis {
    /// The run time [s] (the explorer with timings shown, and the report).
    RunTime,
    /// The number of elements n.
    Elements,
}

/// A point's error against the reference; none for the reference itself.
fn error_of(point: &MeshPoint) -> Option<f64> {
    point
        .error
        .filter(|e| e.reference != Reference::ThisSolution)
        .and_then(|e| e.max_rel)
}

/// A point's x value.
fn x_of(point: &MeshPoint, against: ErrorAxis) -> f64 {
    match against {
        ErrorAxis::RunTime => point.run_time.as_secs_f64(),
        ErrorAxis::Elements => point.elements as f64,
    }
}

/// One series per method that has a point to plot, in [`Method::ALL`] order, its points in
/// the order of the sweep (by n); refused points and the reference's own are left out.
pub fn method_series(points: &[MeshPoint], against: ErrorAxis) -> Vec<Series> {
    Method::ALL
        .into_iter()
        .map(|method| Series {
            name: method.name().into(),
            style: SeriesStyle::of_method(method),
            points: plottable(
                points
                    .iter()
                    .filter(|p| p.method == method && p.refused.is_none())
                    .map(|p| (x_of(p, against), error_of(p))),
            ),
        })
        .filter(|s| !s.points.is_empty())
        .collect()
}

/// Every method's error against its run time (or against n): one line with markers per
/// method; the current run (its n and method) marked by a rule at its n, or at its run time,
/// and a ring, its error (and run time) in the legend.
pub fn error_time_figure(
    points: &[MeshPoint],
    against: ErrorAxis,
    current: Option<CurrentRun>,
    title: &str,
) -> String {
    let reference = points
        .iter()
        .find_map(|p| p.error.map(|e| e.reference))
        .filter(|r| *r != Reference::ThisSolution)
        .map_or("the reference".to_string(), |r| r.label().to_string());
    let x_name = match against {
        ErrorAxis::RunTime => "run time t [s]",
        ErrorAxis::Elements => "elements n [1]",
    };
    let note = match against {
        ErrorAxis::RunTime => format!("error against: {reference}; t: median run time"),
        ErrorAxis::Elements => format!("error against: {reference}"),
    };
    let mut svg = page(
        title,
        "Every method's error against its run time or mesh size",
        (x_name, ERROR_AXIS),
        &note,
    );
    let series = method_series(points, against);
    let Some(axes) = log_axes(&series) else {
        draw_notice(
            &mut svg,
            "no error to plot: no method gave a positive finite error against the reference",
        );
        return svg.finish();
    };
    axes.draw(&mut svg, 34.0);
    let selected = current.map(|c| c.method);
    let mut legend: Vec<LegendEntry> = series
        .iter()
        .map(|s| LegendEntry {
            bold: selected.is_some_and(|m| m.name() == s.name),
            ..LegendEntry::new(Sample::Series(s.style), vec![s.name.clone()])
        })
        .collect();
    let at = current.and_then(|run| {
        points
            .iter()
            .find(|p| p.method == run.method && p.elements == run.elements)
    });
    if let Some(run) = current {
        legend.push(LegendEntry::new(
            Sample::Current,
            current_lines(run, at, against),
        ));
        let rule = match against {
            ErrorAxis::Elements => Some(run.elements as f64),
            ErrorAxis::RunTime => at
                .filter(|p| p.refused.is_none())
                .map(|p| x_of(p, against))
                .filter(|t| *t > 0.0),
        };
        if let Some(x) = rule {
            current_rule(&mut svg, PLOT, axes.x_px(x));
        }
    }
    // The selected method last: drawn over the others.
    let mut order: Vec<&Series> = series.iter().collect();
    order.sort_by_key(|s| selected.is_some_and(|m| m.name() == s.name));
    for s in order {
        draw_series(&mut svg, &axes, s);
    }
    if let Some(p) = at.filter(|p| p.refused.is_none()) {
        for (x, y) in plottable([(x_of(p, against), error_of(p))]) {
            current_ring(&mut svg, &axes, x, y);
        }
    }
    if against == ErrorAxis::RunTime {
        // Against time, n is not on an axis: one method's points say theirs (the selected
        // method's, else the one with the most points).
        let labelled = selected.or_else(|| {
            series
                .iter()
                .max_by_key(|s| s.points.len())
                .and_then(|s| Method::ALL.into_iter().find(|m| m.name() == s.name))
        });
        if let Some(method) = labelled {
            draw_sizes(&mut svg, &axes, points, method);
        }
    }
    draw_legend(&mut svg, PLOT, &legend);
    svg.finish()
}

/// Each point of `method` against run time labelled with its n (`n = 10`, `32`, … `3.2e4`),
/// right of its marker, or left where that would leave the plot.
fn draw_sizes(svg: &mut super::svg::Svg, axes: &Axes, points: &[MeshPoint], method: Method) {
    use super::svg::{Anchor, NOTE_SIZE, text_width};
    let mut first = true;
    for p in points
        .iter()
        .filter(|p| p.method == method && p.refused.is_none())
    {
        let Some((x, y)) = plottable([(x_of(p, ErrorAxis::RunTime), error_of(p))]).pop() else {
            continue;
        };
        let size = if p.elements < 10_000 {
            p.elements.to_string()
        } else {
            sci(p.elements as f64, 2)
        };
        let text = if first { format!("n = {size}") } else { size };
        first = false;
        let (px, py) = axes.to_px(x, y);
        let (at, anchor) = if px + 10.0 + text_width(&text, NOTE_SIZE) <= PLOT.right {
            (px + 10.0, Anchor::Start)
        } else {
            (px - 10.0, Anchor::End)
        };
        svg.text(
            (at, py - 10.0),
            anchor,
            NOTE_SIZE,
            &text,
            &format!(r#"class="n-label" data-n="{}""#, p.elements),
        );
    }
}

/// The legend's lines for the current run: its method and n, its error (or why there is
/// none) and its run time.
fn current_lines(run: CurrentRun, at: Option<&MeshPoint>, against: ErrorAxis) -> Vec<String> {
    let mut lines = vec![
        format!("current: n = {}", run.elements),
        run.method.name().to_string(),
    ];
    lines.push(match at {
        None => "not in the sweep".into(),
        Some(p) if p.refused.is_some() => "gave no result".into(),
        Some(p) if p.is_reference() => "is the reference".into(),
        Some(p) => format!("error {}", error_of(p).map_or("n/a".into(), |e| sci(e, 3))),
    });
    if against == ErrorAxis::RunTime
        && let Some(p) = at.filter(|p| p.refused.is_none())
    {
        lines.push(format!("in {}", duration(p.run_time)));
    }
    lines
}
