//! An independent high-precision reference for the discrete problem (38) on the program's own
//! mesh (issue 10), and the hard-scene generator and comparison harness built on it.
//!
//! - [`mp`]: the multi-precision number (dashu-float, 384 bits by default).
//! - [`solver`]: assembly and the exact friction solve with its certificate.
//! - [`epsilon`]: the same assembly, the regularised ε-problem of paper 2.7.1, (40)–(43), by
//!   semismooth Newton with exact line searches (the problem `regularized` and
//!   `regularized-newton` solve).
//! - [`compare`]: a program solution against the reference (relative errors, flags).
//! - [`scenes`]: the seeded hard-scene generator, its proptest strategy, the regression scenes
//!   of `tests/scenes/hard/`.
//! - [`program`]: the program's methods run and judged against the reference (the stable
//!   method's acceptance check).
//!
//! Declared once in `tests/it/main.rs`; `benches/reference.rs` (the measurement tools) includes
//! the same files with `#[path]`. Nothing in the reference itself ([`mp`], [`solver`],
//! [`epsilon`]) reads `src/solve` or `src/linalg`: from the program it takes the validated
//! [`beamfric::model::Problem`] and, from [`beamfric::fem::Mesh`], only the node positions and
//! E·J per element; only [`program`] calls the program's solver, to judge it.
#![allow(dead_code, unused_imports)]
// The kernels index several arrays in lockstep, as in the formulas (as the library does).
#![allow(clippy::needless_range_loop)]

pub mod compare;
pub mod epsilon;
pub mod mp;
pub mod program;
pub mod scenes;
pub mod solver;

pub use compare::{Comparison, FIELD_TOLERANCE, FORCE_TOLERANCE, compare};
pub use epsilon::solve_epsilon_reference;
pub use program::{REGULARIZED_TOLERANCE, STABLE_METHOD, check_stable, env_number, run_method};
pub use scenes::{hard_scene, hard_scenes, problem_of, regression_scenes};
pub use solver::{Certificate, FrictionState, RefSolution, solve_reference, solve_reference_with};
