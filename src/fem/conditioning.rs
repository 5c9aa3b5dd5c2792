//! A cheap rigorous lower bound on the condition number of the stiffness matrix A of (38) (the
//! paper's Figure 5 plots it), from the mesh alone (A is never stored): what the solve path's
//! conditioning warning rests on. Stages: the coarse Rayleigh–Ritz space, bounds on the
//! largest eigenvalues, the coarse stiffness and mass forms, inverse iteration.

use super::element::{element_stiffness, unit_hermite};
use super::mesh::Mesh;
use crate::linalg::BlockTridiagonal;
use crate::linalg::condition::{ConditionKind, ConditionNumber, smallest_rayleigh_quotient};
use crate::linalg::stop::{NEVER, Stop, Stopped};

/// Coarse elements per mesh piece in the Rayleigh–Ritz space of
/// [`stiffness_condition_bounds`].
const COARSE_PER_PIECE: usize = 4;

/// Rigorous lower bounds on cond₂(A) and on cond₂(D^{-1/2} A D^{-1/2}) (D = diag(A)) of the
/// stiffness matrix, in O(n) without storing A; `None` when the coarse problem could not be
/// solved in floating point (never a made-up bound).
///
/// λ_max(A) is at least A's largest diagonal entry, and λ_max of the scaled matrix at least 1.
/// λ_min is at most the Rayleigh quotient vᵀAv / vᵀMv (M = I, or M = D for the scaled matrix)
/// of any vector v. The vectors tried are the nodal values of piecewise cubics on a coarse
/// mesh — the mesh pieces, each cut into a few coarse elements at fine nodes — so that on every
/// fine element they are cubic and their energy vᵀAv is exactly the coarse stiffness form.
/// That space holds the smooth global modes and the near-rigid motions of a stiff stretch, so
/// inverse iteration in it (block-tridiagonal, a few dozen unknowns) finds a Rayleigh quotient
/// close to λ_min in both cases. The scaled number does not depend on the units (A's u- and
/// u'-rows scale differently with l), which is why the solve path's warning uses it.
pub fn stiffness_condition_bounds(
    mesh: &Mesh,
) -> (Option<ConditionNumber>, Option<ConditionNumber>) {
    stiffness_condition_bounds_until(mesh, NEVER).expect("never stopped")
}

/// [`stiffness_condition_bounds`], giving up when `stop` says so (asked every
/// [`NODES_BETWEEN_QUESTIONS`] fine nodes of the sums over them: 10⁷ nodes are a tenth of a
/// second).
pub fn stiffness_condition_bounds_until(
    mesh: &Mesh,
    stop: Stop,
) -> Result<(Option<ConditionNumber>, Option<ConditionNumber>), Stopped> {
    let coarse = CoarseMesh::of(mesh);
    let sides = diagonal_sides(mesh);
    let (largest, largest_scaled) = largest_eigenvalue_bounds(mesh, &sides);
    let forms = coarse.forms(mesh, &sides, stop)?;
    // No bound at all rather than a made-up one when the coarse problem fails.
    let lower_bound = |largest: f64, mass: &BlockTridiagonal| {
        let smallest = smallest_rayleigh_quotient(&forms.stiffness, mass);
        let value = largest / smallest;
        (value.is_finite() && smallest > 0.0).then_some(ConditionNumber {
            value,
            kind: ConditionKind::LowerBound,
        })
    };
    Ok((
        lower_bound(largest, &forms.plain),
        lower_bound(largest_scaled, &forms.weighted),
    ))
}

/// Fine nodes summed between two questions to `stop`: about a millisecond.
const NODES_BETWEEN_QUESTIONS: usize = 1 << 16;

/// The coarse mesh of the Rayleigh–Ritz space: every piece boundary and a few fine nodes inside
/// each piece; each coarse element lies in one piece.
struct CoarseMesh {
    /// The fine node of every coarse node.
    nodes: Vec<usize>,
    /// The mesh piece of every coarse element.
    piece: Vec<usize>,
}

