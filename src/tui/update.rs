//! The one place that changes the explorer's state: [`update`] takes an [`Action`] (what a
//! key means in the current mode, from [`super::keymap`], or a mouse event, placed on what is
//! drawn under it by [`super::mouse::target`]) and applies it. Every change of the scene goes
//! through the scene's validation; a rejected value leaves the state as it was and says why.

use crate::scene::{LoadedScene, ObstacleSpec, PRESETS, Scene, SceneSource, save_scene};
use crate::solve::Method;

use super::app::{App, Diagram, Discard, Drag, Mode, SavePolicy, UNDO_LIMIT};
use super::keymap::{Action, Key};
use super::mouse::{Target, dragged_position, obstacle_row, target};
use super::params::{Row, set_from_text, step};
use super::picker::PresetPicker;
use super::prompt::{Prompt, Typed, editable_number};
use super::view::{picker_layout, screen_layout};
use crate::scene::Panel;

/// Longest value a prompt accepts.
const PROMPT_LIMIT: usize = 200;
/// Longest file name the save prompt accepts (PATH_MAX on Linux).
const PATH_LIMIT: usize = 4096;

/// Applies `action` to the state.
pub fn update(app: &mut App, action: Action) {
    apply(app, action);
    keep_selection_in_view(app);
}

/// Scrolls the parameters (and the preset list) only as far as needed to show the selected
/// row (after any change of the selection, the rows or the size).
fn keep_selection_in_view(app: &mut App) {
    let height = parameter_rows_shown(app);
    app.parameters_offset = app.parameters_offset(height);
    let visible = picker_rows_shown(app);
    if let Mode::Presets(picker) = &mut app.mode {
        picker.scroll_to_highlight(visible);
    }
}

/// How many parameter rows the frame shows now (at least one).
fn parameter_rows_shown(app: &App) -> usize {
    let area = ratatui::layout::Rect::new(0, 0, app.size.0, app.size.1);
    screen_layout(app, area)
        .map_or(1, |layout| {
            usize::from(layout.parameters.height.saturating_sub(2))
        })
        .max(1)
}

/// How many entries the preset picker's list shows now (at least one).
fn picker_rows_shown(app: &App) -> usize {
    let area = ratatui::layout::Rect::new(0, 0, app.size.0, app.size.1);
    usize::from(picker_layout(area).list.height).max(1)
}

fn apply(app: &mut App, action: Action) {
    match action {
        Action::Interrupt => {
            // Ctrl-C quits at once unless that loses changes; then it asks, and a second
            // Ctrl-C forces.
            let asked = app.mode
                == Mode::ConfirmDiscard {
                    then: Discard::Quit,
                };
            if asked || !app.modified() {
                app.quit = true;
            } else {
                app.mode = Mode::ConfirmDiscard {
                    then: Discard::Quit,
                };
            }
            return;
        }
        Action::Resize(width, height) => {
            app.size = (width, height);
            // What is visible may have changed: studies follow.
            app.refresh_studies();
            return;
        }
        Action::Suspend => {
            app.suspend_requested = true;
            return;
        }
        Action::Fork => {
            super::follow::fork(app);
            return;
        }
        Action::Rejoin => {
            super::follow::rejoin(app);
            return;
        }
        Action::PasteIgnored => {
            app.message =
                Some("a paste is typed only into a prompt (Enter opens one); ignored".into());
            return;
        }
        Action::Click { .. }
        | Action::Drag { .. }
        | Action::Release { .. }
        | Action::Scroll { .. } => {
            mouse(app, action);
            return;
        }
        _ => {}
    }
    match app.mode.clone() {
        Mode::Normal => normal(app, action),
        Mode::Help { offset } => {
            app.mode = scrolled(offset, action).map_or(Mode::Normal, |offset| Mode::Help { offset })
        }
        Mode::SceneText => {
            if action == Action::Cancel {
                app.mode = Mode::Normal;
            }
        }
        Mode::Warnings { offset } => {
            app.mode =
                scrolled(offset, action).map_or(Mode::Normal, |offset| Mode::Warnings { offset })
        }
        Mode::Editing { row, prompt } => editing(app, action, row, prompt),
        Mode::Presets(picker) => presets(app, action, picker),
        Mode::Save { prompt } => save_prompt(app, action, prompt),
        Mode::ConfirmOverwrite { path } => confirm_overwrite(app, action, path),
        Mode::ConfirmDiscard { then } => confirm_discard(app, action, then),
    }
}

