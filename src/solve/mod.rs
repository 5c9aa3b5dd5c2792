//! The methods of DESIGN.md section 3, one module each, and the [`Solution`] they all return.
//!
//! [`solve`] runs a method and then certifies its answer the same way for every method: the
//! relative KKT residual of (38), the friction state of every obstacle, condition numbers when
//! asked, the error against a reference (the closed form (50) where it applies, else the
//! `flexibility` method on the same mesh) and warnings in words.

mod closed_form;
mod condensed;
mod dual;
mod dual_inverse;
mod flexibility;
mod regularized;
mod regularized_newton;
mod stiffness_route;

use std::fmt;
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use crate::fem::{BlockMatrix, Mesh, NodalField, StiffnessMatrix, kkt_stationarity};
use crate::linalg::condition::{
    ConditionNumber, block_condition, dense_condition, jacobi_scaled, stiffness_condition_bounds,
};
use crate::model::Problem;

pub use closed_form::{ClosedForm, closed_form};
pub use condensed::{
    CondensedFailure, CondensedSolution, FrictionState, solve_condensed, solve_condensed_while,
};

/// A way to solve the problem (DESIGN.md section 3).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Paper 2.7.1: regularise |·| by ω̃_ε (40), enumerate the 9^k cases of Table 1.
    Regularized,
    /// The same ε-problem by semismooth Newton (a few factorizations).
    RegularizedNewton,
    /// Paper 2.7.2 as written: the dual (49) with an explicit inverse of A.
    DualInverse,
    /// The dual (49) with S and z0 from one factorization of A.
    #[default]
    Dual,
    /// The force formulation: same discrete solution without the stiffness matrix.
    Flexibility,
    /// Paper (50)–(51): one obstacle, constant E, J and f.
    ClosedForm,
    /// Exact relations of each piece between special points (multiple shooting), condensed
    /// onto the friction DOFs; stable on every scene, meant as the reference.
    Condensed,
}

impl Method {
    /// Every method, in the order the explorer cycles through them.
    pub const ALL: [Method; 6] = [
        Method::Dual,
        Method::Flexibility,
        Method::Regularized,
        Method::RegularizedNewton,
        Method::DualInverse,
        Method::ClosedForm,
    ];

    /// The name used in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Method::Regularized => "regularized",
            Method::RegularizedNewton => "regularized-newton",
            Method::DualInverse => "dual-inverse",
            Method::Dual => "dual",
            Method::Flexibility => "flexibility",
            Method::ClosedForm => "closed-form",
            Method::Condensed => "condensed",
        }
    }

    /// Does the method work through the stiffness matrix A (and so inherit its conditioning)?
    pub fn uses_stiffness_matrix(self) -> bool {
        !matches!(
            self,
            Method::Flexibility | Method::ClosedForm | Method::Condensed
        )
    }

    /// Does the method solve the regularised problem (and so depend on ε)?
    pub fn is_regularized(self) -> bool {
        matches!(self, Method::Regularized | Method::RegularizedNewton)
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Which condition numbers to compute.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum ConditionLevel {
    /// None (the explorer's per-keystroke path).
    Off,
    /// Exact for N ≤ 200, a cheap lower bound above.
    #[default]
    Auto,
    /// Exact for N ≤ 200, Lanczos estimates above (slow at very large n).
    Full,
}

/// How to solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolveOptions {
    /// ε of (40) for the regularised methods.
    pub epsilon: f64,
    /// The enumeration refuses when 9^k exceeds this.
    pub max_cases: u64,
    /// `dual-inverse` refuses when N = 2(n − 1) exceeds this (the inverse is N² doubles).
    pub max_dense_unknowns: usize,
    pub condition: ConditionLevel,
    /// Compare against a reference (closed form or flexibility) and report the error.
    pub reference: bool,
}

