//! A cheap rigorous lower bound on the condition number of the stiffness matrix A, from the
//! mesh alone (A is never stored): what the solve path's conditioning warning rests on.

use super::element::element_stiffness;
use super::mesh::Mesh;
use crate::linalg::BlockTridiagonal;
use crate::linalg::condition::{ConditionKind, ConditionNumber, smallest_rayleigh_quotient};

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
    let last = mesh.elements();
    // Coarse nodes: every piece boundary and a few fine nodes inside each piece; each coarse
    // element lies in one piece.
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
    let interior = coarse.len() - 2;
    let empty = || BlockTridiagonal {
        diag: vec![[0.0; 3]; interior],
        upper: vec![[0.0; 4]; interior.saturating_sub(1)],
    };
    let (mut g, mut plain, mut weighted) = (empty(), empty(), empty());
    // Adds a symmetric 4×4 element form (DOFs u_a, u'_a, u_b, u'_b) on coarse element e.
    let add = |matrix: &mut BlockTridiagonal, e: usize, k: &[[f64; 4]; 4]| {
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
    };
    // The diagonal of A at a node from the elements on either side: (12EJ/h³, 4EJ/h) each.
    let sides: Vec<(f64, f64)> = mesh
        .pieces
        .iter()
        .map(|piece| {
            let h = mesh.element_length(piece);
            let ej = piece.bending_stiffness;
            (12.0 * ej / (h * h * h), 4.0 * ej / h)
        })
        .collect();
    // λ_max ≥ the diagonal, and ≥ the Rayleigh quotient (48m − 72)/(m − 1)·EJ/h³ of u = ±1
    // alternating over a piece's m − 1 inner nodes (u' = 0, zero outside): twice the diagonal
    // for long pieces. Scaled by D the same vector gives (48m − 72)/(24(m − 1)).
    let (mut largest, mut largest_scaled) = (0.0f64, 1.0f64);
    for (piece, &(ku, kt)) in mesh.pieces.iter().zip(&sides) {
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
    for e in 0..coarse.len() - 1 {
        let (first, end) = (coarse[e], coarse[e + 1]);
        let piece = &mesh.pieces[coarse_piece[e]];
        let (a, length) = (mesh.nodes[first], mesh.nodes[end] - mesh.nodes[first]);
        add(
            &mut g,
            e,
            &element_stiffness(piece.bending_stiffness, length),
        );
        // Σ N Nᵀ and Σ N' N'ᵀ over the fine nodes first..end (the left end belongs here; the
        // supports have no DOFs), N the coarse Hermite basis. Inside a piece D is constant;
        // the piece's first node also sees the previous piece.
        let mut nn = [[0.0f64; 4]; 4];
        let mut dd = [[0.0f64; 4]; 4];
        let (mut first_nn, mut first_dd) = ([[0.0f64; 4]; 4], [[0.0f64; 4]; 4]);
        let inv = 1.0 / length;
        for node in first.max(1)..end.min(last) {
            let xi = (mesh.nodes[node] - a) * inv;
            let (x2, x3) = (xi * xi, xi * xi * xi);
            let n = [
                1.0 - 3.0 * x2 + 2.0 * x3,
                length * (xi - 2.0 * x2 + x3),
                3.0 * x2 - 2.0 * x3,
                length * (x3 - x2),
            ];
            let dn = [
                6.0 * (x2 - xi) * inv,
                1.0 - 4.0 * xi + 3.0 * x2,
                6.0 * (xi - x2) * inv,
                3.0 * x2 - 2.0 * xi,
            ];
            let (target_nn, target_dd) = if node == piece.first_node {
                (&mut first_nn, &mut first_dd)
            } else {
                (&mut nn, &mut dd)
            };
            for r in 0..4 {
                for c in r..4 {
                    target_nn[r][c] += n[r] * n[c];
                    target_dd[r][c] += dn[r] * dn[c];
                }
            }
        }
        let p = coarse_piece[e];
        let inner = (2.0 * sides[p].0, 2.0 * sides[p].1);
        let at_first = match p.checked_sub(1) {
            Some(q) => (sides[q].0 + sides[p].0, sides[q].1 + sides[p].1),
            None => inner,
        };
        let form = |wu: f64, wt: f64, wu0: f64, wt0: f64| -> [[f64; 4]; 4] {
            std::array::from_fn(|r| {
                std::array::from_fn(|c| {
                    let (r, c) = (r.min(c), r.max(c));
                    wu * nn[r][c] + wt * dd[r][c] + wu0 * first_nn[r][c] + wt0 * first_dd[r][c]
                })
            })
        };
        add(&mut plain, e, &form(1.0, 1.0, 1.0, 1.0));
        add(
            &mut weighted,
            e,
            &form(inner.0, inner.1, at_first.0, at_first.1),
        );
    }
    // No bound at all rather than a made-up one when the coarse problem fails.
    let lower_bound = |largest: f64, mass: &BlockTridiagonal| {
        let smallest = smallest_rayleigh_quotient(&g, mass);
        let value = largest / smallest;
        (value.is_finite() && smallest > 0.0).then_some(ConditionNumber {
            value,
            kind: ConditionKind::LowerBound,
        })
    };
    (
        lower_bound(largest, &plain),
        lower_bound(largest_scaled, &weighted),
    )
}
