//! Giving up on long numerical work: a kernel that can run for more than a few milliseconds
//! takes a `stop` question ([`Stop`], the caller's "should this end now?", `Sync` because the
//! sweeps over independent stretches run on two threads) and asks
//! it every millisecond or so of work, ending with [`Stopped`] when the answer is yes. The
//! arithmetic does not depend on it: a computation that is not stopped gives the same bits as
//! one that is never asked.

/// The caller's question "should this work stop now?".
pub type Stop<'a> = &'a (dyn Fn() -> bool + Sync);

/// Never stops.
pub const NEVER: Stop<'static> = &never;

fn never() -> bool {
    false
}

/// The work was given up because its `stop` said so.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Stopped;

/// Multiply-adds between two questions: about a millisecond of dense work, so that asking
/// costs nothing measurable and an answer of yes is heard within milliseconds.
const WORK_BETWEEN_QUESTIONS: usize = 1 << 20;

/// Asks `stop` once every [`WORK_BETWEEN_QUESTIONS`] multiply-adds of work reported to it:
/// small problems never ask at all.
pub struct StopCheck<'a> {
    stop: Stop<'a>,
    work_since: usize,
}

impl<'a> StopCheck<'a> {
    pub fn new(stop: Stop<'a>) -> StopCheck<'a> {
        StopCheck {
            stop,
            work_since: 0,
        }
    }

    /// Counts `work` multiply-adds done; [`Stopped`] when it is time to ask and `stop` says so.
    #[inline]
    pub fn after(&mut self, work: usize) -> Result<(), Stopped> {
        self.work_since += work;
        if self.work_since < WORK_BETWEEN_QUESTIONS {
            return Ok(());
        }
        self.work_since = 0;
        self.now()
    }

    /// Asks now, whatever the work since the last question.
    pub fn now(&self) -> Result<(), Stopped> {
        if (self.stop)() { Err(Stopped) } else { Ok(()) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn asks_once_per_millisecond_of_work() {
        let asked = AtomicUsize::new(0);
        let stop = || asked.fetch_add(1, Ordering::Relaxed) + 1 >= 3;
        let mut check = StopCheck::new(&stop);
        for _ in 0..1000 {
            check.after(1000).unwrap();
        }
        assert_eq!(
            asked.load(Ordering::Relaxed),
            0,
            "a million multiply-adds is below one question"
        );
        assert_eq!(check.after(WORK_BETWEEN_QUESTIONS), Ok(()));
        assert_eq!(check.after(WORK_BETWEEN_QUESTIONS), Ok(()));
        assert_eq!(check.after(WORK_BETWEEN_QUESTIONS), Err(Stopped));
        assert!(!NEVER());
    }
}
