//! The dual's picture for one obstacle: the (λ1, λ2) plane with the box [−g1, g1] × [−g2, g2]
//! of (49), level curves of the dual quadratic restricted to that pair (the other obstacles
//! held at their solution forces), its unconstrained minimiser, the box QP's iterates and the
//! solution. Where the solution sits on the box is the friction state: inside (stuck), on an
//! edge (slides or swivels), at a corner (both).

use ratatui::Frame;
use ratatui::style::Style;
use ratatui::widgets::{Dataset, GraphType};

use super::Theme;
use super::chart::{PanelFrame, Piece, curve_marker, marker_char, panel_with_key};
use super::plot_area::{AxisKind, AxisSpec, Markers, PlotArea};
use crate::format::sci;
use crate::study::{BoxPosition, DualPair};

/// Rows the chart keeps before the readout takes the rest.
const PLOT_ROWS: u16 = 6;

/// What the picture shows besides the pair itself.
pub struct DualBoxView<'a> {
    pub pair: &'a DualPair,
    /// The box QP's iterates for this obstacle (N, N m), in order; the last is the solution.
    pub iterates: &'a [[f64; 2]],
    /// The iterate the iterations panel selects, if one.
    pub selected: Option<usize>,
    /// The state the Results panel names for this obstacle (`stuck`, `slides`, …).
    pub state: &'a str,
}

/// Words for where the solution is on the box.
pub fn position_words(position: BoxPosition) -> &'static str {
    match position {
        BoxPosition::Interior => "inside the box",
        BoxPosition::SlidingEdge => "on the edge |λ1| = g1",
        BoxPosition::SwivelEdge => "on the edge |λ2| = g2",
        BoxPosition::Corner => "at a corner",
        BoxPosition::Undecided => "on the box within rounding",
    }
}

/// The half-widths of the plotted window: the box with a margin, the solution and the
/// iterates always inside, the minimiser when it is not far off.
fn window(view: &DualBoxView) -> [f64; 2] {
    let pair = view.pair;
    let mut half = [0.0f64; 2];
    for axis in 0..2 {
        let mut extent = pair.thresholds[axis].abs().max(pair.solution[axis].abs());
        for iterate in view.iterates {
            extent = extent.max(iterate[axis].abs());
        }
        let minimiser = pair.minimiser[axis].abs();
        if minimiser.is_finite() && minimiser <= 3.0 * extent {
            extent = extent.max(minimiser);
        }
        half[axis] = if extent > 0.0 && extent.is_finite() {
            extent * 1.25
        } else {
            1.0
        };
    }
    half
}

/// The level values drawn: the one through the solution and others around it.
fn levels(pair: &DualPair, half: [f64; 2]) -> Vec<f64> {
    let lowest = pair.value(pair.minimiser);
    let at_solution = pair.value(pair.solution);
    let corner = pair
        .value([half[0], half[1]])
        .max(pair.value([half[0], -half[1]]));
    if !(lowest.is_finite() && at_solution.is_finite() && corner.is_finite()) {
        return Vec::new();
    }
    if at_solution - lowest > 1e-12 * (corner - lowest).abs() {
        [0.25, 1.0, 2.25, 4.0, 6.25]
            .iter()
            .map(|t| lowest + t * (at_solution - lowest))
            .collect()
    } else {
        [0.02, 0.1, 0.3, 0.6]
            .iter()
            .map(|t| lowest + t * (corner - lowest))
            .collect()
    }
}

/// The lines under the picture: where the solution is and what that means, the forces, the
/// minimiser, the iterates and the box.
fn readout(theme: &Theme, view: &DualBoxView, minimiser_shown: bool) -> Vec<Piece> {
    let pair = view.pair;
    let solution_marker = marker_char(theme, '●', 'O');
    let minimiser_marker = marker_char(theme, '×', 'x');
    let iterate_marker = marker_char(theme, '∘', 'o');
    let mut readout: Vec<Piece> = vec![
        (
            format!(
                "{solution_marker} {}: {}",
                position_words(pair.position),
                view.state
            ),
            theme.current(),
        ),
        (
            format!(
                "λ = ({} N, {} N m)",
                sci(pair.solution[0], 3),
                sci(pair.solution[1], 3)
            ),
            theme.current(),
        ),
    ];
    readout.push((
        format!(
            "{minimiser_marker} minimum ({}, {}){}",
            sci(pair.minimiser[0], 2),
            sci(pair.minimiser[1], 2),
            if minimiser_shown {
                ""
            } else {
                " off the chart"
            }
        ),
        theme.series(1),
    ));
    if view.iterates.len() > 1 {
        readout.push((
            format!("{iterate_marker} {} box-QP iterates", view.iterates.len()),
            theme.series(2),
        ));
    }
    readout.push((
        format!(
            "box |λ1| ≤ g1 = {} N, |λ2| ≤ g2 = {} N m (λ2 up)",
            sci(pair.thresholds[0], 2),
            sci(pair.thresholds[1], 2)
        ),
        theme.dim(),
    ));
    readout
}

