//! Gaussian elimination with row equilibration and partial pivoting for a banded square system,
//! in O(N·kl·(kl + ku)) work and O(N·(2kl + ku)) memory.
//!
//! This is the linear solver of the `condensed` method (the multiple-shooting system of the
//! exact piece relations, paper (18)–(21) on the special points): that system is not symmetric,
//! mixes displacements, rotations, moments and shears, and its natural pivots can be tiny
//! (a piece 1e-9·l long next to one of length l), so it is solved by the textbook stable
//! choice for banded matrices, LAPACK's `gbsv` algorithm: every row is first scaled by a power
//! of two to a largest entry in [0.5, 1) (exact), then each column is pivoted on its largest
//! entry within the band. Pivoting can move a row at most `kl` places up, so a row's entries
//! stay within `kl + ku` columns to the right of its diagonal.

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
    /// Width of a stored row: columns row − lower ..= row + lower + upper.
    width: usize,
    entries: Vec<f64>,
    rhs: Vec<f64>,
}

impl BandedSystem {
    /// A zero system of `size` unknowns.
    pub fn new(size: usize, lower: usize, upper: usize) -> BandedSystem {
        let width = 2 * lower + upper + 1;
        BandedSystem {
            size,
            lower,
            upper,
            width,
            entries: vec![0.0; size * width],
            rhs: vec![0.0; size],
        }
    }

    /// Number of unknowns.
    pub fn size(&self) -> usize {
        self.size
    }

    fn index(&self, row: usize, column: usize) -> usize {
        row * self.width + (column + self.lower - row)
    }

    /// Adds `value` to entry (row, column), which must lie in the band.
    pub fn add(&mut self, row: usize, column: usize, value: f64) {
        assert!(
            column + self.lower >= row && column <= row + self.upper,
            "entry ({row}, {column}) outside the band ({}, {})",
            self.lower,
            self.upper
        );
        let i = self.index(row, column);
        self.entries[i] += value;
    }

    /// Adds `value` to the right-hand side of `row`.
    pub fn add_rhs(&mut self, row: usize, value: f64) {
        self.rhs[row] += value;
    }

    /// Solves the system, consuming it.
    pub fn solve(mut self) -> Result<Vec<f64>, SingularColumn> {
        let n = self.size;
        let reach = self.lower + self.upper;
        self.equilibrate_rows();
        for j in 0..n {
            let last_row = (j + self.lower).min(n - 1);
            let mut pivot = j;
            let mut largest = self.entries[self.index(j, j)].abs();
            for r in j + 1..=last_row {
                let v = self.entries[self.index(r, j)].abs();
                if v > largest {
                    largest = v;
                    pivot = r;
                }
            }
            if largest == 0.0 || !largest.is_finite() {
                return Err(SingularColumn { column: j });
            }
            let last_column = (j + reach).min(n - 1);
            if pivot != j {
                for c in j..=last_column {
                    let (a, b) = (self.index(j, c), self.index(pivot, c));
                    self.entries.swap(a, b);
                }
                self.rhs.swap(j, pivot);
            }
            let diagonal = self.entries[self.index(j, j)];
            for r in j + 1..=last_row {
                let at = self.index(r, j);
                let factor = self.entries[at] / diagonal;
                if factor == 0.0 {
                    continue;
                }
                self.entries[at] = 0.0;
                for c in j + 1..=last_column {
                    let source = self.entries[self.index(j, c)];
                    let target = self.index(r, c);
                    self.entries[target] -= factor * source;
                }
                self.rhs[r] -= factor * self.rhs[j];
            }
        }
        let mut x = vec![0.0; n];
        for i in (0..n).rev() {
            let last_column = (i + reach).min(n - 1);
            let mut sum = self.rhs[i];
            for c in i + 1..=last_column {
                sum -= self.entries[self.index(i, c)] * x[c];
            }
            x[i] = sum / self.entries[self.index(i, i)];
        }
        Ok(x)
    }

    /// Scales every row (and its right-hand side) by a power of two so that its largest entry
    /// lies in [0.5, 1): exact, and it makes the pivot choice independent of the rows' units.
    fn equilibrate_rows(&mut self) {
        for row in 0..self.size {
            let start = row * self.width;
            let largest = self.entries[start..start + self.width]
                .iter()
                .fold(0.0f64, |m, v| m.max(v.abs()));
            if largest == 0.0 || !largest.is_finite() {
                continue;
            }
            let exponent = -(largest.log2().floor() as i32) - 1;
            for v in &mut self.entries[start..start + self.width] {
                *v = times_power_of_two(*v, exponent);
            }
            self.rhs[row] = times_power_of_two(self.rhs[row], exponent);
        }
    }
}

/// x·2^e, exact unless the result leaves the range of doubles (done in steps so that 2^e
/// itself never overflows).
pub fn times_power_of_two(mut x: f64, mut e: i32) -> f64 {
    const STEP: i32 = 1000;
    let step_up = 2f64.powi(STEP);
    let step_down = 2f64.powi(-STEP);
    while e > STEP {
        x *= step_up;
        e -= STEP;
    }
    while e < -STEP {
        x *= step_down;
        e += STEP;
    }
    x * 2f64.powi(e)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_system_that_needs_pivoting() {
        // The first pivot is zero: row exchanges are needed.
        let mut a = BandedSystem::new(3, 1, 1);
        let rows = [[0.0, 1.0, 0.0], [1.0, 0.0, 2.0], [0.0, 3.0, 1.0]];
        let x_true = [1.0, 1.0, 2.0];
        for (r, row) in rows.iter().enumerate() {
            for (c, &v) in row.iter().enumerate() {
                if v != 0.0 {
                    a.add(r, c, v);
                }
            }
            let rhs: f64 = row.iter().zip(x_true).map(|(a, x)| a * x).sum();
            a.add_rhs(r, rhs);
        }
        let x = a.solve().unwrap();
        for (x, t) in x.iter().zip(x_true) {
            assert!((x - t).abs() < 1e-15, "{x} vs {t}");
        }
    }

    #[test]
    fn reports_a_singular_system() {
        let mut a = BandedSystem::new(2, 1, 1);
        a.add(0, 0, 1.0);
        a.add(0, 1, 1.0);
        a.add(1, 0, 2.0);
        a.add(1, 1, 2.0);
        assert_eq!(a.solve().unwrap_err(), SingularColumn { column: 1 });
    }

    #[test]
    fn powers_of_two_scale_exactly_across_the_range() {
        assert_eq!(times_power_of_two(3.0, 2000 - 1998), 12.0);
        assert_eq!(times_power_of_two(1.5, -1073), 3.0 * f64::from_bits(1));
        assert_eq!(
            times_power_of_two(times_power_of_two(0.7, 1500), -1500),
            0.7
        );
    }
}