/// The warnings view and the help scroll at most this far (drawing stops at the last line
/// anyway).
const WARNINGS_SCROLL_LIMIT: u16 = 200;

/// A scrolled view's new offset after `action` (↑ and ↓ scroll), or `None`: any other key
/// closes it.
fn scrolled(offset: u16, action: Action) -> Option<u16> {
    match action {
        Action::SelectPrevious => Some(offset.saturating_sub(1)),
        Action::SelectNext => Some(offset.saturating_add(1).min(WARNINGS_SCROLL_LIMIT)),
        _ => None,
    }
}

/// Does `then` at once, or asks first when it would lose unsaved changes.
fn unless_unsaved(app: &mut App, then: Discard) {
    if app.modified() {
        app.mode = Mode::ConfirmDiscard { then };
    } else {
        discard_and(app, then);
    }
}

fn discard_and(app: &mut App, then: Discard) {
    match then {
        Discard::Quit => app.quit = true,
        Discard::Reset => {
            remember(app);
            let (problem, settings) = app.loaded_problem.clone();
            app.scene = app.loaded.clone();
            app.saved = app.loaded.clone();
            app.selected = app.selected.min(app.rows().len() - 1);
            app.resolve(problem, settings);
            app.message = Some("reset to the scene as loaded (u undoes)".into());
        }
        Discard::Preset(index) => load_preset(app, index),
    }
}

fn confirm_discard(app: &mut App, action: Action, then: Discard) {
    app.mode = Mode::Normal;
    match action {
        Action::Confirm => discard_and(app, then),
        Action::Save => {
            // Save first, then do what was asked once the save has succeeded (only where a
            // save writes a file: a served session shows the text instead).
            start_save(app);
            if matches!(app.mode, Mode::Save { .. }) {
                app.after_save = Some(then);
            }
        }
        _ => app.message = Some("kept the unsaved changes".into()),
    }
}

/// Keeps the current scene for undo, before it changes.
fn remember(app: &mut App) {
    app.undo.push(app.scene.clone());
    if app.undo.len() > UNDO_LIMIT {
        app.undo.remove(0);
    }
    app.redo.clear();
}

/// Steps back (`undo`) or forward through the scenes.
fn undo_redo(app: &mut App, undo: bool) {
    let (from, word) = if undo {
        (&mut app.undo, "undone")
    } else {
        (&mut app.redo, "redone")
    };
    let Some(scene) = from.pop() else {
        app.message = Some(format!("nothing to {}", if undo { "undo" } else { "redo" }));
        return;
    };
    match scene.validate(&app.source.to_string()) {
        Ok((problem, settings)) => {
            let current = std::mem::replace(&mut app.scene, scene);
            if undo {
                app.redo.push(current);
            } else {
                app.undo.push(current);
            }
            app.selected = app.selected.min(app.rows().len() - 1);
            app.resolve(problem, settings);
            let left = if undo { app.undo.len() } else { app.redo.len() };
            app.message = Some(format!("{word} ({left} more)"));
        }
        Err(e) => app.message = Some(format!("cannot restore: {e}")),
    }
}

/// Where saving to a file is off (a served session): says why, or shows the scene as text.
/// Returns whether it was.
fn saving_is_off(app: &mut App) -> bool {
    match &app.save_policy {
        SavePolicy::Refuse(reason) => app.message = Some(format!("not saved: {reason}")),
        SavePolicy::ShowText => app.mode = Mode::SceneText,
        _ => return false,
    }
    true
}

/// Asks for the file name to save to, unless saving is off here.
fn start_save(app: &mut App) {
    if !saving_is_off(app) {
        app.mode = Mode::Save {
            prompt: Prompt::new(app.save_path.clone(), false),
        };
    }
}

/// The reason `scene` is beyond this explorer's limits (a served session's element cap).
fn beyond_limits(app: &App, scene: &Scene) -> Option<String> {
    let max = app.max_elements?;
    (scene.mesh.elements > max).then(|| {
        format!(
            "rejected: mesh.elements: at most {max} here ({} asked for)",
            scene.mesh.elements
        )
    })
}

