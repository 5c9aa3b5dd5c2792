//! The pieces every chart panel is made of: a bordered block with, on its last lines, the
//! readout of the current point and the key; a notice in place of a chart; markers in Unicode
//! or ASCII; log10 points of data.

use ratatui::Frame;
use ratatui::layout::{Alignment, Rect};
use ratatui::style::Style;
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

use super::Theme;

/// Where a chart goes: its area, the title of its block, and whether it has the focus.
#[derive(Debug, Clone)]
pub struct PanelFrame {
    pub area: Rect,
    pub title: String,
    pub focused: bool,
}

/// A panel's title as it fits on its top border (`width` cells, corners included): whole
/// words only, and no bracket left open — `Deflection u(x) [m] (b: next) [1/4 Tab]` in 28
/// cells is ` Deflection u(x) [m]… ` — with `…` (`.` in ASCII) where it was cut.
pub fn fitted_title(title: &str, width: u16, ascii: bool) -> String {
    let room = usize::from(width.saturating_sub(2));
    if title.chars().count() <= room {
        return title.to_string();
    }
    // Whole, without its closing blank.
    let whole = format!(" {}", title.trim());
    if whole.chars().count() <= room {
        return whole;
    }
    let words: Vec<&str> = title.trim().split(' ').collect();
    let mut fitted = String::new();
    for count in (1..=words.len()).rev() {
        let candidate = words[..count].join(" ");
        let open = candidate.matches(['(', '[']).count();
        let closed = candidate.matches([')', ']']).count();
        // " " + candidate + "…" + " " within the room.
        if open == closed && candidate.chars().count() + 3 <= room {
            fitted = candidate;
            break;
        }
    }
    if fitted.is_empty() {
        return String::new();
    }
    format!(" {fitted}{} ", if ascii { "." } else { "…" })
}

/// A message in place of a chart.
pub fn notice(frame: &mut Frame, theme: &Theme, panel: PanelFrame, text: String) {
    let title = fitted_title(
        &theme.text(&panel.title),
        panel.area.width,
        theme.look.ascii,
    );
    let block = theme.block(title, panel.focused);
    frame.render_widget(
        Paragraph::new(theme.text(&text).into_owned())
            .wrap(Wrap { trim: true })
            .alignment(Alignment::Center)
            .block(block),
        panel.area,
    );
}

/// One entry of a chart's key: its marker and name (and a shorter name for narrow panels).
pub struct KeyEntry {
    pub marker: char,
    pub name: String,
    pub style: Style,
    /// Used for every entry when the full names would not fit.
    pub short: Option<String>,
}

/// One piece of a readout or key line: text in a style. Pieces are laid out in lines no wider
/// than the panel, never split.
pub type Piece = (String, Style);

/// Lays `pieces` out in lines of at most `width` characters, `gap` blanks apart; a piece wider
/// than a line is cut with `…` (`.` in ASCII).
pub fn pack(pieces: &[Piece], width: usize, gap: usize, ascii: bool) -> Vec<Line<'static>> {
    let mut lines: Vec<Vec<Span<'static>>> = Vec::new();
    let mut used = 0usize;
    for (text, style) in pieces {
        let mut text = text.clone();
        let mut len = text.chars().count();
        if len > width {
            text = text.chars().take(width.saturating_sub(1)).collect();
            text.push(if ascii { '.' } else { '…' });
            len = width;
        }
        if lines.is_empty() || used + gap + len > width {
            lines.push(Vec::new());
            used = 0;
        } else {
            lines
                .last_mut()
                .expect("a line")
                .push(Span::raw(" ".repeat(gap)));
            used += gap;
        }
        lines
            .last_mut()
            .expect("a line")
            .push(Span::styled(text, *style));
        used += len;
    }
    lines.into_iter().map(Line::from).collect()
}

/// Draws the panel's block with the readout and the key on its last lines (as many as are
/// needed, while at least `plot_rows` rows stay for the chart; the key's entries packed two
/// blanks apart, or one when that saves a line, with their short names when the full ones do
/// not fit; the `optional` pieces after the readout only when there is room for them) and
/// returns the rectangle left for the chart.
pub fn panel_with_key(
    frame: &mut Frame,
    theme: &Theme,
    panel: &PanelFrame,
    readout: &[Piece],
    optional: &[Piece],
    key: &[KeyEntry],
    plot_rows: u16,
) -> Rect {
    let title = fitted_title(
        &theme.text(&panel.title),
        panel.area.width,
        theme.look.ascii,
    );
    let block = theme.block(title, panel.focused);
    let inner = block.inner(panel.area);
    frame.render_widget(block, panel.area);
    let (plot, lines) = key_layout(theme, inner, readout, optional, key, plot_rows);
    let text_area = Rect {
        y: inner.y + plot.height,
        height: inner.height - plot.height,
        ..inner
    };
    frame.render_widget(Paragraph::new(lines), text_area);
    plot
}

