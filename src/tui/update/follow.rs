//! Follow mode's changes: the presenter's new state shown by a student who follows (one clone
//! of the shared [`Exploration`] — scene, solve, sweeps and view — so the presenter's solve is
//! done once and shared), `f` forking into the student's own exploration, `F` rejoining, and
//! the keys a following student may not use (they would change the presenter's scene).

use std::sync::Arc;

use crate::tui::input::keymap::{Action, Key, action_for, follow_action};
use crate::tui::state::follow::{Following, Role};
use crate::tui::state::{App, Exploration, Mode};

use super::{act, refresh_sweeps};

/// Makes `app` show the presenter's state (its own view size and mode stay).
fn show(app: &mut App, exploration: &Exploration) {
    app.exploration = exploration.clone();
    // Nothing of the presenter's is the student's to lose.
    app.saved = app.exploration.scene.clone();
    app.busy_since = None;
    let rows = app.exploration.rows().len();
    app.exploration.selected = app.exploration.selected.min(rows - 1);
    refresh_sweeps(app);
}

/// A presenter's new state arrived: shown while following, kept for `F` while forked.
pub(super) fn receive(app: &mut App, exploration: Arc<Exploration>) {
    let Some(follow) = &mut app.follow else {
        return;
    };
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
    app.message = Some(if following.take().is_some() {
        "your own exploration from here: F follows the presenter again".into()
    } else {
        "exploring on your own already: F follows the presenter".into()
    });
}

/// [`Action::Rejoin`]: the student follows the presenter again, at its newest state.
pub(super) fn rejoin(app: &mut App) {
    let Some(follow) = &mut app.follow else {
        return;
    };
    let Role::Student(following) = &mut follow.role else {
        return;
    };
    if following.is_some() {
        app.message = Some("following already: f forks".into());
        return;
    }
    *following = Some(Following::new(&follow.followers));
    if let Some(latest) = follow.latest.clone() {
        show(app, &latest);
    }
    app.message = Some("following the presenter".into());
}

/// Keys of follow mode: `f` forks, `F` rejoins; while following, only keys that change no
/// state of the presenter's pass (help, quit, timings, and what only this screen shows).
/// Returns whether the key was taken here.
pub(super) fn intercept(app: &mut App, key: Key) -> bool {
    let Some(follow) = &app.follow else {
        return false;
    };
    if !follow.is_student() || app.mode != Mode::Normal {
        return false;
    }
    if let Some(action) = follow_action(key) {
        act(app, action);
        return true;
    }
    if !follow.is_following() {
        return false;
    }
    let passes = matches!(
        action_for(&app.mode, key),
        Some(
            Action::ShowHelp
                | Action::Quit
                | Action::Interrupt
                | Action::Suspend
                | Action::ToggleTimings
                // What only this student's screen shows: not part of the presenter's state, so
                // a follower may change it.
                | Action::ShowWarnings
                | Action::CycleTheme
                | Action::ToggleDifference
                | Action::ToggleZoom
        )
    );
    if !passes {
        app.message = Some("following the presenter: f to explore on your own".into());
    }
    !passes
}

#[cfg(test)]
mod tests {
    use super::super::{Msg, update};
    use crate::tui::input::keymap::Key;
    use crate::tui::runtime::headless::{draw_to_buffer, settled};
    use crate::tui::state::follow::{Follow, Followers};
    use crate::tui::state::{App, Mode, Options};

    fn student() -> App {
        let loaded = crate::scene::load("benchmark-1").unwrap();
        let look = crate::plot::Look {
            ascii: false,
            color: false,
        };
        let options = Options {
            follow: Some(Follow::student(&Followers::new(|| {}))),
            ..Options::new(look)
        };
        settled(App::new(loaded, options).unwrap())
    }

    /// A key as the event loop applies it.
    fn press(app: &mut App, key: Key) {
        update(app, Msg::Key(key));
    }

    fn screen(app: &App) -> String {
        let buffer = draw_to_buffer(app, 120, 40);
        crate::plot::buffer_to_text(&buffer, false)
    }

    #[test]
    fn a_students_help_and_hints_list_the_follow_keys_and_fork_and_rejoin_work() {
        let mut app = student();
        assert!(screen(&app).contains("f:fork F:rejoin"), "{}", screen(&app));
        press(&mut app, Key::Char('?'));
        assert_eq!(app.mode, Mode::Help { offset: 0 });
        let help = screen(&app);
        assert!(help.contains("fork: explore on your own"), "{help}");
        assert!(help.contains("follow the presenter again"), "{help}");
        press(&mut app, Key::Esc);
        // Following: a change is refused; forked: it is made; rejoined: following again.
        press(&mut app, Key::Char(']'));
        assert!(!app.modified());
        press(&mut app, Key::Char('f'));
        assert!(screen(&app).contains("own exploration"));
        press(&mut app, Key::Char(']'));
        assert!(app.modified());
        press(&mut app, Key::Char('F'));
        assert!(screen(&app).contains("following the presenter"));
    }

    #[test]
    fn a_follower_may_change_what_only_its_own_screen_shows() {
        let mut app = student();
        let palette = app.palette;
        press(&mut app, Key::Char('T'));
        assert_ne!(app.palette, palette, "the theme is the student's own");
        press(&mut app, Key::Char('c'));
        assert!(app.show_difference);
        press(&mut app, Key::Char('z'));
        assert!(app.zoom);
        press(&mut app, Key::Char('w'));
        assert_eq!(app.mode, Mode::Warnings { offset: 0 });
        press(&mut app, Key::Esc);
        // The scene is still the presenter's.
        assert!(!app.modified());
    }
}
