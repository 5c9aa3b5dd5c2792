//! Arithmetic on the 2×2 blocks of the block-tridiagonal factorization of A ((38); the
//! blocks of (52) in the uniform case): symmetric blocks stored as [a11, a12, a22], general
//! ones row-major.

pub(super) type Sym = [f64; 3];
pub(super) type Mat = [f64; 4];

/// Inverse of a symmetric 2×2 block, and whether it was positive definite; `None` when the
/// block is singular or its determinant is not finite.
pub(super) fn sym_inverse(p: Sym) -> Option<(Sym, bool)> {
    let det = p[0] * p[2] - p[1] * p[1];
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let r = 1.0 / det;
    Some(([p[2] * r, -p[1] * r, p[0] * r], p[0] > 0.0 && det > 0.0))
}

/// S·M for symmetric S.
pub(super) fn sym_mul(s: Sym, m: Mat) -> Mat {
    [
        s[0] * m[0] + s[1] * m[2],
        s[0] * m[1] + s[1] * m[3],
        s[1] * m[0] + s[2] * m[2],
        s[1] * m[1] + s[2] * m[3],
    ]
}

/// M·N.
pub(super) fn mul(m: Mat, n: Mat) -> Mat {
    [
        m[0] * n[0] + m[1] * n[2],
        m[0] * n[1] + m[1] * n[3],
        m[2] * n[0] + m[3] * n[2],
        m[2] * n[1] + m[3] * n[3],
    ]
}

/// Mᵀ·N where the product is known to be symmetric.
pub(super) fn tmul_sym(m: Mat, n: Mat) -> Sym {
    [
        m[0] * n[0] + m[2] * n[2],
        m[0] * n[1] + m[2] * n[3],
        m[1] * n[1] + m[3] * n[3],
    ]
}

/// Mᵀ·v.
pub(super) fn tmul_vec(m: Mat, v: [f64; 2]) -> [f64; 2] {
    [m[0] * v[0] + m[2] * v[1], m[1] * v[0] + m[3] * v[1]]
}

/// M·v.
pub(super) fn mul_vec(m: Mat, v: [f64; 2]) -> [f64; 2] {
    [m[0] * v[0] + m[1] * v[1], m[2] * v[0] + m[3] * v[1]]
}

pub(super) fn sym_vec(s: Sym, v: [f64; 2]) -> [f64; 2] {
    [s[0] * v[0] + s[1] * v[1], s[1] * v[0] + s[2] * v[1]]
}

pub(super) fn neg(m: Mat) -> Mat {
    [-m[0], -m[1], -m[2], -m[3]]
}