/// Default limit of the enumeration: 9^6 = 531 441 cases (k ≤ 6 obstacles).
pub const MAX_CASES: u64 = 531_441;
/// Default limit of `dual-inverse`: N ≤ 4000 unknowns, a 128 MB inverse.
pub const MAX_DENSE_UNKNOWNS: usize = 4000;

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            epsilon: 1e-6,
            max_cases: MAX_CASES,
            max_dense_unknowns: MAX_DENSE_UNKNOWNS,
            condition: ConditionLevel::Auto,
            reference: true,
        }
    }
}

/// Why a method gave no solution, and which method works instead.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveError {
    pub method: Method,
    pub kind: SolveErrorKind,
    /// What went wrong, in words.
    pub reason: String,
    /// A method that works for this problem.
    pub suggestion: Method,
}

/// The kind of [`SolveError`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SolveErrorKind {
    /// The method is outside its range (too many cases, too large for a dense inverse).
    Refused,
    /// The method does not apply to these data (closed form).
    NotApplicable,
    /// The computation broke down (a factorization failed in floating point).
    Breakdown,
}

impl fmt::Display for SolveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let what = match self.kind {
            SolveErrorKind::Refused => "refused",
            SolveErrorKind::NotApplicable => "not applicable",
            SolveErrorKind::Breakdown => "failed",
        };
        write!(
            f,
            "{} {what}: {}; the {} method works here",
            self.method, self.reason, self.suggestion
        )
    }
}

impl std::error::Error for SolveError {}

/// Run time of the stages of a method. For the regularised methods, `dual_solve` is the
/// work on the friction DOFs: the case enumeration or the Newton iterations.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Timing {
    pub assembly: Duration,
    pub factorization: Duration,
    pub dual_solve: Duration,
    pub reconstruction: Duration,
}

impl Timing {
    /// Sum of the stages.
    pub fn total(&self) -> Duration {
        self.assembly + self.factorization + self.dual_solve + self.reconstruction
    }
}

/// Condition numbers of the matrices a method uses (all optional).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Conditioning {
    /// cond₂(A) of the stiffness matrix.
    pub stiffness: Option<ConditionNumber>,
    /// cond₂ of the Jacobi-scaled stiffness matrix D^{-1/2} A D^{-1/2}.
    pub stiffness_scaled: Option<ConditionNumber>,
    /// Largest cond₂(Â) over the regularised cases (paper Figure 5).
    pub regularized_max: Option<ConditionNumber>,
    /// Largest cond₂ of the Jacobi-scaled Â over the same cases.
    pub regularized_scaled_max: Option<ConditionNumber>,
    /// cond₂(S) of the dual matrix S = B A⁻¹ Bᵀ.
    pub dual: Option<ConditionNumber>,
}

/// What a warning is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum WarningCode {
    /// More elements than asked for (every piece needs one).
    MeshRaised,
    /// cond(A)·eps says the stiffness route cannot be trusted at this n.
    StiffnessConditioning,
    /// The solution differs visibly from the reference.
    AccuracyLoss,
    /// The QP did not reach its KKT conditions.
    QpNotConverged,
    /// No regularisation case was exactly consistent; the closest was kept.
    RegularizationInconsistent,
    /// The Newton iteration hit its limit.
    NewtonNotConverged,
    /// The stiffness matrix lost positive definiteness to rounding during factorization.
    IndefiniteFactorization,
    /// A value is NaN or infinite.
    NonFinite,
}

/// A warning in words.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Warning {
    pub code: WarningCode,
    pub message: String,
}

impl Warning {
    pub(crate) fn new(code: WarningCode, message: impl Into<String>) -> Warning {
        Warning {
            code,
            message: message.into(),
        }
    }
}

