//! The figures' axes: where the plot sits in the view box, log axes over whole decades (each
//! decade labelled as the power of ten it is, 10⁻⁸), linear axes with 1-2-5 steps (each
//! label the exact value at its tick), the transform from data to pixels, and the drawing of
//! the frame, grid, ticks and axis names (at the ends of the axes, away from the tick labels).

use super::svg::{Anchor, LABEL_SIZE, Svg, data_value, px};

/// Where the data area sits in the view box [px]; the legend is the column right of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlotFrame {
    pub left: f64,
    pub right: f64,
    pub top: f64,
    pub bottom: f64,
}

/// The data area of every figure: room for y tick labels on the left, the title and the y
/// axis's name above, the x tick labels and a note below, the legend on the right.
pub const PLOT: PlotFrame = PlotFrame {
    left: 130.0,
    right: 900.0,
    top: 100.0,
    bottom: 610.0,
};

/// The left edge of the legend column [px].
pub const LEGEND_LEFT: f64 = 930.0;

/// How an axis maps values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scale {
    Log,
    Linear,
}

impl Scale {
    fn name(self) -> &'static str {
        match self {
            Scale::Log => "log",
            Scale::Linear => "linear",
        }
    }
}

/// One axis: its scale and the values at its two ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axis {
    pub scale: Scale,
    pub low: f64,
    pub high: f64,
}

/// A tick: its value, and its label if it has one (the label reads as exactly that value).
#[derive(Debug, Clone, PartialEq)]
pub struct Tick {
    pub value: f64,
    pub label: Option<String>,
}

/// Most labelled ticks on an axis.
const MOST_LABELS: usize = 9;

impl Axis {
    /// A log axis over whole decades covering the positive finite `values`; `None` when
    /// there is none.
    pub fn log_over(values: impl IntoIterator<Item = f64>) -> Option<Axis> {
        let (low, high) = values
            .into_iter()
            .filter(|v| v.is_finite() && *v > 0.0)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
        if !low.is_finite() {
            return None;
        }
        let mut from = low.log10().floor() as i32;
        let mut to = high.log10().ceil() as i32;
        if from == to {
            from -= 1;
            to += 1;
        }
        Some(Axis {
            scale: Scale::Log,
            low: decade(from),
            high: decade(to),
        })
    }

    /// A linear axis over the finite `values` and zero, rounded out to whole steps.
    pub fn linear_over(values: impl IntoIterator<Item = f64>) -> Axis {
        let (mut low, mut high) = values
            .into_iter()
            .filter(|v| v.is_finite())
            .fold((0.0f64, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
        if high - low <= 0.0 {
            low -= 1.0;
            high += 1.0;
        }
        let step = nice_step((high - low) / 6.0);
        Axis {
            scale: Scale::Linear,
            low: (low / step.value()).floor() * step.value(),
            high: (high / step.value()).ceil() * step.value(),
        }
    }

    /// Where `value` lies between the ends, 0 at `low` and 1 at `high`.
    pub fn fraction(&self, value: f64) -> f64 {
        match self.scale {
            Scale::Log => {
                (value.log10() - self.low.log10()) / (self.high.log10() - self.low.log10())
            }
            Scale::Linear => (value - self.low) / (self.high - self.low),
        }
    }

    /// The ticks: every decade of a log axis (labelled every one, two, … decades so that at
    /// most nine are), or the 1-2-5 steps of a linear one.
    pub fn ticks(&self) -> Vec<Tick> {
        match self.scale {
            Scale::Log => {
                let (from, to) = (self.low.log10().round(), self.high.log10().round());
                // Decades of doubles span −324..=308; anything else is no log axis.
                if !(from.is_finite() && to.is_finite() && from <= to) {
                    return Vec::new();
                }
                let (from, to) = (from as i32, to as i32);
                let every = ((to - from) as usize).div_ceil(MOST_LABELS - 1).max(1) as i32;
                (from..=to)
                    .map(|exponent| Tick {
                        value: decade(exponent),
                        label: (exponent.rem_euclid(every) == 0)
                            .then(|| format!("10{}", superscript(exponent))),
                    })
                    .collect()
            }
            Scale::Linear => {
                let span = self.high - self.low;
                // A span that overflows (data from −1e308 to 1e308) or is empty has no
                // 1-2-5 ticks: the axis is drawn without them.
                if !(span.is_finite() && span > 0.0) {
                    return Vec::new();
                }
                let step = nice_step(span / 6.0);
                let first = (self.low / step.value()).round() as i64;
                let last = (self.high / step.value()).round() as i64;
                if !(0..=MOST_TICKS).contains(&(last.saturating_sub(first))) {
                    return Vec::new();
                }
                (first..=last)
                    .map(|k| {
                        let (label, value) = step.multiple(k);
                        Tick {
                            value,
                            label: Some(label),
                        }
                    })
                    .collect()
            }
        }
    }

    /// The axis as `data-` attributes of the plot area, for readers that map pixels back to
    /// values: `data-x-scale="log" data-x-low="1e-16" data-x-high="1e0"`.
    fn attributes(&self, name: &str) -> String {
        format!(
            r#"data-{name}-scale="{}" data-{name}-low="{}" data-{name}-high="{}""#,
            self.scale.name(),
            data_value(self.low),
            data_value(self.high)
        )
    }
}

/// 10^exponent, as the nearest f64 to the decimal (`1e-8`, not a power computed in binary).
fn decade(exponent: i32) -> f64 {
    format!("1e{exponent}").parse().expect("a decade parses")
}

/// A step of a linear axis: 1, 2 or 5 times a power of ten.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Step {
    mantissa: i64,
    exponent: i32,
}

impl Step {
    fn value(self) -> f64 {
        self.multiple(1).1
    }

