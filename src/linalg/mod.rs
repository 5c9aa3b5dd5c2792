//! Linear algebra the methods share, pure mathematics with no knowledge of meshes: 2×2-block
//! tridiagonal matrices, the block-tridiagonal factorization with the friction
//! DOFs last (the stiffness route's one factorization), small dense Cholesky for the 2k×2k
//! systems on the friction DOFs, the box-constrained QP of the dual problem (49), and
//! condition numbers (dense eigenvalues through faer, Lanczos estimates for large N), faer's
//! dense Cholesky and inverse in interruptible steps (`faer_stepwise`); `stop` is how the long
//! kernels give up when their result is no longer wanted; `release` frees their large buffers off
//! the solving thread.

pub mod banded_lu;
pub mod banded_lu_dd;
mod block;
pub mod blocktri;
pub mod boxqp;
pub mod condition;
pub mod dense;
pub mod double_double;
pub mod faer_stepwise;
pub(crate) mod parallel;
pub mod release;
pub mod stop;
mod two_by_two;

pub use block::{BlockMatrix, BlockTridiagonal};