/// The result at one obstacle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ObstacleResult {
    /// Position [m].
    pub x: f64,
    /// u(x̂) [m].
    pub u: f64,
    /// u'(x̂) [rad].
    pub slope: f64,
    /// Friction force λ1 [N] (A c = b − Bᵀλ; |λ1| ≤ g1).
    pub force: f64,
    /// Friction moment λ2 [N m] (|λ2| ≤ g2).
    pub moment: f64,
    /// The point slides (u(x̂) ≠ 0, |λ1| = g1).
    pub sliding: bool,
    /// The point swivels (u'(x̂) ≠ 0, |λ2| = g2).
    pub swivel: bool,
}

impl ObstacleResult {
    /// The friction state in words: `stuck`, `slides`, `swivels` or `slides and swivels`;
    /// `unknown` when the numbers it rests on are not finite.
    pub fn state(&self) -> &'static str {
        if ![self.u, self.slope, self.force, self.moment]
            .iter()
            .all(|v| v.is_finite())
        {
            return "unknown";
        }
        match (self.sliding, self.swivel) {
            (false, false) => "stuck",
            (true, false) => "slides",
            (false, true) => "swivels",
            (true, true) => "slides and swivels",
        }
    }
}

/// Which solution the error is measured against.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Reference {
    /// The closed form (50)–(51).
    ClosedForm,
    /// The flexibility method on the same mesh.
    Flexibility,
    /// This solution is itself the reference; no error is reported.
    #[serde(rename = "self")]
    ThisSolution,
}

/// Nodal error against the reference. The numbers are `None` when this solution is the
/// reference.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ErrorReport {
    pub reference: Reference,
    /// max |u − u_ref| over the nodes [m].
    pub max_abs: Option<f64>,
    /// max |u − u_ref| / max |u_ref|.
    pub max_rel: Option<f64>,
    /// mean |u − u_ref| over the nodes [m] (the paper's err of section 2.8).
    pub mean_abs: Option<f64>,
    /// mean |u − u_ref| / max |u_ref|.
    pub mean_rel: Option<f64>,
    /// max |u' − u'_ref| / max |u'_ref|.
    pub slope_max_rel: Option<f64>,
}

/// Extra facts about how a method ran.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct MethodDetails {
    /// Regularised cases enumerated (9^k).
    pub cases: Option<u64>,
    /// Newton iterations (= factorizations of the condensed system).
    pub newton_iterations: Option<usize>,
    /// Iterations of the box QP.
    pub qp_iterations: Option<usize>,
    /// How many case matrices the reported largest condition number was taken over.
    pub conditioned_cases: Option<usize>,
}

/// A solution with its certificate.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    pub method: Method,
    /// ε used (regularised methods only).
    pub epsilon: Option<f64>,
    /// Nodal u and u'.
    pub field: NodalField,
    pub obstacles: Vec<ObstacleResult>,
    /// Relative KKT residual of (38).
    pub kkt_residual: f64,
    pub timing: Timing,
    pub conditioning: Conditioning,
    pub error: Option<ErrorReport>,
    pub warnings: Vec<Warning>,
    pub details: MethodDetails,
}

impl Solution {
    /// The largest |u| over the nodes [m]; NaN when any is not finite (never a quiet 0).
    pub fn max_deflection(&self) -> f64 {
        let u = &self.field.deflection;
        if u.iter().all(|v| v.is_finite()) {
            u.iter().fold(0.0f64, |m, v| m.max(v.abs()))
        } else {
            f64::NAN
        }
    }

    /// Does the certification carry a warning of this kind?
    pub fn has_warning(&self, code: WarningCode) -> bool {
        self.warnings.iter().any(|w| w.code == code)
    }

    /// Is every reported number finite?
    pub fn is_finite(&self) -> bool {
        self.field
            .deflection
            .iter()
            .chain(&self.field.slope)
            .all(|v| v.is_finite())
            && self
                .obstacles
                .iter()
                .all(|o| o.force.is_finite() && o.moment.is_finite())
    }
}

