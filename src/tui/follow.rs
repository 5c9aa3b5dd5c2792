//! Follow mode, on the explorer's side: a presenter's state is copied into the explorers that
//! follow it — scene, solution, studies and view, so the presenter's solve is done once and
//! shared — and `f` forks the current state into the student's own exploration, `F` rejoins
//! (keys of [`super::keymap::FOLLOW`], applied by `update` as [`Action::Fork`] and
//! [`Action::Rejoin`]). Who presents and who follows is decided by the server (`crate::serve`); this module only
//! keeps an explorer's role, applies what arrives, and says in the status line which mode it
//! is in and how many follow.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::model::Problem;
use crate::scene::{Scene, SceneSource, Settings};

use super::app::{App, Diagram, Mode, Shown, SolveRequest};
use super::keymap::{Action, Binding, FOLLOW, Key, action_for};
use super::studies::StudySlot;

/// How many explorers follow now, shared by the presenter and every student, and who to tell
/// when that changes (the presenters, whose status line shows it).
#[derive(Default)]
pub struct Followers {
    count: AtomicUsize,
    on_change: std::sync::Mutex<Option<Box<dyn Fn() + Send + Sync>>>,
}

impl std::fmt::Debug for Followers {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Followers({})", self.count())
    }
}

impl Followers {
    /// `on_change` is called (on the thread that made the change) whenever the count changes.
    pub fn new(on_change: impl Fn() + Send + Sync + 'static) -> Arc<Followers> {
        Arc::new(Followers {
            count: AtomicUsize::new(0),
            on_change: std::sync::Mutex::new(Some(Box::new(on_change))),
        })
    }

    pub fn count(&self) -> usize {
        self.count.load(Ordering::Acquire)
    }

    fn changed(&self) {
        let on_change = self.on_change.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(on_change) = on_change.as_ref() {
            on_change();
        }
    }
}

/// An explorer's part in follow mode.
#[derive(Debug, Clone)]
pub struct Follow {
    pub role: Role,
    pub followers: Arc<Followers>,
    /// The presenter's newest state, kept while forked for `F`.
    pub latest: Option<Arc<Snapshot>>,
}

#[derive(Debug, Clone)]
pub enum Role {
    Presenter,
    /// A student; `Some` while following (the guard counts it).
    Student(Option<Following>),
}

/// Counts one following explorer for as long as it lives.
#[derive(Debug)]
pub struct Following(Arc<Followers>);

impl Following {
    pub fn new(followers: &Arc<Followers>) -> Following {
        followers.count.fetch_add(1, Ordering::AcqRel);
        followers.changed();
        Following(Arc::clone(followers))
    }
}

impl Clone for Following {
    fn clone(&self) -> Following {
        Following::new(&self.0)
    }
}

impl Drop for Following {
    fn drop(&mut self) {
        self.0.count.fetch_sub(1, Ordering::AcqRel);
        self.0.changed();
    }
}

impl Follow {
    /// A student who follows from the start.
    pub fn student(followers: &Arc<Followers>) -> Follow {
        Follow {
            role: Role::Student(Some(Following::new(followers))),
            followers: Arc::clone(followers),
            latest: None,
        }
    }

    pub fn presenter(followers: &Arc<Followers>) -> Follow {
        Follow {
            role: Role::Presenter,
            followers: Arc::clone(followers),
            latest: None,
        }
    }

    fn is_following(&self) -> bool {
        matches!(self.role, Role::Student(Some(_)))
    }

    /// The mode in words, for the status line.
    pub fn label(&self) -> String {
        let count = self.followers.count();
        match &self.role {
            Role::Presenter => format!("presenting · {count} follow"),
            Role::Student(Some(_)) => format!("following the presenter · {count} follow · f forks"),
            Role::Student(None) => format!("own exploration · {count} follow · F rejoins"),
        }
    }
}

/// What a follower takes over from the presenter.
#[derive(Debug, Clone)]
pub struct Snapshot {
    scene: Scene,
    loaded: Scene,
    source: SceneSource,
    loaded_problem: (Problem, Settings),
    problem: Problem,
    wanted: SolveRequest,
    shown: Option<Shown>,
    studies: Vec<StudySlot>,
    diagram: Diagram,
    focus: usize,
    selected: usize,
}

