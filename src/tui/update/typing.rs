//! The editing keys every prompt shares (a value, a file name): typing, Backspace, the cursor
//! keys, Ctrl-U.

use crate::tui::input::keymap::Action;
use crate::tui::state::prompt::{Prompt, Typed};

/// The editing keys every prompt shares: what typing did, or `None` when `action` is not one
/// of them.
pub(super) fn edit_prompt(prompt: &mut Prompt, action: Action, limit: usize) -> Option<Typed> {
    match action {
        Action::Type(c) => return Some(prompt.insert(c, limit)),
        Action::DeleteChar => prompt.delete_before(),
        Action::CursorLeft => prompt.move_by(-1),
        Action::CursorRight => prompt.move_by(1),
        Action::CursorHome => prompt.home(),
        Action::CursorEnd => prompt.end(),
        Action::EraseToStart => prompt.erase_to_start(),
        _ => return None,
    }
    Some(Typed::Inserted)
}

/// What a prompt says of characters refused for its length: `refused` past `limit`.
pub(super) fn too_long(what: &str, limit: usize, refused: usize) -> String {
    format!("{what} has at most {limit} characters ({refused} more typed, not taken)")
}