    /// k steps: the label (exact: plain decimals for moderate sizes, else `4×10⁻⁶`) and the
    /// value it reads as.
    fn multiple(self, k: i64) -> (String, f64) {
        let digits = k * self.mantissa;
        let value: f64 = format!("{digits}e{}", self.exponent)
            .parse()
            .expect("a number parses");
        let label = if digits == 0 {
            "0".to_string()
        } else if (-5..=5).contains(&self.exponent) {
            let decimals = (-self.exponent).max(0) as usize;
            format!("{value:.decimals$}")
        } else {
            // 10×10⁻⁶ reads as 1×10⁻⁵: the trailing zeros go into the exponent.
            let (mut mantissa, mut exponent) = (digits, self.exponent);
            while mantissa % 10 == 0 {
                mantissa /= 10;
                exponent += 1;
            }
            format!("{mantissa}×10{}", superscript(exponent))
        };
        (label.replace('-', "−"), value)
    }
}

/// Most linear ticks an axis takes (a 1-2-5 step of at least a sixth of the span gives at most
/// 13).
const MOST_TICKS: i64 = 64;

/// The 1-2-5 step nearest above `rough` (finite and positive; anything else gives 1).
fn nice_step(rough: f64) -> Step {
    if !(rough.is_finite() && rough > 0.0) {
        return Step {
            mantissa: 1,
            exponent: 0,
        };
    }
    let exponent = rough.log10().floor() as i32;
    let scaled = rough / decade(exponent);
    let (mantissa, exponent) = if scaled <= 1.0 {
        (1, exponent)
    } else if scaled <= 2.0 {
        (2, exponent)
    } else if scaled <= 5.0 {
        (5, exponent)
    } else {
        (1, exponent + 1)
    };
    Step { mantissa, exponent }
}

/// An exponent in Unicode superscripts: `⁻¹⁶`.
pub fn superscript(exponent: i32) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut text = String::new();
    if exponent < 0 {
        text.push('⁻');
    }
    for c in exponent.unsigned_abs().to_string().chars() {
        text.push(DIGITS[c.to_digit(10).unwrap_or(0) as usize]);
    }
    text
}

/// The x and y axes of a plot in [`PLOT`]: the transform from data to pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axes {
    pub x: Axis,
    pub y: Axis,
    pub frame: PlotFrame,
}

impl Axes {
    pub fn new(x: Axis, y: Axis) -> Axes {
        Axes { x, y, frame: PLOT }
    }

    /// The pixel of the data point (x, y).
    pub fn to_px(&self, x: f64, y: f64) -> (f64, f64) {
        let f = &self.frame;
        (
            f.left + self.x.fraction(x) * (f.right - f.left),
            f.bottom - self.y.fraction(y) * (f.bottom - f.top),
        )
    }

    /// The pixel column of `x`.
    pub fn x_px(&self, x: f64) -> f64 {
        self.to_px(x, self.y.low).0
    }

    /// The pixel row of `y`.
    pub fn y_px(&self, y: f64) -> f64 {
        self.to_px(self.x.low, y).1
    }

    /// The frame, grid lines, ticks and their labels; x labels `label_gap` px below the axis.
    pub fn draw(&self, svg: &mut Svg, label_gap: f64) {
        let f = self.frame;
        for tick in self.x.ticks() {
            let x = self.x_px(tick.value);
            svg.line((x, f.top), (x, f.bottom), "#e3e3e3", 1.0, "");
            svg.line((x, f.bottom), (x, f.bottom + 8.0), "#000000", 1.5, "");
            if let Some(label) = &tick.label {
                let attributes = format!(
                    r#"class="tick-label" data-axis="x" data-value="{}""#,
                    data_value(tick.value)
                );
                svg.text(
                    (x, f.bottom + label_gap),
                    Anchor::Middle,
                    LABEL_SIZE,
                    label,
                    &attributes,
                );
            }
        }
        for tick in self.y.ticks() {
            let y = self.y_px(tick.value);
            svg.line((f.left, y), (f.right, y), "#e3e3e3", 1.0, "");
            svg.line((f.left - 8.0, y), (f.left, y), "#000000", 1.5, "");
            if let Some(label) = &tick.label {
                let attributes = format!(
                    r#"class="tick-label" data-axis="y" data-value="{}""#,
                    data_value(tick.value)
                );
                let baseline = y + 0.35 * LABEL_SIZE;
                svg.text(
                    (f.left - 12.0, baseline),
                    Anchor::End,
                    LABEL_SIZE,
                    label,
                    &attributes,
                );
            }
        }
        self.draw_frame(svg);
    }

