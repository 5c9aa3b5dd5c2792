//! Follow mode, on the server's side: the hub that takes each frame's state of a presenter
//! (a session logged in with a key of `--presenter-keys`) and hands it to every student's
//! explorer, which shows it while following. The presenter's solve and sweeps travel with
//! the state, so they are computed once, not once per student. Of several presenters the
//! newest leads. It also tells the students when a presenter arrives where none was (those
//! waiting for one follow), when the last leaves (they get their keys back) and when the
//! class ends (each shows its closing screen).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use crate::tui::runtime::remote::Feed;
use crate::tui::state::Exploration;
use crate::tui::state::follow::{ClassNews, Followers};

/// Feeds by id.
type Feeds = Mutex<Vec<(u64, Feed)>>;

/// The students' and presenters' feeds and the presenter's newest state.
pub struct Hub {
    students: Arc<Feeds>,
    presenters: Arc<Feeds>,
    latest: Mutex<Option<Arc<Exploration>>>,
    next_id: AtomicU64,
    /// Students following now; presenters redraw when it changes.
    pub followers: Arc<Followers>,
}

impl Default for Hub {
    fn default() -> Hub {
        let presenters: Arc<Feeds> = Arc::default();
        let students: Arc<Feeds> = Arc::default();
        let told = Arc::clone(&presenters);
        let followers = Followers::new(move || {
            for (_, feed) in lock(&told).iter() {
                feed.redraw();
            }
        });
        // A presenter's word (bring everyone back, a broadcast line) goes to every student.
        let class = Arc::clone(&students);
        followers.set_announce(move |news| tell(&class, news));
        Hub {
            students,
            presenters,
            latest: Mutex::default(),
            next_id: AtomicU64::new(0),
            followers,
        }
    }
}

impl std::fmt::Debug for Hub {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Hub")
            .field("followers", &self.followers.count())
            .finish_non_exhaustive()
    }
}

impl Hub {
    /// A student joins: its feed hears every new state from now on. Returns its id (for
    /// [`Hub::leave`]), the newest state so far and whether a presenter is connected (without
    /// one, the student starts on their own and hears [`ClassNews::PresenterArrived`]).
    pub fn join(&self, feed: Feed) -> (u64, Option<Arc<Exploration>>, bool) {
        let id = self.next_id.fetch_add(1, Ordering::Relaxed);
        // Listed before it asks: a presenter arriving meanwhile tells it.
        lock(&self.students).push((id, feed));
        let presenter_here = !lock(&self.presenters).is_empty();
        (id, lock(&self.latest).clone(), presenter_here)
    }

    /// A presenter joins and leads (the newest presenter leads: a lecturer who reconnects is
    /// not locked out by a connection that has not yet timed out); the one that led hears it
    /// no longer does, and where none was there, every student hears that one arrived. It
    /// hears when the number of followers changes. Returns its id.
    pub fn join_presenter(&self, feed: Feed) -> u64 {
        let id = self.next_id.fetch_add(1, Ordering::Relaxed);
        // Told under the presenters' lock, so that the students hear of arrivals and
        // departures in the order they happened (a presenter leaving as another joins).
        let mut presenters = lock(&self.presenters);
        if let Some((_, leader)) = presenters.last() {
            leader.class_news(ClassNews::Lead(false));
        }
        presenters.push((id, feed));
        if presenters.len() == 1 {
            self.tell_students(ClassNews::PresenterArrived);
        }
        id
    }

    /// A student or presenter left. When the leading presenter leaves, the one before it
    /// leads again; when the last leaves, every student hears it (a follower gets its keys
    /// back).
    pub fn leave(&self, id: u64) {
        lock(&self.students).retain(|(student, _)| *student != id);
        // Under the presenters' lock, as in `join_presenter` (the students' lock is only ever
        // taken inside it, never the other way round).
        let mut presenters = lock(&self.presenters);
        let led = presenters.last().is_some_and(|(leader, _)| *leader == id);
        let before = presenters.len();
        presenters.retain(|(presenter, _)| *presenter != id);
        if led && let Some((_, leader)) = presenters.last() {
            leader.class_news(ClassNews::Lead(true));
        }
        if before > 0 && presenters.is_empty() {
            self.tell_students(ClassNews::PresenterLeft);
        }
    }

    /// The class ends, by `by`: every student's explorer shows its closing screen. Returns how
    /// many students were told.
    pub fn end_class(&self, by: &str) -> usize {
        self.tell_students(ClassNews::Ended { by: by.to_string() })
    }

    fn tell_students(&self, news: ClassNews) -> usize {
        tell(&self.students, news)
    }

    /// The newest state a leading presenter published, if any.
    pub fn latest(&self) -> Option<Arc<Exploration>> {
        lock(&self.latest).clone()
    }

    /// Presenter `id` drew a frame: where it leads, its state goes to every student.
    pub fn publish(&self, id: u64, exploration: &Exploration) {
        let leads = lock(&self.presenters)
            .last()
            .is_some_and(|(leader, _)| *leader == id);
        if !leads {
            return;
        }
        let snapshot = Arc::new(exploration.clone());
        *lock(&self.latest) = Some(Arc::clone(&snapshot));
        for (_, feed) in lock(&self.students).iter() {
            feed.follow(Arc::clone(&snapshot));
        }
    }
}

/// Tells every student's feed `news`; returns how many.
fn tell(students: &Feeds, news: ClassNews) -> usize {
    let students = lock(students);
    for (_, feed) in students.iter() {
        feed.class_news(news.clone());
    }
    students.len()
}

fn lock<T>(mutex: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(|e| e.into_inner())
}
