//! 2-norm condition numbers of SPD matrices, as the paper's Figure 5 plots them:
//! exact from all eigenvalues (faer) for small N, Lanczos estimates of the extreme eigenvalues
//! for large N (λ_max from A, λ_min from A⁻¹ through the block-tridiagonal factorization), and
//! a cheap rigorous lower bound for the stiffness matrix (max diagonal entry over a
//! Rayleigh–Ritz value of smooth vectors) that the solve path uses for its warnings.

use faer::{Mat, Side};
use serde::Serialize;

use super::blocktri::FrictionLastFactor;
use crate::fem::{BlockMatrix, BlockTridiagonal, Mesh};

/// Largest N for which all eigenvalues are computed.
pub const DENSE_LIMIT: usize = 200;
/// Lanczos steps for each extreme eigenvalue.
const LANCZOS_STEPS: usize = 40;

/// How a condition number was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ConditionKind {
    /// From all eigenvalues.
    Exact,
    /// Lanczos estimate of the extreme eigenvalues (from below).
    Estimate,
    /// A rigorous lower bound.
    LowerBound,
}

/// A condition number and how it was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ConditionNumber {
    pub value: f64,
    pub kind: ConditionKind,
}

impl ConditionNumber {
    /// Does the number mean that a backward-stable solve may lose every digit
    /// (cond · eps ≥ 1)?
    pub fn beyond_double_precision(&self) -> bool {
        self.value * f64::EPSILON >= 1.0
    }
}

/// Extreme eigenvalues (min, max) of a dense symmetric row-major matrix.
pub fn dense_extremes(a: &[f64], n: usize) -> Option<(f64, f64)> {
    let m = Mat::from_fn(n, n, |i, j| a[i * n + j]);
    let values = m.self_adjoint_eigenvalues(Side::Lower).ok()?;
    Some((*values.first()?, *values.last()?))
}

/// cond₂ of a dense SPD matrix from its eigenvalues.
pub fn dense_condition(a: &[f64], n: usize) -> Option<ConditionNumber> {
    let (min, max) = dense_extremes(a, n)?;
    condition_from(min, max, ConditionKind::Exact)
}

fn condition_from(min: f64, max: f64, kind: ConditionKind) -> Option<ConditionNumber> {
    let value = max / min;
    (min > 0.0 && value.is_finite()).then_some(ConditionNumber { value, kind })
}

/// The matrix D^{-1/2} A D^{-1/2} with D = diag(A): unit diagonal.
pub fn jacobi_scaled(a: &BlockTridiagonal) -> BlockTridiagonal {
    let s: Vec<[f64; 2]> = a
        .diag
        .iter()
        .map(|d| [1.0 / d[0].sqrt(), 1.0 / d[2].sqrt()])
        .collect();
    BlockTridiagonal {
        diag: a
            .diag
            .iter()
            .zip(&s)
            .map(|(d, s)| [d[0] * s[0] * s[0], d[1] * s[0] * s[1], d[2] * s[1] * s[1]])
            .collect(),
        upper: a
            .upper
            .iter()
            .enumerate()
            .map(|(i, u)| {
                let (l, r) = (s[i], s[i + 1]);
                [
                    u[0] * l[0] * r[0],
                    u[1] * l[0] * r[1],
                    u[2] * l[1] * r[0],
                    u[3] * l[1] * r[1],
                ]
            })
            .collect(),
    }
}

/// cond₂ of a block-tridiagonal SPD matrix: exact for N ≤ [`DENSE_LIMIT`], else a Lanczos
/// estimate. `None` if the matrix is not positive definite to working precision.
pub fn block_condition(a: &BlockTridiagonal) -> Option<ConditionNumber> {
    let n = 2 * a.blocks();
    if n <= DENSE_LIMIT {
        return dense_condition(&a.to_dense(), n);
    }
    let max = lanczos_largest(n, |v| flat_apply(a, v));
    let factor = FrictionLastFactor::new(a.clone(), &[]).ok()?;
    if factor.first_indefinite.is_some() {
        // A is not positive definite in floating point: cond(A)·eps ≳ 1.
        return None;
    }
    let inverse_max = lanczos_largest(n, |v| {
        let mut u: Vec<f64> = v.iter().step_by(2).copied().collect();
        let mut t: Vec<f64> = v.iter().skip(1).step_by(2).copied().collect();
        factor.solve(&mut u, &mut t, |_| Vec::new());
        u.iter().zip(&t).flat_map(|(a, b)| [*a, *b]).collect()
    });
    condition_from(1.0 / inverse_max, max, ConditionKind::Estimate)
}

fn flat_apply(a: &BlockTridiagonal, v: &[f64]) -> Vec<f64> {
    let blocks: Vec<[f64; 2]> = v.chunks(2).map(|c| [c[0], c[1]]).collect();
    a.apply(&blocks).into_iter().flatten().collect()
}

