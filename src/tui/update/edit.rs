//! Changes of the scene: a value stepped or typed, an obstacle added or deleted, the next
//! method, undo and redo, a preset loaded — each checked by the scene's rules (and a served
//! session's element cap) before it is kept, kept for undo, and followed by a request for the
//! new solve.

use crate::model::Problem;
use crate::scene::{LoadedScene, ObstacleSpec, PRESETS, Scene, Settings};
use crate::solve::Method;
use crate::tui::jobs::solve::SolveRequest;
use crate::tui::state::app::sorted;
use crate::tui::state::params::{Row, step};
use crate::tui::state::{App, Diagram, Exploration, History};

use super::refresh_sweeps;

/// Asks for the solve of the scene after a change, with the problem and settings its
/// validation built. Nothing is solved here: the runtimes solve what the state wants.
pub(super) fn request_solve(app: &mut App, problem: Problem, settings: Settings) {
    let exploration = &mut app.exploration;
    exploration.wanted = SolveRequest::for_scene(&exploration.scene, &problem, settings)
        .starting_from(exploration.shown.as_ref());
    exploration.problem = problem;
    refresh_sweeps(app);
}

/// Keeps the selection on an existing row after the rows changed.
pub(super) fn clamp_selection(app: &mut App) {
    let rows = app.exploration.rows().len();
    app.exploration.selected = app.exploration.selected.min(rows - 1);
}

/// Keeps the current scene for undo, before it changes.
pub(super) fn remember(app: &mut App) {
    app.history.remember(app.exploration.scene.clone());
}

/// Steps back (`undo`) or forward through the scenes.
pub(super) fn undo_redo(app: &mut App, undo: bool) {
    let word = if undo { "undone" } else { "redone" };
    let Some(scene) = app.history.pop(undo) else {
        app.message = Some(format!("nothing to {}", if undo { "undo" } else { "redo" }));
        return;
    };
    // A scene from before a cap (a fork or a lesson step beyond a served session's limit)
    // stays out of reach.
    if let Some(message) = beyond_limits(app, &scene) {
        app.history.push(undo, scene);
        app.message = Some(message);
        return;
    }
    match scene.validate(&app.exploration.source.to_string()) {
        Ok((problem, settings)) => {
            let current = std::mem::replace(&mut app.exploration.scene, scene);
            app.history.push(!undo, current);
            clamp_selection(app);
            request_solve(app, problem, settings);
            let left = if undo {
                app.history.undo_len()
            } else {
                app.history.redo_len()
            };
            app.message = Some(format!("{word} ({left} more)"));
        }
        Err(e) => app.message = Some(format!("cannot restore: {e}")),
    }
}

/// The reason `scene` is beyond this explorer's limits (a served session's element cap).
pub(super) fn beyond_limits(app: &App, scene: &Scene) -> Option<String> {
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
pub(super) fn try_apply(app: &mut App, candidate: Scene) -> bool {
    try_apply_keeping_undo(app, candidate, true)
}

/// [`try_apply`], keeping the scene before for undo only when `undo_step` (a drag keeps one
/// undo step for all its moves).
pub(super) fn try_apply_keeping_undo(app: &mut App, mut candidate: Scene, undo_step: bool) -> bool {
    if let Some(message) = beyond_limits(app, &candidate) {
        app.message = Some(message);
        return false;
    }
    let source = app.exploration.source.to_string();
    if let Err(e) = candidate.validate(&source) {
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
    match candidate.validate(&source) {
        Ok((problem, settings)) => {
            let selected = app.exploration.selected_row();
            if undo_step {
                remember(app);
            }
            app.exploration.scene = candidate;
            app.message = None;
            if let Some(old) = selected.obstacle()
                && let Some(new) = order.iter().position(|&i| i == old)
                && new != old
            {
                let moved = selected.for_obstacle(new);
                let rows = app.exploration.rows();
                app.exploration.selected = rows.iter().position(|r| *r == moved).unwrap_or(0);
            }
            clamp_selection(app);
            request_solve(app, problem, settings);
            true
        }
        Err(e) => {
            app.message = Some(format!("rejected: {}: {}", e.field, e.rule));
            false
        }
    }
}

/// `dual-inverse` at its limit (N = 3998 unknowns) takes about 3 s (criterion, release), and
/// its cost grows like N³.
const DUAL_INVERSE_SECONDS_AT_LIMIT: (f64, f64) = (3.0, 3998.0);
/// Cycling `m` does not enter a method expected to take longer than this; typing its name in
/// the method row still runs it.
const QUICK_SECONDS: f64 = 1.0;

/// Expected run time of `method` on the current mesh, where it is known to be slow.
fn expected_seconds(app: &App, method: Method) -> Option<f64> {
    let unknowns = 2.0 * app.exploration.wanted.elements.saturating_sub(1) as f64;
    match method {
        Method::DualInverse => {
            let (seconds, at) = DUAL_INVERSE_SECONDS_AT_LIMIT;
            Some(seconds * (unknowns / at).powi(3))
        }
        _ => None,
    }
}

/// The next method in the cycle, skipping (with a note) one expected to take long here.
pub(super) fn next_method(app: &mut App) {
    let mut candidate = step(app.scene(), Row::Method, 1, false);
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
            app.exploration.wanted.elements
        ));
    }
}

