//! The one keymap: every key of the explorer, what it means in each mode, and the words the
//! help overlay and the hint lines show for it. Terminal input (decoded by
//! `tui::input::decode`) and the key names of `beamfric render --keys` both become [`Key`]s;
//! [`action_for`] turns a key into the [`Action`] it means in the current mode, from the
//! tables of [`tables`] ([`GLOBAL`] first, then the mode's own, then what the mode does with
//! any other key). The help and the hints ([`help`]) are generated from the same tables, so
//! they cannot promise a key that does nothing.

mod action;
pub mod help;
pub mod tables;

pub use super::keys::{Key, parse_keys};
pub use action::Action;
pub use help::{
    fitted_hint_line, fitted_hint_line_of, help_lines, help_lines_with, hint_line, hint_line_with,
    up_down,
};
pub use tables::{
    Binding, DISCARD_QUESTION, END_CLASS_QUESTION, FOLLOW, GLOBAL, Hint, LESSON, NORMAL,
    OVERWRITE_QUESTION, PICKER, PRESENTING, PROMPT, SCROLLING, STUDENTS,
};

use super::super::state::{App, Mode};

/// What a mode does with a key its table does not bind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Otherwise {
    /// Nothing, with a note naming the key (normal mode).
    Unbound,
    /// Closes what is open or says no.
    Cancel,
    /// A character is typed; other keys do nothing.
    Type,
}

/// A mode's table and what it does with any other key.
fn keys_of(mode: &Mode) -> (&'static [Binding], Otherwise) {
    match mode {
        Mode::Normal => (NORMAL, Otherwise::Unbound),
        Mode::SceneText => (&[], Otherwise::Cancel),
        Mode::Help { .. } | Mode::Warnings { .. } => (SCROLLING, Otherwise::Cancel),
        Mode::Editing { .. } | Mode::Save { .. } | Mode::Broadcast { .. } => {
            (PROMPT, Otherwise::Type)
        }
        Mode::Students { .. } => (STUDENTS, Otherwise::Cancel),
        Mode::Presets(_) => (PICKER, Otherwise::Type),
        Mode::ConfirmOverwrite { .. } => (OVERWRITE_QUESTION, Otherwise::Cancel),
        Mode::ConfirmDiscard { .. } => (DISCARD_QUESTION, Otherwise::Cancel),
        Mode::ConfirmEndClass => (END_CLASS_QUESTION, Otherwise::Cancel),
        Mode::ClassEnded { .. } | Mode::Join => (&[], Otherwise::Cancel),
    }
}

/// The action a table binds `key` to, listed or as an alias.
fn bound(table: &[Binding], key: Key) -> Option<Action> {
    table
        .iter()
        .flat_map(|b| b.keys.iter().chain(b.aliases))
        .find(|(k, _)| *k == key)
        .map(|(_, action)| *action)
}

/// The action `key` stands for in `mode`, if any.
pub fn action_for(mode: &Mode, key: Key) -> Option<Action> {
    if let Some(action) = bound(GLOBAL, key) {
        return Some(action);
    }
    let (table, otherwise) = keys_of(mode);
    bound(table, key).or(match (otherwise, key) {
        (Otherwise::Unbound, key) => Some(Action::Unbound(key)),
        (Otherwise::Cancel, _) => Some(Action::Cancel),
        (Otherwise::Type, Key::Char(c)) => Some(Action::Type(c)),
        (Otherwise::Type, _) => None,
    })
}

/// The follow-mode key `key` stands for in a student's explorer, if any (taken before the
/// mode's own keys, in normal mode).
pub fn follow_action(key: Key) -> Option<Action> {
    bound(FOLLOW, key)
}

/// The key of a lecturer's explorer `key` stands for, if any (taken before the mode's own
/// keys, in normal mode).
pub fn presenting_action(key: Key) -> Option<Action> {
    bound(PRESENTING, key)
}

/// What a bracketed paste means in `mode`: its printable characters typed into a prompt
/// (a pasted newline does not submit it), or, anywhere else, nothing but a note.
pub fn paste_actions(mode: &Mode, text: &str) -> Vec<Action> {
    match keys_of(mode).1 {
        Otherwise::Type => text
            .chars()
            .filter(|c| !c.is_control())
            .map(Action::Type)
            .collect(),
        _ => vec![Action::PasteIgnored],
    }
}

/// The key of a lesson `key` stands for, if any (taken before the mode's own keys in normal
/// mode, when the explorer has a lesson).
pub fn lesson_action(key: Key) -> Option<Action> {
    bound(LESSON, key)
}

