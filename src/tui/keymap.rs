//! The one keymap: every key of the explorer, what it means in each mode, and the words the
//! help overlay and the hint line show for it. Terminal input (decoded by `tui::input`) and
//! the key names of `beamfric render --keys` both become [`Key`]s; [`action_for`] turns a key
//! into the [`Action`] it means in the current mode, from the table [`NORMAL`] in normal mode. The help
//! ([`help_lines`]) and the hints ([`hint_line`]) are generated from the same table, so they
//! cannot promise a key that does nothing.

use super::app::Mode;

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

/// What the user asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// Previous parameter row, or previous entry of a list.
    SelectPrevious,
    /// Next parameter row, or next entry of a list.
    SelectNext,
    /// The first row or entry (`g`, Home).
    SelectFirst,
    /// The last row or entry (`G`, End).
    SelectLast,
    /// A page up (PgUp).
    PageUp,
    /// A page down (PgDn).
    PageDown,
    /// The focused panel fills the screen, or back.
    ToggleZoom,
    /// A mouse button pressed at column `x`, row `y` (0-based); `double` when it is the second
    /// press at that cell within [`super::mouse::DOUBLE_CLICK`].
    Click {
        x: u16,
        y: u16,
        double: bool,
    },
    /// The mouse moved to `x`, `y` with a button held.
    Drag {
        x: u16,
        y: u16,
    },
    /// The mouse button was let go at `x`, `y`.
    Release {
        x: u16,
        y: u16,
    },
    /// The wheel turned over `x`, `y`: `up` away from the user.
    Scroll {
        x: u16,
        y: u16,
        up: bool,
    },
    /// Change the selected value one step down; `coarse` for a coarse step.
    Decrease {
        coarse: bool,
    },
    /// One step up.
    Increase {
        coarse: bool,
    },
    /// Type an exact value for the selected row.
    EditValue,
    AddObstacle,
    DeleteObstacle,
    NextMethod,
    PickPreset,
    Save,
    /// Back to the scene as loaded.
    Reset,
    /// Deflection, bending moment, shear.
    NextDiagram,
    /// The next panel when one is shown at a time.
    NextPanel,
    ToggleTimings,
    /// The deflection panel: u and the reference u_ref, or the difference u − u_ref.
    ToggleDifference,
    /// The next colour palette (dark, light, high contrast).
    CycleTheme,
    ShowHelp,
    /// Every warning of the solution shown, in full.
    ShowWarnings,
    /// Take back the last change of the scene.
    Undo,
    /// Do again what was undone.
    Redo,
    Quit,
    /// Ctrl-C: quit from anywhere.
    Interrupt,
    /// Ctrl-Z: suspend (the shell's `fg` resumes).
    Suspend,
    /// A character typed into a prompt.
    Type(char),
    /// Delete the character before a prompt's cursor.
    DeleteChar,
    /// Move a prompt's cursor one character left.
    CursorLeft,
    /// One character right.
    CursorRight,
    /// To the start of the prompt.
    CursorHome,
    /// To its end.
    CursorEnd,
    /// Erase the prompt's text before the cursor (Ctrl-U).
    EraseToStart,
    /// Accept a prompt, a list entry or a question.
    Confirm,
    /// Leave a prompt, an overlay or a question without doing anything.
    Cancel,
    /// A key that means nothing in normal mode (its name goes into the message).
    Unbound(Key),
    /// Text pasted where no prompt takes it: ignored, never run as commands.
    PasteIgnored,
    /// The terminal changed size.
    Resize(u16, u16),
    /// Follow mode: leave the presenter, exploring on from the current state.
    Fork,
    /// Follow mode: follow the presenter again.
    Rejoin,
}

/// One line of the help: keys and what each does, the words, and the key hint if any.
pub struct Binding {
    /// The keys the help lists, each with its action, in the order listed.
    pub keys: &'static [(Key, Action)],
    /// Keys that do the same without being listed.
    pub aliases: &'static [(Key, Action)],
    /// What the keys do, in words.
    pub help: &'static str,
    pub hint: Option<Hint>,
}

/// A binding's entry in the hint line.
pub struct Hint {
    /// The keys the hint names (a subset of the binding's keys).
    pub keys: &'static [Key],
    pub word: &'static str,
    /// Position in the hint line (the most useful first).
    pub order: u8,
}

