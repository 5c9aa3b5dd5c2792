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

/// Does the processor have AVX and FMA? The twisted factorisation (`banded_lu`) is compiled
/// a second time for such processors (`#[target_feature]`) and takes that copy where it does:
/// the VEX encoding of the same operations in the same order, so the same bits (Rust fuses a
/// multiply and an add only where the code asks for it, and that code does not). Checked at
/// run time, not assumed at build time: the program still runs on processors without them.
/// The same copy of the one-ended factorisation and of the condensed method's exact residual
/// was slower, and is not made (docs/many-obstacles/close-obstacles-and-near-ties.md, stop 51); the
/// double-double factorisation and solve (`banded_lu_dd`) have one (stop 55).
#[cfg(target_arch = "x86_64")]
#[inline]
pub(crate) fn has_avx_and_fma() -> bool {
    std::arch::is_x86_feature_detected!("avx") && std::arch::is_x86_feature_detected!("fma")
}
