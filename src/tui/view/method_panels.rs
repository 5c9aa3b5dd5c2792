//! The panels that show how a method works (issue 24): its iterations (from the solve's own
//! history, recorded only while this panel is on screen), the dual's box for the selected
//! obstacle, the regularised method's cases of Table 1, and the matrices' structure — each
//! reading its data from the state and drawing it with `crate::plot`.

use ratatui::Frame;

use crate::plot::{
    DualBoxView, PanelFrame, Theme, cases_table, dual_box_chart, iterations_chart, notice,
    spy_panel,
};
use crate::scene::Panel;
use crate::study::{CaseStudy, MatrixStructure};
use crate::tui::jobs::sweeps::DualPicture;
use crate::tui::state::App;
use crate::tui::state::sweeps::SweepView;

/// The title's mark of a panel whose data belongs to the state before.
fn updating<T>(view: &SweepView<T>) -> &'static str {
    match view {
        SweepView::Outdated(_) => " · updating…",
        _ => "",
    }
}

/// Draws one of the method panels into `panel` (its title filled in here).
pub(super) fn draw(
    frame: &mut Frame,
    app: &App,
    theme: &Theme,
    which: Panel,
    mut panel: PanelFrame,
    suffix: &str,
) {
    match which {
        Panel::Iterations => iterations(frame, app, theme, panel, suffix),
        Panel::DualBox => {
            let view = app.exploration.sweep_view::<DualPicture>(Panel::DualBox);
            let obstacle = match &view {
                SweepView::Ready(p) | SweepView::Outdated(p) => {
                    format!(" at obstacle {}", p.pair.obstacle + 1)
                }
                SweepView::Notice(_) => String::new(),
            };
            panel.title = format!(" Dual (49){obstacle}{suffix}{} ", updating(&view));
            match view {
                SweepView::Ready(picture) | SweepView::Outdated(picture) => {
                    let selected = app
                        .exploration
                        .iterate
                        .filter(|_| app.exploration.panels().contains(&Panel::Iterations));
                    let view = DualBoxView {
                        pair: &picture.pair,
                        iterates: &picture.iterates,
                        selected: selected
                            .filter(|_| app.scene().solver.method == crate::solve::Method::Dual),
                        state: picture.state,
                    };
                    dual_box_chart(frame, theme, panel, &view)
                }
                SweepView::Notice(text) => notice(frame, theme, panel, text),
            }
        }
        Panel::Cases => {
            let view = app.exploration.sweep_view::<CaseStudy>(Panel::Cases);
            panel.title = format!(" Cases of Table 1 (43){suffix}{} ", updating(&view));
            match view {
                SweepView::Ready(study) | SweepView::Outdated(study) => {
                    cases_table(frame, theme, panel, study)
                }
                SweepView::Notice(text) => notice(frame, theme, panel, text),
            }
        }
        Panel::Matrices => {
            let view = app
                .exploration
                .sweep_view::<Vec<MatrixStructure>>(Panel::Matrices);
            panel.title = format!(" Matrices: pattern and size{suffix}{} ", updating(&view));
            match view {
                SweepView::Ready(matrices) | SweepView::Outdated(matrices) => {
                    spy_panel(frame, theme, panel, matrices)
                }
                SweepView::Notice(text) => notice(frame, theme, panel, text),
            }
        }
        _ => {}
    }
}

/// The iterations panel: the history the shown solve recorded.
fn iterations(frame: &mut Frame, app: &App, theme: &Theme, mut panel: PanelFrame, suffix: &str) {
    let method = app.scene().solver.method;
    let outdated = if app.exploration.is_current() {
        ""
    } else {
        " · updating…"
    };
    panel.title = format!(" Iterations of {}{suffix}{outdated} ", method.name());
    let history = match app.exploration.solution() {
        None => return notice(frame, theme, panel, "solving…".into()),
        Some(Err(error)) => {
            return notice(
                frame,
                theme,
                panel,
                format!("no solution: {}", error.reason),
            );
        }
        Some(Ok(solution)) => solution.history.as_ref(),
    };
    match history {
        Some(history) if !history.iterations.is_empty() => {
            iterations_chart(frame, theme, panel, history, app.exploration.iterate)
        }
        _ if !app.exploration.is_current() => notice(frame, theme, panel, "solving…".into()),
        _ => notice(
            frame,
            theme,
            panel,
            format!(
                "{} takes no iterations: {}",
                method.name(),
                no_iterations(method)
            ),
        ),
    }
}

/// Why a method has no iterations to show, and where to look instead.
fn no_iterations(method: crate::solve::Method) -> &'static str {
    use crate::solve::Method;
    match method {
        Method::Regularized => {
            "it solves every case of Table 1 and keeps the consistent one (the cases panel)"
        }
        Method::ClosedForm => "the answer is a formula, (50)-(51)",
        _ => "none recorded",
    }
}
