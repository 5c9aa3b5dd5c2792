//! Chart axes whose labels are where their values are. Ratatui's chart spreads axis labels
//! evenly whatever their values, so the charts here leave its labels empty and draw their own:
//! a [`Scale`] is the bounds of an axis, its tick values and its labels, chosen for the number
//! of cells the axis has so that labels fit without overlapping; [`cell`] is where a value
//! lands, by the same rounding as ratatui's canvas, so a label sits on its value's column or
//! row. Log axes ([`log_scale`]) take log10 values and tick whole decades; linear axes
//! ([`linear_scale`]) tick "nice" values, 1, 2 or 5 × 10^k.

/// An axis: bounds in plotted values (log10 for a log axis), the ticks, and the ticks that
/// carry a label with the label's text.
#[derive(Debug, Clone, PartialEq)]
pub struct Scale {
    pub bounds: [f64; 2],
    /// Every tick mark, in plotted values.
    pub ticks: Vec<f64>,
    /// The labelled ticks and their text.
    pub labels: Vec<(f64, String)>,
}

/// The cell (column from the left, or row from the bottom) of `value` on an axis of `cells`
/// cells over `bounds`: ratatui's canvas rounding (`round((v - low)·(cells − 1)/(high −
/// low))`), so a label and a point of the same value share a cell. `None` outside the bounds.
pub fn cell(value: f64, [low, high]: [f64; 2], cells: u16) -> Option<u16> {
    let unit = to_unit(value, [low, high]);
    if !(0.0..=1.0).contains(&unit) || cells == 0 {
        return None;
    }
    Some((unit * f64::from(cells - 1)).round() as u16)
}

/// The first column of a label of `width` characters centred on `column` (for an even width,
/// the left of the two middle characters is on the column).
pub fn label_start(column: u16, width: u16) -> i32 {
    i32::from(column) - (i32::from(width) - 1) / 2
}

/// Do labels at these cells fit along the axis: on a horizontal axis centred on their columns
/// with a blank between neighbours, on a vertical one on distinct rows `gap` apart?
fn labels_fit(placed: &[(u16, usize)], horizontal: bool, gap: u16) -> bool {
    placed.windows(2).all(|pair| {
        let ((a, wa), (b, wb)) = (pair[0], pair[1]);
        if horizontal {
            let end_a = label_start(a, wa as u16) + wa as i32 - 1;
            label_start(b, wb as u16) >= end_a + 2
        } else {
            b.abs_diff(a) >= gap
        }
    })
}

/// The text of the label of decade `k`.
pub fn decade_label(k: i64) -> String {
    format!("1e{k}")
}

/// The widest decade label on an axis over [min, max] (log10 values).
pub fn widest_decade_label(min: f64, max: f64) -> u16 {
    let (low, high) = decade_range(min, max);
    [low, high, low.min(-1), high.max(1)]
        .iter()
        .filter(|k| (low..=high).contains(k))
        .map(|&k| decade_label(k).len() as u16)
        .max()
        .unwrap_or(3)
}

/// Whole decades covering [min, max] (log10 values): at least one decade wide; [0, 1] for
/// values that are not finite.
fn decade_range(min: f64, max: f64) -> (i64, i64) {
    if !(min.is_finite() && max.is_finite()) {
        return (0, 1);
    }
    let low = min.min(max).floor().clamp(-400.0, 400.0) as i64;
    let high = max.max(min).ceil().clamp(-400.0, 400.0) as i64;
    (low, high.max(low + 1))
}

/// A log axis over [min, max] (log10 values) along `cells` cells: bounds on whole decades,
/// a tick on every decade when they are at least two cells apart, and labels `1eK` on the
/// decades that are multiples of the smallest step (1, 2, 3, 4, 5, 10, 20, … decades) at which
/// they fit — one label at least.
pub fn log_scale(min: f64, max: f64, cells: u16, horizontal: bool) -> Scale {
    let (low, high) = decade_range(min, max);
    let bounds = [low as f64, high as f64];
    let at = |k: i64| cell(k as f64, bounds, cells);
    let gap = if cells >= 5 { 2 } else { 1 };
    let labelled =
        |step: i64| -> Vec<i64> { (low..=high).filter(|k| k.rem_euclid(step) == 0).collect() };
    let fits = |decades: &[i64]| {
        let placed: Vec<(u16, usize)> = decades
            .iter()
            .filter_map(|&k| Some((at(k)?, decade_label(k).len())))
            .collect();
        labels_fit(&placed, horizontal, gap)
    };
    let mut steps = vec![1, 2, 3, 4, 5];
    let mut s = 10;
    while s <= 2 * (high - low) + 10 {
        steps.extend([s, 2 * s, 5 * s]);
        s *= 10;
    }
    let chosen = steps
        .into_iter()
        .map(labelled)
        .find(|decades| !decades.is_empty() && fits(decades))
        .unwrap_or_else(|| vec![low]);
    let spacing = |a: i64, b: i64| match (at(a), at(b)) {
        (Some(a), Some(b)) => b.abs_diff(a),
        _ => 0,
    };
    let every_decade = (low..high).all(|k| spacing(k, k + 1) >= 2);
    let ticks = if every_decade {
        (low..=high).map(|k| k as f64).collect()
    } else {
        chosen.iter().map(|&k| k as f64).collect()
    };
    Scale {
        bounds,
        ticks,
        labels: chosen
            .into_iter()
            .map(|k| (k as f64, decade_label(k)))
            .collect(),
    }
}

