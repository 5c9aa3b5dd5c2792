//! The Results panel: the solution at the obstacles, one compact line each — its state, the
//! friction force λ1 and the friction moment λ2 (the paper's names, so they are not mistaken
//! for the chart's bending moment M) — then u and u' of the selected obstacle. The rows
//! follow the selection when there are more obstacles than lines.
//!
//! For the regularised methods an obstacle below its threshold is not stuck: in the
//! regularised model (the paper's ε-band) the point moves by about ε·λ, so it is said to
//! creep, with the exact method's state next to it when the reference is at hand.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::Paragraph;

use crate::format::eng;
use crate::plot::Theme;
use crate::solve::Solution;
use crate::tui::state::App;
use crate::tui::state::motion::{NOISE, state_word};

/// `value` with its unit, or `≈0` when it is below the rounding noise `noise`.
fn small(value: f64, noise: f64, unit: &str) -> String {
    if value.is_finite() && value.abs() <= noise {
        format!("≈0 {unit}")
    } else {
        format!("{} {unit}", eng(value))
    }
}

/// The first obstacle row shown: the selected obstacle stays visible.
fn first_row(selected: Option<usize>, count: usize, visible: usize) -> usize {
    let selected = selected.unwrap_or(0).min(count.saturating_sub(1));
    (selected + 1).saturating_sub(visible)
}

pub(super) fn draw_results(frame: &mut Frame, app: &App, theme: &Theme, area: Rect) {
    let (Some(Ok(solution)), Some(shown)) = (app.exploration.solution(), &app.exploration.shown)
    else {
        let block = theme.block(" Results ", false);
        let inner = block.inner(area);
        frame.render_widget(block, area);
        let text = match app.exploration.solution() {
            None => "solving…",
            Some(_) => "no solution (w: why)",
        };
        frame.render_widget(Paragraph::new(text).style(theme.error()), inner);
        return;
    };
    let width = area.width.saturating_sub(2) as usize;
    let height = area.height.saturating_sub(2) as usize;
    let selected = app.exploration.selected_row().obstacle();
    let count = solution.obstacles.len();
    // max |u|, the header and (when there is room) the selected obstacle's detail: one line,
    // and under a regularised method a second with the exact state.
    let wanted_detail = if solution.method.is_regularized() {
        2
    } else {
        1
    };
    let detail_rows = if count == 0 {
        0
    } else if height >= 2 + count + wanted_detail || height >= 6 + wanted_detail {
        wanted_detail
    } else {
        usize::from(height > 2 + count || height >= 6)
    };
    let visible = height.saturating_sub(2 + detail_rows).max(1);
    let first = first_row(selected, count, visible);
    let last = (first + visible).min(count);
    let title = if count > visible {
        format!(" Results {}–{} of {count} ", first + 1, last)
    } else {
        " Results ".to_string()
    };
    let block = theme.block(title, false);
    let lines = result_lines(
        app,
        solution,
        shown.max_deflection,
        width,
        first..last,
        detail_rows,
        theme,
    );
    frame.render_widget(Paragraph::new(lines).block(block), area);
}

fn result_lines(
    app: &App,
    solution: &Solution,
    max_deflection: f64,
    width: usize,
    rows: std::ops::Range<usize>,
    detail_rows: usize,
    theme: &Theme,
) -> Vec<Line<'static>> {
    let detail = detail_rows > 0;
    let regularized = solution.method.is_regularized();
    let wide = width >= 36;
    let mut lines = vec![Line::from(format!("max |u| {} m", eng(max_deflection)))];
    let header = if wide {
        format!(
            "{:>2} {:<6} {:<7} {:>8} {:>8}",
            "#", "x [m]", "state", "λ1 [N]", "λ2 [N m]"
        )
    } else {
        format!(
            "{:>2} {:<7} {:>8} {:>8}",
            "#", "state", "λ1 [N]", "λ2 [N m]"
        )
    };
    lines.push(Line::styled(header, theme.dim()));
    let selected = app.exploration.selected_row().obstacle();
    for i in rows {
        let o = &solution.obstacles[i];
        let state = state_word(o, regularized, max_deflection);
        let text = if wide {
            format!(
                "{:>2} {:<6} {:<7} {:>8} {:>8}",
                i + 1,
                eng(o.x),
                state,
                eng(o.force),
                eng(o.moment)
            )
        } else {
            format!(
                "{:>2} {:<7} {:>8} {:>8}",
                i + 1,
                state,
                eng(o.force),
                eng(o.moment)
            )
        };
        let style = if Some(i) == selected {
            theme.selected()
        } else {
            theme.plain()
        };
        lines.push(Line::styled(text, style));
    }
    if detail {
        let i = selected.unwrap_or(0).min(solution.obstacles.len() - 1);
        let o = &solution.obstacles[i];
        let slope_noise = NOISE * max_deflection / app.exploration.problem.length;
        let mut text = super::fit::fit_items(
            &[
                super::fit::Item::new(
                    0,
                    format!("#{} u {}", i + 1, small(o.u, NOISE * max_deflection, "m")),
                ),
                super::fit::Item::new(1, format!("u' {}", small(o.slope, slope_noise, "rad"))),
            ],
            ", ",
            width,
        );
        // The exact problem's state of the same obstacle, next to a regularised one's.
        let exact = app
            .exploration
            .shown
            .as_ref()
            .and_then(|shown| shown.reference.as_ref())
            .and_then(|reference| reference.obstacles.get(i))
            .filter(|_| regularized)
            .map(|r| state_word(r, false, max_deflection));
        let creeps = regularized && state_word(o, true, max_deflection) == "creeps";
        match exact {
            // One row: u and the exact state first, the slope if it fits.
            Some(exact) if detail_rows < 2 => {
                text = super::fit::fit_items(
                    &[
                        super::fit::Item::new(
                            0,
                            format!("#{} u {}", i + 1, small(o.u, NOISE * max_deflection, "m")),
                        ),
                        super::fit::Item::new(1, format!("exact: {exact}")),
                    ],
                    ", ",
                    width,
                );
                lines.push(Line::styled(text, theme.dim()));
            }
            Some(exact) => {
                if creeps {
                    text = format!("#{} creeps {} m in the ε-band", i + 1, eng(o.u.abs()));
                }
                lines.push(Line::styled(text, theme.dim()));
                lines.push(Line::styled(
                    format!("   exact (condensed): {exact}"),
                    theme.dim(),
                ));
            }
            None => {
                if o.state().contains("threshold") {
                    text = format!("#{} {}", i + 1, o.state());
                }
                lines.push(Line::styled(text, theme.dim()));
            }
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_follow_the_selection() {
        assert_eq!(first_row(None, 8, 5), 0);
        assert_eq!(first_row(Some(4), 8, 5), 0);
        assert_eq!(first_row(Some(5), 8, 5), 1);
        assert_eq!(first_row(Some(7), 8, 5), 3);
        assert_eq!(first_row(Some(20), 8, 5), 3);
        assert_eq!(first_row(Some(0), 0, 5), 0);
    }

    #[test]
    fn noise_is_shown_as_noise() {
        assert_eq!(small(2.78e-17, 1e-14, "rad"), "≈0 rad");
        assert_eq!(small(5.7e-3, 1e-14, "m"), "5.7e-3 m");
    }
}