    /// The plot area's outline, with the transform in its `data-` attributes.
    pub fn draw_frame(&self, svg: &mut Svg) {
        let f = self.frame;
        let attributes = format!(
            r#"class="plot-area" {} {}"#,
            self.x.attributes("x"),
            self.y.attributes("y")
        );
        svg.rect(
            (f.left, f.top),
            (f.right - f.left, f.bottom - f.top),
            r##"fill="none" stroke="#000000" stroke-width="1.5""##,
            &attributes,
        );
    }
}

/// The axis names, with their units: the x axis's right of its right end, the y axis's above
/// its top, both clear of the tick labels.
pub fn draw_axis_names(svg: &mut Svg, frame: PlotFrame, x_name: &str, y_name: &str) {
    svg.text(
        (frame.right + 14.0, frame.bottom + 0.35 * LABEL_SIZE),
        Anchor::Start,
        LABEL_SIZE,
        x_name,
        r#"class="axis-name" data-axis="x""#,
    );
    svg.text(
        (frame.left, frame.top - 16.0),
        Anchor::Start,
        LABEL_SIZE,
        y_name,
        r#"class="axis-name" data-axis="y""#,
    );
}

/// A vertical dashed rule across the plot at pixel column `x`: the current point.
pub fn current_rule(svg: &mut Svg, frame: PlotFrame, x: f64) {
    svg.raw(&format!(
        r##"<line class="current-rule" x1="{x}" y1="{}" x2="{x}" y2="{}" stroke="#000000" stroke-width="2.00" stroke-dasharray="10 7"/>"##,
        px(frame.top),
        px(frame.bottom),
        x = px(x)
    ));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_beyond_doubles_have_no_ticks_and_do_not_panic() {
        // A span that overflows to infinity (found by the random-key fuzzer: `e` on a scene
        // driven to extreme values), an empty one, and non-finite ends.
        for (scale, low, high) in [
            (Scale::Linear, -1.5e308, 1.5e308),
            (Scale::Linear, 2.0, 2.0),
            (Scale::Linear, f64::NAN, 1.0),
            (Scale::Log, 0.0, 1.0),
            (Scale::Log, 1.0, f64::INFINITY),
        ] {
            assert!(Axis { scale, low, high }.ticks().is_empty(), "{low} {high}");
        }
        let ordinary = Axis {
            scale: Scale::Linear,
            low: 0.0,
            high: 1.0,
        };
        assert_eq!(ordinary.ticks().len(), 6, "0, 0.2, …, 1");
    }

    #[test]
    fn log_axis_labels_only_decades_at_their_values() {
        let axis = Axis::log_over([3e-9, 0.5]).unwrap();
        assert_eq!((axis.low, axis.high), (1e-9, 1.0));
        let ticks = axis.ticks();
        assert_eq!(ticks.len(), 10);
        for tick in &ticks {
            if let Some(label) = &tick.label {
                let exponent = tick.value.log10().round() as i32;
                assert_eq!(label, &format!("10{}", superscript(exponent)));
            }
        }
        let wide = Axis::log_over([1e-16, 1.0]).unwrap();
        let labelled = wide.ticks().iter().filter(|t| t.label.is_some()).count();
        assert!((4..=MOST_LABELS).contains(&labelled), "{labelled}");
    }

    #[test]
    fn one_decade_is_widened() {
        let axis = Axis::log_over([2e-3, 3e-3]).unwrap();
        assert_eq!((axis.low, axis.high), (1e-3, 1e-2));
        let axis = Axis::log_over([1e-3]).unwrap();
        assert_eq!((axis.low, axis.high), (1e-4, 1e-2));
        assert!(Axis::log_over([0.0, -1.0, f64::NAN]).is_none());
    }

    #[test]
    fn linear_labels_read_as_their_values() {
        let axis = Axis::linear_over([0.0, 5.7e-3]);
        for tick in axis.ticks() {
            let label = tick.label.unwrap().replace('−', "-");
            assert_eq!(label.parse::<f64>().unwrap(), tick.value);
        }
        let tiny = Axis::linear_over([-3e-8, 0.0]);
        let labels: Vec<String> = tiny.ticks().into_iter().filter_map(|t| t.label).collect();
        assert!(labels.iter().any(|l| l.contains("×10⁻")), "{labels:?}");
        let upto = Axis::linear_over([0.0, 1e-5]);
        let top: Vec<String> = upto.ticks().into_iter().filter_map(|t| t.label).collect();
        assert!(top.contains(&"1×10⁻⁵".to_string()), "{top:?}");
        assert!(!top.iter().any(|l| l.starts_with("10×")), "{top:?}");
        assert!(tiny.low <= -3e-8 && tiny.high >= 0.0);
    }
}