/// The picture of the dual restricted to one obstacle's pair.
pub fn dual_box_chart(frame: &mut Frame, theme: &Theme, panel: PanelFrame, view: &DualBoxView) {
    let pair = view.pair;
    let half = window(view);
    let solution_marker = marker_char(theme, '●', 'O');
    let minimiser_marker = marker_char(theme, '×', 'x');
    let iterate_marker = marker_char(theme, '∘', 'o');
    let minimiser_shown = (0..2).all(|a| pair.minimiser[a].abs() <= half[a]);
    let readout = readout(theme, view, minimiser_shown);
    let plot = panel_with_key(frame, theme, &panel, &readout, &[], &[], PLOT_ROWS);
    let x_axis = AxisSpec {
        kind: AxisKind::Linear,
        range: [-half[0], half[0]],
        title: theme.text("λ1 [N]").into_owned(),
    };
    let y_axis = AxisSpec {
        kind: AxisKind::Linear,
        range: [-half[1], half[1]],
        title: String::new(),
    };
    let Some(area) = PlotArea::new(plot, &x_axis, &y_axis) else {
        return;
    };
    let unit = |p: [f64; 2]| area.unit((p[0], p[1]));
    let curves: Vec<Vec<(f64, f64)>> = levels(pair, half)
        .into_iter()
        .map(|level| pair.level_curve(level, 240).into_iter().map(unit).collect())
        .collect();
    let [g1, g2] = pair.thresholds;
    let edges: Vec<(f64, f64)> = [[-g1, -g2], [g1, -g2], [g1, g2], [-g1, g2], [-g1, -g2]]
        .into_iter()
        .map(unit)
        .collect();
    let path: Vec<(f64, f64)> = view.iterates.iter().copied().map(unit).collect();
    let mut datasets: Vec<Dataset> = curves
        .iter()
        .map(|curve| {
            Dataset::default()
                .marker(curve_marker(theme))
                .graph_type(GraphType::Line)
                .style(theme.faint())
                .data(curve)
        })
        .collect();
    datasets.push(
        Dataset::default()
            .marker(curve_marker(theme))
            .graph_type(GraphType::Line)
            .style(theme.series(0))
            .data(&edges),
    );
    if path.len() > 1 {
        datasets.push(
            Dataset::default()
                .marker(curve_marker(theme))
                .graph_type(GraphType::Line)
                .style(theme.series(2))
                .data(&path),
        );
    }
    let buffer = frame.buffer_mut();
    area.draw_datasets(buffer, theme, datasets);
    area.draw_axes(buffer, theme);
    let point = |p: [f64; 2], style: Style| (p[0], p[1], style);
    let mut iterates: Vec<(f64, f64, Style)> = view
        .iterates
        .iter()
        .map(|&p| point(p, theme.series(2)))
        .collect();
    iterates.pop();
    let mut series = vec![Markers {
        symbol: solution_marker,
        points: vec![point(pair.solution, theme.current())],
    }];
    if let Some(selected) = view.selected.and_then(|i| view.iterates.get(i)) {
        series.push(Markers {
            symbol: marker_char(theme, '◆', '@'),
            points: vec![point(*selected, theme.current())],
        });
    }
    if minimiser_shown {
        series.push(Markers {
            symbol: minimiser_marker,
            points: vec![point(pair.minimiser, theme.series(1))],
        });
    }
    series.push(Markers {
        symbol: iterate_marker,
        points: iterates,
    });
    area.scatter(buffer, &series);
}
