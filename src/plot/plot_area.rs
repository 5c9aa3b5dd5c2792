//! The plotting rectangle of a chart with axes whose labels are at their values: [`PlotArea`]
//! lays out the y labels on the left, the x labels and title below, and the graph between, with
//! margins wide enough that every label can sit centred on its tick; it draws the axis lines,
//! ticks and labels itself (ratatui's chart, which spreads labels evenly, only draws the data,
//! into the graph, in a unit square), point markers that move aside instead of hiding each
//! other, and vertical or horizontal marker lines.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::Style;
use ratatui::widgets::{Axis, Chart, Dataset};

use super::Theme;
use super::axes::{
    Scale, cell, label_start, linear_scale, log_scale, to_unit, widest_decade_label,
};

/// Log or linear.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisKind {
    /// Values are log10 of the data; ticks on decades.
    Log,
    /// Nice ticks, 1, 2 or 5 × 10^k.
    Linear,
}

/// What an axis must cover.
#[derive(Debug, Clone)]
pub struct AxisSpec {
    pub kind: AxisKind,
    /// Smallest and largest plotted value (log10 for a log axis).
    pub range: [f64; 2],
    /// The axis title (already spelled for the look); x only.
    pub title: String,
}

impl AxisSpec {
    fn scale(&self, cells: u16, horizontal: bool) -> Scale {
        match self.kind {
            AxisKind::Log => log_scale(self.range[0], self.range[1], cells, horizontal),
            AxisKind::Linear => linear_scale(self.range[0], self.range[1], cells, horizontal),
        }
    }
}

/// A laid-out chart: where the graph is and the two scales.
#[derive(Debug, Clone)]
pub struct PlotArea {
    /// The whole rectangle (graph, axes, labels).
    pub area: Rect,
    /// Where the data goes.
    pub graph: Rect,
    pub x: Scale,
    pub y: Scale,
    x_title: String,
}

fn widest(labels: &[(f64, String)]) -> u16 {
    labels
        .iter()
        .map(|(_, t)| t.chars().count() as u16)
        .max()
        .unwrap_or(1)
}

impl PlotArea {
    /// Lays out a chart in `area`, or `None` when it is too small for one (under 12×4 cells).
    /// The x title goes at the end of the x axis, right of its last tick (the graph narrows to
    /// make room when it must), so that it never sits beside a tick's label and reads as a
    /// value; when even that leaves no graph, the chart has no x title (the panel's title
    /// names the axis).
    pub fn new(area: Rect, x: &AxisSpec, y: &AxisSpec) -> Option<PlotArea> {
        PlotArea::lay_out(area, x, y, true).or_else(|| PlotArea::lay_out(area, x, y, false))
    }

    fn lay_out(area: Rect, x: &AxisSpec, y: &AxisSpec, with_title: bool) -> Option<PlotArea> {
        if area.height < 4 || area.width < 12 {
            return None;
        }
        let graph_height = area.height - 2;
        let y_scale = y.scale(graph_height, false);
        let y_width = widest(&y_scale.labels);
        // The widest x label: exact for decades, from a first try for linear axes.
        let mut x_width = match x.kind {
            AxisKind::Log => widest_decade_label(x.range[0], x.range[1]),
            AxisKind::Linear => {
                widest(&x.scale(area.width.saturating_sub(y_width + 2), true).labels)
            }
        };
        let title = if with_title { x.title.as_str() } else { "" };
        // Cells the title takes at the end of the axis row: a blank, then the title.
        let title_cells = match title.chars().count() as u16 {
            0 => 0,
            width => width + 1,
        };
        let mut title_room = 0u16;
        for _ in 0..6 {
            let left = (y_width + 1).max((x_width - 1) / 2);
            let right = (x_width / 2).max(1) + title_room;
            let graph_width = area.width.checked_sub(left + right)?;
            if graph_width < 4 {
                return None;
            }
            let x_scale = x.scale(graph_width, true);
            let needed = widest(&x_scale.labels);
            if needed > x_width {
                x_width = needed;
                continue;
            }
            // Free cells of the axis row right of the last tick (to the area's right edge).
            let last_tick = x_scale
                .ticks
                .iter()
                .filter_map(|&t| cell(t, x_scale.bounds, graph_width))
                .max()
                .map_or(0, |c| c + 1);
            let free = area.width - left - last_tick;
            if free < title_cells {
                title_room += title_cells - free;
                continue;
            }
            let graph = Rect::new(area.x + left, area.y, graph_width, graph_height);
            return Some(PlotArea {
                area,
                graph,
                x: x_scale,
                y: y_scale,
                x_title: title.to_string(),
            });
        }
        None
    }

    /// The column of `x` (plotted value), if inside.
    pub fn column(&self, x: f64) -> Option<u16> {
        cell(x, self.x.bounds, self.graph.width).map(|c| self.graph.x + c)
    }

