//! Follow mode, in the explorer's state: an explorer's role (presenter, student following,
//! student exploring on its own), the presenter's newest state kept for rejoining, the class's
//! counts shared by every explorer of a server (students following, students connected, and
//! how many of them hold unsaved work: the presenter's quit asks with them), and the news of
//! the class a student hears (the presenter left, the class ended). Who presents and who
//! follows is decided by the server (`crate::serve`); what arrives and what the keys do is
//! `tui::update::follow`.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use super::exploration::Exploration;

/// How many explorers follow now, shared by the presenter and every student, and who to tell
/// when that changes (the presenters, whose status line shows it).
#[derive(Default)]
pub struct Followers {
    count: AtomicUsize,
    /// Students connected (following or not), and how many of them hold unsaved work.
    students: AtomicUsize,
    unsaved: AtomicUsize,
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
            students: AtomicUsize::new(0),
            unsaved: AtomicUsize::new(0),
            on_change: std::sync::Mutex::new(Some(Box::new(on_change))),
        })
    }

    pub fn count(&self) -> usize {
        self.count.load(Ordering::Acquire)
    }

    /// Students connected now, following or exploring on their own.
    pub fn students(&self) -> usize {
        self.students.load(Ordering::Acquire)
    }

    /// Students whose own exploration differs from what they last saved.
    pub fn unsaved(&self) -> usize {
        self.unsaved.load(Ordering::Acquire)
    }

    fn changed(&self) {
        let on_change = self.on_change.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(on_change) = on_change.as_ref() {
            on_change();
        }
    }
}

/// A student's place in the class counts, for as long as its explorer lives (shared by its
/// clones), with whether it holds unsaved work.
#[derive(Debug)]
pub struct Seat {
    followers: Arc<Followers>,
    unsaved: AtomicBool,
}

impl Seat {
    fn new(followers: &Arc<Followers>) -> Arc<Seat> {
        followers.students.fetch_add(1, Ordering::AcqRel);
        followers.changed();
        Arc::new(Seat {
            followers: Arc::clone(followers),
            unsaved: AtomicBool::new(false),
        })
    }
}

impl Drop for Seat {
    fn drop(&mut self) {
        if self.unsaved.load(Ordering::Acquire) {
            self.followers.unsaved.fetch_sub(1, Ordering::AcqRel);
        }
        self.followers.students.fetch_sub(1, Ordering::AcqRel);
        self.followers.changed();
    }
}

/// What the server tells a student's explorer about the class.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ClassNews {
    /// The presenter went away (a `--presenter-keys` session ended): a follower gets its keys
    /// back and keeps what it shows.
    PresenterLeft,
    /// The class was ended, by `by`: the explorer shows its closing screen (the scene saved
    /// or as text to copy) until a key closes it or the server does.
    Ended { by: String },
}

/// An explorer's part in follow mode.
#[derive(Debug, Clone)]
pub struct Follow {
    pub role: Role,
    pub followers: Arc<Followers>,
    /// The presenter's newest state, kept while forked for `F`.
    pub latest: Option<Arc<Exploration>>,
    /// A student's seat in the class counts.
    seat: Option<Arc<Seat>>,
    /// A presenter whose quit ends the class (`beamfric present`): it asks first when
    /// students are connected.
    pub ends_class: bool,
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
            seat: Some(Seat::new(followers)),
            ends_class: false,
        }
    }

    /// A presenter; `ends_class` when its quit ends the class (the lecturer's own explorer).
    pub fn presenter(followers: &Arc<Followers>, ends_class: bool) -> Follow {
        Follow {
            role: Role::Presenter,
            followers: Arc::clone(followers),
            latest: None,
            seat: None,
            ends_class,
        }
    }

    /// A student's unsaved work, counted for the presenter's question (`update` tells it
    /// after every message).
    pub fn note_unsaved(&self, unsaved: bool) {
        let Some(seat) = &self.seat else {
            return;
        };
        if seat.unsaved.swap(unsaved, Ordering::AcqRel) != unsaved {
            if unsaved {
                seat.followers.unsaved.fetch_add(1, Ordering::AcqRel);
            } else {
                seat.followers.unsaved.fetch_sub(1, Ordering::AcqRel);
            }
            seat.followers.changed();
        }
    }

    /// The students whose class this presenter's quit would end, if any: (connected, with
    /// unsaved work).
    pub fn class_to_end(&self) -> Option<(usize, usize)> {
        let students = self.followers.students();
        (self.ends_class && students > 0).then(|| (students, self.followers.unsaved()))
    }

    /// A student following the presenter now (not forked).
    pub fn is_following(&self) -> bool {
        matches!(self.role, Role::Student(Some(_)))
    }

    /// A student, following or not.
    pub fn is_student(&self) -> bool {
        matches!(self.role, Role::Student(_))
    }

    /// The mode in words, for the status line.
    pub fn label(&self) -> String {
        let count = self.followers.count();
        match &self.role {
            Role::Presenter => {
                let students = self.followers.students();
                format!(
                    "presenting · {count} follow · {students} student{}",
                    if students == 1 { "" } else { "s" }
                )
            }
            Role::Student(Some(_)) => format!("following the presenter · {count} follow · f forks"),
            Role::Student(None) => format!("own exploration · {count} follow · F rejoins"),
        }
    }
}
