//! ASCII mode, in words that keep their meaning: ε is spelled `eps` (a lone `e` reads as an
//! exponent), Â `A^` (cond2(A) would be another matrix), superscripts `^4`, × `x`, a separating
//! ` · ` becomes ` | ` and a multiplying `·` becomes `*`. Text the charts draw is spelled before
//! layout ([`spell_ascii`]); after drawing, [`transliterate`] replaces every cell that is still
//! not ASCII, spelling it out in the blanks to its right when there is room (two or more blanks
//! before the next border) and with a one-cell look-alike otherwise (box drawing by + - |,
//! Braille by *), so a frame never needs Unicode, whatever a widget or a label used.

use ratatui::buffer::Buffer;

/// The one-cell ASCII stand-in for one character.
pub fn ascii_char(c: char) -> char {
    if c.is_ascii() {
        return c;
    }
    if let Some(d) = superscript(c).or_else(|| subscript(c)) {
        // Where there is no room for the caret of ^T.
        return d;
    }
    match c {
        '─' | '━' | '═' | '╌' | '╍' | '┄' | '┅' => '-',
        '│' | '┃' | '║' | '╎' | '╏' | '┆' | '┇' | '┊' => '|',
        '┌' | '┐' | '└' | '┘' | '┏' | '┓' | '┗' | '┛' | '╭' | '╮' | '╰' | '╯' | '├' | '┤' | '┬'
        | '┴' | '┼' | '╔' | '╗' | '╚' | '╝' | '┣' | '┫' | '┳' | '┻' | '╋' => {
            '+'
        }
        'ε' => 'e',
        'λ' => 'l',
        'θ' => 't',
        'µ' | 'μ' => 'u',
        'Â' => 'A',
        '²' | '₂' => '2',
        '³' | '₃' => '3',
        '⁴' => '4',
        '·' | '•' => '*',
        '×' => 'x',
        '≥' => '>',
        '≤' => '<',
        '≈' | '∼' => '~',
        '—' | '–' | '−' => '-',
        '→' => '>',
        '←' => '<',
        '↑' => '^',
        '↓' => 'v',
        '…' => '.',
        '⚠' => '!',
        '\u{2800}' => ' ',
        '\u{2801}'..='\u{28ff}' => '*',
        // Block elements, quadrants and sextants: the marker sets' curves.
        '\u{2580}'..='\u{259f}' | '\u{1fb00}'..='\u{1fb3b}' => '#',
        '≠' => '#',
        // The charts' markers, as their ASCII legends show them (so a caption naming one
        // names the same in ASCII): the methods' (`study_charts`) and the obstacle states'
        // and the iterate's (`tui::layout::deflection`).
        '●' | '∘' => 'o',
        '■' => '#',
        '▲' => '^',
        '◆' => '%',
        '✚' => '+',
        '✖' => 'x',
        '★' => '@',
        '↕' => 'S',
        '↻' => 'W',
        '✱' => 'X',
        _ => '?',
    }
}

/// The digit of a superscript character (⁻ as `-`), if it is one.
fn superscript(c: char) -> Option<char> {
    Some(match c {
        '⁰' => '0',
        '¹' => '1',
        '²' => '2',
        '³' => '3',
        '⁴' => '4',
        '⁵' => '5',
        '⁶' => '6',
        '⁷' => '7',
        '⁸' => '8',
        '⁹' => '9',
        '⁻' => '-',
        'ᵀ' => 'T',
        _ => return None,
    })
}

/// The digit of a subscript character, if it is one.
fn subscript(c: char) -> Option<char> {
    let index = "₀₁₂₃₄₅₆₇₈₉".chars().position(|s| s == c)?;
    char::from_digit(index as u32, 10)
}

/// How `c` is spelled in ASCII, given the characters before and after it.
fn spell_char(previous: Option<char>, c: char, next: Option<char>) -> String {
    if c.is_ascii() {
        return c.to_string();
    }
    if let Some(d) = superscript(c) {
        // One caret for a run of superscripts: 10⁻¹⁶ is 10^-16.
        return if previous.and_then(superscript).is_some() {
            d.to_string()
        } else {
            format!("^{d}")
        };
    }
    if let Some(d) = subscript(c) {
        return d.to_string();
    }
    match c {
        'ε' => "eps".into(),
        'Â' => "A^".into(),
        'λ' => "lambda".into(),
        '·' if previous.is_none_or(|p| p == ' ') && next.is_none_or(|n| n == ' ') => "|".into(),
        '·' => "*".into(),
        '≥' => ">=".into(),
        '≠' => "!=".into(),
        '≤' => "<=".into(),
        '…' => "...".into(),
        '→' => "->".into(),
        '←' => "<-".into(),
        _ => ascii_char(c).to_string(),
    }
}

/// `text` spelled in ASCII (see the module comment).
pub fn spell_ascii(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    for (i, &c) in chars.iter().enumerate() {
        let previous = i.checked_sub(1).map(|j| chars[j]);
        out.push_str(&spell_char(previous, c, chars.get(i + 1).copied()));
    }
    out
}

/// Is this cell the edge of a widget (a border), beyond which text must not be pushed?
fn is_barrier(symbol: &str) -> bool {
    symbol == "|"
        || symbol == "+"
        || symbol
            .chars()
            .next()
            .is_some_and(|c| ('\u{2500}'..='\u{257f}').contains(&c))
}

