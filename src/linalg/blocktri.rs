//! Cholesky-type (block LDLᵀ) factorization of the block-tridiagonal stiffness matrix A with the
//! friction nodes ordered last. The trailing block is the Schur complement
//! K = A_FF − A_FI A_II⁻¹ A_IF on the 2k friction DOFs, so that
//! S = B A⁻¹ Bᵀ = K⁻¹ and z0 = B A⁻¹ b = K⁻¹ (b_F − A_FI A_II⁻¹ b_I) — the matrices of the dual
//! problem (49) — come from one sweep, and the primal solution (48) from one more.
//!
//! The interior nodes between consecutive friction nodes form independent banded blocks; each
//! is eliminated left to right with 2×2 pivots while the coupling to the friction node on its
//! left is carried along. Cost O(n) with a small constant, independent of k; memory: three
//! numbers per node (the pivot inverses). A general sparse Cholesky (faer) does the same work
//! with more bookkeeping and memory; `benches/solve.rs` measures the difference.
//!
//! At 10⁷ elements a sweep is most of a second: the `_until` variants ask the caller's `stop`
//! every [`BLOCKS_BETWEEN_QUESTIONS`] blocks of every stretch (`linalg::stop`).
//!
//! In exact arithmetic every pivot is positive definite. When rounding of A's entries has
//! destroyed that (cond(A)·eps ≳ 1, around n = 10⁶ for the paper's beam), the elimination goes
//! on with the indefinite pivot — like the paper's sparse LU would — and reports where it
//! first happened, so the caller can say that the result means nothing.

use super::BlockMatrix;
use super::parallel::run_jobs;
use super::stop::{NEVER, Stop, Stopped};
use super::two_by_two::{
    Mat, Sym, mul, mul_vec, neg, sym_inverse, sym_mul, sym_vec, tmul_sym, tmul_vec,
};

/// Blocks eliminated or substituted between two questions to `stop`: about a millisecond.
const BLOCKS_BETWEEN_QUESTIONS: usize = 1 << 16;

/// The factorization broke down: a pivot is singular or not finite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Breakdown {
    /// Block (interior node − 1) where it happened.
    pub block: usize,
}

/// A stretch of interior blocks `first..end` between two friction nodes (or supports).
#[derive(Debug, Clone, Copy)]
struct Stretch {
    /// Index (into the friction nodes) of the node on the left, if any.
    left: Option<usize>,
    first: usize,
    end: usize,
    /// Index of the node on the right, if any.
    right: Option<usize>,
}

/// What eliminating one stretch adds to the Schur complement and the condensed load.
#[derive(Debug, Clone, Copy, Default)]
struct StretchResult {
    left_left: Mat,
    left_right: Mat,
    right_right: Mat,
    load_left: [f64; 2],
    load_right: [f64; 2],
    first_indefinite: Option<usize>,
}

/// The factorization of a [`BlockMatrix`] with chosen blocks (the friction nodes) last.
#[derive(Debug, Clone)]
pub struct FrictionLastFactor<M> {
    matrix: M,
    /// Pivot inverses of the interior blocks (unused entries at friction nodes).
    pivots: Vec<Sym>,
    /// Block index of each friction node (ascending).
    boundary: Vec<usize>,
    stretches: Vec<Stretch>,
    /// The Schur complement K on the friction DOFs, 2k×2k row-major.
    pub schur: Vec<f64>,
    /// The first block whose pivot was not positive definite (rounding destroyed A).
    pub first_indefinite: Option<usize>,
}

/// Splits `data` into the ranges of the stretches (disjoint, ascending), dropping the rest.
fn split_by_stretch<'a, T>(mut data: &'a mut [T], stretches: &[Stretch]) -> Vec<&'a mut [T]> {
    let mut parts = Vec::with_capacity(stretches.len());
    let mut offset = 0;
    for s in stretches {
        let (_, rest) = std::mem::take(&mut data).split_at_mut(s.first.max(offset) - offset);
        let (part, rest) = rest.split_at_mut(s.end.max(s.first) - s.first);
        parts.push(part);
        data = rest;
        offset = s.end.max(s.first);
    }
    parts
}

