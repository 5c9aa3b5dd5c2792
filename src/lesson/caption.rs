//! A step's caption as the explorer shows it: paragraphs of plain text (a single newline in
//! the file is a space, a blank line starts a new paragraph), word-wrapped greedily to the
//! caption strip's width in terminal columns. The lesson's rules and the strip use this one wrapping, so a caption
//! accepted as fitting [`CAPTION_LINES`] lines at 80 columns is never cut there.

/// Most lines a caption may take at [`CAPTION_WIDTH`] columns: the strip at 80×24 has room for
/// these under its step line.
pub const CAPTION_LINES: usize = 3;
/// The caption strip's text width on an 80-column terminal (one column of margin each side).
pub const CAPTION_WIDTH: usize = 78;

/// The paragraphs of a caption as written: blank lines separate them; inside one, any run of
/// whitespace is one space.
pub fn paragraphs(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut current: Vec<&str> = Vec::new();
    for line in text.lines() {
        if line.trim().is_empty() {
            if !current.is_empty() {
                out.push(current.join(" "));
                current.clear();
            }
        } else {
            current.extend(line.split_whitespace());
        }
    }
    if !current.is_empty() {
        out.push(current.join(" "));
    }
    out
}

/// The columns `text` takes on a terminal: a CJK character two, a combining mark none.
pub fn columns(text: &str) -> usize {
    unicode_width::UnicodeWidthStr::width(text)
}

/// The longest start of `text` that fits `width` columns (possibly empty).
pub fn prefix_in_columns(text: &str, width: usize) -> &str {
    let mut used = 0;
    for (i, c) in text.char_indices() {
        used += char_columns(c);
        if used > width {
            return &text[..i];
        }
    }
    text
}

/// `text` in at most `width` columns, ending in `…` when cut.
pub fn fit_columns(text: &str, width: usize) -> String {
    if columns(text) <= width {
        return text.to_string();
    }
    format!("{}…", prefix_in_columns(text, width.saturating_sub(1)))
}

fn char_columns(c: char) -> usize {
    unicode_width::UnicodeWidthChar::width(c).unwrap_or(0)
}

/// The paragraphs wrapped to `width` columns (at least 1): greedy, at spaces; a word wider
/// than the line is cut into pieces that fit (at least a character each). Widths are terminal
/// columns: a CJK character takes two, a combining mark none.
pub fn wrap(paragraphs: &[String], width: usize) -> Vec<String> {
    let width = width.max(1);
    let mut lines = Vec::new();
    for paragraph in paragraphs {
        let mut line = String::new();
        let mut used = 0usize;
        for word in paragraph.split(' ').filter(|w| !w.is_empty()) {
            let mut word = word.to_string();
            // A word wider than a line: pieces that fill lines first.
            while columns(&word) > width {
                if used > 0 {
                    lines.push(std::mem::take(&mut line));
                    used = 0;
                }
                let (piece, rest) = split_at_columns(&word, width);
                lines.push(piece);
                word = rest;
            }
            let length = columns(&word);
            if used > 0 && used + 1 + length > width {
                lines.push(std::mem::take(&mut line));
                used = 0;
            }
            if used > 0 {
                line.push(' ');
                used += 1;
            }
            line.push_str(&word);
            used += length;
        }
        if used > 0 {
            lines.push(line);
        }
    }
    lines
}

/// The longest start of `word` that fits `width` columns (at least one character), and the
/// rest.
fn split_at_columns(word: &str, width: usize) -> (String, String) {
    let mut used = 0;
    let mut end = 0;
    for (i, c) in word.char_indices() {
        let w = char_columns(c);
        if used + w > width && end > 0 {
            break;
        }
        used += w;
        end = i + c.len_utf8();
    }
    (word[..end].to_string(), word[end..].to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paragraphs_join_lines_and_split_at_blank_ones() {
        let text = "  One line\nand the next.\n\n\nA second   paragraph.\n";
        assert_eq!(
            paragraphs(text),
            vec!["One line and the next.", "A second paragraph."]
        );
        assert!(paragraphs(" \n\t\n").is_empty());
    }

    #[test]
    fn wrapping_is_greedy_never_exceeds_the_width_and_keeps_every_word() {
        let text = vec!["aa bb cc dd ee".to_string(), "ffffffffff g".to_string()];
        let lines = wrap(&text, 5);
        assert_eq!(lines, vec!["aa bb", "cc dd", "ee", "fffff", "fffff", "g"]);
        for width in 1..20 {
            let lines = wrap(&text, width);
            assert!(
                lines.iter().all(|l| l.chars().count() <= width),
                "{lines:?}"
            );
            let words: String = lines.concat().split_whitespace().collect();
            assert_eq!(words, "aabbccddeeffffffffffg");
        }
        // ε and the like take one column each, a CJK character two, a combining mark none.
        assert_eq!(wrap(&["ε = 1e-2 ε".to_string()], 8), vec!["ε = 1e-2", "ε"]);
        assert_eq!(wrap(&["梁梁梁 梁".to_string()], 6), vec!["梁梁梁", "梁"]);
        assert_eq!(wrap(&["梁梁梁梁".to_string()], 5), vec!["梁梁", "梁梁"]);
        assert_eq!(wrap(&["梁".to_string()], 1), vec!["梁"]);
        assert_eq!(prefix_in_columns("梁a梁", 3), "梁a");
        assert_eq!(prefix_in_columns("梁", 1), "");
        assert_eq!(fit_columns("abcdef", 4), "abc…");
        assert_eq!(fit_columns("梁梁梁", 4), "梁…");
        assert_eq!(fit_columns("abc", 3), "abc");
        let accented = "e\u{301}".repeat(10);
        assert_eq!(
            wrap(std::slice::from_ref(&accented), 10),
            vec![accented.clone()]
        );
        for width in 1..12 {
            for line in wrap(&["梁a梁 bb 梁梁梁梁梁 c".to_string()], width) {
                assert!(columns(&line) <= width.max(2), "{line:?} at {width}");
            }
        }
    }
}