/// Replaces every non-ASCII symbol in `buffer`, spelling it out when there is room.
pub fn transliterate(buffer: &mut Buffer) {
    let area = buffer.area;
    for y in area.top()..area.bottom() {
        let mut x = area.left();
        let mut previous: Option<char> = None;
        while x < area.right() {
            let symbol = buffer[(x, y)].symbol().to_string();
            let c = symbol.chars().next().unwrap_or(' ');
            if symbol.is_ascii() {
                previous = Some(c);
                x += 1;
                continue;
            }
            let next = (x + 1 < area.right())
                .then(|| buffer[(x + 1, y)].symbol().chars().next())
                .flatten();
            let spelled = spell_char(previous, c, next);
            previous = Some(c);
            let extra = spelled.chars().count().saturating_sub(1) as u16;
            let room = extra > 0 && make_room(buffer, x, y, extra);
            let text: Vec<char> = if room || extra == 0 {
                spelled.chars().collect()
            } else {
                vec![ascii_char(c)]
            };
            let style = buffer[(x, y)].style();
            for (i, ch) in text.iter().enumerate() {
                let cell = &mut buffer[(x + i as u16, y)];
                cell.set_char(*ch);
                cell.set_style(style);
            }
            x += text.len() as u16;
        }
    }
}

/// Shifts the cells right of `(x, y)` by `extra` cells into a run of blanks further right
/// (leaving one blank of the run, unless it ends at a border or the row's end), so that the
/// cell at `x` can be spelled with `extra` more characters. Returns false, changing nothing,
/// when there is no such run before a border.
fn make_room(buffer: &mut Buffer, x: u16, y: u16, extra: u16) -> bool {
    let right = buffer.area.right();
    let blank = |b: &Buffer, i: u16| b[(i, y)].symbol() == " ";
    let mut i = x + 1;
    let found = loop {
        if i >= right || is_barrier(buffer[(i, y)].symbol()) {
            break None;
        }
        if blank(buffer, i) {
            let mut end = i;
            while end < right && blank(buffer, end) {
                end += 1;
            }
            let run = end - i;
            let at_edge = end >= right || is_barrier(buffer[(end, y)].symbol());
            if run > extra || (at_edge && run >= extra) {
                break Some(i);
            }
            i = end;
        } else {
            i += 1;
        }
    };
    let Some(start) = found else { return false };
    // Cells x+1 .. start-1 move right by `extra`, into the blanks.
    let moved: Vec<_> = (x + 1..start).map(|i| buffer[(i, y)].clone()).collect();
    for (k, cell) in moved.into_iter().enumerate() {
        buffer[(x + 1 + extra + k as u16, y)] = cell;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use ratatui::layout::Rect;

    #[test]
    fn a_marker_named_in_text_reads_as_its_ascii_legend_shows_it() {
        // Stop 59's lecture pass: an ASCII caption said "the dual (?)" where the legend
        // showed "o dual".
        for (unicode, ascii) in super::super::study_charts::METHOD_MARKERS {
            assert_eq!(ascii_char(unicode), ascii, "{unicode}");
        }
        assert_eq!(
            spell_ascii("the dual (●), flexibility (▲)"),
            "the dual (o), flexibility (^)"
        );
        assert_eq!(ascii_char('ᵀ'), 'T');
        assert_eq!(ascii_char('⁻'), '-');
        assert_eq!(spell_ascii("B A⁻¹ Bᵀ"), "B A^-1 B^T");
    }

    #[test]
    fn every_character_becomes_ascii() {
        for c in ['ε', '│', '⣿', '●', '≥', 'µ', '漢'] {
            assert!(ascii_char(c).is_ascii(), "{c}");
        }
        // Every marker set's curve characters are drawn, not '?'.
        for c in ['▄', '▀', '▖', '▟', '█', '🬋', '🬀', '🬻'] {
            assert_eq!(ascii_char(c), '#', "{c}");
        }
    }

    #[test]
    fn words_keep_their_meaning() {
        assert_eq!(spell_ascii("ε = 1.0e-6"), "eps = 1.0e-6");
        assert_eq!(spell_ascii("cond₂(Â)"), "cond2(A^)");
        assert_eq!(spell_ascii("dual · n = 20"), "dual | n = 20");
        assert_eq!(spell_ascii("0.02·cond·eps"), "0.02*cond*eps");
        assert_eq!(spell_ascii("n⁴ and 10⁻¹⁶"), "n^4 and 10^-16");
        assert_eq!(spell_ascii("100×30"), "100x30");
        assert_eq!(spell_ascii("u ≠ 0"), "u != 0");
    }

    fn row(text: &str, width: u16) -> Buffer {
        let mut buffer = Buffer::empty(Rect::new(0, 0, width, 1));
        buffer.set_string(0, 0, text, ratatui::style::Style::default());
        buffer
    }

    fn text_of(buffer: &Buffer) -> String {
        buffer.content.iter().map(|c| c.symbol()).collect()
    }

    #[test]
    fn a_cell_is_spelled_out_into_the_blanks_to_its_right() {
        let mut buffer = row("epsilon ε      1.0e-6 |", 23);
        transliterate(&mut buffer);
        assert_eq!(text_of(&buffer), "epsilon eps    1.0e-6 |");
        let mut buffer = row("ε = 1e-6 · n⁴  ", 15);
        transliterate(&mut buffer);
        // The trailing blanks went to eps: n⁴ gets the one-cell stand-in.
        assert_eq!(text_of(&buffer), "eps = 1e-6 | n4");
        let mut buffer = row("ε = 1e-6 · n⁴      ", 19);
        transliterate(&mut buffer);
        assert_eq!(text_of(&buffer), "eps = 1e-6 | n^4   ");
        // No room before the border: a one-cell stand-in, nothing pushed over the border.
        let mut buffer = row("ab ε|cd", 7);
        transliterate(&mut buffer);
        assert_eq!(text_of(&buffer), "ab e|cd");
    }
}