    /// The row of `y` (plotted value), if inside.
    pub fn row(&self, y: f64) -> Option<u16> {
        cell(y, self.y.bounds, self.graph.height).map(|c| self.graph.bottom() - 1 - c)
    }

    /// A point in the unit square the chart widget draws in.
    pub fn unit(&self, (x, y): (f64, f64)) -> (f64, f64) {
        (to_unit(x, self.x.bounds), to_unit(y, self.y.bounds))
    }

    /// The row of the x axis line, and of the x labels.
    fn axis_row(&self) -> u16 {
        self.graph.bottom()
    }

    /// Draws the axis lines, ticks, labels and the x title.
    pub fn draw_axes(&self, buffer: &mut Buffer, theme: &Theme) {
        let ascii = theme.look.ascii;
        let line = theme.faint();
        let label_style = theme.plain();
        let axis_x = self.graph.x - 1;
        let axis_row = self.axis_row();
        let label_row = axis_row + 1;
        let (vertical, horizontal, corner, y_tick, x_tick) = if ascii {
            ("|", "-", "+", "+", "+")
        } else {
            ("│", "─", "└", "┤", "┬")
        };
        for row in self.graph.top()..self.graph.bottom() {
            buffer[(axis_x, row)].set_symbol(vertical).set_style(line);
        }
        for column in self.graph.left()..self.graph.right() {
            buffer[(column, axis_row)]
                .set_symbol(horizontal)
                .set_style(line);
        }
        buffer[(axis_x, axis_row)]
            .set_symbol(corner)
            .set_style(line);
        for &t in &self.y.ticks {
            if let Some(row) = self.row(t) {
                buffer[(axis_x, row)].set_symbol(y_tick).set_style(line);
            }
        }
        for &t in &self.x.ticks {
            if let Some(column) = self.column(t) {
                buffer[(column, axis_row)]
                    .set_symbol(x_tick)
                    .set_style(line);
            }
        }
        for (value, text) in &self.y.labels {
            if let Some(row) = self.row(*value) {
                let width = text.chars().count() as u16;
                let x = axis_x.saturating_sub(width).max(self.area.x);
                buffer.set_stringn(x, row, text, (axis_x - x) as usize, label_style);
            }
        }
        // x labels centred on their columns.
        for (value, text) in &self.x.labels {
            if let Some(column) = self.column(*value) {
                let width = text.chars().count() as u16;
                let start = label_start(column, width).max(i32::from(self.area.x)) as u16;
                buffer.set_stringn(start, label_row, text, width as usize, label_style);
            }
        }
        // The x title ends the axis row, after a blank, right of the last tick (see `new`).
        let width = self.x_title.chars().count() as u16;
        if width > 0 {
            let start = self.area.right() - width;
            if start > self.graph.x {
                buffer[(start - 1, axis_row)].set_symbol(" ");
            }
            buffer.set_stringn(start, axis_row, &self.x_title, width as usize, theme.dim());
        }
    }

    /// Draws the datasets (their points in the unit square, see [`PlotArea::unit`]) into the
    /// graph with ratatui's chart.
    pub fn draw_datasets(&self, buffer: &mut Buffer, theme: &Theme, datasets: Vec<Dataset>) {
        use ratatui::widgets::Widget;
        Chart::new(datasets)
            .style(theme.base())
            .x_axis(Axis::default().bounds([0.0, 1.0]))
            .y_axis(Axis::default().bounds([0.0, 1.0]))
            .legend_position(None)
            .render(self.graph, buffer);
    }

    /// A vertical line at `x` over the whole graph, under what is drawn later.
    pub fn vertical_line(&self, buffer: &mut Buffer, x: f64, symbol: &str, style: Style) {
        if let Some(column) = self.column(x) {
            for row in self.graph.top()..self.graph.bottom() {
                buffer[(column, row)].set_symbol(symbol).set_style(style);
            }
        }
    }

    /// Marks the x axis line from `range[0]` to `range[1]` (plotted values) with `glyph`,
    /// ticks kept: a stretch of the x axis told apart (the beam's segments).
    pub fn mark_axis(&self, buffer: &mut Buffer, range: [f64; 2], glyph: char, style: Style) {
        let (Some(from), Some(to)) = (self.column(range[0]), self.column(range[1])) else {
            return;
        };
        let ticks: Vec<u16> = self
            .x
            .ticks
            .iter()
            .filter_map(|&t| self.column(t))
            .collect();
        for column in from..=to {
            if !ticks.contains(&column) {
                buffer[(column, self.axis_row())]
                    .set_char(glyph)
                    .set_style(style);
            }
        }
    }