/// The coarse matrices of the Rayleigh quotients: the stiffness form, and the two mass forms
/// vᵀv (the plain condition number) and vᵀDv (the Jacobi-scaled one) on the fine nodes.
struct CoarseForms {
    stiffness: BlockTridiagonal,
    plain: BlockTridiagonal,
    weighted: BlockTridiagonal,
}

/// Σ N Nᵀ and Σ N' N'ᵀ over the fine nodes of one coarse element (upper triangles), apart for
/// the first node of its mesh piece, which also sees the previous piece in D.
#[derive(Default)]
struct FineSums {
    nn: [[f64; 4]; 4],
    dd: [[f64; 4]; 4],
    first_nn: [[f64; 4]; 4],
    first_dd: [[f64; 4]; 4],
}

impl FineSums {
    /// The form wu·Σ N Nᵀ + wt·Σ N' N'ᵀ, with the weights (wu0, wt0) at the piece's first node.
    fn form(&self, wu: f64, wt: f64, wu0: f64, wt0: f64) -> [[f64; 4]; 4] {
        std::array::from_fn(|r| {
            std::array::from_fn(|c| {
                let (r, c) = (r.min(c), r.max(c));
                wu * self.nn[r][c]
                    + wt * self.dd[r][c]
                    + wu0 * self.first_nn[r][c]
                    + wt0 * self.first_dd[r][c]
            })
        })
    }
}

/// The diagonal of A at a node from the elements on either side: (12EJ/h³, 4EJ/h) of every
/// piece.
fn diagonal_sides(mesh: &Mesh) -> Vec<(f64, f64)> {
    mesh.pieces
        .iter()
        .map(|piece| {
            let h = mesh.element_length(piece);
            let ej = piece.bending_stiffness;
            (12.0 * ej / (h * h * h), 4.0 * ej / h)
        })
        .collect()
}

/// Lower bounds on λ_max of A and of the Jacobi-scaled matrix. λ_max ≥ the diagonal, and ≥ the
/// Rayleigh quotient (48m − 72)/(m − 1)·EJ/h³ of u = ±1 alternating over a piece's m − 1 inner
/// nodes (u' = 0, zero outside): twice the diagonal for long pieces. Scaled by D the same
/// vector gives (48m − 72)/(24(m − 1)).
fn largest_eigenvalue_bounds(mesh: &Mesh, sides: &[(f64, f64)]) -> (f64, f64) {
    let (mut largest, mut largest_scaled) = (0.0f64, 1.0f64);
    for (piece, &(ku, kt)) in mesh.pieces.iter().zip(sides) {
        // Only a piece of two or more elements has nodes with the piece on both sides.
        if piece.elements() >= 2 {
            let m = piece.elements() as f64;
            let ratio = (48.0 * m - 72.0) / (24.0 * (m - 1.0));
            largest = largest.max(ratio * 2.0 * ku).max(2.0 * kt);
            largest_scaled = largest_scaled.max(ratio);
        }
    }
    for pair in sides.windows(2) {
        largest = largest
            .max(pair[0].0 + pair[1].0)
            .max(pair[0].1 + pair[1].1);
    }
    (largest, largest_scaled)
}

impl CoarseMesh {
    /// [`COARSE_PER_PIECE`] coarse elements per mesh piece (fewer on a piece of fewer
    /// elements).
    fn of(mesh: &Mesh) -> CoarseMesh {
        let mut coarse: Vec<usize> = vec![0];
        let mut coarse_piece = Vec::new();
        for (p, piece) in mesh.pieces.iter().enumerate() {
            let m = piece.elements();
            let parts = COARSE_PER_PIECE.min(m);
            for i in 1..=parts {
                coarse.push(piece.first_node + (i * m + parts / 2) / parts);
                coarse_piece.push(p);
            }
        }
        CoarseMesh {
            nodes: coarse,
            piece: coarse_piece,
        }
    }

