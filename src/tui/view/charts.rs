//! The chart panels of the explorer: each reads the state it shows from the [`App`] and draws
//! it with the shared charts of [`crate::plot`] (the deflection here, laid out by
//! `tui::layout::deflection`; the sweep charts there).
//! The deflection (or moment, or shear) is drawn with the reference solution (`condensed` on
//! the same mesh, solved on the worker) as a second curve under it, or, with `c`, the
//! difference from the reference on its own scale; nice linear ticks and a zero line.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::widgets::{Dataset, GraphType};

use crate::plot::{
    CurrentRun, PanelFrame, Theme, curve_marker, eps_condition_chart, eps_error_chart,
    error_time_chart, figure5_chart, marker_char, notice, panel_with_key, point_marker,
};
use crate::scene::Panel;
use crate::study::{EpsPoint, MeshPoint};
use crate::tui::layout::deflection::{
    DEFLECTION_ROWS, ITERATE_MARKER, REFERENCE_MARKER, STATE_MARKERS, WALL, deflection_data,
    deflection_plot,
};
use crate::tui::state::sweeps::SweepView;
use crate::tui::state::{App, Diagram};

/// The title's mark of a chart whose data belongs to the state before.
fn updating<T>(view: &SweepView<T>) -> &'static str {
    match view {
        SweepView::Outdated(_) => " · updating…",
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
            let view = app.exploration.sweep_view::<Vec<EpsPoint>>(Panel::EpsError);
            let panel = frame_of(format!(
                " Error vs ε (regularised){title_suffix}{} ",
                updating(&view)
            ));
            match view {
                SweepView::Ready(points) | SweepView::Outdated(points) => {
                    let epsilon = Some(app.scene().solver.epsilon);
                    eps_error_chart(frame, theme, panel, points, epsilon)
                }
                SweepView::Notice(text) => notice(frame, theme, panel, text),
            }
        }
        Panel::EpsCond => {
            let view = app.exploration.sweep_view::<Vec<EpsPoint>>(Panel::EpsCond);
            let panel = frame_of(format!(
                " cond2 of the cases vs ε{title_suffix}{} ",
                updating(&view)
            ));
            match view {
                SweepView::Ready(points) | SweepView::Outdated(points) => {
                    let epsilon = Some(app.scene().solver.epsilon);
                    eps_condition_chart(frame, theme, panel, points, epsilon)
                }
                SweepView::Notice(text) => notice(frame, theme, panel, text),
            }
        }
        Panel::Figure5 => {
            let view = app.exploration.sweep_view::<Vec<EpsPoint>>(Panel::Figure5);
            let panel = frame_of(format!(
                " Figure 5: error and cond2 vs ε{title_suffix}{} ",
                updating(&view)
            ));
            match view {
                SweepView::Ready(points) | SweepView::Outdated(points) => {
                    let epsilon = Some(app.scene().solver.epsilon);
                    figure5_chart(frame, theme, panel, points, epsilon)
                }
                SweepView::Notice(text) => notice(frame, theme, panel, text),
            }
        }
        Panel::Iterations | Panel::DualBox | Panel::Cases | Panel::Matrices => {
            super::method_panels::draw(
                frame,
                app,
                theme,
                panel,
                frame_of(String::new()),
                title_suffix,
            )
        }
        Panel::ErrorTime => {
            let view = app
                .exploration
                .sweep_view::<Vec<MeshPoint>>(Panel::ErrorTime);
            let panel = frame_of(if app.show_timings {
                format!(" Error vs run time{title_suffix}{} ", updating(&view))
            } else {
                format!(" Error vs n (t: time){title_suffix}{} ", updating(&view))
            });
            match view {
                SweepView::Ready(points) | SweepView::Outdated(points) => {
                    let current = CurrentRun {
                        elements: app.scene().mesh.elements,
                        method: app.scene().solver.method,
                    };
                    error_time_chart(frame, theme, panel, points, app.show_timings, Some(current))
                }
                SweepView::Notice(text) => notice(frame, theme, panel, text),
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
    let (name, symbol, unit) = match app.exploration.diagram {
        Diagram::Deflection => ("Deflection u(x)", "u", "m"),
        Diagram::Moment => ("Bending moment M = -EJu''", "M", "N m"),
        Diagram::Shear => ("Shear force T = M'", "T", "N"),
    };
    let outdated = if app.exploration.is_current() {
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
    let iterate_curve = unit(&data.iterate_curve);
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
            .marker(point_marker(theme, ITERATE_MARKER.0, ITERATE_MARKER.1))
            .graph_type(GraphType::Line)
            .style(theme.series(3))
            .data(&iterate_curve),
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
    if let Some(x) = data.selected_obstacle {
        let rule = marker_char(theme, '┆', ':').to_string();
        plot.vertical_line(buffer, x, &rule, theme.current());
    }
    plot.draw_datasets(buffer, theme, datasets);
    number_obstacles(buffer, &plot, &data.obstacles, theme);
    plot.draw_axes(buffer, theme);
    // Stretches of their own stiffness, along the x axis.
    for segment in &data.segments {
        plot.mark_axis(
            buffer,
            [segment.from, segment.to],
            segment.glyph,
            theme.plain(),
        );
    }
}

/// Each obstacle's number in the row above its marker (below it on the top row, or for a
/// second obstacle in the same column), where those cells are blank and no digit touches
/// them: a number never hides the curve, a marker or another number, and two numbers never
/// read as one. None where more than two obstacles share a column: a number there could be
/// any of theirs.
fn number_obstacles(
    buffer: &mut ratatui::buffer::Buffer,
    plot: &crate::plot::PlotArea,
    obstacles: &[(f64, f64)],
    theme: &Theme,
) {
    let graph = plot.graph;
    // How many obstacles each column holds: one pass, whatever the number of obstacles.
    let columns: Vec<Option<u16>> = obstacles.iter().map(|&(x, _)| plot.column(x)).collect();
    let mut sharing = vec![0usize; usize::from(graph.right())];
    for column in columns.iter().flatten() {
        sharing[usize::from(*column)] += 1;
    }
    for (i, (column, &(_, y))) in columns.iter().zip(obstacles).enumerate() {
        let Some(column) = *column else { continue };
        if sharing[usize::from(column)] > 2 {
            continue;
        }
        // Written at once: the next number's place sees this one in the buffer.
        if let Some((start, row, number)) = number_place(buffer, plot, column, y, i + 1) {
            buffer.set_stringn(start, row, &number, number.len(), theme.plain());
        }
    }
}

/// Where obstacle `number`'s label goes (start column, row, text): the row above its marker
/// at height `y`, else the row below, whichever is blank with no digit beside it.
fn number_place(
    buffer: &ratatui::buffer::Buffer,
    plot: &crate::plot::PlotArea,
    column: u16,
    y: f64,
    number: usize,
) -> Option<(u16, u16, String)> {
    let graph = plot.graph;
    let row = plot.row(y)?;
    let number = number.to_string();
    let width = number.len() as u16;
    let start = column.saturating_sub((width - 1) / 2).max(graph.left());
    if start + width > graph.right() {
        return None;
    }
    let digit_at = |c: u16, r: u16| {
        (graph.left()..graph.right()).contains(&c)
            && buffer[(c, r)]
                .symbol()
                .starts_with(|d: char| d.is_ascii_digit())
    };
    let free = |r: u16| {
        (start..start + width).all(|c| buffer[(c, r)].symbol() == " ")
            && !(start > 0 && digit_at(start - 1, r))
            && !digit_at(start + width, r)
    };
    let above = row.checked_sub(1).filter(|r| *r >= graph.top());
    let below = Some(row + 1).filter(|r| *r < graph.bottom());
    let free_row = above.into_iter().chain(below).find(|r| free(*r))?;
    Some((start, free_row, number))
}
