//! The one place that changes the explorer's state: [`update`] takes a [`Msg`] — a key (what
//! it means in the current mode comes from `tui::input::keymap`), a paste, a mouse event
//! (placed on what is drawn under it by `tui::layout::hit`), a new terminal size, a finished
//! solve or sweep, the presenter's new state, a suspension or the end — and applies it. Every
//! change of the scene goes through the scene's validation; a rejected value leaves the state
//! as it was and says why.
//!
//! By subject: [`normal`] (the keys of normal mode), [`edit`] (changes of the scene: values,
//! obstacles, methods, undo and redo, presets), [`discard`] (what would lose unsaved changes
//! asks first), [`prompts`] (typing a value, the preset picker, the scrolled views) and the
//! editing keys of every prompt ([`typing`]), [`save`], [`export`] (the focused panel as an SVG figure), [`pointer`] (the mouse), [`follow`]
//! (forks, rejoins, the presenter's states), [`lesson`] (a lesson's steps) and [`results`]
//! (solves and sweeps arriving).

mod discard;
mod edit;
mod export;
mod follow;
mod lesson;
mod method_view;
mod normal;
mod pointer;
mod prompts;
mod results;
mod save;
mod students;
mod typing;

use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::scene::Panel;
use crate::tui::input::decode::{DroppedPaste, PASTE_LIMIT};
use crate::tui::input::keymap::{Action, Key, action_for, lesson_action, paste_actions};
use crate::tui::input::pointer::Pointer;
use crate::tui::jobs::solve::Solved;
use crate::tui::jobs::sweeps::{SWEEPS, SweepContext, SweepResult};
use crate::tui::layout::picker::picker_rows_shown;
use crate::tui::layout::screen::{fits, screen};
use crate::tui::layout::{parameter_rows_shown, visible_panels};
use crate::tui::state::follow::ClassNews;
use crate::tui::state::{App, Discard, Ending, Exploration, Mode};

pub use save::save_target;

/// Everything that changes the explorer's state.
#[derive(Debug, Clone)]
pub enum Msg {
    /// A key, from the terminal or `render --keys`: what it means depends on the mode (the
    /// keymap) and on follow mode.
    Key(Key),
    /// An action decided already (what a key means, without follow mode's interception).
    Action(Action),
    /// Text the terminal marked as pasted: typed into a prompt, never run as commands.
    Paste(String),
    /// A paste over the limit, dropped whole: only a note says so.
    PasteDropped(DroppedPaste),
    /// A mouse event (ignored without mouse capture).
    Pointer(Pointer),
    /// The terminal's size in cells (columns, rows).
    Resize(u16, u16),
    /// The solve the state wants started at this instant (the runtime's clock: the busy
    /// note's elapsed time).
    SolveStarted(Instant),
    /// A solve finished: kept if it is the one wanted now.
    Solved(Box<Solved>),
    /// The solve worker failed (a panic in a method): the message says so.
    SolveFailed(String),
    /// A sweep finished: kept if its inputs are still current.
    Swept(SweepResult),
    /// The presenter's new state (follow mode).
    Follow(Arc<Exploration>),
    /// News of the class from the server (the presenter left, the class ended).
    Class(ClassNews),
    /// What came of Ctrl-Z or SIGTSTP.
    Suspension(Suspension),
    /// Time passed (a redraw while work is in flight); nothing changes.
    Tick,
    /// A note from outside the explorer (the recording cannot be written), shown as its
    /// message.
    Notice(String),
    /// The session ends in the given time unless input comes (the idle timeout is near).
    IdleWarning(Duration),
    /// The explorer ends: the terminal hung up, a signal, the idle timeout.
    End(Ending),
}

/// The status line's warning that the session ends in `left` for want of a key.
fn idle_warning(left: Duration, unsaved: bool) -> String {
    let kept = if unsaved {
        "; your unsaved changes are kept"
    } else {
        ""
    };
    format!(
        "idle: this session ends in {} s without a key{kept}",
        left.as_secs_f64().round()
    )
}

/// What came of a suspension the state asked for (Ctrl-Z) or a signal did (SIGTSTP).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Suspension {
    /// This terminal cannot be suspended (a remote one).
    Refused,
    /// The process was stopped and resumed; the terminal has this size now.
    Resumed(u16, u16),
}

