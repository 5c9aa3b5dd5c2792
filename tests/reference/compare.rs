//! Comparison of a program solution (`beamfric::solve::solve`) with the reference on the same
//! mesh: relative nodal errors, relative force errors per kind, and the friction flags.
//!
//! Normalisation (issue 10): u and slope by max |u| and max |u'| of the reference over the
//! nodes; forces by max(max_i |λ1_i|, |f|·l) and moments by max(max_i |λ2_i|, |f|·l²), with
//! |f| = max(|f0|, |f1|). A non-finite program value counts as an infinite error. Flags: a
//! program's `sliding`/`swivel` must match the reference state; "at threshold" accepts either.

use beamfric::model::Problem;
use beamfric::solve::{Solution, WarningCode};

use super::solver::RefSolution;

/// Default agreement bounds of the acceptance criterion for the stable method.
pub const FIELD_TOLERANCE: f64 = 1e-12;
pub const FORCE_TOLERANCE: f64 = 1e-10;

/// How a program solution compares with the reference.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// max |u − u_ref| / max |u_ref| over the nodes.
    pub u: f64,
    /// max |u' − u'_ref| / max |u'_ref| over the nodes.
    pub slope: f64,
    /// max |λ1 − λ1_ref| / max(max |λ1_ref|, |f| l).
    pub force: f64,
    /// max |λ2 − λ2_ref| / max(max |λ2_ref|, |f| l²).
    pub moment: f64,
    /// One line per wrong flag, e.g. `obstacle 3 (x = 0.5): sliding = true, reference stuck`.
    pub flag_errors: Vec<String>,
    /// The program's warnings, `mesh-raised` left out (it says nothing about accuracy).
    pub warnings: Vec<WarningCode>,
}

impl Comparison {
    /// Largest of the field errors (u, slope).
    pub fn field_error(&self) -> f64 {
        self.u.max(self.slope)
    }

    /// Largest of the force errors (force, moment).
    pub fn force_error(&self) -> f64 {
        self.force.max(self.moment)
    }

    /// Within the tolerances, with right flags.
    pub fn agrees(&self, field_tolerance: f64, force_tolerance: f64) -> bool {
        self.field_error() <= field_tolerance
            && self.force_error() <= force_tolerance
            && self.flag_errors.is_empty()
    }

    /// Did the program warn about anything that bears on accuracy?
    pub fn warned(&self) -> bool {
        !self.warnings.is_empty()
    }
}

/// max |a − b| / max |b|; 0 when both are all zero, ∞ when a is non-finite or b is all zero
/// and a is not.
pub fn relative_error(a: &[f64], b: &[f64], scale: f64) -> f64 {
    assert_eq!(a.len(), b.len(), "same number of values");
    let mut worst = 0f64;
    for (x, y) in a.iter().zip(b) {
        if !x.is_finite() {
            return f64::INFINITY;
        }
        worst = worst.max((x - y).abs());
    }
    if worst == 0.0 {
        0.0
    } else if scale == 0.0 {
        f64::INFINITY
    } else {
        worst / scale
    }
}

fn max_abs(values: &[f64]) -> f64 {
    values.iter().fold(0f64, |m, v| m.max(v.abs()))
}

/// Compares `solution` with `reference`, both on the mesh of `problem` with the same nodes.
pub fn compare(problem: &Problem, solution: &Solution, reference: &RefSolution) -> Comparison {
    let field = &solution.field;
    assert_eq!(
        field.deflection.len(),
        reference.nodes.len(),
        "the solution and the reference are on different meshes"
    );
    let (u_ref, slope_ref) = (reference.u_f64(), reference.slope_f64());
    let u = relative_error(&field.deflection, &u_ref, max_abs(&u_ref));
    let slope = relative_error(&field.slope, &slope_ref, max_abs(&slope_ref));

    let lambda = reference.lambda_f64();
    let load = problem.load.f0.abs().max(problem.load.f1.abs());
    let l = problem.length;
    let kind = |k: usize, natural: f64| -> f64 {
        let program: Vec<f64> = solution
            .obstacles
            .iter()
            .map(|o| if k == 0 { o.force } else { o.moment })
            .collect();
        let exact: Vec<f64> = lambda.iter().map(|pair| pair[k]).collect();
        relative_error(&program, &exact, max_abs(&exact).max(natural))
    };
    let force = kind(0, load * l);
    let moment = kind(1, load * l * l);

    let mut flag_errors = Vec::new();
    for (i, (o, states)) in solution.obstacles.iter().zip(&reference.states).enumerate() {
        for (name, flag, state) in [
            ("sliding", o.sliding, states[0]),
            ("swivel", o.swivel, states[1]),
        ] {
            if !state.accepts(flag) {
                flag_errors.push(format!(
                    "obstacle {} (x = {:e}): {name} = {flag}, reference {}",
                    i + 1,
                    o.x,
                    state.word()
                ));
            }
        }
    }
    let warnings = solution
        .warnings
        .iter()
        .map(|w| w.code)
        .filter(|&c| c != WarningCode::MeshRaised)
        .collect();
    Comparison {
        u,
        slope,
        force,
        moment,
        flag_errors,
        warnings,
    }
}
