//! The many-obstacle cases of `beamfric check` (issue 26): each family of `families` at
//! k = 1000 and 4000 on 10⁴ elements. Every other method refuses more than 512 obstacles (its
//! dense 2k × 2k matrices) and names `condensed`, so a case runs the condensed method, judged
//! on its own certificate: finite, converged, no warning, KKT residual within
//! [`MANY_KKT_TOLERANCE`].

use super::families::{Family, family_scene};
use super::{CaseReport, MethodRun, options, summarize};
use crate::fem::Mesh;
use crate::solve::{Method, solve};

/// Obstacle counts of the many-obstacle cases.
pub const MANY_SIZES: [usize; 2] = [1000, 4000];

/// Elements of the many-obstacle cases.
const MANY_ELEMENTS: usize = 10_000;

/// The seed of every many-obstacle case.
const MANY_SEED: u64 = 1;

/// KKT residual the condensed method must reach (relative, as the certificate reports it).
const MANY_KKT_TOLERANCE: f64 = 1e-10;

/// The many-obstacle cases, every family at every size of [`MANY_SIZES`].
pub fn check_families() -> Vec<CaseReport> {
    Family::ALL
        .iter()
        .flat_map(|&family| MANY_SIZES.map(|k| check_family(family, k)))
        .collect()
}

/// One many-obstacle case.
pub fn check_family(family: Family, k: usize) -> CaseReport {
    let case = format!("{} k={k}", family.name());
    let mut report = CaseReport::empty(&case, MANY_ELEMENTS);
    let scene = family_scene(family, k, MANY_SEED, MANY_ELEMENTS);
    let (problem, settings) = match scene.validate(&case) {
        Ok(valid) => valid,
        Err(e) => {
            report.failures.push(format!("does not validate: {e}"));
            return report;
        }
    };
    let mesh = Mesh::new(&problem, settings.elements);
    report.elements = mesh.elements();
    let reference = match solve(
        &problem,
        &mesh,
        Method::Condensed,
        &options(settings.epsilon),
    ) {
        Ok(s) => s,
        Err(e) => {
            report.failures.push(format!("condensed failed: {e}"));
            return report;
        }
    };
    if !reference.is_finite() {
        report
            .failures
            .push("condensed: NaN or infinite values".into());
        return report;
    }
    for warning in &reference.warnings {
        report
            .failures
            .push(format!("condensed warns: {}", warning.message));
    }
    if reference.kkt_residual.is_nan() || reference.kkt_residual > MANY_KKT_TOLERANCE {
        report.failures.push(format!(
            "condensed: KKT residual {:e} above {MANY_KKT_TOLERANCE:e}",
            reference.kkt_residual
        ));
    }
    report.runs.push(MethodRun {
        method: Method::Condensed,
        outcome: "solved".into(),
        disagreement: Some(0.0),
        kkt_residual: Some(reference.kkt_residual),
        flagged: false,
        warnings: reference.warnings.iter().map(|w| w.code).collect(),
    });
    summarize(&mut report);
    report
}
