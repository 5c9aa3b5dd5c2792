//! `regularized-newton`: the ε-problem of paper 2.7.1 (the same as `regularized`) solved by a
//! semismooth Newton method instead of enumerating the 9^k cases of Table 1. Newton's matrix
//! is the case matrix of the current regions (K + g/ε on middle DOFs). The objective
//! φ(c) = ½cᵀKc − b̃ᵀc + Σ g_i ω̃_ε(c_i) is convex and piecewise quadratic, with curvature
//! jumping by g/ε between regions, so a backtracking line search crawls for small ε; the
//! exact minimiser along each Newton direction is cheap to find instead, and with it the
//! iteration converges from c = 0 in a few steps. The cost grows with k polynomially: the
//! exponential cost of the paper's method is the enumeration's, not ε's.

use super::history::{DofState, ProgressMeasure, Recorder};
use super::options::SolveOptions;
use super::regularized::{EpsilonRegion, middle_additions, regularized_forces, regularized_output};
use super::shared::check_cancel;
use super::shared::{MethodOutput, Stopwatch};
use super::solution::{MethodDetails, SolveError, Timing, Warning, WarningCode};
use super::stiffness_route::{assemble_and_factor, indefinite_warning};
use crate::fem::Mesh;
use crate::linalg::dense::Cholesky;
use crate::model::{Method, Problem};

/// The step t ≥ 0 minimising φ(c + t d) exactly. Along the line φ is convex and piecewise
/// quadratic: φ'(t) = dᵀ∇φ(c) + t dᵀKd + Σ g_i d_i (ω̃'_ε(c_i + t d_i) − ω̃'_ε(c_i)) is
/// piecewise linear and nondecreasing, with a break wherever some c_i + t d_i crosses ±ε.
/// Walk the breaks in order until φ' changes sign, then solve the linear piece. A full
/// Newton step (t = 1) is taken when it is the minimiser.
fn exact_line_search(
    c: &[f64],
    d: &[f64],
    gradient: &[f64],
    kd: &[f64],
    g: &[f64],
    epsilon: f64,
) -> f64 {
    let slope0: f64 = d.iter().zip(gradient).map(|(d, g)| d * g).sum();
    let curvature: f64 = d.iter().zip(kd).map(|(d, k)| d * k).sum();
    let derivative = |t: f64| -> f64 {
        slope0
            + t * curvature
            + (0..c.len())
                .map(|i| {
                    let at = |s: f64| EpsilonRegion::of(s, epsilon).multiplier(s, g[i], epsilon);
                    d[i] * (at(c[i] + t * d[i]) - at(c[i]))
                })
                .sum::<f64>()
    };
    if slope0 >= 0.0 {
        return 0.0;
    }
    let mut breaks: Vec<f64> = (0..c.len())
        .filter(|&i| d[i] != 0.0 && g[i] > 0.0)
        .flat_map(|i| [(epsilon - c[i]) / d[i], (-epsilon - c[i]) / d[i]])
        .filter(|&t| t > 0.0 && t.is_finite())
        .collect();
    // No region changes on (0, 1]: the Newton model is exact there and t = 1 is the minimiser.
    if breaks.iter().all(|&t| t > 1.0) {
        return 1.0;
    }
    breaks.push(1.0);
    breaks.sort_by(f64::total_cmp);
    let (mut t0, mut f0) = (0.0, slope0);
    for &t1 in &breaks {
        let f1 = derivative(t1);
        if f1 >= 0.0 {
            // φ' is linear on [t0, t1]: its zero.
            return if f1 == f0 {
                t1
            } else {
                t0 + (t1 - t0) * (-f0) / (f1 - f0)
            };
        }
        (t0, f0) = (t1, f1);
    }
    // Past every break φ' is linear with the slope of the last piece.
    let last = breaks[breaks.len() - 1];
    let slope = (derivative(last + 1.0) - f0).max(f64::MIN_POSITIVE);
    last - f0 / slope
}

const MAX_ITERATIONS: usize = 200;

