//! Gaussian elimination with row equilibration and partial pivoting for a banded square system,
//! in O(N·kl·(kl + ku)) work and O(N·(2kl + ku)) memory.
//!
//! This is the linear solver of the `condensed` method (the multiple-shooting system of the
//! exact piece relations of (1) with the friction conditions (3)–(6) at the obstacles, for the
//! linear systems of the algebraic problem (38)): that system is not symmetric,
//! mixes displacements, rotations, moments and shears, and its natural pivots can be tiny
//! (a piece 1e-9·l long next to one of length l), so it is solved by the textbook stable
//! choice for banded matrices, LAPACK's `gbsv` algorithm: every row is first scaled by a power
//! of two to a largest entry in [0.5, 1) (exact), then each column is pivoted on its largest
//! entry within the band. Pivoting can move a row at most `kl` places up, so a row's entries
//! stay within `kl + ku` columns to the right of its diagonal. A few steps of iterative
//! refinement with the residual summed in double-double then make each component accurate to
//! its own size: a deflection of 7e-17 m next to a support is resolved even where the largest
//! deflection is 2e-2 m, which the sign of a friction force depends on (issue 10 item 2).

use super::double_double::DoubleDouble;

/// A pivot column was zero: the system is singular (to working precision).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SingularColumn {
    pub column: usize,
}

/// A square banded system A x = r with `lower` sub-diagonals and `upper` super-diagonals.
#[derive(Debug, Clone)]
pub struct BandedSystem {
    size: usize,
    lower: usize,
    upper: usize,
    /// A as given, row by row: columns row − lower ..= row + upper.
    entries: Vec<f64>,
    rhs: Vec<f64>,
    /// Storage of the factors, kept between solves of systems of the same shape.
    factor_storage: Vec<f64>,
    /// The factors of the last solve, until the system is reset.
    factors: Option<Factors>,
}

/// Largest number of refinement steps after the first solve.
const REFINEMENT_STEPS: usize = 4;

impl BandedSystem {
    /// A zero system of `size` unknowns.
    pub fn new(size: usize, lower: usize, upper: usize) -> BandedSystem {
        BandedSystem {
            size,
            lower,
            upper,
            entries: vec![0.0; size * (lower + upper + 1)],
            rhs: vec![0.0; size],
            factor_storage: Vec::new(),
            factors: None,
        }
    }

    /// Makes this a zero system of `size` unknowns with the same band, reusing its memory.
    pub fn reset(&mut self, size: usize) {
        if let Some(factors) = self.factors.take() {
            self.factor_storage = factors.entries;
        }
        self.size = size;
        self.entries.clear();
        self.entries
            .resize(size * (self.lower + self.upper + 1), 0.0);
        self.rhs.clear();
        self.rhs.resize(size, 0.0);
    }

    /// Makes this a copy of `other`'s matrix (same band) with a zero right-hand side, reusing
    /// this system's memory: for systems that differ from a common part in a few entries.
    pub fn reset_to(&mut self, other: &BandedSystem) {
        assert_eq!(
            (self.lower, self.upper),
            (other.lower, other.upper),
            "the same band"
        );
        if let Some(factors) = self.factors.take() {
            self.factor_storage = factors.entries;
        }
        self.size = other.size;
        self.entries.clone_from(&other.entries);
        self.rhs.clear();
        self.rhs.resize(other.size, 0.0);
    }

    /// Number of unknowns.
    pub fn size(&self) -> usize {
        self.size
    }

    /// Adds `value` to entry (row, column), which must lie in the band.
    pub fn add(&mut self, row: usize, column: usize, value: f64) {
        assert!(
            column + self.lower >= row && column <= row + self.upper,
            "entry ({row}, {column}) outside the band ({}, {})",
            self.lower,
            self.upper
        );
        let i = row * (self.lower + self.upper + 1) + column + self.lower - row;
        self.entries[i] += value;
    }

    /// Adds `value` to the right-hand side of `row`.
    pub fn add_rhs(&mut self, row: usize, value: f64) {
        self.rhs[row] += value;
    }

