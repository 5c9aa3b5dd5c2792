//! The certificate [`solve`](crate::solve::solve) attaches to every method's answer, the same way for
//! every method: the relative KKT residual of (38), the friction state of every obstacle,
//! condition numbers when asked, the error against a reference (the closed form (50) where it
//! applies, else the `condensed` method on the same mesh) and warnings in words. The reference
//! of one mesh ([`MeshReference`]) is solved at most once per [`solve`](crate::solve::solve) call,
//! whoever asks for it first.

use std::borrow::Cow;
use std::cell::OnceCell;

use crate::solve::closed_form::closed_form;
use crate::solve::condensed;
mod equilibrium;

use crate::fem::{Mesh, NodalField, StiffnessMatrix, stiffness_condition_bounds};
use crate::linalg::BlockMatrix;
use crate::linalg::condition::{
    ConditionKind, ConditionNumber, DENSE_LIMIT, block_condition, jacobi_scaled,
};
use crate::model::{Method, Problem};
use crate::solve::options::{Cancellation, ConditionLevel, SolveOptions};
use crate::solve::shared::MethodOutput;
use crate::solve::solution::{
    Conditioning, ErrorReport, FrictionState, ObstacleResult, Reference, Solution, Warning,
    WarningCode,
};
use equilibrium::{Equilibrium, Judging};

