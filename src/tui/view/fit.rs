//! Text made to fit a width without cutting a number or a word in two: word wrapping for the
//! warnings, and status lines that drop their least important items instead of running off
//! the edge.

/// `text` wrapped at spaces into lines of at most `width` characters; a word longer than the
/// width gets a line of its own, broken only then.
pub fn wrap_words(text: &str, width: usize) -> Vec<String> {
    let width = width.max(1);
    let mut lines = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        let mut word: Vec<char> = word.chars().collect();
        let line_width = line.chars().count();
        if line_width > 0 && line_width + 1 + word.len() <= width {
            line.push(' ');
            line.extend(word.iter());
            continue;
        }
        if line_width > 0 {
            lines.push(std::mem::take(&mut line));
        }
        while word.len() > width {
            lines.push(word.drain(..width).collect());
        }
        line = word.into_iter().collect();
    }
    if !line.is_empty() || lines.is_empty() {
        lines.push(line);
    }
    lines
}

/// The first row of `text` at `width` and the rest: cut after the last whole word that fits
/// (a word longer than the width is cut at the width), the rest starting at its next word, so
/// that a path keeps its characters in order with nothing put in.
pub fn first_row(text: &str, width: usize) -> (String, &str) {
    let width = width.max(1);
    let end = text
        .char_indices()
        .nth(width)
        .map_or(text.len(), |(at, _)| at);
    if end == text.len() {
        return (text.trim_end().to_string(), "");
    }
    let cut = if text[end..].starts_with(char::is_whitespace) {
        end
    } else {
        text[..end].rfind(' ').filter(|&at| at > 0).unwrap_or(end)
    };
    (text[..cut].trim_end().to_string(), text[cut..].trim_start())
}

/// An item of a status line: its text and its importance (0 most important).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Item {
    pub text: String,
    pub importance: u8,
}

impl Item {
    pub fn new(importance: u8, text: impl Into<String>) -> Item {
        Item {
            text: text.into(),
            importance,
        }
    }
}

/// The items joined by `separator`, dropping the least important ones (the later first among
/// equals) until the line fits `width`; the order of the kept items is kept. Never cuts an
/// item: if even the most important alone is too wide, it is the only one kept.
pub fn fit_items(items: &[Item], separator: &str, width: usize) -> String {
    let joined: Vec<(&Item, &str)> = items.iter().map(|item| (item, separator)).collect();
    fit_joined(&joined, width)
}

/// As [`fit_items`], each item with the separator that goes before it (when an item before
/// it is kept).
pub fn fit_joined(items: &[(&Item, &str)], width: usize) -> String {
    let mut kept: Vec<(&Item, &str)> = items.to_vec();
    loop {
        let mut line = String::new();
        for (i, (item, separator)) in kept.iter().enumerate() {
            if i > 0 {
                line.push_str(separator);
            }
            line.push_str(&item.text);
        }
        if line.chars().count() <= width || kept.len() <= 1 {
            return line;
        }
        // Drop the least important item, the last of them if several (`max_by_key` returns
        // the last maximum).
        let (drop, _) = kept
            .iter()
            .enumerate()
            .max_by_key(|(_, (item, _))| item.importance)
            .expect("at least two items");
        kept.remove(drop);
    }
}

/// `text` cut to `width` characters at a word boundary, ending in `…` when cut (a single word
/// wider than the line is cut inside it only then).
pub fn cut_at_word(text: &str, width: usize) -> String {
    if text.chars().count() <= width {
        return text.to_string();
    }
    let room = width.saturating_sub(1);
    let mut cut: String = text.chars().take(room).collect();
    let next_is_space = text.chars().nth(room).is_some_and(char::is_whitespace);
    if !next_is_space && let Some(space) = cut.rfind(' ') {
        cut.truncate(space);
    }
    let mut cut = cut
        .trim_end()
        .trim_end_matches(['·', '|'])
        .trim_end()
        .to_string();
    cut.push('…');
    cut
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_first_row_ends_at_a_word_and_the_rest_keeps_every_character() {
        assert_eq!(first_row("short", 10), ("short".to_string(), ""));
        assert_eq!(
            first_row("figure not written: a/b.svg (no files)", 20),
            ("figure not written:".to_string(), "a/b.svg (no files)")
        );
        // A word longer than the row: cut at the width, nothing added.
        let path = "/tmp/a-very-long-directory-name/recording.cast";
        let (row, rest) = first_row(path, 16);
        assert_eq!(row.chars().count(), 16);
        assert_eq!(format!("{row}{rest}"), path);
        // Multibyte characters count as one column each.
        assert_eq!(first_row("ε ε ε ε", 3), ("ε ε".to_string(), "ε ε"));
    }

    #[test]
    fn wrapping_keeps_every_word_whole() {
        let text = "A is not positive definite in floating point at n = 200000 (first at node \
                    78137 of 200000): rounding has destroyed the stiffness matrix and this \
                    result means nothing";
        for width in 1..=120 {
            let lines = wrap_words(text, width);
            assert!(lines.iter().all(|l| l.chars().count() <= width), "{width}");
            let joined: Vec<&str> = lines.iter().flat_map(|l| l.split(' ')).collect();
            if width >= 12 {
                // Every word whole ("positive" is the longest), in order.
                assert_eq!(
                    joined,
                    text.split_whitespace().collect::<Vec<_>>(),
                    "{width}"
                );
            }
            assert_eq!(
                lines.concat().replace(' ', ""),
                text.replace(' ', ""),
                "{width}"
            );
        }
        assert_eq!(wrap_words("", 10), vec![String::new()]);
    }

    #[test]
    fn cutting_at_a_word_ends_in_an_ellipsis_and_never_splits_a_word() {
        assert_eq!(cut_at_word("short", 10), "short");
        assert_eq!(cut_at_word("the quick brown fox", 12), "the quick…");
        assert_eq!(cut_at_word("the quick brown fox", 10), "the quick…");
        assert_eq!(cut_at_word("a · b · c", 6), "a · b…");
        assert_eq!(cut_at_word("unbreakable", 5), "unbr…");
        for width in 1..30 {
            let cut = cut_at_word("one two three four five six", width);
            assert!(cut.chars().count() <= width.max(1), "{cut:?} at {width}");
        }
    }

    #[test]
    fn fitting_drops_the_least_important_items_whole() {
        let items = [
            Item::new(0, "dual"),
            Item::new(1, "n = 20"),
            Item::new(3, "(N = 38)"),
            Item::new(2, "error 6.1e-14 vs closed form"),
            Item::new(2, "KKT 2.0e-16"),
        ];
        let full = fit_items(&items, " · ", 200);
        assert_eq!(
            full,
            "dual · n = 20 · (N = 38) · error 6.1e-14 vs closed form · KKT 2.0e-16"
        );
        assert_eq!(
            fit_items(&items, " · ", full.chars().count() - 1),
            "dual · n = 20 · error 6.1e-14 vs closed form · KKT 2.0e-16"
        );
        assert_eq!(
            fit_items(&items, " · ", 50),
            "dual · n = 20 · error 6.1e-14 vs closed form"
        );
        assert_eq!(fit_items(&items, " · ", 3), "dual");
        for width in 0..100 {
            let line = fit_items(&items, " · ", width);
            // Whole items only.
            for part in line.split(" · ") {
                assert!(items.iter().any(|i| i.text == part), "{width}: {part}");
            }
        }
    }
}