/// Keeps `candidate` if it is a valid scene (and re-solves), else reports the rule it broke.
/// Errors name obstacles by the numbers the user sees (the candidate is checked before its
/// obstacles are put in order); once kept, the selection stays on the same obstacle even if
/// a new position moved it past another.
fn try_apply(app: &mut App, candidate: Scene) -> bool {
    try_apply_keeping_undo(app, candidate, true)
}

/// [`try_apply`], keeping the scene before for undo only when `undo_step` (a drag keeps one
/// undo step for all its moves).
fn try_apply_keeping_undo(app: &mut App, mut candidate: Scene, undo_step: bool) -> bool {
    if let Some(message) = beyond_limits(app, &candidate) {
        app.message = Some(message);
        return false;
    }
    if let Err(e) = candidate.validate(&app.source.to_string()) {
        app.message = Some(format!("rejected: {}: {}", e.field, e.rule));
        return false;
    }
    // Where each obstacle goes when sorted by position (stable: ties keep their order).
    let mut order: Vec<usize> = (0..candidate.obstacles.len()).collect();
    order.sort_by(|&a, &b| {
        candidate.obstacles[a]
            .x
            .total_cmp(&candidate.obstacles[b].x)
    });
    candidate.obstacles = order.iter().map(|&i| candidate.obstacles[i]).collect();
    match candidate.validate(&app.source.to_string()) {
        Ok((problem, settings)) => {
            let selected = app.selected_row();
            if undo_step {
                remember(app);
            }
            app.scene = candidate;
            app.message = None;
            if let Some(old) = selected.obstacle()
                && let Some(new) = order.iter().position(|&i| i == old)
                && new != old
            {
                let moved = selected.for_obstacle(new);
                app.selected = app.rows().iter().position(|r| *r == moved).unwrap_or(0);
            }
            app.selected = app.selected.min(app.rows().len() - 1);
            app.resolve(problem, settings);
            true
        }
        Err(e) => {
            app.message = Some(format!("rejected: {}: {}", e.field, e.rule));
            false
        }
    }
}

