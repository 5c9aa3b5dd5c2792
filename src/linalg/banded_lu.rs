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
//!
//! The elimination is LAPACK's one-ended order (`one_ended`); where the last bits decide
//! nothing (the interior-point steps of the condensed method), long systems of the band (3, 3)
//! are eliminated from both ends at once (`twisted`), which the processor overlaps.

use super::double_double::DoubleDouble;
use one_ended::{CONDENSED_BAND, Factors};
use twisted::{TWISTED_FROM, TwistedFactors};

mod one_ended;
mod twisted;

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
    /// Storage of the factors (all of their vectors), kept between solves.
    factor_storage: FactorStorage,
    /// The factors of the last solve, until the system is reset.
    factors: Option<Factored>,
    /// A⁻¹ r by the one-ended factors of the last solve, before any refinement, until the
    /// system is reset or factored again (emptied first thing by both, so never stale):
    /// [`BandedSystem::first_solve`].
    first_solve: Vec<f64>,
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
            factor_storage: FactorStorage::default(),
            factors: None,
            first_solve: Vec::new(),
        }
    }

    /// Makes this a zero system of `size` unknowns with the same band, reusing its memory.
    pub fn reset(&mut self, size: usize) {
        if let Some(factors) = self.factors.take() {
            self.factor_storage = factors.into_storage();
        }
        self.first_solve.clear();
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
            self.factor_storage = factors.into_storage();
        }
        self.first_solve.clear();
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
        let i = self.position(row, column);
        self.entries[i] += value;
    }

    /// Where entry (row, column), which must lie in the band, is kept: for
    /// [`BandedSystem::matrix_and_rhs_mut`], the same in every system of this band.
    pub fn position(&self, row: usize, column: usize) -> usize {
        assert!(
            column + self.lower >= row && column <= row + self.upper,
            "entry ({row}, {column}) outside the band ({}, {})",
            self.lower,
            self.upper
        );
        row * (self.lower + self.upper + 1) + column + self.lower - row
    }

    /// The matrix's entries (each at its [`BandedSystem::position`]) and the right-hand side,
    /// to write in place.
    pub fn matrix_and_rhs_mut(&mut self) -> (&mut [f64], &mut [f64]) {
        (&mut self.entries, &mut self.rhs)
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

    /// [`BandedSystem::solve_unrefined`] by elimination from both ends at once where the system
    /// is long and of the band (3, 3) (`twisted`): the same partial pivoting in another order,
    /// with other rounding in the last bits. A factorisation with its solve took 0.52 ms
    /// instead of 0.64 at 16 002 rows, 0.12 instead of 0.15 at 4002; a solve alone 86–94 µs
    /// instead of 111–113 (random entries, fastest of 300, this machine). For solves whose
    /// last bits decide nothing (the interior-point steps of the condensed method); the
    /// pattern search keeps the one-ended order, whose decisions its tests pin down: with
    /// both ends there too, ties with the last swivel threshold one notch down took 336
    /// pattern solves at k = 4000 instead of 207.
    pub fn solve_from_both_ends(&mut self) -> Result<Vec<f64>, SingularColumn> {
        self.factor(true)?;
        let factors = self.factors.as_ref().expect("just factored");
        Ok(self.refine(factors, 0, None))
    }

    fn solve_refined(&mut self, steps: usize) -> Result<Vec<f64>, SingularColumn> {
        self.factor(false)?;
        let mut first = std::mem::take(&mut self.first_solve);
        let factors = self.factors.as_ref().expect("just factored");
        let solution = self.refine(factors, steps, Some(&mut first));
        self.first_solve = first;
        Ok(solution)
    }

    /// A⁻¹ r as the last [`BandedSystem::solve`] or [`BandedSystem::solve_unrefined`] found it
    /// by its factors, before any refinement: the bits [`BandedSystem::apply_inverse`] would
    /// give for [`BandedSystem::rhs`], without the substitutions; `None` after a reset, or
    /// after a factorisation by [`BandedSystem::solve_from_both_ends`].
    pub fn first_solve(&self) -> Option<&[f64]> {
        (!self.first_solve.is_empty()).then_some(&self.first_solve)
    }

    /// Factors the system anew in the memory of the last factors.
    fn factor(&mut self, from_both_ends: bool) -> Result<(), SingularColumn> {
        self.first_solve.clear();
        let storage = match self.factors.take() {
            Some(factors) => factors.into_storage(),
            None => std::mem::take(&mut self.factor_storage),
        };
        self.factors = Some(Factored::new(self, storage, from_both_ends)?);
        Ok(())
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

    /// The solution by `factors`, refined by up to `steps` steps; the first solve, before
    /// refinement, copied into `first` where given ([`BandedSystem::first_solve`]).
    fn refine(&self, factors: &Factored, steps: usize, first: Option<&mut Vec<f64>>) -> Vec<f64> {
        let mut hi = self.rhs.clone();
        factors.solve_in_place(&mut hi);
        if let Some(first) = first {
            first.clone_from(&hi);
        }
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

/// The factors of a system: long systems of the condensed band are eliminated from both
/// ends (`twisted`), others from the top.
#[derive(Debug, Clone)]
enum Factored {
    Plain(Factors),
    /// Boxed: its 6 × 6 block makes it four times the size of the other.
    Twisted(Box<TwistedFactors>),
}

impl Factored {
    fn new(
        system: &BandedSystem,
        storage: FactorStorage,
        from_both_ends: bool,
    ) -> Result<Factored, SingularColumn> {
        let long = (system.lower, system.upper) == CONDENSED_BAND && system.size >= TWISTED_FROM;
        if from_both_ends && long {
            TwistedFactors::new(&system.entries, system.size, storage)
                .map(|factors| Factored::Twisted(Box::new(factors)))
        } else {
            Factors::new(system, storage).map(Factored::Plain)
        }
    }

    fn into_storage(self) -> FactorStorage {
        match self {
            Factored::Plain(factors) => factors.into_storage(),
            Factored::Twisted(factors) => (*factors).into_storage(),
        }
    }

    fn solve_in_place(&self, b: &mut [f64]) {
        match self {
            Factored::Plain(factors) => factors.solve_in_place(b),
            Factored::Twisted(factors) => factors.solve_in_place(b),
        }
    }
}

/// The vectors of the factors (one-ended or twisted), kept for the next factorisation of
/// the same system (at 16 002 rows each is 128 KB or more).
#[derive(Debug, Clone, Default)]
struct FactorStorage {
    entries: Vec<f64>,
    row_scale: Vec<f64>,
    inverse_diagonal: Vec<f64>,
    pivot: Vec<usize>,
    /// The bottom half's, where the system is eliminated from both ends.
    bottom_entries: Vec<f64>,
    bottom_pivot: Vec<usize>,
    bottom_inverse_diagonal: Vec<f64>,
}

/// Writes `source` scaled by a power of two to a largest entry in [0.5, 1) (exact: the pivot
/// choice no longer depends on the rows' units) into `target`; the scale (1 for a zero or
/// non-finite row, copied as it is).
fn scale_row<'t>(source: &[f64], target: impl Iterator<Item = &'t mut f64>) -> f64 {
    let largest = source.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let scale = if largest > 0.0 && largest.is_finite() {
        power_of_two(-binary_exponent(largest) - 1)
    } else {
        None
    };
    let scale = scale.unwrap_or(1.0);
    for (t, &v) in target.zip(source) {
        *t = v * scale;
    }
    scale
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