/// What a method module hands back before the common certification.
pub(crate) struct MethodOutput {
    pub field: NodalField,
    /// (force, moment) per obstacle.
    pub lambda: Vec<[f64; 2]>,
    /// (sliding, swivel) per obstacle.
    pub moving: Vec<[bool; 2]>,
    pub timing: Timing,
    pub warnings: Vec<Warning>,
    pub details: MethodDetails,
    /// cond₂(S), when the method has S and conditioning was asked for.
    pub dual_condition: Option<ConditionNumber>,
    /// Regularised methods: the per-case diagonal additions (DOF index in the friction
    /// vector → g/ε) whose largest condition number is reported.
    pub regularized_cases: Vec<Vec<(usize, f64)>>,
}

/// Solves with `method`, then certifies the answer (KKT residual, friction states, optional
/// condition numbers and reference error, warnings).
pub fn solve(
    problem: &Problem,
    mesh: &Mesh,
    method: Method,
    options: &SolveOptions,
) -> Result<Solution, SolveError> {
    let output = match method {
        Method::Regularized => regularized::solve(problem, mesh, options)?,
        Method::RegularizedNewton => regularized_newton::solve(problem, mesh, options)?,
        Method::DualInverse => dual_inverse::solve(problem, mesh, options)?,
        Method::Dual => dual::solve(problem, mesh, options)?,
        Method::Flexibility => flexibility::solve(problem, mesh, options)?,
        Method::ClosedForm => closed_form::solve(problem, mesh)?,
        Method::Condensed => condensed::solve(problem, mesh, options)?,
    };
    Ok(certify(problem, mesh, method, options, output))
}

fn certify(
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
        details,
        dual_condition,
        regularized_cases,
    } = output;
    let obstacles: Vec<ObstacleResult> = problem
        .obstacles
        .iter()
        .zip(&mesh.obstacle_nodes)
        .zip(lambda.iter().zip(&moving))
        .map(|((o, &node), (l, m))| ObstacleResult {
            x: o.x,
            u: field.deflection[node],
            slope: field.slope[node],
            force: l[0],
            moment: l[1],
            sliding: m[0],
            swivel: m[1],
        })
        .collect();
    let kkt_residual = kkt_residual(problem, mesh, &field, &lambda, &obstacles);

    if mesh.elements() > mesh.requested_elements {
        warnings.insert(
            0,
            Warning::new(
                WarningCode::MeshRaised,
                format!(
                    "{} elements asked for, {} used: every stretch between obstacles, \
                     supports and segment ends needs one",
                    mesh.requested_elements,
                    mesh.elements()
                ),
            ),
        );
    }

    let mut conditioning = Conditioning {
        dual: dual_condition,
        ..Conditioning::default()
    };
    let mut details = details;
    if method.is_regularized() && options.condition != ConditionLevel::Off {
        details.conditioned_cases = Some(regularized_cases.len());
    }
    if method.uses_stiffness_matrix() {
        let (bound, scaled_bound) = stiffness_condition_bounds(mesh);
        if options.condition != ConditionLevel::Off {
            let computed = stiffness_conditioning(mesh, options, &regularized_cases);
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
        solution.error = reference_error(problem, mesh, &solution);
        if let Some(w) = accuracy_warning(&solution) {
            solution.warnings.push(w);
        }
    }
    solution
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
    let exact_possible = mesh.unknowns() <= crate::linalg::condition::DENSE_LIMIT;
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
/// a support, for n from 20 to 5000; 0.02 is typical. DESIGN.md fact 2 is the same law.
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
    let relation = match scaled.kind {
        crate::linalg::condition::ConditionKind::LowerBound => "≥",
        crate::linalg::condition::ConditionKind::Estimate => "≈",
        crate::linalg::condition::ConditionKind::Exact => "=",
    };
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
            "cond(D^-1/2 A D^-1/2) {relation} {:.1e} at n = {}: {consequence}; the flexibility \
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
                    reference_name(error.reference),
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
                reference_name(error.reference)
            ),
        )
    })
}

