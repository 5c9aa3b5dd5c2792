//! `e`: the focused panel as a slide-quality SVG figure (`crate::figure`, the same drawing as
//! `beamfric figure` and the report's), written next to where the scene would be saved,
//! named after it and the panel (`benchmark-1-eps-error.svg`), never over a file (`-2`, `-3`
//! … instead), atomically, only where this explorer may write; the message names the file.

use std::path::{Path, PathBuf};

use crate::figure::{
    DeflectionInput, ErrorAxis, FigurePanel, deflection_figure, eps_cond_figure, eps_error_figure,
    error_time_figure,
};
use crate::plot::CurrentRun;
use crate::scene::{Panel, SaveError, write_atomic};
use crate::study::{EpsPoint, MeshPoint};
use crate::tui::state::sweeps::SweepView;
use crate::tui::state::{App, SavePolicy};

use super::save::save_target;

/// Most numbered names tried before giving up (`…-99.svg`).
const MOST_NUMBERED: usize = 99;

/// Exports the focused panel, or says why not.
pub(super) fn export_figure(app: &mut App) {
    let panels = app.exploration.panels();
    let Some(&panel) = panels.get(app.exploration.focus).or(panels.first()) else {
        app.message = Some("no panel to export".into());
        return;
    };
    let svg = match figure_of(app, panel) {
        Ok(svg) => svg,
        Err(why) => {
            app.message = Some(format!("figure not written: {why}"));
            return;
        }
    };
    app.message = Some(match write_figure(app, panel, &svg) {
        Ok(name) if panel == Panel::Deflection && !shows_deflection(app) => {
            format!("figure saved: {name} (of u(x): M, T and u − u_ref are not exported)")
        }
        Ok(name) => format!("figure saved: {name} (SVG, 1280×720, for slides)"),
        Err(why) => format!("figure not written: {why}"),
    });
}

/// Does the deflection panel show u(x) itself (not M, T or u − u_ref)?
fn shows_deflection(app: &App) -> bool {
    app.exploration.diagram == crate::tui::state::Diagram::Deflection && !app.show_difference
}

/// The SVG of `panel` from what the explorer shows, or why there is none yet.
fn figure_of(app: &App, panel: Panel) -> Result<String, String> {
    let scene = app.scene();
    let against = if app.show_timings {
        ErrorAxis::RunTime
    } else {
        ErrorAxis::Elements
    };
    let scene_title = if scene.title.is_empty() {
        app.exploration.source.stem()
    } else {
        scene.title.clone()
    };
    let Some(figure_panel) = FigurePanel::of(panel) else {
        return Err(format!(
            "the {} panel is for the screen only; e exports the deflection, eps-error, eps-cond \
             and error-time panels (`beamfric figure` too)",
            panel.name()
        ));
    };
    let title = crate::figure::figure_title(&scene_title, figure_panel, against);
    let computing = |view_notice: String| format!("the panel has no data yet ({view_notice})");
    match panel {
        Panel::Deflection => {
            let shown = app
                .exploration
                .shown
                .as_ref()
                .ok_or_else(|| "the scene is still being solved".to_string())?;
            let solution = shown
                .solution
                .as_ref()
                .map_err(|e| format!("no solution to draw: {e}"))?;
            Ok(deflection_figure(
                &DeflectionInput {
                    problem: &shown.request.problem,
                    mesh: &shown.mesh,
                    solution,
                    reference: shown.reference.as_ref(),
                },
                &title,
            ))
        }
        Panel::EpsError | Panel::EpsCond => {
            let points: &Vec<EpsPoint> = match app.exploration.sweep_view::<Vec<EpsPoint>>(panel) {
                SweepView::Ready(points) => points,
                SweepView::Outdated(_) => return Err(computing("updating".into())),
                SweepView::Notice(text) => return Err(computing(text)),
            };
            let epsilon = Some(scene.solver.epsilon);
            Ok(if panel == Panel::EpsError {
                eps_error_figure(points, epsilon, &title)
            } else {
                eps_cond_figure(points, epsilon, &title)
            })
        }
        Panel::ErrorTime => {
            let points: &Vec<MeshPoint> = match app.exploration.sweep_view::<Vec<MeshPoint>>(panel)
            {
                SweepView::Ready(points) => points,
                SweepView::Outdated(_) => return Err(computing("updating".into())),
                SweepView::Notice(text) => return Err(computing(text)),
            };
            let current = CurrentRun {
                elements: scene.mesh.elements,
                method: scene.solver.method,
            };
            Ok(error_time_figure(points, against, Some(current), &title))
        }
        // Refused above: no figure of their own.
        Panel::Figure5 | Panel::Iterations | Panel::DualBox | Panel::Cases | Panel::Matrices => {
            Err(format!("the {} panel has no figure", panel.name()))
        }
    }
}

/// The figure's file name: the scene's save name without `.toml`, then the panel's name.
fn figure_name(save_path: &str, panel: Panel, number: usize) -> String {
    let stem = save_path.strip_suffix(".toml").unwrap_or(save_path);
    let stem = if stem.is_empty() { "figure" } else { stem };
    match number {
        1 => format!("{stem}-{}.svg", panel.name()),
        n => format!("{stem}-{}-{n}.svg", panel.name()),
    }
}

/// Writes the figure under the first free name; returns that name as the user would type it.
fn write_figure(app: &App, panel: Panel, svg: &str) -> Result<String, String> {
    let target_of = |name: &str| -> Result<PathBuf, String> {
        match &app.save_policy {
            SavePolicy::Write => Ok(PathBuf::from(name)),
            SavePolicy::Within(dir) if !dir.is_dir() => Err(format!(
                "{} is not a directory, and it is the only place files may go",
                super::save::directory_shown(app, dir)
            )),
            SavePolicy::Within(dir) => save_target(&app.save_policy, name)
                .ok_or_else(|| super::save::not_a_target(app, dir, name)),
            SavePolicy::Simulate => Err(format!(
                "{name} (a render writes no files without --allow-save DIR)"
            )),
            SavePolicy::Refuse(reason) => Err(reason.clone()),
            SavePolicy::ShowText => {
                Err("this server keeps no files (it was started without --save-dir)".into())
            }
        }
    };
    for number in 1..=MOST_NUMBERED {
        let name = figure_name(&app.save_path, panel, number);
        let target = target_of(&name)?;
        match write_atomic(Path::new(&target), svg.as_bytes(), false) {
            Ok(_) => return Ok(name),
            Err(SaveError::Exists(_)) => continue,
            Err(e) => return Err(super::save::error_shown(app, &e)),
        }
    }
    Err(format!(
        "{} to {} are all taken",
        figure_name(&app.save_path, panel, 1),
        figure_name(&app.save_path, panel, MOST_NUMBERED)
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_follow_the_scene_and_the_panel() {
        assert_eq!(
            figure_name("benchmark-1.toml", Panel::EpsError, 1),
            "benchmark-1-eps-error.svg"
        );
        assert_eq!(
            figure_name("out/alice-b.toml", Panel::ErrorTime, 3),
            "out/alice-b-error-time-3.svg"
        );
        assert_eq!(
            figure_name("", Panel::Deflection, 1),
            "figure-deflection.svg"
        );
    }
}
