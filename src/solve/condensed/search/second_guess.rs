//! The interior-point guess and the search from it, and a second guess where that search runs
//! long (issue 26, stop 61): the iteration again with every step's solve refined with the
//! exact relations (`mixed_refinement`), and the search anew from its guess.
//!
//! On tight clusters at ties (`check::families::tight_clusters_ties_scene`, k = 2000, seeds
//! 1–300) the search from the f64 iteration's guess took 397–748 pattern solves on five
//! seeds; there the iteration had stalled at its cap of 80 steps (four of them) or ended
//! there. With refined steps it reaches its μ in 61–66 steps and the search settles in 7–10
//! (docs/many-obstacles/refined-steps.md). Every refined step costs a residual in
//! double-double and a back substitution more, so it is kept for searches that have run
//! [`SECOND_GUESS_AFTER`] solves: a search that settles sooner is the same, solve for solve.

use super::{PatternSearch, Settled};
use crate::linalg::banded_lu::BandedSystem;
use crate::linalg::double_double::DoubleDouble;
use crate::solve::condensed::CondensedFailure;
use crate::solve::condensed::system::{Pattern, PatternSolution};

/// Pattern solves of the search from the first guess after which the second guess is made.
/// On the 300 seeds above the searches that settled took at most 61 solves; the slow ones
/// took 397 and more.
pub(in crate::solve::condensed) const SECOND_GUESS_AFTER: usize = 64;

/// Pattern solves of the search from the second guess before the first search goes on
/// where it stopped instead. On tight clusters at ties (k = 2000 seeds 1–300, k = 3000 seeds
/// 1–100) 16, 32 or 64 gave the same counts (the eight searches it shortens settle within
/// 16); where it does not settle (k = 2000 seed 42 with obstacle 666's swivel threshold three
/// notches down: 650 solves without the second guess), 706, 722 and 754 solves. Left to run,
/// the search from the second guess took 14 820 solves where the first took 6499 (clusters
/// of 50 obstacles 1e-9·l apart at ties, k = 4000, stop 61; since stop 62's end of the
/// iteration, `centrality`, that scene settles in 5).
pub(in crate::solve::condensed) const SECOND_GUESS_SOLVES: usize = 16;

impl<'a> PatternSearch<'a> {
    /// The interior-point guess from the held forces `held` (its offers checked on the side,
    /// counted in `side_solves`), then the start of the search from it: the consistent
    /// solution and its pattern where an offer or the start settled it.
    pub(in crate::solve::condensed) fn guess_and_start(
        &mut self,
        held: Vec<DoubleDouble>,
        keep_going: &mut dyn FnMut() -> bool,
        observe: &mut dyn FnMut(&PatternSolution, &[Pattern]),
    ) -> Result<Settled, CondensedFailure> {
        let system = self.system;
        let mut crossed = None;
        let mut crossover_solves = 0;
        let guess =
            {
                // A pattern the iteration settles on is tried at once (one solve); if it is
                // consistent, that is the answer.
                let mut crossover =
                    |candidate: &[Pattern],
                     banded: &mut BandedSystem,
                     keep_going: &mut dyn FnMut() -> bool| {
                        let (settled, solves) = PatternSearch::offered(system, candidate)
                            .settle_in(banded, keep_going, &mut *observe)?;
                        crossover_solves += solves;
                        if settled.is_some() {
                            crossed = settled;
                        }
                        Ok(crossed.is_some())
                    };
                system.interior_point_pattern(&held, &mut self.banded, keep_going, &mut crossover)
            };
        self.side_solves += crossover_solves;
        self.newton.held = Some(held);
        if let Some(guess) = guess?.filter(|_| crossed.is_none()) {
            self.guess = Some(guess.clone());
            crossed = self.start_from_guess(guess, keep_going, observe)?;
        }
        Ok(crossed)
    }

    /// This search, from the first guess, stopped after [`SECOND_GUESS_AFTER`] solves with
    /// `last` inconsistent: the search from the second guess, where that guess is another
    /// pattern, for at most [`SECOND_GUESS_SOLVES`] solves; where it does not settle, this
    /// search goes on where it stopped, up to `limit` solves. The search that ended, its last
    /// solution and whether that is consistent.
    pub(in crate::solve::condensed) fn with_second_guess(
        mut self,
        last: PatternSolution,
        limit: usize,
        keep_going: &mut dyn FnMut() -> bool,
        observe: &mut dyn FnMut(&PatternSolution, &[Pattern]),
    ) -> Result<(PatternSearch<'a>, PatternSolution, bool), CondensedFailure> {
        let (mut second, settled, fraction) = self.second_guess(keep_going, observe)?;
        if let Some((solution, pattern)) = settled {
            second.pattern = pattern;
            return Ok((second, solution, true));
        }
        if second.guess.is_some() && second.guess != self.guess {
            second.limit = second.limit.min(second.solves + SECOND_GUESS_SOLVES);
            let result = second.run(keep_going, observe);
            if let Ok((solution, true)) = result {
                return Ok((second, solution, true));
            }
            result.inspect_err(|_| second.banded.keep())?;
        }
        // The same guess, or its search did not settle soon: this one goes on.
        self.go_on_after(second, last, (limit, fraction));
        let result = self.run(keep_going, observe);
        let (solution, converged) = result.inspect_err(|_| self.banded.keep())?;
        Ok((self, solution, converged))
    }

    /// A new search from the iteration with refined steps, handed this one's banded system and
    /// counting this one's solves as made on the side. Its outcome: settled at the start,
    /// or the search to run; and this search's σ fraction, for [`PatternSearch::go_on_after`].
    fn second_guess(
        &mut self,
        keep_going: &mut dyn FnMut() -> bool,
        observe: &mut dyn FnMut(&PatternSolution, &[Pattern]),
    ) -> Result<(PatternSearch<'a>, Settled, f64), CondensedFailure> {
        let held = self.newton.held.clone().unwrap_or_default();
        let mut second = PatternSearch::new(self.system, held.len() / 2, self.newton.fractions);
        second.banded = std::mem::replace(&mut self.banded, BandedSystem::empty());
        second.side_solves = self.solves_in_all();
        let system = self.system;
        let fraction = system.reversal_fraction.get();
        system.reversal_fraction.set(self.newton.fractions[0]);
        system.refined_steps.set(true);
        let settled = second.guess_and_start(held, keep_going, observe);
        system.refined_steps.set(false);
        let settled = settled?;
        Ok((second, settled, fraction))
    }

    /// The first search goes on where it stopped (its last solve `last` handed back, its
    /// limit `limit` and its σ fraction `fraction` again) after the search from the second
    /// guess, `second`, did not settle: it takes the banded system back, and that search's
    /// solves count as made on the side.
    fn go_on_after(
        &mut self,
        second: PatternSearch<'a>,
        last: PatternSolution,
        (limit, fraction): (usize, f64),
    ) {
        self.system.reversal_fraction.set(fraction);
        self.side_solves += second.solves_in_all() - self.solves_in_all();
        self.banded = second.banded;
        self.limit = limit;
        self.handed = Some(last);
    }
}