/// The pivots (one per node: 240 MB at n = 10⁷) are freed off the solving thread.
impl<M> Drop for FrictionLastFactor<M> {
    fn drop(&mut self) {
        super::release::release(std::mem::take(&mut self.pivots));
    }
}

impl<M: BlockMatrix + Sync> FrictionLastFactor<M> {
    /// Factors `matrix` with the blocks `boundary` (ascending, distinct) ordered last.
    pub fn new(matrix: M, boundary: &[usize]) -> Result<Self, Breakdown> {
        Self::with_rhs(matrix, boundary, &mut [], &mut []).map(|(factor, _)| factor)
    }

    /// Factors `matrix` and, in the same sweep, eliminates the right-hand side (`u`, `t`, one
    /// entry per block) as [`forward`](Self::forward) would; pass empty slices for none.
    /// Returns the factor and the condensed right-hand side on the friction DOFs.
    pub fn with_rhs(
        matrix: M,
        boundary: &[usize],
        u: &mut [f64],
        t: &mut [f64],
    ) -> Result<(Self, Vec<f64>), Breakdown> {
        Self::with_rhs_until(matrix, boundary, (u, t), NEVER).expect("never stopped")
    }

    /// [`with_rhs`](Self::with_rhs), giving up when `stop` says so (asked every
    /// [`BLOCKS_BETWEEN_QUESTIONS`] blocks).
    pub fn with_rhs_until(
        matrix: M,
        boundary: &[usize],
        (u, t): (&mut [f64], &mut [f64]),
        stop: Stop,
    ) -> Result<Result<(Self, Vec<f64>), Breakdown>, Stopped> {
        let m = matrix.blocks();
        let k = boundary.len();
        let stretches: Vec<Stretch> = (0..=k)
            .map(|i| Stretch {
                left: i.checked_sub(1),
                first: if i == 0 { 0 } else { boundary[i - 1] + 1 },
                end: boundary.get(i).copied().unwrap_or(m),
                right: (i < k).then_some(i),
            })
            .collect();
        let dim = 2 * k;
        let mut schur = vec![0.0; dim * dim];
        let mut condensed = vec![0.0; dim];
        let has_rhs = !u.is_empty();
        for (j, &b) in boundary.iter().enumerate() {
            let d = matrix.diag(b);
            schur[(2 * j) * dim + 2 * j] = d[0];
            schur[(2 * j) * dim + 2 * j + 1] = d[1];
            schur[(2 * j + 1) * dim + 2 * j] = d[1];
            schur[(2 * j + 1) * dim + 2 * j + 1] = d[2];
            if has_rhs {
                condensed[2 * j] = u[b];
                condensed[2 * j + 1] = t[b];
            }
        }
        let mut pivots = vec![[0.0; 3]; m];
        let results = {
            let pivot_parts = split_by_stretch(&mut pivots, &stretches);
            let (u_parts, t_parts) = if has_rhs {
                (
                    split_by_stretch(u, &stretches),
                    split_by_stretch(t, &stretches),
                )
            } else {
                (Vec::new(), Vec::new())
            };
            let mut u_parts = u_parts.into_iter();
            let mut t_parts = t_parts.into_iter();
            let jobs: Vec<_> = stretches
                .iter()
                .zip(pivot_parts)
                .map(|(s, p)| (*s, p, u_parts.next(), t_parts.next()))
                .collect();
            let (matrix, boundary) = (&matrix, boundary);
            run_jobs(
                jobs,
                |(s, ..)| s.end.saturating_sub(s.first),
                |(s, p, u, t)| eliminate(matrix, boundary, s, p, u.zip(t), stop),
            )
        };
        let mut factor = FrictionLastFactor {
            pivots,
            matrix,
            boundary: boundary.to_vec(),
            stretches,
            schur,
            first_indefinite: None,
        };
        if results.iter().any(|r| r.is_err()) {
            return Err(Stopped);
        }
        for (stretch, result) in factor.stretches.clone().iter().zip(results) {
            let r = match result {
                Ok(Ok(r)) => r,
                Ok(Err(breakdown)) => return Ok(Err(breakdown)),
                Err(Stopped) => return Err(Stopped),
            };
            if let Some(li) = stretch.left {
                factor.add_schur(li, li, r.left_left);
                condensed[2 * li] += r.load_left[0];
                condensed[2 * li + 1] += r.load_left[1];
            }
            if let Some(ri) = stretch.right {
                factor.add_schur(ri, ri, r.right_right);
                condensed[2 * ri] += r.load_right[0];
                condensed[2 * ri + 1] += r.load_right[1];
            }
            if let (Some(li), Some(ri)) = (stretch.left, stretch.right) {
                let x = r.left_right;
                factor.add_schur(li, ri, x);
                factor.add_schur(ri, li, [x[0], x[2], x[1], x[3]]);
            }
            factor.first_indefinite = factor.first_indefinite.or(r.first_indefinite);
        }
        if !has_rhs {
            condensed.iter_mut().for_each(|v| *v = 0.0);
        }
        Ok(Ok((factor, condensed)))
    }