/// Applies `msg` to the state.
pub fn update(app: &mut App, msg: Msg) {
    if matches!(msg, Msg::Key(_) | Msg::Paste(_) | Msg::Pointer(_))
        && let Some(follow) = &app.follow
    {
        // A student's idle time, for the presenter's list.
        follow.note_input(Instant::now());
    }
    // The presenter's states keep only a follower from being idle (a forked student's warning
    // stays while its presenter works: stop 60's pass).
    let active = match msg {
        Msg::Key(_) | Msg::Paste(_) | Msg::Pointer(_) | Msg::Resize(..) => true,
        Msg::Follow(_) => app.is_following(),
        _ => false,
    };
    if active
        && let Some(warning) = app.idle_warning.take()
        && app.message.as_ref() == Some(&warning)
    {
        // Not idle any more (as the event loop counts it): the warning goes.
        app.message = None;
    }
    match msg {
        // Below the smallest size nothing is drawn but a notice: a key there would change what
        // nobody can see, so only those that leave act (quit and its yes, Ctrl-C, Ctrl-Z, Esc).
        Msg::Key(key) if !fits(screen(app)) => {
            let quitting = matches!(
                app.mode,
                Mode::ConfirmDiscard {
                    then: Discard::Quit
                } | Mode::ConfirmEndClass
            );
            match action_for(&app.mode, key) {
                Some(
                    action @ (Action::Quit | Action::Interrupt | Action::Suspend | Action::Cancel),
                ) => act(app, action),
                Some(Action::Confirm) if quitting => act(app, Action::Confirm),
                _ => {}
            }
        }
        Msg::Paste(_) | Msg::Pointer(_) if !fits(screen(app)) => {}
        Msg::Key(key) => {
            if follow::intercept(app, key) {
                // Taken by follow mode.
            } else if let Some(action) = lesson_action(key)
                .filter(|_| app.mode == Mode::Normal && app.exploration.lesson.is_some())
            {
                act(app, action);
            } else if let Some(action) = action_for(&app.mode, key) {
                act(app, action);
            }
        }
        Msg::Action(action) => act(app, action),
        Msg::Paste(text) => {
            for action in paste_actions(&app.mode, &text) {
                act(app, action);
            }
        }
        Msg::PasteDropped(dropped) => app.message = Some(paste_dropped_note(dropped)),
        Msg::Pointer(pointer) => {
            // Without mouse capture (`--no-mouse`) the mouse means nothing, even if a client
            // sends its sequences.
            if app.mouse {
                pointer::apply(app, pointer);
                keep_selection_in_view(app);
                refresh_sweeps(app);
            }
        }
        Msg::Resize(width, height) => resize(app, width, height),
        Msg::SolveStarted(at) => results::solve_started(app, at),
        Msg::Solved(solved) => results::solved(app, *solved),
        Msg::SolveFailed(message) => app.message = Some(message),
        Msg::Swept(result) => results::swept(app, result),
        Msg::Follow(exploration) => follow::receive(app, exploration),
        Msg::Class(news) => follow::class_news(app, news),
        Msg::Suspension(suspension) => {
            app.suspend_requested = false;
            match suspension {
                Suspension::Refused if app.follow.as_ref().is_some_and(|f| !f.is_student()) => {
                    app.message = Some(
                        "Ctrl-Z would stop the server and every student with it: not done".into(),
                    );
                }
                Suspension::Refused => {
                    app.message = Some("Ctrl-Z does nothing here: q quits".into());
                }
                Suspension::Resumed(width, height) => resize(app, width, height),
            }
        }
        Msg::Tick => {}
        Msg::Notice(text) => app.message = Some(text),
        Msg::IdleWarning(left) => {
            let warning = idle_warning(left, app.has_unsaved_work());
            app.message = Some(warning.clone());
            app.idle_warning = Some(warning);
        }
        Msg::End(ending) => {
            if app.ending.is_none() && matches!(ending, Ending::Idle | Ending::Hangup) {
                // Closed for the user, not by them: changes go to the save directory where
                // there is one (else the idle session prints them, `runtime::remote`).
                app.saved_at_closing = save::save_at_closing(app);
            }
            app.ending.get_or_insert(ending);
        }
    }
    // A student's unsaved work is counted for the lecturer's "end the class?", and whether
    // they follow is shown in the lecturer's list.
    if let Some(follow) = &app.follow {
        follow.note_state(app.has_unsaved_work());
    }
}

/// What the user is told of a paste dropped for its size (sizes in KiB, rounded up).
fn paste_dropped_note(dropped: DroppedPaste) -> String {
    let limit = PASTE_LIMIT / 1024;
    let size = dropped.bytes.div_ceil(1024);
    if dropped.ended {
        format!("paste of {size} KiB dropped: a paste may have at most {limit} KiB")
    } else {
        format!("paste over {limit} KiB: dropping it whole (nothing is typed until it ends)")
    }
}

/// Applies a key's action, then keeps the selected row in view.
fn act(app: &mut App, action: Action) {
    apply(app, action);
    keep_selection_in_view(app);
    // A panel may look at the selected row (the dual's box: its obstacle).
    refresh_sweeps(app);
}

