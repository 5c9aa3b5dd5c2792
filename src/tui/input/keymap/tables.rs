//! The keymap's tables: every key of every mode, what it means there, and the words the help
//! overlay and the hint lines show for it. `tui::input::keymap` looks keys up here, and the
//! help and hints are generated from the same tables, so they cannot name a key that does
//! something else.

use super::super::keys::Key;
use super::action::Action;

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

/// The keys of normal mode. Ctrl-C and Ctrl-Z ([`GLOBAL`]) work in every mode.
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
        Key::Char('v'),
        Action::NextPanelSet,
        "next view: the scene's panels, then how the method works: its iterations, the \
         dual's box (49), the cases of Table 1, Figure 5 in one panel, the matrices",
        "view",
        9,
    ),
    Binding {
        keys: &[
            (Key::Char('<'), Action::StepIterate(-1)),
            (Key::Char('>'), Action::StepIterate(1)),
        ],
        aliases: &[
            (Key::Char(','), Action::StepIterate(-1)),
            (Key::Char('.'), Action::StepIterate(1)),
        ],
        help: "the iterations panel: the previous / next iterate (drawn over u(x) and in the \
               dual's box)",
        hint: None,
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
    bind!(
        Key::Char('e'),
        Action::ExportFigure,
        "export the focused panel as an SVG figure (16:9, for slides)",
        "export",
        17,
    ),
    bind!(
        Key::Char('M'),
        Action::CycleMarkers,
        "curves drawn in Braille, half blocks, quadrants, sextants, blocks, ASCII",
        "markers",
        19,
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
        "every warning in full, most serious first (↑↓ PgUp PgDn scroll, any other key closes)",
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

/// The keys of a served session that follows a presenter (`tui::update::follow` takes them
/// before [`NORMAL`]); its help and hint line list them after and among those of [`NORMAL`].
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

/// The keys of a presenter's explorer, taken before [`NORMAL`] as [`FOLLOW`] is for a
/// student: how students join (`beamfric present`) and the list of students.
pub const PRESENTING: &[Binding] = &[
    bind!(
        Key::Char('J'),
        Action::ShowJoin,
        "join: the address, the host key's fingerprint and how students log in",
        "join",
        1,
    ),
    bind!(
        Key::Char('S'),
        Action::ShowStudents,
        "students: who follows, who explores, idle, unsaved; bring everyone back; a message to all",
        "students",
        2,
    ),
];

/// The keys of an explorer with a lesson (`--lesson FILE`), taken before [`NORMAL`] in normal
/// mode: the next and the previous step.
pub const LESSON: &[Binding] = &[
    Binding {
        keys: &[
            (Key::Char(' '), Action::NextStep),
            (Key::Char('n'), Action::NextStep),
        ],
        aliases: &[],
        help: "lesson: the next step",
        hint: Some(Hint {
            keys: &[Key::Char(' ')],
            word: "next",
            order: 1,
        }),
    },
    Binding {
        keys: &[
            (Key::Backspace, Action::PreviousStep),
            (Key::Char('N'), Action::PreviousStep),
        ],
        aliases: &[],
        help: "lesson: the step before (your changes to a step are kept for when you come back)",
        hint: Some(Hint {
            keys: &[Key::Char('N')],
            word: "back",
            order: 2,
        }),
    },
];

/// Keys of every mode, looked up before the mode's own: Ctrl-C quits from anywhere (asking
/// first when that loses changes; the help lists it on [`NORMAL`]'s quit line), Ctrl-Z
/// suspends (the shell's `fg` resumes; a served session says it cannot).
pub const GLOBAL: &[Binding] = &[
    Binding {
        keys: &[(Key::Ctrl('c'), Action::Interrupt)],
        aliases: &[],
        help: "",
        hint: None,
    },
    Binding {
        keys: &[(Key::Ctrl('z'), Action::Suspend)],
        aliases: &[],
        help: "suspend to the shell (fg resumes; not in a served session)",
        hint: None,
    },
];

/// A binding the help does not list (the keys of prompts, lists and questions, which their
/// own hint lines name).
macro_rules! keys {
    ($($key:expr => $action:expr),+ $(,)?) => {
        Binding {
            keys: &[$(($key, $action)),+],
            aliases: &[],
            help: "",
            hint: None,
        }
    };
}

/// The help and the warnings view: ↑ ↓ (and k j) scroll, PgUp PgDn by a page; any other key
/// closes.
pub const SCROLLING: &[Binding] = &[keys![
    Key::Up => Action::SelectPrevious,
    Key::Down => Action::SelectNext,
    Key::Char('k') => Action::SelectPrevious,
    Key::Char('j') => Action::SelectNext,
    Key::PageUp => Action::PageUp,
    Key::PageDown => Action::PageDown,
]];

/// A one-line prompt (a value, a file name): characters are typed; these keys edit.
pub const PROMPT: &[Binding] = &[keys![
    Key::Backspace => Action::DeleteChar,
    Key::Left => Action::CursorLeft,
    Key::Right => Action::CursorRight,
    Key::Home => Action::CursorHome,
    Key::Ctrl('a') => Action::CursorHome,
    Key::End => Action::CursorEnd,
    Key::Ctrl('e') => Action::CursorEnd,
    Key::Ctrl('u') => Action::EraseToStart,
    Key::Enter => Action::Confirm,
    Key::Esc => Action::Cancel,
]];

/// The preset picker: typing searches, so only keys that are not text move through the list.
pub const PICKER: &[Binding] = &[keys![
    Key::Up => Action::SelectPrevious,
    Key::Down => Action::SelectNext,
    Key::PageUp => Action::PageUp,
    Key::PageDown => Action::PageDown,
    Key::Home => Action::SelectFirst,
    Key::End => Action::SelectLast,
    Key::Backspace => Action::DeleteChar,
    Key::Enter => Action::Confirm,
    Key::Esc => Action::Cancel,
]];

/// "The file exists: overwrite it?": y says yes, any other key no.
pub const OVERWRITE_QUESTION: &[Binding] = &[keys![
    Key::Char('y') => Action::Confirm,
    Key::Char('Y') => Action::Confirm,
]];

/// "End the class?" (the lecturer's quit with students connected): y says yes, any other
/// key no.
pub const END_CLASS_QUESTION: &[Binding] = &[keys![
    Key::Char('y') => Action::Confirm,
    Key::Char('Y') => Action::Confirm,
]];

/// "Lose the unsaved changes?": y says yes, s saves first, any other key no.
pub const DISCARD_QUESTION: &[Binding] = &[keys![
    Key::Char('y') => Action::Confirm,
    Key::Char('Y') => Action::Confirm,
    Key::Char('s') => Action::Save,
]];

/// The list of students: ↑ ↓ (k j) and PgUp PgDn scroll, `b` brings everyone back to
/// follow, `m` writes a line to all; any other key closes it.
pub const STUDENTS: &[Binding] = &[keys![
    Key::Up => Action::SelectPrevious,
    Key::Down => Action::SelectNext,
    Key::Char('k') => Action::SelectPrevious,
    Key::Char('j') => Action::SelectNext,
    Key::PageUp => Action::PageUp,
    Key::PageDown => Action::PageDown,
    Key::Char('b') => Action::BringEveryoneBack,
    Key::Char('m') => Action::WriteBroadcast,
]];