impl Snapshot {
    pub fn of(app: &App) -> Snapshot {
        Snapshot {
            scene: app.scene.clone(),
            loaded: app.loaded.clone(),
            source: app.source.clone(),
            loaded_problem: app.loaded_problem.clone(),
            problem: app.problem.clone(),
            wanted: app.wanted.clone(),
            shown: app.shown.clone(),
            studies: app.studies.clone(),
            diagram: app.diagram,
            focus: app.focus,
            selected: app.selected,
        }
    }

    /// Makes `app` show this state (its own view size and mode stay).
    fn apply(&self, app: &mut App) {
        app.scene = self.scene.clone();
        app.loaded = self.loaded.clone();
        // Nothing of the presenter's is the student's to lose.
        app.saved = self.scene.clone();
        app.source = self.source.clone();
        app.loaded_problem = self.loaded_problem.clone();
        app.problem = self.problem.clone();
        app.wanted = self.wanted.clone();
        app.shown = self.shown.clone();
        app.busy_since = None;
        app.studies = self.studies.clone();
        app.diagram = self.diagram;
        app.focus = self.focus;
        app.selected = self.selected.min(app.rows().len() - 1);
        app.refresh_studies();
    }
}

/// A presenter's new state arrived.
pub fn receive(app: &mut App, snapshot: Arc<Snapshot>) {
    let Some(follow) = &mut app.follow else {
        return;
    };
    let following = follow.is_following();
    follow.latest = Some(Arc::clone(&snapshot));
    if following {
        snapshot.apply(app);
    }
}

/// The keys of follow mode this explorer has, for its help and hint line: those of
/// [`FOLLOW`] for a student, none for a presenter or an explorer of its own.
pub fn keys(app: &App) -> &'static [Binding] {
    match app.follow.as_ref().map(|f| &f.role) {
        Some(Role::Student(_)) => FOLLOW,
        _ => &[],
    }
}

/// [`Action::Fork`] (called by `update` only): the student explores on from here.
pub fn fork(app: &mut App) {
    let Some(Follow {
        role: Role::Student(following),
        ..
    }) = &mut app.follow
    else {
        return;
    };
    app.message = Some(if following.take().is_some() {
        "your own exploration from here: F follows the presenter again".into()
    } else {
        "exploring on your own already: F follows the presenter".into()
    });
}

/// [`Action::Rejoin`] (called by `update` only): the student follows the presenter again, at
/// its newest state.
pub fn rejoin(app: &mut App) {
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
    let latest = follow.latest.clone();
    if let Some(snapshot) = latest {
        snapshot.apply(app);
    }
    app.message = Some("following the presenter".into());
}

/// Keys of follow mode: `f` forks, `F` rejoins (through `update`); while following, only keys
/// that change no state pass (help, quit, timings). Returns whether the key was taken here.
pub fn intercept(app: &mut App, key: Key) -> bool {
    let Some(follow) = &mut app.follow else {
        return false;
    };
    let Role::Student(following) = &mut follow.role else {
        return false;
    };
    if app.mode != Mode::Normal {
        return false;
    }
    let following = following.is_some();
    let follow_action = FOLLOW
        .iter()
        .flat_map(|b| b.keys)
        .find(|(k, _)| *k == key)
        .map(|(_, action)| *action);
    if let Some(action) = follow_action {
        super::update::update(app, action);
        return true;
    }
    match following {
        true => {
            let passes = matches!(
                action_for(&app.mode, key),
                Some(
                    Action::ShowHelp
                        | Action::Quit
                        | Action::Interrupt
                        | Action::Suspend
                        | Action::ToggleTimings
                        // What only this student's screen shows: not part of the presenter's
                        // state, so a follower may change it.
                        | Action::ShowWarnings
                        | Action::CycleTheme
                        | Action::ToggleDifference
                        | Action::ToggleZoom
                )
            );
            if passes {
                return false;
            }
            app.message = Some("following the presenter: f to explore on your own".into());
        }
        false => return false,
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tui::{draw_to_buffer, keymap::Key};

    fn student() -> App {
        let loaded = crate::scene::load("benchmark-1").unwrap();
        let look = crate::plot::Look {
            ascii: false,
            color: false,
        };
        let mut app = App::new(loaded, look, false).unwrap();
        app.settle();
        app.follow = Some(Follow::student(&Followers::new(|| {})));
        app
    }

    /// A key as the event loop applies it.
    fn press(app: &mut App, key: Key) {
        if !intercept(app, key)
            && let Some(action) = action_for(&app.mode, key)
        {
            super::super::update::update(app, action);
        }
    }

    fn screen(app: &App) -> String {
        let buffer = draw_to_buffer(app, 120, 40).unwrap();
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