/// The label of a tick of a linear axis with ticks `step` apart: as few digits as tell the
/// ticks apart, plain decimals for moderate values, else `1.5e-2`.
pub fn tick_label(value: f64, step: f64) -> String {
    if value == 0.0 || value.abs() < step * 1e-9 {
        return "0".into();
    }
    let step_exponent = step.abs().log10().floor() as i32;
    let magnitude = value.abs();
    if (1e-3..1e5).contains(&magnitude) && step_exponent >= -4 {
        let decimals = (-step_exponent).max(0) as usize;
        let text = format!("{value:.decimals$}");
        return if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        };
    }
    let exponent = magnitude.log10().floor() as i32;
    let digits = (exponent - step_exponent).clamp(0, 15) as usize;
    let text = format!("{value:.digits$e}");
    match text.split_once('e') {
        Some((mantissa, exp)) if mantissa.contains('.') => {
            let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
            format!("{mantissa}e{exp}")
        }
        _ => text,
    }
}

/// A linear axis over [min, max] along `cells` cells: bounds on multiples of a nice step
/// (1, 2 or 5 × 10^k), the smallest step whose labels fit, every multiple ticked and labelled.
/// Data that is not finite or whose nice bounds would not be gives the bounds [min, max]
/// (padded when they are equal) labelled at both ends; finite for any finite input.
pub fn linear_scale(min: f64, max: f64, cells: u16, horizontal: bool) -> Scale {
    let (min, max) = if min <= max { (min, max) } else { (max, min) };
    let (min, max) = if !(min.is_finite() && max.is_finite()) {
        (0.0, 1.0)
    } else if min == max {
        let pad = if min == 0.0 { 1.0 } else { 0.1 * min.abs() };
        (min - pad, max + pad)
    } else {
        (min, max)
    };
    let fallback = || {
        let bounds = [min, max];
        let label = |v: f64| crate::format::sci(v, 3);
        Scale {
            bounds,
            ticks: vec![min, max],
            labels: vec![(min, label(min)), (max, label(max))],
        }
    };
    // Halves first, so that the span of ±1.7e308 does not overflow.
    let span = 2.0 * (0.5 * max - 0.5 * min);
    if !span.is_finite() || span <= 0.0 || cells < 2 {
        return fallback();
    }
    let gap = if cells >= 5 { 2 } else { 1 };
    // At most one tick per eight columns across, per two rows up: room for the title.
    let most = f64::from(if horizontal { cells / 8 } else { cells / 2 }.max(2));
    // Clamped: span / most can underflow to 0 (log10 = -inf) for subnormal data.
    let mut exponent = (span / most).log10().floor().clamp(-330.0, 310.0) as i32 - 1;
    for _ in 0..40 {
        for mantissa in [1.0, 2.0, 5.0] {
            let step = mantissa * 10f64.powi(exponent);
            if !(step.is_finite() && step > 0.0) {
                continue;
            }
            let low = (min / step).floor();
            let high = (max / step).ceil();
            let count = high - low;
            if count > most || count < 1.0 {
                continue;
            }
            let bounds = [low * step, high * step];
            if !(bounds[0].is_finite() && bounds[1].is_finite()) {
                return fallback();
            }
            let ticks: Vec<f64> = (0..=count as i64)
                .map(|i| (low + i as f64) * step)
                .collect();
            let labels: Vec<(f64, String)> =
                ticks.iter().map(|&v| (v, tick_label(v, step))).collect();
            let placed: Vec<(u16, usize)> = labels
                .iter()
                .filter_map(|(v, text)| Some((cell(*v, bounds, cells)?, text.chars().count())))
                .collect();
            if placed.len() == labels.len() && labels_fit(&placed, horizontal, gap) {
                return Scale {
                    bounds,
                    ticks,
                    labels,
                };
            }
        }
        exponent += 1;
    }
    fallback()
}

