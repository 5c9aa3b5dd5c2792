//! The mesh sweep: every method over a range of mesh sizes, with its error against the
//! reference (closed form where it applies, else the flexibility method on the same mesh) and
//! its median run time — the data of the error-against-run-time picture.

use std::time::Duration;

use serde::Serialize;

use super::{Cancel, Cancelled, Progress};
use crate::fem::Mesh;
use crate::model::Problem;
use crate::solve::{
    ConditionLevel, ErrorReport, Method, Reference, SolveErrorKind, SolveOptions, WarningCode,
    solve,
};

/// One method at one mesh size.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeshPoint {
    pub method: Method,
    pub elements: usize,
    /// ε, for the regularised methods.
    pub epsilon: Option<f64>,
    /// Error against the reference; `reference: self` with no numbers for the reference
    /// itself.
    pub error: Option<ErrorReport>,
    /// Median over the repeats of the method's run time (its stages, without certification).
    #[serde(serialize_with = "seconds")]
    pub run_time: Duration,
    pub kkt_residual: Option<f64>,
    pub warnings: Vec<WarningCode>,
    /// Why the method gave no solution here, if it did not.
    pub refused: Option<String>,
}

impl MeshPoint {
    /// Is this point the reference itself (no error to show)?
    pub fn is_reference(&self) -> bool {
        self.error
            .is_some_and(|e| e.reference == Reference::ThisSolution)
    }
}

fn seconds<S: serde::Serializer>(d: &Duration, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_f64(d.as_secs_f64())
}

/// `points` mesh sizes from `from` to `to`, log-spaced and rounded, without repeats.
pub fn mesh_sizes(from: usize, to: usize, points: usize) -> Vec<usize> {
    let mut sizes: Vec<usize> = super::log_space(from.max(1) as f64, to.max(1) as f64, points)
        .into_iter()
        .map(|n| n.round() as usize)
        .collect();
    sizes.dedup();
    sizes
}

/// The largest mesh `dual-inverse` is run at in the error study: its O(N³) cost shows well
/// before.
pub const DENSE_MAX: usize = 400;

/// The error study of the error-vs-run-time panel and `beamfric figure error-time`: every
/// method over `sizes` and the scene's own n (`current`), `dual-inverse` only up to
/// [`DENSE_MAX`].
pub fn error_study(
    problem: &Problem,
    sizes: &[usize],
    current: usize,
    repeat: usize,
    epsilon: f64,
    cancel: &Cancel,
    progress: Progress,
) -> Result<Vec<MeshPoint>, Cancelled> {
    let mut sizes = sizes.to_vec();
    sizes.push(current);
    sizes.sort();
    sizes.dedup();
    let (dense, others): (Vec<Method>, Vec<Method>) = Method::ALL
        .into_iter()
        .partition(|m| *m == Method::DualInverse);
    let small: Vec<usize> = sizes.iter().copied().filter(|&n| n <= DENSE_MAX).collect();
    let mut points = mesh_sweep(problem, &others, &sizes, repeat, epsilon, cancel, progress)?;
    points.extend(mesh_sweep(
        problem, &dense, &small, repeat, epsilon, cancel, progress,
    )?);
    Ok(points)
}

/// Runs each method at each size `repeat` times (median run time). Every (method, size) gets
/// a point; a method that cannot apply at one size is not run again at larger sizes, its
/// points there carry the same reason; a refusal (decided before any work: too many cases,
/// too large a dense matrix) is asked again at each size, so its figures are that size's.
pub fn mesh_sweep(
    problem: &Problem,
    methods: &[Method],
    sizes: &[usize],
    repeat: usize,
    epsilon: f64,
    cancel: &Cancel,
    progress: Progress,
) -> Result<Vec<MeshPoint>, Cancelled> {
    let mut points = Vec::new();
    let mut refused: Vec<Option<String>> = vec![None; methods.len()];
    let total = sizes.len() * methods.len();
    for (s, &n) in sizes.iter().enumerate() {
        let mesh = Mesh::new(problem, n);
        for (m, &method) in methods.iter().enumerate() {
            progress(s * methods.len() + m, total, &format!("{method} n = {n}"));
            if let Some(reason) = &refused[m] {
                points.push(MeshPoint {
                    method,
                    elements: mesh.elements(),
                    epsilon: method.is_regularized().then_some(epsilon),
                    error: None,
                    run_time: Duration::ZERO,
                    kkt_residual: None,
                    warnings: Vec::new(),
                    refused: Some(reason.clone()),
                });
                continue;
            }
            if cancel.is_cancelled() {
                return Err(Cancelled);
            }
            let options = SolveOptions {
                epsilon,
                condition: ConditionLevel::Off,
                cancel: cancel.clone(),
                ..SolveOptions::default()
            };
            let mut times = Vec::with_capacity(repeat.max(1));
            let mut last = None;
            for _ in 0..repeat.max(1) {
                match solve(problem, &mesh, method, &options) {
                    Ok(s) => {
                        times.push(s.timing.total());
                        last = Some(Ok(s));
                    }
                    Err(e) if e.kind == crate::solve::SolveErrorKind::Cancelled => {
                        return Err(Cancelled);
                    }
                    Err(e) => {
                        last = Some(Err(e));
                        break;
                    }
                }
            }
            times.sort();
            let median = times.get(times.len() / 2).copied().unwrap_or_default();
            let epsilon = method.is_regularized().then_some(epsilon);
            match last.expect("at least one run") {
                Ok(s) => points.push(MeshPoint {
                    method,
                    elements: mesh.elements(),
                    epsilon,
                    error: s.error,
                    run_time: median,
                    kkt_residual: Some(s.kkt_residual),
                    warnings: s.warnings.iter().map(|w| w.code).collect(),
                    refused: None,
                }),
                Err(e) => {
                    let reason = format!("{}: {}", e.kind.label(), e.reason);
                    // Too large now means too large at every larger size too: not run again.
                    // A refusal is decided before any work, so it is asked again at each size
                    // and names that size's own figures.
                    if !matches!(e.kind, SolveErrorKind::Breakdown | SolveErrorKind::Refused) {
                        refused[m] = Some(reason.clone());
                    }
                    points.push(MeshPoint {
                        method,
                        elements: mesh.elements(),
                        epsilon,
                        error: None,
                        run_time: Duration::ZERO,
                        kkt_residual: None,
                        warnings: Vec::new(),
                        refused: Some(reason),
                    });
                }
            }
        }
    }
    Ok(points)
}
