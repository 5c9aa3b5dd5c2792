//! A served session's time budget: its event loop may keep one core busy for only a share of
//! the time on average (a token bucket of seconds, with a burst of up to a second), so a flood
//! of keys or window changes that would cost seconds each second is slowed to that share
//! instead of queueing work the session would go on doing after its client left.

use std::time::{Duration, Instant};

/// Seconds of work a loop may still do now; refilled at `share` seconds per second.
#[derive(Debug)]
pub struct TimeBudget {
    /// Seconds of credit (negative: owed).
    available: f64,
    share: f64,
    burst: f64,
    last: Instant,
}

impl TimeBudget {
    /// A budget of `share` (0 < share ≤ 1) of one core, starting full with `burst` of credit.
    pub fn new(share: f64, burst: Duration) -> TimeBudget {
        let share = if share.is_finite() {
            share.clamp(0.01, 1.0)
        } else {
            1.0
        };
        TimeBudget {
            available: burst.as_secs_f64(),
            share,
            burst: burst.as_secs_f64(),
            last: Instant::now(),
        }
    }

    /// Counts `spent` of work.
    pub fn spend(&mut self, spent: Duration) {
        self.refill(Instant::now());
        self.available -= spent.as_secs_f64();
    }

    /// How long to rest before more work: zero while there is credit.
    pub fn rest(&mut self) -> Duration {
        self.rest_at(Instant::now())
    }

    fn rest_at(&mut self, now: Instant) -> Duration {
        self.refill(now);
        if self.available >= 0.0 {
            Duration::ZERO
        } else {
            Duration::from_secs_f64(-self.available / self.share)
        }
    }

    fn refill(&mut self, now: Instant) {
        let elapsed = now.saturating_duration_since(self.last).as_secs_f64();
        self.last = now;
        self.available = (self.available + elapsed * self.share).min(self.burst);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn work_beyond_the_burst_is_paid_back_at_the_share() {
        let mut budget = TimeBudget::new(0.5, Duration::from_secs(1));
        let start = budget.last;
        budget.available -= 0.4;
        assert_eq!(budget.rest_at(start), Duration::ZERO);
        // 1.6 s of work in all: 0.6 s owed, paid back at half a second per second.
        budget.available -= 1.2;
        let rest = budget.rest_at(start);
        assert!((rest.as_secs_f64() - 1.2).abs() < 1e-9, "{rest:?}");
        assert_eq!(
            budget.rest_at(start + Duration::from_millis(1200)),
            Duration::ZERO
        );
        // Credit never grows beyond the burst.
        let _ = budget.rest_at(start + Duration::from_secs(1000));
        assert!((budget.available - 1.0).abs() < 1e-9);
    }
}
