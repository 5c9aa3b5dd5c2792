//! Connections before login, counted apart from the sessions (as OpenSSH's `MaxStartups` and
//! `LoginGraceTime` do, but so that a flood never locks a student out): at most
//! [`WAITING_CAP`] wait at once; when a new one comes to a full table, the oldest that has not
//! even begun to log in is dropped (a silent TCP connection, or a handshake in progress), and
//! only when there is none, the oldest that is logging in. A connection must begin to log in
//! within [`HANDSHAKE_GRACE`] and finish within [`LOGIN_GRACE`]. Logged-in connections are
//! never dropped for newcomers, and nothing is keyed by address: a lecture hall sits behind
//! one NAT address.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::sync::Notify;

/// Most connections waiting to log in at once.
pub const WAITING_CAP: usize = 256;
/// How long a new connection has to send its first login request (handshake included).
pub const HANDSHAKE_GRACE: Duration = Duration::from_secs(10);
/// How long a connection has from its start to finish logging in (a person typing a password).
pub const LOGIN_GRACE: Duration = Duration::from_secs(60);

/// One connection's place before login.
#[derive(Debug, Default)]
pub struct Gate {
    /// Dropped to make room, or told to leave.
    dropped: Notify,
    logging_in: AtomicBool,
    logged_in: AtomicBool,
}

impl Gate {
    /// Completes when the connection must end before it logged in: dropped for a newcomer, or
    /// past its grace. Never completes once it logged in.
    pub async fn ended_before_login(&self) {
        let handshake = async {
            tokio::time::sleep(HANDSHAKE_GRACE).await;
            if self.logging_in.load(Ordering::Acquire) {
                tokio::time::sleep(LOGIN_GRACE.saturating_sub(HANDSHAKE_GRACE)).await;
            }
        };
        tokio::select! {
            () = self.dropped.notified() => {}
            () = handshake => {}
        }
        if self.logged_in.load(Ordering::Acquire) {
            std::future::pending::<()>().await;
        }
    }
}

/// The connections waiting to log in: those that have not asked to log in yet, and those that
/// have, each oldest first.
#[derive(Debug, Default)]
pub struct Admission {
    waiting: Mutex<Waiting>,
}

#[derive(Debug, Default)]
struct Waiting {
    silent: VecDeque<Arc<Gate>>,
    logging_in: VecDeque<Arc<Gate>>,
}

impl Waiting {
    fn len(&self) -> usize {
        self.silent.len() + self.logging_in.len()
    }

    fn remove(&mut self, gate: &Arc<Gate>) {
        self.silent.retain(|g| !Arc::ptr_eq(g, gate));
        self.logging_in.retain(|g| !Arc::ptr_eq(g, gate));
    }
}

impl Admission {
    fn lock(&self) -> std::sync::MutexGuard<'_, Waiting> {
        self.waiting.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// A new connection's gate; a full table drops its oldest silent connection first.
    pub fn admit(&self) -> Arc<Gate> {
        let gate = Arc::new(Gate::default());
        let mut waiting = self.lock();
        while waiting.len() >= WAITING_CAP {
            let oldest = match waiting.silent.pop_front() {
                Some(oldest) => oldest,
                None => match waiting.logging_in.pop_front() {
                    Some(oldest) => oldest,
                    None => break,
                },
            };
            oldest.dropped.notify_one();
        }
        waiting.silent.push_back(Arc::clone(&gate));
        gate
    }

    /// The connection asked to log in (its handshake is done).
    pub fn logging_in(&self, gate: &Arc<Gate>) {
        if gate.logging_in.swap(true, Ordering::AcqRel) {
            return;
        }
        let mut waiting = self.lock();
        let before = waiting.silent.len();
        waiting.silent.retain(|g| !Arc::ptr_eq(g, gate));
        // Not moved if it was dropped meanwhile.
        if waiting.silent.len() < before {
            waiting.logging_in.push_back(Arc::clone(gate));
        }
    }

    /// The connection logged in: it waits no more and is never dropped for a newcomer.
    pub fn logged_in(&self, gate: &Arc<Gate>) {
        gate.logged_in.store(true, Ordering::Release);
        self.lock().remove(gate);
    }

    /// The connection ended.
    pub fn left(&self, gate: &Arc<Gate>) {
        self.lock().remove(gate);
    }

    /// Connections waiting to log in now.
    pub fn waiting(&self) -> usize {
        self.lock().len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn is_dropped(gate: &Gate) -> bool {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_time()
            .start_paused(true)
            .build()
            .unwrap();
        runtime.block_on(async {
            tokio::select! {
                biased;
                () = gate.dropped.notified() => true,
                () = tokio::task::yield_now() => false,
            }
        })
    }

    #[test]
    fn a_full_table_drops_the_oldest_silent_connection_and_never_a_logged_in_one() {
        let admission = Admission::default();
        let student = admission.admit();
        admission.logging_in(&student);
        let early = admission.admit();
        admission.logging_in(&early);
        admission.logged_in(&early);
        let silent: Vec<_> = (0..WAITING_CAP - 1).map(|_| admission.admit()).collect();
        assert_eq!(admission.waiting(), WAITING_CAP);
        // The flood goes on: silent ones make room for each other, oldest first.
        let newest = admission.admit();
        assert!(is_dropped(&silent[0]));
        assert!(!is_dropped(&silent[1]));
        assert!(!is_dropped(&student));
        assert!(!is_dropped(&early));
        assert_eq!(admission.waiting(), WAITING_CAP);
        // A student logging in is dropped only once no silent connection is left.
        for gate in silent.iter().skip(1).chain([&newest]) {
            admission.left(gate);
        }
        let others: Vec<_> = (0..WAITING_CAP - 1).map(|_| admission.admit()).collect();
        for gate in &others {
            admission.logging_in(gate);
        }
        admission.admit();
        assert!(is_dropped(&student));
        assert!(!is_dropped(&early));
    }

    #[test]
    fn a_connection_that_never_logs_in_ends_after_its_grace() {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_time()
            .start_paused(true)
            .build()
            .unwrap();
        let admission = Admission::default();
        let silent = admission.admit();
        let slow = admission.admit();
        admission.logging_in(&slow);
        let student = admission.admit();
        admission.logging_in(&student);
        admission.logged_in(&student);
        runtime.block_on(async {
            let start = tokio::time::Instant::now();
            silent.ended_before_login().await;
            assert_eq!(start.elapsed(), HANDSHAKE_GRACE);
            let start = tokio::time::Instant::now();
            slow.ended_before_login().await;
            assert_eq!(start.elapsed(), LOGIN_GRACE);
            let logged_in = tokio::time::timeout(LOGIN_GRACE * 10, student.ended_before_login());
            assert!(
                logged_in.await.is_err(),
                "a logged-in connection never ends here"
            );
        });
    }
}