    /// A horizontal line at `y` over the whole graph, under what is drawn later.
    pub fn horizontal_line(&self, buffer: &mut Buffer, y: f64, symbol: &str, style: Style) {
        if let Some(row) = self.row(y) {
            for column in self.graph.left()..self.graph.right() {
                buffer[(column, row)].set_symbol(symbol).set_style(style);
            }
        }
    }

    /// Point markers of several series, in the order given (the first placed first, at their
    /// own cells): a marker whose cell another series already took moves to the nearest free
    /// cell in its row, at most three columns away, so no series hides another. Returns how
    /// many markers could not be placed without covering another.
    pub fn scatter(&self, buffer: &mut Buffer, series: &[Markers]) -> usize {
        let (w, h) = (self.graph.width as usize, self.graph.height as usize);
        let mut owner: Vec<Option<usize>> = vec![None; w * h];
        let mut hidden = 0;
        for (s, markers) in series.iter().enumerate() {
            for &(x, y, style) in &markers.points {
                let (Some(column), Some(row)) = (self.column(x), self.row(y)) else {
                    continue;
                };
                let (c, r) = (
                    (column - self.graph.x) as usize,
                    (row - self.graph.y) as usize,
                );
                let free = |c: i64| -> Option<usize> {
                    (0..w as i64).contains(&c).then_some(())?;
                    let index = r * w + c as usize;
                    match owner[index] {
                        None => Some(index),
                        Some(o) if o == s => Some(index),
                        Some(_) => None,
                    }
                };
                let spot = [0i64, 1, -1, 2, -2, 3, -3]
                    .iter()
                    .find_map(|d| free(c as i64 + d))
                    .unwrap_or_else(|| {
                        hidden += 1;
                        r * w + c
                    });
                owner[spot] = Some(s);
                let (sx, sy) = ((spot % w) as u16, (spot / w) as u16);
                buffer[(self.graph.x + sx, self.graph.y + sy)]
                    .set_char(markers.symbol)
                    .set_style(style);
            }
        }
        hidden
    }
}

/// The point markers of one series: the character and each point (plotted values) with its
/// style.
#[derive(Debug, Clone)]
pub struct Markers {
    pub symbol: char,
    pub points: Vec<(f64, f64, Style)>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use ratatui::symbols::Marker;
    use ratatui::widgets::GraphType;

    fn look() -> Theme {
        Theme::new(
            super::super::Look {
                ascii: false,
                color: false,
            },
            super::super::Palette::Dark,
            super::super::MarkerSet::Braille,
        )
    }

    /// Where ratatui's chart draws these points (plotted values): the cells it marks, in
    /// reading order — the independent reference for where the labels must be.
    fn drawn(plot: &PlotArea, points: &[(f64, f64)], marker: Marker) -> Vec<(u16, u16)> {
        let mut buffer = Buffer::empty(plot.area);
        let data: Vec<(f64, f64)> = points.iter().map(|p| plot.unit(*p)).collect();
        plot.draw_datasets(
            &mut buffer,
            &look(),
            vec![
                Dataset::default()
                    .marker(marker)
                    .graph_type(GraphType::Scatter)
                    .data(&data),
            ],
        );
        let area = plot.graph;
        (area.top()..area.bottom())
            .flat_map(|y| (area.left()..area.right()).map(move |x| (x, y)))
            .filter(|&(x, y)| buffer[(x, y)].symbol() != " ")
            .collect()
    }

    /// The words of a row of the buffer with their first columns.
    fn words(buffer: &Buffer, row: u16, from: u16, to: u16) -> Vec<(u16, String)> {
        let mut out: Vec<(u16, String)> = Vec::new();
        let mut current: Option<(u16, String)> = None;
        for x in from..to {
            let symbol = buffer[(x, row)].symbol();
            if symbol == " " {
                out.extend(current.take());
            } else {
                current
                    .get_or_insert_with(|| (x, String::new()))
                    .1
                    .push_str(symbol);
            }
        }
        out.extend(current);
        out
    }

