//! The patterns an interior-point iteration (`interior`) offers to the search before it
//! ends, as interior-point methods for linear programs cross over to a vertex: a pattern the
//! same after two steps in a row with every DOF clearly on its side, not the one it started
//! from, at most [`MOST_CROSSOVERS`] of them.

use super::CondensedFailure;
use super::system::Pattern;
use crate::linalg::banded_lu::BandedSystem;

/// Where the iteration has settled on a pattern (the same after two steps in a row, every DOF
/// clearly on its side after the second, and not the one it started from), it offers it to its
/// caller, which solves it and says whether the search is settled from there (true: the
/// iteration ends). Measured (`cargo bench --bench many_obstacles -- report`): on the
/// clustered family at k = 1000 and 4000 the pattern is final after 4 of 15 steps.
///
/// The offer solves in the iteration's own banded system (given with it), whose factors the
/// iteration's next step makes anew.
pub(super) type Crossover<'c> = dyn FnMut(&[Pattern], &mut BandedSystem, &mut dyn FnMut() -> bool) -> Result<bool, CondensedFailure>
    + 'c;

/// Most patterns the iteration offers to its caller ([`Crossover`]): an offer that fails
/// costs a pattern solve, so at most this many are lost.
pub(super) const MOST_CROSSOVERS: usize = 4;

/// The patterns of the iteration's last steps, and those it has offered ([`Crossover`]).
pub(super) struct Offers {
    /// The pattern it started from.
    start: Vec<Pattern>,
    /// The last step's pattern.
    previous: Option<Vec<Pattern>>,
    /// The last pattern offered.
    offered: Option<Vec<Pattern>>,
    count: usize,
}

impl Offers {
    /// None offered yet, from an iterate describing `start`.
    pub(super) fn new(start: Vec<Pattern>) -> Offers {
        Offers {
            start,
            previous: None,
            offered: None,
            count: 0,
        }
    }

    /// After a step whose iterate describes `pattern`, with every DOF clearly on its side
    /// where `clear`: offers it when it is clear, is the last step's pattern too (that step
    /// need not have been clear: docs/many-obstacles/monotone-search.md, "Offered one step
    /// sooner"), is not the start's and was not offered just before (at most [`MOST_CROSSOVERS`]
    /// times); whether `crossover` settled the search from it.
    pub(super) fn settled(
        &mut self,
        pattern: Vec<Pattern>,
        clear: bool,
        banded: &mut BandedSystem,
        keep_going: &mut dyn FnMut() -> bool,
        crossover: &mut Crossover,
    ) -> Result<bool, CondensedFailure> {
        let settled_here = clear
            && self.previous.as_ref() == Some(&pattern)
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
