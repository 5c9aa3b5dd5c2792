//! Elimination of the band (3, 3) from both ends at once ("twisted" or "burn at both ends"
//! factorisation): the condensed method's systems are long and narrow, and their elimination
//! and substitutions are chains where every column waits for the last (a division, then a
//! multiply–subtract per row). Two chains, one from the first row down and one from the last
//! row up, run side by side in one loop, so the processor overlaps them; they meet in a 6 × 6
//! block solved last.
//!
//! The top half is `gbtrf`'s elimination of the first `m` columns, pivoting within the band
//! as [`super::one_ended::Factors`] does. The bottom half is the same elimination of the row- and
//! column-reversed system (again of band (3, 3)) on the last columns. Each leaves three rows
//! whose entries lie in the six middle columns only; those six rows are solved by Gaussian
//! elimination with partial pivoting. Every pivot is the largest in its column among the rows
//! it may be taken from, as in LAPACK's order, so the stability is that of partial pivoting;
//! the rounding differs from the one-ended order in the last bits.

use super::one_ended::{
    CONDENSED_BLOCK, CONDENSED_WIDTH, back_row, eliminate_condensed, forward_column, scale_rows,
};
use super::{FactorStorage, SingularColumn, scale_row};

/// Rows and columns of the block the two halves meet in: kl + ku of the band (3, 3).
const MIDDLE: usize = 6;

/// Shortest system eliminated from both ends. Each half needs its four-row block and the
/// substitutions read four rows from each end, so far fewer would do; 64 keeps short
/// systems (a few µs either way) on the one-ended path, where the speed was not measured.
pub(super) const TWISTED_FROM: usize = 64;

/// One half's factors, in the layout of [`super::one_ended::Factors`] (row width 10, the diagonal at
/// offset 3 of its row): the first `columns` columns eliminated.
#[derive(Debug, Clone)]
struct Half {
    entries: Vec<f64>,
    pivot: Vec<usize>,
    inverse_diagonal: Vec<f64>,
    columns: usize,
}

/// The twisted factors of a band (3, 3) system of `size` ≥ [`TWISTED_FROM`] rows.
#[derive(Debug, Clone)]
pub(super) struct TwistedFactors {
    size: usize,
    row_scale: Vec<f64>,
    /// Columns 0..m from the top, in rows 0..m + 3.
    top: Half,
    /// Columns size − 1 down to m + 6 from the bottom, reversed: reversed row i is row
    /// size − 1 − i.
    bottom: Half,
    /// LU of the 6 × 6 block (its rows: the top's three rows left, then the bottom's, in its
    /// reversed order; its columns m..m + 6), row by row, with its row exchanges.
    middle: [[f64; MIDDLE]; MIDDLE],
    middle_pivot: [usize; MIDDLE],
}

impl TwistedFactors {
    /// Factors the band (3, 3) system whose rows are `given` (7 entries per row, columns
    /// row − 3 ..= row + 3), reusing `storage`.
    pub(super) fn new(
        given: &[f64],
        size: usize,
        storage: FactorStorage,
    ) -> Result<TwistedFactors, SingularColumn> {
        #[cfg(target_arch = "x86_64")]
        if crate::linalg::has_avx_and_fma() {
            // SAFETY: the processor has both features, just checked.
            return unsafe { Self::new_with_avx(given, size, storage) };
        }
        Self::portable(given, size, storage)
    }

    /// [`TwistedFactors::new`] compiled for processors with AVX and FMA
    /// (`linalg::has_avx_and_fma`).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx,fma")]
    fn new_with_avx(
        given: &[f64],
        size: usize,
        storage: FactorStorage,
    ) -> Result<TwistedFactors, SingularColumn> {
        Self::portable(given, size, storage)
    }

