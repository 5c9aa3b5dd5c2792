//! faer's dense Cholesky factorization and the inverse it gives (`dual-inverse`'s explicit A⁻¹:
//! at N = 4000 two faer calls of a second or more each), and the inverse from faer's LU
//! factors (the stiffness route's S = K⁻¹ when rounding made K indefinite: 50 ms at
//! 2k = 1022), cut into calls of about sixteen million multiply-adds, with the caller's `stop`
//! asked between them (`linalg::stop`); and the LU factorization itself in panels (`lu`, not
//! faer's bits but faer's pivots).
//!
//! The cuts follow faer's own algorithms (faer 0.24): the right-looking factorization with
//! diagonal blocks of 128 (`cholesky_recursion_right_looking`), the Cholesky inverse as L⁻¹ by
//! halves (`invert_lower_triangular`) and then the lower half of L⁻ᵀ L⁻¹ by halves
//! (`upper_x_lower_into_lower`), the LU inverse as L⁻¹ and U⁻¹ by halves and then U⁻¹ L⁻¹ by
//! halves (`upper_x_lower`) with the columns permuted, with faer's calls at the leaves (the
//! triangular steps are in `triangular`). Where faer makes one large product or triangular
//! solve, it is split by rows or columns of its result, which faer's kernels compute
//! independently of each other: every piece keeps the whole inner dimension and at least
//! [`Cuts::piece`] rows or columns, so it runs on the kernel faer uses for the whole (not its
//! small-matrix or matrix-vector kernels). The results are faer's bit for bit; the tests
//! compare them for many sizes and cuts.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch};
use faer::linalg::matmul::matmul;
use faer::linalg::matmul::triangular::{BlockStructure, matmul as triangular_matmul};
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::perm::{PermRef, permute_cols};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, Mat, MatMut, MatRef, Par};

use super::release::Background;
use super::stop::{Stop, Stopped};
use triangular::{Diagonal, invert_lower, upper_times_lower_into_lower, upper_times_unit_lower};

mod lu;
mod triangular;

pub use lu::partial_piv_lu_until;

/// A pivot of the factorization was not positive: the matrix is not positive definite in
/// floating point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NotPositiveDefinite;

/// Where the work is cut.
#[derive(Debug, Clone, Copy)]
struct Cuts {
    /// Problems of at most this size go to faer in one call (a few million multiply-adds).
    direct: usize,
    /// Multiply-adds per call above that: a few milliseconds.
    work: usize,
    /// Entries per step of a pass that only moves memory (zeroing, mirroring, a product with
    /// a vector): a few milliseconds where fresh pages or strided reads cost more than the
    /// arithmetic.
    memory: usize,
    /// Fewest rows or columns of a piece of a product or a solve.
    piece: usize,
}

const CUTS: Cuts = Cuts {
    direct: 256,
    work: 1 << 24,
    memory: 1 << 20,
    piece: 128,
};

/// faer's `a.llt(Side::Lower)` in place on the lower triangle of `a`, asking `stop` between
/// steps. The strict upper triangle must be zero, as in the copy faer factors; faer uses it as
/// scratch, so afterwards only the lower triangle is the factor.
pub fn llt_in_place_until(
    a: MatMut<'_, f64>,
    stop: Stop,
) -> Result<Result<(), NotPositiveDefinite>, Stopped> {
    llt_with_cuts(a, stop, CUTS)
}

/// faer's `Llt::inverse` of the factor `l` (lower triangular, as [`llt_in_place_until`] leaves
/// it): A⁻¹, symmetric, asking `stop` between steps.
pub fn llt_inverse_until(l: MatRef<'_, f64>, stop: Stop) -> Result<Mat<f64>, Stopped> {
    llt_inverse_with_cuts(l, stop, CUTS)
}