fn normal(app: &mut App, action: Action) {
    let rows = app.rows();
    match action {
        Action::SelectPrevious => app.selected = app.selected.saturating_sub(1),
        Action::SelectNext => app.selected = (app.selected + 1).min(rows.len() - 1),
        Action::SelectFirst => app.selected = 0,
        Action::SelectLast => app.selected = rows.len() - 1,
        Action::PageUp => {
            app.selected = app.selected.saturating_sub(parameter_rows_shown(app));
        }
        Action::PageDown => {
            app.selected = (app.selected + parameter_rows_shown(app)).min(rows.len() - 1);
        }
        Action::ToggleZoom => toggle_zoom(app),
        Action::Decrease { coarse } => change(app, -1, coarse),
        Action::Increase { coarse } => change(app, 1, coarse),
        Action::EditValue => {
            let row = app.selected_row();
            let current = match row {
                Row::Method => app.scene.solver.method.name().to_string(),
                Row::Elements => app.scene.mesh.elements.to_string(),
                _ => row
                    .number(&app.scene)
                    .map(editable_number)
                    .unwrap_or_default(),
            };
            app.mode = Mode::Editing {
                row,
                prompt: Prompt::new(current, true),
            }
        }
        Action::AddObstacle => add_obstacle(app),
        Action::DeleteObstacle => delete_obstacle(app),
        Action::NextMethod => next_method(app),
        Action::PickPreset => {
            let index = PRESETS
                .iter()
                .position(|p| app.source == SceneSource::Preset(p.name))
                .unwrap_or(0);
            let mut picker = PresetPicker::at(index);
            picker.scroll_to_highlight(picker_rows_shown(app));
            app.mode = Mode::Presets(picker);
        }
        Action::Save => start_save(app),
        Action::Reset => unless_unsaved(app, Discard::Reset),
        Action::ShowHelp => app.mode = Mode::Help { offset: 0 },
        Action::ShowWarnings => app.mode = Mode::Warnings { offset: 0 },
        Action::Quit => unless_unsaved(app, Discard::Quit),
        Action::Undo => undo_redo(app, true),
        Action::Redo => undo_redo(app, false),
        Action::NextDiagram => next_diagram(app),
        Action::ToggleDifference => app.show_difference = !app.show_difference,
        Action::CycleTheme => {
            app.palette = app.palette.next();
            app.message = Some(format!(
                "theme {}: {}",
                app.palette.name(),
                app.palette.description()
            ));
        }
        Action::ToggleTimings => {
            app.show_timings = !app.show_timings;
            app.refresh_studies();
        }
        Action::NextPanel => {
            let count = app.panels().len().max(1);
            app.focus = (app.focus + 1) % count;
            app.refresh_studies();
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
        // Prompt and list actions, and keys without a meaning here.
        Action::Unbound(_)
        | Action::Type(_)
        | Action::DeleteChar
        | Action::CursorLeft
        | Action::CursorRight
        | Action::CursorHome
        | Action::CursorEnd
        | Action::EraseToStart
        | Action::Confirm
        | Action::Cancel => {}
        Action::Interrupt
        | Action::Resize(..)
        | Action::Suspend
        | Action::PasteIgnored
        | Action::Click { .. }
        | Action::Drag { .. }
        | Action::Release { .. }
        | Action::Scroll { .. }
        | Action::Fork
        | Action::Rejoin => {
            unreachable!("handled before the mode")
        }
    }
}

/// `b`: the deflection panel's next diagram. Where that panel is not on screen it is brought
/// forward first (the change is then visible); a scene without it says so.
fn next_diagram(app: &mut App) {
    let panels = app.panels();
    let Some(index) = panels.iter().position(|p| *p == Panel::Deflection) else {
        app.message = Some("this scene shows no deflection panel (b has nothing to switch)".into());
        return;
    };
    if !app.visible_panels().contains(&Panel::Deflection) {
        app.focus = index;
        app.refresh_studies();
    }
    app.diagram = match app.diagram {
        Diagram::Deflection => Diagram::Moment,
        Diagram::Moment => Diagram::Shear,
        Diagram::Shear => Diagram::Deflection,
    };
}

/// `dual-inverse` at its limit (N = 3998 unknowns) takes about 3 s (criterion, release), and
/// its cost grows like N³.
const DUAL_INVERSE_SECONDS_AT_LIMIT: (f64, f64) = (3.0, 3998.0);
/// Cycling `m` does not enter a method expected to take longer than this; typing its name in
/// the method row still runs it.
const QUICK_SECONDS: f64 = 1.0;

/// Expected run time of `method` on the current mesh, where it is known to be slow.
fn expected_seconds(app: &App, method: Method) -> Option<f64> {
    let unknowns = 2.0 * app.wanted.elements.saturating_sub(1) as f64;
    match method {
        Method::DualInverse => {
            let (seconds, at) = DUAL_INVERSE_SECONDS_AT_LIMIT;
            Some(seconds * (unknowns / at).powi(3))
        }
        _ => None,
    }
}

/// The next method in the cycle, skipping (with a note) one expected to take long here.
fn next_method(app: &mut App) {
    let mut candidate = step(&app.scene, Row::Method, 1, false);
    let mut skipped = None;
    if let Some(seconds) = expected_seconds(app, candidate.solver.method)
        && seconds > QUICK_SECONDS
    {
        skipped = Some((candidate.solver.method, seconds));
        candidate = step(&candidate, Row::Method, 1, false);
    }
    if try_apply(app, candidate)
        && let Some((method, seconds)) = skipped
    {
        app.message = Some(format!(
            "skipped {method}: about {seconds:.0} s at n = {} (type it in the method row to \
             run it anyway)",
            app.wanted.elements
        ));
    }
}

fn change(app: &mut App, direction: i32, coarse: bool) {
    let row = app.selected_row();
    let candidate = step(&app.scene, row, direction, coarse);
    if candidate == app.scene {
        app.message = Some(format!("{} cannot go further", row.label().trim()));
        return;
    }
    try_apply(app, candidate);
}

fn add_obstacle(app: &mut App) {
    let l = app.scene.beam.length;
    let mut points: Vec<f64> = vec![0.0];
    points.extend(app.scene.obstacles.iter().map(|o| o.x));
    points.push(l);
    // The middle of the widest gap.
    let (a, b) = points
        .windows(2)
        .map(|w| (w[0], w[1]))
        .max_by(|p, q| (p.1 - p.0).total_cmp(&(q.1 - q.0)))
        .expect("at least two points");
    let template = app
        .selected_row()
        .obstacle()
        .or(app.scene.obstacles.len().checked_sub(1))
        .map(|i| app.scene.obstacles[i]);
    let new = ObstacleSpec {
        x: 0.5 * (a + b),
        sliding: template.map_or(1e2, |o| o.sliding),
        swivel: template.map_or(5e4, |o| o.swivel),
    };
    let mut candidate = app.scene.clone();
    candidate.obstacles.push(new);
    if try_apply(app, candidate) {
        let index = app
            .scene
            .obstacles
            .iter()
            .position(|o| *o == new)
            .unwrap_or(0);
        app.selected = app
            .rows()
            .iter()
            .position(|r| *r == Row::ObstacleX(index))
            .unwrap_or(0);
        app.message = Some(format!("obstacle {} added at x = {} m", index + 1, new.x));
    }
}

fn delete_obstacle(app: &mut App) {
    let Some(index) = app.selected_row().obstacle() else {
        app.message = Some("select a row of an obstacle to delete it".into());
        return;
    };
    let mut candidate = app.scene.clone();
    candidate.obstacles.remove(index);
    if try_apply(app, candidate) {
        app.selected = app.selected.min(app.rows().len() - 1);
        app.message = Some(format!("obstacle {} deleted", index + 1));
    }
}

/// The editing keys every prompt shares; returns whether `action` was one of them.
fn edit_prompt(prompt: &mut Prompt, action: Action, limit: usize) -> Option<Typed> {
    match action {
        Action::Type(c) => return Some(prompt.insert(c, limit)),
        Action::DeleteChar => prompt.delete_before(),
        Action::CursorLeft => prompt.move_by(-1),
        Action::CursorRight => prompt.move_by(1),
        Action::CursorHome => prompt.home(),
        Action::CursorEnd => prompt.end(),
        Action::EraseToStart => prompt.erase_to_start(),
        _ => return None,
    }
    Some(Typed::Inserted)
}

fn editing(app: &mut App, action: Action, row: Row, mut prompt: Prompt) {
    if edit_prompt(&mut prompt, action, PROMPT_LIMIT).is_some() {
        app.mode = Mode::Editing { row, prompt };
        return;
    }
    match action {
        Action::Confirm => {
            app.mode = Mode::Normal;
            if prompt.text.trim().is_empty() {
                return;
            }
            match set_from_text(&app.scene, row, &prompt.text) {
                Ok(candidate) => {
                    try_apply(app, candidate);
                }
                Err(message) => app.message = Some(format!("rejected: {message}")),
            }
        }
        Action::Cancel => app.mode = Mode::Normal,
        _ => app.mode = Mode::Editing { row, prompt },
    }
}

fn presets(app: &mut App, action: Action, mut picker: PresetPicker) {
    let visible = picker_rows_shown(app);
    let index = picker.index as isize;
    let page = visible as isize;
    match action {
        Action::SelectPrevious => picker.select(index - 1, visible),
        Action::SelectNext => picker.select(index + 1, visible),
        Action::SelectFirst => picker.select(0, visible),
        Action::SelectLast => picker.select(isize::MAX, visible),
        Action::PageUp => picker.select(index - page, visible),
        Action::PageDown => picker.select(index + page, visible),
        Action::Type(c) => picker.type_char(c, visible),
        Action::DeleteChar => picker.delete_char(visible),
        Action::Confirm => {
            match picker.highlighted() {
                Some(preset) => {
                    app.mode = Mode::Normal;
                    unless_unsaved(app, Discard::Preset(preset));
                }
                None => {
                    app.message = Some(format!(
                        "no preset matches \"{}\": Backspace edits the search",
                        picker.query
                    ))
                }
            }
            return;
        }
        Action::Cancel => {
            app.mode = Mode::Normal;
            return;
        }
        _ => {}
    }
    app.mode = Mode::Presets(picker);
}

/// The focused panel fills the screen, or the screen goes back to all panels.
fn toggle_zoom(app: &mut App) {
    if app.panels().is_empty() {
        app.message = Some("this scene shows no panel to zoom".into());
        return;
    }
    app.zoom = !app.zoom;
    // Other panels come into view or leave it: studies follow.
    app.refresh_studies();
}

/// Is this a served student following the presenter (who may not change the scene)?
fn following(app: &App) -> bool {
    use super::follow::Role;
    matches!(
        app.follow.as_ref().map(|f| &f.role),
        Some(Role::Student(Some(_)))
    )
}

/// A mouse event: what it does depends on the mode and on what is under the pointer.
fn mouse(app: &mut App, action: Action) {
    match app.mode.clone() {
        Mode::Normal => normal_mouse(app, action),
        Mode::Presets(picker) => picker_mouse(app, action, picker),
        // The wheel scrolls the warnings view and the help; a click closes them, as a key does.
        Mode::Warnings { .. } | Mode::Help { .. } => match action {
            Action::Scroll { up: true, .. } => apply(app, Action::SelectPrevious),
            Action::Scroll { up: false, .. } => apply(app, Action::SelectNext),
            Action::Click { .. } => app.mode = Mode::Normal,
            _ => {}
        },
        // Prompts and questions are answered with keys; the scene as text is selected with the
        // mouse (no mouse capture then).
        _ => {}
    }
}

fn normal_mouse(app: &mut App, action: Action) {
    match action {
        Action::Click { x, y, double } => {
            app.drag = None;
            match target(app, x, y) {
                Target::Row(row) => {
                    app.selected = row;
                    if double {
                        normal(app, Action::EditValue);
                    }
                }
                Target::Obstacle(index) => {
                    focus_panel(app, crate::scene::Panel::Deflection);
                    if double {
                        toggle_zoom(app);
                    } else {
                        app.selected = obstacle_row(app, index).unwrap_or(app.selected);
                        app.drag = Some(Drag::Obstacle {
                            index,
                            moved: false,
                        });
                    }
                }
                Target::Panel { index, title } => {
                    if app.focus != index {
                        app.focus = index;
                        app.refresh_studies();
                    }
                    if double || title {
                        toggle_zoom(app);
                    }
                }
                Target::Status => show_warnings(app),
                _ => {}
            }
        }
        Action::Drag { x, .. } => {
            let Some(Drag::Obstacle { index, moved }) = app.drag else {
                return;
            };
            if following(app) {
                app.message = Some("following the presenter: f to explore on your own".into());
                return;
            }
            let Some(position) = dragged_position(app, index, x) else {
                return;
            };
            if app
                .scene
                .obstacles
                .get(index)
                .is_none_or(|o| o.x == position)
            {
                return;
            }
            let mut candidate = app.scene.clone();
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
        Action::Release { .. } => app.drag = None,
        Action::Scroll { x, y, up } => {
            if matches!(target(app, x, y), Target::Row(_) | Target::Parameters) {
                if following(app) {
                    app.message = Some("following the presenter: f to explore on your own".into());
                    return;
                }
                change(app, if up { 1 } else { -1 }, false);
            }
        }
        _ => {}
    }
}

/// Focuses `panel` if the scene shows it.
fn focus_panel(app: &mut App, panel: crate::scene::Panel) {
    if let Some(index) = app.panels().iter().position(|p| *p == panel)
        && app.focus != index
    {
        app.focus = index;
        app.refresh_studies();
    }
}

/// A click on the status lines, where the warnings are: opens the warnings view (as `w`) when
/// the solution shown has any.
fn show_warnings(app: &mut App) {
    if let Some(Ok(solution)) = app.solution()
        && !solution.warnings.is_empty()
    {
        normal(app, Action::ShowWarnings);
    }
}

fn picker_mouse(app: &mut App, action: Action, mut picker: PresetPicker) {
    let visible = picker_rows_shown(app);
    match action {
        Action::Click { x, y, double } => match target(app, x, y) {
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
        Action::Scroll { up, .. } => {
            let index = picker.index as isize;
            picker.select(if up { index - 1 } else { index + 1 }, visible);
            app.mode = Mode::Presets(picker);
        }
        _ => {}
    }
}

fn load_preset(app: &mut App, index: usize) {
    let preset = &PRESETS[index.min(PRESETS.len() - 1)];
    match LoadedScene::preset(preset) {
        Ok(loaded) if beyond_limits(app, &loaded.scene).is_some() => {
            app.message = beyond_limits(app, &loaded.scene);
        }
        Ok(loaded) => {
            app.save_path = app
                .save_directory
                .join(format!("{}.toml", preset.name))
                .display()
                .to_string();
            // A new scene starts with its own view: nothing of the last one's carries over.
            app.selected = 0;
            app.focus = 0;
            app.zoom = false;
            app.diagram = Diagram::Deflection;
            app.load(loaded);
            app.message = Some(format!("loaded {}", preset.name));
        }
        Err(e) => app.message = Some(e.to_string()),
    }
}

fn save_prompt(app: &mut App, action: Action, mut prompt: Prompt) {
    match edit_prompt(&mut prompt, action, PATH_LIMIT) {
        Some(Typed::Full) => {
            app.message = Some(format!("a file name has at most {PATH_LIMIT} characters"));
            app.mode = Mode::Save { prompt };
            return;
        }
        Some(Typed::Inserted) => {
            app.mode = Mode::Save { prompt };
            return;
        }
        None => {}
    }
    match action {
        Action::Confirm => {
            let path = prompt.text.trim().to_string();
            if path.is_empty() {
                app.mode = Mode::Normal;
                app.message = Some("not saved: no file name".into());
            } else if save_target(&app.save_policy, &path).is_some_and(|t| t.exists()) {
                // The file the save would write (under --allow-save DIR, inside DIR).
                app.mode = Mode::ConfirmOverwrite { path };
            } else {
                app.mode = Mode::Normal;
                save(app, &path, false);
            }
        }
        Action::Cancel => {
            app.mode = Mode::Normal;
            app.after_save = None;
            app.message = Some("not saved".into());
        }
        _ => app.mode = Mode::Save { prompt },
    }
}

fn confirm_overwrite(app: &mut App, action: Action, path: String) {
    app.mode = Mode::Normal;
    match action {
        Action::Confirm => save(app, &path, true),
        _ => {
            app.after_save = None;
            app.message = Some(format!("not saved: {path} left as it was"));
        }
    }
}

fn save(app: &mut App, path: &str, overwrite: bool) {
    // What to do after a successful save; a failed or refused one drops it.
    let then = app.after_save.take();
    if saving_is_off(app) {
        return;
    }
    let target = match &app.save_policy {
        SavePolicy::Write => std::path::PathBuf::from(path),
        // Handled by `saving_is_off`.
        SavePolicy::Refuse(_) | SavePolicy::ShowText => return,
        SavePolicy::Simulate => {
            app.message = Some(format!(
                "not saved: a headless render writes no files (it would save to {path}; \
                 --allow-save DIR lets it)"
            ));
            return;
        }
        SavePolicy::Within(dir) => match save_target(&app.save_policy, path) {
            Some(target) => target,
            None => {
                app.message = Some(format!(
                    "not saved: {path} is outside {}, the only directory saves may go to",
                    dir.display()
                ));
                return;
            }
        },
    };
    match save_scene(&app.scene, &target, overwrite) {
        Ok(outcome) => {
            app.save_path = path.to_string();
            app.saved = app.scene.clone();
            let notes = outcome.summary();
            app.message = Some(if notes.is_empty() {
                format!("saved to {path}")
            } else {
                format!("saved to {path} ({notes})")
            });
            if let Some(then) = then {
                discard_and(app, then);
            }
        }
        Err(e) => app.message = Some(format!("not saved: {e}")),
    }
}

/// The file a save of `path` writes: the path itself, or under `--allow-save DIR` the path
/// inside DIR (`None` when it leads out of DIR, by `..`, an absolute path elsewhere, or a
/// symbolic link inside DIR that points out — the save would follow it).
fn save_target(policy: &SavePolicy, path: &str) -> Option<std::path::PathBuf> {
    use std::path::Component;
    let dir = match policy {
        SavePolicy::Within(dir) => dir,
        _ => return Some(std::path::PathBuf::from(path)),
    };
    let real_dir = dir.canonicalize().ok()?;
    let path = std::path::Path::new(path);
    let relative = path
        .strip_prefix(dir)
        .or_else(|_| path.strip_prefix(&real_dir))
        .unwrap_or(path);
    let plain = relative
        .components()
        .all(|c| matches!(c, Component::Normal(_) | Component::CurDir));
    if !plain || relative.as_os_str().is_empty() {
        return None;
    }
    let target = real_dir.join(relative);
    // Where the write really lands: the parent resolved, and the file's own link followed.
    let parent = target.parent()?.canonicalize().ok()?;
    let landing = match std::fs::symlink_metadata(&target) {
        Ok(meta) if meta.file_type().is_symlink() => target.canonicalize().ok()?,
        _ => parent.join(target.file_name()?),
    };
    landing.starts_with(&real_dir).then_some(target)
}
