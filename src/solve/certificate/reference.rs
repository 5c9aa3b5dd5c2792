//! The reference a solution is graded against ([`MeshReference`]): the closed form (50)–(51)
//! where it applies, else the `condensed` method on the same mesh, solved at most once per
//! [`solve`](crate::solve::solve) call, and the nodal error against it ([`compare`]).

use std::borrow::Cow;
use std::cell::OnceCell;

use crate::fem::{Mesh, NodalField};
use crate::linalg::stop::Stop;
use crate::model::{Method, Problem};
use crate::solve::closed_form::closed_form;
use crate::solve::condensed;
use crate::solve::options::{Cancellation, ConditionLevel, SolveOptions, WarmStart};
use crate::solve::shared::MethodOutput;
use crate::solve::solution::{ErrorReport, FrictionState, Reference, Solution};

/// The reference of one mesh for one [`solve`](crate::solve::solve) call: the closed form where it
/// applies, else the `condensed` method on the same mesh. The condensed method is solved the
/// first time something asks for it (the error against the reference, the alternative named
/// with a non-finite answer, a refusal's suggestion tried, the explorer's reference curve) and
/// kept for the rest of the call: one call solves it at most once.
pub(in crate::solve) struct MeshReference<'a> {
    problem: &'a Problem,
    mesh: &'a Mesh,
    /// Gives up (no reference) when the solve is not wanted any more.
    cancel: Cancellation,
    /// Where the condensed search may start (the solve's own options').
    warm_start: WarmStart,
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
    /// Nothing solved yet; cancelled and started as the solve of `options`.
    pub(in crate::solve) fn new(
        problem: &'a Problem,
        mesh: &'a Mesh,
        options: &SolveOptions,
    ) -> Self {
        MeshReference {
            problem,
            mesh,
            cancel: options.cancel.clone(),
            warm_start: options.warm_start.clone(),
            condensed: OnceCell::new(),
        }
    }

    /// The options of the condensed reference: no condition numbers, no reference of its own.
    fn options(&self) -> SolveOptions {
        SolveOptions {
            condition: ConditionLevel::Off,
            reference: false,
            cancel: self.cancel.clone(),
            warm_start: self.warm_start.clone(),
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
            let cancel = &self.cancel;
            let stop = || cancel.is_cancelled();
            let field = exact.nodal_field_until(self.mesh, &stop).ok()?;
            return Some((Reference::ClosedForm, Cow::Owned(field)));
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

    /// The problem of this reference.
    pub(super) fn problem(&self) -> &'a Problem {
        self.problem
    }

    /// The mesh of this reference.
    pub(super) fn mesh(&self) -> &'a Mesh {
        self.mesh
    }

    /// The condensed method's output on this mesh, trusted or not, and the options of its
    /// certificate (no condition numbers, no reference: it is the reference): the solve already
    /// made if there was one. `None` when it failed or was cancelled.
    pub(super) fn into_condensed_output(self) -> Option<(MethodOutput, SolveOptions)> {
        self.condensed_run();
        let options = self.options();
        let CondensedRun { output, .. } = self.condensed.into_inner().flatten()?;
        Some((output, options))
    }
}

/// The error of `solution` against the reference: none for the reference itself, `None` when
/// there is no trusted reference.
pub(super) fn reference_error(
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
    let (kind, field) = reference.field()?;
    let cancel = &reference.cancel;
    let stop = || cancel.is_cancelled();
    let mut report = compare(kind, &solution.field, &field, problem.length, &stop)?;
    // A reference that is zero at every node: relative to the natural scale f l⁴/EJ instead
    // of an infinite or undefined ratio.
    let largest = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if largest(&field.deflection) == 0.0 && !stop() && largest(&field.slope) == 0.0 {
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
/// suite's independent comparison (tests/it/reference/compare.rs) uses the same rule.
/// `None` when `stop` says so, asked between the passes over the nodes (each a few
/// milliseconds at 10⁷ nodes).
pub(super) fn compare(
    reference: Reference,
    field: &NodalField,
    reference_field: &NodalField,
    length: f64,
    stop: Stop,
) -> Option<ErrorReport> {
    let still_wanted = || (!stop()).then_some(());
    let largest = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let u_largest = largest(&reference_field.deflection);
    still_wanted()?;
    let slope_largest = largest(&reference_field.slope);
    let u_scale = u_largest.max(1e-3 * slope_largest * length);
    let slope_scale = slope_largest.max(1e-3 * u_largest / length);
    let stats = |a: &[f64], b: &[f64], scale: f64| {
        still_wanted()?;
        let finite = a.iter().all(|v| v.is_finite()) && {
            still_wanted()?;
            b.iter().all(|v| v.is_finite())
        };
        if !finite {
            // No error at all rather than one that `max` computed by skipping NaN.
            return Some((f64::NAN, f64::NAN, f64::NAN, f64::NAN));
        }
        still_wanted()?;
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
        Some((max_abs, mean, relative(max_abs), relative(mean)))
    };
    let (max_abs, mean_abs, max_rel, mean_rel) =
        stats(&field.deflection, &reference_field.deflection, u_scale)?;
    let (_, _, slope_rel, _) = stats(&field.slope, &reference_field.slope, slope_scale)?;
    let finite = |v: f64| v.is_finite().then_some(v);
    Some(ErrorReport {
        reference,
        max_abs: finite(max_abs),
        max_rel: finite(max_rel),
        mean_abs: finite(mean_abs),
        mean_rel: finite(mean_rel),
        slope_max_rel: finite(slope_rel),
    })
}
