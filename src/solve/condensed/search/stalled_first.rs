//! Where the search starts from the interior-point guess (issue 26). Where the iteration's
//! first run stalled and a second, with near ties widened, made the guess
//! (`interior::Guess::stalled_first`), the search starts from whichever of the two guesses
//! leaves fewer DOFs inconsistent when solved. The widening settles the partial ties it was
//! made for (stop 53: the first guess's solve left 2514–5703 DOFs inconsistent, the
//! second's 0–4), but on tight clusters at ties (`check::families::tight_clusters_ties_scene`)
//! it moved the guess away: at k = 2000, seeds 123 and 186, the first guess's solve leaves 19
//! and 400 DOFs inconsistent, the second's 475 and 693, and the search took 582 and 875
//! pattern solves from the second where it takes 9 and 8 from the first (docs/numerics.md,
//! "Two guesses where the first stalled").

use super::PatternSearch;
use crate::solve::condensed::CondensedFailure;
use crate::solve::condensed::interior::Guess;
use crate::solve::condensed::system::{Accuracy, Pattern, PatternSolution};

impl PatternSearch<'_> {
    /// Starts the search from `guess` or, where it was made after a stalled iteration, from
    /// whichever of the two guesses leaves fewer DOFs inconsistent (the second on a tie, and
    /// without solving the first where the second leaves none). The search is handed the
    /// solve of the chosen guess where the banded system still holds its factors, and solves
    /// it again otherwise. These solves are the search's, and `observe` sees them;
    /// [`CondensedFailure::Stopped`] where `keep_going`, asked before each, says no.
    pub(super) fn start_from_guess(
        &mut self,
        mut guess: Guess,
        keep_going: &mut dyn FnMut() -> bool,
        observe: &mut dyn FnMut(&PatternSolution, &[Pattern]),
    ) -> Result<(), CondensedFailure> {
        if let Some(first) = guess.stalled_first.take() {
            let (solution, second_left) =
                self.solve_and_count(&guess.pattern, keep_going, observe)?;
            if second_left == 0 {
                self.handed = solution;
            } else {
                let (solution, first_left) =
                    self.solve_and_count(&first.pattern, keep_going, observe)?;
                if first_left < second_left {
                    guess = *first;
                    self.handed = solution;
                }
            }
        }
        self.pattern = guess.pattern.clone();
        self.newton.start = Some(guess.pattern);
        self.unclear_held = guess.unclear_held;
        self.monotone_from_guess = true;
        Ok(())
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
        self.solves += 1;
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