pub(super) fn solve(
    problem: &Problem,
    mesh: &Mesh,
    options: &SolveOptions,
) -> Result<MethodOutput, SolveError> {
    super::shared::refuse_many_obstacles(problem, Method::RegularizedNewton)?;
    let epsilon = options.epsilon;
    let mut timing = Timing::default();
    let factored = assemble_and_factor(
        problem,
        mesh,
        (Method::RegularizedNewton, options),
        &mut timing,
    )?;
    let stiffness_indefinite_warning = indefinite_warning(&factored, mesh);
    let mut clock = Stopwatch::start();
    let (k, b, dim) = (
        &factored.friction_stiffness,
        &factored.friction_load,
        factored.friction_dofs,
    );
    let g = problem.thresholds();

    let eps_problem = EpsilonProblem {
        k,
        b,
        g: &g,
        epsilon,
    };
    let mut recorder = Recorder::when(
        options.history,
        Method::RegularizedNewton,
        ProgressMeasure::SemismoothResidual,
    );
    let mut c = vec![0.0; dim];
    eps_problem.record(recorder.as_mut(), &c);
    let mut iterations = 0;
    let mut converged = dim == 0;
    while !converged && iterations < MAX_ITERATIONS {
        check_cancel(options, Method::RegularizedNewton)?;
        iterations += 1;
        let grad = eps_problem.gradient(&c);
        let mut matrix = k.clone();
        for q in 0..dim {
            if EpsilonRegion::of(c[q], epsilon) == EpsilonRegion::Middle {
                matrix[q * dim + q] += g[q] / epsilon;
            }
        }
        // A second of work at 2k = 1022: cancelled between columns.
        let stop = || options.cancel.is_cancelled();
        let factor = Cholesky::factor_until(&matrix, dim, &stop)
            .map_err(|_| super::shared::cancelled(Method::RegularizedNewton))?;
        let Some(factor) = factor else {
            break;
        };
        // Newton direction d = −(K + D)⁻¹ ∇φ, then the exact minimiser along it.
        let mut direction = grad.clone();
        factor.solve_in_place(&mut direction);
        direction.iter_mut().for_each(|d| *d = -*d);
        let kd = eps_problem.times_k(&direction);
        let t = exact_line_search(&c, &direction, &grad, &kd, &g, epsilon);
        let next: Vec<f64> = c.iter().zip(&direction).map(|(c, d)| c + t * d).collect();
        let moved = c
            .iter()
            .zip(&next)
            .any(|(a, b)| EpsilonRegion::of(*a, epsilon) != EpsilonRegion::of(*b, epsilon));
        c = next;
        eps_problem.record(recorder.as_mut(), &c);
        // The model is exact inside a fixed pattern of regions: a full step that keeps the
        // pattern lands on the solution.
        converged =
            (!moved && t == 1.0) || eps_problem.rows_converged(&c, &eps_problem.gradient(&c));
    }
    let regions: Vec<EpsilonRegion> = c.iter().map(|&c| EpsilonRegion::of(c, epsilon)).collect();
    timing.friction_stage = clock.lap();
    let lambda = regularized_forces((&regions, &c, &g, epsilon), (k, b));
    let friction_stiffness = k.to_vec();
    let field = factored.reconstruct(&c, (Method::RegularizedNewton, options))?;
    timing.reconstruction = clock.lap();

    let mut warnings: Vec<Warning> = stiffness_indefinite_warning.into_iter().collect();
    if !converged {
        warnings.push(Warning::new(
            WarningCode::NewtonNotConverged,
            format!("Newton stopped after {iterations} iterations without converging"),
        ));
    }
    let condition_cases = vec![
        middle_additions(&regions, &g, epsilon),
        middle_additions(&vec![EpsilonRegion::Middle; dim], &g, epsilon),
    ];
    let details = MethodDetails {
        newton_iterations: Some(iterations),
        ..MethodDetails::default()
    };
    let output = regularized_output(
        (field, lambda),
        (&friction_stiffness, &c, options),
        (timing, warnings, details),
        condition_cases,
    );
    Ok(MethodOutput {
        history: recorder.map(Recorder::finish),
        friction_pattern: None,
        ..output
    })
}

