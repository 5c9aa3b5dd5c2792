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
                    self.entries[target] = self.entries[target] - factor * self.entries[source];
                }
            }
        }
        self.factored = true;
        Ok(())
    }

    /// A⁻¹ b in double-double, for a factored matrix.
    pub fn solve(&self, b: &[f64]) -> Vec<DoubleDouble> {
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
                    x[r] = x[r] - self.entries[self.at(r, j)] * xj;
                }
            }
        }
        let reach = kl + self.upper;
        for i in (0..n).rev() {
            let last = (i + reach).min(n - 1);
            let mut sum = x[i];
            for (c, xc) in x.iter().enumerate().take(last + 1).skip(i + 1) {
                sum = sum - self.entries[self.at(i, c)] * *xc;
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

    #[test]
    fn reports_a_singular_matrix() {
        let mut a = DoubleDoubleBanded::new(2, 1, 1);
        a.add(0, 0, DoubleDouble::from(1.0));
        a.add(1, 0, DoubleDouble::from(1.0));
        assert_eq!(a.factor(), Err(SingularColumn { column: 1 }));
    }
}
