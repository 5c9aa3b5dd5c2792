//! The interior-point guess with the DOFs it leaves unclear held stuck (`interior::Guess`),
//! tried where the guess's own pattern, solved first, is inconsistent (issue 26): on obstacles
//! 1e-7·l apart and on clusters at ties the guess cannot put every DOF on a side, and the
//! variant settles in a few solves where the search from the guess took hundreds
//! (docs/many-obstacles/close-obstacles-and-near-ties.md, "The guess with its unclear DOFs held,
//! tried first (stop 49)").

use super::{PatternSearch, Settled};
use crate::solve::condensed::CondensedFailure;
use crate::solve::condensed::system::{Pattern, PatternSolution};

/// Most solves of the attempt ([`PatternSearch::try_unclear_held`]). Where it settled, it
/// took 1–15 solves on the scenes measured (clustered and lowered ties, `cargo bench --bench
/// many_obstacles`; dense stretches of near-coincident obstacles, `-- dense`).
const UNCLEAR_HELD_SOLVES: usize = 16;

/// The attempt is made only where the solve of the guess's own pattern changes at least this
/// many DOFs. In stop 49, on the eight scenes measured where it changed one or two, the
/// attempt never saved a solve and cost one to three (ties at k = 3000: 3 → 5 pattern
/// solves; lowered ties at k = 4096: 28 → 30), so it was 3. Since the guess holds motions
/// below what its steps resolve (stop 52), a guess with two DOFs inconsistent can be tens of
/// DOFs from the answer while its variant is a few: with 2 instead of 3, on the 240 scenes
/// of stop 52's sweep, dense k = 3000 seed 3 took 5 pattern solves instead of 50 and lowered
/// ties at k = 4096 (obstacle 1365's swivel, one notch) 4 instead of 13; no scene took more.
/// With 1, ties at k = 3000 took 5 instead of 3.
pub(super) const UNCLEAR_HELD_FROM: usize = 2;

/// The attempt gives up once two solves in a row change more DOFs than this. Traced with the
/// cap alone, the attempts that settled never had two such solves in a row but one (clustered
/// ties k = 1500 seed 7: 79, 59, 33, … settled at 14, where the search from the guess takes
/// 22); those that did not changed hundreds, falling by about a third a solve (e.g. 1438,
/// 3211 on ties at k = 4096 with the last swivel threshold lowered, where the search from
/// the guess settles in 28 solves).
const UNCLEAR_HELD_MOST_CHANGES: usize = 32;

impl PatternSearch<'_> {
    /// The variant `variant` tried from the search's point after the guess's own solve: a
    /// Newton phase from it (then the monotone search if the phase ends), at most
    /// [`UNCLEAR_HELD_SOLVES`] solves in all, giving up once two solves in a row change more
    /// than [`UNCLEAR_HELD_MOST_CHANGES`] DOFs. The consistent solution and its pattern if
    /// it settles. It solves in this search's banded system and its solves are counted apart
    /// (`side_solves`), so the search goes on from the guess as it would have without it;
    /// its solves are observed (and so recorded in a history) like the search's.
    pub(super) fn try_unclear_held(
        &mut self,
        variant: Vec<Pattern>,
        keep_going: &mut dyn FnMut() -> bool,
        observe: &mut dyn FnMut(&PatternSolution, &[Pattern]),
    ) -> Result<Settled, CondensedFailure> {
        let first_phase = &self.newton.fractions[..self.newton.fractions.len().min(1)];
        let mut attempt = self.attempt_from_guess(variant, first_phase, UNCLEAR_HELD_SOLVES);
        attempt.give_up_above = Some(UNCLEAR_HELD_MOST_CHANGES);
        self.settle_on_the_side(attempt, keep_going, observe)
    }

    /// Counts this solve's `changes` against the attempt's [`PatternSearch::give_up_above`]
    /// (nothing without one): true once two solves in a row changed more DOFs than that.
    pub(super) fn wandered_off(&mut self, changes: &[(usize, Pattern)]) -> bool {
        let Some(most) = self.give_up_above else {
            return false;
        };
        self.wide_solves_in_a_row = if changes.len() > most {
            self.wide_solves_in_a_row + 1
        } else {
            0
        };
        self.wide_solves_in_a_row >= 2
    }
}
