//! The scale of μ in the interior-point iteration on (38) (`interior`): each friction DOF's own
//! scale (its nearest bound times the motions of its kind), the start centred at their mean,
//! and the end — μ at [`CENTRALITY_TOLERANCE`] of the smallest scale, or later where many
//! DOFs are still not clearly on their side there ([`IterationEnd`]).
//!
//! Why the end can come later (issue 26, stop 62; docs/many-obstacles/iteration-end.md): a
//! scale is an estimate, and on clusters at ties it overstates the swivel DOFs' by orders of
//! magnitude (the motions of their kind at the start are the clusters' largest). At the μ it
//! sets, 3972 of the 4000 swivel DOFs of `check::families::lowered_clustered_ties_scene` at
//! k = 4000 (seed 1) were still not clearly on their side (neither clearly moving nor clearly
//! stuck); the guess was thousands of DOFs off, and the search took 38 pattern solves. Six
//! steps more settle them (3 solves); on clusters of 50 obstacles 1e-9·l apart at ties,
//! 21–44 s became 49–66 ms.

use super::held_bounds::nearest;

/// μ, relative to the smallest DOF's own scale, at which the guess is taken.
const CENTRALITY_TOLERANCE: f64 = 1e-12;

/// At most this many DOFs not clearly on their side (or [`UNCLEAR_FRACTION`] of them, if more)
/// and the iteration ends at its μ; with more, it goes on while their number falls. The ties
/// family ends with 1–4 such DOFs (a DOF at its threshold that hardly moves is never clear:
/// docs/many-obstacles/step-costs.md, stop 57), and going on would not settle them.
const UNCLEAR_FEW: usize = 8;

/// See [`UNCLEAR_FEW`]: the fraction of the friction variables that may be left unclear.
/// Measured with [`UNCLEAR_FEW`] on 60 generated scenes (the families, clusters at ties with a
/// threshold lowered, tight clusters, half ties, dense stretches, pairs): 1 % and 8 gave 213
/// pattern solves where the iteration as it was took 494; 2 % and 16 gave 224; none and 4
/// gave 213 with 31 interior steps more.
const UNCLEAR_FRACTION: f64 = 0.01;

/// Steps past its μ without a new low in the number of unclear DOFs, after which the
/// iteration ends anyway. On the same 60 scenes: 2 steps gave 283 pattern solves, 3 gave 213,
/// 5 gave 221 with 23 interior steps more.
const UNCLEAR_PATIENCE: usize = 3;

/// Where the iteration starts and ends, from every friction DOF's `bounds` (`None` without
/// friction) and the `motion` of the start: (the mean of the DOFs' own scales, at which the
/// start is centred; the μ at which the iteration may end).
pub(super) fn centrality_scales(bounds: &[Option<(f64, f64)>], motion: &[f64]) -> (f64, f64) {
    // Each DOF's own scale of μ: its nearest bound times the motions of its kind.
    let motion_scale = largest_of_each_kind(motion);
    let scales: Vec<f64> = bounds
        .iter()
        .enumerate()
        .filter_map(|(dof, b)| Some(nearest((*b)?) * 0.1 * motion_scale[dof % 2]))
        .collect();
    let mean = scales.iter().sum::<f64>() / scales.len().max(1) as f64;
    let smallest = scales
        .iter()
        .copied()
        .filter(|&scale| scale > 0.0)
        .fold(f64::INFINITY, f64::min);
    (mean, CENTRALITY_TOLERANCE * smallest)
}

/// The largest |value| of each kind (even and odd DOFs), at least the smallest normal.
fn largest_of_each_kind(values: &[f64]) -> [f64; 2] {
    [0, 1].map(|kind| {
        values
            .iter()
            .skip(kind)
            .step_by(2)
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(f64::MIN_POSITIVE)
    })
}

/// Whether the iteration ends: at its μ, if at most a few DOFs are not clearly on their side
/// ([`UNCLEAR_FEW`], [`UNCLEAR_FRACTION`]) or their number has not fallen for
/// [`UNCLEAR_PATIENCE`] steps.
pub(super) struct IterationEnd {
    /// The μ from which the iteration may end.
    final_centrality: f64,
    /// Unclear DOFs the iteration may end with at once.
    few: usize,
    /// Unclear DOFs after the last step (`None` before the first).
    unclear: Option<usize>,
    /// The fewest unclear DOFs since μ reached its end, and the steps taken when they were.
    fewest: Option<(usize, usize)>,
}

