//! The one-ended elimination of [`super::BandedSystem`]: LAPACK's `gbtrf` order, column by
//! column from the first, with a fixed-size path for the condensed method's band (3, 3), and
//! its substitutions.

use super::{BandedSystem, FactorStorage, SingularColumn, scale_row};

/// The LU factors of an equilibrated copy of A in LAPACK's `gbtrf` layout: U in the rows,
/// the multipliers of column j below its diagonal, and the row exchanged with j.
#[derive(Debug, Clone)]
pub(super) struct Factors {
    size: usize,
    lower: usize,
    upper: usize,
    entries: Vec<f64>,
    /// The power of two each row was scaled by.
    row_scale: Vec<f64>,
    /// 1 / U_jj: a division per row would sit on the substitution's critical path.
    inverse_diagonal: Vec<f64>,
    pivot: Vec<usize>,
}

/// The band of the condensed method's systems (`solve::condensed::search`): [`Factors`]
/// works on it with the band as constants, which lets the compiler unroll the inner loops.
pub(super) const CONDENSED_BAND: (usize, usize) = (3, 3);

/// Rows of a column's block in the band (3, 3) ([`CONDENSED_BAND`]), times the row width of
/// its factors (2·3 + 3 + 1).
pub(super) const CONDENSED_BLOCK: usize = 4 * CONDENSED_WIDTH;
pub(super) const CONDENSED_WIDTH: usize = 10;

/// Eliminates the first column of `block` (rows j..=j+3 of the factors in the band (3, 3),
/// column j at offset 3 of row j): the pivot's row (0..=3) and 1 / pivot, `None` when the
/// column is zero. The same arithmetic as the general loop of [`Factors::new_with_band`], in
/// the same order, on a fixed-size block the compiler checks once.
#[inline(always)]
pub(super) fn eliminate_condensed(block: &mut [f64; CONDENSED_BLOCK]) -> Option<(usize, f64)> {
    const W: usize = CONDENSED_WIDTH;
    let diagonal = |d: usize| d * W + 3 - d;
    let mut best = 0;
    let mut largest = block[diagonal(0)].abs();
    for d in 1..4 {
        let v = block[diagonal(d)].abs();
        if v > largest {
            largest = v;
            best = d;
        }
    }
    if largest == 0.0 || !largest.is_finite() {
        return None;
    }
    if best != 0 {
        for c in 0..7 {
            block.swap(diagonal(0) + c, diagonal(best) + c);
        }
    }
    let inverse = 1.0 / block[diagonal(0)];
    let pivot_row: [f64; 6] = std::array::from_fn(|c| block[diagonal(0) + 1 + c]);
    for d in 1..4 {
        let factor = block[diagonal(d)] * inverse;
        block[diagonal(d)] = factor;
        if factor == 0.0 {
            continue;
        }
        for (c, &s) in pivot_row.iter().enumerate() {
            block[diagonal(d) + 1 + c] -= factor * s;
        }
    }
    Some((best, inverse))
}

impl Factors {
    pub(super) fn into_storage(self) -> FactorStorage {
        FactorStorage {
            entries: self.entries,
            row_scale: self.row_scale,
            inverse_diagonal: self.inverse_diagonal,
            pivot: self.pivot,
            ..FactorStorage::default()
        }
    }

    pub(super) fn new(
        system: &BandedSystem,
        entries: FactorStorage,
    ) -> Result<Factors, SingularColumn> {
        match (system.lower, system.upper) {
            CONDENSED_BAND => Self::new_with_band(system, entries, CONDENSED_BAND),
            band => Self::new_with_band(system, entries, band),
        }
    }

