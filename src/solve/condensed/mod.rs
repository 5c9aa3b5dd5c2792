//! `condensed`: the exact solution of (38) from the exact relations of every piece between
//! special points (supports, obstacles, segment ends), condensed onto the friction DOFs, with
//! the friction solved in the primal. It is the method meant to grade the others.
//!
//! **Pieces.** On a piece between consecutive special points E·J is constant and f linear, so
//! the beam equation (EJ u'')'' = f has the exact transfer y(b) = Φ y(a) + q for the state
//! y = (u, u', m, m') with m = EJ u'' (the force formulation of docs/design.md fact 3, but applied
//! to one piece at a time). Because the finite-element solution is exact at the nodes
//! (docs/design.md fact 1), the states at the special points determine the discrete solution of (38)
//! on any mesh.
//!
//! **Multiple shooting instead of single shooting.** The unknowns are the state at the start of
//! every piece; the equations are each piece's transfer, the jumps at the obstacles (m' jumps
//! by −λ1, m by +λ2: conditions (3)–(6)) and the clamped ends. A stuck DOF has a known value
//! (zero) and an unknown reaction, so its reaction takes the column of its value: no known
//! zero and no row c = 0 enters the matrix. That is a banded system (band (3, 3), 4 unknowns
//! per special point), solved by Gaussian elimination with row equilibration and partial
//! pivoting (`linalg::banded_lu`), refined in double-double where a decision needs it.
//!
//! **Why it is stable.**
//! - *Nondimensional, exactly.* Length, stiffness and load are scaled by powers of two (l, the
//!   geometric mean of E·J, max |f|): exact, so a beam of 1 mm or 1 km, loads of 1e-300 or
//!   1e300 and stiffness contrasts of 1e16 run the same arithmetic on numbers near 1.
//! - *No sum along the beam.* Each equation involves one piece only, so no rounding is carried
//!   from one end of the beam to the other (single shooting's failure, issue 10 items 1–2).
//! - *No stiffness of a short piece.* A piece 1e-9·l long is an almost-identity transfer whose
//!   flexibility (t u', t² m/2EJ, t³ m'/6EJ) is an entry of its own rows, not a stiffness of
//!   1e27 added to one of 1 (which loses the rigid motion between two sliding obstacles).
//!   Because known zeros are substituted, row equilibration sees the rows of a short piece
//!   between stuck DOFs at their own scale (with a column and a row per stuck DOF, 69 of 2000
//!   hard scenes were singular to working precision).
//! - *Forces are unknowns.* The force of a stuck DOF is solved for, not a difference of large
//!   displacements times large stiffnesses; the friction search never multiplies a stiffness
//!   by a displacement either (below).
//! - *Each value to its own size.* Iterative refinement with the residual in double-double
//!   gives every component to a few ulps of itself where the system allows, so a motion of
//!   7e-17 m next to a support is resolved where max |u| is 2e-2 m.
//!
//! **Friction.** (38) is min ½cᵀAc − bᵀc + Σ g_i|c_i|; each friction DOF is stuck (c_i = 0,
//! |λ_i| ≤ g_i) or moves (λ_i = g_i·sign c_i). Given the pattern of states, one banded solve
//! gives c and the stuck λ. The search starts from the pattern of an interior-point method
//! (`interior`: Mehrotra's predictor–corrector, each step one solve of the same banded
//! system with a mixed condition c − m = D(λ − λ₀) at every friction DOF, `mixed`), which
//! takes 11–23 steps whatever k and the arrangement, where the search alone needed up to 1948
//! pattern solves at k = 4000 (issue 26); on random, clustered and mixed arrangements the
//! guess is consistent, or two DOFs off, and one or three pattern solves finish (where the
//! search runs past 64 solves, the iteration runs again with its steps refined in
//! double-double, `mixed_refinement`, and a short search tries its guess). From there
//! the pattern is found by semismooth Newton (the primal–dual active set method): every inconsistent DOF changes at once — a stuck force above its threshold
//! starts to move its way, a moving DOF that reverses is held (or, by the prediction λ + σc
//! with σ a fraction of its diagonal stiffness, sent to the other bound). Two variants of σ
//! are tried in turn, each abandoned on a repeated pattern or when it stops improving (a step
//! that only frees stuck DOFs counts as improving, and where such steps free a stretch from
//! its ends, each end goes on twice as far each step: `fronts`); then a
//! monotone search takes over that can neither cycle nor stall: an exact line search on the
//! convex, piecewise quadratic J between the current point and the optimum of the next
//! pattern, adding stuck DOFs only at the optimum of a pattern, and only the worst one when
//! adding all of them gives no descent (feature-sign search). The line search works on the
//! friction DOFs' motions c and forces r = b − Kc, both linear in the point and known
//! accurately at every solve, so its slope −rᵀd and curvature dᵀ(r(c) − r(target)) never
//! multiply a stiffness by a displacement. The answer is the refined solve of the final
//! pattern, so it satisfies (38) up to the rounding of that one solve. A caller that solved a
//! nearby scene can start from its final pattern ([`solve_condensed_from`], a warm start):
//! where its first solve leaves at most 16 DOFs inconsistent, the monotone search goes on
//! from there for at most 16 solves, else the search starts over as without it; one notch of
//! one threshold at k = 4000 then costs one pattern solve in clusters and 3–8 on random
//! scenes (`cargo bench --bench many_obstacles -- warm`).
//!
//! **Decisions.** A decision is made only where the number is computed accurately: the motion
//! at the DOF itself and the force at the DOF itself. Each pattern is first solved by
//! elimination alone; a decision within 1e-6 of the largest value of its kind waits: Newton
//! changes the other DOFs first, and when only such decisions are left (or the pattern looks
//! consistent), the same factors are refined — while such decisions remain, only until each
//! is settled beyond four times its last correction; the pattern that looks final is refined
//! to the last bits and decided again — and the decision is taken on the refined values;
//! the monotone search refines every step with an uncertain decision until each is settled
//! and the largest correction is the noise of the residual. The refinement's residual is
//! that of the exact piece relations in double-double (`linalg::double_double`), so the
//! refined values are those of the exact discrete problem, and the force is compared with its
//! threshold in double-double. When the refined |motion|, or |force| − threshold, is within
//! the refinement's own error estimate (its last correction) or 2⁻⁹⁸ of the values around the
//! DOF, the DOF is reported [`FrictionState::AtThreshold`] rather than a coin toss
//! ([`CondensedSolution::states`]). Where refinement with the f64 factors diverges (their
//! matrix is too far from the exact relations: obstacles a few 1e-9·l from a clamp next to
//! long pieces), the exact relations themselves are factored in double-double
//! (`linalg::banded_lu_dd`) and refinement goes on with those factors.
//!
//! **Nodes.** Every node inside a piece is evaluated from that piece's end values (Hermite
//! cubic) plus the piece's exact clamped–clamped response to its linear load: O(n) in total,
//! and the error does not grow with n.
//!
//! **Layout.** `scaling` (the power-of-two units and one piece's exact transfer), `system` (the
//! banded system of a pattern and its solve), `mixed`, `mixed_refinement`, `held_bounds` and
//! `interior` (the interior-point guess), `refinement` (double-double refinement and the
//! exact matrix), `decisions` (what a solve says about each DOF), `line_search` (the monotone
//! search's line search), `monotone` (its steps and next patterns), `search` (the Newton
//! phases, then the monotone search), `fronts` (how far a
//! Newton step that frees a stretch from its ends goes on), `nodes` (every node
//! from its piece).

