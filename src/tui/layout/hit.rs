//! Hit-testing: what is drawn at a cell of the frame — a parameter row, an obstacle's marker,
//! a panel or its title, the status lines, an entry of the preset picker — found from the
//! same layout the frame is drawn with ([`super::screen::screen_layout`],
//! [`super::picker::picker_layout`] and the deflection chart's
//! [`super::deflection::deflection_columns`]), so a click lands on what is drawn there; and
//! where a drag along the deflection chart puts an obstacle. Pure functions of the state.

use ratatui::layout::Rect;

use crate::plot::{Theme, iterations_plot};
use crate::scene::Panel;
use crate::tui::state::App;
use crate::tui::state::Mode;
use crate::tui::state::params::Row;

use super::deflection::deflection_columns;
use super::picker::picker_layout;
use super::screen::{Region, screen, screen_layout};

/// What is under the pointer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// A parameter row (an index into the rows of the scene).
    Row(usize),
    /// Elsewhere in the parameters box (its border, or below the last row).
    Parameters,
    /// An obstacle's marker on the deflection chart (within a column of it).
    Obstacle(usize),
    /// An iterate on the iterations chart (an index into the history shown), the nearest to
    /// the pointer's column inside the plot.
    Iterate(usize),
    /// A panel (an index into the scene's panels); `title` on its top border, where the title is.
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
            if row < app.exploration.rows().len() {
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
            if panel == Panel::Iterations
                && let Some(index) = iterate_at(app, area, x, y)
            {
                return Target::Iterate(index);
            }
            let index = app
                .exploration
                .panels()
                .iter()
                .position(|p| *p == panel)
                .unwrap_or(0);
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
    app.scene()
        .obstacles
        .iter()
        .enumerate()
        .map(|(i, o)| (i, columns.column_of(o.x).abs_diff(x)))
        .filter(|(_, distance)| *distance <= 1)
        .min_by_key(|(_, distance)| *distance)
        .map(|(i, _)| i)
}

/// The iterate nearest column `x` on the iterations chart in `area`, when `x`, `y` is inside
/// its plot.
fn iterate_at(app: &App, area: Rect, x: u16, y: u16) -> Option<usize> {
    let solution = app.exploration.solution()?.as_ref().ok()?;
    let history = solution.history.as_ref()?;
    let theme = Theme::new(app.look, app.palette, app.markers);
    let plot = iterations_plot(&theme, area, history, app.exploration.iterate)?;
    if !plot.graph.contains(ratatui::layout::Position { x, y }) {
        return None;
    }
    history
        .iterations
        .iter()
        .enumerate()
        .filter_map(|(i, r)| Some((i, plot.column(r.iteration as f64)?.abs_diff(x))))
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
    let obstacles = &app.scene().obstacles;
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
    app.exploration
        .rows()
        .iter()
        .position(|r| *r == Row::ObstacleX(index))
}

#[cfg(test)]
mod tests {
    use super::*;

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
