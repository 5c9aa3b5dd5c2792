//! The presenter's class controls and what students hear of them: the list of students (`S`),
//! bringing everyone back to follow (`b` there: a student whose own exploration holds unsaved
//! work is asked, never pulled away from it) and a one-line message to every student (`m`).
//! What a student does on hearing them is `super::follow`'s.

use crate::format::printable;
use crate::tui::input::keymap::Action;
use crate::tui::state::follow::ClassNews;
use crate::tui::state::prompt::{Prompt, Typed};
use crate::tui::state::{App, Mode};

use super::typing::{edit_prompt, too_long};

/// Longest message to the students: with `from the presenter: ` it fills one status line at
/// 80 columns, never cut on a student's screen.
pub const BROADCAST_LIMIT: usize = 58;

/// `S`: the list of students (a presenter's explorer only).
pub(super) fn show(app: &mut App) {
    match &app.follow {
        Some(follow) if !follow.is_student() => app.mode = Mode::Students { offset: 0 },
        _ => {}
    }
}

/// A key in the list of students: scrolling keeps it open (the drawing stops at the last
/// row), `b` and `m` act, anything else closes it.
pub(super) fn in_list(app: &mut App, action: Action, offset: u16) {
    const PAGE: u16 = 10;
    let scrolled = match action {
        Action::SelectPrevious => Some(offset.saturating_sub(1)),
        Action::SelectNext => Some(offset.saturating_add(1)),
        Action::PageUp => Some(offset.saturating_sub(PAGE)),
        Action::PageDown => Some(offset.saturating_add(PAGE)),
        _ => None,
    };
    let Some(follow) = &app.follow else {
        app.mode = Mode::Normal;
        return;
    };
    // No further than the list is long.
    let last = u16::try_from(follow.followers.students()).unwrap_or(u16::MAX);
    if let Some(offset) = scrolled {
        app.mode = Mode::Students {
            offset: offset.min(last.saturating_sub(1)),
        };
        return;
    }
    app.mode = Mode::Normal;
    match action {
        Action::BringEveryoneBack if !follow.leads => {
            // The students would follow the presenter who leads, not this one.
            app.message =
                Some("another presenter leads the class: only they bring everyone back".into());
        }
        Action::BringEveryoneBack => {
            let exploring = follow
                .followers
                .students()
                .saturating_sub(follow.followers.count());
            follow.followers.announce(ClassNews::Rejoin);
            // One status line at 80 columns (one with unsaved work is only asked: the list's
            // "unsaved" says who).
            app.message = Some(format!(
                "asked the {exploring} student{} exploring on their own to follow again",
                if exploring == 1 { "" } else { "s" }
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
    if let Some(typed) = edit_prompt(&mut prompt, action, BROADCAST_LIMIT) {
        if typed == Typed::Full {
            app.message = Some(too_long("a message", BROADCAST_LIMIT, prompt.refused));
        }
        if matches!(action, Action::DeleteChar | Action::EraseToStart) {
            // Shortened after the refusal: what is shown is what the lecturer now means to
            // send (a message is words, not a number that a cut would change).
            prompt.refused = 0;
        }
        app.mode = Mode::Broadcast { prompt };
        return;
    }
    match action {
        Action::Confirm if prompt.refused > 0 => {
            // Kept to shorten: sent cut, the message would say something else.
            app.message = Some(format!(
                "nothing sent ({} typed past {BROADCAST_LIMIT} characters): Backspace, then Enter",
                prompt.refused
            ));
            app.mode = Mode::Broadcast { prompt };
        }
        Action::Confirm => {
            app.mode = Mode::Normal;
            let text = printable(prompt.text.trim()).into_owned();
            if text.is_empty() {
                app.message = Some("nothing sent: the message was empty".into());
                return;
            }
            let width = crate::lesson::columns(&text);
            if width > BROADCAST_LIMIT {
                // Kept to shorten: wide characters take two columns.
                app.message = Some(format!(
                    "{width} columns: at most {BROADCAST_LIMIT} fit a student's status line"
                ));
                app.mode = Mode::Broadcast { prompt };
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
