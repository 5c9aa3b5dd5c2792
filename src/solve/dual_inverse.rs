//! `dual-inverse`: the dual method of paper 2.7.2 exactly as the paper computes it — the
//! explicit inverse A⁻¹ (dense, faer's Cholesky), Â = B A⁻¹ Bᵀ and b̂ = B A⁻¹ b of (49), the box
//! QP, then c = A⁻¹ (b − Bᵀ λ) of (48) by a dense product. O(N³) time and O(N²) memory: it is
//! here to show why the paper's dual was slow (its Figures 6 and 8), and refuses sizes whose
//! inverse would not fit comfortably ([`SolveOptions::max_dense_unknowns`]). faer's
//! factorization and inverse run in steps (`linalg::faer_stepwise`, the same bits) so that a
//! cancelled solve stops within milliseconds, not after seconds of O(N³) work.

use faer::Col;

use super::options::SolveOptions;
use super::shared::{MethodOutput, Stopwatch, check_cancel, dual_box_qp, dual_output};
use super::solution::{SolveError, SolveErrorKind, Timing};
use super::stiffness_route::breakdown;
use crate::fem::{Mesh, NodalField, StiffnessMatrix, load_vector};
use crate::linalg::BlockMatrix;
use crate::linalg::faer_stepwise::{
    llt_in_place_until, llt_inverse_until, mat_vec_until, zeros_until,
};
use crate::linalg::release::Background;
use crate::linalg::stop::Stopped;
use crate::model::{Method, Problem};

pub(super) fn solve(
    problem: &Problem,
    mesh: &Mesh,
    options: &SolveOptions,
) -> Result<MethodOutput, SolveError> {
    super::shared::refuse_many_obstacles(problem, Method::DualInverse)?;
    let n = mesh.unknowns();
    if n > options.max_dense_unknowns {
        return Err(SolveError {
            method: Method::DualInverse,
            kind: SolveErrorKind::Refused,
            reason: format!(
                "the dense inverse of A would have N² = {:.1e} entries ({:.0} MB) for n = {} \
                 elements; the limit is N = {} unknowns",
                (n as f64).powi(2),
                (n as f64).powi(2) * 8.0 / 1e6,
                mesh.elements(),
                options.max_dense_unknowns
            ),
            suggestion: Method::Condensed,
        });
    }
    let stop = || options.cancel.is_cancelled();
    let cancelled = |_: Stopped| super::shared::cancelled(Method::DualInverse);
    let mut timing = Timing::default();
    let mut clock = Stopwatch::start();
    let matrix = StiffnessMatrix::new(mesh);
    // The lower triangle of A: what faer's `llt(Side::Lower)` reads.
    // The N×N matrices are freed off this thread, on a cancel too (`linalg::release`).
    let mut a = Background::new(zeros_until(n, &stop).map_err(cancelled)?);
    for i in 0..n / 2 {
        let d = matrix.diag(i);
        a[(2 * i, 2 * i)] = d[0];
        a[(2 * i + 1, 2 * i)] = d[1];
        a[(2 * i + 1, 2 * i + 1)] = d[2];
        if 2 * i + 2 < n {
            let u = matrix.upper(i);
            for r in 0..2 {
                for c in 0..2 {
                    a[(2 * i + 2 + c, 2 * i + r)] = u[2 * r + c];
                }
            }
        }
    }
    let (load_u, load_t) = load_vector(problem, mesh);
    let b = Col::from_fn(n, |i| {
        if i % 2 == 0 {
            load_u[i / 2 + 1]
        } else {
            load_t[i / 2 + 1]
        }
    });
    timing.assembly = clock.lap();

    llt_in_place_until(a.as_mut(), &stop)
        .map_err(cancelled)?
        .map_err(|_| {
            breakdown(
                Method::DualInverse,
                mesh,
                "the dense Cholesky factorization of A failed".into(),
            )
        })?;
    let inverse = Background::new(llt_inverse_until(a.as_ref(), &stop).map_err(cancelled)?);
    drop(a); // off this thread
    timing.factorization = clock.lap();

    // Rows of B: the friction DOFs (u and u' of each obstacle node).
    let dofs: Vec<usize> = mesh
        .obstacle_nodes
        .iter()
        .flat_map(|&node| [2 * (node - 1), 2 * (node - 1) + 1])
        .collect();
    let dim = dofs.len();
    let inverse_b = mat_vec_until(inverse.as_ref(), b.as_ref(), &stop).map_err(cancelled)?;
    let s: Vec<f64> = (0..dim * dim)
        .map(|ij| inverse[(dofs[ij / dim], dofs[ij % dim])])
        .collect();
    let z0: Vec<f64> = dofs.iter().map(|&d| inverse_b[d]).collect();
    let (qp, history) = dual_box_qp(
        (&s, &z0, &problem.thresholds()),
        Method::DualInverse,
        options,
    );
    check_cancel(options, Method::DualInverse)?;
    let lambda = qp.x.clone();
    timing.friction_stage = clock.lap();

    let mut load = b;
    for (q, &d) in dofs.iter().enumerate() {
        load[d] -= lambda[q];
    }
    let c = mat_vec_until(inverse.as_ref(), load.as_ref(), &stop).map_err(cancelled)?;
    let mut field = NodalField::zeros(mesh.nodes.len());
    for i in 0..n / 2 {
        field.deflection[i + 1] = c[2 * i];
        field.slope[i + 1] = c[2 * i + 1];
    }
    timing.reconstruction = clock.lap();

    Ok(MethodOutput {
        history,
        ..dual_output(field, (&qp, &s, &z0), None, (timing, Vec::new()), options)
    })
}
