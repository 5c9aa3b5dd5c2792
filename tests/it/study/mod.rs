//! The studies behind the explorer's "how the methods work" panels (issue 24): the
//! regularised method's case table, the matrices' structure and the dual restricted to one
//! obstacle, each checked against an independent computation here (dense matrices assembled
//! from A and b, a Gaussian elimination and faer's eigenvalues).

// Index loops read closer to the matrices here.
#![allow(clippy::needless_range_loop)]

mod cases;
mod dual_pair;
mod structure;

use std::sync::Arc;
use std::sync::atomic::AtomicU64;

use beamfric::fem::{Mesh, StiffnessMatrix, load_vector};
use beamfric::linalg::BlockMatrix;
use beamfric::model::{LinearLoad, Obstacle, Problem, StiffnessPiece};
use beamfric::solve::Cancellation;
use faer::{Mat, Side};

/// A cancellation that has already fired.
fn cancelled() -> Cancellation {
    Cancellation::watching(Arc::new(AtomicU64::new(1)), 0)
}

/// Benchmark 1's steel beam and load with obstacles (x, g1, g2), and a stiffer stretch on
/// [0.5, 0.6] when `stepped` (so the mesh has pieces of different element lengths).
fn steel_beam(obstacles: &[(f64, f64, f64)], stepped: bool) -> Problem {
    let ej = 2.15e11 * 0.02f64.powi(4) / 12.0;
    let stiffness = if stepped {
        vec![
            StiffnessPiece {
                from: 0.0,
                to: 0.5,
                bending_stiffness: ej,
            },
            StiffnessPiece {
                from: 0.5,
                to: 0.6,
                bending_stiffness: 3.0 * ej,
            },
            StiffnessPiece {
                from: 0.6,
                to: 1.0,
                bending_stiffness: ej,
            },
        ]
    } else {
        vec![StiffnessPiece {
            from: 0.0,
            to: 1.0,
            bending_stiffness: ej,
        }]
    };
    Problem {
        length: 1.0,
        stiffness,
        load: LinearLoad { f0: 5e4, f1: 2e4 },
        obstacles: obstacles
            .iter()
            .map(|&(x, g1, g2)| Obstacle {
                x,
                sliding_threshold: g1,
                swivel_threshold: g2,
            })
            .collect(),
    }
}

/// A (N×N row-major) and b (N) of (38), from the library's assembly, and N.
fn dense_system(problem: &Problem, mesh: &Mesh) -> (Vec<f64>, Vec<f64>, usize) {
    let matrix = StiffnessMatrix::new(mesh);
    let n = 2 * matrix.blocks();
    let a = matrix.to_dense();
    let (u, du) = load_vector(problem, mesh);
    let b = (1..mesh.elements()).flat_map(|i| [u[i], du[i]]).collect();
    (a, b, n)
}

/// The index in the unknowns of obstacle j's DOF d (0: u, 1: u').
fn friction_index(mesh: &Mesh, j: usize, d: usize) -> usize {
    2 * (mesh.obstacle_nodes[j] - 1) + d
}

/// Solves a x = b by Gaussian elimination with partial pivoting; `None` when singular.
fn gaussian_solve(a: &[f64], b: &[f64], n: usize) -> Option<Vec<f64>> {
    let mut m = a.to_vec();
    let mut x = b.to_vec();
    for col in 0..n {
        let pivot =
            (col..n).max_by(|&p, &q| m[p * n + col].abs().total_cmp(&m[q * n + col].abs()))?;
        if m[pivot * n + col] == 0.0 {
            return None;
        }
        if pivot != col {
            for c in 0..n {
                m.swap(pivot * n + c, col * n + c);
            }
            x.swap(pivot, col);
        }
        for row in col + 1..n {
            let factor = m[row * n + col] / m[col * n + col];
            if factor != 0.0 {
                for c in col..n {
                    m[row * n + c] -= factor * m[col * n + c];
                }
                x[row] -= factor * x[col];
            }
        }
    }
    for row in (0..n).rev() {
        let sum: f64 = (row + 1..n).map(|c| m[row * n + c] * x[c]).sum();
        x[row] = (x[row] - sum) / m[row * n + row];
    }
    Some(x)
}

/// cond₂ of a symmetric positive definite matrix from all its eigenvalues (faer).
fn eigen_condition(a: &[f64], n: usize) -> f64 {
    let m = Mat::from_fn(n, n, |i, j| a[i * n + j]);
    let values = m.self_adjoint_eigenvalues(Side::Lower).unwrap();
    values[n - 1] / values[0]
}

/// |a − b| / |b|.
fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}
