//! Building the certificate of a solution (the module `certificate`): the independent check
//! of (38) and the friction states (`equilibrium`), the condition numbers of A and of the
//! regularised case matrices when asked, the error against the reference and the warnings.

use super::equilibrium::{self, Equilibrium, Judging};
use super::reference::{MeshReference, reference_error};
use super::warnings::{
    accuracy_warning, conditioning_warning, force_warning, kkt_warning, mesh_raised_warning,
    non_finite_warning, unresolved_force_warning, untrusted_reference_warning,
};
use crate::fem::{Mesh, NodalField, StiffnessMatrix, stiffness_condition_bounds_until};
use crate::linalg::condition::{
    ConditionKind, ConditionNumber, DENSE_LIMIT, block_condition_until, jacobi_scaled,
};
use crate::linalg::{BlockMatrix, BlockTridiagonal};
use crate::model::{Method, Problem};
use crate::solve::options::{ConditionLevel, SolveOptions};
use crate::solve::shared::MethodOutput;
use crate::solve::solution::{Conditioning, FrictionState, ObstacleResult, Solution, Warning};

/// Certifies a method's `output`. `reference` grades it (and names the alternative of a
/// non-finite answer); `None` only for the condensed reference's own certificate, which asks
/// for no reference (method `condensed`, `options.reference` off). `None` when the solve was
/// cancelled: asked between the stages and inside the long ones (each O(n)).
pub(in crate::solve) fn certify(
    problem: &Problem,
    mesh: &Mesh,
    method: Method,
    options: &SolveOptions,
    output: MethodOutput,
    reference: Option<&MeshReference>,
) -> Option<Solution> {
    let stop = || options.cancel.is_cancelled();
    let still_wanted = || (!stop()).then_some(());
    let MethodOutput {
        field,
        lambda,
        states: method_states,
        timing,
        mut warnings,
        mut details,
        dual_condition,
        regularized_cases,
        friction_accuracy,
        history,
        friction_pattern,
    } = output;
    if let Some(w) = mesh_raised_warning(mesh) {
        warnings.insert(0, w);
    }
    if method.is_regularized() && options.condition != ConditionLevel::Off {
        details.conditioned_cases = Some(regularized_cases.len());
    }
    let mut conditioning = Conditioning {
        dual: dual_condition,
        ..Conditioning::default()
    };
    // The Jacobi-scaled cond(A) the stiffness route's rounding follows (None: not known).
    let mut stiffness_scaled = None;
    if method.uses_stiffness_matrix() {
        (conditioning, stiffness_scaled) = stiffness_conditioning_checked(
            mesh,
            options,
            &regularized_cases,
            conditioning,
            &mut warnings,
        )?;
        still_wanted()?;
    }
    // A method's own account of its friction stage: a dual method's with the rounding of its
    // S and z0, a regularised one's of what ε does.
    let own_errors = friction_accuracy
        .map(|a| a.with_rounding(friction_data_rounding(problem, method, stiffness_scaled)));
    let judging = Judging {
        motion_resolution: motion_resolution(problem, method, stiffness_scaled),
        epsilon: method.is_regularized().then_some(options.epsilon),
        own_errors: own_errors.as_ref(),
    };
    let Equilibrium {
        residual: kkt_residual,
        mut states,
        unresolved_force,
    } = equilibrium::check(problem, mesh, (&field, &lambda), judging, &stop)?;
    if let Some(method_states) = method_states {
        refine_states(&mut states, &method_states);
    }
    let obstacles = obstacle_results(problem, mesh, &field, &lambda, &states);
    if let Some(w) = kkt_warning(kkt_residual, method) {
        warnings.push(w);
    }
    if let Some(w) = judging
        .epsilon
        .and_then(|epsilon| unresolved_force_warning(epsilon, unresolved_force))
    {
        warnings.push(w);
    }
    let mut solution = Solution {
        method,
        epsilon: method.is_regularized().then_some(options.epsilon),
        field,
        obstacles,
        kkt_residual,
        timing,
        conditioning,
        error: None,
        warnings,
        details,
        history,
        friction_pattern,
    };
    debug_assert!(
        reference.is_some() || (method == Method::Condensed && !options.reference),
        "only the condensed reference's own certificate goes without a reference"
    );
    judge_solution(problem, options, &mut solution, reference)?;
    Some(solution)
}

