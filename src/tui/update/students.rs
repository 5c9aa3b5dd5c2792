//! The presenter's class controls and what students hear of them: the list of students (`S`),
//! bringing everyone back to follow (`b` there: a student whose own exploration holds unsaved
//! work is asked, never pulled away from it) and a one-line message to every student (`m`).
//! What a student does on hearing them is `super::follow`'s.

use crate::format::printable;
use crate::tui::input::keymap::Action;
use crate::tui::state::follow::ClassNews;
use crate::tui::state::prompt::Prompt;
use crate::tui::state::{App, Mode};

use super::typing::edit_prompt;

/// Longest message to the students: with `from the presenter: ` it fills one status line at
/// 80 columns, never cut on a student's screen.
pub const BROADCAST_LIMIT: usize = 58;

/// `S`: the list of students (a presenter's explorer only).
pub(super) fn show(app: &mut App) {
    match &app.follow {
        Some(follow) if !follow.is_student() => app.mode = Mode::Students,
        _ => {}
    }
}

/// A key in the list of students.
pub(super) fn in_list(app: &mut App, action: Action) {
    app.mode = Mode::Normal;
    let Some(follow) = &app.follow else {
        return;
    };
    match action {
        Action::BringEveryoneBack => {
            let told = follow.followers.announce(ClassNews::Rejoin);
            app.message = Some(format!(
                "asked {told} student{} to follow again (a student with unsaved work is asked \
                 first)",
                if told == 1 { "" } else { "s" }
            ));
        }
        Action::WriteBroadcast => {
            app.mode = Mode::Broadcast {
                prompt: Prompt::new("", false),
            };
        }
        _ => {}
    }
}

/// A key in the message prompt: Enter sends the line to every student.
pub(super) fn broadcast_prompt(app: &mut App, action: Action, mut prompt: Prompt) {
    if edit_prompt(&mut prompt, action, BROADCAST_LIMIT).is_some() {
        app.mode = Mode::Broadcast { prompt };
        return;
    }
    match action {
        Action::Confirm => {
            app.mode = Mode::Normal;
            let text = printable(prompt.text.trim()).into_owned();
            if text.is_empty() {
                app.message = Some("nothing sent: the message was empty".into());
                return;
            }
            let Some(follow) = &app.follow else {
                return;
            };
            let told = follow
                .followers
                .announce(ClassNews::Broadcast { text: text.clone() });
            app.message = Some(format!(
                "sent to {told} student{}: {text}",
                if told == 1 { "" } else { "s" }
            ));
        }
        Action::Cancel => app.mode = Mode::Normal,
        _ => app.mode = Mode::Broadcast { prompt },
    }
}
