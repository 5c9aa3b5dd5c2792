//! Keys: what the terminal reports (decoded by `tui::input::decode`) and what
//! `beamfric render --keys` names, with the labels the help and the hints show them by.

/// A key as the terminal reports it, or as `render --keys` names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Key {
    Up,
    Down,
    Left,
    Right,
    ShiftLeft,
    ShiftRight,
    Enter,
    Esc,
    Tab,
    BackTab,
    Backspace,
    Home,
    End,
    PageUp,
    PageDown,
    /// A printable character.
    Char(char),
    /// A letter with Ctrl held: never the plain letter.
    Ctrl(char),
}

impl Key {
    /// The name of a key in `render --keys` and in the help, or `None` for a plain character.
    fn name(self) -> Option<&'static str> {
        Some(match self {
            Key::Up => "Up",
            Key::Down => "Down",
            Key::Left => "Left",
            Key::Right => "Right",
            Key::ShiftLeft => "S-Left",
            Key::ShiftRight => "S-Right",
            Key::Enter => "Enter",
            Key::Esc => "Esc",
            Key::Tab => "Tab",
            Key::BackTab => "BackTab",
            Key::Backspace => "Backspace",
            Key::Home => "Home",
            Key::End => "End",
            Key::PageUp => "PgUp",
            Key::PageDown => "PgDn",
            Key::Char(' ') => "Space",
            Key::Char(_) | Key::Ctrl(_) => return None,
        })
    }

    /// How the help and the hints show the key: arrows as arrows, or as words in ASCII.
    pub fn label(self, ascii: bool) -> String {
        match (self, ascii) {
            (Key::Up, false) => "↑".into(),
            (Key::Down, false) => "↓".into(),
            (Key::Left, false) => "←".into(),
            (Key::Right, false) => "→".into(),
            (Key::ShiftLeft, false) => "Shift+←".into(),
            (Key::ShiftRight, false) => "Shift+→".into(),
            (Key::ShiftLeft, true) => "Shift+Left".into(),
            (Key::ShiftRight, true) => "Shift+Right".into(),
            (Key::Ctrl(c), _) => format!("Ctrl-{}", c.to_ascii_uppercase()),
            (Key::Char(' '), _) => "Space".into(),
            (Key::Char(c), _) => c.to_string(),
            (key, _) => key.name().unwrap_or_default().to_string(),
        }
    }

    pub(super) fn is_arrow(self) -> bool {
        matches!(self, Key::Up | Key::Down | Key::Left | Key::Right)
    }

    pub(super) fn is_shifted_arrow(self) -> bool {
        matches!(self, Key::ShiftLeft | Key::ShiftRight)
    }
}

/// The keys `--keys` names by a word (every other key is a single character, or `C-x`).
const NAMED: [Key; 16] = [
    Key::Up,
    Key::Down,
    Key::Left,
    Key::Right,
    Key::ShiftLeft,
    Key::ShiftRight,
    Key::Enter,
    Key::Esc,
    Key::Tab,
    Key::BackTab,
    Key::Backspace,
    Key::Home,
    Key::End,
    Key::PageUp,
    Key::PageDown,
    Key::Char(' '),
];

/// A word of `--keys` that names no key: it is not one character, not `C-` and one character,
/// and not one of the names of [`NAMED`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownKeyName(pub String);

impl std::fmt::Display for UnknownKeyName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let names: Vec<&str> = NAMED.iter().filter_map(|k| k.name()).collect();
        write!(
            f,
            "'{}' is not a key name; the names are {}, C-x (Ctrl and a letter) and any single \
             character (type text one character at a time: 3 e 4 for 3e4)",
            self.0,
            names.join(" ")
        )
    }
}

impl std::error::Error for UnknownKeyName {}

/// Parses the key names of `--keys`: space-separated `Up`, `Down`, `Left`, `Right`, `S-Left`,
/// `S-Right`, `Enter`, `Esc`, `Tab`, `BackTab`, `Backspace`, `Home`, `End`, `PgUp`, `PgDn`,
/// `Space`, `C-x` (Ctrl and a letter) and single characters (text is typed one character at a
/// time). Any other word is an error naming it: a misspelt name (`Escape`) is never typed as
/// its letters.
pub fn parse_keys(text: &str) -> Result<Vec<Key>, UnknownKeyName> {
    text.split_whitespace().map(parse_key).collect()
}

/// One word of `--keys`.
fn parse_key(word: &str) -> Result<Key, UnknownKeyName> {
    let mut chars = word.chars();
    if let (Some(c), None) = (chars.next(), chars.next()) {
        return Ok(Key::Char(c));
    }
    if let Some(key) = NAMED.iter().find(|k| k.name() == Some(word)) {
        return Ok(*key);
    }
    let mut letter = word.strip_prefix("C-").unwrap_or_default().chars();
    match (letter.next(), letter.next()) {
        (Some(c), None) => Ok(Key::Ctrl(c)),
        _ => Err(UnknownKeyName(word.to_string())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn key_names_parse() {
        assert_eq!(
            parse_keys("Down S-Right Enter 5 e 4 Enter q C-d Home End PgUp PgDn").unwrap(),
            vec![
                Key::Down,
                Key::ShiftRight,
                Key::Enter,
                Key::Char('5'),
                Key::Char('e'),
                Key::Char('4'),
                Key::Enter,
                Key::Char('q'),
                Key::Ctrl('d'),
                Key::Home,
                Key::End,
                Key::PageUp,
                Key::PageDown,
            ]
        );
    }

    #[test]
    fn an_unknown_key_name_is_an_error_naming_it_and_the_names() {
        // Issue 22: `w Escape` typed "Escape" into the save prompt.
        let error = parse_keys("w Escape").unwrap_err();
        assert_eq!(error, UnknownKeyName("Escape".into()));
        let text = error.to_string();
        for name in ["'Escape'", "Esc", "Enter", "S-Left", "PgDn", "Space", "C-x"] {
            assert!(text.contains(name), "{name}: {text}");
        }
        for word in ["3e4", "C-", "C-ab", "esc", "S-Up"] {
            assert_eq!(parse_keys(word), Err(UnknownKeyName(word.into())));
        }
        // Single characters are typed, whatever they are.
        assert_eq!(
            parse_keys("- C é").unwrap(),
            vec![Key::Char('-'), Key::Char('C'), Key::Char('é')]
        );
    }
}
