//! Fair sharing of the machine's cores between explorers that run in one process (the
//! sessions of `beamfric serve`): every explorer keeps its own workers, but a worker runs a
//! solve or a sweep only while it holds one of at most `limit` permits (the machine's
//! available parallelism). Waiting workers are served in turn, a session that holds no permit
//! before one that already runs something, so one student at n = 10⁵ takes at most its share
//! while 39 others at Benchmark 1 are served between its jobs. A worker waits for its turn
//! before it picks its newest request, so a request that became outdated while waiting is
//! never run, and a key pressed while waiting does not lose the worker its place. The local
//! explorer runs without this (its workers have the machine to themselves).

use std::collections::VecDeque;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::Duration;

/// How often a waiting worker looks whether it should give up (its explorer ended).
const GIVE_UP_POLL: Duration = Duration::from_millis(20);
/// Sessions whose last turn the queue remembers.
const REMEMBERED_SESSIONS: usize = 256;

/// The permits, shared by all sessions of a server.
#[derive(Debug)]
pub struct Cores {
    state: Mutex<Queue>,
    freed: Condvar,
    limit: usize,
    next_session: AtomicU64,
}

/// Who runs and who waits.
#[derive(Debug, Default, Clone)]
pub struct Queue {
    /// The session of every permit held now (one entry per permit).
    pub running: Vec<u64>,
    /// Waiting workers in order of arrival: (ticket, session).
    pub waiting: VecDeque<(u64, u64)>,
    next_ticket: u64,
    /// Sessions in the order they last gave back a permit, the longest ago first (at most
    /// [`REMEMBERED_SESSIONS`]; a session not here was served longer ago than any that is).
    served: VecDeque<u64>,
    /// The most permits ever held at once.
    pub peak: usize,
}

impl Queue {
    /// The ticket served next when a permit is free: among the waiters whose session runs
    /// nothing now (else among all), the one whose session gave back a permit longest ago,
    /// then the first to arrive. So a heavy session whose solve was just replaced does not
    /// pass its other worker, queued long ago, ahead of a light session's new request.
    pub fn next(&self, limit: usize) -> Option<u64> {
        if self.running.len() >= limit {
            return None;
        }
        let first_in_turn = |idle_only: bool| {
            self.waiting
                .iter()
                .filter(|(_, session)| !idle_only || !self.running.contains(session))
                .min_by_key(|(ticket, session)| (self.last_served(*session), *ticket))
                .map(|(ticket, _)| *ticket)
        };
        first_in_turn(true).or_else(|| first_in_turn(false))
    }

    /// When `session` last gave back a permit: `None` (never, or too long ago to remember)
    /// sorts before every remembered turn.
    fn last_served(&self, session: u64) -> Option<usize> {
        self.served.iter().position(|s| *s == session)
    }

    /// Queues a worker of `session`; returns its ticket.
    pub fn arrive(&mut self, session: u64) -> u64 {
        let ticket = self.next_ticket;
        self.next_ticket += 1;
        self.waiting.push_back((ticket, session));
        ticket
    }

    /// `ticket` gets its permit.
    fn grant(&mut self, ticket: u64) {
        if let Some(at) = self.waiting.iter().position(|(t, _)| *t == ticket)
            && let Some((_, session)) = self.waiting.remove(at)
        {
            self.running.push(session);
            self.peak = self.peak.max(self.running.len());
        }
    }

    fn leave(&mut self, ticket: u64) {
        self.waiting.retain(|(t, _)| *t != ticket);
    }

    fn release(&mut self, session: u64) {
        if let Some(at) = self.running.iter().position(|s| *s == session) {
            self.running.swap_remove(at);
        }
        self.served.retain(|s| *s != session);
        self.served.push_back(session);
        if self.served.len() > REMEMBERED_SESSIONS {
            self.served.pop_front();
        }
    }
}

impl Cores {
    /// At most `limit` (at least one) solves and sweeps at once.
    pub fn new(limit: usize) -> Arc<Cores> {
        Arc::new(Cores {
            state: Mutex::default(),
            freed: Condvar::new(),
            limit: limit.max(1),
            next_session: AtomicU64::new(0),
        })
    }

    /// Solves and sweeps that may run at once.
    pub fn limit(&self) -> usize {
        self.limit
    }

    /// As many permits as the machine has cores (its available parallelism).
    pub fn of_this_machine() -> Arc<Cores> {
        Cores::new(std::thread::available_parallelism().map_or(1, |n| n.get()))
    }

    /// A new session's share.
    pub fn session(self: &Arc<Self>) -> Share {
        Share {
            cores: Arc::clone(self),
            session: self.next_session.fetch_add(1, Ordering::Relaxed),
        }
    }

    /// Who runs and who waits now.
    pub fn queue(&self) -> Queue {
        self.lock().clone()
    }

