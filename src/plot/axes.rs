//! Axes for ratatui's chart, which has no log axis: log–log charts plot log10 values and label
//! the axis in decades, with bounds chosen so that the evenly spread labels fall on decades;
//! linear axes are padded and finite for any finite data.

/// Bounds and labels of a log10 axis covering [min, max]: whole decades, as many labels as
/// `room` cells allow (two to five), the bounds a whole number of label steps apart.
pub fn decade_axis(min: f64, max: f64, room: u16) -> ([f64; 2], Vec<String>) {
    let low = min.floor();
    let mut high = max.ceil();
    if high <= low {
        high = low + 1.0;
    }
    let span = high - low;
    let intervals_wanted = (f64::from(room) / 7.0).floor().clamp(1.0, 4.0);
    let step = (span / intervals_wanted).ceil().max(1.0);
    let intervals = (span / step).ceil();
    let high = low + step * intervals;
    let labels = (0..=intervals as i64)
        .map(|i| format!("1e{}", (low + step * i as f64) as i64))
        .collect();
    ([low, high], labels)
}

/// Bounds and three labels of a linear axis covering [min, max], padded a little. Finite for
/// any finite input, the extremes of f64 included.
pub fn linear_axis(min: f64, max: f64) -> ([f64; 2], Vec<String>) {
    let label = |v: f64| crate::format::sci(v, 3);
    // Halves first, so that the span of ±1.7e308 does not overflow.
    let half_span = 0.5 * max - 0.5 * min;
    let pad = if half_span > 0.0 {
        0.16 * half_span
    } else if min == 0.0 {
        1.0
    } else {
        0.1 * min.abs()
    };
    let low = (min - pad).max(f64::MIN);
    let high = (max + pad).min(f64::MAX);
    (
        [low, high],
        vec![label(low), label(0.5 * low + 0.5 * high), label(high)],
    )
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