    /// [`TwistedFactors::new`] as compiled for any processor.
    #[inline(always)]
    pub(super) fn portable(
        given: &[f64],
        size: usize,
        storage: FactorStorage,
    ) -> Result<TwistedFactors, SingularColumn> {
        const W: usize = CONDENSED_WIDTH;
        debug_assert!(size >= TWISTED_FROM && given.len() == size * 7);
        let top_columns = (size - MIDDLE) / 2;
        let bottom_columns = size - MIDDLE - top_columns;
        let (top_rows, bottom_rows) = (top_columns + 3, bottom_columns + 3);
        let FactorStorage {
            mut entries,
            mut row_scale,
            mut inverse_diagonal,
            mut pivot,
            mut bottom_entries,
            mut bottom_pivot,
            mut bottom_inverse_diagonal,
        } = storage;
        let reset = |v: &mut Vec<f64>, len: usize, value: f64| {
            v.clear();
            v.resize(len, value);
        };
        // Every row of the factors is written whole below (its fill-in slots zeroed): no
        // need to clear them first (a megabyte of writes at 16 002 rows).
        entries.resize(top_rows * W, 0.0);
        bottom_entries.resize(bottom_rows * W, 0.0);
        reset(&mut row_scale, size, 1.0);
        reset(&mut inverse_diagonal, top_columns, 0.0);
        reset(&mut bottom_inverse_diagonal, bottom_columns, 0.0);
        pivot.clear();
        pivot.resize(top_columns, 0);
        bottom_pivot.clear();
        bottom_pivot.resize(bottom_columns, 0);
        // Each row is scaled into the factors just before the first column that reaches it
        // is eliminated (row j + 3 before column j), while it is at hand, rather than in a
        // pass of its own before: the same values, one pass over the factors fewer.
        for row in 0..3 {
            row_scale[row] = scale_into(given, row, &mut entries, false);
            let from_end = size - 1 - row;
            row_scale[from_end] = scale_into(given, from_end, &mut bottom_entries, true);
        }
        for j in 0..bottom_columns {
            // The bottom's reversed row j + 3.
            let from_end = size - 4 - j;
            row_scale[from_end] = scale_into(given, from_end, &mut bottom_entries, true);
            if j < top_columns {
                row_scale[j + 3] = scale_into(given, j + 3, &mut entries, false);
                let (best, inverse) = eliminate_condensed(block(&mut entries, j))
                    .ok_or(SingularColumn { column: j })?;
                pivot[j] = j + best;
                inverse_diagonal[j] = inverse;
            }
            let (best, inverse) =
                eliminate_condensed(block(&mut bottom_entries, j)).ok_or(SingularColumn {
                    column: size - 1 - j,
                })?;
            bottom_pivot[j] = j + best;
            bottom_inverse_diagonal[j] = inverse;
        }
        let mut middle = [[0.0; MIDDLE]; MIDDLE];
        for t in 0..3 {
            let (top_row, bottom_row) = (top_columns + t, bottom_columns + t);
            for q in 0..MIDDLE {
                // Column top_columns + q: offset q + 3 − t in the top's row, and, reversed
                // (column bottom_columns + 5 − q), 8 − q − t in the bottom's.
                middle[t][q] = entries[top_row * W + q + 3 - t];
                middle[3 + t][q] = bottom_entries[bottom_row * W + 8 - q - t];
            }
        }
        let middle_pivot = factor_middle(&mut middle).map_err(|q| SingularColumn {
            column: top_columns + q,
        })?;
        Ok(TwistedFactors {
            size,
            row_scale,
            top: Half {
                entries,
                pivot,
                inverse_diagonal,
                columns: top_columns,
            },
            bottom: Half {
                entries: bottom_entries,
                pivot: bottom_pivot,
                inverse_diagonal: bottom_inverse_diagonal,
                columns: bottom_columns,
            },
            middle,
            middle_pivot,
        })
    }

    /// Gives the vectors back for the next factorisation.
    pub(super) fn into_storage(self) -> FactorStorage {
        FactorStorage {
            entries: self.top.entries,
            row_scale: self.row_scale,
            inverse_diagonal: self.top.inverse_diagonal,
            pivot: self.top.pivot,
            bottom_entries: self.bottom.entries,
            bottom_pivot: self.bottom.pivot,
            bottom_inverse_diagonal: self.bottom.inverse_diagonal,
        }
    }