/// Steps the selected row's value in `direction` (fine or coarse).
pub(super) fn change(app: &mut App, direction: i32, coarse: bool) {
    let row = app.exploration.selected_row();
    let candidate = step(app.scene(), row, direction, coarse);
    if candidate == *app.scene() {
        app.message = Some(format!("{} cannot go further", row.label().trim()));
        return;
    }
    try_apply(app, candidate);
}

/// `a`: an obstacle in the middle of the widest gap, with the thresholds of the selected
/// obstacle (or the last one).
pub(super) fn add_obstacle(app: &mut App) {
    let scene = app.scene();
    let l = scene.beam.length;
    let mut points: Vec<f64> = vec![0.0];
    points.extend(scene.obstacles.iter().map(|o| o.x));
    points.push(l);
    // The middle of the widest gap.
    let (a, b) = points
        .windows(2)
        .map(|w| (w[0], w[1]))
        .max_by(|p, q| (p.1 - p.0).total_cmp(&(q.1 - q.0)))
        .expect("at least two points");
    let template = app
        .exploration
        .selected_row()
        .obstacle()
        .or(scene.obstacles.len().checked_sub(1))
        .map(|i| scene.obstacles[i]);
    let new = ObstacleSpec {
        x: 0.5 * (a + b),
        sliding: template.map_or(1e2, |o| o.sliding),
        swivel: template.map_or(5e4, |o| o.swivel),
    };
    let mut candidate = scene.clone();
    candidate.obstacles.push(new);
    if try_apply(app, candidate) {
        let index = app
            .scene()
            .obstacles
            .iter()
            .position(|o| *o == new)
            .unwrap_or(0);
        let rows = app.exploration.rows();
        app.exploration.selected = rows
            .iter()
            .position(|r| *r == Row::ObstacleX(index))
            .unwrap_or(0);
        app.message = Some(format!("obstacle {} added at x = {} m", index + 1, new.x));
    }
}

/// `d`: the selected obstacle goes.
pub(super) fn delete_obstacle(app: &mut App) {
    let Some(index) = app.exploration.selected_row().obstacle() else {
        app.message = Some("select a row of an obstacle to delete it".into());
        return;
    };
    let mut candidate = app.scene().clone();
    candidate.obstacles.remove(index);
    if try_apply(app, candidate) {
        clamp_selection(app);
        app.message = Some(format!("obstacle {} deleted", index + 1));
    }
}

/// Replaces the scene by a newly loaded one (a preset), and re-solves. Undo starts afresh,
/// and nothing of the last scene's view carries over.
pub(super) fn load(app: &mut App, loaded: LoadedScene) {
    let Ok(loaded) = sorted(loaded) else { return };
    let (problem, settings) = (loaded.problem.clone(), loaded.settings);
    app.saved = loaded.scene.clone();
    app.history = History::default();
    app.zoom = false;
    // The last solve and sweeps stay, drawn as out of date until the new ones arrive.
    let shown = app.exploration.shown.take();
    let sweeps = std::mem::take(&mut app.exploration.sweeps);
    app.exploration = Exploration {
        shown,
        sweeps,
        ..Exploration::new(loaded)
    };
    request_solve(app, problem, settings);
}

/// Shows the scene at this explorer's element limit when it asks for more (a fork of the
/// presenter's finer mesh, a lesson's step), as the scene loaded: `r` comes back to it, undo
/// does not go past it, and nothing of it is unsaved. Returns the n asked for when it capped.
pub(super) fn cap_at_limit(app: &mut App) -> Option<usize> {
    let max = app.max_elements?;
    let asked = app.scene().mesh.elements;
    if asked <= max {
        return None;
    }
    let mut capped = app.scene().clone();
    capped.mesh.elements = max;
    let validated = capped.validate(&app.exploration.source.to_string()).ok()?;
    if !try_apply_keeping_undo(app, capped, false) {
        return None;
    }
    app.saved = app.exploration.scene.clone();
    app.exploration.loaded = app.exploration.scene.clone();
    app.exploration.loaded_problem = validated;
    Some(asked)
}

/// Loads the preset with this index into [`PRESETS`], unless it is beyond this explorer's
/// limits.
pub(super) fn load_preset(app: &mut App, index: usize) {
    let preset = &PRESETS[index.min(PRESETS.len() - 1)];
    match LoadedScene::preset(preset) {
        Ok(loaded) if beyond_limits(app, &loaded.scene).is_some() => {
            app.message = beyond_limits(app, &loaded.scene);
        }
        Ok(loaded) => {
            app.save_path = crate::tui::state::app::default_save_path(
                &app.save_policy,
                Some(&app.save_directory),
                app.owner.as_deref(),
                &loaded.source,
            );
            load(app, loaded);
            app.message = Some(format!("loaded {}", preset.name));
        }
        Err(e) => app.message = Some(e.to_string()),
    }
}

/// `b`: the deflection panel's next diagram.
pub(super) fn next_diagram(exploration: &mut Exploration) {
    exploration.diagram = match exploration.diagram {
        Diagram::Deflection => Diagram::Moment,
        Diagram::Moment => Diagram::Shear,
        Diagram::Shear => Diagram::Deflection,
    };
}
