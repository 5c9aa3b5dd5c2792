//! Follow mode's changes: the presenter's new state shown by a student who follows (one clone
//! of the shared [`Exploration`] — scene, solve, sweeps and view — so the presenter's solve is
//! done once and shared), `f` forking into the student's own exploration, `F` rejoining, and
//! the keys a following student may not use (they would change the presenter's scene), and the
//! news of the class: the presenter leaving frees a follower, the class ending shows a
//! student's closing screen with their work saved or shown to copy, the presenter bringing
//! everyone back (a fork with unsaved work is only asked) and the presenter's messages.

use std::sync::Arc;

use crate::format::printable;
use crate::tui::input::keymap::{
    Key, a_follower_may, action_for, follow_action, presenting_action,
};
use crate::tui::state::follow::{ClassNews, Following, Role};
use crate::tui::state::{App, Discard, Exploration, Mode};

use super::edit::cap_at_limit;
use super::save::save_at_closing;
use super::{act, refresh_sweeps};

/// Makes `app` show the presenter's state (its own view size and mode stay).
fn show(app: &mut App, exploration: &Exploration) {
    app.exploration = exploration.clone();
    // Nothing of the presenter's is the student's to lose; a save is offered under the name
    // of the scene shown (a lesson step's, a preset's), as on loading it.
    app.saved = app.exploration.scene.clone();
    app.save_path = crate::tui::state::app::default_save_path(
        &app.save_policy,
        Some(&app.save_directory),
        app.owner.as_deref(),
        &app.exploration.source,
    );
    app.busy_since = None;
    let rows = app.exploration.rows().len();
    app.exploration.selected = app.exploration.selected.min(rows - 1);
    refresh_sweeps(app);
}

/// A presenter's new state arrived: shown while following, kept for `F` while forked. A
/// presenter hears one, the class's, as it joins: it goes on from there (a lecturer whose
/// connection dropped comes back at the step the class is at, not at the first).
pub(super) fn receive(app: &mut App, exploration: Arc<Exploration>) {
    let Some(follow) = &mut app.follow else {
        return;
    };
    if !follow.is_student() {
        show(app, &exploration);
        app.message = Some("presenting from where the class is".into());
        return;
    }
    let following = follow.is_following();
    follow.latest = Some(Arc::clone(&exploration));
    if following {
        show(app, &exploration);
    }
}

/// [`Action::Fork`]: the student explores on from here.
pub(super) fn fork(app: &mut App) {
    let Some(follow) = &mut app.follow else {
        return;
    };
    let Role::Student(following) = &mut follow.role else {
        return;
    };
    // Their own by choice: a presenter arriving does not pull them back.
    follow.waiting = false;
    app.message = Some(if following.take().is_some() {
        "your own exploration from here: F follows the presenter again".into()
    } else if !follow.presenter_here {
        "on your own: the next presenter to log in will not pull you in (F: it will)".into()
    } else {
        "exploring on your own already: F follows the presenter".into()
    });
    cap_elements(app);
}

/// A fork of the presenter's scene beyond this server's `--max-elements` starts at the limit,
/// with a note, so that the student's explorer is usable at once (issue 23 item 5); `r` and
/// undo stay at the limit.
fn cap_elements(app: &mut App) {
    if let (Some(asked), Some(max)) = (cap_at_limit(app), app.max_elements) {
        app.message = Some(format!(
            "own exploration at n = {max}, this server's limit (the presenter's: {asked})"
        ));
    }
}

/// What the server says of the class: to a student, the presenter's coming and going, the
/// class's end, a bring-back or a broadcast; to a presenter, whether it leads.
pub(super) fn class_news(app: &mut App, news: ClassNews) {
    let Some(follow) = &mut app.follow else {
        return;
    };
    let Role::Student(following) = &mut follow.role else {
        if let ClassNews::Lead(leads) = news {
            follow.leads = leads;
            // One status line at 80 columns.
            app.message = Some(if leads {
                "you lead the class again: the students see your explorer".into()
            } else {
                "another presenter logged in and leads: the students see theirs".into()
            });
        }
        return;
    };
    match news {
        ClassNews::PresenterLeft => {
            follow.presenter_here = false;
            // The view stays; the keys are the student's again.
            app.message = Some(if following.take().is_some() {
                follow.waiting = true;
                // One status line at 80 columns.
                "the presenter left: the keys are yours (you follow again once one is back)".into()
            } else {
                "the presenter left".into()
            });
        }
        ClassNews::PresenterArrived => {
            follow.presenter_here = true;
            presenter_arrived(app);
        }
        ClassNews::Ended { by } => {
            following.take();
            let saved = save_at_closing(app);
            app.mode = Mode::ClassEnded { by, saved };
        }
        ClassNews::Rejoin => asked_to_rejoin(app),
        ClassNews::Broadcast { text } => {
            app.message = Some(format!("from the presenter: {}", printable(&text)));
        }
        ClassNews::Lead(_) => {}
    }
}

