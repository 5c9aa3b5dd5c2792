//! What the method modules share: the [`MethodOutput`] they hand to the certificate, a
//! stopwatch for their stages, the refusal of dense 2k × 2k matrices on too many obstacles,
//! cancellation, and the common ending of the three dual methods (the box QP of (49)).

use std::sync::Arc;
use std::time::{Duration, Instant};

use super::condensed::pattern::FrictionPattern;
use super::friction_accuracy::{EntryErrors, FrictionAccuracy, friction_accuracy};
use super::history::{History, ProgressMeasure, Recorder};
use super::options::{ConditionLevel, SolveOptions};
use super::solution::{FrictionState, MethodDetails, Timing, Warning, WarningCode};
use crate::fem::NodalField;
use crate::linalg::boxqp::{QpObserver, QpResult, solve_box_qp_observed};
use crate::linalg::condition::{ConditionNumber, dense_condition_until};

/// What a method module hands back before the common certification.
pub(crate) struct MethodOutput {
    pub field: NodalField,
    /// (force, moment) per obstacle. The friction states are the certificate's to decide.
    pub lambda: Vec<[f64; 2]>,
    /// The method's own friction states, when it resolved them beyond what the returned f64
    /// values show (the condensed method decides in double-double). The certificate uses one
    /// only where its independent check finds the DOF at the threshold within rounding, i.e.
    /// where both descriptions fit the returned values; it never overrides a state the check
    /// decides.
    pub states: Option<Vec<[FrictionState; 2]>>,
    pub timing: Timing,
    pub warnings: Vec<Warning>,
    pub details: MethodDetails,
    /// cond₂(S), when the method has S and conditioning was asked for.
    pub dual_condition: Option<ConditionNumber>,
    /// Regularised methods: the per-case diagonal additions (DOF index in the friction
    /// vector → g/ε) whose largest condition number is reported.
    pub regularized_cases: Vec<Vec<(usize, f64)>>,
    /// The dual methods: how far their friction stage may be off at every DOF, for the
    /// certificate to judge the states with (`None` for the others, and when the QP's free
    /// block is not positive definite).
    pub friction_accuracy: Option<FrictionAccuracy>,
    /// The convergence history, when asked for and the method iterates.
    pub history: Option<History>,
    /// `condensed`: its final friction pattern, for a warm start of the next solve.
    pub friction_pattern: Option<Arc<FrictionPattern>>,
}

/// Most obstacles for the methods that work with dense 2k × 2k matrices on the friction DOFs
/// (`dual`, `dual-inverse`, `flexibility`, `regularized-newton`): 1024² doubles = 8 MB, and the
/// box QP's cost grows like k³ beyond. The condensed method has no such limit.
const MAX_DENSE_OBSTACLES: usize = 512;

/// Refuses a method with dense 2k × 2k matrices on more than [`MAX_DENSE_OBSTACLES`].
pub(crate) fn refuse_many_obstacles(
    problem: &crate::model::Problem,
    method: crate::model::Method,
) -> Result<(), super::solution::SolveError> {
    let k = problem.obstacles.len();
    if k <= MAX_DENSE_OBSTACLES {
        return Ok(());
    }
    let dim = 2 * k;
    Err(super::solution::SolveError {
        method,
        kind: super::solution::SolveErrorKind::Refused,
        reason: format!(
            "{k} obstacles need a dense {dim} × {dim} matrix ({:.0} MB) and a box QP whose \
             cost grows like k³; the limit is {MAX_DENSE_OBSTACLES} obstacles",
            (dim * dim * 8) as f64 / 1e6
        ),
        suggestion: crate::model::Method::Condensed,
    })
}

/// The error of a solve stopped by its [`super::options::Cancellation`].
pub(crate) fn cancelled(method: crate::model::Method) -> super::solution::SolveError {
    super::solution::SolveError {
        method,
        kind: super::solution::SolveErrorKind::Cancelled,
        reason: "a newer request replaced it".into(),
        suggestion: method,
    }
}

/// Stops with [`cancelled`] when the solve is no longer wanted.
pub(crate) fn check_cancel(
    options: &SolveOptions,
    method: crate::model::Method,
) -> Result<(), super::solution::SolveError> {
    if options.cancel.is_cancelled() {
        Err(cancelled(method))
    } else {
        Ok(())
    }
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
/// QP has given λ and the nodal field is rebuilt: a warning if the QP did not converge, cond(S)
/// when asked for, and the accuracy of the friction stage from S, z0 (`dual`) and the entry
/// errors the method measured itself (`lost`).
pub(crate) fn dual_output(
    field: NodalField,
    (qp, s, z0): (&QpResult, &[f64], &[f64]),
    lost: Option<&EntryErrors>,
    (timing, mut warnings): (Timing, Vec<Warning>),
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
        field,
        lambda: qp.x.chunks(2).map(|c| [c[0], c[1]]).collect(),
        states: None,
        timing,
        warnings,
        details: MethodDetails {
            qp_iterations: Some(qp.iterations),
            ..MethodDetails::default()
        },
        dual_condition: dual_condition(s, qp.x.len(), options),
        regularized_cases: Vec::new(),
        // A cancelled solve ends right after the method: no account is needed then.
        friction_accuracy: friction_accuracy(s, z0, qp, lost, &|| options.cancel.is_cancelled())
            .unwrap_or(None),
        // The caller's recorder, if any, sets it.
        history: None,
        friction_pattern: None,
    }
}

/// The box QP of (49) for the three dual methods, recording its iterates when
/// [`SolveOptions::history`] asks for it: the answer and the history.
pub(crate) fn dual_box_qp(
    (s, z0, g): (&[f64], &[f64], &[f64]),
    method: crate::model::Method,
    options: &SolveOptions,
) -> (QpResult, Option<History>) {
    let stop = || options.cancel.is_cancelled();
    let mut recorder = Recorder::when(options.history, method, ProgressMeasure::ProjectedGradient);
    let observer = recorder.as_mut().map(|r| r as &mut dyn QpObserver);
    let qp = solve_box_qp_observed(s, z0, g, &stop, observer);
    (qp, recorder.map(Recorder::finish))
}

/// cond₂(S) of a dense 2k×2k matrix, when asked for. A cancelled solve gets none, and
/// `solve` turns it into the cancelled error right after the method.
pub(crate) fn dual_condition(
    s: &[f64],
    dim: usize,
    options: &SolveOptions,
) -> Option<ConditionNumber> {
    let stop = || options.cancel.is_cancelled();
    (options.condition != ConditionLevel::Off && dim > 0)
        .then(|| dense_condition_until(s, dim, &stop).unwrap_or(None))
        .flatten()
}
