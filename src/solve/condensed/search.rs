//! The search for the friction pattern: semismooth Newton phases, then a monotone search (exact
//! line search on the convex objective, feature-sign fallback) that can neither cycle nor
//! stall.

use std::collections::HashSet;

use super::nodes::nodal_field;
use super::scaling::Scales;
use super::system::{Accuracy, BAND_LOWER, BAND_UPPER, Condensed, Pattern, PatternSolution};
use super::{CondensedFailure, CondensedSolution};
use crate::fem::Mesh;
use crate::linalg::banded_lu::{BandedSystem, times_power_of_two};
use crate::model::Problem;
use crate::solve::solution::FrictionState;

/// A point of the monotone search on the friction DOFs: the motions c and the forces
/// r = b − K c there (K c = b − Bᵀλ, so r is λ at an optimum of a pattern). Both are linear in
/// the point, so a point between two solves carries the same combination of their forces:
/// no stiffness (1e27 for a piece 1e-9·l long) is ever multiplied by a displacement.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct SearchPoint {
    pub(super) motion: Vec<f64>,
    pub(super) force: Vec<f64>,
}

impl Condensed {
    /// The friction DOFs' motions and forces of a solve.
    pub(super) fn search_point(&self, solution: &PatternSolution) -> SearchPoint {
        SearchPoint {
            motion: (0..solution.lambda.len())
                .map(|i| self.friction_value(solution, i))
                .collect(),
            force: solution.lambda.clone(),
        }
    }

    /// Exact minimisation of J(c + t d), d = target − c, over t ∈ [0, 1]: J is convex and
    /// piecewise quadratic along the segment, with kinks where a friction DOF crosses zero.
    /// The slope of its smooth part is −rᵀd and its curvature dᵀK d = dᵀ(r(c) − r(target)).
    /// Returns the new point (DOFs that stop at their kink set to exactly zero) and whether
    /// it is the target itself.
    pub(super) fn line_search(
        &self,
        current: &SearchPoint,
        target: &SearchPoint,
    ) -> (SearchPoint, bool) {
        let (c, r) = (&current.motion, &current.force);
        let d: Vec<f64> = target.motion.iter().zip(c).map(|(t, c)| t - c).collect();
        let q: f64 = d
            .iter()
            .zip(r.iter().zip(&target.force))
            .map(|(d, (a, b))| d * (a - b))
            .sum();
        let sign = |v: f64| {
            if v > 0.0 {
                1.0
            } else if v < 0.0 {
                -1.0
            } else {
                0.0
            }
        };
        // Slope of J at t = 0⁺ and the kinks ahead.
        let mut slope = 0.0;
        let mut kinks = Vec::new();
        for (i, (&ci, &di)) in c.iter().zip(&d).enumerate() {
            let g = self.thresholds[i / 2][i % 2];
            if di == 0.0 {
                continue;
            }
            if g == 0.0 {
                slope -= r[i] * di;
                continue;
            }
            let direction = if ci != 0.0 { sign(ci) } else { sign(di) };
            // One term per DOF, (g·sign − r)·d: exactly zero for a DOF that moves on at its
            // threshold, so a large moving DOF cannot round away the slope of the others.
            slope += (g * direction - r[i]) * di;
            if ci != 0.0 && sign(ci) != sign(di) {
                let t = -ci / di;
                if t < 1.0 {
                    kinks.push((t, i, 2.0 * g * di.abs()));
                }
            }
        }
        kinks.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut at = 0.0;
        let mut stop = None;
        if slope >= 0.0 {
            stop = Some((0.0, None));
        } else {
            for &(t, i, jump) in &kinks {
                // J'(s) = slope + q (s − at) on [at, t].
                if q > 0.0 && slope + q * (t - at) >= 0.0 {
                    stop = Some((at - slope / q, None));
                    break;
                }
                // The jump first: past a DOF's own kink it often cancels the slope.
                slope = (slope + jump) + q * (t - at);
                at = t;
                if slope >= 0.0 {
                    stop = Some((t, Some(i)));
                    break;
                }
            }
            if stop.is_none() && q > 0.0 && slope + q * (1.0 - at) >= 0.0 {
                stop = Some((at - slope / q, None));
            }
        }
        match stop {
            None => (target.clone(), true),
            Some((t, kink)) => {
                let t = t.clamp(0.0, 1.0);
                let between = |a: &[f64], b: &[f64]| -> Vec<f64> {
                    a.iter().zip(b).map(|(a, b)| a + t * (b - a)).collect()
                };
                let mut next = SearchPoint {
                    motion: between(c, &target.motion),
                    force: between(r, &target.force),
                };
                if let Some(i) = kink {
                    next.motion[i] = 0.0;
                }
                // Every DOF whose kink lies at or before t has crossed or stopped at zero.
                for &(tk, i, _) in &kinks {
                    if tk == t {
                        next.motion[i] = 0.0;
                    }
                }
                (next, false)
            }
        }
    }

