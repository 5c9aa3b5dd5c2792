//! The banded elimination of [`banded_lu`](super::banded_lu) — row equilibration by powers of
//! two, partial pivoting within the band — carried out in double-double on a matrix given in
//! double-double.
//!
//! It is the `condensed` method's fallback for the rare pattern systems (of (38)'s friction
//! conditions on the multiple-shooting relations of (1)) whose f64 factors are too far from
//! the exact relations for iterative refinement to converge: there the matrix, not only its
//! factorization, must be carried past f64. Three obstacles within 4e-9·l of a clamp next to
//! pieces of length 0.2·l make the reactions λ a difference of terms 10²⁷ times larger, and
//! the f64-rounded coefficients t³/6EJ of the short pieces already change λ in the third
//! digit (seed 10597097354911579289 of the tests' hard scenes). About 30 times the work of
//! the f64 elimination; only used when refinement with that one diverges.
//!
//! Two things make it cheaper without changing a bit (docs/many-obstacles/step-costs.md, stop 55).
//! Products with an entry that is exactly zero (most of the fill-in room, and the zeros of the
//! shooting relations) are skipped: subtracting a zero product leaves a double-double as it was.
//! And factor and solve are compiled a second time for processors with AVX and FMA
//! (`linalg::has_avx_and_fma`), where the fused multiply–add of every two-product is one
//! instruction instead of a call. Clusters at ties with one threshold moved (k = 3000), whose
//! search then refactored in double-double 944 times: 15.6 → 11.3 s (since then the search stops at
//! the floor of the residual instead, `refinement::SEARCH_WANDER`, and refactors once or twice).

use super::banded_lu::SingularColumn;
use super::double_double::DoubleDouble;

/// A square banded matrix with `lower` subdiagonals and `upper` superdiagonals in
/// double-double, and (after [`DoubleDoubleBanded::factor`]) its LU factors in place.
#[derive(Debug, Clone)]
pub struct DoubleDoubleBanded {
    size: usize,
    lower: usize,
    upper: usize,
    /// Row-major storage of width 2·lower + upper + 1 (LAPACK `gbtrf` layout): row r holds
    /// columns r − lower ..= r + lower + upper, room for the fill-in of pivoting.
    entries: Vec<DoubleDouble>,
    /// The power of two each row was scaled by.
    row_scale: Vec<f64>,
    /// The row exchanged with row j at step j.
    pivot: Vec<usize>,
    factored: bool,
}

impl DoubleDoubleBanded {
    /// A zero matrix of `size` unknowns.
    pub fn new(size: usize, lower: usize, upper: usize) -> DoubleDoubleBanded {
        DoubleDoubleBanded {
            size,
            lower,
            upper,
            entries: vec![DoubleDouble::ZERO; size * (2 * lower + upper + 1)],
            row_scale: vec![1.0; size],
            pivot: vec![0; size],
            factored: false,
        }
    }

    fn at(&self, row: usize, column: usize) -> usize {
        row * (2 * self.lower + self.upper + 1) + column + self.lower - row
    }

    /// Adds `value` to entry (row, column), which must lie within the band.
    pub fn add(&mut self, row: usize, column: usize, value: DoubleDouble) {
        debug_assert!(!self.factored, "entries are added before factoring");
        debug_assert!(column + self.lower >= row && column <= row + self.upper);
        let at = self.at(row, column);
        self.entries[at] = self.entries[at] + value;
    }

    /// LU factorization with row equilibration and partial pivoting, in place.
    pub fn factor(&mut self) -> Result<(), SingularColumn> {
        #[cfg(target_arch = "x86_64")]
        if crate::linalg::has_avx_and_fma() {
            // SAFETY: the processor has both features, just checked.
            return unsafe { self.factor_with_fma() };
        }
        self.factor_portable()
    }

    /// [`DoubleDoubleBanded::factor`] compiled for processors with AVX and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx,fma")]
    fn factor_with_fma(&mut self) -> Result<(), SingularColumn> {
        self.factor_portable()
    }

