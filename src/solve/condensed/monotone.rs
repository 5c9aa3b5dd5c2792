//! The monotone search for the friction pattern: from its point, a step towards the optimum of
//! the present pattern (the full step, or the exact line search of `line_search` on J of (38)
//! where a DOF reverses), then the next pattern. J never rises, so it can neither cycle nor
//! stall — except where rounding decides the slope (at ties) and no step gives descent: it
//! then takes the optimum as it is, and never the same such jump twice (stop 45). At an
//! optimum it frees at most twice as many DOFs as the last freeing that gave descent, then
//! fewer (design notes: `docs/numerics.md`, stops 42 and 45).

use std::collections::HashSet;

use super::line_search::SearchPoint;
use super::newton_phases::fingerprint;
use super::system::{Pattern, PatternSolution, ShootingSystem};

/// The state of the monotone search.
#[derive(Default)]
pub(super) struct MonotoneSearch {
    /// The iterate (u, u' at every interior special point), which only ever lowers J.
    pub(super) current: Option<SearchPoint>,
    /// After freeing several DOFs at an optimum, the patterns to solve instead while the step
    /// towards the present one gives no descent, the next on top: the half of them whose force
    /// exceeds its threshold most, then a quarter, …, then the worst one alone (which always
    /// descends). Measured on ties with one threshold lowered (`cargo bench --bench
    /// many_obstacles -- lowered`, k = 1000): the worst one alone took 2725 pattern solves,
    /// halving 1371.
    fallback: Vec<Vec<Pattern>>,
    /// DOFs the pattern being solved frees at once (0: none); each fallback frees half as
    /// many as the one before it.
    freeing: usize,
    /// DOFs the last freeing that gave descent freed: the next one frees at most twice as
    /// many first, then halves as before. Freeing all at once first, the last swivel threshold
    /// two notches down at k = 2000 (ties, `-- lowered`) tried all, half, a quarter, … before
    /// the one or two that descend: 1814 failed tries in 3645 solves; now 2195 solves.
    last_freed: Option<usize>,
    /// The solve it started at.
    pub(super) started_at: usize,
    /// Fingerprints of the patterns reached by taking an optimum without descent as it is
    /// (rounding decides the slope there): such a jump is never taken twice.
    jumped: HashSet<u64>,
    /// Fingerprints of the states (pattern solved, point, jumps taken, last freeing) from which
    /// such a jump was refused and DOFs freed instead.
    freed_from: HashSet<u64>,
    /// The search would repeat itself from here on: rounding decides every step left (a
    /// scene at ties whose decisions hang on slopes below what f64 resolves).
    pub(super) stalled: bool,
}

/// A fingerprint of a point's motions, bit for bit.
fn point_fingerprint(point: &SearchPoint) -> u64 {
    point
        .motion
        .iter()
        .fold(0x8422_2325_cbf2_9ce4u64, |hash, motion| {
            (hash ^ motion.to_bits()).wrapping_mul(0x0000_0100_0000_01b3)
        })
}

impl MonotoneSearch {
    /// A step towards the optimum of `pattern` solved in `solution` (the full step, or the
    /// exact line search where a DOF reverses), then the next pattern in `pattern` — at the
    /// optimum the stuck DOFs whose force exceeds the threshold are freed (at most twice as
    /// many as last time, fewer if that gives no descent, down to the worst one), else the
    /// signs of the new point.
    pub(super) fn step(
        &mut self,
        system: &ShootingSystem,
        pattern: &mut Vec<Pattern>,
        solution: &PatternSolution,
        changes: &[(usize, Pattern)],
    ) {
        let candidate = system.search_point(solution);
        // Every moving DOF keeps its sign (to within what the solve resolves): the candidate
        // minimises the pattern's quadratic, which equals J there and at the current point
        // (whose moving DOFs have these signs or are zero, and stuck ones are zero), so it is
        // a descent step as it is. The line search is for reversals only; on a step of
        // rounding size it would decide by noise and could stall.
        let keeps_signs = changes.iter().all(|&(i, _)| pattern[i] == Pattern::Stuck);
        let (c, full_step) = match self.current.take() {
            None => (candidate, true),
            Some(_) if keeps_signs => (candidate, true),
            Some(c) => {
                let (point, full) = system.line_search(&c, &candidate);
                if !full && point == c {
                    // No descent towards the optimum of the changed pattern.
                    match self.fallback.pop() {
                        // Several DOFs changed at once: change fewer.
                        Some(fewer) if fewer != *pattern => {
                            *pattern = fewer;
                            self.freeing /= 2;
                            self.current = Some(c);
                            return;
                        }
                        // Rounding decides the slope here: take the optimum as it is
                        // (J may rise), but not twice to the same pattern.
                        _ => {
                            if self.jump_is_new(system, &candidate, changes, pattern) {
                                (candidate, true)
                            } else {
                                self.free_instead_of_jumping(
                                    system, pattern, solution, changes, &c,
                                );
                                self.current = Some(c);
                                return;
                            }
                        }
                    }
                } else {
                    (point, full)
                }
            }
        };
        self.fallback.clear();
        if self.freeing > 0 {
            self.last_freed = Some(self.freeing);
            self.freeing = 0;
        }
        // At the optimum of the pattern (full step, every moving DOF with its sign): free the
        // stuck DOFs whose force exceeds the threshold (semismooth Newton / primal–dual active
        // set). Otherwise (the step stopped where a DOF reached zero): take the signs of the
        // new point, with its zeros stuck, and find that pattern's optimum first.
        let at_optimum = full_step && keeps_signs;
        if at_optimum {
            self.free_the_most_excessive(system, pattern, solution, changes);
        } else {
            *pattern = system.signs_of(&c);
        }
        self.current = Some(c);
    }

