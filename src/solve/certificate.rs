//! The certificate [`solve`](super::solve) attaches to every method's answer, the same way for
//! every method: the relative KKT residual of (38), the friction state of every obstacle,
//! condition numbers when asked, the error against a reference (the closed form (50) where it
//! applies, else the `condensed` method on the same mesh) and warnings in words.

use super::closed_form::closed_form;
use super::condensed;
use super::options::{Cancellation, ConditionLevel, SolveOptions};
use super::shared::MethodOutput;
use super::solution::{
    Conditioning, ErrorReport, ObstacleResult, Reference, Solution, Warning, WarningCode,
};
use crate::fem::{Mesh, NodalField, StiffnessMatrix, kkt_stationarity, stiffness_condition_bounds};
use crate::linalg::BlockMatrix;
use crate::linalg::condition::{ConditionNumber, DENSE_LIMIT, block_condition, jacobi_scaled};
use crate::model::{Method, Problem};

pub(super) fn certify(
    problem: &Problem,
    mesh: &Mesh,
    method: Method,
    options: &SolveOptions,
    output: MethodOutput,
) -> Solution {
    let MethodOutput {
        field,
        lambda,
        moving,
        timing,
        mut warnings,
        mut details,
        dual_condition,
        regularized_cases,
    } = output;
    let obstacles = obstacle_results(problem, mesh, &field, &lambda, &moving);
    let kkt_residual = kkt_residual(problem, mesh, &field, &lambda, &obstacles);
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
    if method.uses_stiffness_matrix() {
        conditioning = stiffness_conditioning_checked(
            mesh,
            options,
            &regularized_cases,
            conditioning,
            &mut warnings,
        );
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
    };
    judge_solution(problem, mesh, options, &mut solution);
    solution
}

/// The checks on the assembled solution: the non-finite warning first, then the error
/// against the reference and the accuracy warning.
fn judge_solution(problem: &Problem, mesh: &Mesh, options: &SolveOptions, solution: &mut Solution) {
    if !solution.is_finite() || !solution.kkt_residual.is_finite() {
        // First: it is what matters most about this solution.
        solution.warnings.insert(
            0,
            Warning::new(
                WarningCode::NonFinite,
                "the solution contains NaN or infinite values: an input is out of \
             floating-point range for this method; no number is shown",
            ),
        );
    }
    if options.reference {
        solution.error = reference_error(problem, mesh, solution, options.cancel);
        if solution.error.is_none() && !options.cancel.is_cancelled() {
            solution.warnings.push(Warning::new(
                WarningCode::UntrustedReference,
                "no trusted reference: the condensed method did not certify itself on this \
                 scene (its friction search did not converge), so no error is reported",
            ));
        }
        if let Some(w) = accuracy_warning(solution) {
            solution.warnings.push(w);
        }
    }
}

/// The result at every obstacle: position, nodal values, friction forces and state.
fn obstacle_results(
    problem: &Problem,
    mesh: &Mesh,
    field: &NodalField,
    lambda: &[[f64; 2]],
    moving: &[[bool; 2]],
) -> Vec<ObstacleResult> {
    problem
        .obstacles
        .iter()
        .zip(&mesh.obstacle_nodes)
        .zip(lambda.iter().zip(moving))
        .map(|((o, &node), (l, m))| ObstacleResult {
            x: o.x,
            u: field.deflection[node],
            slope: field.slope[node],
            force: l[0],
            moment: l[1],
            sliding: m[0],
            swivel: m[1],
        })
        .collect()
}

/// The mesh has more elements than asked for.
fn mesh_raised_warning(mesh: &Mesh) -> Option<Warning> {
    (mesh.elements() > mesh.requested_elements).then(|| {
        Warning::new(
            WarningCode::MeshRaised,
            format!(
                "{} elements asked for, {} used: every stretch between obstacles, \
                 supports and segment ends needs one",
                mesh.requested_elements,
                mesh.elements()
            ),
        )
    })
}

/// For a method that works through A: its condition numbers (when asked for, else only the
/// dual one already in `conditioning`), and the warning when A's conditioning — the better of
/// the computed number and the cheap bound — predicts a visible loss of digits.
fn stiffness_conditioning_checked(
    mesh: &Mesh,
    options: &SolveOptions,
    regularized_cases: &[Vec<(usize, f64)>],
    mut conditioning: Conditioning,
    warnings: &mut Vec<Warning>,
) -> Conditioning {
    let (bound, scaled_bound) = stiffness_condition_bounds(mesh);
    if options.condition != ConditionLevel::Off {
        let computed = stiffness_conditioning(mesh, options, regularized_cases);
        conditioning.stiffness = computed.stiffness.or(Some(bound));
        conditioning.stiffness_scaled = computed.stiffness_scaled.or(Some(scaled_bound));
        conditioning.regularized_max = computed.regularized_max;
        conditioning.regularized_scaled_max = computed.regularized_scaled_max;
    }
    // The better of the computed number and the bound (an estimate can fall below it).
    let scaled = conditioning
        .stiffness_scaled
        .filter(|c| c.value >= scaled_bound.value)
        .unwrap_or(scaled_bound);
    if let Some(w) = conditioning_warning(scaled, mesh) {
        warnings.push(w);
    }
    conditioning
}

