//! A small SVG writer: the elements the figures use (lines, polylines, markers, rectangles,
//! text), numbers written with fixed precision (the same data give the same bytes), text
//! escaped for XML, and every element kept inside the view box — text that would not fit is
//! shortened with "…", its width estimated conservatively at 0.6 × font size per character.

use std::fmt::Write;

/// The view box: 16:9, in user units that are pixels at 96 dpi.
pub const WIDTH: f64 = 1280.0;
pub const HEIGHT: f64 = 720.0;

/// Font sizes [px]: a figure shown 1280 px wide on a 16:9 slide keeps every text ≥ 14 pt
/// (18.7 px); the smallest here is 20 px.
pub const TITLE_SIZE: f64 = 28.0;
pub const LABEL_SIZE: f64 = 22.0;
pub const NOTE_SIZE: f64 = 20.0;

/// The conservative width of one character, as a fraction of the font size.
const CHAR_WIDTH: f64 = 0.6;
/// How far text reaches above its baseline and below it, as fractions of the font size.
const ASCENT: f64 = 1.0;
const DESCENT: f64 = 0.3;
/// Text keeps this far from the view box's edges.
const EDGE: f64 = 4.0;

/// Where text is anchored at its x.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Anchor {
    Start,
    Middle,
    End,
}

impl Anchor {
    fn name(self) -> &'static str {
        match self {
            Anchor::Start => "start",
            Anchor::Middle => "middle",
            Anchor::End => "end",
        }
    }
}

/// The shape of a series' markers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MarkerShape {
    Circle,
    Square,
    TriangleUp,
    Diamond,
    Plus,
    Cross,
    TriangleDown,
}

/// A number for an attribute: two decimals, no `-0.00`.
pub fn px(value: f64) -> String {
    let text = format!("{value:.2}");
    if text == "-0.00" { "0.00".into() } else { text }
}

/// A data value for a `data-` attribute: the shortest text that reads back as the same f64.
pub fn data_value(value: f64) -> String {
    format!("{value:e}")
}

/// `text` escaped for XML text and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            // A control character is not allowed in XML 1.0 at all, and a bidirectional
            // control would show the rest of the line reversed: each written as its escape,
            // as every output writes them (`format::printable`).
            c if crate::format::acts_on_text(c) => out.push_str(&c.escape_unicode().to_string()),
            c => out.push(c),
        }
    }
    out
}

/// The estimated width [px] of `text` at `size`.
pub fn text_width(text: &str, size: f64) -> f64 {
    text.chars().count() as f64 * CHAR_WIDTH * size
}

/// `text` in lines of at most `width` px at `size`, broken between words (a word longer than
/// a line is cut with "…"): a legend's entry wraps rather than loses its unit.
pub fn wrap_text(text: &str, size: f64, width: f64) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split(' ').filter(|w| !w.is_empty()) {
        match lines.last_mut() {
            Some(line) if text_width(&format!("{line} {word}"), size) <= width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(fit_text(word, size, width)),
        }
    }
    if lines.is_empty() {
        lines.push(String::new());
    }
    lines
}

/// `text` cut (with "…") to at most `width` px at `size`.
pub fn fit_text(text: &str, size: f64, width: f64) -> String {
    let most = (width / (CHAR_WIDTH * size)).floor().max(1.0) as usize;
    if text.chars().count() <= most {
        return text.to_string();
    }
    let mut cut: String = text.chars().take(most - 1).collect();
    cut.push('…');
    cut
}

/// An SVG document being written.
pub struct Svg {
    body: String,
}

impl Svg {
    /// A white 16:9 page with a title and a description for screen readers.
    pub fn new(title: &str, description: &str) -> Svg {
        let mut body = String::new();
        let _ = writeln!(
            body,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="DejaVu Sans, Helvetica, Arial, sans-serif">"#,
            w = WIDTH,
            h = HEIGHT
        );
        let _ = writeln!(body, "<title>{}</title>", escape(title));
        let _ = writeln!(body, "<desc>{}</desc>", escape(description));
        let _ = writeln!(
            body,
            r##"<rect class="background" x="0" y="0" width="{WIDTH}" height="{HEIGHT}" fill="#ffffff"/>"##
        );
        Svg { body }
    }

    /// Raw markup (already escaped), e.g. a group's opening tag.
    pub fn raw(&mut self, markup: &str) {
        self.body.push_str(markup);
        self.body.push('\n');
    }

