//! Where the search starts from the interior-point guess (issue 26). Where the iteration's
//! first run stalled and a second, with near ties widened, made the guess
//! (`interior::Guess::stalled_first`), the stalled run's own guess gets a short search first
//! where its solve leaves fewer DOFs inconsistent than the second guess's. The widening
//! settles the partial ties it was made for (stop 53: the first guess's solve left 2514–5703
//! DOFs inconsistent, the second's 0–4), but on tight clusters at ties
//! (`check::families::tight_clusters_ties_scene`) it moved the guess away: at k = 2000, seeds
//! 123 and 186, the first guess's solve leaves 19 and 400 DOFs inconsistent, the second's 475
//! and 693, and the search took 582 and 875 pattern solves from the second where it takes 9
//! and 8 from the first. Which guess's search is shorter is not always the one with fewer
//! DOFs inconsistent, so the search from the first is cut short ([`FIRST_GUESS_SOLVES`]) and
//! the search from the second then goes on as without it (docs/many-obstacles/step-costs.md, "Two
//! guesses where the first stalled").

use super::{PatternSearch, Settled};
use crate::solve::condensed::CondensedFailure;
use crate::solve::condensed::interior::Guess;
use crate::solve::condensed::system::{Accuracy, Pattern, PatternSolution};

/// Most pattern solves of the search from the stalled iteration's guess, where that guess
/// leaves fewer DOFs inconsistent than the second's; where it does not settle within them,
/// the search starts from the second guess as it would have without the first. Measured on
/// tight clusters at ties (docs/many-obstacles/step-costs.md): where the search from the first
/// guess settles, the whole solve takes 8–14 pattern solves (one 82, with 128 allowed); where it
/// does not, each allowed solve is one more.
const FIRST_GUESS_SOLVES: usize = 32;

impl PatternSearch<'_> {
    /// Starts the search from `guess`. Where it was made after a stalled iteration, its
    /// solve is tried first: where that leaves no DOF inconsistent, the search is handed it.
    /// Otherwise the stalled iteration's own guess is solved too, and where it leaves fewer
    /// DOFs inconsistent, a search from it (at most [`FIRST_GUESS_SOLVES`] solves) goes
    /// first: its consistent solution and pattern if it settles. Those solves are counted
    /// apart (`side_solves`), so that the search from `guess` is the same after them as
    /// without them; `observe` sees them, and [`CondensedFailure::Stopped`] comes back where
    /// `keep_going`, asked before each, says no.
    pub(super) fn start_from_guess(
        &mut self,
        mut guess: Guess,
        keep_going: &mut dyn FnMut() -> bool,
        observe: &mut dyn FnMut(&PatternSolution, &[Pattern]),
    ) -> Result<Settled, CondensedFailure> {
        let mut settled = None;
        if let Some(first) = guess.stalled_first.take() {
            let (solution, second_left) =
                self.solve_and_count(&guess.pattern, keep_going, observe)?;
            if second_left == 0 {
                // The search's own first solve, made already.
                (self.side_solves, self.solves) = (self.side_solves - 1, self.solves + 1);
                self.handed = solution;
            } else {
                let (solution, first_left) =
                    self.solve_and_count(&first.pattern, keep_going, observe)?;
                if first_left < second_left {
                    settled = self.search_from_first(*first, solution, keep_going, observe)?;
                }
            }
        }
        self.pattern = guess.pattern.clone();
        self.newton.start = Some(guess.pattern);
        self.unclear_held = guess.unclear_held;
        self.monotone_from_guess = true;
        Ok(settled)
    }

    /// A search like this one from the stalled iteration's guess `first`, handed `solution`
    /// (its solve, whose factors the banded system holds), for at most
    /// [`FIRST_GUESS_SOLVES`] solves: the consistent solution and its pattern if it settles.
    fn search_from_first(
        &mut self,
        first: Guess,
        solution: Option<PatternSolution>,
        keep_going: &mut dyn FnMut() -> bool,
        observe: &mut dyn FnMut(&PatternSolution, &[Pattern]),
    ) -> Result<Settled, CondensedFailure> {
        let fractions = self.newton.fractions;
        let mut attempt = self.attempt_from_guess(first.pattern, fractions, FIRST_GUESS_SOLVES);
        attempt.handed = solution;
        attempt.unclear_held = first.unclear_held;
        attempt.monotone_from_guess = true;
        self.settle_on_the_side(attempt, keep_going, observe)
    }

    /// One plain solve of `pattern` in the search's banded system, if `keep_going` says yes:
    /// the solution and how many DOFs it leaves inconsistent (`None` and `usize::MAX` where
    /// the pattern is singular).
    fn solve_and_count(
        &mut self,
        pattern: &[Pattern],
        keep_going: &mut dyn FnMut() -> bool,
        observe: &mut dyn FnMut(&PatternSolution, &[Pattern]),
    ) -> Result<(Option<PatternSolution>, usize), CondensedFailure> {
        if !keep_going() {
            return Err(CondensedFailure::Stopped);
        }
        self.side_solves += 1;
        let system = self.system;
        let Ok(solution) = system.solve_pattern(pattern, Accuracy::Plain, &mut self.banded) else {
            return Ok((None, usize::MAX));
        };
        observe(&solution, pattern);
        let left = self.inconsistent_as_decided(&solution, pattern);
        Ok((Some(solution), left))
    }

    /// The DOFs `solution` (a plain solve of `pattern`, whose factors the banded system
    /// holds) leaves inconsistent as the search's first Newton step decides: those elimination
    /// alone settles, or, where there are none, those of the solve refined as far as its
    /// decisions need.
    fn inconsistent_as_decided(
        &mut self,
        solution: &PatternSolution,
        pattern: &[Pattern],
    ) -> usize {
        let system = self.system;
        let uncertain = system.uncertain(solution, pattern);
        let changes = system.inconsistent_dofs(solution, pattern);
        let certain = changes.iter().filter(|&&(i, _)| !uncertain[i]).count();
        if certain > 0 || changes.is_empty() {
            return certain;
        }
        match system.solve_pattern(pattern, Accuracy::RefineForDecisions, &mut self.banded) {
            Ok(refined) => system.inconsistent_dofs(&refined, pattern).len(),
            Err(_) => usize::MAX,
        }
    }
}
