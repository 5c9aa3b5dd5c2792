//! A method's convergence history: per iteration the measure the method itself stops on (the
//! projected-gradient norm of the box QP of (49), the semismooth residual of Newton's method
//! on (40), the KKT residual of the condensed search), on a log axis against the iteration,
//! with how many friction DOFs changed state at each step; the selected iterate marked and
//! its numbers printed.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::Style;
use ratatui::widgets::{Dataset, GraphType};

use super::Theme;
use super::chart::{
    PanelFrame, Piece, curve_marker, key_layout, marker_char, notice, panel_with_key,
};
use super::plot_area::{AxisKind, AxisSpec, Markers, PlotArea};
use crate::format::sci;
use crate::solve::History;

/// Rows the chart keeps before the readout takes the rest.
const PLOT_ROWS: u16 = 5;
/// Most per-iterate change counts listed in the readout.
const CHANGES_LISTED: usize = 12;

/// The changes of state per iterate, as a short list.
fn changes(history: &History) -> String {
    let counts: Vec<String> = history
        .iterations
        .iter()
        .skip(1)
        .map(|r| r.changed.to_string())
        .collect();
    let total: usize = history.iterations.iter().skip(1).map(|r| r.changed).sum();
    if counts.len() <= CHANGES_LISTED {
        format!("DOFs changing state per step: {}", counts.join(" "))
    } else {
        format!(
            "DOFs changing state per step: {} … {} (total {total})",
            counts[..CHANGES_LISTED - 2].join(" "),
            counts[counts.len() - 1]
        )
    }
}

/// The readout (always shown) and the optional lines of the chart.
fn readout(theme: &Theme, history: &History, selected: usize) -> (Vec<Piece>, Vec<Piece>) {
    let record = &history.iterations[selected];
    let last = history.iterations.len() - 1;
    let marker = marker_char(theme, '◆', '@');
    let mut readout: Vec<Piece> = vec![(
        format!(
            "{marker} iterate {} of {}: {} {}",
            record.iteration,
            history.iterations[last].iteration,
            history.measure.label(),
            sci(record.measure, 2)
        ),
        theme.current(),
    )];
    if selected > 0 {
        readout.push((
            format!("{} DOFs changed state", record.changed),
            theme.series(1),
        ));
    }
    if let Some(objective) = record.objective {
        readout.push((format!("objective {}", sci(objective, 4)), theme.dim()));
    }
    let zero = history.iterations.iter().any(|r| r.measure == 0.0);
    let mut optional: Vec<Piece> = vec![
        (changes(history), theme.dim()),
        (
            if zero {
                "(the lowest points are exactly 0)".into()
            } else {
                String::new()
            },
            theme.dim(),
        ),
        (
            if history.truncated {
                "(long history: the first and last iterates kept) < >: iterate".into()
            } else {
                "< >: iterate".into()
            },
            theme.dim(),
        ),
    ];
    optional.retain(|(text, _)| !text.is_empty());
    (readout, optional)
}

/// The measure's log10 points (iteration, log10 measure). A measure of exactly 0 (an exact
/// solve's last step) has no logarithm: it sits a decade under the smallest other, where the
/// readout says it is 0 (and the drawing moves it to the plot's bottom).
fn measure_points(history: &History) -> Vec<(f64, f64)> {
    let zero_at = zero_level(history);
    history
        .iterations
        .iter()
        .filter_map(|r| {
            let y = if r.measure > 0.0 && r.measure.is_finite() {
                r.measure.log10()
            } else if r.measure == 0.0 {
                zero_at
            } else {
                return None;
            };
            Some((r.iteration as f64, y))
        })
        .collect()
}

/// Where a measure of 0 is placed for the axes: a decade under the smallest positive one.
fn zero_level(history: &History) -> f64 {
    let floor = history
        .iterations
        .iter()
        .filter(|r| r.measure > 0.0 && r.measure.is_finite())
        .map(|r| r.measure.log10())
        .fold(f64::INFINITY, f64::min);
    if floor.is_finite() { floor - 1.0 } else { -1.0 }
}

