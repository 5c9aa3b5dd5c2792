//! What a keystroke means. Terminal key events and the key names of `beamfric render --keys`
//! both become [`Action`]s, so the interactive and headless explorers share one update path.

use crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers};

/// Something the user asked for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Action {
    /// Previous row (↑, k) or entry.
    Up,
    /// Next row (↓, j) or entry.
    Down,
    /// Change the selected value one step down; `coarse` for Shift or `[`.
    Decrease {
        coarse: bool,
    },
    /// One step up; `coarse` for Shift or `]`.
    Increase {
        coarse: bool,
    },
    /// Type an exact value / confirm.
    Enter,
    /// Leave an overlay or prompt; in normal mode, quit.
    Escape,
    /// A typed character (in prompts), or a command key in normal mode.
    Char(char),
    Backspace,
    /// Cycle the panel shown when only one fits.
    NextPanel,
    /// Ctrl-C: quit from anywhere.
    Interrupt,
    /// The terminal changed size.
    Resize(u16, u16),
}

/// The action of a terminal key event, if any (key releases are ignored).
pub fn from_key(event: KeyEvent) -> Option<Action> {
    if event.kind == KeyEventKind::Release {
        return None;
    }
    let shift = event.modifiers.contains(KeyModifiers::SHIFT);
    let ctrl = event.modifiers.contains(KeyModifiers::CONTROL);
    Some(match event.code {
        KeyCode::Char('c') if ctrl => Action::Interrupt,
        KeyCode::Up => Action::Up,
        KeyCode::Down => Action::Down,
        KeyCode::Left => Action::Decrease { coarse: shift },
        KeyCode::Right => Action::Increase { coarse: shift },
        KeyCode::Enter => Action::Enter,
        KeyCode::Esc => Action::Escape,
        KeyCode::Backspace => Action::Backspace,
        KeyCode::Tab | KeyCode::BackTab => Action::NextPanel,
        KeyCode::Char(c) => Action::Char(c),
        _ => return None,
    })
}

/// Parses the key names of `--keys`: space-separated `Up`, `Down`, `Left`, `Right`, `S-Left`,
/// `S-Right`, `Enter`, `Esc`, `Tab`, `Backspace`, `Space`, `C-c`, single characters, and
/// any other word as the characters typed (e.g. a value after `Enter`).
pub fn parse_keys(text: &str) -> Vec<Action> {
    let mut actions = Vec::new();
    for word in text.split_whitespace() {
        let action = match word {
            "Up" => Action::Up,
            "Down" => Action::Down,
            "Left" => Action::Decrease { coarse: false },
            "Right" => Action::Increase { coarse: false },
            "S-Left" => Action::Decrease { coarse: true },
            "S-Right" => Action::Increase { coarse: true },
            "Enter" => Action::Enter,
            "Esc" => Action::Escape,
            "Tab" => Action::NextPanel,
            "Backspace" => Action::Backspace,
            "Space" => Action::Char(' '),
            "C-c" => Action::Interrupt,
            _ => {
                actions.extend(word.chars().map(Action::Char));
                continue;
            }
        };
        actions.push(action);
    }
    actions
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn key_names_parse() {
        assert_eq!(
            parse_keys("Down S-Right Enter 5e4 Enter q"),
            vec![
                Action::Down,
                Action::Increase { coarse: true },
                Action::Enter,
                Action::Char('5'),
                Action::Char('e'),
                Action::Char('4'),
                Action::Enter,
                Action::Char('q'),
            ]
        );
        let shifted = KeyEvent::new(KeyCode::Right, KeyModifiers::SHIFT);
        assert_eq!(from_key(shifted), Some(Action::Increase { coarse: true }));
        let ctrl_c = KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL);
        assert_eq!(from_key(ctrl_c), Some(Action::Interrupt));
    }
}