/// A binding of one key whose hint names the same key.
macro_rules! bind {
    ($key:expr, $action:expr, $help:expr, $word:expr, $order:expr $(,)?) => {
        Binding {
            keys: &[($key, $action)],
            aliases: &[],
            help: $help,
            hint: Some(Hint {
                keys: &[$key],
                word: $word,
                order: $order,
            }),
        }
    };
}

const FINE: bool = false;
const COARSE: bool = true;

/// The keys of normal mode. Ctrl-C ([`Action::Interrupt`]) works in every mode.
pub const NORMAL: &[Binding] = &[
    Binding {
        keys: &[
            (Key::Up, Action::SelectPrevious),
            (Key::Down, Action::SelectNext),
            (Key::Char('k'), Action::SelectPrevious),
            (Key::Char('j'), Action::SelectNext),
        ],
        aliases: &[],
        help: "select a parameter",
        hint: Some(Hint {
            keys: &[Key::Up, Key::Down],
            word: "select",
            order: 2,
        }),
    },
    Binding {
        keys: &[
            (Key::Char('g'), Action::SelectFirst),
            (Key::Char('G'), Action::SelectLast),
            (Key::Home, Action::SelectFirst),
            (Key::End, Action::SelectLast),
        ],
        aliases: &[],
        help: "first / last parameter (Home End in lists too)",
        hint: None,
    },
    Binding {
        keys: &[
            (Key::PageUp, Action::PageUp),
            (Key::PageDown, Action::PageDown),
        ],
        aliases: &[],
        help: "a page up / down (in lists too)",
        hint: None,
    },
    Binding {
        keys: &[
            (Key::Left, Action::Decrease { coarse: FINE }),
            (Key::Right, Action::Increase { coarse: FINE }),
            (Key::Char('h'), Action::Decrease { coarse: FINE }),
            (Key::Char('l'), Action::Increase { coarse: FINE }),
        ],
        aliases: &[],
        help: "change it by a fine step",
        hint: Some(Hint {
            keys: &[Key::Left, Key::Right],
            word: "change",
            order: 3,
        }),
    },
    Binding {
        keys: &[
            (Key::ShiftLeft, Action::Decrease { coarse: COARSE }),
            (Key::ShiftRight, Action::Increase { coarse: COARSE }),
            (Key::Char('['), Action::Decrease { coarse: COARSE }),
            (Key::Char(']'), Action::Increase { coarse: COARSE }),
        ],
        aliases: &[],
        help: "change it by a coarse step",
        hint: Some(Hint {
            keys: &[Key::Char('['), Key::Char(']')],
            word: "coarse",
            order: 10,
        }),
    },
    bind!(
        Key::Enter,
        Action::EditValue,
        "type an exact value (Enter sets, Esc cancels)",
        "type",
        4,
    ),
    bind!(
        Key::Char('a'),
        Action::AddObstacle,
        "add an obstacle in the widest gap",
        "add",
        11,
    ),
    bind!(
        Key::Char('d'),
        Action::DeleteObstacle,
        "delete the selected obstacle",
        "delete",
        12,
    ),
    bind!(
        Key::Char('m'),
        Action::NextMethod,
        "cycle the method",
        "method",
        5
    ),
    bind!(
        Key::Char('p'),
        Action::PickPreset,
        "pick a preset",
        "preset",
        7
    ),
    bind!(
        Key::Char('s'),
        Action::Save,
        "save the scene to a TOML file",
        "save",
        13,
    ),
    bind!(
        Key::Char('r'),
        Action::Reset,
        "reset to the scene as loaded",
        "reset",
        15,
    ),
    bind!(
        Key::Char('b'),
        Action::NextDiagram,
        "deflection, bending moment, shear",
        "diagram",
        9,
    ),
    Binding {
        keys: &[(Key::Tab, Action::NextPanel)],
        aliases: &[(Key::BackTab, Action::NextPanel)],
        help: "next panel (when one is shown at a time)",
        hint: Some(Hint {
            keys: &[Key::Tab],
            word: "panel",
            order: 8,
        }),
    },
    bind!(
        Key::Char('z'),
        Action::ToggleZoom,
        "zoom the focused panel, or back (or double-click it)",
        "zoom",
        17,
    ),
    bind!(
        Key::Char('t'),
        Action::ToggleTimings,
        "show or hide run times",
        "time",
        16,
    ),
    bind!(
        Key::Char('c'),
        Action::ToggleDifference,
        "deflection: the reference curve, or u - u_ref alone",
        "compare",
        17,
    ),
    bind!(
        Key::Char('T'),
        Action::CycleTheme,
        "colour theme: dark, light, high-contrast",
        "theme",
        18,
    ),
    Binding {
        keys: &[
            (Key::Char('u'), Action::Undo),
            (Key::Ctrl('r'), Action::Redo),
        ],
        aliases: &[],
        help: "undo the last change / redo it",
        hint: Some(Hint {
            keys: &[Key::Char('u')],
            word: "undo",
            order: 14,
        }),
    },
    bind!(Key::Char('?'), Action::ShowHelp, "this help", "help", 0),
    bind!(
        Key::Char('w'),
        Action::ShowWarnings,
        "every warning in full, most serious first (↑↓ scroll, any other key closes)",
        "warnings",
        6,
    ),
    Binding {
        keys: &[
            (Key::Char('q'), Action::Quit),
            (Key::Ctrl('c'), Action::Interrupt),
        ],
        aliases: &[],
        help: "quit (asks first when there are unsaved changes; Ctrl-C twice forces)",
        hint: Some(Hint {
            keys: &[Key::Char('q')],
            word: "quit",
            order: 1,
        }),
    },
];

