//! `regularized`: the method of paper 2.7.1. |z| is replaced by the Huber-type ω̃_ε of (40), so
//! the optimality condition A c − b + ∇q̃_ε(c) = 0 is linear in each of the three regions of
//! every friction DOF (Table 1): outside [−ε, ε] the gradient adds ∓g_i to the right-hand side,
//! inside it adds g_i/ε to the diagonal (43). All 3^{2k} = 9^k combinations are solved and the
//! one whose solution lies in its own regions is kept.
//!
//! Each case's system (43) is solved through the Schur complement on the friction DOFs (the
//! cases differ only there), so A is factored once and each case costs one 2k×2k Cholesky.
//! The enumeration refuses when 9^k exceeds [`SolveOptions::max_cases`].

use super::friction_accuracy::regularization_accuracy;
use super::options::SolveOptions;
use super::shared::check_cancel;
use super::shared::{MethodOutput, Stopwatch};
use super::solution::{MethodDetails, SolveError, SolveErrorKind, Timing, Warning, WarningCode};
use super::stiffness_route::{assemble_and_factor, indefinite_warning};
use crate::fem::Mesh;
use crate::linalg::dense::Cholesky;
use crate::model::{Method, Problem};

/// The ε-region of a friction DOF in Table 1: where its value c lies relative to [−ε, ε].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum EpsilonRegion {
    /// c < −ε: gradient −g.
    Negative,
    /// |c| ≤ ε: gradient g c / ε.
    Middle,
    /// c > ε: gradient +g.
    Positive,
}

impl EpsilonRegion {
    pub(crate) fn from_digit(d: u64) -> EpsilonRegion {
        match d {
            0 => EpsilonRegion::Middle,
            1 => EpsilonRegion::Positive,
            _ => EpsilonRegion::Negative,
        }
    }

    /// How far c is outside the region, in units of ε (0 when inside).
    pub(crate) fn violation(self, c: f64, epsilon: f64) -> f64 {
        let outside = match self {
            EpsilonRegion::Negative => c + epsilon,
            EpsilonRegion::Middle => c.abs() - epsilon,
            EpsilonRegion::Positive => epsilon - c,
        };
        outside.max(0.0) / epsilon
    }

    /// The region c lies in.
    pub(super) fn of(c: f64, epsilon: f64) -> EpsilonRegion {
        if c > epsilon {
            EpsilonRegion::Positive
        } else if c < -epsilon {
            EpsilonRegion::Negative
        } else {
            EpsilonRegion::Middle
        }
    }

    /// The friction force g ω̃'_ε(c) (41).
    pub(super) fn multiplier(self, c: f64, g: f64, epsilon: f64) -> f64 {
        match self {
            EpsilonRegion::Negative => -g,
            EpsilonRegion::Middle => g * c / epsilon,
            EpsilonRegion::Positive => g,
        }
    }
}

/// Number of cases 9^k, or `None` on overflow.
pub(crate) fn case_count(obstacles: usize) -> Option<u64> {
    9u64.checked_pow(u32::try_from(obstacles).ok()?)
}

/// The regions of case number `case` in the enumeration's order: digit q of `case` in base 3
/// is friction DOF q's region (0 middle, 1 positive, 2 negative).
pub(crate) fn case_regions(case: u64, regions: &mut [EpsilonRegion]) {
    let mut code = case;
    for r in regions.iter_mut() {
        *r = EpsilonRegion::from_digit(code % 3);
        code /= 3;
    }
}

/// How far the values `c` of a case lie outside the case's own `regions`, in units of ε (0:
/// the case is consistent, the method's test); infinite when a value is not finite (a NaN
/// lies in no region).
pub(crate) fn case_violation(regions: &[EpsilonRegion], c: &[f64], epsilon: f64) -> f64 {
    if c.iter().any(|v| !v.is_finite()) {
        return f64::INFINITY;
    }
    regions
        .iter()
        .zip(c)
        .map(|(r, &c)| r.violation(c, epsilon))
        .fold(0.0, f64::max)
}

