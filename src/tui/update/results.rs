//! Work arriving from the runtimes: the solve the state wants started, a solve or a sweep
//! finished. A result is kept only when it answers the current state (its request or inputs
//! are still the wanted ones); an outdated one is dropped unseen.

use std::time::Instant;

use crate::tui::jobs::solve::Solved;
use crate::tui::jobs::sweeps::SweepResult;
use crate::tui::state::App;

/// The wanted solve started at `at` (the busy note's elapsed time counts from here).
pub(super) fn solve_started(app: &mut App, at: Instant) {
    if !app.exploration.is_current() && app.busy_since.is_none() {
        app.busy_since = Some(at);
    }
}

/// Takes a finished solve if it is the one wanted now.
pub(super) fn solved(app: &mut App, solved: Solved) {
    if solved.request != app.exploration.wanted {
        return;
    }
    app.exploration.shown = Some(solved);
    app.busy_since = None;
    // The iterate the iterations panel selects belongs to this solve's history.
    super::refresh_sweeps(app);
}

/// Takes a finished sweep if it belongs to the current state.
pub(super) fn swept(app: &mut App, result: SweepResult) {
    if let Some(slot) = app.exploration.sweeps.get_mut(result.sweep) {
        slot.accept(&result.inputs, result.data);
    }
}
