//! The paper's Figure 5 as one chart: the regularisation error (left of the figure) and the
//! largest cond₂ of the case matrices Â of (43) (right of the figure) against ε, stacked on one
//! shared ε axis, the current ε marked on both with both values printed — readable at 80×24
//! without paging between two panels.

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Dataset, GraphType, Paragraph};

use super::Theme;
use super::chart::{
    PanelFrame, bounds_of, curve_key, curve_marker, fitted_title, log_points, marker_char, notice,
    point_marker,
};
use super::plot_area::Markers;
use super::study_charts::{current_line, epsilon_plot, point_at};
use crate::format::sci;
use crate::study::EpsPoint;

/// A series of a chart: its log10 points, marker (Unicode, ASCII), style, and whether it is
/// drawn as a line (else as markers).
type Series<'a> = (&'a [(f64, f64)], (char, char), Style, bool);

/// One of the two stacked charts: its label line's pieces and its series.
struct Half<'a> {
    label: Vec<(String, Style)>,
    series: Vec<Series<'a>>,
    /// The current ε's values on this chart (log10 points).
    current: Vec<(f64, f64)>,
}

/// Figure 5 in one panel: error above, cond₂(Â) (and its Jacobi-scaled value) below, one ε
/// axis for both.
pub fn figure5_chart(
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
    let (Some((x_error, y_error)), Some((x_cond, y_cond))) =
        (bounds_of(&error), bounds_of(plain.iter().chain(&scaled)))
    else {
        let text = format!(
            "Figure 5 needs both curves: the error and the condition numbers (computed for N ≤ \
             {} unknowns)",
            crate::study::CONDITION_LIMIT
        );
        return notice(frame, theme, panel, text);
    };
    // One ε axis for both.
    let x = [x_error[0].min(x_cond[0]), x_error[1].max(x_cond[1])];
    let title = fitted_title(
        &theme.text(&panel.title),
        panel.area.width,
        theme.look.ascii,
    );
    let block = theme.block(title, panel.focused);
    let inner = block.inner(panel.area);
    frame.render_widget(block, panel.area);
    let current = point_at(points, current_epsilon);
    let value = |v: Option<f64>| v.map_or("n/a".to_string(), |v| sci(v, 2));
    let curve = curve_key(theme);
    let scaled_marker = ('+', '+');
    let mut error_label = Vec::new();
    if let Some(epsilon) = current_epsilon {
        error_label.push((
            format!("{} ε = {}:", current_line(theme), sci(epsilon, 2)),
            theme.current(),
        ));
    }
    let reference = points
        .iter()
        .find_map(|p| p.error.map(|e| e.reference.label()))
        .unwrap_or("the reference");
    let error_value = current.and_then(|p| p.error.and_then(|e| e.max_rel));
    error_label.push((
        format!("{curve} error {} vs {reference}", value(error_value)),
        theme.series(0),
    ));
    let upper = Half {
        label: error_label,
        series: vec![(&error, ('•', '*'), theme.series(0), true)],
        current: log_points([(current_epsilon.unwrap_or(0.0), error_value)].into_iter()),
    };
    let plain_value = current.and_then(|p| p.cond_max.map(|c| c.value));
    let scaled_value = current.and_then(|p| p.cond_scaled_max.map(|c| c.value));
    let lower = Half {
        label: vec![
            (
                format!("{curve} cond₂(Â) {}", value(plain_value)),
                theme.series(0),
            ),
            (
                format!(
                    "{} Jacobi-scaled {}",
                    marker_char(theme, scaled_marker.0, scaled_marker.1),
                    value(scaled_value)
                ),
                theme.series(1),
            ),
        ],
        // The scaled markers first: the cond₂ curve is drawn over them.
        series: vec![
            (&scaled, scaled_marker, theme.series(1), false),
            (&plain, ('•', '*'), theme.series(0), true),
        ],
        current: log_points(
            [
                (current_epsilon.unwrap_or(0.0), plain_value),
                (current_epsilon.unwrap_or(0.0), scaled_value),
            ]
            .into_iter(),
        ),
    };
    let [top, bottom] =
        Layout::vertical([Constraint::Ratio(1, 2), Constraint::Ratio(1, 2)]).areas(inner);
    draw_half(frame, theme, top, &upper, x, y_error, current_epsilon);
    draw_half(frame, theme, bottom, &lower, x, y_cond, current_epsilon);
}

/// One stacked chart: its label line on top, the plot under it.
fn draw_half(
    frame: &mut Frame,
    theme: &Theme,
    area: Rect,
    half: &Half,
    x: [f64; 2],
    y: [f64; 2],
    current_epsilon: Option<f64>,
) {
    if area.height == 0 {
        return;
    }
    let [label, plot] = Layout::vertical([Constraint::Length(1), Constraint::Min(0)]).areas(area);
    let mut spans = Vec::new();
    for (i, (text, style)) in half.label.iter().enumerate() {
        if i > 0 {
            spans.push(Span::raw("  "));
        }
        spans.push(Span::styled(theme.text(text).into_owned(), *style));
    }
    frame.render_widget(Paragraph::new(Line::from(spans)), label);
    let Some(chart) = epsilon_plot(frame, theme, plot, x, y, current_epsilon) else {
        return;
    };
    let buffer = frame.buffer_mut();
    let units: Vec<Vec<(f64, f64)>> = half
        .series
        .iter()
        .map(|(points, ..)| points.iter().map(|p| chart.unit(*p)).collect())
        .collect();
    let datasets = half
        .series
        .iter()
        .zip(&units)
        .map(|((_, marker, style, line), data)| {
            let dataset = Dataset::default().style(*style).data(data);
            if *line {
                dataset
                    .marker(curve_marker(theme))
                    .graph_type(GraphType::Line)
            } else {
                dataset
                    .marker(point_marker(theme, marker.0, marker.1))
                    .graph_type(GraphType::Scatter)
            }
        })
        .collect();
    chart.draw_datasets(buffer, theme, datasets);
    chart.draw_axes(buffer, theme);
    let marks: Vec<(f64, f64, Style)> = half
        .current
        .iter()
        .map(|&(x, y)| (x, y, theme.current()))
        .collect();
    chart.scatter(
        buffer,
        &[Markers {
            symbol: marker_char(theme, '●', 'O'),
            points: marks,
        }],
    );
}