impl IterationEnd {
    /// For an iteration of `variables` friction variables that may end at μ = `final_centrality`.
    pub(super) fn new(final_centrality: f64, variables: usize) -> IterationEnd {
        IterationEnd {
            final_centrality,
            few: UNCLEAR_FEW.max((UNCLEAR_FRACTION * variables as f64) as usize),
            unclear: None,
            fewest: None,
        }
    }

    /// After `taken` steps, `unclear` DOFs are not clearly on their side.
    pub(super) fn stepped(&mut self, taken: usize, unclear: usize) {
        self.unclear = Some(unclear);
        if let Some((fewest, taken_then)) = &mut self.fewest
            && unclear < *fewest
        {
            (*fewest, *taken_then) = (unclear, taken);
        }
    }

    /// Does the iteration end after `taken` steps, at μ = `mu`? Before any step, as soon as μ
    /// is at its end (a start there takes no step). The first time μ is at its end after a
    /// step, that step's unclear DOFs become the fewest so far, from which the patience counts.
    pub(super) fn reached(&mut self, mu: f64, taken: usize) -> bool {
        if mu > self.final_centrality {
            return false;
        }
        let Some(unclear) = self.unclear else {
            return true;
        };
        let (_, taken_then) = *self.fewest.get_or_insert((unclear, taken));
        unclear <= self.few || taken >= taken_then + UNCLEAR_PATIENCE
    }
}

#[cfg(test)]
mod tests {
    use super::{IterationEnd, UNCLEAR_PATIENCE};

    /// μ at its end from 1.0 down, in these tests.
    const END: f64 = 1.0;

    /// An iteration of 100 variables (8 may stay unclear) that reached its μ after 10 steps
    /// with `unclear` DOFs unclear, more than a few: it goes on.
    fn going_on_with(unclear: usize) -> IterationEnd {
        let mut end = IterationEnd::new(END, 100);
        end.stepped(10, unclear);
        assert!(!end.reached(0.5, 10), "{unclear} unclear: it goes on");
        end
    }

    #[test]
    fn it_ends_at_its_mu_when_few_dofs_are_unclear() {
        let mut end = IterationEnd::new(END, 100);
        end.stepped(1, 20);
        assert!(!end.reached(2.0, 1), "μ above its end");
        end.stepped(2, 8);
        assert!(end.reached(0.5, 2), "8 unclear of 100 variables");
    }

    #[test]
    fn with_no_step_taken_it_ends_as_soon_as_mu_is_at_its_end() {
        let mut end = IterationEnd::new(END, 100);
        assert!(!end.reached(1.5, 0));
        assert!(end.reached(END, 0));
    }

    #[test]
    fn it_goes_on_while_the_unclear_dofs_reach_new_lows() {
        let mut end = going_on_with(50);
        // A new low at step 12, then none: it ends UNCLEAR_PATIENCE steps after the low.
        end.stepped(11, 55);
        assert!(!end.reached(0.4, 11));
        end.stepped(12, 30);
        for taken in 12..12 + UNCLEAR_PATIENCE {
            assert!(!end.reached(0.3, taken), "{taken} steps");
            end.stepped(taken + 1, 31 + taken);
        }
        assert!(end.reached(0.2, 12 + UNCLEAR_PATIENCE));
    }

    #[test]
    fn it_ends_once_the_unclear_dofs_fall_to_a_few() {
        let mut end = going_on_with(50);
        end.stepped(11, 9);
        assert!(!end.reached(0.4, 11), "9 of 100: one too many");
        end.stepped(12, 0);
        assert!(end.reached(0.3, 12));
    }

    #[test]
    fn it_does_not_end_while_mu_is_above_its_end_again() {
        let mut end = going_on_with(50);
        for taken in 11..20 {
            end.stepped(taken, 50);
            assert!(
                !end.reached(1.5, taken),
                "μ above its end after {taken} steps"
            );
        }
        assert!(end.reached(0.5, 20), "no new low since 10 steps");
    }

    #[test]
    fn a_few_is_one_percent_of_many_variables() {
        let mut end = IterationEnd::new(END, 8000);
        end.stepped(10, 81);
        assert!(!end.reached(0.5, 10), "81 of 8000");
        end.stepped(11, 80);
        assert!(end.reached(0.5, 11), "80 of 8000");
    }
}