    /// The pattern of a point: moving DOFs with their sign, zeros stuck.
    pub(super) fn signs_of(&self, point: &SearchPoint) -> Vec<Pattern> {
        point
            .motion
            .iter()
            .map(|&v| {
                if v > 0.0 {
                    Pattern::Positive
                } else if v < 0.0 {
                    Pattern::Negative
                } else {
                    Pattern::Stuck
                }
            })
            .collect()
    }

    /// σ of the semismooth Newton prediction λ + σc for a DOF that reverses: a fraction of
    /// its diagonal stiffness (12EJ/L³ per adjacent piece for a deflection, 4EJ/L for a slope).
    /// With σ = 0 a reversing DOF is first held stuck.
    pub(super) fn reversal_stiffness(&self, i: usize) -> f64 {
        let p = self.point_of_obstacle[i / 2];
        let diagonal: f64 = [p - 1, p]
            .iter()
            .map(|&q| {
                let piece = &self.pieces[q];
                if i.is_multiple_of(2) {
                    12.0 * piece.stiffness / piece.length.powi(3)
                } else {
                    4.0 * piece.stiffness / piece.length
                }
            })
            .sum();
        self.reversal_fraction.get() * diagonal
    }

    pub(super) fn state(
        &self,
        solution: &PatternSolution,
        pattern: &[Pattern],
        i: usize,
    ) -> FrictionState {
        let (motion_noise, force_noise) = self.resolution(solution, i);
        match pattern[i] {
            Pattern::Stuck if self.force_excess(solution, i) < -force_noise => FrictionState::Stuck,
            Pattern::Stuck => FrictionState::AtThreshold,
            _ if self.friction_value(solution, i).abs() > motion_noise => FrictionState::Moves,
            _ => FrictionState::AtThreshold,
        }
    }
}

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
    let condensed = Condensed::new(problem, mesh, &scales, first_fraction);
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
    let mut system = BandedSystem::new(0, BAND_LOWER, BAND_UPPER);
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
                let wanted = condensed.wanted(solution, pattern, i);
                (wanted != pattern[i]).then_some((i, wanted))
            })
            .collect()
    };
    let (solution, converged) = loop {
        if !keep_going() {
            return Err(CondensedFailure::Stopped);
        }
        let mut solution = condensed.solve_pattern(&pattern, Accuracy::Plain, &mut system)?;
        solves += 1;
        let mut changes = changes_of(&solution, &pattern);
        // Newton steps take the decisions that elimination alone settles first, the others
        // on refined values once nothing else is left to change; the monotone search (which
        // must not be misled by a wrong sign) decides on refined values whenever any
        // decision is uncertain.
        let uncertain = condensed.uncertain(&solution, &pattern);
        if newton_phase {
            changes.retain(|&(i, _)| !uncertain[i]);
        } else if uncertain.iter().any(|&u| u) {
            changes.clear();
        }
        if changes.is_empty() {
            solution = condensed.solve_pattern(&pattern, Accuracy::RefineLast, &mut system)?;
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
                    Some(&fraction) => condensed.reversal_fraction.set(fraction),
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
        let candidate = condensed.search_point(&solution);
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
                let (next, full) = condensed.line_search(&c, &candidate);
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
                let excess = (l - condensed.thresholds[i / 2][i % 2]) / l;
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
            pattern = condensed.signs_of(&c);
        }
        current = Some(c);
    };

    let states: Vec<[FrictionState; 2]> = (0..problem.obstacles.len())
        .map(|j| {
            [
                condensed.state(&solution, &pattern, 2 * j),
                condensed.state(&solution, &pattern, 2 * j + 1),
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
    let field = nodal_field(mesh, &condensed, &solution, &scales);
    Ok(CondensedSolution {
        field,
        friction,
        states,
        solves,
        converged,
    })
}