    /// Where no step towards the optimum of `pattern` (solved, with `changes`) gives descent
    /// and no fallback is left, the search takes that optimum as it is: is that jump new (a
    /// pattern no jump reached before), or is there no stuck DOF over its threshold to free
    /// instead? Two such jumps that led to each other cycled to the limit of solves (clusters
    /// at ties, k = 4000: 32 385 solves, 102 s, not converged).
    fn jump_is_new(
        &mut self,
        system: &ShootingSystem,
        candidate: &SearchPoint,
        changes: &[(usize, Pattern)],
        pattern: &[Pattern],
    ) -> bool {
        self.jumped.insert(fingerprint(&system.signs_of(candidate)))
            || changes.iter().all(|&(i, _)| pattern[i] != Pattern::Stuck)
    }

    /// In place of a jump taken before: frees the most excessive stuck DOFs of `changes` from
    /// the point `c` (the fallbacks halve them down to the worst one alone, which descends
    /// unless rounding decides its slope too). Freeing from the same state again would repeat
    /// every step since (the search is deterministic): the search has then stalled.
    fn free_instead_of_jumping(
        &mut self,
        system: &ShootingSystem,
        pattern: &mut Vec<Pattern>,
        solution: &PatternSolution,
        changes: &[(usize, Pattern)],
        c: &SearchPoint,
    ) {
        let frees: Vec<(usize, Pattern)> = changes
            .iter()
            .copied()
            .filter(|&(i, _)| pattern[i] == Pattern::Stuck)
            .collect();
        // Everything the next steps depend on: the pattern solved (so its solution, the frees
        // and their fallbacks), the point, the jumps taken and the last freeing.
        let state = fingerprint(pattern)
            ^ point_fingerprint(c)
            ^ (self.jumped.len() as u64).rotate_left(17)
            ^ (self.last_freed.unwrap_or(0) as u64).rotate_left(41);
        *pattern = system.signs_of(c);
        self.free_the_most_excessive(system, pattern, solution, &frees);
        self.stalled |= !self.freed_from.insert(state);
    }

    /// At an optimum: frees the stuck DOFs of `changes` whose force exceeds the threshold
    /// most (all of them, or at most twice as many as the last freeing that descended), with
    /// half, a quarter, … of them as the fallbacks.
    fn free_the_most_excessive(
        &mut self,
        system: &ShootingSystem,
        pattern: &mut [Pattern],
        solution: &PatternSolution,
        changes: &[(usize, Pattern)],
    ) {
        let base = pattern.to_vec();
        let mut by_excess: Vec<(f64, usize, Pattern)> = changes
            .iter()
            .map(|&(i, wanted)| {
                let l = solution.lambda[i].abs();
                ((l - system.thresholds[i / 2][i % 2]) / l, i, wanted)
            })
            .collect();
        by_excess.sort_by(|a, b| b.0.total_cmp(&a.0));
        let mut count = match self.last_freed {
            Some(last) => by_excess.len().min(2 * last),
            None => by_excess.len(),
        };
        for &(_, i, wanted) in &by_excess[..count] {
            pattern[i] = wanted;
        }
        self.freeing = count;
        while count > 1 {
            count /= 2;
            let mut fewer = base.clone();
            for &(_, i, wanted) in &by_excess[..count] {
                fewer[i] = wanted;
            }
            self.fallback.insert(0, fewer);
        }
    }
}