use super::history::{ProgressMeasure, Recorder};
use super::options::SolveOptions;
use super::shared::{MethodOutput, Stopwatch, cancelled};
use super::solution::{
    FrictionState, MethodDetails, SolveError, SolveErrorKind, Timing, Warning, WarningCode,
};
use crate::fem::{Mesh, NodalField};
use crate::model::{Method, Problem};
pub use pattern::FrictionPattern;
use search::{NEWTON_REVERSAL_FRACTIONS, solve_with_newton_phases};
pub(crate) use structure::shooting_matrix;

/// The result of the condensed method, in SI units.
#[derive(Debug, Clone, PartialEq)]
pub struct CondensedSolution {
    /// u and u' at every mesh node.
    pub field: NodalField,
    /// (force [N], moment [N m]) per obstacle, in the convention A c = b − Bᵀλ.
    pub friction: Vec<[f64; 2]>,
    /// (sliding, swivel) state per obstacle.
    pub states: Vec<[FrictionState; 2]>,
    /// Linear solves (one per active-set step).
    pub solves: usize,
    /// What the search cost, step by step.
    pub counts: SolveCounts,
    /// The final friction pattern, for [`solve_condensed_from`] after a small change.
    pub pattern: FrictionPattern,
    /// Did the active-set iteration end with a consistent pattern?
    pub converged: bool,
}

