//! Attempts from the interior-point guess at the search's first inconsistent solve (issue
//! 26): first its variant with the unclear DOFs held (`unclear_held`), then the monotone search
//! from the guess itself where that solve leaves few DOFs inconsistent. On obstacles nearly on
//! top of each other the guess is a few DOFs from the answer, but the Newton phases from it
//! went astray: each freeing was carried on along its fronts (`fronts`) past the answer,
//! hundreds of DOFs changed at once, and the search then took hundreds of solves where the
//! monotone search from the guess, whose J never rises, settles in about one or two solves
//! per DOF to change (docs/many-obstacles/close-obstacles-and-near-ties.md, "The monotone search
//! from a close guess (stop 52)").

use super::{PatternSearch, Settled, unclear_held::UNCLEAR_HELD_FROM};
use crate::solve::condensed::CondensedFailure;
use crate::solve::condensed::system::{Pattern, PatternSolution};

/// The monotone attempt is made only where the guess's solve leaves at most this many DOFs
/// inconsistent (those a Newton step would change). Measured on the 240 scenes of stop 52's
/// sweep (docs/many-obstacles/close-obstacles-and-near-ties.md): at 32, pairs k = 1000 seed 4 took
/// 152 pattern solves (its guess one DOF off, whose solve left 59 inconsistent), at 64 every pairs
/// scene took at most 18, and at 256 the 96 clusters at ties took 5189 instead of 4329 (the attempt
/// wandering where Newton from the guess settles; before `PROJECTED_ABOVE`); no other scene
/// changed.
const FROM_GUESS_MOST_INCONSISTENT: usize = 64;

/// Most solves of the monotone attempt; where it does not settle, the search goes on from the
/// guess as it would have without it.
const FROM_GUESS_SOLVES: usize = 64;

impl<'a> PatternSearch<'a> {
    /// At the search's first inconsistent solve (`solution` of the guess, leaving
    /// `inconsistent` DOFs to change; nothing at any later solve): the variant with the
    /// unclear DOFs held ([`PatternSearch::try_unclear_held`], where at least
    /// [`UNCLEAR_HELD_FROM`] are inconsistent), then, where at most
    /// [`FROM_GUESS_MOST_INCONSISTENT`] are, the monotone search from the guess for at most
    /// [`FROM_GUESS_SOLVES`] solves, from `solution` itself where the factors are still its
    /// own. The consistent solution and its pattern if one settles. Each attempt solves in
    /// this search's banded system, its solves are counted apart (`side_solves`) and
    /// observed like the search's.
    pub(super) fn try_from_guess(
        &mut self,
        solution: &PatternSolution,
        inconsistent: usize,
        keep_going: &mut dyn FnMut() -> bool,
        observe: &mut dyn FnMut(&PatternSolution, &[Pattern]),
    ) -> Result<Settled, CondensedFailure> {
        let mut factors_are_its_own = true;
        if let Some(variant) = self.unclear_held.take()
            && inconsistent >= UNCLEAR_HELD_FROM
        {
            let settled = self.try_unclear_held(variant, keep_going, observe)?;
            if settled.is_some() {
                return Ok(settled);
            }
            factors_are_its_own = false;
        }
        if !std::mem::take(&mut self.monotone_from_guess)
            || inconsistent > FROM_GUESS_MOST_INCONSISTENT
        {
            return Ok(None);
        }
        let mut attempt = PatternSearch::attempt(self.system, &self.pattern, FROM_GUESS_SOLVES);
        attempt.handed = factors_are_its_own.then(|| solution.clone());
        self.settle_on_the_side(attempt, keep_going, observe)
    }

    /// Runs `attempt` in this search's banded system until it settles or gives up: its
    /// solves counted apart (`side_solves`) and observed, the system's σ fraction (which
    /// every search shares) as this search had it; the consistent solution and its pattern if
    /// it settled.
    pub(super) fn settle_on_the_side(
        &mut self,
        attempt: PatternSearch<'_>,
        keep_going: &mut dyn FnMut() -> bool,
        observe: &mut dyn FnMut(&PatternSolution, &[Pattern]),
    ) -> Result<Settled, CondensedFailure> {
        let fraction = self.system.reversal_fraction.get();
        let (settled, solves) = attempt.settle_in(&mut self.banded, keep_going, observe)?;
        self.system.reversal_fraction.set(fraction);
        self.side_solves += solves;
        Ok(settled)
    }

    /// A search with the Newton phases `fractions` from the interior-point guess `pattern`
    /// (the held forces as this search has them), for at most `limit` solves.
    pub(super) fn attempt_from_guess(
        &self,
        pattern: Vec<Pattern>,
        fractions: &'a [f64],
        limit: usize,
    ) -> PatternSearch<'a> {
        let mut attempt = PatternSearch::new(self.system, pattern.len() / 2, fractions);
        attempt.pattern = pattern.clone();
        attempt.newton.start = Some(pattern);
        attempt.newton.held = self.newton.held.clone();
        attempt.limit = limit;
        attempt
    }
}
