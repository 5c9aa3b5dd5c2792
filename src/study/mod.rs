//! Studies: many solves that show a trade-off. The ε sweep reproduces the paper's Figure 5
//! (regularisation error and condition numbers against ε); the mesh sweep puts every method on
//! one error-against-run-time picture. Pure functions of their inputs, cancellable between
//! points, shared by the explorer's panels and the headless `sweep` and `report` commands.

mod epsilon;
mod mesh;

pub use epsilon::{CONDITION_LIMIT, EpsPoint, epsilon_sweep, log_space};
pub use mesh::{DENSE_MAX, MeshPoint, error_study, mesh_sizes, mesh_sweep};

/// Says whether the study should stop (its result is no longer wanted); it also stops the
/// solve of the point in progress, from inside its loops.
pub type Cancel = crate::solve::Cancellation;

/// Told before each point: (points done, points in all, what comes next).
pub type Progress<'a> = &'a (dyn Fn(usize, usize, &str) + Sync);

/// A progress report that goes nowhere.
pub fn silent(_: usize, _: usize, _: &str) {}

/// The study was cancelled before it finished.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cancelled;