    /// Solves the system: elimination with partial pivoting, then iterative refinement with
    /// the solution carried in double-double and the residual summed in double-double. That
    /// makes every component of the result accurate relative to its own size (not only to the
    /// largest component), as long as the system is not singular to working precision.
    pub fn solve(&mut self) -> Result<Vec<f64>, SingularColumn> {
        self.solve_refined(REFINEMENT_STEPS)
    }

    /// Solves by elimination alone: accurate relative to the largest component, about four
    /// times cheaper than [`BandedSystem::solve`].
    pub fn solve_unrefined(&mut self) -> Result<Vec<f64>, SingularColumn> {
        self.solve_refined(0)
    }

    fn solve_refined(&mut self, steps: usize) -> Result<Vec<f64>, SingularColumn> {
        let storage = match self.factors.take() {
            Some(factors) => factors.entries,
            None => std::mem::take(&mut self.factor_storage),
        };
        let factors = Factors::new(self, storage)?;
        let x = self.refine(&factors, steps);
        self.factors = Some(factors);
        Ok(x)
    }

    /// The right-hand side as given.
    pub fn rhs(&self) -> &[f64] {
        &self.rhs
    }

    /// Overwrites `b` with A⁻¹ b by the factors of the last solve (for a caller's own
    /// iterative refinement); false when there was no successful solve since the last reset.
    pub fn apply_inverse(&self, b: &mut [f64]) -> bool {
        match &self.factors {
            Some(factors) if b.len() == self.size => {
                factors.solve_in_place(b);
                true
            }
            _ => false,
        }
    }

    fn refine(&self, factors: &Factors, steps: usize) -> Vec<f64> {
        let mut hi = self.rhs.clone();
        factors.solve_in_place(&mut hi);
        if steps == 0 {
            return hi;
        }
        let mut lo = vec![0.0; self.size];
        let mut previous = f64::INFINITY;
        for _ in 0..steps {
            let mut correction = self.residual(&hi, &lo);
            factors.solve_in_place(&mut correction);
            let size = correction.iter().fold(0.0f64, |m, d| m.max(d.abs()));
            if size == 0.0 || size >= previous || size.is_nan() {
                break;
            }
            previous = size;
            for ((h, l), d) in hi.iter_mut().zip(lo.iter_mut()).zip(&correction) {
                let sum = DoubleDouble { hi: *h, lo: *l }.plus(*d);
                *h = sum.hi;
                *l = sum.lo;
            }
        }
        hi
    }

    /// r − A (hi + lo), each component summed in double-double and rounded once.
    fn residual(&self, hi: &[f64], lo: &[f64]) -> Vec<f64> {
        let width = self.lower + self.upper + 1;
        (0..self.size)
            .map(|row| {
                let first = row.saturating_sub(self.lower);
                let last = (row + self.upper).min(self.size - 1);
                let mut sum = DoubleDouble::from(self.rhs[row]);
                for column in first..=last {
                    let a = self.entries[row * width + column + self.lower - row];
                    if a != 0.0 {
                        sum = sum - DoubleDouble::product(a, hi[column]);
                        sum.lo -= a * lo[column];
                    }
                }
                sum.value()
            })
            .collect()
    }
}

