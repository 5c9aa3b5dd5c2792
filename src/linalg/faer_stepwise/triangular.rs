//! The triangular steps of `faer_stepwise`: faer's recursive triangular inverse and its
//! products of triangular factors, by halves as faer recurses, with its large products and
//! solves cut by rows or columns and `stop` asked between the calls.

use faer::linalg::matmul::matmul;
use faer::linalg::matmul::triangular::{BlockStructure, matmul as triangular_matmul};
use faer::linalg::triangular_inverse::{invert_lower_triangular, invert_unit_lower_triangular};
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_unit_lower_triangular_in_place,
};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, MatMut, MatRef, Par};

use super::{Cuts, ask, piece_size, pieces};
use crate::linalg::stop::{Stop, Stopped};

/// The diagonal of a triangular factor: its entries, or ones that are not stored (LU's L).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Diagonal {
    Stored,
    Unit,
}

impl Diagonal {
    fn lower(self) -> BlockStructure {
        match self {
            Diagonal::Stored => BlockStructure::TriangularLower,
            Diagonal::Unit => BlockStructure::UnitTriangularLower,
        }
    }
}

/// faer's `invert_lower_triangular_impl` (`invert_unit_lower_triangular_impl` for a unit
/// diagonal): both diagonal halves, then the lower-left block −L₂₂⁻¹ L₂₁ L₁₁⁻¹ as a product
/// (by rows) and a triangular solve (by columns).
pub(super) fn invert_lower(
    mut dst: MatMut<'_, f64>,
    src: MatRef<'_, f64>,
    diagonal: Diagonal,
    stop: Stop,
    cuts: Cuts,
) -> Result<(), Stopped> {
    let n = dst.nrows();
    ask(stop)?;
    if n <= cuts.direct.max(2) {
        match diagonal {
            Diagonal::Stored => invert_lower_triangular(dst, src, Par::Seq),
            Diagonal::Unit => invert_unit_lower_triangular(dst, src, Par::Seq),
        }
        return Ok(());
    }
    let mid = n / 2;
    let (mut top_left, _, mut bottom_left, mut bottom_right) = dst.rb_mut().split_at_mut(mid, mid);
    let (src_top_left, _, src_bottom_left, src_bottom_right) = src.split_at(mid, mid);
    invert_lower(top_left.rb_mut(), src_top_left, diagonal, stop, cuts)?;
    invert_lower(
        bottom_right.rb_mut(),
        src_bottom_right,
        diagonal,
        stop,
        cuts,
    )?;
    let rows = n - mid;
    let size = piece_size(cuts.work / (mid * mid / 2).max(1), rows, cuts);
    for (start, end) in pieces(rows, size, cuts) {
        ask(stop)?;
        triangular_matmul(
            bottom_left.rb_mut().subrows_mut(start, end - start),
            BlockStructure::Rectangular,
            Accum::Replace,
            src_bottom_left.subrows(start, end - start),
            BlockStructure::Rectangular,
            top_left.rb(),
            diagonal.lower(),
            -1.0,
            Par::Seq,
        );
    }
    let size = piece_size(cuts.work / (rows * rows / 2).max(1), mid, cuts);
    for (start, end) in pieces(mid, size, cuts) {
        ask(stop)?;
        let columns = bottom_left.rb_mut().subcols_mut(start, end - start);
        match diagonal {
            Diagonal::Stored => {
                solve_lower_triangular_in_place(src_bottom_right, columns, Par::Seq)
            }
            Diagonal::Unit => {
                solve_unit_lower_triangular_in_place(src_bottom_right, columns, Par::Seq)
            }
        }
    }
    Ok(())
}

/// faer's `upper_x_lower_impl_unchecked` (α = 1) with both factors in `factors`: `dst` (β) +
/// (its upper triangle) · (its strictly lower triangle with a unit diagonal), by halves.
pub(super) fn upper_times_unit_lower(
    mut dst: MatMut<'_, f64>,
    beta: Accum,
    factors: MatRef<'_, f64>,
    stop: Stop,
    cuts: Cuts,
) -> Result<(), Stopped> {
    let n = dst.nrows();
    ask(stop)?;
    if n <= cuts.direct.max(16) {
        triangular_matmul(
            dst,
            BlockStructure::Rectangular,
            beta,
            factors,
            BlockStructure::TriangularUpper,
            factors,
            BlockStructure::UnitTriangularLower,
            1.0,
            Par::Seq,
        );
        return Ok(());
    }
    let mid = n / 2;
    let (mut top_left, mut top_right, mut bottom_left, bottom_right) =
        dst.rb_mut().split_at_mut(mid, mid);
    let (top_left_factors, top_right_factors, bottom_left_factors, bottom_right_factors) =
        factors.split_at(mid, mid);
    // β + U₁₂ L₂₁ (a full product, by columns), then + U₁₁ L₁₁.
    let size = piece_size(cuts.work / (mid * (n - mid)).max(1), mid, cuts);
    for (start, end) in pieces(mid, size, cuts) {
        ask(stop)?;
        matmul(
            top_left.rb_mut().subcols_mut(start, end - start),
            beta,
            top_right_factors,
            bottom_left_factors.subcols(start, end - start),
            1.0,
            Par::Seq,
        );
    }
    upper_times_unit_lower(top_left, Accum::Add, top_left_factors, stop, cuts)?;
    // β + U₁₂ L₂₂ (a product with a unit lower triangle), by rows.
    let rest = n - mid;
    let size = piece_size(cuts.work / (rest * rest / 2).max(1), mid, cuts);
    for (start, end) in pieces(mid, size, cuts) {
        ask(stop)?;
        triangular_matmul(
            top_right.rb_mut().subrows_mut(start, end - start),
            BlockStructure::Rectangular,
            beta,
            top_right_factors.subrows(start, end - start),
            BlockStructure::Rectangular,
            bottom_right_factors,
            BlockStructure::UnitTriangularLower,
            1.0,
            Par::Seq,
        );
    }
    // β + U₂₂ L₂₁, transposed: L₂₁ᵀ U₂₂ᵀ (a product with a lower triangle), by rows of the
    // transpose.
    let mut transposed = bottom_left.rb_mut().transpose_mut();
    for (start, end) in pieces(mid, size, cuts) {
        ask(stop)?;
        triangular_matmul(
            transposed.rb_mut().subrows_mut(start, end - start),
            BlockStructure::Rectangular,
            beta,
            bottom_left_factors.transpose().subrows(start, end - start),
            BlockStructure::Rectangular,
            bottom_right_factors.transpose(),
            BlockStructure::TriangularLower,
            1.0,
            Par::Seq,
        );
    }
    upper_times_unit_lower(bottom_right, beta, bottom_right_factors, stop, cuts)
}

