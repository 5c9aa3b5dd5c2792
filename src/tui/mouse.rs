//! The mouse: what a press, a drag, a release or a turn of the wheel at a cell means. The
//! terminal reports the mouse as SGR sequences (`tui::input` decodes them); the event loop
//! turns them into [`Action`]s here (telling a double click by the time between two presses,
//! which only the event loop knows), and `tui::update` applies them, finding what is under
//! the pointer with [`target`] — from the same layout the frame is drawn with
//! ([`crate::tui::view::screen_layout`], [`crate::tui::view::picker_layout`] and the
//! deflection chart's [`crate::tui::view::deflection_columns`]), so a click lands on what is
//! drawn there. Everything here is a pure function of the state.
//!
//! The terminal is asked for button presses, drags and releases (modes 1000 and 1002, no
//! motion without a button: little traffic over SSH) in SGR encoding (1006, any column);
//! Shift+drag still selects text in the usual terminals.

use std::time::{Duration, Instant};

use ratatui::layout::Rect;

use super::app::{App, Mode};
use super::input::MouseInput;
use super::keymap::Action;
use super::params::Row;
use super::view::{Region, deflection_columns, picker_layout, screen_layout};
use crate::scene::Panel;

/// Two presses at the same cell within this time are a double click.
pub const DOUBLE_CLICK: Duration = Duration::from_millis(400);

/// Asks the terminal to report presses, drags and releases, SGR-encoded.
pub const MOUSE_ON: &str = "\x1b[?1000h\x1b[?1002h\x1b[?1006h";
/// Stops the reports (also the any-motion mode 1003 and the urxvt encoding 1015 that other
/// programs may have left on).
pub const MOUSE_OFF: &str = "\x1b[?1006l\x1b[?1015l\x1b[?1003l\x1b[?1002l\x1b[?1000l";

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
}

/// The action of a mouse event at column `x`, row `y` (0-based).
pub fn action(x: u16, y: u16, what: MouseInput, clicks: &mut ClickTracker, now: Instant) -> Action {
    match what {
        MouseInput::Press => Action::Click {
            x,
            y,
            double: clicks.press(x, y, now),
        },
        MouseInput::Drag => Action::Drag { x, y },
        MouseInput::Release => Action::Release { x, y },
        MouseInput::ScrollUp => Action::Scroll { x, y, up: true },
        MouseInput::ScrollDown => Action::Scroll { x, y, up: false },
    }
}

/// What is under the pointer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// A parameter row (an index into [`App::rows`]).
    Row(usize),
    /// Elsewhere in the parameters box (its border, or below the last row).
    Parameters,
    /// An obstacle's marker on the deflection chart (within a column of it).
    Obstacle(usize),
    /// A panel (an index into [`App::panels`]); `title` on its top border, where the title is.
    Panel { index: usize, title: bool },
    /// The status lines, where the warnings are.
    Status,
    /// An entry of the preset picker's list (an index into its filtered list).
    PickerEntry(usize),
    /// Inside the preset picker, on no entry.
    Picker,
    /// Outside the preset picker while it is open.
    OutsidePicker,
    /// Nothing that reacts to the mouse.
    Nothing,
}

/// The whole screen of the app's last known size.
fn screen(app: &App) -> Rect {
    Rect::new(0, 0, app.size.0, app.size.1)
}