/// Solves one case: (K + D) c = b̃ − d, with D = g/ε on middle DOFs, d = ±g on outer ones.
pub(crate) fn solve_case(
    stiffness: &[f64],
    load: &[f64],
    g: &[f64],
    regions: &[EpsilonRegion],
    epsilon: f64,
) -> Option<Vec<f64>> {
    let dim = load.len();
    let mut matrix = stiffness.to_vec();
    let mut rhs = load.to_vec();
    for (q, region) in regions.iter().enumerate() {
        match region {
            EpsilonRegion::Middle => matrix[q * dim + q] += g[q] / epsilon,
            EpsilonRegion::Positive => rhs[q] -= g[q],
            EpsilonRegion::Negative => rhs[q] += g[q],
        }
    }
    let factor = Cholesky::new(&matrix, dim)?;
    factor.solve_in_place(&mut rhs);
    Some(rhs)
}

pub(super) fn solve(
    problem: &Problem,
    mesh: &Mesh,
    options: &SolveOptions,
) -> Result<MethodOutput, SolveError> {
    let k = problem.obstacles.len();
    let cases = case_count(k).filter(|&c| c <= options.max_cases);
    let Some(cases) = cases else {
        return Err(SolveError {
            method: Method::Regularized,
            kind: SolveErrorKind::Refused,
            reason: format!(
                "{k} obstacles need 9^{k} = {} linear systems, more than the limit of {}",
                case_count(k).map_or("more than 1.8e19".to_string(), |c| c.to_string()),
                options.max_cases
            ),
            suggestion: Method::RegularizedNewton,
        });
    };
    let epsilon = options.epsilon;
    let mut timing = Timing::default();
    let factored = assemble_and_factor(problem, mesh, (Method::Regularized, options), &mut timing)?;
    let stiffness_indefinite_warning = indefinite_warning(&factored, mesh);
    let mut clock = Stopwatch::start();
    let dim = factored.friction_dofs;
    let g = problem.thresholds();

    let mut best: Option<(f64, Vec<EpsilonRegion>, Vec<f64>)> = None;
    let mut regions = vec![EpsilonRegion::Middle; dim];
    for case in 0..cases {
        if case % 4096 == 0 {
            check_cancel(options, Method::Regularized)?;
        }
        case_regions(case, &mut regions);
        let Some(c) = solve_case(
            &factored.friction_stiffness,
            &factored.friction_load,
            &g,
            &regions,
            epsilon,
        ) else {
            continue;
        };
        let violation = case_violation(&regions, &c, epsilon);
        if best.as_ref().is_none_or(|(v, _, _)| violation < *v) {
            best = Some((violation, regions.clone(), c));
            if violation == 0.0 {
                break;
            }
        }
    }
    timing.friction_stage = clock.lap();
    let Some((violation, regions, friction_values)) = best else {
        return Err(super::stiffness_route::breakdown(
            Method::Regularized,
            mesh,
            "no case matrix K + g/ε is positive definite".into(),
        ));
    };
    let lambda = regularized_forces(
        (&regions, &friction_values, &g, epsilon),
        (&factored.friction_stiffness, &factored.friction_load),
    );
    let friction_stiffness = factored.friction_stiffness.clone();
    let field = factored.reconstruct(&friction_values, (Method::Regularized, options))?;
    timing.reconstruction = clock.lap();

    let mut warnings: Vec<Warning> = stiffness_indefinite_warning.into_iter().collect();
    if violation > 1e-6 {
        warnings.push(Warning::new(
            WarningCode::RegularizationInconsistent,
            format!(
                "no case of Table 1 is consistent to rounding; the closest was kept \
                 ({violation:.1e} ε outside its region)"
            ),
        ));
    }
    let condition_cases = condition_cases(&g, epsilon, cases, &regions, mesh.unknowns());
    let details = MethodDetails {
        cases: Some(cases),
        ..MethodDetails::default()
    };
    Ok(regularized_output(
        (field, lambda),
        (&friction_stiffness, &friction_values, options),
        (timing, warnings, details),
        condition_cases,
    ))
}

/// The g/ε additions to K's diagonal of the case with these regions (43).
pub(crate) fn middle_additions(
    regions: &[EpsilonRegion],
    g: &[f64],
    epsilon: f64,
) -> Vec<(usize, f64)> {
    regions
        .iter()
        .enumerate()
        .filter(|(_, r)| **r == EpsilonRegion::Middle)
        .map(|(q, _)| (q, g[q] / epsilon))
        .collect()
}