/// The work of one condensed solve: pattern solves (each one banded factorisation),
/// banded solves with existing factors (refinement steps and the like) and refinements in
/// double-double.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SolveCounts {
    /// Patterns solved (a banded factorisation and solve each).
    pub pattern_solves: usize,
    /// Banded factorisations of any kind (pattern solves and the interior-point steps).
    pub factorizations: usize,
    /// Solves with factors already made (refinement steps, predictor–corrector pairs).
    pub back_solves: usize,
    /// Solves refined with the exact relations in double-double.
    pub refinements: usize,
    /// Refinements that went on with the exact relations factored in double-double, where
    /// refinement with the f64 factors diverged (each also one of `factorizations`).
    pub double_double_factorizations: usize,
    /// Steps of the interior-point guess (a factorisation and two solves each).
    pub interior_steps: usize,
}

/// Why the condensed method has no solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CondensedFailure {
    /// The banded system was singular to working precision in this column.
    Singular { column: usize },
    /// The caller's `keep_going` said stop (a newer request replaced this solve).
    Stopped,
}

mod answer;
mod centrality;
mod decisions;
mod fronts;
mod held_bounds;
mod interior;
mod line_search;
mod mixed;
mod mixed_refinement;
mod monotone;
mod newton_phases;
mod nodes;
mod offers;
pub(in crate::solve) mod pattern;
mod projected;
mod refinement;
mod scaling;
mod search;
mod structure;
mod system;
#[cfg(test)]
mod tests;

/// Solves (38) by the condensed method; see the module documentation.
pub fn solve_condensed(
    problem: &Problem,
    mesh: &Mesh,
) -> Result<CondensedSolution, CondensedFailure> {
    solve_condensed_while(problem, mesh, &mut || true)
}

/// [`solve_condensed`], asking `keep_going` before every linear solve (O(n + k) work each)
/// and stopping with [`CondensedFailure::Stopped`] when it says no.
pub fn solve_condensed_while(
    problem: &Problem,
    mesh: &Mesh,
    keep_going: &mut dyn FnMut() -> bool,
) -> Result<CondensedSolution, CondensedFailure> {
    solve_with_newton_phases(
        problem,
        mesh,
        &NEWTON_REVERSAL_FRACTIONS,
        keep_going,
        None,
        None,
    )
}

/// [`solve_condensed_while`] from the friction pattern of an earlier solve (a warm start, for
/// the explorer's re-solve after a small change: the search starts there instead of from the
/// interior-point guess). A pattern for another number of obstacles is ignored.
pub fn solve_condensed_from(
    problem: &Problem,
    mesh: &Mesh,
    start: &FrictionPattern,
    keep_going: &mut dyn FnMut() -> bool,
) -> Result<CondensedSolution, CondensedFailure> {
    solve_with_newton_phases(
        problem,
        mesh,
        &NEWTON_REVERSAL_FRACTIONS,
        keep_going,
        None,
        Some(start),
    )
}

/// `solve` entry point: the condensed solution as the common [`MethodOutput`].
pub(super) fn solve(
    problem: &Problem,
    mesh: &Mesh,
    options: &SolveOptions,
) -> Result<MethodOutput, SolveError> {
    let mut timing = Timing::default();
    let mut clock = Stopwatch::start();
    let mut keep_going = || !options.cancel.is_cancelled();
    let mut recorder = Recorder::when(
        options.history,
        Method::Condensed,
        ProgressMeasure::KktResidual,
    );
    // The iterations panel shows the search from its own start, whatever came before.
    let start = options.warm_start.pattern().filter(|_| recorder.is_none());
    let solution = solve_with_newton_phases(
        problem,
        mesh,
        &NEWTON_REVERSAL_FRACTIONS,
        &mut keep_going,
        recorder.as_mut(),
        start,
    )
    .map_err(|failure| match failure {
        CondensedFailure::Singular { column } => SolveError {
            method: Method::Condensed,
            kind: SolveErrorKind::Breakdown,
            reason: format!(
                "the multiple-shooting system is singular to working precision (column \
                     {column})"
            ),
            suggestion: Method::Flexibility,
        },
        CondensedFailure::Stopped => cancelled(Method::Condensed),
    })?;
    timing.friction_stage = clock.lap();
    let mut warnings = Vec::new();
    if !solution.converged {
        warnings.push(Warning::new(
            WarningCode::QpNotConverged,
            format!(
                "the active-set iteration stopped after {} solves with an inconsistent \
                 friction state",
                solution.solves
            ),
        ));
    }
    Ok(MethodOutput {
        field: solution.field,
        lambda: solution.friction,
        states: Some(solution.states),
        timing,
        warnings,
        details: MethodDetails {
            linear_solves: Some(solution.solves),
            ..MethodDetails::default()
        },
        dual_condition: None,
        regularized_cases: Vec::new(),
        friction_accuracy: None,
        history: recorder.map(Recorder::finish),
        friction_pattern: Some(std::sync::Arc::new(solution.pattern)),
    })
}
