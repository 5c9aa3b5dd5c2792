//! When and what the interior-point guess (`interior`) offers the search: a pattern the
//! iteration has settled on is solved once and, if consistent, ends everything there, as
//! interior-point methods for linear programs cross over to a vertex (issue 26).

use super::CondensedFailure;
use super::system::Pattern;
use crate::linalg::banded_lu::BandedSystem;

/// Most patterns the iteration offers to its caller ([`Crossover`]): an offer that fails
/// costs a pattern solve, so at most this many are lost.
const MOST_CROSSOVERS: usize = 4;

/// Where the iteration has settled on a pattern (the same after two steps in a row, every DOF
/// clearly on its side after the second but at most `interior::MOST_ON_THE_VERGE` on the
/// verge, held, and not the one it started from), it offers it to its caller, which solves it
/// and says whether the search is settled from there (true: the iteration ends). Measured (`cargo bench --bench many_obstacles -- report`): on the
/// clustered family at k = 1000 and 4000 the pattern is final after 4 of 15 steps.
///
/// The offer solves in the iteration's own banded system (given with it), whose factors the
/// iteration's next step makes anew.
pub(in crate::solve::condensed) type Crossover<'c> = dyn FnMut(&[Pattern], &mut BandedSystem, &mut dyn FnMut() -> bool) -> Result<bool, CondensedFailure>
    + 'c;

/// The patterns of the iteration's last steps, and those it has offered ([`Crossover`]).
pub(super) struct Offers {
    /// The pattern it started from.
    pub(super) start: Vec<Pattern>,
    /// The last step's pattern.
    pub(super) previous: Option<Vec<Pattern>>,
    /// The last pattern offered.
    pub(super) offered: Option<Vec<Pattern>>,
    pub(super) count: usize,
}

impl Offers {
    /// After a step whose iterate describes `pattern`: offers it when it is the last step's
    /// too, is not the start's and was not offered just before (at most [`MOST_CROSSOVERS`]
    /// times); whether `crossover` settled the search from it.
    pub(super) fn settled(
        &mut self,
        pattern: Vec<Pattern>,
        banded: &mut BandedSystem,
        keep_going: &mut dyn FnMut() -> bool,
        crossover: &mut Crossover,
    ) -> Result<bool, CondensedFailure> {
        let settled_here = self.previous.as_ref() == Some(&pattern)
            && pattern != self.start
            && self.offered.as_ref() != Some(&pattern)
            && self.count < MOST_CROSSOVERS;
        if !settled_here {
            self.previous = Some(pattern);
            return Ok(false);
        }
        self.count += 1;
        let settled = crossover(&pattern, banded, keep_going)?;
        self.offered = Some(pattern);
        Ok(settled)
    }
}