    /// Issue 13: for every width from 20 to 200 columns and every decade range from 1 to 20
    /// decades, each label is within one column (row) of where the chart draws its value,
    /// labels do not overlap and stay inside the chart.
    #[test]
    fn log_labels_sit_at_their_values() {
        for width in 20..=200u16 {
            for decades in 1..=20i64 {
                for low in [-16i64, -3, 1] {
                    let range = [low as f64, (low + decades) as f64];
                    let spec = |title: &str| AxisSpec {
                        kind: AxisKind::Log,
                        range,
                        title: title.into(),
                    };
                    let height = 6 + (width % 30);
                    let area = Rect::new(3, 2, width, height);
                    let plot = PlotArea::new(area, &spec("n"), &spec("")).expect("room");
                    let mut buffer = Buffer::empty(Rect::new(0, 0, width + 6, height + 4));
                    plot.draw_axes(&mut buffer, &look());
                    let case = format!("width {width}, decades {range:?}");
                    // x: the labels in the label row, left to right, against the columns
                    // where the chart draws their values (dots and Braille).
                    let label_row = plot.graph.bottom() + 1;
                    let drawn_labels: Vec<(u16, String)> =
                        words(&buffer, label_row, 0, buffer.area.width)
                            .into_iter()
                            .filter(|(_, w)| w.starts_with("1e"))
                            .collect();
                    let texts: Vec<&String> = plot.x.labels.iter().map(|(_, t)| t).collect();
                    let shown: Vec<&String> = drawn_labels.iter().map(|(_, t)| t).collect();
                    assert_eq!(texts, shown, "{case}: labels overlap or are missing");
                    let points: Vec<(f64, f64)> =
                        plot.x.labels.iter().map(|(v, _)| (*v, range[0])).collect();
                    for marker in [Marker::Dot, Marker::Braille] {
                        let columns: Vec<u16> =
                            drawn(&plot, &points, marker).iter().map(|p| p.0).collect();
                        assert_eq!(columns.len(), points.len(), "{case}");
                        for ((start, text), column) in drawn_labels.iter().zip(columns) {
                            let centre = start + (text.len() as u16 - 1) / 2;
                            assert!(
                                centre.abs_diff(column) <= 1,
                                "{case}: {text} centred at {centre}, its value at {column}"
                            );
                            assert!(*start >= area.x && start + text.len() as u16 <= area.right());
                        }
                    }
                    // y: each label on the row where the chart draws its value (± 1).
                    let points: Vec<(f64, f64)> =
                        plot.y.labels.iter().map(|(v, _)| (range[0], *v)).collect();
                    let mut rows: Vec<u16> = drawn(&plot, &points, Marker::Dot)
                        .iter()
                        .map(|p| p.1)
                        .collect();
                    rows.reverse(); // reading order is top down, the labels bottom up
                    assert_eq!(rows.len(), points.len(), "{case}");
                    for ((_, text), row) in plot.y.labels.iter().zip(rows) {
                        let found = (plot.graph.top()..plot.graph.bottom()).find(|&y| {
                            words(&buffer, y, area.x, plot.graph.x - 1)
                                .iter()
                                .any(|(_, w)| w == text)
                        });
                        let found = found.unwrap_or_else(|| panic!("{case}: {text} missing"));
                        assert!(found.abs_diff(row) <= 1, "{case}: {text} {found} vs {row}");
                    }
                }
            }
        }
    }

    /// Issue 25: the x title is never beside a tick's label (where `ε 1e-8` reads as a value):
    /// it ends the axis row, right of the last tick, after a blank, on linear and log axes at
    /// every width from 16 to 200 columns; the label row holds only labels.
    #[test]
    fn the_x_title_ends_the_axis_and_never_sits_beside_a_label() {
        for width in 16..=200u16 {
            for (kind, range, title) in [
                (AxisKind::Log, [-16.0, 0.0], "ε"),
                (AxisKind::Log, [1.0, 6.0], "t [s]"),
                (AxisKind::Linear, [0.0, 1.0], "x [m]"),
                (AxisKind::Linear, [0.0, 2.5], "x [m]"),
            ] {
                let x = AxisSpec {
                    kind,
                    range,
                    title: title.into(),
                };
                let y = AxisSpec {
                    kind: AxisKind::Log,
                    range: [-3.0, 0.0],
                    title: String::new(),
                };
                let area = Rect::new(1, 1, width, 10);
                let Some(plot) = PlotArea::new(area, &x, &y) else {
                    continue;
                };
                let mut buffer = Buffer::empty(Rect::new(0, 0, width + 2, 12));
                plot.draw_axes(&mut buffer, &look());
                let case = format!("{title} at width {width}");
                let axis_row = plot.graph.bottom();
                let label_row = axis_row + 1;
                let labels: Vec<String> = plot.x.labels.iter().map(|(_, t)| t.clone()).collect();
                let shown: Vec<String> = words(&buffer, label_row, 0, buffer.area.width)
                    .into_iter()
                    .map(|(_, w)| w)
                    .collect();
                assert_eq!(shown, labels, "{case}: the label row holds only the labels");
                if plot.x_title.is_empty() {
                    // No room even for a narrowed graph: allowed only in narrow charts.
                    assert!(width < 30, "{case}: no title");
                    continue;
                }
                let row: String = (area.x..area.right())
                    .map(|c| buffer[(c, axis_row)].symbol().to_string())
                    .collect();
                assert!(row.ends_with(&format!(" {title}")), "{case}: {row:?}");
                let start = area.right() - title.chars().count() as u16;
                let last_tick = plot.x.ticks.iter().filter_map(|&t| plot.column(t)).max();
                assert!(last_tick.is_some_and(|c| c + 1 < start), "{case}: {row:?}");
            }
        }
    }
}