/// The keys of a served session that follows a presenter (`tui::follow` takes them before
/// [`NORMAL`]); its help and hint line list them after and among those of [`NORMAL`].
pub const FOLLOW: &[Binding] = &[
    bind!(
        Key::Char('f'),
        Action::Fork,
        "fork: explore on your own from the presenter's state",
        "fork",
        1,
    ),
    bind!(
        Key::Char('F'),
        Action::Rejoin,
        "follow the presenter again",
        "rejoin",
        1,
    ),
];

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

    fn is_arrow(self) -> bool {
        matches!(self, Key::Up | Key::Down | Key::Left | Key::Right)
    }

    fn is_shifted_arrow(self) -> bool {
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

/// The action `key` stands for in `mode`, if any.
pub fn action_for(mode: &Mode, key: Key) -> Option<Action> {
    match key {
        Key::Ctrl('c') => return Some(Action::Interrupt),
        Key::Ctrl('z') => return Some(Action::Suspend),
        _ => {}
    }
    match mode {
        Mode::Normal => Some(normal_action(key).unwrap_or(Action::Unbound(key))),
        Mode::SceneText => Some(Action::Cancel),
        Mode::Help { .. } | Mode::Warnings { .. } => match key {
            Key::Up | Key::Char('k') => Some(Action::SelectPrevious),
            Key::Down | Key::Char('j') => Some(Action::SelectNext),
            _ => Some(Action::Cancel),
        },
        Mode::Editing { .. } | Mode::Save { .. } => match key {
            Key::Char(c) => Some(Action::Type(c)),
            Key::Backspace => Some(Action::DeleteChar),
            Key::Left => Some(Action::CursorLeft),
            Key::Right => Some(Action::CursorRight),
            Key::Ctrl('a') | Key::Home => Some(Action::CursorHome),
            Key::Ctrl('e') | Key::End => Some(Action::CursorEnd),
            Key::Ctrl('u') => Some(Action::EraseToStart),
            Key::Enter => Some(Action::Confirm),
            Key::Esc => Some(Action::Cancel),
            _ => None,
        },
        // Typing searches, so only keys that are not text move through the list.
        Mode::Presets(_) => match key {
            Key::Up => Some(Action::SelectPrevious),
            Key::Down => Some(Action::SelectNext),
            Key::Home => Some(Action::SelectFirst),
            Key::End => Some(Action::SelectLast),
            Key::PageUp => Some(Action::PageUp),
            Key::PageDown => Some(Action::PageDown),
            Key::Char(c) => Some(Action::Type(c)),
            Key::Backspace => Some(Action::DeleteChar),
            Key::Enter => Some(Action::Confirm),
            Key::Esc => Some(Action::Cancel),
            _ => None,
        },
        Mode::ConfirmOverwrite { .. } => match key {
            Key::Char('y' | 'Y') => Some(Action::Confirm),
            _ => Some(Action::Cancel),
        },
        Mode::ConfirmDiscard { .. } => match key {
            Key::Char('y' | 'Y') => Some(Action::Confirm),
            Key::Char('s') => Some(Action::Save),
            _ => Some(Action::Cancel),
        },
    }
}

/// What a bracketed paste means in `mode`: its printable characters typed into a prompt
/// (a pasted newline does not submit it), or, anywhere else, nothing but a note.
pub fn paste_actions(mode: &Mode, text: &str) -> Vec<Action> {
    match mode {
        Mode::Editing { .. } | Mode::Save { .. } | Mode::Presets(_) => text
            .chars()
            .filter(|c| !c.is_control())
            .map(Action::Type)
            .collect(),
        _ => vec![Action::PasteIgnored],
    }
}

/// The action of a key in normal mode, from [`NORMAL`].
fn normal_action(key: Key) -> Option<Action> {
    NORMAL
        .iter()
        .flat_map(|b| b.keys.iter().chain(b.aliases))
        .find(|(k, _)| *k == key)
        .map(|(_, action)| *action)
}

/// Joins key labels the way the help writes them: keys of one family (arrows, shifted arrows,
/// characters) separated by a space, families by two; shifted arrows share one `Shift+`.
fn help_label(keys: &[Key], ascii: bool) -> String {
    let family = |k: Key| {
        if k.is_arrow() {
            0
        } else if k.is_shifted_arrow() {
            1
        } else if matches!(k, Key::Char(_)) {
            2
        } else {
            3
        }
    };
    let mut out = String::new();
    for (i, key) in keys.iter().enumerate() {
        let label = key.label(ascii);
        match i.checked_sub(1).map(|p| keys[p]) {
            None => out.push_str(&label),
            Some(previous) if family(previous) == family(*key) && family(*key) != 3 => {
                out.push(' ');
                let shared = if key.is_shifted_arrow() {
                    label.trim_start_matches("Shift+").to_string()
                } else {
                    label
                };
                out.push_str(&shared);
            }
            Some(_) => {
                out.push_str("  ");
                out.push_str(&label);
            }
        }
    }
    out
}

/// The help's lines: (keys, what they do), from [`NORMAL`].
pub fn help_lines(ascii: bool) -> Vec<(String, &'static str)> {
    help_lines_with(ascii, &[])
}

/// The help's lines of [`NORMAL`] and then of `extra` (e.g. [`FOLLOW`]).
pub fn help_lines_with(ascii: bool, extra: &[Binding]) -> Vec<(String, &'static str)> {
    NORMAL
        .iter()
        .chain(extra)
        .map(|b| {
            let keys: Vec<Key> = b.keys.iter().map(|(k, _)| *k).collect();
            (help_label(&keys, ascii), b.help)
        })
        .collect()
}

/// The up and down arrows as the hints write them: `↑↓`, or `Up/Down` in ASCII.
pub fn up_down(ascii: bool) -> &'static str {
    if ascii { "Up/Down" } else { "↑↓" }
}