    /// A straight line; `dash` like `"8 6"`.
    pub fn line(&mut self, from: (f64, f64), to: (f64, f64), stroke: &str, width: f64, dash: &str) {
        let dash = if dash.is_empty() {
            String::new()
        } else {
            format!(r#" stroke-dasharray="{dash}""#)
        };
        let _ = writeln!(
            self.body,
            r#"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="{stroke}" stroke-width="{}"{dash}/>"#,
            px(from.0),
            px(from.1),
            px(to.0),
            px(to.1),
            px(width)
        );
    }

    /// A rectangle; `attributes` are added as they are (e.g. `class="band"`).
    pub fn rect(&mut self, corner: (f64, f64), size: (f64, f64), style: &str, attributes: &str) {
        let _ = writeln!(
            self.body,
            r#"<rect x="{}" y="{}" width="{}" height="{}" {style} {attributes}/>"#,
            px(corner.0),
            px(corner.1),
            px(size.0.max(0.0)),
            px(size.1.max(0.0))
        );
    }

    /// A polyline through `points` (pixels); `attributes` as for [`Svg::rect`].
    pub fn polyline(&mut self, points: &[(f64, f64)], style: &str, attributes: &str) {
        let list: Vec<String> = points
            .iter()
            .map(|(x, y)| format!("{},{}", px(*x), px(*y)))
            .collect();
        let _ = writeln!(
            self.body,
            r#"<polyline points="{}" fill="none" {style} {attributes}/>"#,
            list.join(" ")
        );
    }

    /// A marker of `shape` centred at `at`, `radius` px; `attributes` as for [`Svg::rect`].
    pub fn marker(
        &mut self,
        shape: MarkerShape,
        at: (f64, f64),
        radius: f64,
        style: &str,
        attributes: &str,
    ) {
        let (x, y) = at;
        let r = radius;
        let polygon = |corners: &[(f64, f64)]| {
            corners
                .iter()
                .map(|(dx, dy)| format!("{},{}", px(x + dx * r), px(y + dy * r)))
                .collect::<Vec<_>>()
                .join(" ")
        };
        let t = 0.35;
        let corners: Vec<(f64, f64)> = match shape {
            MarkerShape::Circle => {
                let _ = writeln!(
                    self.body,
                    r#"<circle cx="{}" cy="{}" r="{}" {style} {attributes}/>"#,
                    px(x),
                    px(y),
                    px(r)
                );
                return;
            }
            MarkerShape::Square => vec![(-0.85, -0.85), (0.85, -0.85), (0.85, 0.85), (-0.85, 0.85)],
            MarkerShape::TriangleUp => vec![(0.0, -1.0), (0.95, 0.8), (-0.95, 0.8)],
            MarkerShape::TriangleDown => vec![(0.0, 1.0), (0.95, -0.8), (-0.95, -0.8)],
            MarkerShape::Diamond => vec![(0.0, -1.1), (1.0, 0.0), (0.0, 1.1), (-1.0, 0.0)],
            MarkerShape::Plus => vec![
                (-t, -1.0),
                (t, -1.0),
                (t, -t),
                (1.0, -t),
                (1.0, t),
                (t, t),
                (t, 1.0),
                (-t, 1.0),
                (-t, t),
                (-1.0, t),
                (-1.0, -t),
                (-t, -t),
            ],
            MarkerShape::Cross => {
                let (a, b) = (0.75, 0.25);
                vec![
                    (-a - b, -a + b),
                    (-a + b, -a - b),
                    (0.0, -2.0 * b),
                    (a - b, -a - b),
                    (a + b, -a + b),
                    (2.0 * b, 0.0),
                    (a + b, a - b),
                    (a - b, a + b),
                    (0.0, 2.0 * b),
                    (-a + b, a + b),
                    (-a - b, a - b),
                    (-2.0 * b, 0.0),
                ]
            }
        };
        let _ = writeln!(
            self.body,
            r#"<polygon points="{}" {style} {attributes}/>"#,
            polygon(&corners)
        );
    }

    /// Text at `at` (its baseline), kept inside the view box: cut to fit horizontally, moved
    /// down or up to fit vertically.
    pub fn text(
        &mut self,
        at: (f64, f64),
        anchor: Anchor,
        size: f64,
        text: &str,
        attributes: &str,
    ) {
        let (mut x, y) = at;
        let room = match anchor {
            Anchor::Start => WIDTH - EDGE - x,
            Anchor::End => x - EDGE,
            Anchor::Middle => 2.0 * (x - EDGE).min(WIDTH - EDGE - x),
        };
        let shown = if room <= 0.0 {
            x = x.clamp(EDGE, WIDTH - EDGE);
            fit_text(text, size, WIDTH - 2.0 * EDGE)
        } else {
            fit_text(text, size, room)
        };
        let y = y.clamp(EDGE + ASCENT * size, HEIGHT - EDGE - DESCENT * size);
        let _ = writeln!(
            self.body,
            r##"<text x="{}" y="{}" font-size="{}" text-anchor="{}" fill="#000000" {attributes}>{}</text>"##,
            px(x),
            px(y),
            px(size),
            anchor.name(),
            escape(&shown)
        );
    }

    /// The finished document.
    pub fn finish(mut self) -> String {
        self.body.push_str("</svg>\n");
        self.body
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_escaped_and_cut() {
        assert_eq!(
            escape(r#"a<b & "c">'"#),
            "a&lt;b &amp; &quot;c&quot;&gt;&apos;"
        );
        assert_eq!(escape("a\u{1b}b"), "a\\u{1b}b");
        assert_eq!(escape("a\u{202e}b\u{2066}"), "a\\u{202e}b\\u{2066}");
        assert_eq!(fit_text("abcdef", 10.0, 30.0), "abcd…");
        assert_eq!(fit_text("abc", 10.0, 30.0), "abc");
    }

    #[test]
    fn numbers_have_fixed_precision() {
        assert_eq!(px(1.0), "1.00");
        assert_eq!(px(-0.001), "0.00");
        assert_eq!(data_value(1e-8), "1e-8");
        assert_eq!(data_value(0.1).parse::<f64>().unwrap(), 0.1);
    }
}
