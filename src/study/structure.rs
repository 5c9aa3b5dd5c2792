//! What the methods' matrices look like, for the explorer's spy view: the stiffness matrix A
//! of (38) (Hermite cubic elements, 2×2 blocks per interior node, banded), the dual matrix
//! S = B A⁻¹ Bᵀ of (49) (dense 2k × 2k) and the `condensed` method's multiple-shooting system
//! (band (3, 3), four unknowns per special point), each with its size, nonzeros, bandwidth,
//! cond₂ where it is cheap, and a grid of the largest |entry| over the block of the matrix
//! each cell covers. No dense N × N matrix is ever formed: A's grid is filled block by block
//! from its band in O(N) (N can be 2·10⁶), and S is formed only for k ≤
//! [`DUAL_OBSTACLES_LIMIT`].

use faer::Mat;
use serde::Serialize;

use super::condensation::condense;
use super::{Cancel, Cancelled};
use crate::fem::{Mesh, StiffnessMatrix};
use crate::linalg::BlockMatrix;
use crate::linalg::condition::{
    ConditionKind, ConditionNumber, DENSE_LIMIT, block_condition_until, dense_condition_until,
};
use crate::linalg::stop::{Stop, Stopped};
use crate::model::Problem;
use crate::solve::{FrictionState, solve_condensed_while};

/// Most obstacles for which S (2k × 2k, dense) is formed: the dual methods' own limit.
pub const DUAL_OBSTACLES_LIMIT: usize = 512;

/// Most cells on either side of a spy grid.
pub const GRID_SIDE_LIMIT: usize = 1024;

/// Blocks of A read between two questions to the caller's cancel.
const BLOCKS_BETWEEN_QUESTIONS: usize = 1 << 16;

/// Which matrix.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum MatrixKind {
    /// A, the Hermite cubic finite-element matrix of (38): banded.
    Stiffness,
    /// S = B A⁻¹ Bᵀ of (49): dense 2k × 2k.
    Dual,
    /// The `condensed` method's multiple-shooting system of its final friction pattern.
    Condensed,
}

/// The largest |entry| over the block of the matrix each cell covers: cell (x, y) covers
/// rows ⌊y·rows/height⌋ .. ⌊(y+1)·rows/height⌋ and likewise columns; 0.0 where every entry
/// is zero.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpyGrid {
    pub width: usize,
    pub height: usize,
    /// Row-major, height × width.
    pub cells: Vec<f64>,
}

impl SpyGrid {
    /// An empty grid for a `rows` × `cols` matrix, of at most the asked (width, height), at
    /// most one cell per row and per column, at most [`GRID_SIDE_LIMIT`] on a side.
    fn new(rows: usize, cols: usize, (width, height): (usize, usize)) -> SpyGrid {
        let width = width.min(cols).min(GRID_SIDE_LIMIT);
        let height = height.min(rows).min(GRID_SIDE_LIMIT);
        SpyGrid {
            width,
            height,
            cells: vec![0.0; width * height],
        }
    }

    /// No cells.
    fn empty() -> SpyGrid {
        SpyGrid {
            width: 0,
            height: 0,
            cells: Vec::new(),
        }
    }

    /// The value of cell (x, y), 0.0 outside the grid.
    pub fn at(&self, x: usize, y: usize) -> f64 {
        if x < self.width && y < self.height {
            self.cells[y * self.width + x]
        } else {
            0.0
        }
    }
}

/// Fills a [`SpyGrid`] and counts the nonzeros and the bandwidth of a matrix read entry by
/// entry.
struct Spy {
    rows: usize,
    cols: usize,
    grid: SpyGrid,
    nonzeros: usize,
    bandwidth: usize,
}

impl Spy {
    fn new(rows: usize, cols: usize, cells: (usize, usize)) -> Spy {
        Spy {
            rows,
            cols,
            grid: SpyGrid::new(rows, cols, cells),
            nonzeros: 0,
            bandwidth: 0,
        }
    }

    /// Entry (row, column) is `value`; an exact zero is not a nonzero.
    fn entry(&mut self, row: usize, column: usize, value: f64) {
        if value == 0.0 {
            return;
        }
        self.nonzeros += 1;
        self.bandwidth = self.bandwidth.max(row.abs_diff(column));
        let grid = &mut self.grid;
        if grid.width == 0 || grid.height == 0 {
            return;
        }
        let y = (row as u64 * grid.height as u64 / self.rows as u64) as usize;
        let x = (column as u64 * grid.width as u64 / self.cols as u64) as usize;
        let cell = &mut grid.cells[y * grid.width + x];
        // NaN shows as a nonzero too.
        let magnitude = if value.is_nan() {
            f64::INFINITY
        } else {
            value.abs()
        };
        *cell = cell.max(magnitude);
    }
}

