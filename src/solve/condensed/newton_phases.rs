//! The bookkeeping of the search's semismooth Newton phases (`search`): where each phase
//! starts and when it ends, the best start found for the monotone search, the restart from
//! the projected Newton guess. No equation of its own: it steers the pattern solves of (38).

use std::collections::HashSet;

use super::fronts::Fronts;
use super::system::Pattern;
use crate::linalg::double_double::DoubleDouble;

/// A 64-bit fingerprint of a pattern (FNV-1a over the states).
pub(super) fn fingerprint(pattern: &[Pattern]) -> u64 {
    pattern
        .iter()
        .fold(0xcbf2_9ce4_8422_2325u64, |hash, state| {
            let byte = match state {
                Pattern::Stuck => 0u64,
                Pattern::Positive => 1,
                Pattern::Negative => 2,
            };
            (hash ^ byte).wrapping_mul(0x0000_0100_0000_01b3)
        })
}

/// The bookkeeping of the semismooth Newton phases.
pub(super) struct NewtonPhases<'a> {
    /// σ / diagonal stiffness of every phase, in order.
    pub(super) fractions: &'a [f64],
    /// Still in a Newton phase (else in the monotone search).
    pub(super) active: bool,
    /// The current phase and the solve it started at.
    pub(super) phase: usize,
    pub(super) phase_start: usize,
    /// The fewest inconsistent DOFs seen in this phase, and when.
    pub(super) fewest_changes: (usize, usize),
    /// Over every Newton phase: where the monotone search starts.
    pub(super) starts: MonotoneStarts,
    /// Patterns this phase has solved, by fingerprint (hashing 8000 states with SipHash cost
    /// 2 % of a 4000-obstacle solve; a collision would only end a Newton phase early).
    pub(super) seen: HashSet<u64>,
    /// Where every Newton phase starts: the interior-point guess, if any, else all stuck.
    pub(super) start: Option<Vec<Pattern>>,
    /// Steps of this phase that only freed stuck DOFs: progress that cannot cycle, so they
    /// neither count as a stall nor against `search::NEWTON_STEPS` (at most one per DOF).
    pub(super) freeing_steps: usize,
    /// Where such steps free a stretch from its ends, the fronts that free it faster.
    pub(super) fronts: Fronts,
    /// The held forces (b of J), where known (from `search::INTERIOR_POINT_FROM` obstacles): the
    /// starts are then measured by J (`MonotoneStarts`), else by their inconsistent DOFs; and
    /// once the monotone search has gone on for
    /// `search::MONOTONE_BEFORE_PROJECTED` solves, the projected Newton guess (`projected`) is made
    /// from them and the phases run again from it.
    pub(super) held: Option<Vec<DoubleDouble>>,
    /// That restart has happened (it happens once).
    pub(super) restarted: bool,
    /// Uncertain decisions in this phase's last solves (before any refinement), the last
    /// one last: at most `search::NEWTON_PATIENCE` of them.
    pub(super) recent_uncertain: Vec<usize>,
    /// This phase decides every step on refined values (it has gone on from where it would
    /// have ended with `search::REFINED_PHASE_FROM` decisions or more uncertain, not falling).
    pub(super) refined_decisions: bool,
    /// A later variant's σ would have taken one of this phase's decisions otherwise; if none
    /// would, the later variants would replay this phase solve for solve, and are skipped.
    pub(super) fraction_mattered: bool,
}

impl NewtonPhases<'_> {
    /// Phase `phase` begins at solve `solves`: no stall, no freeing steps, no fronts, no
    /// pattern seen yet, certain decisions first.
    pub(super) fn begin_phase(&mut self, phase: usize, solves: usize) {
        self.phase = phase;
        self.restart_progress(solves);
        self.refined_decisions = false;
        self.fraction_mattered = false;
    }

    /// The present phase goes on from solve `solves`, every decision taken on refined values:
    /// its progress is counted afresh, what its decisions said about σ is kept.
    pub(super) fn go_on_refined(&mut self, solves: usize) {
        self.restart_progress(solves);
        self.refined_decisions = true;
    }

    fn restart_progress(&mut self, solves: usize) {
        self.phase_start = solves;
        self.fewest_changes = (usize::MAX, solves);
        self.seen.clear();
        self.freeing_steps = 0;
        self.fronts.reset();
        self.recent_uncertain.clear();
    }
}

/// Where the monotone search may start: of the solved patterns, the one whose point has the
/// lowest J (where the held forces are known, else the fewest inconsistent DOFs) and the one
/// with the fewest inconsistent DOFs. Any start is a point the search then only improves;
/// from all stuck it frees the DOFs a line search at a time, O(k) solves when hundreds move.
#[derive(Default)]
pub(super) struct MonotoneStarts {
    lowest: Option<Start>,
    fewest: Option<Start>,
}

/// A solved pattern with its measure (J, or the number of inconsistent DOFs) and its number
/// of inconsistent DOFs.
struct Start {
    measure: f64,
    inconsistent: usize,
    pattern: Vec<Pattern>,
}

/// How many times fewer inconsistent DOFs the fewest-inconsistent pattern must have, and how
/// close its J must be to the lowest (relative to |J|), for the search to start there
/// instead. Measured on ties with one threshold lowered (`check::families::
/// lowered_ties_scene_at`, 80 scenes of k = 300 to 4000, as `cargo bench --bench
/// many_obstacles -- lowered` makes them): from the fewest inconsistent DOFs the last
/// sliding threshold ten notches down took 4540 pattern solves at k = 1500 and did not
/// converge in 16 144 at k = 2000, from the lowest J 109 and 68 (stop 37); obstacle k/3's
/// swivel five notches down at k = 2000 139 from the lowest J, 1013 from the fewest. Where
/// the fewest had 10 times fewer, J differed by 0.74 to 38 times |J| on every scene but one:
/// the last swivel threshold two notches down at k = 2000, 15 inconsistent DOFs against 2085
/// and J the same to 5e-9, where the walk from the lowest J took 2195 solves and from the
/// fewest 207.
const FEWER_INCONSISTENT: usize = 10;
const SAME_J: f64 = 1e-6;

impl MonotoneStarts {
    /// A solved pattern with its measure and its number of inconsistent DOFs.
    pub(super) fn offer(&mut self, measure: f64, inconsistent: usize, pattern: &[Pattern]) {
        let start = || Start {
            measure,
            inconsistent,
            pattern: pattern.to_vec(),
        };
        if self.lowest.as_ref().is_none_or(|s| measure < s.measure) {
            self.lowest = Some(start());
        }
        if self
            .fewest
            .as_ref()
            .is_none_or(|s| inconsistent < s.inconsistent)
        {
            self.fewest = Some(start());
        }
    }

    /// Where the monotone search starts: the lowest J, unless the pattern with the fewest
    /// inconsistent DOFs has [`FEWER_INCONSISTENT`] times fewer and J within [`SAME_J`] of it.
    pub(super) fn take(&mut self) -> Option<Vec<Pattern>> {
        let (lowest, fewest) = (self.lowest.take(), self.fewest.take());
        match (lowest, fewest) {
            (Some(lowest), Some(fewest))
                if fewest.inconsistent.saturating_mul(FEWER_INCONSISTENT) < lowest.inconsistent
                    && fewest.measure - lowest.measure <= SAME_J * lowest.measure.abs() =>
            {
                Some(fewest.pattern)
            }
            (lowest, _) => lowest.map(|s| s.pattern),
        }
    }
}
