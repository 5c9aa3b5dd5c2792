//! The warnings of the certificate, in words: a raised mesh, A's conditioning, the KKT
//! residual of (38), values out of floating-point range, an untrusted reference, and the
//! accuracy against the reference (nodal values, friction forces and states, the regularised
//! forces inside ε).

use super::reference::MeshReference;
use crate::fem::Mesh;
use crate::linalg::condition::ConditionNumber;
use crate::model::{Method, Problem};
use crate::solve::solution::{FrictionState, Reference, Solution, Warning, WarningCode};

/// The mesh has more elements than asked for.
pub(super) fn mesh_raised_warning(mesh: &Mesh) -> Option<Warning> {
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

/// Relative KKT residual (checked piece by piece, `equilibrium`) above which the answer is
/// reported as not satisfying (38): an exact solution rounded to double gives a few ulps.
const KKT_WARNING: f64 = 1e-10;

pub(super) fn kkt_warning(residual: f64, method: Method) -> Option<Warning> {
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
                 every stretch between special points, fail by {} (relative): the answer is \
                 {}; {advice}",
                crate::format::sci(residual, 2),
                crate::solve::KktGrade::of(residual).meaning()
            ),
        )
    })
}

/// The solution has values that are not finite; `condensed_works` when the condensed method
/// certified itself on this scene (it is then named).
pub(super) fn non_finite_warning(condensed_works: bool) -> Warning {
    let alternative = if condensed_works {
        "; the condensed method works here"
    } else {
        ""
    };
    Warning::new(
        WarningCode::NonFinite,
        format!(
            "the solution contains NaN or infinite values: an input is out of \
             floating-point range for this method; no number is shown{alternative}"
        ),
    )
}

/// The condensed reference did not certify itself, so no error is reported.
pub(super) fn untrusted_reference_warning() -> Warning {
    Warning::new(
        WarningCode::UntrustedReference,
        "no trusted reference: the condensed method did not certify itself on this \
         scene (its friction search did not converge), so no error is reported",
    )
}

/// The stiffness route's relative nodal error divided by cond₂(D^{-1/2} A D^{-1/2})·eps, the
/// Jacobi-scaled condition number (unit-invariant), was measured between 1.6e-3 and 6.5e-2 on
/// Benchmarks 1 and 3, the tiny and huge beams, the modulus contrast and the obstacle next to
/// a support, for n from 20 to 5000; 0.02 is typical. docs/design.md (fact 2) is the same law.
const ROUNDING_PER_CONDITION: f64 = 0.02;

/// Predicted relative error above which the stiffness route is reported as losing digits
/// visibly (the same threshold as [`ACCURACY_WARNING`]).
const CONDITIONING_WARNING: f64 = 1e-8;

pub(super) fn conditioning_warning(scaled: ConditionNumber, mesh: &Mesh) -> Option<Warning> {
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

pub(super) fn accuracy_warning(solution: &Solution, problem: &Problem) -> Option<Warning> {
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
                "the regularised solution is {} from the {} reference: {cause}",
                relative_errors(&error),
                error.reference.name()
            ),
        ));
    }
    (rel > ACCURACY_WARNING || !rel.is_finite()).then(|| {
        Warning::new(
            WarningCode::AccuracyLoss,
            format!(
                "{} from the {} reference: digits lost to rounding",
                relative_errors(&error),
                error.reference.name()
            ),
        )
    })
}

/// The relative errors in u and in u' in words, each as the status line prints the first
/// (two digits): `8.5e-7 in u and 1.2e-6 in u' (relative)`, so that the status line's
/// `error 8.5e-7` is found in the warning, named.
fn relative_errors(error: &crate::solve::ErrorReport) -> String {
    let parts: Vec<String> = [(error.max_rel, "u"), (error.slope_max_rel, "u'")]
        .into_iter()
        .filter_map(|(value, name)| Some(format!("{} in {name}", crate::format::sci(value?, 2))))
        .collect();
    format!("{} (relative)", parts.join(" and "))
}

/// Relative error of a regularised solution above which it is reported even when ε explains
/// it (the acceptance bound of issue 10 for the ε-problem).
const REGULARIZED_WARNING: f64 = 1e-8;

/// A regularised method with ε = `epsilon` whose forces inside ε are known only to
/// `unresolved_force` of the largest force of their kind (`equilibrium`), when that is more
/// than [`REGULARIZED_WARNING`].
pub(super) fn unresolved_force_warning(epsilon: f64, unresolved_force: f64) -> Option<Warning> {
    (unresolved_force > REGULARIZED_WARNING).then(|| {
        Warning::new(
            WarningCode::AccuracyLoss,
            format!(
                "inside ε = {epsilon:e} a friction force is g·c/ε, and this method resolves c \
                 only well enough to know such a force to {unresolved_force:.1e} of the largest \
                 force of its kind: digits lost to rounding; a larger ε, or the condensed \
                 method, works here"
            ),
        )
    })
}

/// Relative difference of an exact method's friction forces from the reference's above which
/// it is reported: the forces are what the nodal check cannot always resolve (next to a piece
/// 3e10 times stiffer, the split of a moment between its ends is a difference of nearly equal
/// nodal terms), so they are compared with the reference directly.
const FORCE_WARNING: f64 = 1e-10;

/// The friction forces and states of an exact method against the reference's: the forces
/// per kind relative to max(max |λ_ref|, |f|·l) for forces and max(max |λ_ref|, |f|·l²) for
/// moments, the states wherever both decide them (neither is at the threshold).
pub(super) fn force_warning(
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