/// The condensed method's certified solution on the mesh of `reference`, trusted or not,
/// without a reference of its own (it is the reference): the solve already made if there was
/// one. `None` when it failed or was cancelled.
pub(in crate::solve) fn certified_condensed(reference: MeshReference) -> Option<Solution> {
    let (problem, mesh) = (reference.problem(), reference.mesh());
    let (output, options) = reference.into_condensed_output()?;
    let solution = certify(problem, mesh, Method::Condensed, &options, output, None)?;
    // As any solve: a result no longer wanted is none.
    (!options.cancel.is_cancelled()).then_some(solution)
}

/// Where the independent check finds a DOF at the threshold within rounding (the returned
/// values fit both descriptions), the method's own finer decision.
fn refine_states(states: &mut [[FrictionState; 2]], method_states: &[[FrictionState; 2]]) {
    for (checked, own) in states
        .iter_mut()
        .flatten()
        .zip(method_states.iter().flatten())
    {
        if *checked == FrictionState::AtThreshold {
            *checked = *own;
        }
    }
}

/// The checks on the assembled solution: the non-finite warning first, then the error
/// against the reference and the accuracy warning.
fn judge_solution(
    problem: &Problem,
    options: &SolveOptions,
    solution: &mut Solution,
    reference: Option<&MeshReference>,
) -> Option<()> {
    let still_wanted = || (!options.cancel.is_cancelled()).then_some(());
    if !solution.is_finite() || !solution.kkt_residual.is_finite() {
        // Name a method that works only when it does: the condensed method certified itself.
        let condensed_works =
            solution.method != Method::Condensed && reference.is_some_and(|r| r.field().is_some());
        // First: it is what matters most about this solution.
        solution
            .warnings
            .insert(0, non_finite_warning(condensed_works));
    }
    still_wanted()?;
    if let (true, Some(reference)) = (options.reference, reference) {
        solution.error = reference_error(problem, solution, reference);
        still_wanted()?;
        if solution.error.is_none() {
            solution.warnings.push(untrusted_reference_warning());
        }
        if let Some(w) = accuracy_warning(solution, problem) {
            solution.warnings.push(w);
        }
        if let Some(w) = force_warning(solution, problem, reference) {
            solution.warnings.push(w);
        }
    }
    Some(())
}

/// The result at every obstacle: position, nodal values, friction forces and state.
fn obstacle_results(
    problem: &Problem,
    mesh: &Mesh,
    field: &NodalField,
    lambda: &[[f64; 2]],
    states: &[[FrictionState; 2]],
) -> Vec<ObstacleResult> {
    problem
        .obstacles
        .iter()
        .zip(&mesh.obstacle_nodes)
        .zip(lambda.iter().zip(states))
        .map(|((o, &node), (l, s))| ObstacleResult {
            x: o.x,
            u: field.deflection[node],
            slope: field.slope[node],
            force: l[0],
            moment: l[1],
            sliding_state: s[0],
            swivel_state: s[1],
            sliding: s[0] != FrictionState::Stuck,
            swivel: s[1] != FrictionState::Stuck,
        })
        .collect()
}

/// For a method that works through A: its condition numbers (when asked for, else only the
/// dual one already in `conditioning`), and the warning when A's conditioning — the better of
/// the computed number and the cheap bound — predicts a visible loss of digits.
/// `None` when the solve was cancelled.
fn stiffness_conditioning_checked(
    mesh: &Mesh,
    options: &SolveOptions,
    regularized_cases: &[Vec<(usize, f64)>],
    mut conditioning: Conditioning,
    warnings: &mut Vec<Warning>,
) -> Option<(Conditioning, Option<ConditionNumber>)> {
    let stop = || options.cancel.is_cancelled();
    let (bound, scaled_bound) = stiffness_condition_bounds_until(mesh, &stop).ok()?;
    if options.condition != ConditionLevel::Off {
        let computed = stiffness_conditioning(mesh, options, regularized_cases);
        conditioning.stiffness = larger(computed.stiffness, bound);
        conditioning.stiffness_scaled = larger(computed.stiffness_scaled, scaled_bound);
        conditioning.regularized_max = computed.regularized_max;
        conditioning.regularized_scaled_max = computed.regularized_scaled_max;
    }
    let scaled = larger(conditioning.stiffness_scaled, scaled_bound);
    if let Some(w) = scaled.and_then(|scaled| conditioning_warning(scaled, mesh)) {
        warnings.push(w);
    }
    Some((conditioning, scaled))
}

