//! The warnings of a solution as a lecturer reads them: ordered with the real cause first (a
//! matrix destroyed by rounding before the NaN it produced), each with a short form for the
//! status line, and the warnings view (`w`) that shows every word of every one of them.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::{Clear, Paragraph};

use super::fit::wrap_words;

use crate::plot::Theme;
use crate::solve::{KktGrade, Solution, SolveError, Warning, WarningCode};
use crate::tui::input::keymap::up_down;
use crate::tui::state::App;

/// How early a warning of this kind is listed: causes (rounding destroyed the matrix, the
/// conditioning is beyond double precision) before their effects (NaN, visible error, a solver
/// that did not converge), notes last.
pub fn rank(code: WarningCode) -> u8 {
    match code {
        WarningCode::IndefiniteFactorization => 0,
        WarningCode::StiffnessConditioning => 1,
        WarningCode::NonFinite => 2,
        WarningCode::AccuracyLoss => 3,
        WarningCode::KktResidual => 3,
        WarningCode::QpNotConverged => 4,
        WarningCode::NewtonNotConverged => 5,
        WarningCode::RegularizationInconsistent => 6,
        WarningCode::UntrustedReference => 7,
        WarningCode::MeshRaised => 9,
    }
}

/// The warning in a few words, for the status line; the KKT check's graded by the residual
/// of the solution it is about ([`KktGrade`]).
pub fn headline(code: WarningCode, kkt_residual: f64) -> std::borrow::Cow<'static, str> {
    if code == WarningCode::KktResidual {
        return KktGrade::of(kkt_residual).headline(kkt_residual).into();
    }
    code_headline(code).into()
}

fn code_headline(code: WarningCode) -> &'static str {
    match code {
        WarningCode::IndefiniteFactorization => "rounding destroyed A: this result means nothing",
        WarningCode::StiffnessConditioning => "A is too ill-conditioned for double precision",
        WarningCode::NonFinite => "a value is NaN or infinite",
        WarningCode::AccuracyLoss => "visible error against the reference",
        WarningCode::KktResidual => "the independent KKT check fails: not a solution",
        WarningCode::QpNotConverged => "the friction QP did not converge",
        WarningCode::NewtonNotConverged => "Newton's iteration did not converge",
        WarningCode::RegularizationInconsistent => "no regularisation case fits exactly",
        WarningCode::UntrustedReference => "no trusted reference: no error shown",
        WarningCode::MeshRaised => "more elements than asked for",
    }
}

/// The warnings, most serious first (stable: equal ranks keep the solver's order).
pub fn ordered(solution: &Solution) -> Vec<&Warning> {
    let mut warnings: Vec<&Warning> = solution.warnings.iter().collect();
    warnings.sort_by_key(|w| rank(w.code));
    warnings
}

/// The lines of the warnings view, wrapped to `width`: each warning's short form and code,
/// then its whole message; or the error of a failed solve.
fn view_lines(
    result: &Result<Solution, SolveError>,
    theme: &Theme,
    width: usize,
) -> Vec<Line<'static>> {
    let mut lines = Vec::new();
    let mut push = |text: &str, style| {
        lines.extend(
            wrap_words(&theme.text(text), width)
                .into_iter()
                .map(|l| Line::styled(l, style)),
        )
    };
    match result {
        Ok(solution) => {
            let warnings = ordered(solution);
            if warnings.is_empty() {
                push(
                    "no warnings: the certificate found nothing to report",
                    theme.plain(),
                );
            }
            for (i, warning) in warnings.iter().enumerate() {
                if i > 0 {
                    push("", theme.plain());
                }
                let head = format!(
                    "{}. {} ({})",
                    i + 1,
                    headline(warning.code, solution.kkt_residual),
                    warning.code.name()
                );
                push(&head, theme.warning());
                push(&warning.message, theme.plain());
            }
        }
        Err(error) => {
            push(
                &format!("{} could not solve this scene:", error.method),
                theme.error(),
            );
            push(&error.to_string(), theme.plain());
        }
    }
    lines
}

/// The warnings view over the whole frame: every warning, wrapped, nothing cut (scrolled by
/// `offset` lines when taller than the screen).
pub(super) fn draw_view(frame: &mut Frame, app: &App, theme: &Theme, area: Rect, offset: u16) {
    frame.render_widget(Clear, area);
    let Some(shown) = &app.exploration.shown else {
        frame.render_widget(Paragraph::new("no solution yet"), area);
        return;
    };
    let title = format!(
        " Warnings: {} at n = {}{} ({} scroll, any other key closes) ",
        shown.request.method,
        shown.mesh.elements(),
        if app.exploration.is_current() {
            ""
        } else {
            ", previous result"
        },
        up_down(app.look.ascii)
    );
    let block = theme.block(title, true);
    let inner = block.inner(area);
    let lines = view_lines(&shown.solution, theme, inner.width as usize);
    let total = lines.len() as u16;
    let offset = offset.min(total.saturating_sub(inner.height));
    let more_below = total > offset + inner.height;
    let block = if offset > 0 || more_below {
        block.title_bottom(format!(
            " {} PgUp PgDn: lines {}–{} of {total} ",
            up_down(app.look.ascii),
            offset + 1,
            (offset + inner.height).min(total)
        ))
    } else {
        block
    };
    frame.render_widget(Paragraph::new(lines).scroll((offset, 0)).block(block), area);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn causes_come_before_effects() {
        assert!(rank(WarningCode::IndefiniteFactorization) < rank(WarningCode::NonFinite));
        assert!(rank(WarningCode::StiffnessConditioning) < rank(WarningCode::AccuracyLoss));
        assert!(rank(WarningCode::AccuracyLoss) < rank(WarningCode::MeshRaised));
        for code in WarningCode::ALL {
            assert!(!headline(code, 1e-3).is_empty());
        }
    }

    /// Issue 25: a KKT residual of 1e-9 is not called "not a solution"; 1e-1 is.
    #[test]
    fn the_kkt_headline_is_graded_by_the_residual() {
        let at = |residual: f64| headline(WarningCode::KktResidual, residual).into_owned();
        assert_eq!(
            at(1.3e-9),
            "KKT check off by 1.3e-9: accurate to about that"
        );
        assert_eq!(at(2.0e-4), "KKT check off by 2.0e-4: approximate only");
        assert_eq!(
            at(0.5),
            "the independent KKT check fails by 5.0e-1: not a solution"
        );
        assert!(at(f64::NAN).contains("not a solution"));
        assert!(!at(1e-7).contains("not a solution"));
    }
}
