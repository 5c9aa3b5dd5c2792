//! The ε sweep of paper 2.7.1 / Figure 5: for each ε, the regularised solution's nodal error
//! against the reference, the largest 2-norm condition number over the enumerated case
//! matrices Â of (43), the same for their Jacobi scaling, and the run time.

use std::time::Duration;

use serde::Serialize;

use super::{Cancel, Cancelled, Progress};
use crate::fem::Mesh;
use crate::linalg::condition::ConditionNumber;
use crate::model::Problem;
use crate::solve::{ConditionLevel, ErrorReport, Method, SolveError, SolveOptions, Warning, solve};

/// Largest N for which the sweep computes condition numbers (Lanczos beyond N = 200).
pub const CONDITION_LIMIT: usize = 20_000;

/// One ε of the sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EpsPoint {
    pub epsilon: f64,
    /// Error against the reference (closed form or flexibility).
    pub error: Option<ErrorReport>,
    /// Largest cond₂(Â) over the enumerated cases.
    pub cond_max: Option<ConditionNumber>,
    /// Largest cond₂ of the Jacobi-scaled Â.
    pub cond_scaled_max: Option<ConditionNumber>,
    /// How many case matrices the largest condition numbers were taken over.
    pub conditioned_cases: Option<usize>,
    /// Run time of the method's stages.
    #[serde(serialize_with = "seconds")]
    pub run_time: Duration,
    pub warnings: Vec<Warning>,
}

fn seconds<S: serde::Serializer>(d: &Duration, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_f64(d.as_secs_f64())
}

/// `points` values from `from` to `to`, evenly spaced in log10 (from first).
pub fn log_space(from: f64, to: f64, points: usize) -> Vec<f64> {
    if points <= 1 {
        return vec![from];
    }
    let (a, b) = (from.log10(), to.log10());
    (0..points)
        .map(|i| 10f64.powf(a + (b - a) * i as f64 / (points - 1) as f64))
        .collect()
}

/// Why there is no ε sweep where the regularised method fails with `error`: the sweep runs
/// only that method, so a suggestion of another kind (`condensed`) solves the scene but gives
/// no sweep, and is named as such.
pub fn sweep_refusal(error: &SolveError) -> String {
    let failed = format!("{} {}: {}", error.method, error.kind.label(), error.reason);
    if error.suggestion.is_regularized() {
        format!(
            "the ε sweep needs the regularised method: {failed}; the {} method works here",
            error.suggestion
        )
    } else {
        format!(
            "the ε sweep needs the regularised method: {failed}; so this scene has no ε sweep \
             (the {} method solves it, without ε)",
            error.suggestion
        )
    }
}

/// Solves the regularised problem with `method` (the enumeration, or Newton) at every ε.
/// Fails when the method refuses (too many cases); stops early when `cancel` says so.
pub fn epsilon_sweep(
    problem: &Problem,
    elements: usize,
    method: Method,
    epsilons: &[f64],
    cancel: &Cancel,
    progress: Progress,
) -> Result<Result<Vec<EpsPoint>, SolveError>, Cancelled> {
    let mesh = Mesh::new(problem, elements);
    let condition = if mesh.unknowns() <= CONDITION_LIMIT {
        ConditionLevel::Full
    } else {
        ConditionLevel::Off
    };
    let mut points = Vec::with_capacity(epsilons.len());
    for (i, &epsilon) in epsilons.iter().enumerate() {
        if cancel.is_cancelled() {
            return Err(Cancelled);
        }
        progress(i, epsilons.len(), &format!("ε = {epsilon:.1e}"));
        let options = SolveOptions {
            epsilon,
            condition,
            cancel: cancel.clone(),
            ..SolveOptions::default()
        };
        let solution = match solve(problem, &mesh, method, &options) {
            Ok(s) => s,
            Err(e) if e.kind == crate::solve::SolveErrorKind::Cancelled => return Err(Cancelled),
            Err(e) => return Ok(Err(e)),
        };
        points.push(EpsPoint {
            epsilon,
            error: solution.error,
            cond_max: solution.conditioning.regularized_max,
            cond_scaled_max: solution.conditioning.regularized_scaled_max,
            conditioned_cases: solution.details.conditioned_cases,
            run_time: solution.timing.total(),
            warnings: solution.warnings,
        });
    }
    Ok(Ok(points))
}