    fn add_schur(&mut self, row: usize, col: usize, value: Mat) {
        let dim = 2 * self.boundary.len();
        for r in 0..2 {
            for c in 0..2 {
                self.schur[(2 * row + r) * dim + 2 * col + c] += value[2 * r + c];
            }
        }
    }

    /// Number of friction DOFs 2k.
    pub fn friction_dofs(&self) -> usize {
        2 * self.boundary.len()
    }

    /// Forward elimination of another right-hand side given per block as u-part `u` and
    /// u'-part `t`, in place, with the stored pivots. Returns the condensed right-hand side
    /// b_F − A_FI A_II⁻¹ b_I on the friction DOFs (length 2k).
    pub fn forward(&self, u: &mut [f64], t: &mut [f64]) -> Vec<f64> {
        let mut condensed = vec![0.0; self.friction_dofs()];
        for (j, &b) in self.boundary.iter().enumerate() {
            condensed[2 * j] = u[b];
            condensed[2 * j + 1] = t[b];
        }
        for stretch in &self.stretches {
            let Stretch {
                left,
                first,
                end,
                right,
            } = *stretch;
            if first >= end {
                continue;
            }
            let mut coupling = left.map(|li| self.matrix.upper(self.boundary[li]));
            for i in first..end {
                let inverse = self.pivots[i];
                let inner = i + 1 < end;
                let c = if inner || right.is_some() {
                    self.matrix.upper(i)
                } else {
                    [0.0; 4]
                };
                let (load_left, load_right) = eliminate_rhs(
                    inverse,
                    c,
                    coupling,
                    inner,
                    i - first,
                    &mut u[first..end],
                    &mut t[first..end],
                );
                if let Some(li) = left {
                    condensed[2 * li] -= load_left[0];
                    condensed[2 * li + 1] -= load_left[1];
                }
                if let (false, Some(ri)) = (inner, right) {
                    condensed[2 * ri] -= load_right[0];
                    condensed[2 * ri + 1] -= load_right[1];
                }
                if inner {
                    coupling = coupling.map(|x| neg(mul(x, sym_mul(inverse, c))));
                }
            }
        }
        condensed
    }

    /// Back substitution: (`u`, `t`) hold a forward-eliminated right-hand side,
    /// `boundary_values` the solution on the friction DOFs (2k). On return they hold the full
    /// solution.
    pub fn backward(&self, u: &mut [f64], t: &mut [f64], boundary_values: &[f64]) {
        self.backward_until(u, t, boundary_values, NEVER)
            .expect("never stopped");
    }

