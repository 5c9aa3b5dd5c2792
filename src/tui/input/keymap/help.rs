//! The help and the hint lines, generated from the keymap's tables: the help lists every
//! binding of [`NORMAL`] (and of follow mode where it applies), the hint line of normal mode
//! the bindings' hints in order of use, and the hint lines of prompts, lists and questions
//! name their keys by looking them up in those modes' tables.

use super::super::keys::Key;
use super::action::Action;
use super::tables::{
    Binding, DISCARD_QUESTION, END_CLASS_QUESTION, GLOBAL, Hint, NORMAL, OVERWRITE_QUESTION,
    PICKER, PROMPT, SCROLLING,
};

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

/// The help's lines of [`NORMAL`], of [`GLOBAL`] (those not listed there already) and then of
/// `extra` (e.g. [`FOLLOW`]).
pub fn help_lines_with(ascii: bool, extra: &[&[Binding]]) -> Vec<(String, &'static str)> {
    NORMAL
        .iter()
        .chain(GLOBAL.iter().filter(|b| !b.help.is_empty()))
        .chain(extra.iter().flat_map(|table| table.iter()))
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
    hint_items(ascii, &[], &|_| true).join(" ")
}

/// The hint line of [`NORMAL`] and `extra` (e.g. [`FOLLOW`]) together, in the hints' order.
pub fn hint_line_with(ascii: bool, extra: &[&[Binding]]) -> String {
    hint_items(ascii, extra, &|_| true).join(" ")
}

/// The hint line of [`NORMAL`] and `extra` cut to `width` columns: the most useful hints
/// that fit, whole, in their order (`?:help` first, so the rest is always one key away).
pub fn fitted_hint_line(ascii: bool, extra: &[&[Binding]], width: usize) -> String {
    fitted_hint_line_of(ascii, extra, width, &|_| true)
}

/// As [`fitted_hint_line`], of the bindings whose action `keep` keeps (the keys that work
/// now: a following student's few).
pub fn fitted_hint_line_of(
    ascii: bool,
    extra: &[&[Binding]],
    width: usize,
    keep: &dyn Fn(Action) -> bool,
) -> String {
    let mut line = String::new();
    for item in hint_items(ascii, extra, keep) {
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
fn hint_items(ascii: bool, extra: &[&[Binding]], keep: &dyn Fn(Action) -> bool) -> Vec<String> {
    let mut hints: Vec<&Hint> = NORMAL
        .iter()
        .chain(extra.iter().flat_map(|table| table.iter()))
        .filter(|b| b.keys.first().is_none_or(|(_, action)| keep(*action)))
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

/// The label of the first key `table` lists for `action` (empty when none does: a test
/// checks that every label a hint asks for exists).
pub fn label_of(table: &[Binding], action: Action, ascii: bool) -> String {
    table
        .iter()
        .flat_map(|b| b.keys)
        .find(|(_, a)| *a == action)
        .map(|(k, _)| k.label(ascii))
        .unwrap_or_default()
}

/// The keys of `previous` and `next` in `table` as one hint: `↑↓`, or `Up/Down` in ASCII.
fn arrows(table: &[Binding], previous: Action, next: Action, ascii: bool) -> String {
    let separator = if ascii { "/" } else { "" };
    format!(
        "{}{separator}{}",
        label_of(table, previous, ascii),
        label_of(table, next, ascii)
    )
}

/// What Enter and Esc do in a prompt: `Enter sets, Esc cancels` (`confirm`: what Enter does).
pub fn prompt_keys(confirm: &str, ascii: bool) -> String {
    format!(
        "{} {confirm}, {} cancels",
        label_of(PROMPT, Action::Confirm, ascii),
        label_of(PROMPT, Action::Cancel, ascii)
    )
}

/// The hint of the help and the warnings view: `↑↓ scroll`.
pub fn scroll_keys(ascii: bool) -> String {
    let keys = arrows(SCROLLING, Action::SelectPrevious, Action::SelectNext, ascii);
    let pages = format!(
        "{} {}",
        label_of(SCROLLING, Action::PageUp, ascii),
        label_of(SCROLLING, Action::PageDown, ascii)
    );
    format!("{keys} {pages} scroll")
}

/// The hint items of the preset picker, each with its importance (0 most important).
pub fn picker_hints(ascii: bool) -> Vec<(u8, String)> {
    let label = |action| label_of(PICKER, action, ascii);
    let choose = arrows(PICKER, Action::SelectPrevious, Action::SelectNext, ascii);
    vec![
        (0, "type to search".into()),
        (0, format!("{choose} choose")),
        (
            1,
            format!(
                "{} {} {} {}",
                label(Action::PageUp),
                label(Action::PageDown),
                label(Action::SelectFirst),
                label(Action::SelectLast)
            ),
        ),
        (0, format!("{} loads", label(Action::Confirm))),
        (0, format!("{} cancels", label(Action::Cancel))),
    ]
}

/// The question before a file is overwritten: `PATH exists: overwrite it? y / n`.
pub fn overwrite_question(path: &str, ascii: bool) -> String {
    let yes = label_of(OVERWRITE_QUESTION, Action::Confirm, ascii);
    format!("{path} exists: overwrite it? {yes} / n")
}

/// The lecturer's question before a quit ends the class of `students` students, `unsaved`
/// of them with unsaved work.
pub fn end_class_question(students: usize, unsaved: usize, ascii: bool) -> String {
    let yes = label_of(END_CLASS_QUESTION, Action::Confirm, ascii);
    let work = match unsaved {
        0 => String::new(),
        n => format!(" ({n} with unsaved work)"),
    };
    format!(
        "{students} student{}{work}: end the class? {yes} / n",
        if students == 1 { "" } else { "s" }
    )
}

/// The hint items of the question before unsaved changes are lost doing `what`.
pub fn discard_hints(what: &str, ascii: bool) -> Vec<(u8, String)> {
    let label = |action| label_of(DISCARD_QUESTION, action, ascii);
    vec![
        (0, format!("unsaved changes: {what} and lose them?")),
        (0, format!("{}: yes", label(Action::Confirm))),
        (1, format!("{}: save, then {what}", label(Action::Save))),
        (0, "n/Esc: no".into()),
    ]
}