/// The terminal has a new size: what is visible may have changed, and the sweeps follow.
fn resize(app: &mut App, width: u16, height: u16) {
    app.size = (width, height);
    refresh_sweeps(app);
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

/// What an action does: those of every mode first, then the mode's own.
fn apply(app: &mut App, action: Action) {
    match action {
        Action::Interrupt => {
            // Ctrl-C quits at once unless that loses changes or ends a class; then it asks,
            // and a second Ctrl-C forces.
            let asked = app.mode
                == Mode::ConfirmDiscard {
                    then: Discard::Quit,
                }
                || matches!(app.mode, Mode::ConfirmEndClass | Mode::ClassEnded { .. });
            let class = app.follow.as_ref().and_then(|f| f.class_to_end());
            if class.is_some() && !asked {
                app.mode = Mode::ConfirmEndClass;
            } else if asked || !app.has_unsaved_work() {
                app.ending = Some(Ending::Quit);
            } else {
                app.mode = Mode::ConfirmDiscard {
                    then: Discard::Quit,
                };
            }
        }
        Action::Suspend => app.suspend_requested = true,
        Action::Fork => follow::fork(app),
        Action::ShowJoin => {
            if app.join.is_some() {
                app.mode = Mode::Join;
            } else {
                app.message = Some("the join screen is the lecturer's (beamfric present)".into());
            }
        }
        Action::ShowStudents => students::show(app),
        Action::Rejoin => follow::rejoin(app),
        Action::NextStep => lesson::step(app, true),
        Action::PreviousStep => lesson::step(app, false),
        Action::PasteIgnored => {
            app.message =
                Some("a paste is typed only into a prompt (Enter opens one); ignored".into());
        }
        _ => match app.mode.clone() {
            Mode::Normal => normal::apply(app, action),
            Mode::Help { offset } => {
                app.mode = prompts::scrolled(offset, action, scroll_page(app))
                    .map_or(Mode::Normal, |offset| Mode::Help { offset })
            }
            Mode::Warnings { offset } => {
                app.mode = prompts::scrolled(offset, action, scroll_page(app))
                    .map_or(Mode::Normal, |offset| Mode::Warnings { offset })
            }
            Mode::SceneText | Mode::Join => {
                if action == Action::Cancel {
                    app.mode = Mode::Normal;
                }
            }
            Mode::Editing { row, prompt } => prompts::editing(app, action, row, prompt),
            Mode::Presets(picker) => prompts::presets(app, action, picker),
            Mode::Save { prompt } => {
                if let Some(then) = save::save_prompt(app, action, prompt) {
                    discard::discard_and(app, then);
                }
            }
            Mode::ConfirmOverwrite { path } => {
                if let Some(then) = save::confirm_overwrite(app, action, path) {
                    discard::discard_and(app, then);
                }
            }
            Mode::ConfirmDiscard { then } => discard::confirm_discard(app, action, then),
            Mode::ConfirmEndClass => discard::confirm_end_class(app, action),
            Mode::Students { offset } => students::in_list(app, action, offset),
            Mode::Broadcast { prompt } => students::broadcast_prompt(app, action, prompt),
            // Any key leaves the closing screen (its work is saved or was shown).
            Mode::ClassEnded { .. } => app.ending = Some(Ending::Quit),
        },
    }
}

/// A page of the help or the warnings view: the screen's rows less the box and a line kept.
fn scroll_page(app: &App) -> u16 {
    app.size.1.saturating_sub(3)
}

/// Marks the sweeps whose inputs changed as pending (or idle when no visible panel needs
/// them). Their data for older inputs is never drawn as current: it is kept only to be drawn
/// marked as out of date until the new data arrives.
///
/// The keystroke's own solve records its iterations only while the iterations panel is on
/// screen (or, for a follower, while the presenter's solve records them): hidden, the
/// per-keystroke path pays nothing for them.
fn refresh_sweeps(app: &mut App) {
    let panels = visible_panels(app);
    let following = app.is_following();
    let exploration = &mut app.exploration;
    // A follower keeps the presenter's request when it asks for the history anyway, so that
    // the presenter's solve serves both instead of one of the student's own.
    let presenter_records = following && exploration.wanted.options.history;
    // An iterate drawn over u(x) (selected, the deflection on screen, the iterations one Tab
    // away at a small size) needs the history too.
    let iterate_drawn = exploration.iterate.is_some()
        && panels.contains(&Panel::Deflection)
        && exploration.panels().contains(&Panel::Iterations);
    exploration.wanted.options.history =
        panels.contains(&Panel::Iterations) || iterate_drawn || presenter_records;
    let context = SweepContext {
        problem: &exploration.problem,
        elements: exploration.scene.mesh.elements,
        epsilon: exploration.scene.solver.epsilon,
        show_timings: app.show_timings,
        obstacle: exploration.selected_row().obstacle(),
        max_cases: exploration.wanted.options.max_cases,
        iterate: selected_iterate(exploration),
    };
    for (slot, sweep) in exploration.sweeps.iter_mut().zip(SWEEPS) {
        let needed = sweep.panels().iter().any(|p| panels.contains(p)) && sweep.needed(&context);
        slot.refresh(needed, sweep.inputs(context.clone()));
    }
}

/// The iterate the iterations panel selects, when it is not the last of the current solve's
/// history: its number and forces.
fn selected_iterate(exploration: &Exploration) -> Option<(usize, Vec<[f64; 2]>)> {
    let index = exploration.iterate?;
    if !exploration.is_current() {
        return None;
    }
    let solution = exploration.solution()?.as_ref().ok()?;
    let records = &solution.history.as_ref()?.iterations;
    let record = records.get(index).filter(|_| index + 1 < records.len())?;
    Some((record.iteration, record.forces.clone()))
}
