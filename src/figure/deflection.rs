//! The deflection figure: u(x) of a solution, the Hermite interpolant sampled as the explorer
//! samples it (evenly, ends included), the reference (`condensed` on the same mesh) dashed
//! under it, the mesh nodes as markers, the obstacles numbered with their states, and the
//! stretches of different bending stiffness E·J as a band under the axis with their values in
//! the legend.

use super::axes::{Axes, Axis, PLOT};
use super::series::{
    LegendEntry, Sample, Series, SeriesStyle, draw_legend, draw_notice, draw_series, page,
};
use super::svg::{Anchor, LABEL_SIZE, MarkerShape, data_value};
use crate::fem::Mesh;
use crate::format::{eng, sci};
use crate::model::Problem;
use crate::solve::{Method, Solution};

/// What the deflection figure draws: the problem, its mesh, the solution on it and, when the
/// method is another one than the reference's, the reference solution on the same mesh.
#[derive(Debug, Clone, Copy)]
pub struct DeflectionInput<'a> {
    pub problem: &'a Problem,
    pub mesh: &'a Mesh,
    pub solution: &'a Solution,
    pub reference: Option<&'a Solution>,
}

/// The line under the figure: the solution's own warnings first (a flagged answer is never
/// shown clean), then the method, n, ε and the load.
fn footnote(problem: &Problem, mesh: &Mesh, solution: &Solution) -> String {
    let method = solution.method;
    let epsilon = solution
        .epsilon
        .map_or(String::new(), |e| format!(", ε = {}", sci(e, 2)));
    let load = if problem.load.is_constant() {
        format!("f = {} N/m", eng(problem.load.f0))
    } else {
        format!(
            "f = {} … {} N/m",
            eng(problem.load.f0),
            eng(problem.load.f1)
        )
    };
    // The solution's own warnings first, so that a flagged answer is never shown clean.
    let warned = match &solution.warnings[..] {
        [] => String::new(),
        [one] => format!("⚠ {} (beamfric solve says why) · ", one.code.name()),
        [first, rest @ ..] => format!(
            "⚠ {} and {} more (beamfric solve says why) · ",
            first.code.name(),
            rest.len()
        ),
    };
    format!(
        "{warned}{method}, n = {}{epsilon}; load {load}, u positive along the load",
        mesh.elements()
    )
}

/// Points u(x) is sampled at (the explorer's most).
pub const SAMPLES: usize = 401;
/// Node markers are drawn up to this many elements (beyond, they would hide the curve).
const MOST_NODE_MARKERS: usize = 200;
/// Obstacles listed one by one in the legend up to this many.
const MOST_LISTED_OBSTACLES: usize = 3;
/// Fills of the stiffness band, one per distinct E·J.
const BAND_FILLS: [&str; 6] = [
    "#cfe2f3", "#f4cccc", "#d9ead3", "#fff2cc", "#e6d5ec", "#d0e0e3",
];
const OBSTACLE_COLOUR: &str = "#D55E00";

/// u(x) of `solution` at `samples` even positions over [0, l], non-finite values left out.
pub fn sample_deflection(mesh: &Mesh, solution: &Solution, length: f64) -> Vec<(f64, f64)> {
    (0..SAMPLES)
        .map(|i| length * i as f64 / (SAMPLES - 1) as f64)
        .map(|x| (x, solution.field.at(mesh, x).deflection))
        .filter(|(_, u)| u.is_finite())
        .collect()
}