/// faer's `PartialPivLu::inverse` from its factors `l` (unit lower triangular), `u` (upper
/// triangular) and row permutation `p`, asking `stop` between steps.
pub fn lu_inverse_until(
    (l, u, p): (MatRef<'_, f64>, MatRef<'_, f64>, PermRef<'_, usize>),
    stop: Stop,
) -> Result<Mat<f64>, Stopped> {
    lu_inverse_with_cuts((l, u, p), stop, CUTS)
}

/// A zero n×n matrix, written a few columns at a time (at N = 4000 the 128 MB take tens of
/// milliseconds).
pub fn zeros_until(n: usize, stop: Stop) -> Result<Mat<f64>, Stopped> {
    // Freed off this thread when stopped half-way (`release`).
    let mut matrix = Background::new(Mat::<f64>::new());
    matrix.reserve(n, n);
    let columns = (CUTS.memory / n.max(1)).max(1);
    let mut done = 0;
    while done < n {
        ask(stop)?;
        done = (done + columns).min(n);
        matrix.resize_with(n, done, |_, _| 0.0);
    }
    Ok(matrix.into_inner())
}

/// The product `a · x` of faer's `&a * &x` (one column), a few rows at a time.
pub fn mat_vec_until(
    a: MatRef<'_, f64>,
    x: faer::ColRef<'_, f64>,
    stop: Stop,
) -> Result<faer::Col<f64>, Stopped> {
    let n = a.nrows();
    let mut y = faer::Col::<f64>::zeros(n);
    let rows = piece_size(CUTS.memory / a.ncols().max(1), n, CUTS);
    for (start, end) in pieces(n, rows, CUTS) {
        ask(stop)?;
        let mut part = y.as_mut().subrows_mut(start, end - start).as_mat_mut();
        matmul(
            part.rb_mut(),
            Accum::Replace,
            a.subrows(start, end - start),
            x.as_mat(),
            1.0,
            Par::Seq,
        );
    }
    Ok(y)
}

fn ask(stop: Stop) -> Result<(), Stopped> {
    if stop() { Err(Stopped) } else { Ok(()) }
}

/// faer's factorization in one call.
fn faer_llt(a: MatMut<'_, f64>) -> Result<(), NotPositiveDefinite> {
    let n = a.nrows();
    let mut memory = MemBuffer::new(cholesky_in_place_scratch::<f64>(
        n,
        Par::Seq,
        Default::default(),
    ));
    cholesky_in_place(
        a,
        Default::default(),
        Par::Seq,
        MemStack::new(&mut memory),
        Default::default(),
    )
    .map(|_| ())
    .map_err(|_| NotPositiveDefinite)
}

/// faer's right-looking loop (blocks of 128 columns): factor the diagonal block, solve for the
/// block column below it, update the trailing lower triangle.
fn llt_with_cuts(
    mut a: MatMut<'_, f64>,
    stop: Stop,
    cuts: Cuts,
) -> Result<Result<(), NotPositiveDefinite>, Stopped> {
    let n = a.nrows();
    ask(stop)?;
    if n <= cuts.direct.max(64) {
        return Ok(faer_llt(a));
    }
    let block = (n.next_power_of_two() / 2).min(128);
    let mut j = 0;
    while j < n {
        let size = block.min(n - j);
        let (mut diagonal, _, mut below, trailing) =
            a.rb_mut().get_mut(j.., j..).split_at_mut(size, size);
        ask(stop)?;
        if faer_llt(diagonal.rb_mut()).is_err() {
            return Ok(Err(NotPositiveDefinite));
        }
        // The block column below, by rows (columns of the transposed right-hand side).
        let rows = below.nrows();
        let piece = piece_size(cuts.work / (size * size / 2).max(1), rows, cuts);
        for (start, end) in pieces(rows, piece, cuts) {
            ask(stop)?;
            solve_lower_triangular_in_place(
                diagonal.rb(),
                below
                    .rb_mut()
                    .subrows_mut(start, end - start)
                    .transpose_mut(),
                Par::Seq,
            );
        }
        lower_rank_update(trailing, below.rb(), stop, cuts)?;
        j += size;
    }
    Ok(Ok(()))
}

/// The lower triangle of `dst` −= `b bᵀ`, by panels of columns: the triangle on the diagonal
/// and the rectangle below it.
fn lower_rank_update(
    mut dst: MatMut<'_, f64>,
    b: MatRef<'_, f64>,
    stop: Stop,
    cuts: Cuts,
) -> Result<(), Stopped> {
    let n = dst.nrows();
    let depth = b.ncols();
    let width = piece_size(cuts.work / (n * depth).max(1), n, cuts);
    for (start, end) in pieces(n, width, cuts) {
        ask(stop)?;
        let w = end - start;
        let panel = b.subrows(start, w);
        triangular_matmul(
            dst.rb_mut().submatrix_mut(start, start, w, w),
            BlockStructure::TriangularLower,
            Accum::Add,
            panel,
            BlockStructure::Rectangular,
            panel.transpose(),
            BlockStructure::Rectangular,
            -1.0,
            Par::Seq,
        );
        matmul(
            dst.rb_mut().submatrix_mut(end, start, n - end, w),
            Accum::Add,
            b.subrows(end, n - end),
            panel.transpose(),
            -1.0,
            Par::Seq,
        );
    }
    Ok(())
}

/// Rows or columns per piece for `wanted` of `total`: at least [`Cuts::piece`], and all of
/// them when that leaves less than a piece over.
fn piece_size(wanted: usize, total: usize, cuts: Cuts) -> usize {
    let size = wanted.max(cuts.piece);
    if size + cuts.piece > total {
        total
    } else {
        size
    }
}

/// `0..total` in pieces of `size`, the last one taking what is left (never less than a piece
/// unless the whole is).
fn pieces(total: usize, size: usize, cuts: Cuts) -> Vec<(usize, usize)> {
    let mut cut = Vec::new();
    let mut start = 0;
    while start < total {
        let end = if total - start < size + cuts.piece {
            total
        } else {
            start + size
        };
        cut.push((start, end));
        start = end;
    }
    cut
}

/// faer's `Llt::inverse`: L⁻¹, the lower half of L⁻ᵀ L⁻¹, then the upper half mirrored.
fn llt_inverse_with_cuts(l: MatRef<'_, f64>, stop: Stop, cuts: Cuts) -> Result<Mat<f64>, Stopped> {
    let n = l.nrows();
    // Both N×N matrices are freed off this thread, on a cancel too (`release`).
    let mut l_inverse = Background::new(zeros_until(n, stop)?);
    invert_lower(l_inverse.as_mut(), l, Diagonal::Stored, stop, cuts)?;
    let mut out = Background::new(zeros_until(n, stop)?);
    upper_times_lower_into_lower(
        out.as_mut(),
        Accum::Replace,
        l_inverse.transpose(),
        l_inverse.as_ref(),
        stop,
        cuts,
    )?;
    drop(l_inverse);
    // faer's `make_self_adjoint`, a few columns at a time.
    let columns = (cuts.memory / n.max(1)).max(1);
    let mut j = 0;
    while j < n {
        ask(stop)?;
        for column in j..(j + columns).min(n) {
            for i in 0..column {
                out[(i, column)] = out[(column, i)];
            }
        }
        j += columns;
    }
    Ok(out.into_inner())
}

/// faer's `lu::partial_pivoting::inverse`: L⁻¹ (strictly lower) and U⁻¹ (upper, as the lower
/// inverse of U reversed) in one matrix, U⁻¹ L⁻¹, then its columns permuted back.
fn lu_inverse_with_cuts(
    (l, u, p): (MatRef<'_, f64>, MatRef<'_, f64>, PermRef<'_, usize>),
    stop: Stop,
    cuts: Cuts,
) -> Result<Mat<f64>, Stopped> {
    let n = l.ncols();
    // Both N×N matrices are freed off this thread, on a cancel too (`release`).
    let mut out = Background::new(zeros_until(n, stop)?);
    invert_lower(out.as_mut(), l, Diagonal::Unit, stop, cuts)?;
    invert_lower(
        out.as_mut().reverse_rows_and_cols_mut(),
        u.reverse_rows_and_cols(),
        Diagonal::Stored,
        stop,
        cuts,
    )?;
    let mut product = Background::new(zeros_until(n, stop)?);
    upper_times_unit_lower(product.as_mut(), Accum::Replace, out.as_ref(), stop, cuts)?;
    ask(stop)?;
    permute_cols(out.as_mut(), product.as_ref(), p.inverse());
    Ok(out.into_inner())
}

#[cfg(test)]
mod tests;
