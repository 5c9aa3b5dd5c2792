//! LU with partial pivoting (P A = L U) in steps that ask `stop` between them: the route of an
//! indefinite K (rounding has destroyed the condensed stiffness of `dual` at n ≳ 10⁵). faer's
//! `partial_piv_lu` is one call of 35–63 ms at 2k = 1022 that a cancel cannot enter
//! (`cargo bench --bench cancel -- n=100000`); this is the textbook blocked right-looking
//! algorithm (Golub & Van Loan, Algorithm 3.4.2) with faer's kernels for the work that counts:
//! each panel of [`PANEL`] columns is factored in place with row interchanges over the whole
//! matrix, then U12 = L11⁻¹ A12 (faer's unit lower triangular solve) and A22 −= L21 U12
//! (faer's matmul), asking `stop` before every panel and every piece of the update. It is
//! backward stable as faer's is; its bits differ from faer's (a different order of the sums).

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_unit_lower_triangular_in_place;
use faer::perm::Perm;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, Mat, MatRef, Par};

use super::super::release::Background;
use super::super::stop::{Stop, Stopped};
use super::ask;

/// Columns per panel: the panel's own elimination is O(n·PANEL²), the rest goes to matmul.
const PANEL: usize = 64;

/// Columns of the trailing update per question: about 2·n·PANEL·COLUMNS = 33 M flops (a few
/// milliseconds) at n = 1022.
const COLUMNS: usize = 256;

/// L (strictly lower, unit diagonal implied) and U (upper) in one matrix, and P with
/// P A = L U: row i of P A is row `P.forward[i]` of A — what faer's `PartialPivLu::P` is, so
/// that [`super::lu_inverse_until`] takes `(lu, lu, p)`.
pub fn partial_piv_lu_until(
    a: MatRef<'_, f64>,
    stop: Stop,
) -> Result<(Mat<f64>, Perm<usize>), Stopped> {
    let n = a.nrows();
    assert_eq!(n, a.ncols(), "a square matrix");
    let mut lu = Background::new(a.to_owned());
    let mut forward: Vec<usize> = (0..n).collect();
    let mut k = 0;
    while k < n {
        ask(stop)?;
        let width = PANEL.min(n - k);
        factor_panel(&mut lu, &mut forward, k, width);
        if k + width < n {
            let (l11, mut a12, l21, mut a22) =
                lu.as_mut().get_mut(k.., k..).split_at_mut(width, width);
            solve_unit_lower_triangular_in_place(l11.rb(), a12.rb_mut(), Par::Seq);
            let rest = a22.ncols();
            let mut start = 0;
            while start < rest {
                ask(stop)?;
                let columns = COLUMNS.min(rest - start);
                matmul(
                    a22.rb_mut().subcols_mut(start, columns),
                    Accum::Add,
                    l21.rb(),
                    a12.rb().subcols(start, columns),
                    -1.0,
                    Par::Seq,
                );
                start += columns;
            }
        }
        k += width;
    }
    let mut inverse = vec![0; n];
    for (i, &row) in forward.iter().enumerate() {
        inverse[row] = i;
    }
    let perm = Perm::new_checked(forward.into_boxed_slice(), inverse.into_boxed_slice(), n);
    Ok((lu.into_inner(), perm))
}

/// Eliminates columns `k..k + width` (rows `k..`) in place: the largest entry of each column on
/// or below the diagonal becomes the pivot, the multipliers are stored below the diagonal and
/// the rest of the panel updated; the rows are interchanged within the panel first, then in
/// every other column, a contiguous column at a time (row interchanges across a column-major
/// matrix, one element per column, cost more than the panel's arithmetic). A zero pivot is
/// left as it is (the matrix is singular: the inverse is not finite, and the caller says so).
fn factor_panel(lu: &mut Mat<f64>, forward: &mut [usize], k: usize, width: usize) {
    let n = lu.nrows();
    let end = k + width;
    let mut swaps = Vec::with_capacity(width);
    for j in k..end {
        let mut pivot_row = j;
        let mut largest = lu[(j, j)].abs();
        for i in j + 1..n {
            let v = lu[(i, j)].abs();
            if v > largest {
                largest = v;
                pivot_row = i;
            }
        }
        swaps.push(pivot_row);
        if pivot_row != j {
            for c in k..end {
                let column = lu
                    .col_mut(c)
                    .try_as_col_major_mut()
                    .expect("a Mat's columns are contiguous")
                    .as_slice_mut();
                column.swap(j, pivot_row);
            }
            forward.swap(j, pivot_row);
        }
        let pivot = lu[(j, j)];
        if pivot == 0.0 {
            continue;
        }
        for i in j + 1..n {
            lu[(i, j)] /= pivot;
        }
        for c in j + 1..end {
            let u = lu[(j, c)];
            if u != 0.0 {
                for i in j + 1..n {
                    lu[(i, c)] -= lu[(i, j)] * u;
                }
            }
        }
    }
    for c in (0..k).chain(end..n) {
        let column = lu
            .col_mut(c)
            .try_as_col_major_mut()
            .expect("a Mat's columns are contiguous")
            .as_slice_mut();
        for (j, &pivot_row) in (k..end).zip(&swaps) {
            column.swap(j, pivot_row);
        }
    }
}
