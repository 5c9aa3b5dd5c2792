//! Grading an answer computed outside the program (`beamfric grade`, issue 24): friction
//! forces λ, nodal values u and u', or both, get the certificate every built-in method gets
//! (`certificate`): the KKT residual of (38), the friction states, condition numbers, the error
//! against the reference (closed form (50)–(51) or `condensed`) and the warnings in words.
//!
//! What is missing is filled in from the discrete problem the answer was computed from:
//! - **forces only**: u, u' follow from (48), A c = b − Bᵀλ, by the stiffness route the `dual`
//!   method rebuilds with (one factorization of A with the friction nodes last, then
//!   K c_F = b̃ − λ on the friction DOFs and one back substitution);
//! - **nodal values only**: λ follows from the friction rows of (48), λ = (b − A c)_F;
//! - **both**: graded as given, so an inconsistency between them shows in the KKT residual.
//!
//! The answer is graded by the rules of the `dual` method, the built-in method that works from
//! the same exported A, b, B and g: the stiffness route's rounding (cond(D^-1/2 A D^-1/2)·eps)
//! is what it may lose, and the warning about A's conditioning says so where it matters.

use super::certificate::{MeshReference, certify};
use super::options::SolveOptions;
use super::shared::MethodOutput;
use super::solution::{MethodDetails, Solution, SolveError, Timing};
use super::stiffness_route::assemble_and_factor;
use crate::fem::{Mesh, NodalField, StiffnessMatrix, load_vector};
use crate::linalg::BlockMatrix;
use crate::linalg::dense::Cholesky;
use crate::model::{Method, Problem};

/// An answer computed elsewhere, in the units and order of the problem.
#[derive(Debug, Clone, PartialEq)]
pub struct GivenAnswer {
    /// (force λ1 [N], moment λ2 [N m]) per obstacle, in the problem's (position) order: the
    /// λ of (45) with A c = b − Bᵀλ (48).
    pub forces: Option<Vec<[f64; 2]>>,
    /// u [m] and u' [rad] at every node of the mesh, ends included.
    pub field: Option<NodalField>,
}

/// Why an answer could not be graded.
#[derive(Debug, Clone, PartialEq)]
pub enum GradeError {
    /// The answer does not fit the problem or its mesh (the text names the part and the rule).
    Shape(String),
    /// Rebuilding u, u' from the forces broke down, or the grading was cancelled.
    Solve(SolveError),
}

impl std::fmt::Display for GradeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GradeError::Shape(text) => f.write_str(text),
            GradeError::Solve(e) => write!(f, "cannot grade: {e}"),
        }
    }
}

impl std::error::Error for GradeError {}

/// The method whose rules grade a given answer (module doc).
const GRADED_AS: Method = Method::Dual;

/// Grades `answer` on `mesh` with the certificate of the built-in methods (module doc). The
/// solution's `method` is [`Method::Dual`], the rules it was graded by; its timing is the
/// rebuilding of what the answer did not give.
pub fn grade(
    problem: &Problem,
    mesh: &Mesh,
    answer: GivenAnswer,
    options: &SolveOptions,
) -> Result<Solution, GradeError> {
    check_shape(problem, mesh, &answer)?;
    let mut timing = Timing::default();
    let (field, lambda) = match (answer.field, answer.forces) {
        (Some(field), Some(forces)) => (field, forces),
        (Some(field), None) => {
            let forces = forces_of_field(problem, mesh, &field);
            (field, forces)
        }
        (None, Some(forces)) => {
            let field = field_of_forces(problem, mesh, &forces, options, &mut timing)?;
            (field, forces)
        }
        (None, None) => unreachable!("check_shape refuses an empty answer"),
    };
    let output = MethodOutput {
        field,
        lambda,
        states: None,
        timing,
        warnings: Vec::new(),
        details: MethodDetails::default(),
        dual_condition: None,
        regularized_cases: Vec::new(),
        friction_accuracy: None,
        history: None,
        friction_pattern: None,
    };
    let reference = MeshReference::new(problem, mesh, options);
    let mut solution = certify(problem, mesh, GRADED_AS, options, output, Some(&reference))
        .ok_or_else(|| GradeError::Solve(super::shared::cancelled(GRADED_AS)))?;
    // A's conditioning explains a visible error only where the certificate says it does.
    let rounded_a = solution.has_warning(super::WarningCode::StiffnessConditioning);
    for warning in &mut solution.warnings {
        warning.message = in_words_for_a_given_answer(&warning.message, rounded_a);
    }
    Ok(solution)
}

