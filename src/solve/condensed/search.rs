//! The search for the friction pattern: semismooth Newton phases, then a monotone search (exact
//! line search on the convex objective, feature-sign fallback) that can neither cycle nor
//! stall.

use std::collections::HashSet;

use super::line_search::SearchPoint;
use super::nodes::nodal_field;
use super::scaling::Scales;
use super::system::{Accuracy, BAND_LOWER, BAND_UPPER, Pattern, PatternSolution, ShootingSystem};
use super::{CondensedFailure, CondensedSolution};
use crate::fem::Mesh;
use crate::linalg::banded_lu::{BandedSystem, times_power_of_two};
use crate::model::Problem;
use crate::solve::FrictionState;

/// Most solves of one semismooth Newton phase.
pub(super) const NEWTON_STEPS: usize = 40;
/// The Newton phases tried in turn before the monotone search, by σ / diagonal stiffness of
/// the reversal prediction. Measured on the benchmark scenes (`condensed-many-obstacles`,
/// 16–4000 obstacles with random thresholds) once uncertain decisions wait for refinement:
/// σ = 0 converges in 6–16 solves where 0.5 diverges after a few steps at 4000 obstacles;
/// 0.5 stays as the second variant for scenes where 0 cycles.
pub(super) const NEWTON_REVERSAL_FRACTIONS: [f64; 2] = [0.0, 0.5];
/// A Newton phase is abandoned when the number of inconsistent DOFs has not reached a new
/// low for this many solves.
pub(super) const NEWTON_PATIENCE: usize = 6;

/// A 64-bit fingerprint of a pattern (FNV-1a over the states).
fn fingerprint(pattern: &[Pattern]) -> u64 {
    pattern
        .iter()
        .fold(0xcbf2_9ce4_8422_2325u64, |hash, state| {
            let byte = match state {
                Pattern::Stuck => 0u64,
                Pattern::Positive => 1,
                Pattern::Negative => 2,
            };
            (hash ^ byte).wrapping_mul(0x0000_0100_0000_01b3)
        })
}