/// The better of a computed condition number and a rigorous lower bound: an exact number
/// wins; an estimate or a bound below the lower bound gives way to it.
fn larger(
    computed: Option<ConditionNumber>,
    bound: Option<ConditionNumber>,
) -> Option<ConditionNumber> {
    match (computed, bound) {
        (Some(c), _) if c.kind == ConditionKind::Exact => Some(c),
        (Some(c), Some(b)) => Some(if b.value > c.value { b } else { c }),
        (c, b) => c.or(b),
    }
}

/// The method's own rounding of the friction DOFs' values, relative to the largest value of
/// their kind: below it a motion is not resolved (see `equilibrium`). The condensed method and
/// the closed form resolve to a few ulps of the local values (0 here); the box QP of the dual
/// methods stops within 64·2k ulps of its gradient; the stiffness route loses about
/// 0.02·cond(D^-1/2 A D^-1/2)·eps (docs/design.md fact 2; 0.1 for margin), single shooting
/// about 1e-14 on ordinary scenes (1e-12 for margin). The dual methods' states use it only when
/// they have no account of their own (`friction_accuracy`; their QP's free block was not
/// positive definite); the regularised methods' forces inside ε always.
fn motion_resolution(
    problem: &Problem,
    method: Method,
    stiffness_scaled: Option<ConditionNumber>,
) -> f64 {
    let qp = 128.0 * problem.obstacles.len() as f64 * f64::EPSILON;
    match method {
        Method::Condensed | Method::ClosedForm => 0.0,
        Method::Flexibility => qp.max(1e-12),
        Method::Dual | Method::DualInverse | Method::Regularized | Method::RegularizedNewton => {
            // Unknown conditioning: nothing below one ulp of cond·eps = 1 is resolved.
            let scaled = stiffness_scaled.map_or(1.0 / f64::EPSILON, |c| c.value);
            qp.max(1e-12).max(0.1 * scaled * f64::EPSILON)
        }
    }
}

/// The relative rounding of every entry of S and z0 that a dual method's box QP decided from
/// (`friction_accuracy` turns it into errors of the motions and stuck forces): the QP's
/// stopping tolerance, 64·2k ulps of the terms of its gradient (`linalg::boxqp`); on the
/// stiffness route also the loss of the factorization of A, 0.1·cond(D^-1/2 A D^-1/2)·eps as
/// in [`motion_resolution`]. `flexibility` measures its own single-shooting loss on top.
pub(crate) fn friction_data_rounding(
    problem: &Problem,
    method: Method,
    stiffness_scaled: Option<ConditionNumber>,
) -> f64 {
    let qp = 128.0 * problem.obstacles.len() as f64 * f64::EPSILON;
    match method {
        Method::Dual | Method::DualInverse => {
            let scaled = stiffness_scaled.map_or(1.0 / f64::EPSILON, |c| c.value);
            qp.max(0.1 * scaled * f64::EPSILON)
        }
        Method::Flexibility => qp,
        _ => 0.0,
    }
}

/// Condition numbers of A, its Jacobi scaling, and the regularised case matrices.
fn stiffness_conditioning(
    mesh: &Mesh,
    options: &SolveOptions,
    cases: &[Vec<(usize, f64)>],
) -> Conditioning {
    let exact_possible = mesh.unknowns() <= DENSE_LIMIT;
    if !exact_possible && options.condition != ConditionLevel::Full {
        return Conditioning::default();
    }
    // A cancelled solve stops here with what it has; `solve` answers it with the cancelled
    // error right after the certificate.
    let stop = || options.cancel.is_cancelled();
    let condition = |a: &BlockTridiagonal| block_condition_until(a, &stop).unwrap_or(None);
    let matrix = StiffnessMatrix::new(mesh).to_block_tridiagonal();
    let mut result = Conditioning {
        stiffness: condition(&matrix),
        stiffness_scaled: condition(&jacobi_scaled(&matrix)),
        ..Conditioning::default()
    };
    let max = |a: Option<ConditionNumber>, b: Option<ConditionNumber>| match (a, b) {
        (Some(a), Some(b)) => Some(if b.value > a.value { b } else { a }),
        (a, b) => a.or(b),
    };
    for case in cases {
        if stop() {
            break;
        }
        let mut modified = matrix.clone();
        for &(dof, add) in case {
            let block = mesh.obstacle_nodes[dof / 2] - 1;
            modified.diag[block][if dof % 2 == 0 { 0 } else { 2 }] += add;
        }
        result.regularized_max = max(result.regularized_max, condition(&modified));
        result.regularized_scaled_max = max(
            result.regularized_scaled_max,
            condition(&jacobi_scaled(&modified)),
        );
    }
    result
}
