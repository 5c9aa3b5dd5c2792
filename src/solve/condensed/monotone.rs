//! The monotone search for the friction pattern: from its point, a step towards the optimum of
//! the present pattern (the full step, or the exact line search of `line_search` on J of (38)
//! where a DOF reverses), then the next pattern. J never rises, so it can neither cycle nor
//! stall. At an optimum it frees at most twice as many DOFs as the last freeing that gave
//! descent, then fewer (design notes: `docs/numerics.md`, stop 42).

use super::line_search::SearchPoint;
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
                        // Rounding decides the slope here: take the optimum as it is.
                        _ => (candidate, true),
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
