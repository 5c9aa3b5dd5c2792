//! The search for the friction pattern: semismooth Newton phases, then a monotone search (exact
//! line search on the convex objective, feature-sign fallback) that can neither cycle nor
//! stall. It starts from the interior-point guess (where the iteration stalled once, after a
//! short search from the stalled guess: `stalled_first`); where the guess's own pattern is
//! inconsistent, its variant with the unclear DOFs held (`unclear_held`) and then the
//! monotone search from the guess are tried first (`from_guess`). A search that runs past 64
//! solves gets a second guess from refined interior-point steps (`second_guess`). When a
//! convergence history is asked for, every pattern solve is recorded as one iterate
//! ([`record_pattern`]).

use std::collections::HashSet;

mod from_guess;
mod second_guess;
mod stalled_first;
mod unclear_held;

use super::answer::{condensed_solution, record_pattern};
use super::fronts::Fronts;
use super::interior::Guess;
use super::monotone::MonotoneSearch;
use super::newton_phases::{MonotoneStarts, NewtonPhases, fingerprint};
use super::scaling::Scales;
use super::system::{Accuracy, Pattern, PatternSolution, ShootingSystem};
use super::{CondensedFailure, CondensedSolution, FrictionPattern};
use crate::fem::Mesh;
use crate::linalg::banded_lu::BandedSystem;
use crate::linalg::double_double::DoubleDouble;
use crate::model::Problem;
use crate::solve::history::Recorder;
use second_guess::SECOND_GUESS_AFTER;

/// Most solves of one semismooth Newton phase.
const NEWTON_STEPS: usize = 40;
/// The Newton phases tried in turn before the monotone search, by σ / diagonal stiffness of
/// the reversal prediction. Measured on the benchmark scenes (`condensed-many-obstacles`,
/// 16–4000 obstacles with random thresholds) once uncertain decisions wait for refinement:
/// σ = 0 converges in 6–16 solves where 0.5 diverges after a few steps at 4000 obstacles;
/// 0.5 stays as the second variant for scenes where 0 cycles.
pub(super) const NEWTON_REVERSAL_FRACTIONS: [f64; 2] = [0.0, 0.5];
/// Fewest obstacles for which the search starts from the interior-point guess (one refined
/// solve of the held beam, then 13–64 steps of its own): with fewer, semismooth Newton from
/// all stuck takes a handful of solves. Measured on the issue-26 families at k = 128 (`cargo
/// bench --bench many_obstacles -- report`): random, clustered and mixed go from 13–39
/// pattern solves (1.1–3.0 ms) to 1–2 (0.7–0.9 ms); ties from 14 to 2.
const INTERIOR_POINT_FROM: usize = 32;
/// Most pattern solves from a warm start ([`super::solve_condensed_from`]) before the search
/// starts over without it. Measured with `cargo bench --bench many_obstacles -- warm` (one
/// notch of one threshold at k = 1000 and 4000): on clustered scenes one solve settles it; on
/// random ones the old pattern leaves 1–3 DOFs inconsistent and the monotone search settles
/// them in 3–12 solves, where semismooth Newton from there went from 3 to 111 inconsistent
/// DOFs at once (and to thousands without a guard).
const WARM_SOLVES: usize = 16;
/// Most DOFs the old pattern may leave inconsistent for a warm start to go on: after one
/// notch on the ties family it leaves 1750 of 8000 (every force is at its threshold, so one
/// change moves them all) and the monotone search would take hundreds of solves.
const WARM_LOCAL: usize = 16;
/// Solves of a pattern the interior-point iteration offers (`offers::Crossover`): one, so no
/// Newton or monotone step is taken and the search's state (σ included) is untouched; a
/// consistent pattern is refined and decided again on the refined values like any other.
const CROSSOVER_SOLVES: usize = 1;
/// Solves of the monotone search before the Newton phases run again from the projected
/// Newton guess ([`PatternSearch::restart_from_projected_guess`]). Measured on ties with
/// thresholds lowered (`cargo bench --bench many_obstacles -- lowered`, k = 300 to 4000):
/// with obstacle 0's sliding threshold one, two or five notches down and the last one's ten,
/// the monotone search settled in 2–17 solves; with obstacle k/3's swivel threshold two
/// notches down it took 7607 at k = 4000 (55 s). The whole search with the restart after 16,
/// 32 or 64 solves: that swivel case 793, 809, 841; the last swivel threshold one notch down
/// at k = 1000 86, 102, 134; the last sliding threshold ten notches down at k = 4000 183,
/// 109, 109.
const MONOTONE_BEFORE_PROJECTED: usize = 32;
/// The monotone search restarts from the projected Newton guess (after
/// [`MONOTONE_BEFORE_PROJECTED`] solves) only where its last solve leaves more DOFs
/// inconsistent than this; with fewer it is near the answer and goes on. Measured on the 96
/// clusters at ties of stop 52's sweep (docs/many-obstacles/close-obstacles-and-near-ties.md): four
/// scenes took fewer pattern solves (272 → 113, 196 → 113, 131 → 114, 248 → 220; 331–332 → 136–146
/// ms for the first), two more (169 → 175, 186 → 192), and no other of its 240 scenes changed; 4329
/// → 4054 solves in all (with 16: 4125). The lowered ties that the restart was made for (obstacle
/// k/3's swivel two or five notches down at k = 1000–4000) settle in 5–8 solves either way.
const PROJECTED_ABOVE: usize = 32;
/// Uncertain decisions left when a Newton phase (which takes the certain decisions first)
/// would end, from which it goes on instead (unless their number is falling: below half the
/// largest of its last [`NEWTON_PATIENCE`] solves), every step refined as far as its
/// decisions need and all of them taken. Measured on ties with a swivel threshold lowered
/// (`cargo bench --bench many_obstacles -- lowered`): the certain changes cycle among 2 or 3
/// DOFs while thousands of decisions wait on rounding, and the monotone search from there
/// took 801–925 pattern solves (8–33 s) at k = 4000 with obstacle k/3's threshold lowered
/// one, two or five notches; going on with refined decisions, 258–283 (1.3–3.9 s). Where
/// the number was falling (fronts at work), going on cost 6–38 more solves.
const REFINED_PHASE_FROM: usize = 16;
/// A Newton phase is abandoned when the number of inconsistent DOFs has not reached a new
/// low for this many solves.
const NEWTON_PATIENCE: usize = 6;