/// The LU factors of an equilibrated copy of A in LAPACK's `gbtrf` layout: U in the rows,
/// the multipliers of column j below its diagonal, and the row exchanged with j.
#[derive(Debug, Clone)]
struct Factors {
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
const CONDENSED_BAND: (usize, usize) = (3, 3);

/// Rows of a column's block in the band (3, 3) ([`CONDENSED_BAND`]), times the row width of
/// its factors (2·3 + 3 + 1).
const CONDENSED_BLOCK: usize = 4 * CONDENSED_WIDTH;
const CONDENSED_WIDTH: usize = 10;

/// Eliminates the first column of `block` (rows j..=j+3 of the factors in the band (3, 3),
/// column j at offset 3 of row j): the pivot's row (0..=3) and 1 / pivot, `None` when the
/// column is zero. The same arithmetic as the general loop of [`Factors::new_with_band`], in
/// the same order, on a fixed-size block the compiler checks once.
#[inline(always)]
fn eliminate_condensed(block: &mut [f64; CONDENSED_BLOCK]) -> Option<(usize, f64)> {
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
    fn new(system: &BandedSystem, entries: Vec<f64>) -> Result<Factors, SingularColumn> {
        match (system.lower, system.upper) {
            CONDENSED_BAND => Self::new_with_band(system, entries, CONDENSED_BAND),
            band => Self::new_with_band(system, entries, band),
        }
    }

    #[inline(always)]
    fn new_with_band(
        system: &BandedSystem,
        mut entries: Vec<f64>,
        (kl, ku): (usize, usize),
    ) -> Result<Factors, SingularColumn> {
        let n = system.size;
        let width = 2 * kl + ku + 1;
        let given = kl + ku + 1;
        entries.clear();
        entries.resize(n * width, 0.0);
        let mut row_scale = vec![1.0; n];
        // Scale every row by a power of two to a largest entry in [0.5, 1): exact, and the
        // pivot choice no longer depends on the rows' units.
        for row in 0..n {
            let source = &system.entries[row * given..(row + 1) * given];
            let target = &mut entries[row * width..row * width + given];
            let largest = source.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let scale = if largest > 0.0 && largest.is_finite() {
                power_of_two(-binary_exponent(largest) - 1)
            } else {
                None
            };
            match scale {
                Some(scale) => {
                    row_scale[row] = scale;
                    for (t, &v) in target.iter_mut().zip(source) {
                        *t = v * scale;
                    }
                }
                None => target.copy_from_slice(source),
            }
        }
        let mut pivot = vec![0; n];
        let mut inverse_diagonal = vec![0.0; n];
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
    fn solve_in_place(&self, b: &mut [f64]) {
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
        for (v, &scale) in b.iter_mut().zip(&self.row_scale) {
            *v *= scale;
        }
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
        const W: usize = CONDENSED_WIDTH;
        let (n, entries) = (self.size, &self.entries);
        self.scale_rows(b);
        // Forward: w holds rows j ..= j + 3 (the pivot of column j is one of them).
        let mut w = [b[0], b[1], b[2], b[3]];
        for j in 0..n - 3 {
            match self.pivot[j] - j {
                0 => {}
                1 => w.swap(0, 1),
                2 => w.swap(0, 2),
                _ => w.swap(0, 3),
            }
            let bj = w[0];
            if bj != 0.0 {
                w[1] -= entries[(j + 1) * W + 2] * bj;
                w[2] -= entries[(j + 2) * W + 1] * bj;
                w[3] -= entries[(j + 3) * W] * bj;
            }
            b[j] = bj;
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
            let row = &entries[i * W + 4..i * W + 10];
            let far = (1..6).fold(b[i], |sum, c| sum - row[c] * x[c]);
            let xi = (far - row[0] * x[0]) * self.inverse_diagonal[i];
            b[i] = xi;
            x = [xi, x[0], x[1], x[2], x[3], x[4]];
        }
    }
}

/// ⌊log2 x⌋ for a finite x > 0 (read from the bits of a normal number).
fn binary_exponent(x: f64) -> i32 {
    let biased = ((x.to_bits() >> 52) & 0x7ff) as i32;
    if biased == 0 {
        x.log2().floor() as i32
    } else {
        biased - 1023
    }
}

/// 2^e as a normal double, if it is one.
fn power_of_two(e: i32) -> Option<f64> {
    (-1022..=1023)
        .contains(&e)
        .then(|| f64::from_bits(((e + 1023) as u64) << 52))
}

/// x·2^e, exact unless the result leaves the range of doubles (done in steps so that 2^e
/// itself never overflows).
pub fn times_power_of_two(mut x: f64, mut e: i32) -> f64 {
    const STEP: i32 = 1000;
    let exact = |e: i32| power_of_two(e).expect("|e| ≤ 1000 is a normal power of two");
    while e > STEP {
        x *= exact(STEP);
        e -= STEP;
    }
    while e < -STEP {
        x *= exact(-STEP);
        e += STEP;
    }
    x * exact(e)
}

#[cfg(test)]
mod tests;