/// One matrix's structure.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MatrixStructure {
    pub kind: MatrixKind,
    /// "A", "S = B A⁻¹ Bᵀ", "shooting system".
    pub name: &'static str,
    pub rows: usize,
    pub cols: usize,
    /// Entries that are not exactly zero (for S not formed: 0).
    pub nonzeros: usize,
    /// The largest |row − column| of a nonzero, for the banded matrices (A, the condensed
    /// system); `None` for the dense S.
    pub bandwidth: Option<usize>,
    /// cond₂ for N ≤ [`DENSE_LIMIT`] (from all eigenvalues, or singular values for the
    /// unsymmetric condensed system), else `None`.
    pub condition: Option<f64>,
    /// How `condition` was obtained (exact, or an estimate or lower bound when the smallest
    /// eigenvalue is below what rounding resolves).
    pub condition_kind: Option<ConditionKind>,
    pub grid: SpyGrid,
    /// One sentence: what it is and which equation.
    pub note: String,
}

/// The structures of A, S and the condensed system of `problem` on `mesh`, each with a grid
/// of at most `grid` = (width, height) cells. [`Cancelled`] as soon as `cancel` says so (asked
/// inside every O(N) sweep, the factorizations and the eigensolver).
pub fn matrix_structures(
    problem: &Problem,
    mesh: &Mesh,
    grid: (usize, usize),
    cancel: &Cancel,
) -> Result<Vec<MatrixStructure>, Cancelled> {
    let stop = || cancel.is_cancelled();
    let run = || -> Result<Vec<MatrixStructure>, Stopped> {
        Ok(vec![
            stiffness_structure(mesh, grid, &stop)?,
            dual_structure(problem, mesh, grid, &stop)?,
            condensed_structure(problem, mesh, grid, cancel)?,
        ])
    };
    run().map_err(|Stopped| Cancelled)
}

/// A, read block by block from its band.
fn stiffness_structure(
    mesh: &Mesh,
    grid: (usize, usize),
    stop: Stop,
) -> Result<MatrixStructure, Stopped> {
    let matrix = StiffnessMatrix::new(mesh);
    let blocks = matrix.blocks();
    let n = 2 * blocks;
    let mut spy = Spy::new(n, n, grid);
    for i in 0..blocks {
        if i % BLOCKS_BETWEEN_QUESTIONS == 0 && stop() {
            return Err(Stopped);
        }
        let d = matrix.diag(i);
        let (r, s) = (2 * i, 2 * i + 1);
        spy.entry(r, r, d[0]);
        spy.entry(r, s, d[1]);
        spy.entry(s, r, d[1]);
        spy.entry(s, s, d[2]);
        if i + 1 < blocks {
            let u = matrix.upper(i);
            for a in 0..2 {
                for b in 0..2 {
                    spy.entry(2 * i + a, 2 * i + 2 + b, u[2 * a + b]);
                    spy.entry(2 * i + 2 + b, 2 * i + a, u[2 * a + b]);
                }
            }
        }
    }
    let condition = if n > 0 && n <= DENSE_LIMIT {
        block_condition_until(&matrix.to_block_tridiagonal(), stop)?
    } else {
        None
    };
    Ok(finish(
        (MatrixKind::Stiffness, "A"),
        spy,
        true,
        condition,
        format!(
            "A of (38): the Hermite cubic stiffness matrix, a 2×2 block (u, u') per interior \
             node, symmetric and banded ({blocks} nodes, N = {n})"
        ),
    ))
}

/// S = K⁻¹ of (49), formed for k ≤ [`DUAL_OBSTACLES_LIMIT`].
fn dual_structure(
    problem: &Problem,
    mesh: &Mesh,
    grid: (usize, usize),
    stop: Stop,
) -> Result<MatrixStructure, Stopped> {
    let k = problem.obstacles.len();
    let dim = 2 * k;
    let name = (MatrixKind::Dual, "S = B A⁻¹ Bᵀ");
    let not_formed = |why: String| MatrixStructure {
        kind: name.0,
        name: name.1,
        rows: dim,
        cols: dim,
        nonzeros: 0,
        bandwidth: None,
        condition: None,
        condition_kind: None,
        grid: SpyGrid::empty(),
        note: why,
    };
    if k == 0 {
        return Ok(not_formed(
            "S = B A⁻¹ Bᵀ of (49) is empty: there are no obstacles".into(),
        ));
    }
    if k > DUAL_OBSTACLES_LIMIT {
        return Ok(not_formed(format!(
            "S = B A⁻¹ Bᵀ of (49) is not formed: {k} obstacles make it dense {dim} × {dim}, \
             beyond the dual methods' limit of {DUAL_OBSTACLES_LIMIT} obstacles"
        )));
    }
    let matrices = match condense(problem, mesh, stop)? {
        Ok(condensation) => condensation.dual_matrices(stop)?,
        Err(why) => Err(why),
    };
    let s = match matrices {
        Ok((s, _)) => s,
        Err(why) => {
            return Ok(not_formed(format!(
                "S = B A⁻¹ Bᵀ of (49) is not formed: {why}"
            )));
        }
    };
    let mut spy = Spy::new(dim, dim, grid);
    for (ij, &v) in s.iter().enumerate() {
        spy.entry(ij / dim, ij % dim, v);
    }
    let condition = if dim <= DENSE_LIMIT {
        dense_condition_until(&s, dim, stop)?
    } else {
        None
    };
    Ok(finish(
        name,
        spy,
        false,
        condition,
        format!(
            "S = B A⁻¹ Bᵀ of (49): how the {dim} friction DOFs move under unit friction \
             forces, dense and symmetric positive definite (the inverse of A's Schur \
             complement on them)"
        ),
    ))
}