    /// [`DoubleDoubleBanded::factor`] as compiled for any processor.
    #[inline(always)]
    fn factor_portable(&mut self) -> Result<(), SingularColumn> {
        let (n, kl, ku) = (self.size, self.lower, self.upper);
        let width = 2 * kl + ku + 1;
        for row in 0..n {
            let cells = &mut self.entries[row * width..(row + 1) * width];
            let largest = cells.iter().fold(0.0f64, |m, v| m.max(v.hi.abs()));
            if largest > 0.0 && largest.is_finite() {
                let scale = 2f64.powi(-(largest.log2().floor() as i32) - 1);
                if scale.is_finite() && scale > 0.0 {
                    self.row_scale[row] = scale;
                    for v in cells.iter_mut() {
                        *v = v.scaled(scale);
                    }
                }
            }
        }
        let reach = kl + ku;
        for j in 0..n {
            let last_row = (j + kl).min(n - 1);
            let mut best = j;
            let mut largest = self.entries[self.at(j, j)].hi.abs();
            for r in j + 1..=last_row {
                let v = self.entries[self.at(r, j)].hi.abs();
                if v > largest {
                    largest = v;
                    best = r;
                }
            }
            if largest == 0.0 || !largest.is_finite() {
                return Err(SingularColumn { column: j });
            }
            self.pivot[j] = best;
            let last_column = (j + reach).min(n - 1);
            if best != j {
                for c in j..=last_column {
                    let (a, b) = (self.at(j, c), self.at(best, c));
                    self.entries.swap(a, b);
                }
            }
            let diagonal = self.entries[self.at(j, j)];
            for r in j + 1..=last_row {
                let multiplier_at = self.at(r, j);
                let factor = self.entries[multiplier_at] / diagonal;
                self.entries[multiplier_at] = factor;
                if factor.hi == 0.0 {
                    continue;
                }
                for c in j + 1..=last_column {
                    let (source, target) = (self.at(j, c), self.at(r, c));
                    let above = self.entries[source];
                    if !above.is_zero() {
                        self.entries[target] = self.entries[target] - factor * above;
                    }
                }
            }
        }
        self.factored = true;
        Ok(())
    }

    /// A⁻¹ b in double-double, for a factored matrix.
    pub fn solve(&self, b: &[f64]) -> Vec<DoubleDouble> {
        #[cfg(target_arch = "x86_64")]
        if crate::linalg::has_avx_and_fma() {
            // SAFETY: the processor has both features, just checked.
            return unsafe { self.solve_with_fma(b) };
        }
        self.solve_portable(b)
    }

    /// [`DoubleDoubleBanded::solve`] compiled for processors with AVX and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx,fma")]
    fn solve_with_fma(&self, b: &[f64]) -> Vec<DoubleDouble> {
        self.solve_portable(b)
    }

