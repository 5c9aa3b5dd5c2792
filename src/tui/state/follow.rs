//! Follow mode, in the explorer's state: an explorer's role (presenter, student following,
//! student exploring on its own), the presenter's newest state kept for rejoining, and the
//! count of followers shared by every explorer of a server. Who presents and who follows is
//! decided by the server (`crate::serve`); what arrives and what the keys do is
//! `tui::update::follow`.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use super::exploration::Exploration;

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
    pub latest: Option<Arc<Exploration>>,
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
            Role::Presenter => format!("presenting · {count} follow"),
            Role::Student(Some(_)) => format!("following the presenter · {count} follow · f forks"),
            Role::Student(None) => format!("own exploration · {count} follow · F rejoins"),
        }
    }
}
