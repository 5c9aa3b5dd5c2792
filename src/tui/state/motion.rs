//! How the explorer names an obstacle's motion: one word of at most seven letters, shared by
//! the Results panel and the deflection chart's key. For the regularised methods a point below
//! its threshold is not stuck: in the regularised model (the paper's ε-band of (40)) it moves
//! by about ε·λ, so it is said to creep.

use crate::solve::{FrictionState, ObstacleResult};

/// Relative size under which a motion is rounding noise, not motion.
pub const NOISE: f64 = 1e-12;

/// How an obstacle moves, in a word of at most seven letters (the Results panel's detail line
/// gives the full words for a DOF at its threshold).
pub fn state_word(
    obstacle: &ObstacleResult,
    regularized: bool,
    max_deflection: f64,
) -> &'static str {
    use FrictionState::{AtThreshold as T, Moves as M, Stuck as S};
    if obstacle.state() == "unknown" {
        return "unknown";
    }
    let moves = obstacle.u.abs() > NOISE * max_deflection;
    match (obstacle.sliding_state, obstacle.swivel_state) {
        (S, S) if regularized && moves => "creeps",
        (S, S) => "stuck",
        (M, S) | (M, T) => "slides",
        (S, M) | (T, M) => "swivels",
        (M, M) => "both",
        (T, S) => "at g1",
        (S, T) => "at g2",
        (T, T) => "at g1+2",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn obstacle(u: f64, force: f64, sliding: bool) -> ObstacleResult {
        ObstacleResult {
            x: 0.8,
            u,
            slope: 0.0,
            force,
            moment: 0.0,
            sliding_state: if sliding {
                FrictionState::Moves
            } else {
                FrictionState::Stuck
            },
            swivel_state: FrictionState::Stuck,
            sliding,
            swivel: false,
        }
    }

    #[test]
    fn a_regularised_point_below_its_threshold_creeps() {
        let moving = obstacle(5.8e-3, 57.99, false);
        assert_eq!(state_word(&moving, true, 0.03), "creeps");
        // The same numbers from an exact method: stuck (u is noise there by definition).
        assert_eq!(state_word(&moving, false, 0.03), "stuck");
        // Rounding noise is no creep.
        assert_eq!(
            state_word(&obstacle(1e-17, 1.0, false), true, 0.03),
            "stuck"
        );
        assert_eq!(
            state_word(&obstacle(5.8e-3, 100.0, true), true, 0.03),
            "slides"
        );
    }
}
