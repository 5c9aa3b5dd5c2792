//! The keys of the panels that show how a method works: `v` cycles the sets of panels (the
//! scene's own, the method at work, Figure 5, the matrices), `<` `>` step through the
//! iterations panel's iterates.

use crate::scene::Panel;
use crate::tui::state::{App, PanelSet};

use super::refresh_sweeps;

/// `v`: the next set of panels, focused on its first; the sweeps follow what is now visible.
pub(super) fn next_panel_set(app: &mut App) {
    let set = PanelSet::after(app.exploration.panel_set);
    app.exploration.panel_set = set;
    app.exploration.focus = 0;
    app.zoom = false;
    app.message = Some(format!(
        "view: {} (v: next view)",
        PanelSet::description(set)
    ));
    refresh_sweeps(app);
}

/// `<` `>`: the previous or next iterate of the history shown, stopping at either end.
pub(super) fn step_iterate(app: &mut App, direction: i8) {
    if !app.exploration.panels().contains(&Panel::Iterations) {
        app.message = Some("< > step through the iterations panel's iterates (v shows it)".into());
        return;
    }
    let Some(count) = recorded_iterates(app) else {
        app.message = Some("no iterations recorded for this solve yet".into());
        return;
    };
    let last = count - 1;
    let current = app.exploration.iterate.unwrap_or(last).min(last);
    let next = if direction < 0 {
        current.saturating_sub(1)
    } else {
        (current + 1).min(last)
    };
    app.exploration.iterate = (next != last).then_some(next);
    refresh_sweeps(app);
}

/// How many iterates the solution shown recorded (at least one), if it recorded any.
fn recorded_iterates(app: &App) -> Option<usize> {
    let solution = app.exploration.solution()?.as_ref().ok()?;
    let history = solution.history.as_ref()?;
    (!history.iterations.is_empty()).then_some(history.iterations.len())
}