    /// The coarse stiffness form (the element stiffness of every coarse element: exact, the
    /// vectors are cubic on every fine element) and the two mass forms.
    fn forms(&self, mesh: &Mesh, sides: &[(f64, f64)], stop: Stop) -> Result<CoarseForms, Stopped> {
        let interior = self.nodes.len() - 2;
        let empty = || BlockTridiagonal {
            diag: vec![[0.0; 3]; interior],
            upper: vec![[0.0; 4]; interior.saturating_sub(1)],
        };
        let (mut g, mut plain, mut weighted) = (empty(), empty(), empty());
        for e in 0..self.nodes.len() - 1 {
            let (first, end) = (self.nodes[e], self.nodes[e + 1]);
            let piece = &mesh.pieces[self.piece[e]];
            let length = mesh.nodes[end] - mesh.nodes[first];
            add_element_form(
                &mut g,
                interior,
                e,
                &element_stiffness(piece.bending_stiffness, length),
            );
            let sums = fine_sums(mesh, (first, end), piece.first_node, stop)?;
            // Inside a piece D is constant; the piece's first node also sees the previous
            // piece.
            let p = self.piece[e];
            let inner = (2.0 * sides[p].0, 2.0 * sides[p].1);
            let at_first = match p.checked_sub(1) {
                Some(q) => (sides[q].0 + sides[p].0, sides[q].1 + sides[p].1),
                None => inner,
            };
            add_element_form(&mut plain, interior, e, &sums.form(1.0, 1.0, 1.0, 1.0));
            add_element_form(
                &mut weighted,
                interior,
                e,
                &sums.form(inner.0, inner.1, at_first.0, at_first.1),
            );
        }
        Ok(CoarseForms {
            stiffness: g,
            plain,
            weighted,
        })
    }
}

/// Adds a symmetric 4×4 element form (DOFs u_a, u'_a, u_b, u'_b) on coarse element `e` to a
/// coarse matrix of `interior` coarse nodes with DOFs (the ends are clamped).
fn add_element_form(matrix: &mut BlockTridiagonal, interior: usize, e: usize, k: &[[f64; 4]; 4]) {
    let (left, right) = (e.checked_sub(1), (e < interior).then_some(e));
    if let Some(l) = left {
        let d = &mut matrix.diag[l];
        d[0] += k[0][0];
        d[1] += k[0][1];
        d[2] += k[1][1];
    }
    if let Some(r) = right {
        let d = &mut matrix.diag[r];
        d[0] += k[2][2];
        d[1] += k[2][3];
        d[2] += k[3][3];
    }
    if let (Some(l), Some(_)) = (left, right) {
        let u = &mut matrix.upper[l];
        u[0] += k[0][2];
        u[1] += k[0][3];
        u[2] += k[1][2];
        u[3] += k[1][3];
    }
}

/// Σ N Nᵀ and Σ N' N'ᵀ over the fine nodes `first..end` of one coarse element (the left end
/// belongs here; the supports have no DOFs), N the coarse Hermite basis ([`unit_hermite`]);
/// the node `piece_first` (its mesh piece's first node) apart.
fn fine_sums(
    mesh: &Mesh,
    (first, end): (usize, usize),
    piece_first: usize,
    stop: Stop,
) -> Result<FineSums, Stopped> {
    let last = mesh.elements();
    let (a, length) = (mesh.nodes[first], mesh.nodes[end] - mesh.nodes[first]);
    let mut sums = FineSums::default();
    let inv = 1.0 / length;
    for node in first.max(1)..end.min(last) {
        if node % NODES_BETWEEN_QUESTIONS == 0 && stop() {
            return Err(Stopped);
        }
        let xi = (mesh.nodes[node] - a) * inv;
        let (shape, shape_slope, _, _) = unit_hermite(xi);
        let n = [shape[0], length * shape[1], shape[2], length * shape[3]];
        let dn = [
            shape_slope[0] * inv,
            shape_slope[1],
            shape_slope[2] * inv,
            shape_slope[3],
        ];
        let (target_nn, target_dd) = if node == piece_first {
            (&mut sums.first_nn, &mut sums.first_dd)
        } else {
            (&mut sums.nn, &mut sums.dd)
        };
        for r in 0..4 {
            for c in r..4 {
                target_nn[r][c] += n[r] * n[c];
                target_dd[r][c] += dn[r] * dn[c];
            }
        }
    }
    Ok(sums)
}