/// Relative KKT residual of (38): the largest of stationarity ‖Ac − b + Bᵀλ‖∞ (relative to
/// ‖A‖‖c‖ + ‖b‖ + ‖λ‖), feasibility (|λ_i| − g_i)+ and complementarity g_i|c_i| − λ_i c_i. The
/// last two are measured against the problem's own scales: a force scale F = max|f|·l + max g1
/// (times l for moments) and ‖c‖ per kind of DOF.
fn kkt_residual(
    problem: &Problem,
    mesh: &Mesh,
    field: &NodalField,
    lambda: &[[f64; 2]],
    obstacles: &[ObstacleResult],
) -> f64 {
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    if !finite(&field.deflection) || !finite(&field.slope) || !lambda.iter().all(|l| finite(l)) {
        // Not a residual of 0 by `max` skipping NaN: no certificate at all.
        return f64::NAN;
    }
    let (stationarity, scale) =
        kkt_stationarity(problem, mesh, &field.deflection, &field.slope, lambda);
    let mut residual = if scale > 0.0 {
        stationarity / scale
    } else {
        stationarity
    };
    let norm = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let c_norm = [norm(&field.deflection), norm(&field.slope)];
    let load = problem.load.f0.abs().max(problem.load.f1.abs()) * problem.length;
    let thresholds = |d: usize| {
        problem.obstacles.iter().fold(0.0f64, |m, o| {
            m.max(if d == 0 {
                o.sliding_threshold
            } else {
                o.swivel_threshold
            })
        })
    };
    let force_scale = [load + thresholds(0), load * problem.length + thresholds(1)];
    for (o, result) in problem.obstacles.iter().zip(obstacles) {
        let g = [o.sliding_threshold, o.swivel_threshold];
        let l = [result.force, result.moment];
        let c = [result.u, result.slope];
        for d in 0..2 {
            let f = force_scale[d].max(g[d]).max(l[d].abs());
            if f > 0.0 {
                residual = residual.max((l[d].abs() - g[d]).max(0.0) / f);
                if c_norm[d] > 0.0 {
                    residual =
                        residual.max((g[d] * c[d].abs() - l[d] * c[d]).abs() / (f * c_norm[d]));
                }
            }
        }
    }
    residual
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
    let matrix = StiffnessMatrix::new(mesh).to_block_tridiagonal();
    let mut result = Conditioning {
        stiffness: block_condition(&matrix),
        stiffness_scaled: block_condition(&jacobi_scaled(&matrix)),
        ..Conditioning::default()
    };
    let max = |a: Option<ConditionNumber>, b: Option<ConditionNumber>| match (a, b) {
        (Some(a), Some(b)) => Some(if b.value > a.value { b } else { a }),
        (a, b) => a.or(b),
    };
    for case in cases {
        let mut modified = matrix.clone();
        for &(dof, add) in case {
            let block = mesh.obstacle_nodes[dof / 2] - 1;
            modified.diag[block][if dof % 2 == 0 { 0 } else { 2 }] += add;
        }
        result.regularized_max = max(result.regularized_max, block_condition(&modified));
        result.regularized_scaled_max = max(
            result.regularized_scaled_max,
            block_condition(&jacobi_scaled(&modified)),
        );
    }
    result
}

/// The stiffness route's relative nodal error divided by cond₂(D^{-1/2} A D^{-1/2})·eps, the
/// Jacobi-scaled condition number (unit-invariant), was measured between 1.6e-3 and 6.5e-2 on
/// Benchmarks 1 and 3, the tiny and huge beams, the modulus contrast and the obstacle next to
/// a support, for n from 20 to 5000; 0.02 is typical. docs/design.md (fact 2) is the same law.
const ROUNDING_PER_CONDITION: f64 = 0.02;

/// Predicted relative error above which the stiffness route is reported as losing digits
/// visibly (the same threshold as [`ACCURACY_WARNING`]).
const CONDITIONING_WARNING: f64 = 1e-8;

fn conditioning_warning(scaled: ConditionNumber, mesh: &Mesh) -> Option<Warning> {
    let risk = scaled.value * f64::EPSILON;
    let predicted = ROUNDING_PER_CONDITION * risk;
    if predicted < CONDITIONING_WARNING {
        return None;
    }
    let relation = scaled.kind.symbol();
    let consequence = if scaled.beyond_double_precision() {
        "beyond double precision: the stiffness route's result can be entirely wrong".to_string()
    } else {
        format!(
            "expect a relative error near {:.0e} from the stiffness route (typically \
             0.02·cond·eps), growing like n⁴",
            predicted
        )
    };
    Some(Warning::new(
        WarningCode::StiffnessConditioning,
        format!(
            "cond(D^-1/2 A D^-1/2) {relation} {:.1e} at n = {}: {consequence}; the condensed \
             method stays accurate",
            scaled.value,
            mesh.elements(),
        ),
    ))
}