/// The ε-problem on the friction DOFs: K, b̃, the thresholds and ε.
struct EpsilonProblem<'a> {
    k: &'a [f64],
    b: &'a [f64],
    g: &'a [f64],
    epsilon: f64,
}

impl EpsilonProblem<'_> {
    /// K c.
    fn times_k(&self, c: &[f64]) -> Vec<f64> {
        let dim = c.len();
        (0..dim)
            .map(|i| (0..dim).map(|j| self.k[i * dim + j] * c[j]).sum())
            .collect()
    }

    /// g ω̃'_ε(c) at DOF i, the friction force of (41).
    fn multiplier(&self, c: &[f64], i: usize) -> f64 {
        EpsilonRegion::of(c[i], self.epsilon).multiplier(c[i], self.g[i], self.epsilon)
    }

    /// ∇φ(c) = K c − b̃ + g ω̃'_ε(c): the optimality condition (43) as a function.
    fn gradient(&self, c: &[f64]) -> Vec<f64> {
        let kc = self.times_k(c);
        (0..c.len())
            .map(|i| kc[i] - self.b[i] + self.multiplier(c, i))
            .collect()
    }

    /// The size of the terms of row i of ∇φ: Σ_j |K_ij c_j| + |b_i| + |g_i ω̃'_ε(c_i)|.
    fn row_terms(&self, c: &[f64], i: usize) -> f64 {
        let dim = c.len();
        (0..dim)
            .map(|j| (self.k[i * dim + j] * c[j]).abs())
            .sum::<f64>()
            + self.b[i].abs()
            + self.multiplier(c, i).abs()
    }

    /// Scale-free convergence: every row of ∇φ within rounding of its own terms (a threshold
    /// of 1e20 on one row or a load of 1e-300 leaves the other rows' test unchanged).
    fn rows_converged(&self, c: &[f64], grad: &[f64]) -> bool {
        let dim = c.len();
        (0..dim).all(|i| grad[i].abs() <= 64.0 * dim as f64 * f64::EPSILON * self.row_terms(c, i))
    }

    /// Records the iterate c: the largest row of ∇φ relative to its terms (the measure of
    /// [`Self::rows_converged`]), φ(c) = ½cᵀKc − b̃ᵀc + Σ gᵢ ω̃_ε(cᵢ), the ε-regions and the
    /// forces as the method reports them. Nothing without a recorder.
    fn record(&self, recorder: Option<&mut Recorder>, c: &[f64]) {
        let Some(recorder) = recorder else {
            return;
        };
        let (grad, kc, epsilon) = (self.gradient(c), self.times_k(c), self.epsilon);
        let residual = (0..c.len())
            .map(|i| {
                let terms = self.row_terms(c, i);
                if terms > 0.0 {
                    grad[i].abs() / terms
                } else {
                    0.0
                }
            })
            .fold(0.0f64, f64::max);
        let huber = |z: f64| {
            if z.abs() <= epsilon {
                z * z / (2.0 * epsilon)
            } else {
                z.abs() - 0.5 * epsilon
            }
        };
        let objective: f64 = (0..c.len())
            .map(|i| 0.5 * c[i] * kc[i] - self.b[i] * c[i] + self.g[i] * huber(c[i]))
            .sum();
        let regions: Vec<EpsilonRegion> =
            c.iter().map(|&v| EpsilonRegion::of(v, epsilon)).collect();
        let states: Vec<DofState> = regions
            .iter()
            .map(|region| match region {
                EpsilonRegion::Middle => DofState::Inside,
                EpsilonRegion::Negative => DofState::AtLower,
                EpsilonRegion::Positive => DofState::AtUpper,
            })
            .collect();
        let forces = regularized_forces((&regions, c, self.g, epsilon), (self.k, self.b));
        recorder.record(residual, Some(objective), &states, forces);
    }
}