/// The hint line of normal mode, from [`NORMAL`]: `key:word` in the hints' order. Arrow pairs
/// are written together (`↑↓`, or `Up/Down` in ASCII).
pub fn hint_line(ascii: bool) -> String {
    hint_items(ascii, &[]).join(" ")
}

/// The hint line of [`NORMAL`] and `extra` (e.g. [`FOLLOW`]) together, in the hints' order.
pub fn hint_line_with(ascii: bool, extra: &[Binding]) -> String {
    hint_items(ascii, extra).join(" ")
}

/// The hint line of [`NORMAL`] and `extra` cut to `width` columns: the most useful hints
/// that fit, whole, in their order (`?:help` first, so the rest is always one key away).
pub fn fitted_hint_line(ascii: bool, extra: &[Binding], width: usize) -> String {
    let mut line = String::new();
    for item in hint_items(ascii, extra) {
        let needed = if line.is_empty() { 0 } else { 1 } + item.chars().count();
        if line.chars().count() + needed > width {
            break;
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(&item);
    }
    line
}

/// The hints of [`NORMAL`] and `extra`, most useful first, each `key:word`.
fn hint_items(ascii: bool, extra: &[Binding]) -> Vec<String> {
    let mut hints: Vec<&Hint> = NORMAL
        .iter()
        .chain(extra)
        .filter_map(|b| b.hint.as_ref())
        .collect();
    hints.sort_by_key(|h| h.order);
    hints
        .iter()
        .map(|h| {
            let all_arrows = h.keys.iter().all(|k| k.is_arrow());
            let separator = match (all_arrows, ascii) {
                (true, false) => "",
                (true, true) => "/",
                (false, _) => " ",
            };
            let keys: Vec<String> = h.keys.iter().map(|k| k.label(ascii)).collect();
            format!("{}:{}", keys.join(separator), h.word)
        })
        .collect()
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
        // Ctrl and a letter is never the letter.
        assert_eq!(
            action_for(&Mode::Normal, Key::Ctrl('d')),
            Some(Action::Unbound(Key::Ctrl('d')))
        );
        assert_eq!(
            action_for(&Mode::Normal, Key::Ctrl('c')),
            Some(Action::Interrupt)
        );
    }

    #[test]
    fn every_key_the_hints_name_is_bound_to_its_bindings_action() {
        for ascii in [false, true] {
            for binding in NORMAL {
                let Some(hint) = &binding.hint else { continue };
                for key in hint.keys {
                    let bound = binding.keys.iter().find(|(k, _)| k == key);
                    assert!(bound.is_some(), "hint key {key:?} not in its binding");
                    assert_eq!(normal_action(*key), bound.map(|(_, a)| *a));
                }
            }
            // The hint line names no key the table lacks: in ASCII no arrow glyphs at all.
            if ascii {
                assert!(hint_line(true).is_ascii(), "{}", hint_line(true));
            }
        }
    }

    #[test]
    fn the_follow_keys_are_listed_only_where_asked_and_bound_nowhere_else() {
        assert!(!hint_line(false).contains("fork"));
        assert!(
            hint_line_with(false, FOLLOW).starts_with("?:help q:quit f:fork F:rejoin ↑↓:select"),
            "{}",
            hint_line_with(false, FOLLOW)
        );
        let help = help_lines_with(true, FOLLOW);
        assert_eq!(help.len(), NORMAL.len() + 2);
        assert_eq!(help[NORMAL.len()].0, "f");
        assert_eq!(help[NORMAL.len() + 1].0, "F");
        // f and F mean nothing in normal mode itself: follow mode takes them first.
        for binding in FOLLOW {
            for (key, _) in binding.keys {
                assert_eq!(normal_action(*key), None, "{key:?}");
            }
        }
    }

    #[test]
    fn no_key_is_bound_twice_in_normal_mode() {
        let keys: Vec<Key> = NORMAL
            .iter()
            .flat_map(|b| b.keys.iter().chain(b.aliases))
            .map(|(k, _)| *k)
            .collect();
        for (i, key) in keys.iter().enumerate() {
            assert!(!keys[i + 1..].contains(key), "{key:?} bound twice");
        }
    }

    #[test]
    fn the_help_lists_every_binding_as_before() {
        let lines = help_lines(false);
        assert_eq!(lines[0].0, "↑ ↓  k j");
        assert_eq!(lines[1].0, "g G  Home  End");
        assert_eq!(lines[2].0, "PgUp  PgDn");
        assert_eq!(lines[4].0, "Shift+← →  [ ]");
        assert_eq!(lines.last().unwrap().0, "q  Ctrl-C");
        assert_eq!(help_lines(true)[0].0, "Up Down  k j");
        assert_eq!(
            hint_line(false),
            "?:help q:quit ↑↓:select ←→:change Enter:type m:method w:warnings p:preset \
             Tab:panel b:diagram [ ]:coarse a:add d:delete s:save u:undo r:reset t:time z:zoom c:compare T:theme"
        );
    }

    #[test]
    fn the_fitted_hint_line_keeps_whole_hints_in_order() {
        for ascii in [false, true] {
            let full = hint_line(ascii);
            for width in 0..=full.chars().count() + 5 {
                let fitted = fitted_hint_line(ascii, &[], width);
                assert!(fitted.chars().count() <= width, "{width}: {fitted}");
                // A prefix of the full line, ending at a whole hint.
                assert!(full.starts_with(&fitted), "{width}: {fitted}");
                let rest = &full[fitted.len()..];
                assert!(
                    fitted.is_empty() || rest.is_empty() || rest.starts_with(' '),
                    "{width}: {fitted}"
                );
            }
            assert!(fitted_hint_line(ascii, &[], 80).starts_with("?:help q:quit"));
            assert!(fitted_hint_line(ascii, &[], 80).contains(":warnings"));
        }
    }
}
