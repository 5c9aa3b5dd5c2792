//! The monotone search for the friction pattern: from its point, a step towards the optimum of
//! the present pattern (the full step, or the exact line search of `line_search` on J of (38)
//! where a DOF reverses), then the next pattern. J never rises, so it can neither cycle nor
//! stall. At an optimum it frees at most twice as many DOFs as the last freeing that gave
//! descent, then fewer, those whose refined force exceeds the threshold most first. Where a
//! step stops short of the optimum, the next pattern holds every DOF that optimum reversed,
//! not only the one that reached zero (design notes: `docs/many-obstacles/monotone-search.md`,
//! stops 42 and 46).

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
    /// Where the pattern being solved came from, after a step that stopped short.
    after_short: AfterShortStep,
}

/// The pattern being solved, after a step that stopped short of its pattern's optimum.
#[derive(Debug, Default, Clone, Copy, PartialEq)]
enum AfterShortStep {
    /// The point's own signs, or a freeing at an optimum.
    #[default]
    Plain,
    /// The point's signs with the DOFs that optimum reversed held
    /// ([`MonotoneSearch::hold_the_reversed`]): they still move at the current point, so the
    /// step is a line search even when the optimum keeps every sign, and without descent the
    /// fallback is the point's own signs.
    Held,
    /// The point's own signs after a step from a held pattern that stopped short too (the
    /// held DOFs' forces push them on): holding nothing more until this one's step.
    SignsAfterHeld,
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
        let after_short = std::mem::take(&mut self.after_short);
        let off_face = after_short == AfterShortStep::Held;
        let (c, full_step) = match self.current.take() {
            None => (candidate, true),
            Some(_) if keeps_signs && !off_face => (candidate, true),
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
        // set). Otherwise (the step stopped short): take the signs of the new point, with its
        // zeros stuck and every DOF the optimum reversed held as well, and find that
        // pattern's optimum first; after a step from off the face, or the one after it, the
        // signs alone.
        let at_optimum = full_step && keeps_signs;
        if at_optimum {
            self.free_the_most_excessive(system, pattern, solution, changes);
        } else if after_short != AfterShortStep::Plain {
            if off_face && !full_step {
                self.after_short = AfterShortStep::SignsAfterHeld;
            }
            *pattern = system.signs_of(&c);
        } else {
            self.hold_the_reversed(system, pattern, &c, solution);
        }
        self.current = Some(c);
    }

    /// After a step that stopped short of the optimum solved in `solution`: the next pattern
    /// is the signs of the point `c` reached, with every DOF that still moves there but not
    /// in that direction at the optimum held too, so that it goes to zero along the next
    /// step. The line search stops at the first kink where a DOF's jump 2g|d| outweighs the
    /// rest of the slope, and at ties (every force its threshold to a few ulps) that slope is
    /// tiny, so with the signs alone each solve settled one DOF: clusters at ties with a
    /// swivel threshold lowered took 2067 solves at k = 4000 and 4966 at k = 3000; holding
    /// the reversed, 376 and 2021, and ranking the DOFs freed by their refined excess as well
    /// 348 and 2478 (`docs/many-obstacles/monotone-search.md`, "What the optimum reversed, held").
    fn hold_the_reversed(
        &mut self,
        system: &ShootingSystem,
        pattern: &mut Vec<Pattern>,
        c: &SearchPoint,
        solution: &PatternSolution,
    ) {
        let signs = system.signs_of(c);
        let mut held = signs.clone();
        let mut holds = false;
        for (i, &now) in c.motion.iter().enumerate() {
            let then = system.friction_value(solution, i);
            if now != 0.0 && (then == 0.0 || (now > 0.0) != (then > 0.0)) {
                held[i] = Pattern::Stuck;
                holds = true;
            }
        }
        if holds {
            // Without descent towards the held pattern's optimum: the point's own signs.
            self.fallback.push(signs);
            self.after_short = AfterShortStep::Held;
        }
        *pattern = held;
    }

    /// At an optimum: frees the stuck DOFs of `changes` whose force exceeds the threshold
    /// most (all of them, or at most twice as many as the last freeing that descended), with
    /// half, a quarter, … of them as the fallbacks. The excess is the refined force's
    /// (`ShootingSystem::force_excess`): at ties every force is its threshold to a few ulps,
    /// so the f64 force's excess is rounding, and ranked by it the DOFs were freed in a random
    /// order. With the last obstacle's swivel threshold lowered one or ten notches on equally
    /// spaced ties at k = 4096, a freeing of 2m DOFs then gave no descent again and again (396
    /// of 1082 solves); ranked by the refined excess, 543 and 598 solves instead of 1082 and
    /// 1079, the answers the same bits (`docs/many-obstacles/monotone-search.md`, "What the optimum
    /// reversed, held").
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
                (system.force_excess(solution, i) / l, i, wanted)
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