/// The certificate's words are written for a built-in method, whose visible error from the
/// reference can only be rounding; an answer from elsewhere may differ for any reason, and
/// rounding explains it only when A itself is rounded beyond repair (`rounded_a`).
fn in_words_for_a_given_answer(message: &str, rounded_a: bool) -> String {
    let cause = if rounded_a {
        "digits lost to the rounding of A (see its conditioning)"
    } else {
        "more than rounding explains"
    };
    message
        .replace(
            "digits lost to rounding; the condensed method works here",
            &format!("{cause}; `beamfric solve --method condensed` gives the reference"),
        )
        .replace("digits lost to rounding", cause)
}

/// The answer has the problem's number of obstacles and the mesh's number of nodes.
fn check_shape(problem: &Problem, mesh: &Mesh, answer: &GivenAnswer) -> Result<(), GradeError> {
    let obstacles = problem.obstacles.len();
    let nodes = mesh.nodes.len();
    if let Some(forces) = &answer.forces
        && forces.len() != obstacles
    {
        return Err(GradeError::Shape(format!(
            "the answer has forces for {} obstacles; the scene has {obstacles}",
            forces.len()
        )));
    }
    if let Some(field) = &answer.field {
        for (name, values) in [("u", &field.deflection), ("u'", &field.slope)] {
            if values.len() != nodes {
                return Err(GradeError::Shape(format!(
                    "the answer has {name} at {} nodes; the mesh has {nodes} (ends included)",
                    values.len()
                )));
            }
        }
    }
    if answer.forces.is_none() && answer.field.is_none() {
        return Err(GradeError::Shape(
            "the answer gives neither friction forces nor nodal values".into(),
        ));
    }
    Ok(())
}

/// λ = (b − A c) on the friction rows of (48): the forces the nodal values imply.
fn forces_of_field(problem: &Problem, mesh: &Mesh, field: &NodalField) -> Vec<[f64; 2]> {
    let n = mesh.elements();
    let interior: Vec<[f64; 2]> = (1..n)
        .map(|node| [field.deflection[node], field.slope[node]])
        .collect();
    let a_c = StiffnessMatrix::new(mesh).apply(&interior);
    let (load_u, load_slope) = load_vector(problem, mesh);
    mesh.obstacle_nodes
        .iter()
        .map(|&node| {
            let row = a_c[node - 1];
            [load_u[node] - row[0], load_slope[node] - row[1]]
        })
        .collect()
}

/// u, u' from (48) for the given forces, on the stiffness route (module doc).
fn field_of_forces(
    problem: &Problem,
    mesh: &Mesh,
    forces: &[[f64; 2]],
    options: &SolveOptions,
    timing: &mut Timing,
) -> Result<NodalField, GradeError> {
    let factored = assemble_and_factor(problem, mesh, (GRADED_AS, options), timing)
        .map_err(GradeError::Solve)?;
    let dim = factored.friction_dofs;
    // K c_F = b̃ − λ.
    let mut friction_values: Vec<f64> = factored
        .friction_load
        .iter()
        .zip(forces.iter().flatten())
        .map(|(load, force)| load - force)
        .collect();
    let schur = Cholesky::new(&factored.friction_stiffness, dim).ok_or_else(|| {
        GradeError::Solve(super::stiffness_route::breakdown(
            GRADED_AS,
            mesh,
            "the condensed stiffness on the friction DOFs is not positive definite".into(),
        ))
    })?;
    schur.solve_in_place(&mut friction_values);
    factored
        .reconstruct(&friction_values, (GRADED_AS, options))
        .map_err(GradeError::Solve)
}
