//! Comparison of a program solution (`beamfric::solve::solve`) with the reference on the same
//! mesh: relative nodal errors, relative force errors per kind, and the friction flags.
//!
//! Normalisation (issue 10): u and slope by max |u| and max |u'| of the reference over the
//! nodes, guarded against a kind that is (nearly) all zero — u' on Benchmark 1 with 2 elements,
//! where the only interior node is a stuck obstacle — by 1e-3 of the other kind times l (over
//! l), and by |f| l⁴/EJ_max (|f| l³/EJ_max) when the reference is zero at every node; forces by max(max_i |λ1_i|, |f|·l) and moments by max(max_i |λ2_i|, |f|·l²), with
//! |f| = max(|f0|, |f1|). A non-finite program value counts as an infinite error. Flags: a
//! program's `sliding`/`swivel` must match the reference state; "at threshold" accepts either.
//! A program's own "at threshold" state is right where the reference is within 1e-12 (of the
//! same scales) of a tie, 1e-8 against the ε-reference (the agreement asked of the regularised
//! methods).
//! A wrong flag is *gross* when the reference motion is at least 1e-12 of max |u| (max |u'|)
//! or the stuck force at most 1 − 1e-10 of its threshold: something f64 can resolve globally;
//! the others need the motion resolved locally (issue 10, finding 3). Against the ε-reference
//! ([`super::epsilon`], `RefSolution::epsilon` > 0) "moves" means |motion| > ε, as the program
//! decides it for its regularised methods, and a motion is gross when it exceeds ε by 1e-12 of
//! max |u| (max |u'|); the states carry ε already.

use beamfric::model::Problem;
use beamfric::solve::{FrictionState as ProgramState, Solution, WarningCode};

use super::solver::{FrictionState, RefSolution};

/// Default agreement bounds of the acceptance criterion for the stable method.
pub const FIELD_TOLERANCE: f64 = 1e-12;
pub const FORCE_TOLERANCE: f64 = 1e-10;

/// How close to a tie (relative, see `compare`) the reference must be for a program's "at the
/// threshold" to count as right.
pub const TIE_TOLERANCE: f64 = 1e-12;

/// The same against the ε-reference: the regularised methods are asked to agree with it to
/// 1e-8 (issue 10), and a solution that agrees to 1e-8 may honestly call a DOF within 1e-8 of
/// |c| = ε "at the threshold".
pub const EPSILON_TIE_TOLERANCE: f64 = 1e-8;

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
    /// How many of the wrong flags are gross (see the module doc).
    pub gross_flag_errors: usize,
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

    /// [`Comparison::agrees`] up to what double precision can decide: every flag the reference
    /// settles by more than rounding (a motion of at least 1e-12 of the largest of its kind, a
    /// stuck force clearly below its threshold) must be right; a motion below that may be
    /// reported "at the threshold" (not moving), which is what the stable method does with a
    /// motion its own rounding cannot resolve.
    pub fn agrees_to_resolution(&self, field_tolerance: f64, force_tolerance: f64) -> bool {
        self.field_error() <= field_tolerance
            && self.force_error() <= force_tolerance
            && self.gross_flag_errors == 0
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
    let (u_max, slope_max) = (max_abs(&u_ref), max_abs(&slope_ref));
    let l = problem.length;
    let load = problem.load.f0.abs().max(problem.load.f1.abs());
    let stiffest = problem
        .stiffness
        .iter()
        .fold(0f64, |m, p| m.max(p.bending_stiffness));
    let (u_scale, slope_scale) = if u_max == 0.0 && slope_max == 0.0 {
        (load * l.powi(4) / stiffest, load * l.powi(3) / stiffest)
    } else {
        (
            u_max.max(1e-3 * slope_max * l),
            slope_max.max(1e-3 * u_max / l),
        )
    };
    let u = relative_error(&field.deflection, &u_ref, u_scale);
    let slope = relative_error(&field.slope, &slope_ref, slope_scale);

    let lambda = reference.lambda_f64();
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
    let force_scale = [0, 1].map(|k| {
        let natural = load * l.powi(k as i32 + 1);
        lambda.iter().fold(natural, |m, pair| m.max(pair[k].abs()))
    });

    let mut flag_errors = Vec::new();
    let mut gross_flag_errors = 0;
    let motion = reference.motion_f64();
    for (i, (o, states)) in solution.obstacles.iter().zip(&reference.states).enumerate() {
        let p = &problem.obstacles[i];
        for (k, name, flag, state, program_state) in [
            (0, "sliding", o.sliding, states[0], o.sliding_state),
            (1, "swivel", o.swivel, states[1], o.swivel_state),
        ] {
            let threshold = [p.sliding_threshold, p.swivel_threshold][k];
            let scale = [u_scale, slope_scale][k];
            // The program's "at the threshold" is a right answer where the reference itself is
            // within TIE_TOLERANCE of a tie: a motion that small, or a stuck force that close
            // to its threshold relative to the forces of its kind (a threshold of 1e-319 of
            // the forces is not one f64 can tell from zero).
            let tie_tolerance = if reference.epsilon > 0.0 {
                EPSILON_TIE_TOLERANCE
            } else {
                TIE_TOLERANCE
            };
            let tie = match state {
                FrictionState::Moves => {
                    motion[i][k].abs() - reference.epsilon <= tie_tolerance * scale
                }
                _ => threshold - lambda[i][k].abs() <= tie_tolerance * force_scale[k],
            };
            let right = state.accepts(flag) || (program_state == ProgramState::AtThreshold && tie);
            if !right {
                let gross = match state {
                    // Past ε (0 for the exact problem) by more than f64 resolves.
                    FrictionState::Moves => motion[i][k].abs() - reference.epsilon >= 1e-12 * scale,
                    _ => lambda[i][k].abs() <= (1.0 - 1e-10) * threshold,
                };
                gross_flag_errors += usize::from(gross);
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
        gross_flag_errors,
        warnings,
    }
}