/// Maps `value` from `bounds` onto [0, 1], so that the chart widget only ever sees a unit
/// square: its own mapping to the character grid breaks down (and its line drawing can walk
/// billions of cells) when the bounds are extreme or subnormal. Values that land far outside
/// are clamped; the widget clips lines to the square.
pub fn to_unit(value: f64, [low, high]: [f64; 2]) -> f64 {
    let unit = (0.5 * value - 0.5 * low) / (0.5 * high - 0.5 * low);
    if unit.is_finite() {
        unit.clamp(-1.0, 2.0)
    } else {
        0.5
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decades_are_labelled_at_their_own_cells_and_never_overlap() {
        for cells in 10..=200u16 {
            for decades in 1..=20i64 {
                for low in [-20i64, -16, -7, -1, 0, 1, 3] {
                    let (min, max) = (low as f64 + 0.3, (low + decades) as f64 - 0.2);
                    for horizontal in [true, false] {
                        let scale = log_scale(min, max, cells, horizontal);
                        assert!(!scale.labels.is_empty());
                        assert!(scale.bounds[0] <= min && scale.bounds[1] >= max);
                        for (value, text) in &scale.labels {
                            assert_eq!(*text, decade_label(*value as i64));
                            // Independent of `cell`: where the value lies proportionally.
                            let exact = (value - scale.bounds[0])
                                / (scale.bounds[1] - scale.bounds[0])
                                * f64::from(cells - 1);
                            let at = cell(*value, scale.bounds, cells).unwrap();
                            assert!((f64::from(at) - exact).abs() <= 0.5 + 1e-9);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn nice_linear_ticks() {
        let scale = linear_scale(-1.73e-3, 2.146e-2, 20, false);
        for (value, text) in &scale.labels {
            let mantissa = value.abs() / 10f64.powf(value.abs().log10().floor());
            assert!(
                *value == 0.0
                    || [1.0, 2.0, 2.5, 4.0, 5.0, 6.0, 8.0]
                        .iter()
                        .any(|m| (mantissa / m - 1.0).abs() < 1e-9)
                    || (mantissa * 10.0).fract().abs() < 1e-6,
                "{value} {text}"
            );
        }
        assert!(scale.bounds[0] <= -1.73e-3 && scale.bounds[1] >= 2.146e-2);
        let texts: Vec<&str> = scale.labels.iter().map(|(_, t)| t.as_str()).collect();
        assert!(texts.contains(&"0"), "{texts:?}");
        assert!(
            texts.contains(&"0.01") || texts.contains(&"0.02"),
            "{texts:?}"
        );
        // The extremes of f64 stay finite; a span so small that span / cells underflows to
        // zero (found by tests/it/fuzz.rs) does not overflow the exponent.
        for (a, b) in [
            (-f64::MAX, f64::MAX),
            (0.0, 0.0),
            (5e-324, 1e-323),
            (0.0, 5e-324),
            (-5e-324, 5e-324),
            (1e300, 1e300),
        ] {
            for cells in [1, 2, 5, 30, 200] {
                for horizontal in [true, false] {
                    let s = linear_scale(a, b, cells, horizontal);
                    assert!(s.bounds.iter().all(|v| v.is_finite()), "{a} {b}");
                    assert!(s.bounds[0] < s.bounds[1], "{a} {b}");
                }
            }
            let s = linear_scale(a, b, 30, true);
            assert!(s.bounds.iter().all(|v| v.is_finite()), "{a} {b}");
            assert!(s.bounds[0] < s.bounds[1], "{a} {b}");
        }
    }

    #[test]
    fn tick_labels_are_short_and_exact() {
        assert_eq!(tick_label(0.015, 0.005), "0.015");
        assert_eq!(tick_label(0.01, 0.005), "0.01");
        assert_eq!(tick_label(-0.005, 0.005), "-0.005");
        assert_eq!(tick_label(2e-6, 1e-6), "2e-6");
        assert_eq!(tick_label(1.5e-6, 5e-7), "1.5e-6");
        assert_eq!(tick_label(0.4, 0.2), "0.4");
        assert_eq!(tick_label(3e5, 1e5), "3e5");
        assert_eq!(tick_label(1e-17, 0.005), "0");
    }
}