    /// Overwrites b with A⁻¹ b: both forward substitutions side by side, the middle block,
    /// then both back substitutions side by side, each with the rows in its reach held in
    /// locals (a value stored and loaded again would wait for its store).
    pub(super) fn solve_in_place(&self, b: &mut [f64]) {
        let n = self.size;
        scale_rows(b, &self.row_scale);
        let (top, bottom) = (&self.top, &self.bottom);
        let (m, nb) = (top.columns, bottom.columns);
        // Forward: u holds rows j ..= j + 3 of the top, w reversed rows j ..= j + 3.
        let mut u = [b[0], b[1], b[2], b[3]];
        let mut w = [b[n - 1], b[n - 2], b[n - 3], b[n - 4]];
        for j in 0..nb {
            if j < m {
                forward_column(&mut u, &top.entries, top.pivot[j] - j, j);
                b[j] = u[0];
                u = [u[1], u[2], u[3], b[j + 4]];
            }
            forward_column(&mut w, &bottom.entries, bottom.pivot[j] - j, j);
            b[n - 1 - j] = w[0];
            w = [w[1], w[2], w[3], b[n - 5 - j]];
        }
        // The top's u holds rows m ..= m + 3 when it stopped, the bottom's w reversed rows
        // nb ..= nb + 3: their first three are the middle block's right-hand side.
        let rhs = [u[0], u[1], u[2], w[0], w[1], w[2]];
        let middle = solve_middle(&self.middle, &self.middle_pivot, rhs);
        b[m..m + MIDDLE].copy_from_slice(&middle);
        // Back: x holds x_{i+1} ..= x_{i+6} of the top, y the same of the reversed bottom.
        let mut x: [f64; 6] = middle;
        let mut y: [f64; 6] = std::array::from_fn(|q| middle[MIDDLE - 1 - q]);
        for t in 0..nb {
            let i = nb - 1 - t;
            let bottom_row = n - 1 - i;
            b[bottom_row] = back_row(
                &bottom.entries,
                i,
                b[bottom_row],
                bottom.inverse_diagonal[i],
                &mut y,
            );
            if t + m >= nb {
                // The top's row i as well (it has m ≤ nb rows to go).
                b[i] = back_row(&top.entries, i, b[i], top.inverse_diagonal[i], &mut x);
            }
        }
    }
}

/// Writes row `row` of `given` (7 entries per row), scaled ([`scale_row`]), into its row of
/// a half's factors, `reversed` for the bottom half (its row size − 1 − row, the entry of
/// column row + d at offset 3 − d), the fill-in slots zeroed; the scale.
#[inline(always)]
fn scale_into(given: &[f64], row: usize, half: &mut [f64], reversed: bool) -> f64 {
    const W: usize = CONDENSED_WIDTH;
    let source = &given[row * 7..row * 7 + 7];
    let size = given.len() / 7;
    let at = if reversed { size - 1 - row } else { row };
    let target = &mut half[at * W..at * W + W];
    let scale = if reversed {
        scale_row(source, target[..7].iter_mut().rev())
    } else {
        scale_row(source, target[..7].iter_mut())
    };
    target[7..].fill(0.0);
    scale
}

/// The block of column j (rows j ..= j + 3) of a half's factors.
#[inline(always)]
fn block(entries: &mut [f64], j: usize) -> &mut [f64; CONDENSED_BLOCK] {
    const W: usize = CONDENSED_WIDTH;
    (&mut entries[j * W..j * W + CONDENSED_BLOCK])
        .try_into()
        .expect("a block of four rows")
}

/// Gaussian elimination with partial pivoting of the middle block in place (multipliers
/// below the diagonal); its row exchanges, or the first column without a pivot.
#[inline(always)]
fn factor_middle(a: &mut [[f64; MIDDLE]; MIDDLE]) -> Result<[usize; MIDDLE], usize> {
    let mut pivot = [0; MIDDLE];
    for j in 0..MIDDLE {
        let best = (j..MIDDLE)
            .max_by(|&r, &s| a[r][j].abs().total_cmp(&a[s][j].abs()))
            .expect("a row");
        let largest = a[best][j].abs();
        if largest == 0.0 || !largest.is_finite() {
            return Err(j);
        }
        a.swap(j, best);
        pivot[j] = best;
        for r in j + 1..MIDDLE {
            let factor = a[r][j] / a[j][j];
            a[r][j] = factor;
            for c in j + 1..MIDDLE {
                a[r][c] -= factor * a[j][c];
            }
        }
    }
    Ok(pivot)
}

/// Solves the factored middle block for `rhs`.
fn solve_middle(
    a: &[[f64; MIDDLE]; MIDDLE],
    pivot: &[usize; MIDDLE],
    mut rhs: [f64; MIDDLE],
) -> [f64; MIDDLE] {
    // The rows were exchanged whole, multipliers too: every exchange first.
    for (j, &p) in pivot.iter().enumerate() {
        rhs.swap(j, p);
    }
    for j in 0..MIDDLE {
        for r in j + 1..MIDDLE {
            rhs[r] -= a[r][j] * rhs[j];
        }
    }
    for i in (0..MIDDLE).rev() {
        let sum = (i + 1..MIDDLE).fold(rhs[i], |s, c| s - a[i][c] * rhs[c]);
        rhs[i] = sum / a[i][i];
    }
    rhs
}