/// [`solve_condensed_while`] with the given Newton phases (none: the monotone search alone):
/// the system in dimensionless units, the search for a consistent pattern
/// ([`PatternSearch::run`]), then the answer in SI units ([`condensed_solution`]). Every
/// pattern solve goes to `recorder`, if any.
///
/// [`solve_condensed_while`]: super::solve_condensed_while
pub(super) fn solve_with_newton_phases(
    problem: &Problem,
    mesh: &Mesh,
    newton_phases: &[f64],
    keep_going: &mut dyn FnMut() -> bool,
    mut recorder: Option<&mut Recorder>,
    start: Option<&FrictionPattern>,
) -> Result<CondensedSolution, CondensedFailure> {
    let scales = Scales::of(problem);
    // The first Newton phase's σ fraction; without Newton phases, the first variant's (a
    // reversing DOF is held stuck).
    let first_fraction = newton_phases
        .first()
        .copied()
        .unwrap_or(NEWTON_REVERSAL_FRACTIONS[0]);
    let system = ShootingSystem::new(problem, mesh, &scales, first_fraction);
    let obstacles = problem.obstacles.len();
    let mut observe = |solution: &PatternSolution, pattern: &[Pattern]| {
        if let Some(recorder) = recorder.as_deref_mut() {
            record_pattern(recorder, (problem, &scales, &system), solution, pattern);
        }
    };
    // A warm start whose first solve leaves few DOFs inconsistent (the change stayed local)
    // gets a few steps of the monotone search; otherwise the search starts over as without
    // one (so it costs one solve, or at most WARM_SOLVES, more than a cold solve).
    let mut warm_solves = 0;
    // Every attempt and the search solve in the system the last solve on this thread kept.
    let mut banded = BandedSystem::kept();
    if let Some(start) = start.filter(|start| start.dofs() == 2 * obstacles) {
        let mut attempt = PatternSearch::attempt(&system, &start.0, WARM_SOLVES);
        attempt.local_only = Some(WARM_LOCAL);
        // A warm start that does not settle (or meets a singular pattern) only costs solves.
        let (settled, solves) = attempt.settle_in(&mut banded, keep_going, &mut observe)?;
        if let Some((solution, pattern)) = settled {
            banded.keep();
            return condensed_solution(
                (problem, mesh, &scales),
                &system,
                (&solution, &pattern),
                (solves, true),
                keep_going,
            );
        }
        warm_solves = solves;
        system.reversal_fraction.set(first_fraction);
    }
    let mut search = PatternSearch::new(&system, obstacles, newton_phases);
    search.banded = banded;
    let mut crossed = None;
    let mut second_guess_after = None;
    if !newton_phases.is_empty() && obstacles >= INTERIOR_POINT_FROM {
        if !keep_going() {
            return Err(CondensedFailure::Stopped);
        }
        let held = search.held_forces()?;
        if held.len() == 2 * obstacles {
            // The iteration and the attempts solve in the search's banded system (one
            // system's memory for all: fresh memory is faulted in page by page).
            let natural_limit = search.limit;
            search.limit = natural_limit.min(search.solves + SECOND_GUESS_AFTER);
            second_guess_after = Some((search.limit, natural_limit));
            crossed = search.guess_and_start(held, keep_going, &mut observe)?;
        }
    }
    let answer = |search: &PatternSearch,
                  solution: &PatternSolution,
                  converged: bool,
                  keep_going: &mut dyn FnMut() -> bool| {
        condensed_solution(
            (problem, mesh, &scales),
            &system,
            (solution, &search.pattern),
            (warm_solves + search.solves_in_all(), converged),
            keep_going,
        )
    };
    if let Some((solution, pattern)) = crossed {
        search.pattern = pattern;
        search.banded.keep();
        return answer(&search, &solution, true, keep_going);
    }
    let result = search.run(keep_going, &mut observe);
    let (solution, converged) = result.inspect_err(|_| search.banded.keep())?;
    let ran_out = second_guess_after
        .is_some_and(|(allowed, natural)| allowed < natural && search.solves >= allowed);
    let (mut search, solution, converged) = match second_guess_after {
        Some((_, natural_limit)) if ran_out && !converged => {
            search.with_second_guess(solution, natural_limit, keep_going, &mut observe)?
        }
        _ => (search, solution, converged),
    };
    search.banded.keep();
    answer(&search, &solution, converged, keep_going)
}

