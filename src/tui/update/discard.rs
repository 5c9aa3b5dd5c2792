//! What would lose unsaved changes — quitting, a reset, loading a preset — asks first: the
//! question's answer (yes, save first, or keep them), and the reset itself.

use crate::tui::input::keymap::Action;
use crate::tui::state::{App, Discard, Ending, Mode};

use super::edit::{cap_at_limit, clamp_selection, load_preset, remember, request_solve};
use super::save::start_save;

/// `q`: the lecturer's quit asks first while students are connected (it ends their class),
/// then, like every quit, when it would lose unsaved changes.
pub(super) fn quit(app: &mut App) {
    match app.follow.as_ref().and_then(|f| f.class_to_end()) {
        Some(_) => app.mode = Mode::ConfirmEndClass,
        None => unless_unsaved(app, Discard::Quit),
    }
}

/// The answer to "end the class?".
pub(super) fn confirm_end_class(app: &mut App, action: Action) {
    app.mode = Mode::Normal;
    match action {
        Action::Confirm => unless_unsaved(app, Discard::Quit),
        _ => app.message = Some("the class goes on".into()),
    }
}

/// Does `then` at once, or asks first when it would lose unsaved changes.
pub(super) fn unless_unsaved(app: &mut App, then: Discard) {
    // Quitting loses the lesson steps left with changes too, and so does following the
    // presenter (the steps are the presenter's from then on).
    let unsaved = match then {
        Discard::Quit | Discard::Rejoin => app.has_unsaved_work(),
        _ => app.modified(),
    };
    if unsaved {
        app.mode = Mode::ConfirmDiscard { then };
    } else {
        discard_and(app, then);
    }
}

/// Does `then`, losing the unsaved changes.
pub(super) fn discard_and(app: &mut App, then: Discard) {
    match then {
        Discard::Quit => app.ending = Some(Ending::Quit),
        Discard::Reset => {
            remember(app);
            let exploration = &mut app.exploration;
            let (problem, settings) = exploration.loaded_problem.clone();
            exploration.scene = exploration.loaded.clone();
            app.saved = exploration.loaded.clone();
            clamp_selection(app);
            request_solve(app, problem, settings);
            app.message = Some("reset to the scene as loaded (u undoes)".into());
            // A scene loaded beyond a served session's limit (the presenter's, forked) is
            // shown at the limit.
            if let (Some(asked), Some(max)) = (cap_at_limit(app), app.max_elements) {
                app.message = Some(format!(
                    "reset to the scene as loaded, at n = {max}: its n = {asked} is beyond this \
                     server's limit (u undoes)"
                ));
            }
        }
        Discard::Preset(index) => load_preset(app, index),
        Discard::Rejoin => super::follow::follow_again(app),
    }
}

/// The answer to "lose the unsaved changes?".
pub(super) fn confirm_discard(app: &mut App, action: Action, then: Discard) {
    app.mode = Mode::Normal;
    match action {
        Action::Confirm => discard_and(app, then),
        Action::Save => {
            // Save first, then do what was asked once the save has succeeded (only where a
            // save writes a file: a served session shows the text instead).
            start_save(app);
            if matches!(app.mode, Mode::Save { .. }) {
                app.after_save = Some(then);
            }
        }
        _ => app.message = Some("kept the unsaved changes".into()),
    }
}
