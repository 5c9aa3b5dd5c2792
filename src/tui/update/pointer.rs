//! The mouse: what a click, a drag, a release or a turn of the wheel does depends on the mode
//! and on what is drawn under the pointer (`tui::layout::hit`) — select a row (a double click
//! types its value), step the selected value with the wheel, drag an obstacle along the
//! deflection chart (one undo step per drag), focus or zoom a panel, open the warnings, pick a
//! preset.

use crate::scene::Panel;
use crate::tui::input::keymap::Action;
use crate::tui::input::pointer::Pointer;
use crate::tui::layout::hit::{Target, dragged_position, obstacle_row, target};
use crate::tui::layout::picker::picker_rows_shown;
use crate::tui::state::picker::PresetPicker;
use crate::tui::state::{App, Drag, Mode};

use super::edit::{change, try_apply_keeping_undo};
use super::normal::{edit_value, focus_panel, toggle_zoom};
use super::prompts::{presets, scrolled};
use super::refresh_sweeps;

/// What a follower is told when the mouse would change the presenter's scene.
const FOLLOWING: &str = "following the presenter: f to explore on your own";

/// A mouse event.
pub(super) fn apply(app: &mut App, pointer: Pointer) {
    match app.mode.clone() {
        Mode::Normal => normal(app, pointer),
        Mode::Presets(picker) => picker_pointer(app, pointer, picker),
        // The wheel scrolls the warnings view and the help; a click closes them, as a key does.
        Mode::Warnings { offset } | Mode::Help { offset } => {
            let step = match pointer {
                Pointer::Scroll { up: true, .. } => Action::SelectPrevious,
                Pointer::Scroll { up: false, .. } => Action::SelectNext,
                Pointer::Click { .. } => {
                    app.mode = Mode::Normal;
                    return;
                }
                _ => return,
            };
            let offset = scrolled(offset, step, 1).unwrap_or(offset);
            app.mode = match app.mode {
                Mode::Help { .. } => Mode::Help { offset },
                _ => Mode::Warnings { offset },
            };
        }
        // Prompts and questions are answered with keys; the scene as text is selected with the
        // mouse (no mouse capture then).
        _ => {}
    }
}

fn normal(app: &mut App, pointer: Pointer) {
    match pointer {
        Pointer::Click { x, y, double } => click(app, x, y, double),
        Pointer::Drag { x, .. } => drag(app, x),
        Pointer::Release { .. } => app.drag = None,
        Pointer::Scroll { x, y, up } => {
            let over = target(app, x, y);
            if matches!(over, Target::Iterate(_)) {
                if app.is_following() {
                    app.message = Some(FOLLOWING.into());
                    return;
                }
                super::method_view::step_iterate(app, if up { 1 } else { -1 });
            } else if matches!(over, Target::Row(_) | Target::Parameters) {
                if app.is_following() {
                    app.message = Some(FOLLOWING.into());
                    return;
                }
                change(app, if up { 1 } else { -1 }, false);
            }
        }
    }
}

/// A press in normal mode: on a row, an obstacle's marker, a panel or the status lines.
fn click(app: &mut App, x: u16, y: u16, double: bool) {
    app.drag = None;
    match target(app, x, y) {
        Target::Row(row) => {
            app.exploration.selected = row;
            if double {
                edit_value(app);
            }
        }
        Target::Obstacle(index) => {
            focus_panel(app, Panel::Deflection);
            if double {
                toggle_zoom(app);
            } else {
                app.exploration.selected =
                    obstacle_row(app, index).unwrap_or(app.exploration.selected);
                app.drag = Some(Drag::Obstacle {
                    index,
                    moved: false,
                });
            }
        }
        Target::Panel { index, title } => {
            if app.exploration.focus != index {
                app.exploration.focus = index;
                refresh_sweeps(app);
            }
            if double || title {
                toggle_zoom(app);
            }
        }
        Target::Iterate(_) if app.is_following() => app.message = Some(FOLLOWING.into()),
        Target::Iterate(index) => {
            let last = app
                .exploration
                .solution()
                .and_then(|s| s.as_ref().ok()?.history.as_ref())
                .map_or(0, |h| h.iterations.len().saturating_sub(1));
            app.exploration.iterate = (index < last).then_some(index);
            refresh_sweeps(app);
        }
        Target::Status => show_warnings(app),
        _ => {}
    }
}

/// The pointer moved with the button held: a dragged obstacle follows it.
fn drag(app: &mut App, x: u16) {
    let Some(Drag::Obstacle { index, moved }) = app.drag else {
        return;
    };
    if app.is_following() {
        app.message = Some(FOLLOWING.into());
        return;
    }
    let Some(position) = dragged_position(app, index, x) else {
        return;
    };
    if app
        .scene()
        .obstacles
        .get(index)
        .is_none_or(|o| o.x == position)
    {
        return;
    }
    let mut candidate = app.scene().clone();
    candidate.obstacles[index].x = position;
    if try_apply_keeping_undo(app, candidate, !moved) {
        app.drag = Some(Drag::Obstacle { index, moved: true });
        app.message = Some(format!(
            "obstacle {} at x = {} m (drag; u undoes)",
            index + 1,
            crate::format::eng(position)
        ));
    }
}

/// A click on the status lines, where the warnings are: opens the warnings view (as `w`) when
/// the solution shown has any.
fn show_warnings(app: &mut App) {
    if let Some(Ok(solution)) = app.exploration.solution()
        && !solution.warnings.is_empty()
    {
        app.mode = Mode::Warnings { offset: 0 };
    }
}

fn picker_pointer(app: &mut App, pointer: Pointer, mut picker: PresetPicker) {
    let visible = picker_rows_shown(app);
    match pointer {
        Pointer::Click { x, y, double } => match target(app, x, y) {
            Target::PickerEntry(entry) => {
                picker.select(entry as isize, visible);
                app.mode = Mode::Presets(picker.clone());
                if double {
                    presets(app, Action::Confirm, picker);
                }
            }
            Target::OutsidePicker => app.mode = Mode::Normal,
            _ => {}
        },
        Pointer::Scroll { up, .. } => {
            let index = picker.index as isize;
            picker.select(if up { index - 1 } else { index + 1 }, visible);
            app.mode = Mode::Presets(picker);
        }
        _ => {}
    }
}
