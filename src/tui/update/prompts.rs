//! The modes that take keys for themselves: a prompt for a value (the editing keys every
//! prompt shares are here too), the preset picker with its search, and the scrolled views
//! (help, warnings).

use crate::tui::input::keymap::Action;
use crate::tui::layout::picker::picker_rows_shown;
use crate::tui::state::params::{Row, set_from_text};
use crate::tui::state::picker::PresetPicker;
use crate::tui::state::prompt::{Prompt, Typed};
use crate::tui::state::{App, Discard, Mode};

use super::discard::unless_unsaved;
use super::edit::try_apply;
use super::typing::{edit_prompt, too_long};

/// Longest value a prompt accepts.
const PROMPT_LIMIT: usize = 200;

/// The warnings view and the help scroll at most this far (drawing stops at the last line
/// anyway).
const WARNINGS_SCROLL_LIMIT: u16 = 200;

/// A scrolled view's new offset after `action` (↑ and ↓ scroll a line, PgUp and PgDn a page
/// of `page` lines), or `None`: any other key closes it.
pub(super) fn scrolled(offset: u16, action: Action, page: u16) -> Option<u16> {
    let page = page.max(1);
    match action {
        Action::SelectPrevious => Some(offset.saturating_sub(1)),
        Action::SelectNext => Some(offset.saturating_add(1).min(WARNINGS_SCROLL_LIMIT)),
        Action::PageUp => Some(offset.saturating_sub(page)),
        Action::PageDown => Some(offset.saturating_add(page).min(WARNINGS_SCROLL_LIMIT)),
        _ => None,
    }
}

/// A key in the prompt for `row`'s value: Enter sets it (if the scene's rules accept it).
pub(super) fn editing(app: &mut App, action: Action, row: Row, mut prompt: Prompt) {
    if let Some(typed) = edit_prompt(&mut prompt, action, PROMPT_LIMIT) {
        if typed == Typed::Full {
            app.message = Some(too_long("a value", PROMPT_LIMIT, prompt.refused));
        }
        app.mode = Mode::Editing { row, prompt };
        return;
    }
    match action {
        Action::Confirm => {
            app.mode = Mode::Normal;
            if prompt.refused > 0 {
                // What the prompt holds is not what was typed: a cut number is another.
                app.message = Some(format!(
                    "rejected: {}; nothing changed",
                    too_long("a value", PROMPT_LIMIT, prompt.refused)
                ));
                return;
            }
            if prompt.text.trim().is_empty() {
                return;
            }
            match set_from_text(app.scene(), row, &prompt.text) {
                Ok(candidate) => {
                    try_apply(app, candidate);
                }
                Err(message) => app.message = Some(format!("rejected: {message}")),
            }
        }
        Action::Cancel => app.mode = Mode::Normal,
        _ => app.mode = Mode::Editing { row, prompt },
    }
}

/// A key in the preset picker: move, search, load (asking first when that loses changes).
pub(super) fn presets(app: &mut App, action: Action, mut picker: PresetPicker) {
    let visible = picker_rows_shown(app);
    let index = picker.index as isize;
    let page = visible as isize;
    match action {
        Action::SelectPrevious => picker.select(index - 1, visible),
        Action::SelectNext => picker.select(index + 1, visible),
        Action::SelectFirst => picker.select(0, visible),
        Action::SelectLast => picker.select(isize::MAX, visible),
        Action::PageUp => picker.select(index - page, visible),
        Action::PageDown => picker.select(index + page, visible),
        Action::Type(c) => picker.type_char(c, visible),
        Action::DeleteChar => picker.delete_char(visible),
        Action::Confirm => {
            match picker.highlighted() {
                Some(preset) => {
                    app.mode = Mode::Normal;
                    unless_unsaved(app, Discard::Preset(preset));
                }
                None => {
                    app.message = Some(format!(
                        "no preset matches \"{}\": Backspace edits the search",
                        picker.query
                    ))
                }
            }
            return;
        }
        Action::Cancel => {
            app.mode = Mode::Normal;
            return;
        }
        _ => {}
    }
    app.mode = Mode::Presets(picker);
}
