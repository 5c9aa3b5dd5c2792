//! Assembly of the stiffness matrix A and load vector b of (38) in block-tridiagonal form
//! (2×2 blocks, one per interior node; paper (52) is the uniform special case), and the
//! stationarity residual A c − b + Bᵀλ of (48), computed element by element.
//!
//! Every piece of the mesh is uniform, so A is piecewise constant: [`StiffnessMatrix`] keeps one
//! element matrix per piece and reads blocks through the mesh's element → piece table, instead
//! of storing 7 numbers per node. That matters: at n = 10⁶ the explicit blocks are 56 MB, and
//! touching fresh memory costs more than the arithmetic (see `benches/solve.rs`).
//! [`BlockTridiagonal`](crate::linalg::BlockTridiagonal) is the explicit form, for modified
//! matrices (condition numbers of the regularised cases, Jacobi scaling) and dense conversion.

use super::element::{element_load, element_stiffness};
use super::mesh::Mesh;
use crate::linalg::BlockMatrix;
use crate::linalg::stop::{NEVER, Stop, Stopped};
use crate::model::Problem;

/// The blocks of one element matrix: left-left, left-right and right-right.
#[derive(Debug, Clone, Copy, PartialEq)]
struct ElementBlocks {
    left: [f64; 3],
    coupling: [f64; 4],
    right: [f64; 3],
}

/// The stiffness matrix A, one element matrix per (uniform) mesh piece.
#[derive(Debug, Clone)]
pub struct StiffnessMatrix<'m> {
    mesh: &'m Mesh,
    pieces: Vec<ElementBlocks>,
}

impl<'m> StiffnessMatrix<'m> {
    /// A for `mesh`: element stiffness EJ ∫ φ'' φ'' of every piece.
    pub fn new(mesh: &'m Mesh) -> StiffnessMatrix<'m> {
        let pieces = mesh
            .pieces
            .iter()
            .map(|piece| {
                let k = element_stiffness(piece.bending_stiffness, mesh.element_length(piece));
                ElementBlocks {
                    left: [k[0][0], k[0][1], k[1][1]],
                    coupling: [k[0][2], k[0][3], k[1][2], k[1][3]],
                    right: [k[2][2], k[2][3], k[3][3]],
                }
            })
            .collect();
        StiffnessMatrix { mesh, pieces }
    }

    fn element(&self, e: usize) -> &ElementBlocks {
        &self.pieces[self.mesh.element_piece[e] as usize]
    }
}

impl BlockMatrix for StiffnessMatrix<'_> {
    fn blocks(&self) -> usize {
        self.mesh.elements() - 1
    }
    /// Node i + 1 is the right end of element i and the left end of element i + 1.
    fn diag(&self, i: usize) -> [f64; 3] {
        let (r, l) = (self.element(i).right, self.element(i + 1).left);
        [r[0] + l[0], r[1] + l[1], r[2] + l[2]]
    }
    /// Element i + 1 joins nodes i + 1 and i + 2.
    fn upper(&self, i: usize) -> [f64; 4] {
        self.element(i + 1).coupling
    }
}

/// b of (38) by node, ends included (as zeros): (∫ f φ_u, ∫ f φ_u') at every node. Integrated
/// exactly for the linear load.
pub fn load_vector(problem: &Problem, mesh: &Mesh) -> (Vec<f64>, Vec<f64>) {
    load_vector_until(problem, mesh, NEVER).expect("never stopped")
}

/// [`load_vector`], giving up when `stop` says so (asked every 2¹⁶ elements: 10⁷ elements
/// are most of a second with the fresh memory).
pub fn load_vector_until(
    problem: &Problem,
    mesh: &Mesh,
    stop: Stop,
) -> Result<(Vec<f64>, Vec<f64>), Stopped> {
    let n = mesh.elements();
    let mut u = vec![0.0; n + 1];
    let mut du = vec![0.0; n + 1];
    for piece in &mesh.pieces {
        let h = mesh.element_length(piece);
        let mut fa = problem.load_at(mesh.nodes[piece.first_node]);
        for e in piece.first_node..piece.last_node {
            if e % (1 << 16) == 0 && stop() {
                return Err(Stopped);
            }
            let fb = problem.load_at(mesh.nodes[e + 1]);
            let load = element_load(h, fa, fb);
            u[e] += load[0];
            du[e] += load[1];
            u[e + 1] += load[2];
            du[e + 1] += load[3];
            fa = fb;
        }
    }
    u[0] = 0.0;
    du[0] = 0.0;
    u[n] = 0.0;
    du[n] = 0.0;
    Ok((u, du))
}

