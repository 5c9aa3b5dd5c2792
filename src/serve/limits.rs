//! The server's limits: a cap on concurrent explorers (a slot is held for as long as the
//! explorer's thread runs, so a count that drops means its workers were let go), and a bound
//! on the bytes a client may type per second (a token bucket: bursts such as a paste pass,
//! a flood is cut).

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// Counts the explorers running; at most `max` at once.
#[derive(Debug)]
pub struct SessionSlots {
    running: AtomicUsize,
    max: usize,
}

/// One running explorer; its slot is freed on drop.
#[derive(Debug)]
pub struct SessionSlot(Arc<SessionSlots>);

impl SessionSlots {
    pub fn new(max: usize) -> Arc<SessionSlots> {
        Arc::new(SessionSlots {
            running: AtomicUsize::new(0),
            max,
        })
    }

    /// A slot, unless `max` explorers are running.
    pub fn take(self: &Arc<Self>) -> Option<SessionSlot> {
        self.running
            .fetch_update(Ordering::AcqRel, Ordering::Acquire, |n| {
                (n < self.max).then_some(n + 1)
            })
            .ok()
            .map(|_| SessionSlot(Arc::clone(self)))
    }

    /// Explorers running now.
    pub fn running(&self) -> usize {
        self.running.load(Ordering::Acquire)
    }

    pub fn max(&self) -> usize {
        self.max
    }
}

impl Drop for SessionSlot {
    fn drop(&mut self) {
        self.0.running.fetch_sub(1, Ordering::AcqRel);
    }
}

/// Bytes per second a client may type (and the burst it may send at once).
pub const INPUT_BYTES_PER_SECOND: usize = 32 * 1024;

/// What a window change costs of the input budget, in bytes.
pub const WINDOW_CHANGE_BYTES: usize = 64;

/// A token bucket of input bytes.
#[derive(Debug)]
pub struct InputBudget {
    available: f64,
    per_second: f64,
    last: Instant,
}

impl InputBudget {
    pub fn new(per_second: usize) -> InputBudget {
        InputBudget {
            available: per_second as f64,
            per_second: per_second as f64,
            last: Instant::now(),
        }
    }

    /// How many of `wanted` bytes may pass now.
    pub fn take(&mut self, wanted: usize) -> usize {
        self.take_at(wanted, Instant::now())
    }

    fn take_at(&mut self, wanted: usize, now: Instant) -> usize {
        let elapsed = now.saturating_duration_since(self.last).as_secs_f64();
        self.last = now;
        self.available = (self.available + elapsed * self.per_second).min(self.per_second);
        let granted = (wanted as f64).min(self.available.floor()).max(0.0);
        self.available -= granted;
        granted as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn slots_are_capped_and_freed_on_drop() {
        let slots = SessionSlots::new(2);
        let a = slots.take().unwrap();
        let _b = slots.take().unwrap();
        assert!(slots.take().is_none());
        assert_eq!(slots.running(), 2);
        drop(a);
        assert_eq!(slots.running(), 1);
        assert!(slots.take().is_some());
    }

    #[test]
    fn the_budget_passes_a_burst_cuts_a_flood_and_refills() {
        let start = Instant::now();
        let mut budget = InputBudget::new(1000);
        budget.last = start;
        assert_eq!(budget.take_at(600, start), 600);
        assert_eq!(budget.take_at(600, start), 400);
        assert_eq!(budget.take_at(10, start), 0);
        // Half a second later, half the budget is back; never more than one second's worth.
        assert_eq!(
            budget.take_at(1000, start + Duration::from_millis(500)),
            500
        );
        assert_eq!(budget.take_at(5000, start + Duration::from_secs(100)), 1000);
    }
}