/// Relative error against the reference above which an exact method's answer is reported as
/// visibly wrong.
const ACCURACY_WARNING: f64 = 1e-8;

fn accuracy_warning(solution: &Solution) -> Option<Warning> {
    let error = solution.error?;
    let rel = error.max_rel?;
    if solution.method.is_regularized() {
        return (rel > 1e-3).then(|| {
            Warning::new(
                WarningCode::AccuracyLoss,
                format!(
                    "the regularised solution is {rel:.1e} (relative) from the {} reference; \
                     the regularisation alone costs an error of order ε = {:e}",
                    error.reference.name(),
                    solution.epsilon.unwrap_or(f64::NAN)
                ),
            )
        });
    }
    (rel > ACCURACY_WARNING || !rel.is_finite()).then(|| {
        Warning::new(
            WarningCode::AccuracyLoss,
            format!(
                "{rel:.1e} relative error against the {} reference: digits lost to rounding",
                error.reference.name()
            ),
        )
    })
}

/// The reference nodal field for `problem` on `mesh`: the closed form where it applies, else
/// the condensed method. `None` only if the condensed method itself fails.
pub fn reference_field(problem: &Problem, mesh: &Mesh) -> Option<(Reference, NodalField)> {
    reference_field_until(problem, mesh, Cancellation::NEVER)
}

/// [`reference_field`] that gives up (`None`) when `cancel` says the solve is not wanted.
pub(crate) fn reference_field_until(
    problem: &Problem,
    mesh: &Mesh,
    cancel: Cancellation,
) -> Option<(Reference, NodalField)> {
    if let Ok(exact) = closed_form(problem) {
        return Some((Reference::ClosedForm, exact.nodal_field(mesh)));
    }
    let options = SolveOptions {
        condition: ConditionLevel::Off,
        reference: false,
        cancel,
        ..SolveOptions::default()
    };
    let output = condensed::solve(problem, mesh, &options).ok()?;
    // A reference that did not certify itself grades nothing.
    let certified = output.warnings.is_empty()
        && output
            .field
            .deflection
            .iter()
            .chain(&output.field.slope)
            .all(|v| v.is_finite());
    certified.then_some((Reference::Condensed, output.field))
}

fn reference_error(
    problem: &Problem,
    mesh: &Mesh,
    solution: &Solution,
    cancel: Cancellation,
) -> Option<ErrorReport> {
    let closed_form_applies = closed_form(problem).is_ok();
    let is_reference = match solution.method {
        Method::ClosedForm => true,
        Method::Condensed => !closed_form_applies,
        _ => false,
    };
    if is_reference {
        return Some(ErrorReport {
            reference: Reference::ThisSolution,
            max_abs: None,
            max_rel: None,
            mean_abs: None,
            mean_rel: None,
            slope_max_rel: None,
        });
    }
    let (reference, field) = reference_field_until(problem, mesh, cancel)?;
    Some(compare(reference, &solution.field, &field))
}

/// Nodal error of `field` against `reference_field`.
pub fn compare(
    reference: Reference,
    field: &NodalField,
    reference_field: &NodalField,
) -> ErrorReport {
    let stats = |a: &[f64], b: &[f64]| {
        if !a.iter().chain(b).all(|v| v.is_finite()) {
            // No error at all rather than one that `max` computed by skipping NaN.
            return (f64::NAN, f64::NAN, f64::NAN, f64::NAN);
        }
        let (mut max_abs, mut sum, mut scale) = (0.0f64, 0.0f64, 0.0f64);
        for (x, y) in a.iter().zip(b) {
            let d = (x - y).abs();
            max_abs = max_abs.max(d);
            sum += d;
            scale = scale.max(y.abs());
        }
        let relative = |v: f64| {
            if scale > 0.0 {
                v / scale
            } else if v == 0.0 {
                0.0
            } else {
                f64::INFINITY
            }
        };
        let mean = sum / a.len() as f64;
        (max_abs, mean, relative(max_abs), relative(mean))
    };
    let (max_abs, mean_abs, max_rel, mean_rel) =
        stats(&field.deflection, &reference_field.deflection);
    let (_, _, slope_rel, _) = stats(&field.slope, &reference_field.slope);
    let finite = |v: f64| v.is_finite().then_some(v);
    ErrorReport {
        reference,
        max_abs: finite(max_abs),
        max_rel: finite(max_rel),
        mean_abs: finite(mean_abs),
        mean_rel: finite(mean_rel),
        slope_max_rel: finite(slope_rel),
    }
}
