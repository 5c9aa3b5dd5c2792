//! The last stage of the search (`search`): the final pattern's solution in SI units, and
//! the record of every pattern solve for the convergence history (the KKT residual of (38)'s
//! friction conditions on it).

use super::nodes::nodal_field;
use super::scaling::Scales;
use super::system::{Pattern, PatternSolution, ShootingSystem};
use super::{CondensedFailure, CondensedSolution, FrictionPattern};
use crate::fem::Mesh;
use crate::linalg::banded_lu::times_power_of_two;
use crate::model::Problem;
use crate::solve::FrictionState;
use crate::solve::history::{DofState, Recorder};

/// The last stage: the final pattern's solution in SI units — the friction states, the
/// friction forces (a moving DOF's exactly its threshold) and every node (asking `keep_going`
/// as it goes).
pub(super) fn condensed_solution(
    (problem, mesh, scales): (&Problem, &Mesh, &Scales),
    system: &ShootingSystem,
    (solution, pattern): (&PatternSolution, &[Pattern]),
    (solves, converged): (usize, bool),
    keep_going: &mut dyn FnMut() -> bool,
) -> Result<CondensedSolution, CondensedFailure> {
    let states: Vec<[FrictionState; 2]> = (0..problem.obstacles.len())
        .map(|j| {
            [
                system.state(solution, pattern, 2 * j),
                system.state(solution, pattern, 2 * j + 1),
            ]
        })
        .collect();
    let friction = physical_friction(problem, scales, solution, pattern);
    let field = nodal_field(mesh, system, solution, scales, keep_going)?;
    Ok(CondensedSolution {
        field,
        friction,
        states,
        solves,
        counts: system.counts.get(),
        pattern: FrictionPattern(pattern.to_vec()),
        converged,
    })
}

/// The friction forces of a pattern's solution in SI units, (force [N], moment [N m]) per
/// obstacle: a moving DOF's exactly its threshold, a stuck one's solved force clamped to it.
fn physical_friction(
    problem: &Problem,
    scales: &Scales,
    solution: &PatternSolution,
    pattern: &[Pattern],
) -> Vec<[f64; 2]> {
    problem
        .obstacles
        .iter()
        .enumerate()
        .map(|(j, o)| {
            let physical = |d: usize, threshold: f64, exponent: i32| match pattern[2 * j + d] {
                // Exactly the threshold: no round trip through the scaling.
                Pattern::Positive => threshold,
                Pattern::Negative => -threshold,
                Pattern::Stuck => {
                    let l = times_power_of_two(solution.lambda[2 * j + d], exponent);
                    l.clamp(-threshold, threshold)
                }
            };
            [
                physical(0, o.sliding_threshold, scales.force()),
                physical(1, o.swivel_threshold, scales.moment()),
            ]
        })
        .collect()
}

/// Records one pattern solve: the KKT residual of (38)'s friction conditions on it — the
/// worst of a stuck force's excess over its threshold, relative to the largest force of its
/// kind (or the threshold, if larger), and a moving DOF's motion against its force's sign,
/// relative to the largest motion of its kind — the pattern as the states, and the forces in
/// SI units as the answer would report them.
pub(super) fn record_pattern(
    recorder: &mut Recorder,
    (problem, scales, system): (&Problem, &Scales, &ShootingSystem),
    solution: &PatternSolution,
    pattern: &[Pattern],
) {
    let ratio = |violation: f64, scale: f64| {
        if violation > 0.0 && scale > 0.0 {
            violation / scale
        } else {
            0.0
        }
    };
    let residual = (0..pattern.len())
        .map(|i| {
            let d = i % 2;
            let g = system.thresholds[i / 2][d];
            match pattern[i] {
                Pattern::Stuck => ratio(
                    solution.lambda[i].abs() - g,
                    solution.largest_force[d].max(g),
                ),
                Pattern::Positive => ratio(
                    -system.friction_value(solution, i),
                    solution.largest_motion[d],
                ),
                Pattern::Negative => ratio(
                    system.friction_value(solution, i),
                    solution.largest_motion[d],
                ),
            }
        })
        .fold(0.0f64, f64::max);
    let states: Vec<DofState> = pattern
        .iter()
        .map(|state| match state {
            Pattern::Stuck => DofState::Inside,
            Pattern::Negative => DofState::AtLower,
            Pattern::Positive => DofState::AtUpper,
        })
        .collect();
    let forces = physical_friction(problem, scales, solution, pattern);
    recorder.record(residual, None, &states, forces);
}