/// The keys beyond [`NORMAL`] this explorer has, for its help and hint line: [`FOLLOW`] for a
/// student, [`PRESENTING`] for the lecturer's explorer, [`LESSON`] where a lesson is open and
/// this explorer may step it (not a student's while a presenter is connected).
pub fn extra_keys(app: &App) -> Vec<&'static [Binding]> {
    let student = app.follow.as_ref().is_some_and(|f| f.is_student());
    let steps_lesson = app
        .follow
        .as_ref()
        .is_none_or(|f| !f.is_student() || !f.presenter_here);
    let mut tables: Vec<&'static [Binding]> = Vec::new();
    if app.exploration.lesson.is_some() && steps_lesson {
        tables.push(LESSON);
    }
    match &app.follow {
        Some(_) if student => tables.push(FOLLOW),
        Some(_) => tables.push(PRESENTING),
        _ => {}
    }
    tables
}

/// May a student following the presenter do `action`? Only what changes nothing of the
/// presenter's state: help, quit, timings, and what only the student's own screen shows.
pub fn a_follower_may(action: Action) -> bool {
    matches!(
        action,
        Action::ShowHelp
            | Action::Quit
            | Action::Interrupt
            | Action::Suspend
            | Action::ToggleTimings
            | Action::ShowWarnings
            | Action::CycleTheme
            | Action::CycleMarkers
            | Action::ExportFigure
            | Action::ToggleDifference
            | Action::ToggleZoom
    )
}

/// Does `action` work in this explorer's normal mode now (for its hint line)? A following
/// student's keys are [`a_follower_may`]'s and `f`; one exploring on their own has every key
/// but `f`, and `F` while a presenter is connected.
pub fn works_now(app: &App, action: Action) -> bool {
    let Some(follow) = app.follow.as_ref().filter(|f| f.is_student()) else {
        return true;
    };
    let following = follow.is_following();
    match action {
        Action::Fork => following,
        Action::Rejoin => !following && follow.presenter_here,
        other => !following || a_follower_may(other),
    }
}