/// Where [`panel_with_key`] puts the chart inside the block (`inner`), and the readout and key
/// lines under it: the same layout for drawing and for hit-testing.
pub fn key_layout(
    theme: &Theme,
    inner: Rect,
    readout: &[Piece],
    optional: &[Piece],
    key: &[KeyEntry],
    plot_rows: u16,
) -> (Rect, Vec<Line<'static>>) {
    let width = inner.width as usize;
    let ascii = theme.look.ascii;
    let key_pieces = |short: bool| -> Vec<Piece> {
        key.iter()
            .map(|e| {
                let name = match (&e.short, short) {
                    (Some(s), true) => s,
                    _ => &e.name,
                };
                let text = format!("{} {name}", e.marker);
                (theme.text(&text).into_owned(), e.style)
            })
            .collect()
    };
    let best = |pieces: &[Piece]| {
        let wide = pack(pieces, width, 2, ascii);
        let tight = pack(pieces, width, 1, ascii);
        if tight.len() < wide.len() {
            tight
        } else {
            wide
        }
    };
    let readout: Vec<Piece> = readout
        .iter()
        .chain(optional)
        .map(|(t, s)| (theme.text(t).into_owned(), *s))
        .collect();
    let room = inner.height.saturating_sub(plot_rows) as usize;
    let essential = readout.len() - optional.len().min(readout.len());
    let readout_lines: Vec<Line> = pack(&readout[..essential], width, 1, ascii)
        .into_iter()
        .take(room)
        .collect();
    let mut key_lines = best(&key_pieces(false));
    if key_lines.len() > room - readout_lines.len() && key.iter().any(|e| e.short.is_some()) {
        key_lines = best(&key_pieces(true));
    }
    // The optional pieces only where the key leaves room for them.
    let with_optional = pack(&readout, width, 1, ascii);
    let readout_lines = if with_optional.len() + key_lines.len() <= room {
        with_optional
    } else {
        readout_lines
    };
    let key_lines: Vec<Line> = key_lines
        .into_iter()
        .take(room - readout_lines.len())
        .collect();
    let below = (readout_lines.len() + key_lines.len()) as u16;
    let plot = Rect {
        height: inner.height - below,
        ..inner
    };
    let mut lines = readout_lines;
    lines.extend(key_lines);
    (plot, lines)
}

/// The marker of a curve, from the theme's marker set (ASCII in an ASCII look).
pub fn curve_marker(theme: &Theme) -> Marker {
    theme.curve_markers().curve()
}

/// The key's marker of a curve.
pub fn curve_key(theme: &Theme) -> char {
    theme.curve_markers().curve_key()
}

/// A point marker: `unicode`, or `ascii` in ASCII mode.
pub fn point_marker(theme: &Theme, unicode: char, ascii: char) -> Marker {
    Marker::Custom(marker_char(theme, unicode, ascii))
}

/// The character of a point marker for the theme's look.
pub fn marker_char(theme: &Theme, unicode: char, ascii: char) -> char {
    if theme.look.ascii { ascii } else { unicode }
}

/// (log10 x, log10 y) of the pairs whose values are positive and finite.
pub fn log_points(pairs: impl Iterator<Item = (f64, Option<f64>)>) -> Vec<(f64, f64)> {
    pairs
        .filter_map(|(x, y)| {
            let y = y?;
            (x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite()).then(|| (x.log10(), y.log10()))
        })
        .collect()
}

/// The smallest and largest x and y of the points, if any.
pub fn bounds_of<'a>(
    points: impl IntoIterator<Item = &'a (f64, f64)>,
) -> Option<([f64; 2], [f64; 2])> {
    let mut iter = points.into_iter();
    let first = iter.next()?;
    let (mut x, mut y) = ([first.0, first.0], [first.1, first.1]);
    for p in iter {
        x = [x[0].min(p.0), x[1].max(p.0)];
        y = [y[0].min(p.1), y[1].max(p.1)];
    }
    Some((x, y))
}

#[cfg(test)]
mod tests {
    use super::fitted_title;

    #[test]
    fn titles_fit_in_whole_words_with_no_bracket_left_open() {
        let title = " Deflection u(x) [m] (b: next) [1/4 Tab] ";
        assert_eq!(fitted_title(title, 60, false), title);
        assert_eq!(fitted_title(title, 30, false), " Deflection u(x) [m]… ");
        assert_eq!(fitted_title(title, 30, true), " Deflection u(x) [m]. ");
        assert_eq!(
            fitted_title(" Error vs ε (regularised) [2/4 Tab] ", 30, false),
            " Error vs ε (regularised)… "
        );
        assert_eq!(fitted_title(title, 4, false), "");
        assert_eq!(fitted_title(" ab cd ", 9, false), " ab cd ");
        assert_eq!(fitted_title(" ab cd ", 8, false), " ab cd");
        for width in 0..50 {
            let fitted = fitted_title(title, width, false);
            assert!(
                fitted.chars().count() <= usize::from(width.saturating_sub(2)) || fitted == title
            );
        }
    }
}