/// The chart's axes in `plot`.
fn plot_area(plot: Rect, history: &History, points: &[(f64, f64)]) -> Option<PlotArea> {
    let (low, high) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
            (l.min(p.1), h.max(p.1))
        });
    let y_range = if low.is_finite() {
        [low, high]
    } else {
        [-1.0, 0.0]
    };
    // At least four steps across, so that the ticks fall on whole iterations.
    let last_iteration = history.iterations.last().map_or(4, |r| r.iteration.max(4)) as f64;
    let x_axis = AxisSpec {
        kind: AxisKind::Linear,
        range: [0.0, last_iteration],
        title: "iteration".into(),
    };
    let y_axis = AxisSpec {
        kind: AxisKind::Log,
        range: y_range,
        title: String::new(),
    };
    let mut area = PlotArea::new(plot, &x_axis, &y_axis)?;
    // Iterations are whole: no tick between two.
    area.x.ticks.retain(|t| t.fract() == 0.0);
    area.x.labels.retain(|(t, _)| t.fract() == 0.0);
    Some(area)
}

/// Where the chart of a panel of `area` plots (the same layout as the drawing): for a click
/// on an iterate.
pub fn iterations_plot(
    theme: &Theme,
    area: Rect,
    history: &History,
    selected: Option<usize>,
) -> Option<PlotArea> {
    let last = history.iterations.len().checked_sub(1)?;
    let (readout, optional) = readout(theme, history, selected.unwrap_or(last).min(last));
    let inner = theme.block(String::new(), false).inner(area);
    let plot = key_layout(theme, inner, &readout, &optional, &[], PLOT_ROWS).0;
    plot_area(plot, history, &measure_points(history))
}

/// The history of one solve, the `selected` iterate (`None`: the last) marked.
pub fn iterations_chart(
    frame: &mut Frame,
    theme: &Theme,
    panel: PanelFrame,
    history: &History,
    selected: Option<usize>,
) {
    let records = &history.iterations;
    let Some(last) = records.len().checked_sub(1) else {
        return notice(frame, theme, panel, "no iterations were recorded".into());
    };
    let selected = selected.unwrap_or(last).min(last);
    let record = &records[selected];
    let marker = marker_char(theme, '◆', '@');
    let (readout, optional) = readout(theme, history, selected);
    let plot = panel_with_key(frame, theme, &panel, &readout, &optional, &[], PLOT_ROWS);
    let mut points = measure_points(history);
    let Some(area) = plot_area(plot, history, &points) else {
        return;
    };
    // Exact zeros on the bottom of the plot, under every logarithm.
    let zero_at = zero_level(history);
    for point in &mut points {
        if point.1 == zero_at {
            point.1 = area.y.bounds[0];
        }
    }
    let buffer = frame.buffer_mut();
    area.vertical_line(
        buffer,
        record.iteration as f64,
        if theme.look.ascii { ":" } else { "┆" },
        theme.current(),
    );
    let data: Vec<(f64, f64)> = points.iter().map(|p| area.unit(*p)).collect();
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
    let dots: Vec<(f64, f64, Style)> = points
        .iter()
        .filter(|p| p.0 != record.iteration as f64)
        .map(|&(x, y)| (x, y, theme.series(0)))
        .collect();
    let chosen: Vec<(f64, f64, Style)> = points
        .iter()
        .filter(|p| p.0 == record.iteration as f64)
        .map(|&(x, y)| (x, y, theme.current()))
        .collect();
    area.scatter(
        buffer,
        &[
            Markers {
                symbol: marker,
                points: chosen,
            },
            Markers {
                symbol: marker_char(theme, '∘', 'o'),
                points: dots,
            },
        ],
    );
}