/// What an attempt made on the side ends with: the consistent solution and its pattern if it
/// settled.
type Settled = Option<(PatternSolution, Vec<Pattern>)>;

/// The search for the friction pattern between two solves: the pattern to solve next, the
/// banded system whose factors a refinement reuses, the count of solves and the state of
/// each stage (Newton phases, then the monotone search).
struct PatternSearch<'a> {
    system: &'a ShootingSystem,
    /// The pattern solved next (at the end: the final one).
    pattern: Vec<Pattern>,
    /// Every pattern is solved by elimination alone; when a decision is within what that can
    /// resolve (or the pattern looks consistent), the same system is refined from its factors
    /// (each value to its own last bits) and the decision is taken on the refined values.
    banded: BandedSystem,
    /// Linear solves so far.
    solves: usize,
    /// Most linear solves.
    limit: usize,
    /// A warm start's attempt: give up when the first solve leaves more DOFs inconsistent
    /// than this (the change was not local).
    local_only: Option<usize>,
    /// A crossover's check of a pattern offered by the interior-point iteration: give up as
    /// soon as a solve leaves a DOF certainly inconsistent (no refinement for it).
    certain_only: bool,
    /// An attempt that gives up once two solves in a row change more DOFs than this
    /// ([`PatternSearch::wandered_off`]).
    give_up_above: Option<usize>,
    /// Solves in a row that changed more than that.
    wide_solves_in_a_row: usize,
    /// The interior-point guess with the DOFs it left unclear held stuck
    /// ([`PatternSearch::try_from_guess`]): taken at the search's first inconsistent solve,
    /// and tried there only if that solve changes at least `UNCLEAR_HELD_FROM` DOFs.
    unclear_held: Option<Vec<Pattern>>,
    /// The interior-point guess the search started from, whole (`second_guess`).
    guess: Option<Guess>,
    /// Solves of attempts made on the side (that variant's), counted apart so that the
    /// search's own limits count its own solves.
    side_solves: usize,
    /// The monotone search from the guess, tried at the search's first inconsistent solve
    /// where that leaves few DOFs inconsistent ([`PatternSearch::try_from_guess`]).
    monotone_from_guess: bool,
    /// A solve of `pattern` already made (by the search that began this attempt): decided
    /// first instead of solved again.
    handed: Option<PatternSolution>,
    newton: NewtonPhases<'a>,
    monotone: MonotoneSearch,
}