/// The friction forces g ω̃'_ε(c) of (41) of both regularised methods, per obstacle. In the
/// middle region g·c/ε multiplies the rounding of a tiny c by g/ε (issue 10, finding 9: a
/// relative error of 2.4e-7 where the enumeration got 3e-12, and worse for g = 1e20); there the
/// force is taken from the equilibrium on the friction DOFs, λ = b̃ − K c (exact at the
/// ε-solution), whenever its rounding, eps·(|b̃_i| + Σ|K_ij c_j|), is the smaller.
pub(super) fn regularized_forces(
    (regions, values, g, epsilon): (&[EpsilonRegion], &[f64], &[f64], f64),
    (stiffness, load): (&[f64], &[f64]),
) -> Vec<[f64; 2]> {
    let dim = values.len();
    let largest = values.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    let lambda: Vec<f64> = (0..dim)
        .map(|i| {
            let from_region = regions[i].multiplier(values[i], g[i], epsilon);
            if regions[i] != EpsilonRegion::Middle {
                return from_region;
            }
            let row = &stiffness[i * dim..(i + 1) * dim];
            let kc: f64 = row.iter().zip(values).map(|(k, c)| k * c).sum();
            let terms: f64 = load[i].abs()
                + row
                    .iter()
                    .zip(values)
                    .map(|(k, c)| (k * c).abs())
                    .sum::<f64>();
            if terms < g[i] / epsilon * largest {
                (load[i] - kc).clamp(-g[i], g[i])
            } else {
                from_region
            }
        })
        .collect();
    lambda.chunks(2).map(|c| [c[0], c[1]]).collect()
}

/// What both regularised methods hand back, with what ε does to their motions (from K, the
/// friction DOFs' values `c` and ε; none when the solve was cancelled meanwhile).
pub(super) fn regularized_output(
    (field, lambda): (crate::fem::NodalField, Vec<[f64; 2]>),
    (k, c, options): (&[f64], &[f64], &SolveOptions),
    (timing, warnings, details): (Timing, Vec<Warning>, MethodDetails),
    condition_cases: Vec<Vec<(usize, f64)>>,
) -> MethodOutput {
    let stop = || options.cancel.is_cancelled();
    let friction_accuracy = regularization_accuracy(k, c, options.epsilon, &stop).unwrap_or(None);
    MethodOutput {
        field,
        lambda,
        states: None,
        timing,
        warnings,
        details,
        dual_condition: None,
        regularized_cases: condition_cases,
        friction_accuracy,
        // `regularized` enumerates and does not iterate; `regularized-newton` sets its own.
        history: None,
        friction_pattern: None,
    }
}

/// Most cases whose condition numbers are all computed (one obstacle: 9).
pub(crate) const CONDITIONED_CASES: u64 = 9;

/// Are the condition numbers of every one of `cases` case matrices computed on a mesh of
/// `unknowns` unknowns (else only the kept case's and the all-middle one's)?
pub(crate) fn conditions_every_case(cases: u64, unknowns: usize) -> bool {
    cases <= CONDITIONED_CASES && unknowns <= crate::linalg::condition::DENSE_LIMIT
}

/// The diagonal additions of the cases whose condition numbers are reported: every case when
/// there are at most [`CONDITIONED_CASES`] and the matrices are small enough for exact
/// eigenvalues, else the kept case and the one with every DOF in the middle region (the
/// largest additions g/ε). [`crate::solve::MethodDetails::conditioned_cases`] says which.
fn condition_cases(
    g: &[f64],
    epsilon: f64,
    cases: u64,
    kept: &[EpsilonRegion],
    unknowns: usize,
) -> Vec<Vec<(usize, f64)>> {
    let dim = g.len();
    let additions = |regions: &[EpsilonRegion]| middle_additions(regions, g, epsilon);
    if conditions_every_case(cases, unknowns) {
        (0..cases)
            .map(|case| {
                let mut regions = vec![EpsilonRegion::Middle; dim];
                case_regions(case, &mut regions);
                additions(&regions)
            })
            .collect()
    } else {
        vec![
            additions(kept),
            additions(&vec![EpsilonRegion::Middle; dim]),
        ]
    }
}
