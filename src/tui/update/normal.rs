//! The keys of normal mode: moving the selection, stepping and typing values, the scene's
//! edits (handed to [`super::edit`]), opening the prompts, the picker, the help and the
//! warnings, and what only this screen shows (panel, zoom, diagram, difference, theme,
//! run times).

use crate::scene::{PRESETS, Panel, SceneSource};
use crate::tui::input::keymap::{Action, Key};
use crate::tui::layout::picker::picker_rows_shown;
use crate::tui::layout::{parameter_rows_shown, visible_panels};
use crate::tui::state::params::Row;
use crate::tui::state::picker::PresetPicker;
use crate::tui::state::prompt::{Prompt, editable_number};
use crate::tui::state::{App, Discard, Mode};

use super::discard::{quit, unless_unsaved};
use super::edit::{add_obstacle, change, delete_obstacle, next_diagram, next_method, undo_redo};
use super::refresh_sweeps;
use super::save::start_save;

/// An action in normal mode.
pub(super) fn apply(app: &mut App, action: Action) {
    let last = app.exploration.rows().len() - 1;
    let selected = app.exploration.selected;
    match action {
        Action::SelectPrevious => app.exploration.selected = selected.saturating_sub(1),
        Action::SelectNext => app.exploration.selected = (selected + 1).min(last),
        Action::SelectFirst => app.exploration.selected = 0,
        Action::SelectLast => app.exploration.selected = last,
        Action::PageUp => {
            app.exploration.selected = selected.saturating_sub(parameter_rows_shown(app));
        }
        Action::PageDown => {
            app.exploration.selected = (selected + parameter_rows_shown(app)).min(last);
        }
        Action::ToggleZoom => toggle_zoom(app),
        Action::Decrease { coarse } => change(app, -1, coarse),
        Action::Increase { coarse } => change(app, 1, coarse),
        Action::EditValue => edit_value(app),
        Action::AddObstacle => add_obstacle(app),
        Action::DeleteObstacle => delete_obstacle(app),
        Action::NextMethod => next_method(app),
        Action::PickPreset => pick_preset(app),
        Action::Save => start_save(app),
        Action::Reset => unless_unsaved(app, Discard::Reset),
        Action::ShowHelp => app.mode = Mode::Help { offset: 0 },
        Action::ShowWarnings => app.mode = Mode::Warnings { offset: 0 },
        Action::Quit => quit(app),
        Action::Undo => undo_redo(app, true),
        Action::Redo => undo_redo(app, false),
        Action::NextDiagram => show_next_diagram(app),
        Action::ToggleDifference => app.show_difference = !app.show_difference,
        Action::CycleTheme => {
            app.palette = app.palette.next();
            app.message = Some(format!(
                "theme {}: {}",
                app.palette.name(),
                app.palette.description()
            ));
        }
        Action::ExportFigure => super::export::export_figure(app),
        Action::CycleMarkers => {
            app.markers = app.markers.next();
            app.message = Some(if app.look.ascii {
                format!(
                    "markers {} (drawn in ASCII: this terminal has no Unicode)",
                    app.markers.name()
                )
            } else {
                format!(
                    "markers {}: {}",
                    app.markers.name(),
                    app.markers.description()
                )
            });
        }
        Action::ToggleTimings => {
            app.show_timings = !app.show_timings;
            refresh_sweeps(app);
        }
        Action::NextPanelSet => super::method_view::next_panel_set(app),
        Action::StepIterate(direction) => super::method_view::step_iterate(app, direction),
        Action::NextPanel => {
            let count = app.exploration.panels().len().max(1);
            app.exploration.focus = (app.exploration.focus + 1) % count;
            refresh_sweeps(app);
        }
        Action::Unbound(Key::Char(c)) => {
            app.message = Some(format!("no command on '{c}': press ? for the keys"));
        }
        Action::Unbound(key @ Key::Ctrl(_)) => {
            app.message = Some(format!(
                "no command on {}: press ? for the keys",
                key.label(false)
            ));
        }
        // Prompt and list actions, the keys of every mode (applied before the mode's own), and
        // keys without a meaning here.
        Action::Unbound(_)
        | Action::Type(_)
        | Action::DeleteChar
        | Action::CursorLeft
        | Action::CursorRight
        | Action::CursorHome
        | Action::CursorEnd
        | Action::EraseToStart
        | Action::Confirm
        | Action::Cancel
        | Action::Interrupt
        | Action::Suspend
        | Action::PasteIgnored
        | Action::Fork
        | Action::Rejoin
        | Action::ShowJoin
        | Action::NextStep
        | Action::PreviousStep
        | Action::ShowStudents
        | Action::BringEveryoneBack
        | Action::WriteBroadcast => {}
    }
}

/// Enter: a prompt pre-filled with the selected row's value.
pub(super) fn edit_value(app: &mut App) {
    let row = app.exploration.selected_row();
    let scene = app.scene();
    let current = match row {
        Row::Method => scene.solver.method.name().to_string(),
        Row::Elements => scene.mesh.elements.to_string(),
        _ => row.number(scene).map(editable_number).unwrap_or_default(),
    };
    app.mode = Mode::Editing {
        row,
        prompt: Prompt::new(current, true),
    }
}

/// `p`: the preset picker, on the scene's own preset when it is one.
fn pick_preset(app: &mut App) {
    let index = PRESETS
        .iter()
        .position(|p| app.exploration.source == SceneSource::Preset(p.name))
        .unwrap_or(0);
    let mut picker = PresetPicker::at(index);
    picker.scroll_to_highlight(picker_rows_shown(app));
    app.mode = Mode::Presets(picker);
}

/// The focused panel fills the screen, or the screen goes back to all panels.
pub(super) fn toggle_zoom(app: &mut App) {
    if app.exploration.panels().is_empty() {
        app.message = Some("this scene shows no panel to zoom".into());
        return;
    }
    app.zoom = !app.zoom;
    // Other panels come into view or leave it: sweeps follow.
    refresh_sweeps(app);
}

/// Focuses `panel` if the scene shows it.
pub(super) fn focus_panel(app: &mut App, panel: Panel) {
    if let Some(index) = app.exploration.panels().iter().position(|p| *p == panel)
        && app.exploration.focus != index
    {
        app.exploration.focus = index;
        refresh_sweeps(app);
    }
}

/// `b`: the deflection panel's next diagram. Where that panel is not on screen it is brought
/// forward first (the change is then visible); a scene without it says so.
fn show_next_diagram(app: &mut App) {
    let panels = app.exploration.panels();
    let Some(index) = panels.iter().position(|p| *p == Panel::Deflection) else {
        app.message = Some("this scene shows no deflection panel (b has nothing to switch)".into());
        return;
    };
    if !visible_panels(app).contains(&Panel::Deflection) {
        app.exploration.focus = index;
        refresh_sweeps(app);
    }
    next_diagram(&mut app.exploration);
}
