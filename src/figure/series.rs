//! What every figure shares: the page (title, axes, axis names, note), a series drawn as one
//! polyline with a marker at each point (its data values in `data-x` / `data-y`), the current
//! point's ring, the legend in its column right of the data, and the notice that replaces
//! the data when there is nothing to plot.

use super::axes::{Axes, LEGEND_LEFT, PLOT, PlotFrame, draw_axis_names};
use super::svg::{
    Anchor, HEIGHT, LABEL_SIZE, MarkerShape, NOTE_SIZE, Svg, TITLE_SIZE, WIDTH, data_value, escape,
    text_width, wrap_text,
};
use crate::solve::Method;

/// Colour-blind-safe colours (Okabe & Ito), darkest first; yellow is left out (too pale on
/// white).
pub const COLOURS: [&str; 7] = [
    "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000",
];

/// Marker shapes, one per series index.
pub const SHAPES: [MarkerShape; 7] = [
    MarkerShape::Circle,
    MarkerShape::Square,
    MarkerShape::TriangleUp,
    MarkerShape::Diamond,
    MarkerShape::Plus,
    MarkerShape::Cross,
    MarkerShape::TriangleDown,
];

/// How a series looks: its colour, marker and line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeriesStyle {
    pub colour: &'static str,
    pub marker: Option<MarkerShape>,
    /// `stroke-dasharray`, empty for a solid line.
    pub dash: &'static str,
    pub line_width: f64,
}

impl SeriesStyle {
    /// The style of the series at `index`: its colour and marker, a solid line.
    pub fn indexed(index: usize) -> SeriesStyle {
        SeriesStyle {
            colour: COLOURS[index % COLOURS.len()],
            marker: Some(SHAPES[index % SHAPES.len()]),
            dash: "",
            line_width: 2.5,
        }
    }

    /// A method's style, the same in every figure: by its place in [`Method::ALL`].
    pub fn of_method(method: Method) -> SeriesStyle {
        let index = Method::ALL.iter().position(|m| *m == method).unwrap_or(0);
        SeriesStyle::indexed(index)
    }
}

/// A series: its name (a method's name, or what it shows) and its points in data values.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub name: String,
    pub style: SeriesStyle,
    pub points: Vec<(f64, f64)>,
}

/// Marker radius [px].
const MARKER_RADIUS: f64 = 6.5;

