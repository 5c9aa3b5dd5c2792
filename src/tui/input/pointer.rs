//! The mouse as input: what a press, a drag, a release or a turn of the wheel at a cell is,
//! telling a double click by the time between two presses (which only the runtime knows: a
//! frame never depends on the clock). `tui::update::pointer` decides what it does, from what
//! is drawn under it (`tui::layout::hit`).

use std::time::{Duration, Instant};

use super::decode::MouseInput;

/// Two presses at the same cell within this time are a double click.
pub const DOUBLE_CLICK: Duration = Duration::from_millis(400);

/// A mouse event at column `x`, row `y` (0-based).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pointer {
    /// A button pressed; `double` when it is the second press at that cell within
    /// [`DOUBLE_CLICK`].
    Click { x: u16, y: u16, double: bool },
    /// The mouse moved with a button held.
    Drag { x: u16, y: u16 },
    /// The button was let go.
    Release { x: u16, y: u16 },
    /// The wheel turned: `up` away from the user.
    Scroll { x: u16, y: u16, up: bool },
}

/// Tells double clicks from single ones by the time between presses.
#[derive(Debug, Default)]
pub struct ClickTracker {
    last: Option<(Instant, u16, u16)>,
}

impl ClickTracker {
    /// A press at `x`, `y` at `now`: is it the second of a double click? (A third press
    /// starts again.)
    pub fn press(&mut self, x: u16, y: u16, now: Instant) -> bool {
        let double = self.last.is_some_and(|(at, px, py)| {
            px == x && py == y && now.saturating_duration_since(at) <= DOUBLE_CLICK
        });
        self.last = if double { None } else { Some((now, x, y)) };
        double
    }

    /// The pointer event of a decoded mouse input at `now`.
    pub fn pointer(&mut self, x: u16, y: u16, what: MouseInput, now: Instant) -> Pointer {
        match what {
            MouseInput::Press => Pointer::Click {
                x,
                y,
                double: self.press(x, y, now),
            },
            MouseInput::Drag => Pointer::Drag { x, y },
            MouseInput::Release => Pointer::Release { x, y },
            MouseInput::ScrollUp => Pointer::Scroll { x, y, up: true },
            MouseInput::ScrollDown => Pointer::Scroll { x, y, up: false },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_press_at_the_same_cell_soon_is_a_double_click() {
        let mut clicks = ClickTracker::default();
        let t0 = Instant::now();
        assert!(!clicks.press(5, 5, t0));
        assert!(clicks.press(5, 5, t0 + Duration::from_millis(200)));
        // A third press starts again.
        assert!(!clicks.press(5, 5, t0 + Duration::from_millis(300)));
        // Too late, or elsewhere.
        assert!(!clicks.press(5, 5, t0 + Duration::from_millis(1000)));
        assert!(!clicks.press(6, 5, t0 + Duration::from_millis(1100)));
        assert!(clicks.press(6, 5, t0 + Duration::from_millis(1100) + DOUBLE_CLICK));
    }
}