/// [`solve_condensed_while`] with the given Newton phases (none: the monotone search alone).
pub(super) fn solve_with_newton_phases(
    problem: &Problem,
    mesh: &Mesh,
    newton_phases: &[f64],
    keep_going: &mut dyn FnMut() -> bool,
) -> Result<CondensedSolution, CondensedFailure> {
    let scales = Scales::of(problem);
    // The first Newton phase's σ fraction; without Newton phases, the first variant's (a
    // reversing DOF is held stuck).
    let first_fraction = newton_phases
        .first()
        .copied()
        .unwrap_or(NEWTON_REVERSAL_FRACTIONS[0]);
    let system = ShootingSystem::new(problem, mesh, &scales, first_fraction);
    let dofs = 2 * problem.obstacles.len();
    let mut pattern = vec![Pattern::Stuck; dofs];
    let limit = 4 * dofs + 64 + newton_phases.len() * NEWTON_STEPS;
    let mut solves = 0;
    // The iterate (u, u' at every interior special point), which only ever lowers J.
    let mut current: Option<SearchPoint> = None;
    // After adding DOFs at an optimum: the pattern and the single worst DOF to fall back on.
    let mut fallback: Option<(Vec<Pattern>, usize, Pattern)> = None;
    // Every pattern is solved by elimination alone; when a decision is within what that can
    // resolve (or the pattern looks consistent), the same system is refined from its factors
    // (each value to its own last bits) and the decision is taken on the refined values.
    let mut banded = BandedSystem::new(0, BAND_LOWER, BAND_UPPER);
    let mut newton_phase = !newton_phases.is_empty();
    let (mut phase, mut phase_start) = (0, 0);
    // The fewest inconsistent DOFs seen in this phase, and when.
    let mut fewest_changes = (usize::MAX, 0);
    // Over every Newton phase: the solved pattern with the fewest inconsistent DOFs, where the
    // monotone search starts (any start is a point it then only improves; from all stuck it
    // frees the DOFs a line search at a time, O(k) solves when hundreds move).
    let mut best_start: (usize, Option<Vec<Pattern>>) = (usize::MAX, None);
    // Patterns this phase has solved, by fingerprint (hashing 8000 states with SipHash cost
    // 2 % of a 4000-obstacle solve; a collision would only end a Newton phase early).
    let mut seen: HashSet<u64> = HashSet::new();
    let changes_of = |solution: &PatternSolution, pattern: &[Pattern]| -> Vec<(usize, Pattern)> {
        (0..dofs)
            .filter_map(|i| {
                let wanted = system.wanted(solution, pattern, i);
                (wanted != pattern[i]).then_some((i, wanted))
            })
            .collect()
    };
    let (solution, converged) = loop {
        if !keep_going() {
            return Err(CondensedFailure::Stopped);
        }
        let mut solution = system.solve_pattern(&pattern, Accuracy::Plain, &mut banded)?;
        solves += 1;
        let mut changes = changes_of(&solution, &pattern);
        // Newton steps take the decisions that elimination alone settles first, the others
        // on refined values once nothing else is left to change; the monotone search (which
        // must not be misled by a wrong sign) decides on refined values whenever any
        // decision is uncertain.
        let uncertain = system.uncertain(&solution, &pattern);
        if newton_phase {
            changes.retain(|&(i, _)| !uncertain[i]);
        } else if uncertain.iter().any(|&u| u) {
            changes.clear();
        }
        if changes.is_empty() {
            solution = system.solve_pattern(&pattern, Accuracy::RefineLast, &mut banded)?;
            changes = changes_of(&solution, &pattern);
            if changes.is_empty() {
                break (solution, true);
            }
        }
        if solves >= limit {
            break (solution, false);
        }
        if newton_phase {
            // Plain semismooth Newton: every inconsistent DOF changes at once. Fast when it
            // works; on a repeated pattern or too many steps, restart the monotone search.
            seen.insert(fingerprint(&pattern));
            if changes.len() < best_start.0 {
                best_start = (changes.len(), Some(pattern.clone()));
            }
            for &(i, wanted) in &changes {
                pattern[i] = wanted;
            }
            if changes.len() < fewest_changes.0 {
                fewest_changes = (changes.len(), solves);
            }
            let stalled = solves >= fewest_changes.1 + NEWTON_PATIENCE;
            if seen.contains(&fingerprint(&pattern))
                || stalled
                || solves >= phase_start + NEWTON_STEPS
            {
                fewest_changes = (usize::MAX, solves);
                // Next Newton variant, or the monotone search; both from the start.
                phase += 1;
                phase_start = solves;
                seen.clear();
                pattern = vec![Pattern::Stuck; dofs];
                match newton_phases.get(phase) {
                    Some(&fraction) => system.reversal_fraction.set(fraction),
                    None => {
                        newton_phase = false;
                        if let Some(start) = best_start.1.take() {
                            pattern = start;
                        }
                    }
                }
            }
            continue;
        }
        let candidate = system.search_point(&solution);
        // Every moving DOF keeps its sign (to within what the solve resolves): the candidate
        // minimises the pattern's quadratic, which equals J there and at the current point
        // (whose moving DOFs have these signs or are zero, and stuck ones are zero), so it is
        // a descent step as it is. The line search is for reversals only; on a step of
        // rounding size it would decide by noise and could stall.
        let keeps_signs = changes.iter().all(|&(i, _)| pattern[i] == Pattern::Stuck);
        let (c, full_step) = match current.take() {
            None => (candidate, true),
            Some(_) if keeps_signs => (candidate, true),
            Some(c) => {
                let (next, full) = system.line_search(&c, &candidate);
                if !full && next == c {
                    // No descent towards the optimum of the enlarged pattern.
                    match fallback.take() {
                        Some((base, i, moving))
                            if base.iter().zip(&pattern).any(|(a, b)| a != b) =>
                        {
                            // Several DOFs were freed at once: free only the worst one.
                            let mut single = base;
                            single[i] = moving;
                            if single != pattern {
                                pattern = single;
                                current = Some(c);
                                continue;
                            }
                            (candidate, true)
                        }
                        // Rounding decides the slope here: take the optimum as it is.
                        _ => (candidate, true),
                    }
                } else {
                    (next, full)
                }
            }
        };
        fallback = None;
        // At the optimum of the pattern (full step, every moving DOF with its sign): free the
        // stuck DOFs whose force exceeds the threshold (semismooth Newton / primal–dual active
        // set). Otherwise (the step stopped where a DOF reached zero): take the signs of the
        // new point, with its zeros stuck, and find that pattern's optimum first.
        let at_optimum = full_step && changes.iter().all(|&(i, _)| pattern[i] == Pattern::Stuck);
        if at_optimum {
            let base = pattern.clone();
            let mut worst: Option<(f64, usize, Pattern)> = None;
            for &(i, wanted) in &changes {
                pattern[i] = wanted;
                let l = solution.lambda[i].abs();
                let excess = (l - system.thresholds[i / 2][i % 2]) / l;
                if worst.is_none_or(|(e, _, _)| excess > e) {
                    worst = Some((excess, i, wanted));
                }
            }
            if changes.len() > 1
                && let Some((_, i, wanted)) = worst
            {
                fallback = Some((base, i, wanted));
            }
        } else {
            pattern = system.signs_of(&c);
        }
        current = Some(c);
    };

    let states: Vec<[FrictionState; 2]> = (0..problem.obstacles.len())
        .map(|j| {
            [
                system.state(&solution, &pattern, 2 * j),
                system.state(&solution, &pattern, 2 * j + 1),
            ]
        })
        .collect();
    let friction = problem
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
        .collect();
    let field = nodal_field(mesh, &system, &solution, &scales);
    Ok(CondensedSolution {
        field,
        friction,
        states,
        solves,
        converged,
    })
}
