//! Symmetric block-tridiagonal matrices with 2×2 blocks: the [`BlockMatrix`] interface that
//! the factorization, the condition numbers and the finite elements share, and the explicit
//! [`BlockTridiagonal`] storage.

/// A symmetric block-tridiagonal matrix with 2×2 blocks, read block by block.
pub trait BlockMatrix {
    /// Number of block rows (interior nodes).
    fn blocks(&self) -> usize;
    /// Diagonal block i as [a11, a12, a22].
    fn diag(&self, i: usize) -> [f64; 3];
    /// Block (i, i+1), row-major [r0c0, r0c1, r1c0, r1c1]; rows are block i's DOFs.
    fn upper(&self, i: usize) -> [f64; 4];

    /// y = A x for a vector stored as (u-part, u'-part) per block.
    fn apply(&self, x: &[[f64; 2]]) -> Vec<[f64; 2]> {
        let m = self.blocks();
        let mut y = vec![[0.0; 2]; m];
        for i in 0..m {
            let d = self.diag(i);
            let mut r = [
                d[0] * x[i][0] + d[1] * x[i][1],
                d[1] * x[i][0] + d[2] * x[i][1],
            ];
            if i + 1 < m {
                let u = self.upper(i);
                r[0] += u[0] * x[i + 1][0] + u[1] * x[i + 1][1];
                r[1] += u[2] * x[i + 1][0] + u[3] * x[i + 1][1];
            }
            if i > 0 {
                let u = self.upper(i - 1);
                r[0] += u[0] * x[i - 1][0] + u[2] * x[i - 1][1];
                r[1] += u[1] * x[i - 1][0] + u[3] * x[i - 1][1];
            }
            y[i] = r;
        }
        y
    }

    /// The explicit block form.
    fn to_block_tridiagonal(&self) -> BlockTridiagonal {
        let m = self.blocks();
        BlockTridiagonal {
            diag: (0..m).map(|i| self.diag(i)).collect(),
            upper: (0..m.saturating_sub(1)).map(|i| self.upper(i)).collect(),
        }
    }

    /// The matrix as a dense row-major N×N array (N = 2·blocks), for small problems.
    fn to_dense(&self) -> Vec<f64> {
        let m = self.blocks();
        let n = 2 * m;
        let mut a = vec![0.0; n * n];
        for i in 0..m {
            let d = self.diag(i);
            a[2 * i * n + 2 * i] = d[0];
            a[2 * i * n + 2 * i + 1] = d[1];
            a[(2 * i + 1) * n + 2 * i] = d[1];
            a[(2 * i + 1) * n + 2 * i + 1] = d[2];
            if i + 1 < m {
                let u = self.upper(i);
                for r in 0..2 {
                    for c in 0..2 {
                        a[(2 * i + r) * n + 2 * i + 2 + c] = u[2 * r + c];
                        a[(2 * i + 2 + c) * n + 2 * i + r] = u[2 * r + c];
                    }
                }
            }
        }
        a
    }
}

/// A block-tridiagonal matrix stored block by block.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockTridiagonal {
    /// Diagonal blocks [a11, a12, a22].
    pub diag: Vec<[f64; 3]>,
    /// Blocks (i, i+1), row-major.
    pub upper: Vec<[f64; 4]>,
}

impl BlockMatrix for BlockTridiagonal {
    fn blocks(&self) -> usize {
        self.diag.len()
    }
    fn diag(&self, i: usize) -> [f64; 3] {
        self.diag[i]
    }
    fn upper(&self, i: usize) -> [f64; 4] {
        self.upper[i]
    }
}