fn reference_name(reference: Reference) -> &'static str {
    match reference {
        Reference::ClosedForm => "closed-form",
        Reference::Flexibility => "flexibility",
        Reference::ThisSolution => "own",
    }
}

/// The reference nodal field for `problem` on `mesh`: the closed form where it applies, else
/// the flexibility method. `None` only if the flexibility method itself fails.
pub fn reference_field(problem: &Problem, mesh: &Mesh) -> Option<(Reference, NodalField)> {
    if let Ok(exact) = closed_form(problem) {
        return Some((Reference::ClosedForm, exact.nodal_field(mesh)));
    }
    let options = SolveOptions {
        condition: ConditionLevel::Off,
        reference: false,
        ..SolveOptions::default()
    };
    let output = flexibility::solve(problem, mesh, &options).ok()?;
    Some((Reference::Flexibility, output.field))
}

fn reference_error(problem: &Problem, mesh: &Mesh, solution: &Solution) -> Option<ErrorReport> {
    let closed_form_applies = closed_form(problem).is_ok();
    let is_reference = match solution.method {
        Method::ClosedForm => true,
        Method::Flexibility => !closed_form_applies,
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
    let (reference, field) = reference_field(problem, mesh)?;
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

/// Is a friction DOF moving? Its value must stand out of rounding noise: more than
/// `1e-10` times the largest nodal value of its kind.
pub(crate) fn is_moving(value: f64, largest_of_kind: f64) -> bool {
    value.abs() > 1e-10 * largest_of_kind
}

/// (sliding, swivel) for every obstacle from the nodal values at the obstacle nodes.
pub(crate) fn moving_from_values(mesh: &Mesh, field: &NodalField) -> Vec<[bool; 2]> {
    let largest = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let (lu, ls) = (largest(&field.deflection), largest(&field.slope));
    mesh.obstacle_nodes
        .iter()
        .map(|&node| {
            [
                is_moving(field.deflection[node], lu),
                is_moving(field.slope[node], ls),
            ]
        })
        .collect()
}

/// A stopwatch for the stages of a method.
pub(crate) struct Stopwatch(Instant);

impl Stopwatch {
    pub fn start() -> Stopwatch {
        Stopwatch(Instant::now())
    }

    /// Time since the last lap.
    pub fn lap(&mut self) -> Duration {
        let now = Instant::now();
        let elapsed = now - self.0;
        self.0 = now;
        elapsed
    }
}

/// What the three dual methods (`dual`, `dual-inverse`, `flexibility`) hand back once the box
/// QP has given λ and the nodal field is rebuilt: friction states from the nodal values, a
/// warning if the QP did not converge, and cond(S) when asked for.
pub(crate) fn dual_output(
    mesh: &Mesh,
    field: NodalField,
    qp: &crate::linalg::boxqp::QpResult,
    s: &[f64],
    timing: Timing,
    mut warnings: Vec<Warning>,
    options: &SolveOptions,
) -> MethodOutput {
    if !qp.converged {
        warnings.push(Warning::new(
            WarningCode::QpNotConverged,
            format!(
                "the dual QP stopped after {} iterations without meeting its KKT conditions",
                qp.iterations
            ),
        ));
    }
    MethodOutput {
        moving: moving_from_values(mesh, &field),
        field,
        lambda: qp.x.chunks(2).map(|c| [c[0], c[1]]).collect(),
        timing,
        warnings,
        details: MethodDetails {
            qp_iterations: Some(qp.iterations),
            ..MethodDetails::default()
        },
        dual_condition: dual_condition(s, qp.x.len(), options),
        regularized_cases: Vec::new(),
    }
}

/// cond₂(S) of a dense 2k×2k matrix, when asked for.
pub(crate) fn dual_condition(
    s: &[f64],
    dim: usize,
    options: &SolveOptions,
) -> Option<ConditionNumber> {
    (options.condition != ConditionLevel::Off && dim > 0)
        .then(|| dense_condition(s, dim))
        .flatten()
}