    /// [`backward`](Self::backward), giving up when `stop` says so (asked every
    /// [`BLOCKS_BETWEEN_QUESTIONS`] blocks); `u` and `t` then hold partial values.
    pub fn backward_until(
        &self,
        u: &mut [f64],
        t: &mut [f64],
        boundary_values: &[f64],
        stop: Stop,
    ) -> Result<(), Stopped> {
        for (j, &b) in self.boundary.iter().enumerate() {
            u[b] = boundary_values[2 * j];
            t[b] = boundary_values[2 * j + 1];
        }
        // Each stretch reads its friction nodes' values and writes only its own blocks.
        let ends: Vec<[Option<[f64; 2]>; 2]> = self
            .stretches
            .iter()
            .map(|s| {
                let value = |index: Option<usize>| {
                    index.map(|j| [boundary_values[2 * j], boundary_values[2 * j + 1]])
                };
                [value(s.left), value(s.right)]
            })
            .collect();
        let jobs: Vec<_> = self
            .stretches
            .iter()
            .zip(ends)
            .zip(split_by_stretch(u, &self.stretches))
            .zip(split_by_stretch(t, &self.stretches))
            .map(|(((s, e), u), t)| (*s, e, u, t))
            .collect();
        let results = run_jobs(
            jobs,
            |(s, ..)| s.end.saturating_sub(s.first),
            |(s, [left_value, right_value], u, t)| {
                self.back_substitute(s, [left_value, right_value], (u, t), stop)
            },
        );
        results.into_iter().collect()
    }

    /// Back substitution on one stretch; `u`, `t` hold its blocks only.
    fn back_substitute(
        &self,
        stretch: Stretch,
        [left_value, right_value]: [Option<[f64; 2]>; 2],
        (u, t): (&mut [f64], &mut [f64]),
        stop: Stop,
    ) -> Result<(), Stopped> {
        let Stretch {
            left, first, end, ..
        } = stretch;
        if first >= end {
            return Ok(());
        }
        let asked = |j: usize| j.is_multiple_of(BLOCKS_BETWEEN_QUESTIONS) && stop();
        let last = end - first - 1;
        let pivots = &self.pivots[first..end];
        // The known left value enters each eliminated equation through the forward sweep.
        if let (Some(li), Some(value)) = (left, left_value) {
            let d = tmul_vec(self.matrix.upper(self.boundary[li]), value);
            let mut delta = [-d[0], -d[1]];
            for j in 0..=last {
                if asked(j) {
                    return Err(Stopped);
                }
                u[j] += delta[0];
                t[j] += delta[1];
                if j < last {
                    let w = sym_mul(pivots[j], self.matrix.upper(first + j));
                    let d = tmul_vec(w, delta);
                    delta = [-d[0], -d[1]];
                }
            }
        }
        if let Some(value) = right_value {
            let d = mul_vec(self.matrix.upper(end - 1), value);
            u[last] -= d[0];
            t[last] -= d[1];
        }
        let mut next = sym_vec(pivots[last], [u[last], t[last]]);
        [u[last], t[last]] = next;
        for j in (0..last).rev() {
            if asked(j) {
                return Err(Stopped);
            }
            let d = mul_vec(self.matrix.upper(first + j), next);
            next = sym_vec(pivots[j], [u[j] - d[0], t[j] - d[1]]);
            [u[j], t[j]] = next;
        }
        Ok(())
    }

    /// Solves A x = rhs in place (friction DOFs included), with `schur_solve` solving
    /// K y = g on the friction DOFs.
    pub fn solve(
        &self,
        u: &mut [f64],
        t: &mut [f64],
        schur_solve: impl FnOnce(&[f64]) -> Vec<f64>,
    ) {
        let condensed = self.forward(u, t);
        let values = if condensed.is_empty() {
            condensed
        } else {
            schur_solve(&condensed)
        };
        self.backward(u, t, &values);
    }
}