    #[inline(always)]
    fn new_with_band(
        system: &BandedSystem,
        storage: FactorStorage,
        (kl, ku): (usize, usize),
    ) -> Result<Factors, SingularColumn> {
        let n = system.size;
        let width = 2 * kl + ku + 1;
        let given = kl + ku + 1;
        let FactorStorage {
            mut entries,
            mut row_scale,
            mut inverse_diagonal,
            mut pivot,
            ..
        } = storage;
        // Every row is written whole below (its fill-in slots zeroed): no need to clear.
        entries.resize(n * width, 0.0);
        row_scale.clear();
        row_scale.resize(n, 1.0);
        // Scale every row by a power of two to a largest entry in [0.5, 1): exact, and the
        // pivot choice no longer depends on the rows' units.
        for row in 0..n {
            let source = &system.entries[row * given..(row + 1) * given];
            let target = &mut entries[row * width..(row + 1) * width];
            row_scale[row] = scale_row(source, target[..given].iter_mut());
            target[given..].fill(0.0);
        }
        pivot.clear();
        pivot.resize(n, 0);
        inverse_diagonal.clear();
        inverse_diagonal.resize(n, 0.0);
        let reach = kl + ku;
        let at = |row: usize, column: usize| row * width + column + kl - row;
        for j in 0..n {
            if (kl, ku) == CONDENSED_BAND && j + kl + ku < n {
                // All of the column's block lies inside: the fixed-size path.
                let block: &mut [f64; CONDENSED_BLOCK] = (&mut entries
                    [j * width..j * width + CONDENSED_BLOCK])
                    .try_into()
                    .expect("a block of four rows");
                let (best, inverse) =
                    eliminate_condensed(block).ok_or(SingularColumn { column: j })?;
                pivot[j] = j + best;
                inverse_diagonal[j] = inverse;
                continue;
            }
            let last_row = (j + kl).min(n - 1);
            let mut best = j;
            let mut largest = entries[at(j, j)].abs();
            for r in j + 1..=last_row {
                let v = entries[at(r, j)].abs();
                if v > largest {
                    largest = v;
                    best = r;
                }
            }
            if largest == 0.0 || !largest.is_finite() {
                return Err(SingularColumn { column: j });
            }
            pivot[j] = best;
            let last_column = (j + reach).min(n - 1);
            let span = last_column - j + 1;
            if best != j {
                let (a, b) = (at(j, j), at(best, j));
                let (head, tail) = entries.split_at_mut(b);
                head[a..a + span].swap_with_slice(&mut tail[..span]);
            }
            let inverse = 1.0 / entries[at(j, j)];
            inverse_diagonal[j] = inverse;
            for r in j + 1..=last_row {
                let multiplier_at = at(r, j);
                let factor = entries[multiplier_at] * inverse;
                entries[multiplier_at] = factor;
                if factor == 0.0 {
                    continue;
                }
                // Columns j + 1 ..= last_column of rows j (pivot) and r (target).
                let (source, target) = (at(j, j + 1), at(r, j + 1));
                let (head, tail) = entries.split_at_mut(target);
                for (t, s) in tail[..span - 1]
                    .iter_mut()
                    .zip(&head[source..source + span - 1])
                {
                    *t -= factor * s;
                }
            }
        }
        Ok(Factors {
            size: n,
            inverse_diagonal,
            lower: kl,
            upper: ku,
            entries,
            row_scale,
            pivot,
        })
    }

    /// Overwrites b with A⁻¹ b.
    pub(super) fn solve_in_place(&self, b: &mut [f64]) {
        match (self.lower, self.upper) {
            CONDENSED_BAND if self.size >= 8 => self.solve_condensed(b),
            CONDENSED_BAND => self.solve_with_band(b, CONDENSED_BAND),
            band => self.solve_with_band(b, band),
        }
    }

    #[inline(always)]
    fn solve_with_band(&self, b: &mut [f64], band: (usize, usize)) {
        self.scale_rows(b);
        for j in 0..self.size {
            self.forward_row(b, j, band);
        }
        for i in (0..self.size).rev() {
            self.backward_row(b, i, band);
        }
    }

    fn scale_rows(&self, b: &mut [f64]) {
        scale_rows(b, &self.row_scale);
    }

    /// Column j of the forward substitution: its row exchange, then its multipliers.
    #[inline(always)]
    fn forward_row(&self, b: &mut [f64], j: usize, (kl, ku): (usize, usize)) {
        let (n, width) = (self.size, 2 * kl + ku + 1);
        b.swap(j, self.pivot[j]);
        let bj = b[j];
        if bj != 0.0 {
            for r in j + 1..=(j + kl).min(n - 1) {
                b[r] -= self.entries[r * width + j + kl - r] * bj;
            }
        }
    }