/// The stationarity part of the KKT conditions of (38): ‖A c − b + Bᵀλ‖∞ together with the
/// scale ‖A‖∞‖c‖∞ + ‖b‖∞ + ‖λ‖∞ that makes it relative. Computed element by element, so no
/// matrix is stored. `lambda` holds (force, moment) per obstacle in the problem's order.
pub fn kkt_stationarity(
    problem: &Problem,
    mesh: &Mesh,
    deflection: &[f64],
    slope: &[f64],
    lambda: &[[f64; 2]],
) -> (f64, f64) {
    let (mut worst, mut a_norm, mut b_norm) = (0.0f64, 0.0f64, 0.0f64);
    let c_norm = deflection
        .iter()
        .chain(slope)
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let lambda_norm = lambda.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    // Bᵀλ: the friction forces at the obstacle nodes, in node order.
    let mut friction = mesh.obstacle_nodes.iter().zip(lambda).peekable();
    // What the element on the left of the current node contributed.
    let mut carried_residual = [0.0f64; 2];
    let mut carried_load = [0.0f64; 2];
    let mut carried_rows = [0.0f64; 2];
    for piece in &mesh.pieces {
        let h = mesh.element_length(piece);
        let k = element_stiffness(piece.bending_stiffness, h);
        let rows: [f64; 4] = std::array::from_fn(|r| k[r].iter().map(|v| v.abs()).sum());
        // ‖A‖∞: the row sums are constant inside a piece and change where two pieces meet.
        if piece.elements() > 1 {
            a_norm = a_norm.max(rows[0] + rows[2]).max(rows[1] + rows[3]);
        }
        if piece.first_node > 0 {
            a_norm = a_norm
                .max(carried_rows[0] + rows[0])
                .max(carried_rows[1] + rows[1]);
        }
        carried_rows = [rows[2], rows[3]];
        let (first, last) = (piece.first_node, piece.last_node);
        let mut fa = problem.load_at(mesh.nodes[first]);
        let mut left = [deflection[first], slope[first]];
        for (node, ((&x, &u), &du)) in (first..).zip(
            mesh.nodes[first + 1..=last]
                .iter()
                .zip(&deflection[first + 1..=last])
                .zip(&slope[first + 1..=last]),
        ) {
            let fb = problem.load_at(x);
            let f = element_load(h, fa, fb);
            fa = fb;
            let c = [left[0], left[1], u, du];
            left = [u, du];
            let kc: [f64; 4] = std::array::from_fn(|r| {
                k[r][0] * c[0] + k[r][1] * c[1] + k[r][2] * c[2] + k[r][3] * c[3]
            });
            // The left node of this element is now complete; node 0 is a support.
            if node > 0 {
                let mut r = [
                    carried_residual[0] + kc[0] - f[0],
                    carried_residual[1] + kc[1] - f[1],
                ];
                if let Some(&(&obstacle, l)) = friction.peek()
                    && obstacle == node
                {
                    r[0] += l[0];
                    r[1] += l[1];
                    friction.next();
                }
                worst = worst.max(r[0].abs()).max(r[1].abs());
                b_norm = b_norm
                    .max((carried_load[0] + f[0]).abs())
                    .max((carried_load[1] + f[1]).abs());
            }
            carried_residual = [kc[2] - f[2], kc[3] - f[3]];
            carried_load = [f[2], f[3]];
        }
    }
    (worst, a_norm * c_norm + b_norm + lambda_norm)
}