/// The condensed method's system of its final pattern (all stuck when it fails).
fn condensed_structure(
    problem: &Problem,
    mesh: &Mesh,
    grid: (usize, usize),
    cancel: &Cancel,
) -> Result<MatrixStructure, Stopped> {
    let stop = || cancel.is_cancelled();
    let mut keep_going = || !cancel.is_cancelled();
    let (stuck, pattern) = match solve_condensed_while(problem, mesh, &mut keep_going) {
        Ok(solution) => {
            let stuck: Vec<bool> = solution
                .states
                .iter()
                .flatten()
                .map(|s| *s != FrictionState::Moves)
                .collect();
            let count = stuck.iter().filter(|s| **s).count();
            let words = format!(
                "its final friction pattern ({count} of {} DOFs stuck)",
                stuck.len()
            );
            (stuck, words)
        }
        Err(crate::solve::CondensedFailure::Stopped) => return Err(Stopped),
        Err(crate::solve::CondensedFailure::Singular { .. }) => (
            Vec::new(),
            "the all-stuck pattern (the method itself found the system singular)".to_string(),
        ),
    };
    let (size, entries) = crate::solve::internals::shooting_matrix(problem, mesh, &stuck);
    let mut spy = Spy::new(size, size, grid);
    for &(row, column, value) in &entries {
        spy.entry(row, column, value);
    }
    let condition = if size <= DENSE_LIMIT {
        if stop() {
            return Err(Stopped);
        }
        singular_value_condition(size, &entries)
    } else {
        None
    };
    Ok(finish(
        (MatrixKind::Condensed, "shooting system"),
        spy,
        true,
        condition,
        format!(
            "the condensed method's multiple-shooting system of {pattern}: each piece's exact \
             transfer, the jumps (3)–(6) at the obstacles and the clamped ends, 4 unknowns per \
             special point, unsymmetric, in its dimensionless units before row equilibration"
        ),
    ))
}

/// cond₂ of an unsymmetric matrix from its singular values: exact when the smallest is
/// resolved (above 1e3·n·eps·σ_max, as for the symmetric ones), else the lower bound
/// σ_max / (σ_min + n·eps·σ_max).
fn singular_value_condition(
    size: usize,
    entries: &[(usize, usize, f64)],
) -> Option<ConditionNumber> {
    if entries.iter().any(|e| !e.2.is_finite()) {
        return None;
    }
    let mut matrix = Mat::<f64>::zeros(size, size);
    for &(row, column, value) in entries {
        matrix[(row, column)] += value;
    }
    let values = matrix.singular_values().ok()?;
    let largest = values.iter().copied().fold(0.0f64, f64::max);
    let smallest = values.iter().copied().fold(f64::INFINITY, f64::min);
    if !(largest > 0.0 && largest.is_finite()) {
        return None;
    }
    let rounding = size as f64 * f64::EPSILON * largest;
    let (value, kind) = if smallest > 1e3 * rounding {
        (largest / smallest, ConditionKind::Exact)
    } else {
        (
            largest / (smallest.max(0.0) + rounding),
            ConditionKind::LowerBound,
        )
    };
    value.is_finite().then_some(ConditionNumber { value, kind })
}

/// The structure from what the spy counted.
fn finish(
    (kind, name): (MatrixKind, &'static str),
    spy: Spy,
    banded: bool,
    condition: Option<ConditionNumber>,
    note: String,
) -> MatrixStructure {
    MatrixStructure {
        kind,
        name,
        rows: spy.rows,
        cols: spy.cols,
        nonzeros: spy.nonzeros,
        bandwidth: banded.then_some(spy.bandwidth),
        condition: condition.map(|c| c.value),
        condition_kind: condition.map(|c| c.kind),
        grid: spy.grid,
        note,
    }
}
