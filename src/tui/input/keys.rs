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

/// Parses the key names of `--keys`: space-separated `Up`, `Down`, `Left`, `Right`, `S-Left`,
/// `S-Right`, `Enter`, `Esc`, `Tab`, `BackTab`, `Backspace`, `Home`, `End`, `PgUp`, `PgDn`,
/// `Space`, `C-x` (Ctrl and a letter), single characters, and any other word as the characters
/// typed (e.g. a value after `Enter`).
pub fn parse_keys(text: &str) -> Vec<Key> {
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
    let mut keys = Vec::new();
    for word in text.split_whitespace() {
        if let Some(key) = NAMED.iter().find(|k| k.name() == Some(word)) {
            keys.push(*key);
        } else if let Some(letter) = word.strip_prefix("C-").filter(|l| l.chars().count() == 1) {
            keys.push(Key::Ctrl(letter.chars().next().unwrap_or('c')));
        } else {
            keys.extend(word.chars().map(Key::Char));
        }
    }
    keys
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn key_names_parse() {
        assert_eq!(
            parse_keys("Down S-Right Enter 5e4 Enter q C-d Home End PgUp PgDn"),
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
}
