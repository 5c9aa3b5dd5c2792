//! `dual`: the dual problem (49) of paper 2.7.2 without the explicit inverse. One factorization
//! of A with the friction nodes last gives K = S⁻¹ and b̃; S = K⁻¹ and z0 = K⁻¹ b̃ are 2k×2k and
//! 2k; the box QP min ½λᵀSλ − z0ᵀλ, |λ| ≤ g is solved exactly (active set) or by MPRGP for
//! large 2k; the primal solution follows from c_F = z0 − Sλ and one back substitution (48).
//! O(n) work and memory.

use super::options::SolveOptions;
use super::shared::{MethodOutput, Stopwatch, check_cancel, dual_box_qp, dual_output};
use super::solution::{SolveError, Timing};
use super::stiffness_route::{assemble_and_factor, indefinite_warning};
use crate::fem::Mesh;
use crate::linalg::dense::mat_vec;
use crate::model::{Method, Problem};

pub(super) fn solve(
    problem: &Problem,
    mesh: &Mesh,
    options: &SolveOptions,
) -> Result<MethodOutput, SolveError> {
    super::shared::refuse_many_obstacles(problem, Method::Dual)?;
    let mut timing = Timing::default();
    let factored = assemble_and_factor(problem, mesh, (Method::Dual, options), &mut timing)?;
    let stiffness_indefinite_warning = indefinite_warning(&factored, mesh);
    let mut clock = Stopwatch::start();
    let (s, z0, indefinite_k) = factored.dual_matrices(Method::Dual, mesh, options)?;
    timing.factorization += clock.lap();

    let g = problem.thresholds();
    let (qp, history) = dual_box_qp((&s, &z0, &g), Method::Dual, options);
    check_cancel(options, Method::Dual)?;
    let lambda = &qp.x;
    timing.friction_stage = clock.lap();

    // c_F = B A⁻¹ (b − Bᵀλ) = z0 − S λ.
    let s_lambda = mat_vec(&s, lambda);
    let friction_values: Vec<f64> = z0.iter().zip(&s_lambda).map(|(z, sl)| z - sl).collect();
    let field = factored.reconstruct(&friction_values, (Method::Dual, options))?;
    timing.reconstruction = clock.lap();

    let warnings = stiffness_indefinite_warning
        .into_iter()
        .chain(indefinite_k)
        .collect();
    Ok(MethodOutput {
        history,
        ..dual_output(field, (&qp, &s, &z0), None, (timing, warnings), options)
    })
}
