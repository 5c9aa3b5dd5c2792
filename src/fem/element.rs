//! The Hermite cubic element of paper 2.6: the basis functions (on the unit element and on an
//! element of length h), the element stiffness EJ ∫ φ_i'' φ_j'' (the blocks of (52)) and the
//! exactly integrated load ∫ f φ_i for a linear f, the pieces of A and b in (38).

/// The four Hermite cubics on the unit element ξ ∈ [0, 1] and their first three derivatives
/// with respect to ξ, the slope DOFs per unit length — the basis of paper 2.6, written once.
/// Order of the degrees of freedom: (u_a, u'_a, u_b, u'_b). On an element of length h the
/// basis is (N₀, h N₁, N₂, h N₃), and each x-derivative one more factor 1/h
/// ([`hermite_basis`]).
pub fn unit_hermite(xi: f64) -> ([f64; 4], [f64; 4], [f64; 4], [f64; 4]) {
    let (x2, x3) = (xi * xi, xi * xi * xi);
    let value = [
        1.0 - 3.0 * x2 + 2.0 * x3,
        xi - 2.0 * x2 + x3,
        3.0 * x2 - 2.0 * x3,
        x3 - x2,
    ];
    let first = [
        6.0 * (x2 - xi),
        1.0 - 4.0 * xi + 3.0 * x2,
        6.0 * (xi - x2),
        3.0 * x2 - 2.0 * xi,
    ];
    let second = [
        12.0 * xi - 6.0,
        6.0 * xi - 4.0,
        6.0 - 12.0 * xi,
        6.0 * xi - 2.0,
    ];
    let third = [12.0, 6.0, -12.0, 6.0];
    (value, first, second, third)
}

/// Values and the first three derivatives (with respect to x) of the four Hermite cubics on an
/// element of length `h` at the local coordinate `xi` = (x − a)/h ∈ [0, 1]: `unit_hermite`
/// scaled to the element. Order of the degrees of freedom: (u_a, u'_a, u_b, u'_b).
pub fn hermite_basis(xi: f64, h: f64) -> ([f64; 4], [f64; 4], [f64; 4], [f64; 4]) {
    let (n, dn, ddn, dddn) = unit_hermite(xi);
    let value = [n[0], h * n[1], n[2], h * n[3]];
    let first = [dn[0] / h, dn[1], dn[2] / h, dn[3]];
    let second = [ddn[0] / (h * h), ddn[1] / h, ddn[2] / (h * h), ddn[3] / h];
    let third = [
        dddn[0] / (h * h * h),
        dddn[1] / (h * h),
        dddn[2] / (h * h * h),
        dddn[3] / (h * h),
    ];
    (value, first, second, third)
}

/// The element stiffness matrix EJ ∫ φ_i'' φ_j'' dx (4×4, symmetric) for DOFs
/// (u_a, u'_a, u_b, u'_b); with EJ = 1 and a uniform mesh it gives the blocks H, G of (52).
pub fn element_stiffness(ej: f64, h: f64) -> [[f64; 4]; 4] {
    let k = ej / (h * h * h);
    let (a, b, c) = (12.0 * k, 6.0 * h * k, 4.0 * h * h * k);
    let d = 2.0 * h * h * k;
    [[a, b, -a, b], [b, c, -b, d], [-a, -b, a, -b], [b, d, -b, c]]
}

/// ∫ f φ_i dx over an element of length `h` for f linear from `fa` to `fb`: exact
/// (the integrand is a polynomial of degree 4).
pub fn element_load(h: f64, fa: f64, fb: f64) -> [f64; 4] {
    [
        h * (7.0 * fa + 3.0 * fb) / 20.0,
        h * h * (3.0 * fa + 2.0 * fb) / 60.0,
        h * (3.0 * fa + 7.0 * fb) / 20.0,
        -h * h * (2.0 * fa + 3.0 * fb) / 60.0,
    ]
}
