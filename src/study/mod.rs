//! Studies: many solves that show a trade-off, and looks inside the methods. The ε sweep
//! reproduces the paper's Figure 5 (regularisation error and condition numbers against ε);
//! the mesh sweep puts every method on one error-against-run-time picture; the case study
//! lists the regularised method's cases of Table 1; the matrix structures show A, S and the
//! condensed system as spy plots; the dual pair is (49) restricted to one obstacle's forces.
//! Pure functions of their inputs, cancellable, shared by the explorer's panels and the
//! headless commands.

mod cases;
mod condensation;
mod dual_pair;
mod epsilon;
mod mesh;
mod structure;

pub use cases::{
    CaseRow, CaseStudy, CaseTable, ConditionedSubset, LISTED_OBSTACLES, Region, case_study,
};
pub use dual_pair::{BoxPosition, DualPair, dual_pair, dual_pair_until};
pub use epsilon::{CONDITION_LIMIT, EpsPoint, epsilon_sweep, log_space, sweep_refusal};
pub use mesh::{DENSE_MAX, MeshPoint, error_study, mesh_sizes, mesh_sweep};
pub use structure::{
    DUAL_OBSTACLES_LIMIT, GRID_SIDE_LIMIT, MatrixKind, MatrixStructure, SpyGrid, matrix_structures,
};

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
