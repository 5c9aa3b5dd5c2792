//! Follow mode, in the explorer's state: an explorer's role (presenter, student following,
//! student exploring on its own), the presenter's newest state kept for rejoining, the class's
//! counts shared by every explorer of a server (students following, students connected, and
//! how many of them hold unsaved work: the presenter's quit asks with them), and the news of
//! the class a student hears (the presenter left, the class ended). Who presents and who
//! follows is decided by the server (`crate::serve`); what arrives and what the keys do is
//! `tui::update::follow`.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, Weak};
use std::time::{Duration, Instant};

use super::exploration::Exploration;

/// How many explorers follow now, shared by the presenter and every student, and who to tell
/// when that changes (the presenters, whose status line shows it).
#[derive(Default)]
pub struct Followers {
    count: AtomicUsize,
    /// Students connected (following or not), and how many of them hold unsaved work.
    students: AtomicUsize,
    unsaved: AtomicUsize,
    on_change: Mutex<Option<Box<dyn Fn() + Send + Sync>>>,
    /// Every student's seat, for the presenter's list of students.
    seats: Mutex<Vec<Weak<Seat>>>,
    /// How a presenter's word reaches every student (set by the server's hub).
    announce: Mutex<Option<Announce>>,
}

/// Tells every student of the class some news; returns how many were told.
type Announce = Box<dyn Fn(ClassNews) -> usize + Send + Sync>;

/// One student as the presenter's list shows them.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StudentView {
    pub user: String,
    pub following: bool,
    pub unsaved: bool,
    /// Since their last key, click or paste.
    pub idle: Duration,
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
            on_change: Mutex::new(Some(Box::new(on_change))),
            seats: Mutex::default(),
            announce: Mutex::default(),
        })
    }

    /// How a presenter's news reaches every student (the server's hub sets it once).
    pub fn set_announce(&self, announce: impl Fn(ClassNews) -> usize + Send + Sync + 'static) {
        *lock(&self.announce) = Some(Box::new(announce));
    }

    /// Tells every student `news`; returns how many were told (none without a hub).
    pub fn announce(&self, news: ClassNews) -> usize {
        lock(&self.announce)
            .as_ref()
            .map_or(0, |announce| announce(news))
    }

    /// The students connected now, in the order they came, as of `now`.
    pub fn roster(&self, now: Instant) -> Vec<StudentView> {
        let mut seats = lock(&self.seats);
        seats.retain(|seat| seat.strong_count() > 0);
        seats
            .iter()
            .filter_map(Weak::upgrade)
            .map(|seat| StudentView {
                user: seat.user.clone(),
                following: seat.following.load(Ordering::Acquire),
                unsaved: seat.unsaved.load(Ordering::Acquire),
                idle: now.saturating_duration_since(*lock(&seat.last_input)),
            })
            .collect()
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
        let on_change = lock(&self.on_change);
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
    /// The student's user name.
    user: String,
    unsaved: AtomicBool,
    following: AtomicBool,
    last_input: Mutex<Instant>,
}

impl Seat {
    fn new(followers: &Arc<Followers>, user: &str) -> Arc<Seat> {
        followers.students.fetch_add(1, Ordering::AcqRel);
        let seat = Arc::new(Seat {
            followers: Arc::clone(followers),
            user: user.to_string(),
            unsaved: AtomicBool::new(false),
            following: AtomicBool::new(true),
            last_input: Mutex::new(Instant::now()),
        });
        lock(&followers.seats).push(Arc::downgrade(&seat));
        followers.changed();
        seat
    }
}

fn lock<T>(mutex: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(|e| e.into_inner())
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
    /// The presenter brings everyone back to follow (a fork with unsaved work is only asked).
    Rejoin,
    /// A line from the presenter to every student.
    Broadcast { text: String },
    /// A presenter logged in where none was (`--presenter-keys`): a student waiting for one
    /// follows it, unless that would lose unsaved work (then only told).
    PresenterArrived,
    /// To a presenter: whether it leads the class now. The newest presenter session leads (a
    /// lecturer who reconnects is not locked out by the old connection); when it leaves, the
    /// one before it leads again.
    Lead(bool),
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
    /// A student: a presenter is connected (without one, a student steps a lesson on their
    /// own).
    pub presenter_here: bool,
    /// A presenter: it leads the class (its frames are what the students follow).
    pub leads: bool,
    /// A student on their own because no presenter was there to follow (they joined before
    /// one, or the one they followed left): they follow the next presenter to log in, unless
    /// they hold unsaved work then.
    pub waiting: bool,
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
    /// A student, `user`, who follows from the start (a presenter is connected).
    pub fn student(followers: &Arc<Followers>, user: &str) -> Follow {
        Follow {
            role: Role::Student(Some(Following::new(followers))),
            followers: Arc::clone(followers),
            latest: None,
            seat: Some(Seat::new(followers, user)),
            ends_class: false,
            presenter_here: true,
            leads: false,
            waiting: false,
        }
    }

    /// A student, `user`, who joins while no presenter is connected: on their own, and
    /// following the first presenter to log in ([`ClassNews::PresenterArrived`]).
    pub fn student_without_presenter(followers: &Arc<Followers>, user: &str) -> Follow {
        Follow {
            role: Role::Student(None),
            followers: Arc::clone(followers),
            latest: None,
            seat: Some(Seat::new(followers, user)),
            ends_class: false,
            presenter_here: false,
            leads: false,
            waiting: true,
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
            presenter_here: true,
            leads: true,
            waiting: false,
        }
    }

    /// A student's key, click or paste: their idle time starts again.
    pub fn note_input(&self, now: Instant) {
        if let Some(seat) = &self.seat {
            *lock(&seat.last_input) = now;
        }
    }

    /// A student's unsaved work and whether they follow, for the presenter's question and
    /// list (`update` tells it after every message).
    pub fn note_state(&self, unsaved: bool) {
        let Some(seat) = &self.seat else {
            return;
        };
        let following = self.is_following();
        if seat.following.swap(following, Ordering::AcqRel) != following {
            seat.followers.changed();
        }
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
                    "{} · {count} follow · {students} student{}",
                    if self.leads {
                        "presenting"
                    } else {
                        "presenting (another presenter leads)"
                    },
                    if students == 1 { "" } else { "s" }
                )
            }
            Role::Student(Some(_)) => format!("following the presenter · {count} follow · f forks"),
            Role::Student(None) if !self.presenter_here => {
                "own exploration · no presenter connected".into()
            }
            Role::Student(None) => format!("own exploration · {count} follow · F rejoins"),
        }
    }
}