impl<'a> PatternSearch<'a> {
    /// Every DOF stuck, with `newton_phases` to try first.
    fn new(
        system: &'a ShootingSystem,
        obstacles: usize,
        newton_phases: &'a [f64],
    ) -> PatternSearch<'a> {
        let dofs = 2 * obstacles;
        PatternSearch {
            system,
            pattern: vec![Pattern::Stuck; dofs],
            banded: BandedSystem::empty(),
            solves: 0,
            limit: 4 * dofs + 64 + 4 * newton_phases.len() * NEWTON_STEPS,
            local_only: None,
            give_up_above: None,
            wide_solves_in_a_row: 0,
            unclear_held: None,
            guess: None,
            side_solves: 0,
            monotone_from_guess: false,
            handed: None,
            certain_only: false,
            newton: NewtonPhases {
                fractions: newton_phases,
                active: !newton_phases.is_empty(),
                phase: 0,
                phase_start: 0,
                fewest_changes: (usize::MAX, 0),
                starts: MonotoneStarts::default(),
                seen: HashSet::new(),
                start: None,
                freeing_steps: 0,
                fronts: Fronts::default(),
                held: None,
                restarted: false,
                recent_uncertain: Vec::new(),
                refined_decisions: false,
                fraction_mattered: false,
            },
            monotone: MonotoneSearch::default(),
        }
    }

    /// An attempt from `start` with the monotone search alone (no Newton phases), of at
    /// most `limit` solves: a warm start's, or the check of an offered pattern.
    fn attempt(system: &'a ShootingSystem, start: &[Pattern], limit: usize) -> PatternSearch<'a> {
        let mut attempt = PatternSearch::new(system, start.len() / 2, &[]);
        attempt.pattern = start.to_vec();
        attempt.limit = limit;
        attempt
    }

    /// The check of a pattern the interior-point iteration offers (`offers::Crossover`): one
    /// solve, no refinement once a DOF is certainly inconsistent.
    fn offered(system: &'a ShootingSystem, candidate: &[Pattern]) -> PatternSearch<'a> {
        let mut attempt = PatternSearch::attempt(system, candidate, CROSSOVER_SOLVES);
        attempt.certain_only = true;
        attempt
    }

    /// Runs this attempt in `banded` (handed back after) until it settles or gives up: the
    /// consistent solution and its pattern if it settled, and its solves (its own attempts'
    /// too). A singular pattern is one that failed (the caller goes on); `Stopped` goes up.
    fn settle_in(
        mut self,
        banded: &mut BandedSystem,
        keep_going: &mut dyn FnMut() -> bool,
        observe: &mut dyn FnMut(&PatternSolution, &[Pattern]),
    ) -> Result<(Settled, usize), CondensedFailure> {
        self.banded = std::mem::replace(banded, BandedSystem::empty());
        let result = self.run(keep_going, observe);
        *banded = std::mem::replace(&mut self.banded, BandedSystem::empty());
        let solves = self.solves_in_all();
        match result {
            Ok((solution, true)) => Ok((Some((solution, self.pattern)), solves)),
            Ok(_) | Err(CondensedFailure::Singular { .. }) => Ok((None, solves)),
            Err(stopped) => Err(stopped),
        }
    }

    /// Pattern solves in all: the search's own and its side attempts'.
    fn solves_in_all(&self) -> usize {
        self.solves + self.side_solves
    }

    /// The search loop: solves patterns until one is consistent or the solves run out; the
    /// last solution and whether its pattern is consistent. `observe` sees every pattern
    /// solved with its (final, possibly refined) solution.
    fn run(
        &mut self,
        keep_going: &mut dyn FnMut() -> bool,
        observe: &mut dyn FnMut(&PatternSolution, &[Pattern]),
    ) -> Result<(PatternSolution, bool), CondensedFailure> {
        loop {
            if !keep_going() {
                return Err(CondensedFailure::Stopped);
            }
            let (solution, changes) = match self.handed.take() {
                // Observed already, by the search that made it.
                Some(solution) => self.decide(solution)?,
                None => {
                    let decided = self.solve_and_decide()?;
                    observe(&decided.0, &self.pattern);
                    decided
                }
            };
            if changes.is_empty() {
                return Ok((solution, true));
            }
            if let Some((solution, pattern)) =
                self.try_from_guess(&solution, changes.len(), keep_going, observe)?
            {
                self.pattern = pattern;
                return Ok((solution, true));
            }
            if self.solves >= self.limit
                || self.is_not_local(&changes)
                || self.wandered_off(&changes)
            {
                return Ok((solution, false));
            }
            if self.newton.active {
                self.newton_step(&solution, &changes);
            } else if self.solves < self.monotone.started_at + MONOTONE_BEFORE_PROJECTED
                || changes.len() <= PROJECTED_ABOVE
                || !self.restart_from_projected_guess(keep_going, changes.len())?
            {
                self.monotone_step(&solution, &changes);
            }
        }
    }

    /// A warm start's first solve leaves too many DOFs inconsistent for the change to be a
    /// local one: the attempt gives up.
    fn is_not_local(&self, changes: &[(usize, Pattern)]) -> bool {
        self.solves == 1 && self.local_only.is_some_and(|most| changes.len() > most)
    }

    /// The forces with every DOF held, to about 106 bits (a pattern solve, refined): the
    /// base point of the interior-point guess. Counted as one of the search's solves.
    fn held_forces(&mut self) -> Result<Vec<DoubleDouble>, CondensedFailure> {
        let held = vec![Pattern::Stuck; self.pattern.len()];
        self.system
            .solve_pattern(&held, Accuracy::Plain, &mut self.banded)?;
        self.solves += 1;
        let refined = self
            .system
            .solve_pattern(&held, Accuracy::RefineLast, &mut self.banded)?;
        Ok(refined.exact.map(|e| e.force).unwrap_or_default())
    }

    /// Stage one of a step: solves the current pattern and decides which DOFs must change,
    /// refining the same solve when the decisions left are uncertain (no change: consistent).
    fn solve_and_decide(
        &mut self,
    ) -> Result<(PatternSolution, Vec<(usize, Pattern)>), CondensedFailure> {
        let solution =
            self.system
                .solve_pattern(&self.pattern, Accuracy::Plain, &mut self.banded)?;
        self.solves += 1;
        self.decide(solution)
    }

    /// [`PatternSearch::solve_and_decide`] for a solve made already: the decisions, with the
    /// refinement they need.
    fn decide(
        &mut self,
        mut solution: PatternSolution,
    ) -> Result<(PatternSolution, Vec<(usize, Pattern)>), CondensedFailure> {
        let system = self.system;
        let mut changes = system.inconsistent_dofs(&solution, &self.pattern);
        if self.is_not_local(&changes) {
            // A warm start that gives up here: no refinement to decide anything.
            return Ok((solution, changes));
        }
        // Newton steps take the decisions that elimination alone settles first, the others
        // on refined values once nothing else is left to change (or, in a phase that goes on
        // deciding on refined values, every step); the monotone search (which must not be
        // misled by a wrong sign) decides on refined values whenever any decision is
        // uncertain.
        let uncertain = system.uncertain(&solution, &self.pattern);
        let uncertain_count = uncertain.iter().filter(|&&u| u).count();
        let any_uncertain = uncertain_count > 0;
        if self.certain_only && changes.iter().any(|&(i, _)| !uncertain[i]) {
            return Ok((solution, changes));
        }
        if self.newton.active {
            changes.retain(|&(i, _)| !uncertain[i]);
            let recent = &mut self.newton.recent_uncertain;
            recent.push(uncertain_count);
            if recent.len() > NEWTON_PATIENCE {
                recent.remove(0);
            }
        } else if any_uncertain {
            changes.clear();
        }
        // Uncertain decisions left: refined only as far as the step needs, then, if the
        // pattern is consistent, to the last bits for the answer (and decided again on those).
        // A Newton step is refined until its decisions are settled; a monotone step, which
        // steps on the values themselves, until they are and its largest correction is the
        // noise of the residual (`Accuracy::RefineForSearch`). Stepping on values refined for
        // the decisions alone, the monotone search ran out of solves on seed 963 of `cargo
        // bench --bench reference -- scan`; refining its steps fully took 80 % of ties at
        // k = 4096 with the last swivel threshold ten notches down. A crossover's candidate,
        // like a pattern without uncertain decisions, is most likely the answer and refined
        // fully at once (refined for the search first, it cost the random family 7 % at
        // k = 1000).
        let partial = if self.newton.active {
            Some(Accuracy::RefineForDecisions)
        } else {
            (!self.certain_only).then_some(Accuracy::RefineForSearch)
        };
        let refine_decisions = changes.is_empty() || self.newton.refined_decisions;
        if let Some(accuracy) = partial.filter(|_| refine_decisions && any_uncertain) {
            solution = system.solve_pattern(&self.pattern, accuracy, &mut self.banded)?;
            changes = system.inconsistent_dofs(&solution, &self.pattern);
        }
        if changes.is_empty() {
            solution =
                system.solve_pattern(&self.pattern, Accuracy::RefineLast, &mut self.banded)?;
            changes = system.inconsistent_dofs(&solution, &self.pattern);
        }
        Ok((solution, changes))
    }

    /// Stage two in a Newton phase: plain semismooth Newton, every inconsistent DOF changes at
    /// once. Fast when it works; on a repeated pattern, a stall or too many steps with many
    /// decisions still uncertain, the phase goes on deciding on refined values
    /// ([`REFINED_PHASE_FROM`]); after that, the next variant starts where the first did
    /// (from the interior-point guess, else all stuck; skipped where it would replay this
    /// one), or after the last one the monotone search from the best pattern seen. (From all stuck, the
    /// second variant on ties with one threshold lowered made the best pattern all stuck, and
    /// the monotone search then freed one DOF per solve: 1705 solves at k = 300, 34 from the
    /// guess.) A step that only frees stuck DOFs is progress, however few it frees, and goes
    /// on along its fronts (`fronts`): on that arrangement with five notches at k = 4000 the
    /// phase used to end while freeing a stretch two DOFs per solve, and the monotone search
    /// then took 7500 solves (110 s).
    fn newton_step(&mut self, solution: &PatternSolution, changes: &[(usize, Pattern)]) {
        let (solves, dofs) = (self.solves, self.pattern.len());
        let newton = &mut self.newton;
        newton.seen.insert(fingerprint(&self.pattern));
        let measure = match &newton.held {
            Some(held) => self
                .system
                .objective(&self.system.search_point(solution), held),
            None => changes.len() as f64,
        };
        newton.starts.offer(measure, changes.len(), &self.pattern);
        let later = &newton.fractions[(newton.phase + 1).min(newton.fractions.len())..];
        newton.fraction_mattered |= changes.iter().any(|&(i, _)| {
            later.iter().any(|&fraction| {
                self.system
                    .decision_depends_on_fraction(solution, &self.pattern, i, fraction)
            })
        });
        let only_frees = changes
            .iter()
            .all(|&(i, _)| self.pattern[i] == Pattern::Stuck);
        for &(i, wanted) in changes {
            self.pattern[i] = wanted;
        }
        if only_frees {
            newton.fewest_changes.1 = solves;
            newton.freeing_steps = (newton.freeing_steps + 1).min(dofs);
            newton.fronts.extend(&mut self.pattern, changes);
        } else {
            newton.fronts.reset();
        }
        if changes.len() < newton.fewest_changes.0 {
            newton.fewest_changes = (changes.len(), solves);
        }
        let stalled = solves >= newton.fewest_changes.1 + NEWTON_PATIENCE;
        if newton.seen.contains(&fingerprint(&self.pattern))
            || stalled
            || solves >= newton.phase_start + newton.freeing_steps + NEWTON_STEPS
        {
            let recent = &newton.recent_uncertain;
            let left = recent.last().copied().unwrap_or(0);
            let falling = 2 * left < recent.iter().copied().max().unwrap_or(0);
            if !newton.refined_decisions && left >= REFINED_PHASE_FROM && !falling {
                // Where only the certain decisions were taken and the uncertain ones have
                // not been falling, go on from here once with every decision taken on
                // refined values.
                newton.go_on_refined(solves);
                return;
            }
            // Next Newton variant (unless it would replay this one), or the monotone search;
            // both from the start.
            let next = if newton.fraction_mattered {
                newton.phase + 1
            } else {
                newton.fractions.len()
            };
            newton.begin_phase(next, solves);
            self.pattern = match &newton.start {
                Some(start) => start.clone(),
                None => vec![Pattern::Stuck; dofs],
            };
            match newton.fractions.get(newton.phase) {
                Some(&fraction) => self.system.reversal_fraction.set(fraction),
                None => {
                    newton.active = false;
                    self.monotone.started_at = solves;
                    if let Some(start) = newton.starts.take() {
                        self.pattern = start;
                    }
                }
            }
        }
    }

    /// When the monotone search has gone on for [`MONOTONE_BEFORE_PROJECTED`] solves: the
    /// Newton phases again, from the projected Newton guess (`projected`), once, if there
    /// are held forces to make it from; the monotone search then starts over from its own
    /// present point or one of theirs ([`MonotoneStarts`]). Whether it restarted.
    fn restart_from_projected_guess(
        &mut self,
        keep_going: &mut dyn FnMut() -> bool,
        inconsistent: usize,
    ) -> Result<bool, CondensedFailure> {
        let newton = &mut self.newton;
        let Some(held) = newton.held.as_ref().filter(|_| !newton.restarted) else {
            return Ok(false);
        };
        newton.restarted = true;
        let Some(guess) = self.system.projected_newton_pattern(held, keep_going)? else {
            return Ok(false);
        };
        let present = match self.monotone.current.take() {
            Some(point) => self.system.objective(&point, held),
            None => f64::INFINITY,
        };
        self.monotone = MonotoneSearch::default();
        let solves = self.solves;
        let newton = &mut self.newton;
        newton.starts = MonotoneStarts::default();
        newton.starts.offer(present, inconsistent, &self.pattern);
        self.pattern = guess.clone();
        newton.start = Some(guess);
        newton.active = true;
        newton.begin_phase(0, solves);
        self.system.reversal_fraction.set(newton.fractions[0]);
        Ok(true)
    }

    /// Stage two in the monotone search ([`MonotoneSearch::step`]).
    fn monotone_step(&mut self, solution: &PatternSolution, changes: &[(usize, Pattern)]) {
        self.monotone
            .step(self.system, &mut self.pattern, solution, changes);
    }
}
