//! Formatting for people: numbers in engineering style (5.0e4, not 50000.000), units,
//! durations — never NaN or infinity as a number — and text from a scene file made safe to
//! show ([`printable`]).

use std::borrow::Cow;
use std::time::Duration;

/// `value` with `digits` significant digits in scientific form, e.g. `5.70e-3`; zero as `0`;
/// a non-finite value as `n/a`.
pub fn sci(value: f64, digits: usize) -> String {
    if !value.is_finite() {
        return "n/a".to_string();
    }
    if value == 0.0 {
        return "0".to_string();
    }
    let text = format!("{:.*e}", digits.saturating_sub(1), value);
    // Keep at least one decimal so that 5e4 reads 5.0e4.
    match text.split_once('e') {
        Some((mantissa, exponent)) if !mantissa.contains('.') => format!("{mantissa}.0e{exponent}"),
        _ => text,
    }
}

/// `value` for a parameter list: plain decimals between 0.01 and 10 000 (`0.8`, `20`,
/// `1.234`), else three significant digits in scientific form (`5.0e4`, `2.15e11`, `1.0e-6`).
pub fn eng(value: f64) -> String {
    if !value.is_finite() {
        return "n/a".to_string();
    }
    let magnitude = value.abs();
    if value == 0.0 {
        "0".to_string()
    } else if (1e-2..1e4).contains(&magnitude) {
        let decimals = (3 - magnitude.log10().floor() as i32).max(0) as usize;
        let text = format!("{value:.decimals$}");
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        }
    } else {
        let text = format!("{value:.2e}");
        let (mantissa, exponent) = text.split_once('e').expect("scientific form");
        let mantissa = mantissa.trim_end_matches('0');
        let mantissa = if mantissa.ends_with('.') {
            format!("{mantissa}0")
        } else {
            mantissa.to_string()
        };
        format!("{mantissa}e{exponent}")
    }
}

/// A duration in the most readable unit: `12.3 µs`, `4.56 ms`, `1.23 s`.
pub fn duration(d: Duration) -> String {
    let s = d.as_secs_f64();
    if s < 1e-3 {
        format!("{:.1} µs", s * 1e6)
    } else if s < 1.0 {
        format!("{:.2} ms", s * 1e3)
    } else {
        format!("{s:.2} s")
    }
}

/// Text from a scene file (a title, a description, a file name) as every output shows it —
/// the terminal, Markdown, SVG, the solve table: each control character (C0, DEL and C1,
/// `char::is_control`; a newline and a tab too) and each bidirectional control (U+061C,
/// U+200E/F, U+202A–U+202E, U+2066–U+2069) written as its `\u{..}` escape, e.g. ESC as
/// `\u{1b}`. An escape sequence in a title would otherwise recolour, retitle or clear the
/// terminal that shows it, a newline break a Markdown heading, a control byte make an SVG
/// file invalid XML, and a right-to-left override show the rest of a line reversed (what the
/// reader sees is not what is there). Text without them is returned as it is.
pub fn printable(text: &str) -> Cow<'_, str> {
    if !text.contains(acts_on_text) {
        return Cow::Borrowed(text);
    }
    Cow::Owned(
        text.chars()
            .map(|c| {
                if acts_on_text(c) {
                    c.escape_unicode().to_string()
                } else {
                    c.to_string()
                }
            })
            .collect(),
    )
}

/// Does `c` act on the text around it instead of showing: a control character, or one that
/// sets the direction of what follows ([`printable`] escapes both)?
pub fn acts_on_text(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{061C}' | '\u{200E}' | '\u{200F}' | '\u{202A}'..='\u{202E}' | '\u{2066}'..='\u{2069}'
        )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn engineering_form() {
        assert_eq!(sci(50000.0, 2), "5.0e4");
        assert_eq!(sci(0.0057016, 4), "5.702e-3");
        assert_eq!(sci(f64::NAN, 3), "n/a");
        assert_eq!(sci(f64::INFINITY, 3), "n/a");
        assert_eq!(sci(0.0, 3), "0");
        assert_eq!(duration(Duration::from_micros(12)), "12.0 µs");
        assert_eq!(eng(5e4), "5.0e4");
        assert_eq!(eng(2.15e11), "2.15e11");
        assert_eq!(eng(0.8), "0.8");
        assert_eq!(eng(20.0), "20");
        assert_eq!(eng(1e-6), "1.0e-6");
        assert_eq!(eng(-4798.46), "-4798");
        assert_eq!(eng(0.0057016), "5.7e-3");
        assert_eq!(eng(1.5e5), "1.5e5");
    }

    #[test]
    fn controls_and_direction_overrides_are_escaped() {
        assert_eq!(printable("plain ünïcode"), "plain ünïcode");
        assert_eq!(printable("a\u{1b}[2Jb"), "a\\u{1b}[2Jb");
        // Stop 58's hostile pass: a right-to-left override in a title was printed raw.
        assert_eq!(printable("beam \u{202E}txt.exe"), "beam \\u{202e}txt.exe");
        assert_eq!(printable("\u{2066}x\u{2069}"), "\\u{2066}x\\u{2069}");
    }

    #[test]
    fn control_characters_are_escaped_visibly() {
        assert_eq!(
            printable("a\x1b[31mred\x07\nb\tc\u{7f}\u{9b}é"),
            "a\\u{1b}[31mred\\u{7}\\u{a}b\\u{9}c\\u{7f}\\u{9b}é"
        );
        assert!(matches!(printable("Benchmark 1"), Cow::Borrowed(_)));
    }
}
