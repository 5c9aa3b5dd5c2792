//! The pieces every chart panel is made of: a bordered block with its key inside, a notice in
//! place of a chart, markers in Unicode or ASCII, and the log–log chart of plain series with
//! decade axes and an optional vertical marker (the current ε).

use ratatui::Frame;
use ratatui::layout::{Alignment, Constraint, Layout, Rect};
use ratatui::style::Style;
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Chart, Dataset, GraphType, Paragraph, Wrap};

use super::Theme;
use super::axes::decade_axis;

/// Where a chart goes: its area, the title of its block, and whether it has the focus.
#[derive(Debug, Clone)]
pub struct PanelFrame {
    pub area: Rect,
    pub title: String,
    pub focused: bool,
}

/// A message in place of a chart.
pub fn notice(frame: &mut Frame, theme: &Theme, panel: PanelFrame, text: String) {
    let block = theme.block(panel.title, panel.focused);
    frame.render_widget(
        Paragraph::new(text)
            .wrap(Wrap { trim: true })
            .alignment(Alignment::Center)
            .block(block),
        panel.area,
    );
}

/// One entry of a chart's key: its marker and name.
pub struct KeyEntry {
    pub marker: char,
    pub name: String,
    pub style: Style,
}

/// Draws `chart` in a bordered block with its key on the last lines inside the block (a
/// ratatui legend would hide itself in narrow panels).
pub fn chart_with_key(
    frame: &mut Frame,
    theme: &Theme,
    panel: PanelFrame,
    chart: Chart,
    key: &[KeyEntry],
) {
    let block = theme.block(panel.title, panel.focused);
    let inner = block.inner(panel.area);
    frame.render_widget(block, panel.area);
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
    let [plot, legend] =
        Layout::vertical([Constraint::Min(1), Constraint::Length(key_height)]).areas(inner);
    frame.render_widget(chart, plot);
    let text: Vec<Line> = lines.into_iter().map(Line::from).collect();
    frame.render_widget(Paragraph::new(text), legend);
}

/// The marker of a curve: Braille dots, or `.` in ASCII.
pub fn curve_marker(theme: &Theme) -> Marker {
    if theme.look.ascii {
        Marker::Custom('.')
    } else {
        Marker::Braille
    }
}

/// A point marker: `unicode`, or `ascii` in ASCII mode.
pub fn point_marker(theme: &Theme, unicode: char, ascii: char) -> Marker {
    Marker::Custom(marker_char(theme, unicode, ascii))
}

/// The character of a point marker for the theme's look.
pub fn marker_char(theme: &Theme, unicode: char, ascii: char) -> char {
    if theme.look.ascii { ascii } else { unicode }
}

/// (log10 x, log10 y) of the pairs whose values are positive and finite.
pub fn log_points(pairs: impl Iterator<Item = (f64, Option<f64>)>) -> Vec<(f64, f64)> {
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
pub type Series = ((char, char), String, Vec<(f64, f64)>, GraphType);

/// What a log–log chart shows.
pub struct LogLog<'a> {
    pub x_title: &'a str,
    pub series: &'a [Series],
    /// The current ε, marked by a vertical line.
    pub current_epsilon: Option<f64>,
    /// The notice when no series has a point.
    pub empty: String,
}

/// A log–log chart of `chart.series` with the current ε marked when given.
pub fn log_log(frame: &mut Frame, theme: &Theme, panel: PanelFrame, chart: LogLog) {
    let all: Vec<&[(f64, f64)]> = chart
        .series
        .iter()
        .map(|(_, _, d, _)| d.as_slice())
        .collect();
    let Some((x, y)) = bounds_of(&all) else {
        return notice(frame, theme, panel, chart.empty);
    };
    let area = panel.area;
    let (x_bounds, x_labels) = decade_axis(x[0], x[1], area.width.saturating_sub(10));
    let (y_bounds, y_labels) = decade_axis(y[0], y[1], area.height.saturating_sub(6) * 3);
    let marker: Vec<(f64, f64)> = chart
        .current_epsilon
        .map(|e| vec![(e.log10(), y_bounds[0]), (e.log10(), y_bounds[1])])
        .unwrap_or_default();
    let mut key = Vec::new();
    let mut datasets = Vec::new();
    for (i, ((u, a), name, data, kind)) in chart.series.iter().enumerate() {
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
    if let Some(epsilon) = chart.current_epsilon {
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
    let widget = Chart::new(datasets)
        .x_axis(
            Axis::default()
                .title(chart.x_title)
                .bounds(x_bounds)
                .labels(x_labels),
        )
        .y_axis(Axis::default().bounds(y_bounds).labels(y_labels))
        .legend_position(None);
    chart_with_key(frame, theme, panel, widget, &key);
}