/// Largest eigenvalue of a symmetric operator by Lanczos without reorthogonalisation (the
/// extreme Ritz value converges from below), deterministic start vector.
fn lanczos_largest(n: usize, apply: impl Fn(&[f64]) -> Vec<f64>) -> f64 {
    let steps = LANCZOS_STEPS.min(n);
    let mut v: Vec<f64> = (0..n)
        .map(|i| 1.0 + 0.5 * ((i as f64) * 0.618_033_988_75).fract())
        .collect();
    let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    v.iter_mut().for_each(|x| *x /= norm);
    let mut previous = vec![0.0; n];
    let (mut alphas, mut betas) = (Vec::new(), Vec::new());
    let mut beta = 0.0;
    for _ in 0..steps {
        let mut w = apply(&v);
        let alpha: f64 = w.iter().zip(&v).map(|(a, b)| a * b).sum();
        for i in 0..n {
            w[i] -= alpha * v[i] + beta * previous[i];
        }
        alphas.push(alpha);
        beta = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        if beta <= 1e-14 * alpha.abs() || !beta.is_finite() {
            break;
        }
        betas.push(beta);
        previous = std::mem::replace(&mut v, w.into_iter().map(|x| x / beta).collect());
    }
    let m = alphas.len();
    let t = Mat::from_fn(m, m, |i, j| {
        if i == j {
            alphas[i]
        } else if i + 1 == j || j + 1 == i {
            betas[i.min(j)]
        } else {
            0.0
        }
    });
    t.self_adjoint_eigenvalues(Side::Lower)
        .ok()
        .and_then(|v| v.last().copied())
        .unwrap_or(f64::NAN)
}

/// Coarse elements per mesh piece in the Rayleigh–Ritz space of
/// [`stiffness_condition_bounds`].
const COARSE_PER_PIECE: usize = 4;
/// Inverse-iteration steps in the coarse space.
const COARSE_ITERATIONS: usize = 30;

/// Rigorous lower bounds on cond₂(A) and on cond₂(D^{-1/2} A D^{-1/2}) (D = diag(A)) of the
/// stiffness matrix, in O(n) without storing A.
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
pub fn stiffness_condition_bounds(mesh: &Mesh) -> (ConditionNumber, ConditionNumber) {
    use crate::fem::element_stiffness;
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
    let lower_bound = |largest: f64, mass: &BlockTridiagonal| {
        let smallest = smallest_rayleigh_quotient(&g, mass);
        let value = largest / smallest;
        ConditionNumber {
            value: if value.is_finite() && smallest > 0.0 {
                value
            } else {
                1.0
            },
            kind: ConditionKind::LowerBound,
        }
    };
    (
        lower_bound(largest, &plain),
        lower_bound(largest_scaled, &weighted),
    )
}

/// The Rayleigh quotient vᵀGv / vᵀMv after inverse iteration v ← G⁻¹Mv: an upper bound on the
/// smallest eigenvalue of the pencil (G, M), close to it after a few dozen steps.
fn smallest_rayleigh_quotient(g: &BlockTridiagonal, m: &BlockTridiagonal) -> f64 {
    let blocks = g.blocks();
    if blocks == 0 {
        return f64::NAN;
    }
    let Ok(factor) = FrictionLastFactor::new(g.clone(), &[]) else {
        return f64::NAN;
    };
    let dot = |x: &[[f64; 2]], y: &[[f64; 2]]| -> f64 {
        x.iter()
            .zip(y)
            .map(|(a, b)| a[0] * b[0] + a[1] * b[1])
            .sum()
    };
    let mut v: Vec<[f64; 2]> = vec![[1.0, 0.0]; blocks];
    let mut quotient = f64::INFINITY;
    for _ in 0..COARSE_ITERATIONS {
        let mv = m.apply(&v);
        let mut u: Vec<f64> = mv.iter().map(|x| x[0]).collect();
        let mut t: Vec<f64> = mv.iter().map(|x| x[1]).collect();
        factor.solve(&mut u, &mut t, |_| Vec::new());
        let norm = u.iter().chain(&t).fold(0.0f64, |s, x| s.max(x.abs()));
        if !(norm > 0.0 && norm.is_finite()) {
            return f64::NAN;
        }
        v = u
            .iter()
            .zip(&t)
            .map(|(a, b)| [a / norm, b / norm])
            .collect();
        // Every quotient is an upper bound on λ_min; stop once it has settled.
        let next = dot(&v, &g.apply(&v)) / dot(&v, &m.apply(&v));
        let settled = (quotient - next).abs() <= 1e-4 * next;
        quotient = quotient.min(next);
        if settled {
            break;
        }
    }
    quotient
}
