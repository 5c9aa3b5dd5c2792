//! The program's methods run and judged against the reference: the one part of the harness
//! that calls `beamfric::solve` (the tests of `tests/it/reference_check/` and the tools of
//! `benches/reference.rs` share it).

use std::panic::{AssertUnwindSafe, catch_unwind};

use beamfric::fem::Mesh;
use beamfric::model::Problem;
use beamfric::scene::Scene;
use beamfric::solve::{Method, Solution, SolveOptions, solve};

use super::compare::{FIELD_TOLERANCE, FORCE_TOLERANCE, compare};
use super::scenes::problem_of;
use super::solver::solve_reference;

/// The method that must agree with the reference on every scene (issue 10's stable method).
pub const STABLE_METHOD: Method = Method::Condensed;

/// Agreement bound of the regularised methods with the ε-reference (issue 10: "the
/// regularised methods agree with the exact ε-solution to 1e-8 or warn").
pub const REGULARIZED_TOLERANCE: f64 = 1e-8;

/// The environment variable `name` as a number, `default` when unset or not a number.
pub fn env_number(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// The program's solution by `method`, or why there is none.
pub fn run_method(
    problem: &Problem,
    mesh: &Mesh,
    method: Method,
    options: &SolveOptions,
) -> Result<Solution, String> {
    match catch_unwind(AssertUnwindSafe(|| solve(problem, mesh, method, options))) {
        Ok(Ok(solution)) => Ok(solution),
        Ok(Err(e)) => Err(format!("refused: {e}")),
        Err(_) => Err("panicked".to_string()),
    }
}

/// The stable method on one scene: within the acceptance bounds, right flags, no warnings.
pub fn check_stable(name: &str, scene: &Scene) -> Result<(), String> {
    let (p, n) = problem_of(scene);
    let mesh = Mesh::new(&p, n);
    let r = solve_reference(&p, n);
    let solution = run_method(&p, &mesh, STABLE_METHOD, &SolveOptions::default())
        .map_err(|e| format!("{name}: {e}"))?;
    let c = compare(&p, &solution, &r);
    if c.agrees_to_resolution(FIELD_TOLERANCE, FORCE_TOLERANCE) && !c.warned() {
        Ok(())
    } else {
        Err(format!("{name}: {c:?}\n{}", scene.to_toml()))
    }
}