    fn lock(&self) -> MutexGuard<'_, Queue> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// One session's way to the cores (cheap to clone: its solve and sweep workers each hold one).
#[derive(Debug, Clone)]
pub struct Share {
    cores: Arc<Cores>,
    session: u64,
}

/// A permit to run one solve or sweep; given back on drop.
#[derive(Debug)]
pub struct Permit {
    cores: Arc<Cores>,
    session: u64,
}

impl Share {
    /// Waits for a permit in turn; `None` as soon as `give_up()` says the worker is no
    /// longer wanted (its explorer ended).
    pub fn acquire(&self, give_up: &dyn Fn() -> bool) -> Option<Permit> {
        let cores = &self.cores;
        let mut queue = cores.lock();
        let ticket = queue.arrive(self.session);
        loop {
            if queue.next(cores.limit) == Some(ticket) {
                queue.grant(ticket);
                return Some(Permit {
                    cores: Arc::clone(cores),
                    session: self.session,
                });
            }
            if give_up() {
                queue.leave(ticket);
                // Another waiter may be first now.
                cores.freed.notify_all();
                return None;
            }
            queue = cores
                .freed
                .wait_timeout(queue, GIVE_UP_POLL)
                .unwrap_or_else(|e| e.into_inner())
                .0;
        }
    }
}

impl Drop for Permit {
    fn drop(&mut self) {
        self.cores.lock().release(self.session);
        self.cores.freed.notify_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_free_permit_goes_to_a_session_that_runs_nothing_first() {
        let mut queue = Queue::default();
        // Session 0 (the heavy one) runs, and queued again before 1 and 2.
        let first = queue.arrive(0);
        queue.grant(first);
        let heavy_again = queue.arrive(0);
        let light = queue.arrive(1);
        let other = queue.arrive(2);
        // With two permits, the free one goes to session 1, not to the heavy session's
        // second worker that arrived first.
        assert_eq!(queue.next(2), Some(light));
        queue.grant(light);
        // Both permits held: nobody.
        assert_eq!(queue.next(2), None);
        queue.release(1);
        assert_eq!(queue.next(2), Some(other));
        queue.grant(other);
        queue.release(0);
        queue.release(2);
        // Nobody runs: first come, first served.
        assert_eq!(queue.next(2), Some(heavy_again));
        assert_eq!(queue.peak, 2);
    }

    /// Two heavy sessions each with a solve running and a sweep queued long ago, a light one
    /// queued later: when a heavy session's solve is replaced (its permit given back), the
    /// free permit goes to the light session, not to that heavy session's sweep, although
    /// both sessions then run nothing and the sweep came first.
    #[test]
    fn a_session_just_served_waits_behind_one_served_longer_ago() {
        let mut queue = Queue::default();
        for heavy in [0, 1] {
            let solve = queue.arrive(heavy);
            queue.grant(solve);
        }
        let sweep_0 = queue.arrive(0);
        let sweep_1 = queue.arrive(1);
        let light = queue.arrive(2);
        queue.release(0);
        assert_eq!(queue.next(2), Some(light));
        queue.grant(light);
        queue.release(2);
        // Now session 0 gave its permit back before session 2 did: its sweep goes first.
        assert_eq!(queue.next(2), Some(sweep_0));
        queue.grant(sweep_0);
        queue.release(1);
        assert_eq!(queue.next(2), Some(sweep_1));
    }

    #[test]
    fn waiting_workers_are_served_in_turn_and_never_more_than_the_limit_run() {
        let cores = Cores::new(2);
        let running = Arc::new(std::sync::atomic::AtomicUsize::new(0));
        let most = Arc::new(std::sync::atomic::AtomicUsize::new(0));
        let threads: Vec<_> = (0..8)
            .map(|_| {
                let share = cores.session();
                let (running, most) = (Arc::clone(&running), Arc::clone(&most));
                std::thread::spawn(move || {
                    for _ in 0..20 {
                        let permit = share.acquire(&|| false).unwrap();
                        let now = running.fetch_add(1, Ordering::SeqCst) + 1;
                        most.fetch_max(now, Ordering::SeqCst);
                        std::thread::yield_now();
                        running.fetch_sub(1, Ordering::SeqCst);
                        drop(permit);
                    }
                })
            })
            .collect();
        for thread in threads {
            thread.join().unwrap();
        }
        assert!(most.load(Ordering::SeqCst) <= 2);
        assert!(cores.queue().peak <= 2);
        assert!(cores.queue().running.is_empty() && cores.queue().waiting.is_empty());
    }

    #[test]
    fn a_worker_that_gives_up_leaves_the_queue() {
        let cores = Cores::new(1);
        let holder = cores.session().acquire(&|| false).unwrap();
        assert!(cores.session().acquire(&|| true).is_none());
        assert!(cores.queue().waiting.is_empty());
        drop(holder);
        assert!(cores.queue().running.is_empty());
    }
}
