//! Waiting for a condition instead of sleeping or timing: poll until it holds. The deadline,
//! [`PATIENCE`], only guards against a hang (a healthy run is far below it); it is never a
//! measurement, so a slow or busy machine makes a test slower, not red.

use std::time::{Duration, Instant};

/// The longest any wait of the suite lasts before it fails.
pub const PATIENCE: Duration = Duration::from_secs(60);

/// How often a polled condition is looked at.
const POLL: Duration = Duration::from_millis(10);

/// When a wait that starts now gives up.
pub fn deadline() -> Instant {
    Instant::now() + PATIENCE
}

/// Waits until `condition` holds; fails after [`PATIENCE`] saying that `what` never happened.
pub fn eventually(what: &str, condition: impl FnMut() -> bool) {
    eventually_or(what, condition, String::new);
}

/// [`eventually`], with `context()` (say, the screen at that moment) in the failure.
pub fn eventually_or(
    what: &str,
    mut condition: impl FnMut() -> bool,
    context: impl Fn() -> String,
) {
    until(what, || condition().then_some(()), context)
}

/// Waits until `value` gives something, and returns it; fails as [`eventually_or`] does.
pub fn until<T>(
    what: &str,
    mut value: impl FnMut() -> Option<T>,
    context: impl Fn() -> String,
) -> T {
    let deadline = deadline();
    loop {
        if let Some(value) = value() {
            return value;
        }
        if Instant::now() > deadline {
            panic!("never: {what} (gave up after {PATIENCE:?})\n{}", context());
        }
        // A sleep inside a polling loop: the condition decides, not the time.
        std::thread::sleep(POLL);
    }
}
