//! The methods of docs/design.md section 3, one module each, and the [`Solution`] they all
//! return.
//!
//! [`solve`] runs a method and then certifies its answer the same way for every method
//! (`certificate`); [`solve_with_condensed`] also hands back the `condensed` solution on the
//! same mesh, from the same solve the certificate graded with; [`grade`] certifies an answer
//! computed elsewhere (`given_answer`, `beamfric grade`). The layout: `options` (how to
//! solve), `solution` (what comes back), `history` (the convergence history recorded when
//! asked), `certificate` (the common checks), `shared` (what the
//! method modules share), `stiffness_route` (the factorization of A that `dual` and the
//! regularised methods share); the method modules depend on those, never on this dispatcher.

mod certificate;
mod closed_form;
mod condensed;
mod dual;
mod dual_inverse;
mod flexibility;
mod friction_accuracy;
mod given_answer;
mod history;
mod options;
mod regularized;
mod regularized_newton;
mod shared;
mod solution;
mod stiffness_route;

use crate::fem::Mesh;
use crate::model::Problem;
use certificate::MeshReference;

pub use crate::model::Method;
pub use closed_form::{ClosedForm, closed_form};
pub use condensed::{
    CondensedFailure, CondensedSolution, FrictionPattern, SolveCounts, solve_condensed,
    solve_condensed_from, solve_condensed_while,
};
pub use given_answer::{GivenAnswer, GradeError, grade};
pub use history::{
    History, IterationRecord, MAX_RECORDED_ITERATIONS, ProgressMeasure, iterate_field,
};
pub use options::{
    Cancellation, ConditionLevel, MAX_CASES, MAX_DENSE_UNKNOWNS, SolveOptions, WarmStart,
};
/// What the studies (`crate::study`) read of the methods' insides: the regularised method's
/// cases, the condensed method's system, a dual method's account of its accuracy.
pub(crate) mod internals {
    pub(crate) use super::certificate::{FORCE_ULPS, MOTION_ULPS, friction_data_rounding};
    pub(crate) use super::condensed::shooting_matrix;
    pub(crate) use super::friction_accuracy::{FrictionErrors, friction_accuracy};
    pub(crate) use super::regularized::{
        EpsilonRegion, case_count, case_regions, case_violation, conditions_every_case,
        middle_additions, solve_case,
    };
}
pub use solution::{
    Conditioning, ErrorReport, FrictionState, KktGrade, MethodDetails, ObstacleResult, Reference,
    Solution, SolveError, SolveErrorKind, Timing, Warning, WarningCode,
};

/// Solves with `method`, then certifies the answer (KKT residual, friction states, optional
/// condition numbers and reference error, warnings). A method that refuses or fails names a
/// method that works on this scene: its own suggestion when that one, tried, gives a finite
/// answer without warnings (see [`works`]), else `condensed`.
pub fn solve(
    problem: &Problem,
    mesh: &Mesh,
    method: Method,
    options: &SolveOptions,
) -> Result<Solution, SolveError> {
    let reference = MeshReference::new(problem, mesh, options);
    solve_graded(problem, mesh, method, options, &reference)
}

/// [`solve`], and the `condensed` method's solution on the same mesh (certified, without a
/// reference of its own: it is the reference) when `method` is another one — what the
/// explorer draws under the answer. The condensed method is solved at most once for both: the
/// certificate grades with that same solve when the closed form does not apply. The second is
/// `None` when `method` is `condensed` (nothing more is solved) or the condensed method failed.
pub fn solve_with_condensed(
    problem: &Problem,
    mesh: &Mesh,
    method: Method,
    options: &SolveOptions,
) -> (Result<Solution, SolveError>, Option<Solution>) {
    let reference = MeshReference::new(problem, mesh, options);
    let solution = solve_graded(problem, mesh, method, options, &reference);
    let condensed = (method != Method::Condensed)
        .then(|| certificate::certified_condensed(reference))
        .flatten();
    (solution, condensed)
}

/// [`solve`] with the reference of the mesh shared with the caller.
fn solve_graded(
    problem: &Problem,
    mesh: &Mesh,
    method: Method,
    options: &SolveOptions,
    reference: &MeshReference,
) -> Result<Solution, SolveError> {
    certified(problem, mesh, method, options, reference).map_err(|mut error| {
        if error.kind != SolveErrorKind::Cancelled
            && error.suggestion != Method::Condensed
            && !works(problem, mesh, error.suggestion, options, reference)
        {
            error.suggestion = Method::Condensed;
        }
        error
    })
}

/// Does `method` give a finite answer here without warnings — other than a raised mesh and,
/// for a regularised method, the distance to the exact solution that ε itself causes?
fn works(
    problem: &Problem,
    mesh: &Mesh,
    method: Method,
    options: &SolveOptions,
    reference: &MeshReference,
) -> bool {
    let quick = SolveOptions {
        condition: ConditionLevel::Off,
        history: false,
        ..options.clone()
    };
    certified(problem, mesh, method, &quick, reference).is_ok_and(|s| {
        s.is_finite()
            && s.warnings.iter().all(|w| {
                w.code == WarningCode::MeshRaised
                    || (method.is_regularized() && w.code == WarningCode::AccuracyLoss)
            })
    })
}

/// [`solve`] without checking the suggestion of a failure.
fn certified(
    problem: &Problem,
    mesh: &Mesh,
    method: Method,
    options: &SolveOptions,
    reference: &MeshReference,
) -> Result<Solution, SolveError> {
    shared::check_cancel(options, method)?;
    let output = match method {
        Method::Regularized => regularized::solve(problem, mesh, options)?,
        Method::RegularizedNewton => regularized_newton::solve(problem, mesh, options)?,
        Method::DualInverse => dual_inverse::solve(problem, mesh, options)?,
        Method::Dual => dual::solve(problem, mesh, options)?,
        Method::Flexibility => flexibility::solve(problem, mesh, options)?,
        Method::ClosedForm => closed_form::solve(problem, mesh, options)?,
        Method::Condensed => condensed::solve(problem, mesh, options)?,
    };
    shared::check_cancel(options, method)?;
    let solution = certificate::certify(problem, mesh, method, options, output, Some(reference));
    // The certificate (or its own reference solve) may have been cut short.
    shared::check_cancel(options, method)?;
    solution.ok_or_else(|| shared::cancelled(method))
}