/// The deflection u(x) over the beam, with the reference, the obstacles and the stiffness
/// band.
pub fn deflection_figure(input: &DeflectionInput, title: &str) -> String {
    let DeflectionInput {
        problem,
        mesh,
        solution,
        reference,
    } = *input;
    let method = solution.method;
    let epsilon = solution
        .epsilon
        .map_or(String::new(), |e| format!(", ε = {}", sci(e, 2)));
    let note = footnote(problem, mesh, solution);
    let mut svg = page(
        title,
        "Deflection u(x) of a clamped beam through point obstacles",
        ("x [m]", "deflection u [m]"),
        &note,
    );
    let curve = sample_deflection(mesh, solution, problem.length);
    if curve.is_empty() {
        draw_notice(
            &mut svg,
            "no finite deflection to plot: see the solution's warnings",
        );
        return svg.finish();
    }
    let reference_curve = reference
        .filter(|r| r.method != method)
        .map(|r| sample_deflection(mesh, r, problem.length))
        .unwrap_or_default();
    let x = Axis {
        scale: super::axes::Scale::Linear,
        low: 0.0,
        high: problem.length,
    };
    let y = Axis::linear_over(curve.iter().chain(&reference_curve).map(|p| p.1));
    let axes = Axes::new(x, y);
    let banded = !problem.has_uniform_stiffness();
    axes.draw(&mut svg, if banded { 46.0 } else { 34.0 });
    let zero = axes.y_px(0.0);
    svg.line((PLOT.left, zero), (PLOT.right, zero), "#808080", 1.5, "");
    let mut legend = Vec::new();
    let solution_series = Series {
        name: method.name().into(),
        style: SeriesStyle {
            marker: None,
            ..SeriesStyle::of_method(method)
        },
        points: curve,
    };
    let mut lines = vec![
        method.name().to_string(),
        format!("n = {}{epsilon}", mesh.elements()),
    ];
    if mesh.elements() <= MOST_NODE_MARKERS {
        lines.push("markers: nodes".into());
    }
    legend.push(LegendEntry::new(
        Sample::Series(SeriesStyle::of_method(method)),
        lines,
    ));
    if !reference_curve.is_empty() {
        let series = Series {
            name: Method::Condensed.name().into(),
            style: SeriesStyle {
                colour: "#000000",
                marker: None,
                dash: "9 6",
                line_width: 2.0,
            },
            points: reference_curve,
        };
        legend.push(LegendEntry::new(
            Sample::Series(series.style),
            vec!["condensed".into(), "(reference)".into()],
        ));
        draw_series(&mut svg, &axes, &series);
    }
    draw_series(&mut svg, &axes, &solution_series);
    if mesh.elements() <= MOST_NODE_MARKERS {
        draw_nodes(&mut svg, &axes, input);
    }
    draw_supports(&mut svg);
    legend.push(LegendEntry::new(
        Sample::Swatch("#555555"),
        vec!["clamped ends".into()],
    ));
    // The stiffness before the obstacles: the bands under the axis must be explained, and
    // the obstacles are numbered on the plot.
    let obstacles = draw_obstacles(&mut svg, &axes, input);
    if banded {
        legend.extend(draw_stiffness_band(&mut svg, &axes, problem));
        legend.extend(obstacles);
    } else {
        legend.extend(obstacles);
        let ej = problem.stiffness[0].bending_stiffness;
        legend.push(LegendEntry::new(
            Sample::Nothing,
            vec![format!("EJ = {} N m²", sci(ej, 3))],
        ));
    }
    draw_legend(&mut svg, PLOT, &legend);
    svg.finish()
}