/// Certifies a method's `output`. `reference` grades it (and names the alternative of a
/// non-finite answer); `None` only for the condensed reference's own certificate, which asks
/// for no reference (method `condensed`, `options.reference` off).
pub(super) fn certify(
    problem: &Problem,
    mesh: &Mesh,
    method: Method,
    options: &SolveOptions,
    output: MethodOutput,
    reference: Option<&MeshReference>,
) -> Solution {
    let MethodOutput {
        field,
        lambda,
        states: method_states,
        timing,
        mut warnings,
        mut details,
        dual_condition,
        regularized_cases,
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
        );
    }
    let judging = Judging {
        motion_resolution: motion_resolution(problem, method, stiffness_scaled),
        epsilon: method.is_regularized().then_some(options.epsilon),
    };
    let Equilibrium {
        residual: kkt_residual,
        mut states,
        unresolved_force,
    } = equilibrium::check(problem, mesh, &field, &lambda, judging);
    // Where the returned values fit both descriptions, the method's own finer decision.
    if let Some(method_states) = method_states {
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
    let obstacles = obstacle_results(problem, mesh, &field, &lambda, &states);
    if let Some(w) = kkt_warning(kkt_residual, method) {
        warnings.push(w);
    }
    if let Some(epsilon) = judging.epsilon
        && unresolved_force > REGULARIZED_WARNING
    {
        warnings.push(Warning::new(
            WarningCode::AccuracyLoss,
            format!(
                "inside ε = {epsilon:e} a friction force is g·c/ε, and this method resolves c \
                 only well enough to know such a force to {unresolved_force:.1e} of the largest \
                 force of its kind: digits lost to rounding; a larger ε, or the condensed \
                 method, works here"
            ),
        ));
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
    debug_assert!(
        reference.is_some() || (method == Method::Condensed && !options.reference),
        "only the condensed reference's own certificate goes without a reference"
    );
    judge_solution(problem, options, &mut solution, reference);
    solution
}

/// The checks on the assembled solution: the non-finite warning first, then the error
/// against the reference and the accuracy warning.
fn judge_solution(
    problem: &Problem,
    options: &SolveOptions,
    solution: &mut Solution,
    reference: Option<&MeshReference>,
) {
    if !solution.is_finite() || !solution.kkt_residual.is_finite() {
        // Name a method that works only when it does: the condensed method certified itself.
        let works =
            solution.method != Method::Condensed && reference.is_some_and(|r| r.field().is_some());
        let alternative = if works {
            "; the condensed method works here"
        } else {
            ""
        };
        // First: it is what matters most about this solution.
        solution.warnings.insert(
            0,
            Warning::new(
                WarningCode::NonFinite,
                format!(
                    "the solution contains NaN or infinite values: an input is out of \
                     floating-point range for this method; no number is shown{alternative}"
                ),
            ),
        );
    }
    if let (true, Some(reference)) = (options.reference, reference) {
        solution.error = reference_error(problem, solution, reference);
        if solution.error.is_none() && !options.cancel.is_cancelled() {
            solution.warnings.push(Warning::new(
                WarningCode::UntrustedReference,
                "no trusted reference: the condensed method did not certify itself on this \
                 scene (its friction search did not converge), so no error is reported",
            ));
        }
        if let Some(w) = accuracy_warning(solution, problem) {
            solution.warnings.push(w);
        }
        if let Some(w) = force_warning(solution, problem, reference) {
            solution.warnings.push(w);
        }
    }
}

/// Relative difference of an exact method's friction forces from the reference's above which
/// it is reported: the forces are what the nodal check cannot always resolve (next to a piece
/// 3e10 times stiffer, the split of a moment between its ends is a difference of nearly equal
/// nodal terms), so they are compared with the reference directly.
const FORCE_WARNING: f64 = 1e-10;

/// The friction forces and states of an exact method against the reference's: the forces
/// per kind relative to max(max |λ_ref|, |f|·l) for forces and max(max |λ_ref|, |f|·l²) for
/// moments, the states wherever both decide them (neither is at the threshold).
fn force_warning(
    solution: &Solution,
    problem: &Problem,
    reference: &MeshReference,
) -> Option<Warning> {
    let graded = solution
        .error
        .is_some_and(|e| e.reference != Reference::ThisSolution);
    if solution.method.is_regularized()
        || solution.method == Method::Condensed
        || !graded
        || !solution.is_finite()
    {
        // A regularised method's forces differ below ε by design (its accuracy warning
        // speaks for it); the condensed method is where these come from.
        return None;
    }
    let (exact, exact_states) = reference.friction()?;
    let load = problem.load.f0.abs().max(problem.load.f1.abs());
    let l = problem.length;
    let mut worst = 0.0f64;
    for (kind, natural) in [(0, load * l), (1, load * l * l)] {
        let scale = exact
            .iter()
            .fold(natural, |m, pair| m.max(pair[kind].abs()));
        for (o, pair) in solution.obstacles.iter().zip(&exact) {
            let value = if kind == 0 { o.force } else { o.moment };
            let difference = (value - pair[kind]).abs();
            if difference > 0.0 {
                worst = worst.max(if scale > 0.0 {
                    difference / scale
                } else {
                    f64::INFINITY
                });
            }
        }
    }
    let reference_name = Reference::Condensed.name();
    // Friction states that both decide, differently.
    let mut differing = Vec::new();
    for (j, (o, states)) in solution.obstacles.iter().zip(exact_states).enumerate() {
        for (kind, own, exact) in [
            ("slides", o.sliding_state, states[0]),
            ("swivels", o.swivel_state, states[1]),
        ] {
            let decided = |s: FrictionState| s != FrictionState::AtThreshold;
            if decided(own) && decided(exact) && own != exact {
                let says = |s: FrictionState| {
                    if s == FrictionState::Moves {
                        "yes"
                    } else {
                        "no"
                    }
                };
                differing.push(format!(
                    "obstacle {} {kind}: {} here, {} in the reference",
                    j + 1,
                    says(own),
                    says(exact)
                ));
            }
        }
    }
    let mut causes = Vec::new();
    if worst > FORCE_WARNING {
        causes.push(format!(
            "the friction forces differ from the {reference_name} reference by {worst:.1e} \
             (relative to the largest force of each kind)"
        ));
    }
    if let Some(first) = differing.first() {
        causes.push(format!(
            "{} friction state{} differ{} from the {reference_name} reference ({first})",
            differing.len(),
            if differing.len() == 1 { "" } else { "s" },
            if differing.len() == 1 { "s" } else { "" },
        ));
    }
    (!causes.is_empty()).then(|| {
        Warning::new(
            WarningCode::AccuracyLoss,
            format!(
                "{}: digits lost to rounding; the condensed method works here",
                causes.join("; ")
            ),
        )
    })
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
) -> (Conditioning, Option<ConditionNumber>) {
    let (bound, scaled_bound) = stiffness_condition_bounds(mesh);
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
    (conditioning, scaled)
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
/// about 1e-14 on ordinary scenes (1e-12 for margin).
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

/// Relative KKT residual (checked piece by piece, `equilibrium`) above which the answer is
/// reported as not satisfying (38): an exact solution rounded to double gives a few ulps.
const KKT_WARNING: f64 = 1e-10;

fn kkt_warning(residual: f64, method: Method) -> Option<Warning> {
    // The condensed method is the one named as accurate elsewhere: when it fails the check
    // itself, naming it again would be false.
    let advice = if method == Method::Condensed {
        "this is the condensed method itself, the most accurate the program has: treat its \
         numbers as approximate here"
    } else {
        "the condensed method stays accurate"
    };
    (residual > KKT_WARNING).then(|| {
        Warning::new(
            WarningCode::KktResidual,
            format!(
                "the KKT conditions of (38), checked piece by piece from the exact solution of \
                 every stretch between special points, fail by {residual:.1e} (relative): the \
                 answer is not the solution of the discrete problem to that accuracy; {advice}"
            ),
        )
    })
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
/// wrong (the acceptance bound of issue 10: every exact method agrees to 1e-10 or warns).
const ACCURACY_WARNING: f64 = 1e-10;

fn accuracy_warning(solution: &Solution, problem: &Problem) -> Option<Warning> {
    let error = solution.error?;
    // u and u' both count: a slope off by 2e-8 with u right is still a wrong answer.
    let rel = match (error.max_rel, error.slope_max_rel) {
        (Some(u), Some(slope)) => u.max(slope),
        (u, slope) => u.or(slope)?,
    };
    if let (true, Some(epsilon)) = (solution.method.is_regularized(), solution.epsilon) {
        // What ε explains: a stuck DOF of the ε-problem moves by up to ε (m or rad), which
        // moves the nodes by about ε·max(1, l) (docs/design.md fact 4: 0.0097·ε on average on
        // Benchmark 1); 4 for margin.
        let explained = 4.0 * epsilon * problem.length.max(1.0);
        let abs = error.max_abs.unwrap_or(f64::INFINITY);
        if rel <= ACCURACY_WARNING || (rel <= REGULARIZED_WARNING && abs <= explained) {
            return None;
        }
        let cause = if abs <= explained {
            format!(
                "the regularisation alone explains it: it moves the nodes by up to about \
                 4·ε·max(1, l) = {explained:.1e} m, here {abs:.1e} m against max |u| of the \
                 reference; a smaller ε or an exact method (condensed) removes it"
            )
        } else {
            format!(
                "more than ε = {epsilon:e} explains ({abs:.1e} m against about \
                 {explained:.1e} m): digits lost to rounding or a wrong regularised case; the \
                 condensed method works here"
            )
        };
        return Some(Warning::new(
            WarningCode::AccuracyLoss,
            format!(
                "the regularised solution is {rel:.1e} (relative, u or u') from the {} \
                 reference: {cause}",
                error.reference.name()
            ),
        ));
    }
    (rel > ACCURACY_WARNING || !rel.is_finite()).then(|| {
        Warning::new(
            WarningCode::AccuracyLoss,
            format!(
                "{rel:.1e} relative error (u or u') against the {} reference: digits lost \
                 to rounding",
                error.reference.name()
            ),
        )
    })
}

/// Relative error of a regularised solution above which it is reported even when ε explains
/// it (the acceptance bound of issue 10 for the ε-problem).
const REGULARIZED_WARNING: f64 = 1e-8;

/// The reference nodal field for `problem` on `mesh`: the closed form where it applies, else
/// the condensed method. `None` only if the condensed method itself fails.
pub fn reference_field(problem: &Problem, mesh: &Mesh) -> Option<(Reference, NodalField)> {
    MeshReference::new(problem, mesh, Cancellation::NEVER)
        .field()
        .map(|(reference, field)| (reference, field.into_owned()))
}

/// The reference of one mesh for one [`solve`](crate::solve::solve) call: the closed form where it
/// applies, else the `condensed` method on the same mesh. The condensed method is solved the
/// first time something asks for it (the error against the reference, the alternative named
/// with a non-finite answer, a refusal's suggestion tried, the explorer's reference curve) and
/// kept for the rest of the call: one call solves it at most once.
pub(super) struct MeshReference<'a> {
    problem: &'a Problem,
    mesh: &'a Mesh,
    /// Gives up (no reference) when the solve is not wanted any more.
    cancel: Cancellation,
    /// The condensed method's output and whether it certified itself; `None` inside: it
    /// failed or was cancelled.
    condensed: OnceCell<Option<CondensedRun>>,
}

/// The reference's (force, moment) and (sliding, swivel) states per obstacle.
pub(super) type ReferenceFriction = (Vec<[f64; 2]>, Vec<[FrictionState; 2]>);

/// The condensed method's answer, before its own certificate.
struct CondensedRun {
    output: MethodOutput,
    /// It certified itself (no warning of its own, every value finite): only then does it
    /// grade another method.
    trusted: bool,
}

impl<'a> MeshReference<'a> {
    /// Nothing solved yet.
    pub(super) fn new(problem: &'a Problem, mesh: &'a Mesh, cancel: Cancellation) -> Self {
        MeshReference {
            problem,
            mesh,
            cancel,
            condensed: OnceCell::new(),
        }
    }

    /// The options of the condensed reference: no condition numbers, no reference of its own.
    fn options(&self) -> SolveOptions {
        SolveOptions {
            condition: ConditionLevel::Off,
            reference: false,
            cancel: self.cancel.clone(),
            ..SolveOptions::default()
        }
    }

    /// The condensed method's run, solved now if nothing asked for it yet.
    fn condensed_run(&self) -> Option<&CondensedRun> {
        self.condensed
            .get_or_init(|| {
                let output = condensed::solve(self.problem, self.mesh, &self.options()).ok()?;
                let trusted = output.warnings.is_empty()
                    && output
                        .field
                        .deflection
                        .iter()
                        .chain(&output.field.slope)
                        .all(|v| v.is_finite());
                Some(CondensedRun { output, trusted })
            })
            .as_ref()
    }

    /// The reference nodal field: the closed form's where it applies, else the condensed
    /// method's if it certified itself. `None` when it did not, failed or was cancelled.
    pub(super) fn field(&self) -> Option<(Reference, Cow<'_, NodalField>)> {
        if let Ok(exact) = closed_form(self.problem) {
            return Some((
                Reference::ClosedForm,
                Cow::Owned(exact.nodal_field(self.mesh)),
            ));
        }
        let run = self.condensed_run()?;
        run.trusted
            .then_some((Reference::Condensed, Cow::Borrowed(&run.output.field)))
    }

    /// The reference friction forces (force, moment) and states per obstacle: the condensed
    /// method's when it certified itself, also where the closed form applies (that formula
    /// decides a state in f64 from a difference of nearly equal terms and was seen to call a
    /// swivelling obstacle stuck; the condensed method decides in double-double).
    pub(super) fn friction(&self) -> Option<ReferenceFriction> {
        let run = self.condensed_run()?;
        let states = run.output.states.clone()?;
        run.trusted.then(|| (run.output.lambda.clone(), states))
    }

    /// The condensed method's certified solution on this mesh, trusted or not, without a
    /// reference of its own (it is the reference): the solve already made if there was one.
    /// `None` when it failed or was cancelled.
    pub(super) fn into_condensed(self) -> Option<Solution> {
        self.condensed_run();
        let options = self.options();
        let CondensedRun { output, .. } = self.condensed.into_inner().flatten()?;
        let solution = certify(
            self.problem,
            self.mesh,
            Method::Condensed,
            &options,
            output,
            None,
        );
        // As any solve: a result no longer wanted is none.
        (!self.cancel.is_cancelled()).then_some(solution)
    }
}

fn reference_error(
    problem: &Problem,
    solution: &Solution,
    reference: &MeshReference,
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
    let (reference, field) = reference.field()?;
    let mut report = compare(reference, &solution.field, &field, problem.length);
    // A reference that is zero at every node: relative to the natural scale f l⁴/EJ instead
    // of an infinite or undefined ratio.
    let largest = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if largest(&field.deflection) == 0.0 && largest(&field.slope) == 0.0 {
        let l = problem.length;
        let load = problem.load.f0.abs().max(problem.load.f1.abs());
        let stiffest = problem
            .stiffness
            .iter()
            .fold(0.0f64, |m, p| m.max(p.bending_stiffness));
        let natural = load * l.powi(4) / stiffest;
        let (u_err, slope_err) = (
            largest(&solution.field.deflection),
            largest(&solution.field.slope),
        );
        let relative = |e: f64, scale: f64| {
            if e == 0.0 {
                Some(0.0)
            } else {
                Some(e / scale).filter(|v| v.is_finite())
            }
        };
        report.max_rel = relative(u_err, natural);
        report.mean_rel = report.mean_abs.and_then(|m| relative(m, natural));
        report.slope_max_rel = relative(slope_err, natural / l);
    }
    Some(report)
}

/// Nodal error of `field` against `reference_field`, on a beam of `length` l.
///
/// Relative errors are relative to max |u_ref| and max |u'_ref|, each guarded by 1e-3 of the
/// other kind's natural size (max |u'_ref|·l, max |u_ref|/l): where every node sits where the
/// beam is nearly flat (a node at the middle of a nearly symmetric scene, where u' is 1e-8 of
/// u/l), the slopes are a cancellation that f64 values of u at the ends of a piece resolve
/// only to ulps of u/l, and a ratio to them would call that rounding "lost digits". The test
/// suite's independent comparison (tests/reference/compare.rs) uses the same rule.
pub fn compare(
    reference: Reference,
    field: &NodalField,
    reference_field: &NodalField,
    length: f64,
) -> ErrorReport {
    let largest = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let (u_largest, slope_largest) = (
        largest(&reference_field.deflection),
        largest(&reference_field.slope),
    );
    let u_scale = u_largest.max(1e-3 * slope_largest * length);
    let slope_scale = slope_largest.max(1e-3 * u_largest / length);
    let stats = |a: &[f64], b: &[f64], scale: f64| {
        if !a.iter().chain(b).all(|v| v.is_finite()) {
            // No error at all rather than one that `max` computed by skipping NaN.
            return (f64::NAN, f64::NAN, f64::NAN, f64::NAN);
        }
        let (mut max_abs, mut sum) = (0.0f64, 0.0f64);
        for (x, y) in a.iter().zip(b) {
            let d = (x - y).abs();
            max_abs = max_abs.max(d);
            sum += d;
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
        stats(&field.deflection, &reference_field.deflection, u_scale);
    let (_, _, slope_rel, _) = stats(&field.slope, &reference_field.slope, slope_scale);
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