/// What is at column `x`, row `y` of the frame the app draws now.
pub fn target(app: &App, x: u16, y: u16) -> Target {
    let position = ratatui::layout::Position { x, y };
    if let Mode::Presets(picker) = &app.mode {
        let layout = picker_layout(screen(app));
        if !layout.outer.contains(position) {
            return Target::OutsidePicker;
        }
        if layout.list.contains(position) {
            let entry = picker.offset + usize::from(y - layout.list.y);
            if entry < picker.matches().len() {
                return Target::PickerEntry(entry);
            }
        }
        return Target::Picker;
    }
    let Some(layout) = screen_layout(app, screen(app)) else {
        return Target::Nothing;
    };
    match layout.region_at(x, y) {
        Some(Region::Parameters) => {
            let parameters = layout.parameters;
            let inner_top = parameters.y + 1;
            let inner_height = parameters.height.saturating_sub(2);
            let inside_rows = y >= inner_top && y < inner_top + inner_height;
            let inside_columns = x > parameters.x && x + 1 < parameters.right();
            if !(inside_rows && inside_columns) {
                return Target::Parameters;
            }
            let row = app.parameters_offset(usize::from(inner_height)) + usize::from(y - inner_top);
            if row < app.rows().len() {
                Target::Row(row)
            } else {
                Target::Parameters
            }
        }
        Some(Region::Panel(panel)) => {
            let Some(&(_, area)) = layout.panels.iter().find(|(p, _)| *p == panel) else {
                return Target::Nothing;
            };
            if panel == Panel::Deflection
                && let Some(index) = obstacle_at(app, area, x, y)
            {
                return Target::Obstacle(index);
            }
            let index = app.panels().iter().position(|p| *p == panel).unwrap_or(0);
            Target::Panel {
                index,
                title: y == area.y,
            }
        }
        Some(Region::Status) => Target::Status,
        _ => Target::Nothing,
    }
}

/// The obstacle whose marker is within a column of `x` on the deflection chart in `area`
/// (the nearest), when `x`, `y` is inside the plot.
fn obstacle_at(app: &App, area: Rect, x: u16, y: u16) -> Option<usize> {
    let columns = deflection_columns(app, area)?;
    if !columns.contains(x, y) {
        return None;
    }
    app.scene
        .obstacles
        .iter()
        .enumerate()
        .map(|(i, o)| (i, columns.column_of(o.x).abs_diff(x)))
        .filter(|(_, distance)| *distance <= 1)
        .min_by_key(|(_, distance)| *distance)
        .map(|(i, _)| i)
}

/// The largest of 1, 2 or 5 × 10^k not above `value` (positive and finite).
fn nice_step(value: f64) -> f64 {
    let decade = 10f64.powf(value.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|step| *step <= value)
        .unwrap_or(decade)
}

/// Where a drag to column `x` puts obstacle `index`: the position drawn at that column,
/// rounded to a round step no coarser than a column, and kept a thousandth of l from its
/// neighbours and the supports (as the arrow keys do), so the obstacles keep their order.
/// `None` when no deflection chart is on screen.
pub fn dragged_position(app: &App, index: usize, x: u16) -> Option<f64> {
    let layout = screen_layout(app, screen(app))?;
    let &(_, area) = layout
        .panels
        .iter()
        .find(|(p, _)| *p == Panel::Deflection)?;
    let columns = deflection_columns(app, area)?;
    let l = columns.length;
    let column_width = l / f64::from(columns.last - columns.first);
    let step = nice_step(column_width);
    let raw = columns.x_at(x);
    let snapped = (raw / step).round() * step;
    let obstacles = &app.scene.obstacles;
    // The obstacle may be gone (deleted or undone during the drag).
    if index >= obstacles.len() {
        return None;
    }
    let gap = l / 1000.0;
    let lower = index.checked_sub(1).map_or(0.0, |i| obstacles[i].x) + gap;
    let upper = obstacles.get(index + 1).map_or(l, |o| o.x) - gap;
    snapped
        .is_finite()
        .then(|| snapped.clamp(lower, upper.max(lower)))
}

/// The row of obstacle `index`'s position.
pub fn obstacle_row(app: &App, index: usize) -> Option<usize> {
    app.rows().iter().position(|r| *r == Row::ObstacleX(index))
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

    #[test]
    fn nice_steps_are_one_two_five_and_never_coarser() {
        for (value, step) in [(0.0167, 0.01), (0.03, 0.02), (0.0051, 0.005), (1.0, 1.0)] {
            let got = nice_step(value);
            assert!((got - step).abs() < 1e-15 * step, "{value}: {got}");
        }
        for i in 1..2000 {
            let value = f64::from(i) * 1.37e-4;
            let step = nice_step(value);
            assert!(
                step <= value && step > value / 2.5 - 1e-18,
                "{value}: {step}"
            );
        }
    }
}
