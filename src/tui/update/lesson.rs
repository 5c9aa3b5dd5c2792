//! Stepping through a lesson (Space / `n` forward, Backspace / `N` back): the step's scene
//! replaces the current one, with its panels and focus, and its caption shows. A step left
//! with changes keeps them for when the lecturer comes back to it (stepping never loses
//! work; `r` resets a step to the lesson's scene). A student's explorer does not step while a
//! presenter is connected: the presenter does, and a fork keeps the caption of the step it
//! forked at; without a presenter, each student steps their own.

use crate::tui::state::{App, LessonPlace, StepEdits};

use super::edit::{cap_at_limit, load, try_apply_keeping_undo};

/// [`Action::NextStep`](crate::tui::input::keymap::Action::NextStep) (`forward`) or
/// [`Action::PreviousStep`](crate::tui::input::keymap::Action::PreviousStep).
pub(super) fn step(app: &mut App, forward: bool) {
    let Some(place) = app.exploration.lesson.clone() else {
        app.message = Some("no lesson is open (beamfric --lesson FILE opens one)".into());
        return;
    };
    // Without a presenter, a student steps their own copy of the lesson.
    if app
        .follow
        .as_ref()
        .is_some_and(|f| f.is_student() && f.presenter_here)
    {
        app.message = Some("the presenter steps through the lesson (F follows them again)".into());
        return;
    }
    let count = place.lesson.steps.len();
    let target = if forward {
        Some(place.step + 1).filter(|s| *s < count)
    } else {
        place.step.checked_sub(1)
    };
    match target {
        Some(target) => go_to_step(app, place, target),
        None if forward => {
            app.message = Some(format!(
                "the last step ({count}/{count}) of the lesson: Backspace goes back"
            ));
        }
        None => app.message = Some("the first step of the lesson: Space goes on".into()),
    }
}

/// Shows step `target` of the lesson, keeping the changes made to the step shown now.
pub(super) fn go_to_step(app: &mut App, place: LessonPlace, target: usize) {
    // Changed from the step as shown (its scene as written, or capped at this server's limit).
    if app.exploration.scene != app.exploration.loaded || app.modified() {
        app.step_edits.insert(
            place.step,
            StepEdits {
                scene: app.exploration.scene.clone(),
                saved: app.saved.clone(),
            },
        );
    } else {
        app.step_edits.remove(&place.step);
    }
    let step = place.lesson.step(target).clone();
    app.save_path = crate::tui::state::app::default_save_path(
        &app.save_policy,
        Some(&app.save_directory),
        app.owner.as_deref(),
        &step.scene.source,
    );
    load(app, step.scene.clone());
    app.exploration.lesson = Some(LessonPlace {
        lesson: place.lesson,
        step: target,
    });
    app.exploration.focus = step.focus;
    app.exploration.panel_set = None;
    app.message = None;
    if let Some(edits) = app.step_edits.remove(&target) {
        if try_apply_keeping_undo(app, edits.scene, false) {
            app.saved = edits.saved;
            app.message =
                Some("your changes to this step are back (r: the step as written)".into());
        }
    } else {
        cap_elements(app, target);
    }
    super::refresh_sweeps(app);
}

/// A step beyond this explorer's element limit (a served session) is shown at the limit,
/// with a note.
fn cap_elements(app: &mut App, target: usize) {
    if let (Some(asked), Some(max)) = (cap_at_limit(app), app.max_elements) {
        app.message = Some(format!(
            "step {} asks for n = {asked}: shown at n = {max}, this server's limit",
            target + 1
        ));
    }
}
