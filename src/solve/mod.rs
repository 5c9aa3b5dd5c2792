//! The methods of docs/design.md section 3, one module each, and the [`Solution`] they all
//! return.
//!
//! [`solve`] runs a method and then certifies its answer the same way for every method
//! (`certificate`). The layout: `options` (how to solve), `solution` (what comes back),
//! `certificate` (the common checks), `shared` (what the method modules share); the method
//! modules depend on those, never on this dispatcher.

mod certificate;
mod closed_form;
mod condensed;
mod dual;
mod dual_inverse;
mod equilibrium;
mod flexibility;
mod options;
mod regularized;
mod regularized_newton;
mod shared;
mod solution;
mod stiffness_route;

use crate::fem::Mesh;
use crate::model::Problem;

pub use crate::model::Method;
pub use certificate::{compare, reference_field};
pub use closed_form::{ClosedForm, closed_form};
pub use condensed::{
    CondensedFailure, CondensedSolution, FrictionState, solve_condensed, solve_condensed_while,
};
pub use options::{Cancellation, ConditionLevel, MAX_CASES, MAX_DENSE_UNKNOWNS, SolveOptions};
pub use solution::{
    Conditioning, ErrorReport, MethodDetails, ObstacleResult, Reference, Solution, SolveError,
    SolveErrorKind, Timing, Warning, WarningCode,
};

/// Solves with `method`, then certifies the answer (KKT residual, friction states, optional
/// condition numbers and reference error, warnings).
pub fn solve(
    problem: &Problem,
    mesh: &Mesh,
    method: Method,
    options: &SolveOptions,
) -> Result<Solution, SolveError> {
    shared::check_cancel(options, method)?;
    let output = match method {
        Method::Regularized => regularized::solve(problem, mesh, options)?,
        Method::RegularizedNewton => regularized_newton::solve(problem, mesh, options)?,
        Method::DualInverse => dual_inverse::solve(problem, mesh, options)?,
        Method::Dual => dual::solve(problem, mesh, options)?,
        Method::Flexibility => flexibility::solve(problem, mesh, options)?,
        Method::ClosedForm => closed_form::solve(problem, mesh)?,
        Method::Condensed => condensed::solve(problem, mesh, options)?,
    };
    shared::check_cancel(options, method)?;
    let solution = certificate::certify(problem, mesh, method, options, output);
    // The certificate's own reference solve may have been cut short.
    shared::check_cancel(options, method)?;
    Ok(solution)
}