/// Eliminates one stretch: stores its pivot inverses in `pivots` (the stretch's blocks only)
/// and, with a right-hand side (the stretch's blocks only), eliminates it too. Returns what
/// the stretch adds to the Schur complement and the condensed load.
fn eliminate<M: BlockMatrix>(
    matrix: &M,
    boundary: &[usize],
    stretch: Stretch,
    pivots: &mut [Sym],
    mut rhs: Option<(&mut [f64], &mut [f64])>,
    stop: Stop,
) -> Result<Result<StretchResult, Breakdown>, Stopped> {
    let Stretch {
        left,
        first,
        end,
        right,
    } = stretch;
    let mut result = StretchResult::default();
    if first >= end {
        // Two friction nodes side by side: their coupling is A's own block.
        if let (Some(li), Some(_)) = (left, right) {
            result.left_right = matrix.upper(boundary[li]);
        }
        return Ok(Ok(result));
    }
    let mut pivot = matrix.diag(first);
    // Coupling between the left friction node (rows) and the current block (columns).
    let mut coupling = left.map(|li| matrix.upper(boundary[li]));
    let mut corner = [0.0; 4];
    let last = end - 1;
    for i in first..=last {
        if (i - first) % BLOCKS_BETWEEN_QUESTIONS == 0 && stop() {
            return Err(Stopped);
        }
        let Some((inverse, definite)) = sym_inverse(pivot) else {
            return Ok(Err(Breakdown { block: i }));
        };
        if !definite && result.first_indefinite.is_none() {
            result.first_indefinite = Some(i);
        }
        pivots[i - first] = inverse;
        if let Some(x) = coupling {
            let t = mul(x, sym_mul(inverse, [x[0], x[2], x[1], x[3]]));
            corner = [
                corner[0] - t[0],
                corner[1] - t[1],
                corner[2] - t[2],
                corner[3] - t[3],
            ];
        }
        let inner = i < last;
        let c = if inner || right.is_some() {
            matrix.upper(i)
        } else {
            [0.0; 4]
        };
        if let Some((u, t)) = rhs.as_mut() {
            let (load_left, load_right) =
                eliminate_rhs(inverse, c, coupling, inner, i - first, u, t);
            result.load_left = [
                result.load_left[0] - load_left[0],
                result.load_left[1] - load_left[1],
            ];
            if !inner {
                result.load_right = [-load_right[0], -load_right[1]];
            }
        }
        if inner {
            let w = sym_mul(inverse, c);
            let update = tmul_sym(c, w);
            let d = matrix.diag(i + 1);
            pivot = [d[0] - update[0], d[1] - update[1], d[2] - update[2]];
            coupling = coupling.map(|x| neg(mul(x, w)));
        } else if right.is_some() {
            let w = sym_mul(inverse, c);
            let update = tmul_sym(c, w);
            result.right_right = [-update[0], -update[1], -update[1], -update[2]];
            if let Some(x) = coupling {
                result.left_right = neg(mul(x, w));
            }
        }
    }
    if left.is_some() {
        result.left_left = corner;
    }
    Ok(Ok(result))
}

/// One step of the forward elimination of a right-hand side at local block `j` of a stretch
/// (`u`, `t` hold the stretch's blocks) with pivot inverse `inverse` and coupling `c` to the
/// next block: the next block loses its share (when `inner`). Returns the shares of the left
/// friction node (through `coupling`) and of the right one (through `c`, at the last block).
#[inline(always)]
fn eliminate_rhs(
    inverse: Sym,
    c: Mat,
    coupling: Option<Mat>,
    inner: bool,
    j: usize,
    u: &mut [f64],
    t: &mut [f64],
) -> ([f64; 2], [f64; 2]) {
    let r = [u[j], t[j]];
    let y = sym_vec(inverse, r);
    let to_left = coupling.map_or([0.0; 2], |x| mul_vec(x, y));
    let d = tmul_vec(c, y);
    if inner {
        u[j + 1] -= d[0];
        t[j + 1] -= d[1];
        (to_left, [0.0; 2])
    } else {
        (to_left, d)
    }
}

#[cfg(test)]
mod tests;
