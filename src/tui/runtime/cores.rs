//! Fair sharing of the machine's cores between explorers that run in one process (the
//! sessions of `beamfric serve`): every explorer keeps its own workers, but a worker runs a
//! solve or a sweep only while it holds one of at most `limit` permits (the machine's
//! available parallelism). Waiting workers are served in turn, a session that holds no permit
//! before one that already runs something, so one student at n = 10⁵ takes at most its share
//! while 39 others at Benchmark 1 are served between its jobs. A worker waits for its turn
//! before it picks its newest request, so a request that became outdated while waiting is
//! never run, and a key pressed while waiting does not lose the worker its place. Sharing is by
//! turns, not time slices, so a quick job (a solve of a few milliseconds, such as Benchmark 1)
//! would wait for a heavy one to end; instead it may take one of `limit` express permits, used
//! only by quick jobs of sessions that run nothing else, and runs beside the heavy ones. The
//! local explorer runs without this (its workers have the machine to themselves).

use std::collections::VecDeque;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::Duration;

/// How often a waiting worker looks whether it should give up (its explorer ended).
const GIVE_UP_POLL: Duration = Duration::from_millis(20);
/// Sessions whose last turn the queue remembers.
const REMEMBERED_SESSIONS: usize = 256;

/// A worker waiting for a permit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Waiter {
    pub ticket: u64,
    pub session: u64,
    /// Its job takes milliseconds: it may take an express permit.
    pub quick: bool,
}

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
    /// The session of every express permit held now (quick jobs only).
    pub express: Vec<u64>,
    /// Waiting workers in order of arrival.
    pub waiting: VecDeque<Waiter>,
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
    /// When every permit is held, an express permit (at most `limit` of them) goes the same way
    /// to a quick waiter whose session runs nothing.
    pub fn next(&self, limit: usize) -> Option<u64> {
        let first_in_turn = |admits: &dyn Fn(&Waiter) -> bool| {
            self.waiting
                .iter()
                .filter(|w| admits(w))
                .min_by_key(|w| (self.last_served(w.session), w.ticket))
                .map(|w| w.ticket)
        };
        if self.running.len() < limit {
            return first_in_turn(&|w| !self.runs(w.session)).or_else(|| first_in_turn(&|_| true));
        }
        if self.express.len() < limit {
            return first_in_turn(&|w| w.quick && !self.runs(w.session));
        }
        None
    }

    /// Whether `session` holds a permit of either kind.
    fn runs(&self, session: u64) -> bool {
        self.running.contains(&session) || self.express.contains(&session)
    }

    /// When `session` last gave back a permit: `None` (never, or too long ago to remember)
    /// sorts before every remembered turn.
    fn last_served(&self, session: u64) -> Option<usize> {
        self.served.iter().position(|s| *s == session)
    }

    /// Queues a worker of `session` (`quick`: its job takes milliseconds); returns its ticket.
    pub fn arrive(&mut self, session: u64, quick: bool) -> u64 {
        let ticket = self.next_ticket;
        self.next_ticket += 1;
        self.waiting.push_back(Waiter {
            ticket,
            session,
            quick,
        });
        ticket
    }

    /// `ticket` gets its permit: an express one when every other is held. Whether it was.
    fn grant(&mut self, ticket: u64, limit: usize) -> bool {
        let Some(at) = self.waiting.iter().position(|w| w.ticket == ticket) else {
            return false;
        };
        let Some(waiter) = self.waiting.remove(at) else {
            return false;
        };
        if self.running.len() < limit {
            self.running.push(waiter.session);
            self.peak = self.peak.max(self.running.len());
            false
        } else {
            self.express.push(waiter.session);
            true
        }
    }

    fn leave(&mut self, ticket: u64) {
        self.waiting.retain(|w| w.ticket != ticket);
    }

    fn release(&mut self, session: u64, express: bool) {
        let held = if express {
            &mut self.express
        } else {
            &mut self.running
        };
        if let Some(at) = held.iter().position(|s| *s == session) {
            held.swap_remove(at);
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
    express: bool,
}

impl Permit {
    /// An express permit: only for a quick job.
    pub fn is_express(&self) -> bool {
        self.express
    }
}

impl Share {
    /// Waits for a permit in turn (`quick`: for a job of milliseconds, which may take an
    /// express permit); `None` as soon as `give_up()` says the worker is no longer wanted
    /// (its explorer ended).
    pub fn acquire(&self, quick: bool, give_up: &dyn Fn() -> bool) -> Option<Permit> {
        let cores = &self.cores;
        let mut queue = cores.lock();
        let ticket = queue.arrive(self.session, quick);
        loop {
            if queue.next(cores.limit) == Some(ticket) {
                let express = queue.grant(ticket, cores.limit);
                return Some(Permit {
                    cores: Arc::clone(cores),
                    session: self.session,
                    express,
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
        self.cores.lock().release(self.session, self.express);
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
        let first = queue.arrive(0, false);
        queue.grant(first, 2);
        let heavy_again = queue.arrive(0, false);
        let light = queue.arrive(1, false);
        let other = queue.arrive(2, false);
        // With two permits, the free one goes to session 1, not to the heavy session's
        // second worker that arrived first.
        assert_eq!(queue.next(2), Some(light));
        queue.grant(light, 2);
        // Both permits held: nobody.
        assert_eq!(queue.next(2), None);
        queue.release(1, false);
        assert_eq!(queue.next(2), Some(other));
        queue.grant(other, 2);
        queue.release(0, false);
        queue.release(2, false);
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
            let solve = queue.arrive(heavy, false);
            queue.grant(solve, 2);
        }
        let sweep_0 = queue.arrive(0, false);
        let sweep_1 = queue.arrive(1, false);
        let light = queue.arrive(2, false);
        queue.release(0, false);
        assert_eq!(queue.next(2), Some(light));
        queue.grant(light, 2);
        queue.release(2, false);
        // Now session 0 gave its permit back before session 2 did: its sweep goes first.
        assert_eq!(queue.next(2), Some(sweep_0));
        queue.grant(sweep_0, 2);
        queue.release(1, false);
        assert_eq!(queue.next(2), Some(sweep_1));
    }

    /// Both permits held by heavy solves: a quick job of a session that runs nothing takes an
    /// express permit at once; a slow job, or a quick one of a session already running, waits;
    /// never more express permits than the limit.
    #[test]
    fn a_quick_job_runs_beside_the_heavy_ones_on_an_express_permit() {
        let mut queue = Queue::default();
        for heavy in [0, 1] {
            let solve = queue.arrive(heavy, false);
            assert!(!queue.grant(solve, 2));
        }
        let slow = queue.arrive(2, false);
        let quick_of_running = queue.arrive(0, true);
        let quick = queue.arrive(3, true);
        assert_eq!(queue.next(2), Some(quick));
        assert!(queue.grant(quick, 2));
        let another = queue.arrive(4, true);
        assert_eq!(queue.next(2), Some(another));
        assert!(queue.grant(another, 2));
        // Two express permits held: a third quick job waits.
        let third = queue.arrive(5, true);
        assert_eq!(queue.next(2), None);
        queue.release(3, true);
        assert_eq!(queue.next(2), Some(third));
        assert_eq!(queue.express, vec![4]);
        // A heavy permit given back goes the ordinary way, to the slow job first in turn.
        queue.release(1, false);
        assert_eq!(queue.next(2), Some(slow));
        assert_eq!(queue.peak, 2);
        assert!(queue.waiting.iter().any(|w| w.ticket == quick_of_running));
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
                        let permit = share.acquire(false, &|| false).unwrap();
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
        let holder = cores.session().acquire(false, &|| false).unwrap();
        assert!(cores.session().acquire(false, &|| true).is_none());
        assert!(cores.queue().waiting.is_empty());
        drop(holder);
        assert!(cores.queue().running.is_empty());
    }
}