    /// Row i of the back substitution, rows i + 1, … done.
    #[inline(always)]
    fn backward_row(&self, b: &mut [f64], i: usize, (kl, ku): (usize, usize)) {
        let (n, width) = (self.size, 2 * kl + ku + 1);
        let last = (i + kl + ku).min(n - 1);
        let first = i * width + kl + 1;
        let row = &self.entries[first..first + (last - i)];
        // The terms of x_{i+2}, … first and x_{i+1}, computed just before, last: only one
        // product and one subtraction wait for it (the substitution is latency-bound).
        let far = row
            .iter()
            .zip(&b[i + 1..=last])
            .skip(1)
            .fold(b[i], |sum, (a, x)| sum - a * x);
        let sum = match row.first() {
            Some(&a) => far - a * b[i + 1],
            None => far,
        };
        b[i] = sum * self.inverse_diagonal[i];
    }

    /// [`Factors::solve_with_band`] in the band (3, 3) of at least 8 rows, with the rows in
    /// reach of the present one held in locals: both substitutions are latency-bound, and a
    /// value stored and loaded again waits for its store. The same operations in the same
    /// order, so the same bits (`the_fixed_size_path_does_the_general_arithmetic`).
    fn solve_condensed(&self, b: &mut [f64]) {
        let (n, entries) = (self.size, &self.entries);
        self.scale_rows(b);
        // Forward: w holds rows j ..= j + 3 (the pivot of column j is one of them).
        let mut w = [b[0], b[1], b[2], b[3]];
        for j in 0..n - 3 {
            forward_column(&mut w, entries, self.pivot[j] - j, j);
            b[j] = w[0];
            w = [w[1], w[2], w[3], b.get(j + 4).copied().unwrap_or(0.0)];
        }
        b[n - 3..].copy_from_slice(&w[..3]);
        for j in n - 3..n {
            self.forward_row(b, j, CONDENSED_BAND);
        }
        // Backward: the last six rows reach fewer than six columns; then x holds
        // x_{i+1} ..= x_{i+6}.
        for i in (n - 6..n).rev() {
            self.backward_row(b, i, CONDENSED_BAND);
        }
        let mut x: [f64; 6] = b[n - 6..].try_into().expect("six values");
        for i in (0..n - 6).rev() {
            b[i] = back_row(entries, i, b[i], self.inverse_diagonal[i], &mut x);
        }
    }
}

/// Column j of a forward substitution in the band (3, 3), on the rows j ..= j + 3 held in
/// `rows`: the row exchange (`offset` rows down), then the multipliers of column j.
#[inline(always)]
pub(super) fn forward_column(rows: &mut [f64; 4], entries: &[f64], offset: usize, j: usize) {
    const W: usize = CONDENSED_WIDTH;
    match offset {
        0 => {}
        1 => rows.swap(0, 1),
        2 => rows.swap(0, 2),
        _ => rows.swap(0, 3),
    }
    let bj = rows[0];
    if bj != 0.0 {
        rows[1] -= entries[(j + 1) * W + 2] * bj;
        rows[2] -= entries[(j + 2) * W + 1] * bj;
        rows[3] -= entries[(j + 3) * W] * bj;
    }
}

/// Row i of a back substitution in the band (3, 3), whose right-hand side is `bi`, with
/// x_{i+1} ..= x_{i+6} held in `x`: x_i, which `x` then holds first. The terms of x_{i+2}, …
/// first and x_{i+1}, computed just before, last: only one product and one subtraction wait
/// for it (the substitution is latency-bound).
#[inline(always)]
pub(super) fn back_row(entries: &[f64], i: usize, bi: f64, inverse: f64, x: &mut [f64; 6]) -> f64 {
    const W: usize = CONDENSED_WIDTH;
    let row = &entries[i * W + 4..i * W + 10];
    let far = (1..6).fold(bi, |sum, c| sum - row[c] * x[c]);
    let xi = (far - row[0] * x[0]) * inverse;
    *x = [xi, x[0], x[1], x[2], x[3], x[4]];
    xi
}

/// Scales b's rows as the factors scaled A's ([`super::scale_row`]).
pub(super) fn scale_rows(b: &mut [f64], row_scale: &[f64]) {
    for (v, &scale) in b.iter_mut().zip(row_scale) {
        *v *= scale;
    }
}