/// The solution's nodal values as markers.
fn draw_nodes(svg: &mut super::svg::Svg, axes: &Axes, input: &DeflectionInput) {
    let style = SeriesStyle::of_method(input.solution.method);
    let fill = format!(r#"fill="{}""#, style.colour);
    let shape = style.marker.unwrap_or(MarkerShape::Circle);
    for (x, u) in input
        .mesh
        .nodes
        .iter()
        .zip(&input.solution.field.deflection)
    {
        if u.is_finite() {
            let attributes = format!(
                r#"class="node-marker" data-x="{}" data-y="{}""#,
                data_value(*x),
                data_value(*u)
            );
            svg.marker(shape, axes.to_px(*x, *u), 4.5, &fill, &attributes);
        }
    }
}

/// The clamped ends: thick grey bars along the plot's left and right edges.
fn draw_supports(svg: &mut super::svg::Svg) {
    for x in [PLOT.left, PLOT.right] {
        svg.rect(
            (x - 4.0, PLOT.top),
            (8.0, PLOT.bottom - PLOT.top),
            r##"fill="#555555""##,
            r#"class="support""#,
        );
    }
}

/// Each obstacle as a marker on the curve with its number above; the legend's entries.
fn draw_obstacles(
    svg: &mut super::svg::Svg,
    axes: &Axes,
    input: &DeflectionInput,
) -> Vec<LegendEntry> {
    let style = SeriesStyle {
        colour: OBSTACLE_COLOUR,
        marker: Some(MarkerShape::Diamond),
        dash: "",
        line_width: 0.0,
    };
    let obstacles = &input.solution.obstacles;
    // Where numbers are already written: a number that would touch one is left out (crowded
    // obstacles keep their marks; the legend says the numbers run from x = 0).
    let mut labelled: Vec<(f64, f64)> = Vec::new();
    for (i, o) in obstacles.iter().enumerate() {
        let u = input.solution.field.at(input.mesh, o.x).deflection;
        if !u.is_finite() {
            continue;
        }
        let at = axes.to_px(o.x, u);
        let attributes = format!(
            r#"class="obstacle" data-obstacle="{}" data-x="{}" data-y="{}""#,
            i + 1,
            data_value(o.x),
            data_value(u)
        );
        svg.marker(
            MarkerShape::Diamond,
            at,
            9.0,
            &format!(r##"fill="{OBSTACLE_COLOUR}" stroke="#000000" stroke-width="1""##),
            &attributes,
        );
        // The number above the mark, or below it when the mark is near the top.
        let baseline = if at.1 - PLOT.top > 40.0 {
            at.1 - 16.0
        } else {
            at.1 + 34.0
        };
        let number = (i + 1).to_string();
        let half = super::svg::text_width(&number, LABEL_SIZE) / 2.0 + 6.0;
        let touches = |&(x, y): &(f64, f64)| {
            (x - at.0).abs() < 2.0 * half && (y - baseline).abs() < LABEL_SIZE
        };
        if labelled.iter().any(touches) {
            continue;
        }
        labelled.push((at.0, baseline));
        svg.text(
            (at.0, baseline),
            Anchor::Middle,
            LABEL_SIZE,
            &number,
            r#"class="obstacle-label" font-weight="bold""#,
        );
    }
    if obstacles.len() <= MOST_LISTED_OBSTACLES {
        obstacles
            .iter()
            .enumerate()
            .map(|(i, o)| {
                LegendEntry::new(
                    Sample::Series(style),
                    vec![
                        format!("obstacle {} at {} m", i + 1, eng(o.x)),
                        o.state().to_string(),
                    ],
                )
            })
            .collect()
    } else {
        vec![LegendEntry::new(
            Sample::Series(style),
            vec![
                format!("obstacles 1–{}", obstacles.len()),
                "numbered from x = 0".into(),
            ],
        )]
    }
}

/// The stretches of constant E·J as a band under the x axis, one fill per distinct value;
/// the legend's entries (each value and where it holds).
fn draw_stiffness_band(
    svg: &mut super::svg::Svg,
    axes: &Axes,
    problem: &Problem,
) -> Vec<LegendEntry> {
    let mut values: Vec<f64> = Vec::new();
    for piece in &problem.stiffness {
        if !values.contains(&piece.bending_stiffness) {
            values.push(piece.bending_stiffness);
        }
    }
    let fill_of = |ej: f64| {
        let index = values.iter().position(|v| *v == ej).unwrap_or(0);
        BAND_FILLS[index % BAND_FILLS.len()]
    };
    for piece in &problem.stiffness {
        let (from, to) = (axes.x_px(piece.from), axes.x_px(piece.to));
        svg.rect(
            (from, PLOT.bottom + 10.0),
            (to - from, 12.0),
            &format!(
                r##"fill="{}" stroke="#000000" stroke-width="0.75""##,
                fill_of(piece.bending_stiffness)
            ),
            &format!(
                r#"class="stiffness-band" data-from="{}" data-to="{}" data-ej="{}""#,
                data_value(piece.from),
                data_value(piece.to),
                data_value(piece.bending_stiffness)
            ),
        );
    }
    // Many values: one entry for them all (the band shows where each holds).
    if values.len() > 3 {
        let low = values.iter().copied().fold(f64::INFINITY, f64::min);
        let high = values.iter().copied().fold(0.0, f64::max);
        return vec![LegendEntry::new(
            Sample::Swatch(BAND_FILLS[0]),
            vec![
                format!("EJ from {} to {} N m²", sci(low, 3), sci(high, 3)),
                format!(
                    "{} values on {} stretches, shaded under the axis",
                    values.len(),
                    problem.stiffness.len()
                ),
            ],
        )];
    }
    values
        .iter()
        .map(|&ej| {
            let pieces: Vec<_> = problem
                .stiffness
                .iter()
                .filter(|p| p.bending_stiffness == ej)
                .collect();
            let place = match pieces[..] {
                [one] => format!("on {} … {} m", eng(one.from), eng(one.to)),
                _ => format!("on {} stretches", pieces.len()),
            };
            LegendEntry::new(
                Sample::Swatch(fill_of(ej)),
                vec![format!("EJ = {} N m²", sci(ej, 3)), place],
            )
        })
        .collect()
}