/// A presenter logged in where none was: a student waiting for one follows it (its first
/// frame comes at once), unless that would lose unsaved work; one on their own by choice is
/// told.
fn presenter_arrived(app: &mut App) {
    // A lesson step left with changes counts too: the student was working on their own.
    let modified = app.has_unsaved_work();
    let Some(follow) = &mut app.follow else {
        return;
    };
    if follow.is_following() {
        return;
    }
    app.message = Some(if modified {
        "a presenter logged in: F follows them (unsaved: s saves first)".into()
    } else if !follow.waiting {
        "a presenter logged in: F follows them".into()
    } else {
        follow.waiting = false;
        if let Role::Student(following) = &mut follow.role {
            *following = Some(Following::new(&follow.followers));
        }
        "a presenter logged in: following them (f explores on your own)".into()
    });
}

/// [`Action::Rejoin`]: the student follows the presenter again, at its newest state; asked
/// first where that would lose unsaved changes of their own.
pub(super) fn rejoin(app: &mut App) {
    let Some(follow) = &app.follow else {
        return;
    };
    if !follow.is_student() {
        return;
    }
    if follow.is_following() {
        app.message = Some("following already: f forks".into());
        return;
    }
    if !follow.presenter_here {
        wait_for_a_presenter(app);
        return;
    }
    // As `discard::unless_unsaved` asks (which calls back here on a yes): a lesson step left
    // with changes counts.
    if app.has_unsaved_work() {
        app.mode = Mode::ConfirmDiscard {
            then: Discard::Rejoin,
        };
    } else {
        follow_again(app);
    }
}

/// No presenter to follow: the student stays on their own, nothing changed, and follows the
/// next presenter to log in (unless they hold unsaved work then).
fn wait_for_a_presenter(app: &mut App) {
    if let Some(follow) = &mut app.follow {
        follow.waiting = true;
    }
    app.message = Some("no presenter is connected: you follow the next to log in".into());
}

/// Follows the presenter again, whatever this student changed (asked by [`rejoin`]); where
/// the presenter left meanwhile (the question was open), nothing is lost: see
/// [`wait_for_a_presenter`].
pub(super) fn follow_again(app: &mut App) {
    if app.follow.as_ref().is_some_and(|f| !f.presenter_here) {
        wait_for_a_presenter(app);
        return;
    }
    let Some(follow) = &mut app.follow else {
        return;
    };
    let Role::Student(following) = &mut follow.role else {
        return;
    };
    *following = Some(Following::new(&follow.followers));
    if let Some(latest) = follow.latest.clone() {
        show(app, &latest);
    }
    // The lesson's steps are the presenter's from here: changes left on them go, as asked
    // (they would stay hidden, and counted as unsaved, stop 60's pass).
    app.step_edits.clear();
    app.message = Some("following the presenter".into());
}

/// Keys of follow mode: `f` forks, `F` rejoins; while following, only keys that change no
/// state of the presenter's pass (help, quit, timings, and what only this screen shows).
/// Returns whether the key was taken here.
pub(super) fn intercept(app: &mut App, key: Key) -> bool {
    let Some(follow) = &app.follow else {
        return false;
    };
    if app.mode != Mode::Normal {
        return false;
    }
    if !follow.is_student() {
        // A presenter's own keys: the join screen, the list of students.
        let action = presenting_action(key);
        if let Some(action) = action {
            act(app, action);
        }
        return action.is_some();
    }
    if let Some(action) = follow_action(key) {
        act(app, action);
        return true;
    }
    if !follow.is_following() {
        return false;
    }
    let passes = action_for(&app.mode, key).is_some_and(a_follower_may);
    if !passes {
        app.message = Some("following the presenter: f to explore on your own".into());
    }
    !passes
}

/// The presenter asks everyone to follow again: a student following already stays; one
/// exploring on their own follows unless that would lose unsaved work (then only asked).
fn asked_to_rejoin(app: &mut App) {
    if app.is_following() {
        return;
    }
    if app.has_unsaved_work() {
        // One status line at 80 columns.
        app.message = Some(
            "the presenter asks everyone to follow: F follows (unsaved: s saves first)".into(),
        );
        return;
    }
    follow_again(app);
    app.message = Some("the presenter brought everyone back: following again".into());
}