/// faer's `upper_x_lower_into_lower_impl_unchecked` (α = 1): the lower half of `dst` (β) +
/// `upper · lower`, by halves.
pub(super) fn upper_times_lower_into_lower(
    mut dst: MatMut<'_, f64>,
    beta: Accum,
    upper: MatRef<'_, f64>,
    lower: MatRef<'_, f64>,
    stop: Stop,
    cuts: Cuts,
) -> Result<(), Stopped> {
    let n = dst.nrows();
    ask(stop)?;
    if n <= cuts.direct.max(16) {
        triangular_matmul(
            dst,
            BlockStructure::TriangularLower,
            beta,
            upper,
            BlockStructure::TriangularUpper,
            lower,
            BlockStructure::TriangularLower,
            1.0,
            Par::Seq,
        );
        return Ok(());
    }
    let mid = n / 2;
    let (mut top_left, _, mut bottom_left, bottom_right) = dst.rb_mut().split_at_mut(mid, mid);
    let (upper_top_left, upper_top_right, _, upper_bottom_right) = upper.split_at(mid, mid);
    let (lower_top_left, _, lower_bottom_left, lower_bottom_right) = lower.split_at(mid, mid);
    // The top-left half: β + U₁₂ L₂₁ (a full product into a lower half), then + U₁₁ L₁₁.
    lower_product(
        top_left.rb_mut(),
        beta,
        upper_top_right,
        lower_bottom_left,
        stop,
        cuts,
    )?;
    upper_times_lower_into_lower(
        top_left,
        Accum::Add,
        upper_top_left,
        lower_top_left,
        stop,
        cuts,
    )?;
    // The bottom-left block, transposed: β + L₂₁ᵀ U₂₂ᵀ (a product with a lower triangle), by
    // rows of the transpose.
    let columns = mid;
    let size = piece_size(
        cuts.work / ((n - mid) * (n - mid) / 2).max(1),
        columns,
        cuts,
    );
    let mut transposed = bottom_left.rb_mut().transpose_mut();
    for (start, end) in pieces(columns, size, cuts) {
        ask(stop)?;
        triangular_matmul(
            transposed.rb_mut().subrows_mut(start, end - start),
            BlockStructure::Rectangular,
            beta,
            lower_bottom_left.transpose().subrows(start, end - start),
            BlockStructure::Rectangular,
            upper_bottom_right.transpose(),
            BlockStructure::TriangularLower,
            1.0,
            Par::Seq,
        );
    }
    upper_times_lower_into_lower(
        bottom_right,
        beta,
        upper_bottom_right,
        lower_bottom_right,
        stop,
        cuts,
    )
}

/// The lower half of `dst` (β) + `lhs · rhs` (faer's `mat_x_mat_into_lower`), by panels of
/// columns: the triangle on the diagonal and the rectangle below it.
fn lower_product(
    mut dst: MatMut<'_, f64>,
    beta: Accum,
    lhs: MatRef<'_, f64>,
    rhs: MatRef<'_, f64>,
    stop: Stop,
    cuts: Cuts,
) -> Result<(), Stopped> {
    let n = dst.nrows();
    let depth = lhs.ncols();
    let width = piece_size(cuts.work / (n * depth).max(1), n, cuts);
    for (start, end) in pieces(n, width, cuts) {
        ask(stop)?;
        let w = end - start;
        triangular_matmul(
            dst.rb_mut().submatrix_mut(start, start, w, w),
            BlockStructure::TriangularLower,
            beta,
            lhs.subrows(start, w),
            BlockStructure::Rectangular,
            rhs.subcols(start, w),
            BlockStructure::Rectangular,
            1.0,
            Par::Seq,
        );
        matmul(
            dst.rb_mut().submatrix_mut(end, start, n - end, w),
            beta,
            lhs.subrows(end, n - end),
            rhs.subcols(start, w),
            1.0,
            Par::Seq,
        );
    }
    Ok(())
}