/// The series' polyline and markers, in a group named after it.
pub fn draw_series(svg: &mut Svg, axes: &Axes, series: &Series) {
    let name = escape(&series.name);
    let style = series.style;
    svg.raw(&format!(r#"<g class="series" data-series="{name}">"#));
    let pixels: Vec<(f64, f64)> = series
        .points
        .iter()
        .map(|&(x, y)| axes.to_px(x, y))
        .collect();
    let dash = if style.dash.is_empty() {
        String::new()
    } else {
        format!(r#" stroke-dasharray="{}""#, style.dash)
    };
    let line_style = format!(
        r#"stroke="{}" stroke-width="{}"{dash} stroke-linejoin="round""#,
        style.colour, style.line_width
    );
    svg.polyline(
        &pixels,
        &line_style,
        &format!(r#"class="series-line" data-series="{name}""#),
    );
    if let Some(shape) = style.marker {
        let fill = format!(
            r##"fill="{}" stroke="#ffffff" stroke-width="1""##,
            style.colour
        );
        for (&(x, y), &at) in series.points.iter().zip(&pixels) {
            let attributes = format!(
                r#"class="marker" data-series="{name}" data-x="{}" data-y="{}""#,
                data_value(x),
                data_value(y)
            );
            svg.marker(shape, at, MARKER_RADIUS, &fill, &attributes);
        }
    }
    svg.raw("</g>");
}

/// The current point's ring, at data point (x, y).
pub fn current_ring(svg: &mut Svg, axes: &Axes, x: f64, y: f64) {
    let (cx, cy) = axes.to_px(x, y);
    svg.marker(
        MarkerShape::Circle,
        (cx, cy),
        13.0,
        r##"fill="none" stroke="#000000" stroke-width="2.5""##,
        &format!(
            r#"class="current-point" data-x="{}" data-y="{}""#,
            data_value(x),
            data_value(y)
        ),
    );
}

/// A legend entry: a series' sample (or the current point's ring, or a band's swatch) and
/// its lines of text.
#[derive(Debug, Clone, PartialEq)]
pub struct LegendEntry {
    pub sample: Sample,
    pub lines: Vec<String>,
    pub bold: bool,
}

/// What a legend entry shows left of its text.
#[derive(Debug, Clone, PartialEq)]
pub enum Sample {
    Series(SeriesStyle),
    Current,
    Swatch(&'static str),
    Nothing,
}

impl LegendEntry {
    pub fn new(sample: Sample, lines: Vec<String>) -> LegendEntry {
        LegendEntry {
            sample,
            lines,
            bold: false,
        }
    }
}

/// Height of one line of the legend [px].
const LEGEND_LINE: f64 = 30.0;
/// The legend's text starts here [px].
const LEGEND_TEXT: f64 = LEGEND_LEFT + 52.0;

/// The legend, in the column right of the plot, from its top down to just above the x
/// axis's name; entries that do not fit are summed up in a last line.
pub fn draw_legend(svg: &mut Svg, frame: PlotFrame, entries: &[LegendEntry]) {
    svg.raw(r#"<g class="legend">"#);
    let bottom = frame.bottom - 2.0 * LEGEND_LINE;
    let mut y = frame.top + LEGEND_LINE / 2.0;
    let width = WIDTH - 8.0 - LEGEND_TEXT;
    for (i, entry) in entries.iter().enumerate() {
        let lines: Vec<String> = entry
            .lines
            .iter()
            .flat_map(|line| wrap_text(line, LABEL_SIZE, width))
            .collect();
        let height = lines.len().max(1) as f64 * LEGEND_LINE;
        if y + height > bottom {
            let left = entries.len() - i;
            svg.text(
                (LEGEND_LEFT, y + 0.35 * LABEL_SIZE),
                Anchor::Start,
                LABEL_SIZE,
                &format!(
                    "… {left} more entr{} (no room)",
                    if left == 1 { "y" } else { "ies" }
                ),
                r#"class="legend-text""#,
            );
            break;
        }
        draw_sample(svg, &entry.sample, y);
        let weight = if entry.bold {
            r#" font-weight="bold""#
        } else {
            ""
        };
        for (k, line) in lines.iter().enumerate() {
            let baseline = y + k as f64 * LEGEND_LINE + 0.35 * LABEL_SIZE;
            svg.text(
                (LEGEND_TEXT, baseline),
                Anchor::Start,
                LABEL_SIZE,
                line,
                &format!(r#"class="legend-text"{weight}"#),
            );
        }
        y += height + 8.0;
    }
    svg.raw("</g>");
}

/// A legend entry's sample, centred on the line at `y`.
fn draw_sample(svg: &mut Svg, sample: &Sample, y: f64) {
    let (from, to) = (LEGEND_LEFT, LEGEND_LEFT + 44.0);
    let middle = (from + to) / 2.0;
    match sample {
        Sample::Series(style) => {
            svg.line(
                (from, y),
                (to, y),
                style.colour,
                style.line_width,
                style.dash,
            );
            if let Some(shape) = style.marker {
                let fill = format!(r#"fill="{}""#, style.colour);
                svg.marker(
                    shape,
                    (middle, y),
                    MARKER_RADIUS,
                    &fill,
                    r#"class="legend-marker""#,
                );
            }
        }
        Sample::Current => {
            svg.line(
                (middle, y - 13.0),
                (middle, y + 13.0),
                "#000000",
                2.0,
                "5 4",
            );
            svg.marker(
                MarkerShape::Circle,
                (middle, y),
                10.0,
                r##"fill="none" stroke="#000000" stroke-width="2.5""##,
                r#"class="legend-marker""#,
            );
        }
        Sample::Swatch(colour) => svg.rect(
            (from, y - 9.0),
            (to - from, 18.0),
            &format!(r##"fill="{colour}" stroke="#000000" stroke-width="1""##),
            r#"class="legend-swatch""#,
        ),
        Sample::Nothing => {}
    }
}

/// A page: the title at the top, the axis names, and a note at the bottom.
pub fn page(title: &str, description: &str, axis_names: (&str, &str), note: &str) -> Svg {
    let mut svg = Svg::new(title, description);
    svg.text(
        (PLOT.left, 38.0),
        Anchor::Start,
        TITLE_SIZE,
        title,
        r#"class="figure-title" font-weight="bold""#,
    );
    draw_axis_names(&mut svg, PLOT, axis_names.0, axis_names.1);
    if !note.is_empty() {
        svg.text(
            (20.0, HEIGHT - 14.0),
            Anchor::Start,
            NOTE_SIZE,
            note,
            r#"class="note""#,
        );
    }
    svg
}

/// Instead of data: the empty plot area with `text` in it, in words, wrapped to fit.
pub fn draw_notice(svg: &mut Svg, text: &str) {
    let f = PLOT;
    svg.rect(
        (f.left, f.top),
        (f.right - f.left, f.bottom - f.top),
        r##"fill="#f7f7f7" stroke="#000000" stroke-width="1.5""##,
        r#"class="plot-area""#,
    );
    let width = f.right - f.left - 40.0;
    let mut lines: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        match lines.last_mut() {
            Some(line) if text_width(&format!("{line} {word}"), LABEL_SIZE) <= width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    let middle = (f.top + f.bottom) / 2.0 - (lines.len() as f64 - 1.0) * LEGEND_LINE / 2.0;
    for (i, line) in lines.iter().enumerate() {
        svg.text(
            ((f.left + f.right) / 2.0, middle + i as f64 * LEGEND_LINE),
            Anchor::Middle,
            LABEL_SIZE,
            line,
            r#"class="notice""#,
        );
    }
}