/// The action of a key in normal mode, from [`NORMAL`].
#[cfg(test)]
fn normal_action(key: Key) -> Option<Action> {
    bound(NORMAL, key)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ctrl_keys_are_never_the_letter_and_global_keys_work_in_every_mode() {
        // Ctrl and a letter is never the letter.
        assert_eq!(
            action_for(&Mode::Normal, Key::Ctrl('d')),
            Some(Action::Unbound(Key::Ctrl('d')))
        );
        assert_eq!(
            action_for(&Mode::Normal, Key::Ctrl('c')),
            Some(Action::Interrupt)
        );
        // Ctrl-C and Ctrl-Z mean the same in every mode, prompts and questions included.
        let prompt = crate::tui::state::prompt::Prompt::new("0.8", true);
        let modes = [
            Mode::Normal,
            Mode::Help { offset: 0 },
            Mode::Warnings { offset: 3 },
            Mode::SceneText,
            Mode::Presets(Default::default()),
            Mode::Save {
                prompt: prompt.clone(),
            },
            Mode::Editing {
                row: crate::tui::state::params::Row::Epsilon,
                prompt,
            },
            Mode::ConfirmOverwrite { path: "x".into() },
            Mode::ConfirmDiscard {
                then: crate::tui::state::Discard::Quit,
            },
            Mode::ConfirmEndClass,
            Mode::Students { offset: 0 },
            Mode::Broadcast {
                prompt: crate::tui::state::prompt::Prompt::new("", false),
            },
            Mode::ClassEnded {
                by: "the lecturer".into(),
                saved: None,
            },
            Mode::Join,
        ];
        for mode in &modes {
            assert_eq!(action_for(mode, Key::Ctrl('c')), Some(Action::Interrupt));
            assert_eq!(action_for(mode, Key::Ctrl('z')), Some(Action::Suspend));
        }
    }

    #[test]
    fn each_mode_does_what_its_table_and_its_other_keys_say() {
        use crate::tui::state::prompt::Prompt;
        let editing = Mode::Save {
            prompt: Prompt::new("", false),
        };
        // A prompt types characters (even those bound in normal mode) and edits with its keys.
        assert_eq!(
            action_for(&editing, Key::Char('q')),
            Some(Action::Type('q'))
        );
        assert_eq!(
            action_for(&editing, Key::Ctrl('u')),
            Some(Action::EraseToStart)
        );
        assert_eq!(action_for(&editing, Key::Enter), Some(Action::Confirm));
        assert_eq!(action_for(&editing, Key::Tab), None);
        // The picker types too; its list keys are not letters.
        let picker = Mode::Presets(Default::default());
        assert_eq!(action_for(&picker, Key::Char('j')), Some(Action::Type('j')));
        assert_eq!(action_for(&picker, Key::PageDown), Some(Action::PageDown));
        // The scrolled views scroll with ↑↓ and k j; any other key closes them.
        let help = Mode::Help { offset: 0 };
        assert_eq!(action_for(&help, Key::Char('j')), Some(Action::SelectNext));
        assert_eq!(action_for(&help, Key::Char('x')), Some(Action::Cancel));
        // The questions: y (and s to save first), anything else is no.
        let question = Mode::ConfirmDiscard {
            then: crate::tui::state::Discard::Reset,
        };
        assert_eq!(action_for(&question, Key::Char('Y')), Some(Action::Confirm));
        assert_eq!(action_for(&question, Key::Char('s')), Some(Action::Save));
        assert_eq!(action_for(&question, Key::Esc), Some(Action::Cancel));
        let overwrite = Mode::ConfirmOverwrite { path: "x".into() };
        assert_eq!(action_for(&overwrite, Key::Char('s')), Some(Action::Cancel));
        // A paste is typed only where characters are.
        assert_eq!(
            paste_actions(&editing, "a\nb"),
            vec![Action::Type('a'), Action::Type('b')]
        );
        assert_eq!(paste_actions(&help, "q"), vec![Action::PasteIgnored]);
    }

    #[test]
    fn the_hints_of_prompts_lists_and_questions_name_bound_keys() {
        use super::help::{
            discard_hints, label_of, overwrite_question, picker_hints, prompt_keys, scroll_keys,
        };
        // Every key a hint names is looked up in its mode's table: a key missing there would
        // leave an empty label.
        for ascii in [false, true] {
            for (table, action) in [
                (PROMPT, Action::Confirm),
                (PROMPT, Action::Cancel),
                (PICKER, Action::SelectPrevious),
                (PICKER, Action::SelectNext),
                (PICKER, Action::PageUp),
                (PICKER, Action::PageDown),
                (PICKER, Action::SelectFirst),
                (PICKER, Action::SelectLast),
                (PICKER, Action::Confirm),
                (PICKER, Action::Cancel),
                (SCROLLING, Action::SelectPrevious),
                (SCROLLING, Action::SelectNext),
                (SCROLLING, Action::PageUp),
                (SCROLLING, Action::PageDown),
                (OVERWRITE_QUESTION, Action::Confirm),
                (DISCARD_QUESTION, Action::Confirm),
                (DISCARD_QUESTION, Action::Save),
            ] {
                assert!(!label_of(table, action, ascii).is_empty(), "{action:?}");
            }
        }
        assert_eq!(prompt_keys("sets", false), "Enter sets, Esc cancels");
        assert_eq!(scroll_keys(false), "↑↓ PgUp PgDn scroll");
        assert_eq!(scroll_keys(true), "Up/Down PgUp PgDn scroll");
        assert_eq!(
            overwrite_question("a.toml", false),
            "a.toml exists: overwrite it? y / n"
        );
        let picker: Vec<String> = picker_hints(false).into_iter().map(|(_, t)| t).collect();
        assert_eq!(
            picker,
            [
                "type to search",
                "↑↓ choose",
                "PgUp PgDn Home End",
                "Enter loads",
                "Esc cancels"
            ]
        );
        let discard: Vec<String> = discard_hints("quit", false)
            .into_iter()
            .map(|(_, t)| t)
            .collect();
        assert_eq!(
            discard,
            [
                "unsaved changes: quit and lose them?",
                "y: yes",
                "s: save, then quit",
                "n/Esc: no"
            ]
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
            hint_line_with(false, &[FOLLOW]).starts_with("?:help q:quit f:fork F:rejoin ↑↓:select"),
            "{}",
            hint_line_with(false, &[FOLLOW])
        );
        let help = help_lines_with(true, &[FOLLOW]);
        let own = help_lines(true).len();
        assert_eq!(help.len(), own + 2);
        assert_eq!(help[own].0, "f");
        assert_eq!(help[own + 1].0, "F");
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
        let quit = lines
            .iter()
            .position(|(keys, _)| keys == "q  Ctrl-C")
            .unwrap();
        assert_eq!(lines[quit + 1].0, "Ctrl-Z");
        assert_eq!(lines.len(), quit + 2);
        assert_eq!(help_lines(true)[0].0, "Up Down  k j");
        assert_eq!(
            hint_line(false),
            "?:help q:quit ↑↓:select ←→:change Enter:type m:method w:warnings p:preset \
             Tab:panel b:diagram v:view [ ]:coarse a:add d:delete s:save u:undo r:reset t:time z:zoom c:compare e:export T:theme M:markers"
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