    /// [`DoubleDoubleBanded::solve`] as compiled for any processor.
    #[inline(always)]
    fn solve_portable(&self, b: &[f64]) -> Vec<DoubleDouble> {
        assert!(self.factored && b.len() == self.size, "solve after factor");
        let (n, kl) = (self.size, self.lower);
        let mut x: Vec<DoubleDouble> = b
            .iter()
            .zip(&self.row_scale)
            .map(|(&v, &s)| DoubleDouble::from(v * s))
            .collect();
        for j in 0..n {
            x.swap(j, self.pivot[j]);
            let xj = x[j];
            if xj.hi != 0.0 {
                for r in j + 1..=(j + kl).min(n - 1) {
                    let multiplier = self.entries[self.at(r, j)];
                    if !multiplier.is_zero() {
                        x[r] = x[r] - multiplier * xj;
                    }
                }
            }
        }
        let reach = kl + self.upper;
        for i in (0..n).rev() {
            let last = (i + reach).min(n - 1);
            let mut sum = x[i];
            for (c, xc) in x.iter().enumerate().take(last + 1).skip(i + 1) {
                let entry = self.entries[self.at(i, c)];
                if !entry.is_zero() {
                    sum = sum - entry * *xc;
                }
            }
            x[i] = sum / self.entries[self.at(i, i)];
        }
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A system whose f64 rounding loses every digit: entries 1 and 1 + 2⁻⁶⁰ (a double-double
    /// number) differ below f64's resolution, so only a double-double factorization solves it.
    #[test]
    fn solves_a_system_singular_in_f64() {
        let tiny = 2f64.powi(-60);
        let mut a = DoubleDoubleBanded::new(2, 1, 1);
        let one = DoubleDouble::from(1.0);
        a.add(0, 0, one);
        a.add(0, 1, one);
        a.add(1, 0, one);
        a.add(1, 1, one + DoubleDouble::from(tiny));
        a.factor().unwrap();
        // x = (1, 1): b = (2, 2 + 2⁻⁶⁰); b is not a double, so solve A x = (0, 2⁻⁶⁰) instead,
        // whose solution is (−1, 1).
        let x = a.solve(&[0.0, tiny]);
        assert!((x[0] + one).abs().hi < 1e-28, "{x:?}");
        assert!((x[1] - one).abs().hi < 1e-28, "{x:?}");
    }

    /// Pivoting: a zero leading entry.
    #[test]
    fn pivots_past_a_zero_diagonal() {
        let mut a = DoubleDoubleBanded::new(3, 1, 1);
        for (r, c, v) in [
            (0, 1, 1.0),
            (1, 0, 2.0),
            (1, 1, 1.0),
            (1, 2, 1.0),
            (2, 1, 1.0),
            (2, 2, 1.0),
        ] {
            a.add(r, c, DoubleDouble::from(v));
        }
        a.factor().unwrap();
        // A (1, 2, 3) = (2, 7, 5).
        let x = a.solve(&[2.0, 7.0, 5.0]);
        for (x, want) in x.iter().zip([1.0, 2.0, 3.0]) {
            assert!((x.hi - want).abs() < 1e-15, "{x:?}");
        }
    }

    /// A banded system of `size` rows with band (3, 3) like the condensed method's: entries
    /// with low parts, a third of them exactly zero (the solve skips those), and small
    /// diagonals so that rows are exchanged.
    fn random_system(size: usize, seed: u64) -> DoubleDoubleBanded {
        let mut state = seed;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut a = DoubleDoubleBanded::new(size, 3, 3);
        for row in 0..size {
            for column in row.saturating_sub(3)..=(row + 3).min(size - 1) {
                let pick = next();
                if pick.abs() < 1.0 / 6.0 && row != column {
                    continue;
                }
                let scale = if row == column { 1e-3 } else { 1.0 };
                let value = DoubleDouble::from(scale * next()) + DoubleDouble::from(1e-20 * next());
                a.add(row, column, value);
            }
        }
        a
    }

    #[test]
    fn the_copy_for_avx_and_fma_gives_the_portable_bits() {
        // Where the processor has AVX and FMA, factor and solve run copies compiled for them
        // (`linalg::has_avx_and_fma`): the same operations in the same order (`f64::mul_add`
        // is the fused multiply–add either way, correctly rounded), so every bit must be the
        // portable code's. Skipped on a processor without the features.
        #[cfg(target_arch = "x86_64")]
        if crate::linalg::has_avx_and_fma() {
            for (size, seed) in [(7, 3), (64, 11), (1001, 13), (12_002, 14)] {
                let mut portable = random_system(size, seed);
                let mut dispatched = portable.clone();
                portable.factor_portable().unwrap();
                dispatched.factor().unwrap();
                let bits = |x: &[DoubleDouble]| {
                    x.iter()
                        .map(|v| (v.hi.to_bits(), v.lo.to_bits()))
                        .collect::<Vec<_>>()
                };
                assert_eq!(
                    bits(&portable.entries),
                    bits(&dispatched.entries),
                    "size {size}"
                );
                assert_eq!(portable.pivot, dispatched.pivot, "size {size}");
                let b: Vec<f64> = (0..size).map(|i| ((i * 37) % 17) as f64 - 8.0).collect();
                let (u, v) = (portable.solve_portable(&b), dispatched.solve(&b));
                assert_eq!(bits(&u), bits(&v), "size {size}");
                assert!(u.iter().all(|v| v.hi.is_finite()), "size {size}");
            }
        }
    }

    /// The solve is right on those systems: the residual b − A x, in double-double, is far
    /// below what f64 resolves (2⁻⁹⁰ of the largest product a·x or b; an f64 solve leaves
    /// about 2⁻⁵²).
    #[test]
    fn solves_banded_systems_with_zero_entries_and_row_exchanges() {
        for (size, seed) in [(7, 5), (64, 6), (1001, 7)] {
            let matrix = random_system(size, seed);
            let mut factored = matrix.clone();
            factored.factor().unwrap();
            let b: Vec<f64> = (0..size).map(|i| ((i * 29) % 13) as f64 - 6.0).collect();
            let x = factored.solve(&b);
            let band = |row: usize| row.saturating_sub(3)..=(row + 3).min(size - 1);
            let product =
                |row: usize, column: usize| matrix.entries[matrix.at(row, column)] * x[column];
            let largest = (0..size)
                .flat_map(|row| band(row).map(move |column| (row, column)))
                .fold(8.0f64, |m, (row, column)| {
                    m.max(product(row, column).hi.abs())
                });
            for (row, &b_row) in b.iter().enumerate() {
                let residual = band(row).fold(DoubleDouble::from(b_row), |sum, column| {
                    sum - product(row, column)
                });
                let bound = 2f64.powi(-90) * largest;
                assert!(
                    residual.hi.abs() <= bound,
                    "size {size} row {row}: {residual:?}"
                );
            }
        }
    }

    #[test]
    fn reports_a_singular_matrix() {
        let mut a = DoubleDoubleBanded::new(2, 1, 1);
        a.add(0, 0, DoubleDouble::from(1.0));
        a.add(1, 0, DoubleDouble::from(1.0));
        assert_eq!(a.factor(), Err(SingularColumn { column: 1 }));
    }
}
