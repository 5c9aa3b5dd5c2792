//! ASCII mode: after drawing, every cell whose symbol is not ASCII is replaced by a one-cell
//! ASCII look-alike (box drawing by + - |, Greek letters by Latin ones, Braille by *), so a
//! frame never needs Unicode, whatever a widget or a label used.

use ratatui::buffer::Buffer;

/// The ASCII stand-in for one character.
pub fn ascii_char(c: char) -> char {
    if c.is_ascii() {
        return c;
    }
    match c {
        '─' | '━' | '═' | '╌' | '╍' | '┄' | '┅' => '-',
        '│' | '┃' | '║' | '╎' | '╏' | '┆' | '┇' => '|',
        '┌' | '┐' | '└' | '┘' | '┏' | '┓' | '┗' | '┛' | '╭' | '╮' | '╰' | '╯' | '├' | '┤' | '┬'
        | '┴' | '┼' | '╔' | '╗' | '╚' | '╝' | '┣' | '┫' | '┳' | '┻' | '╋' => {
            '+'
        }
        'ε' => 'e',
        'λ' => 'l',
        'θ' => 't',
        'µ' | 'μ' => 'u',
        'Â' => 'A',
        '²' => '2',
        '³' => '3',
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
        '\u{2800}' => ' ',
        '\u{2801}'..='\u{28ff}' => '*',
        '█' | '▓' | '▒' | '░' | '▌' | '▐' | '▄' | '▀' => '#',
        _ => '?',
    }
}

/// Replaces every non-ASCII symbol in `buffer`.
pub fn transliterate(buffer: &mut Buffer) {
    for cell in buffer.content.iter_mut() {
        let symbol = cell.symbol();
        if !symbol.is_ascii() {
            let replacement: String = symbol.chars().take(1).map(ascii_char).collect();
            cell.set_symbol(if replacement.is_empty() {
                " "
            } else {
                &replacement
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_character_becomes_ascii() {
        for c in ['ε', '│', '⣿', '●', '≥', 'µ', '漢'] {
            assert!(ascii_char(c).is_ascii(), "{c}");
        }
    }
}
