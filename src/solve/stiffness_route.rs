//! The part of the stiffness route that `dual`, `regularized` and `regularized-newton` share:
//! assemble A and b of (38), factor A once with the friction nodes last
//! ([`FrictionLastFactor`]) and condense onto the 2k friction DOFs; afterwards, rebuild the
//! primal solution from the friction DOF values (48).
//!
//! On the friction DOFs the problem reads: K c_F = b̃ − λ with K the Schur complement and
//! b̃ = b_F − A_FI A_II⁻¹ b_I. Hence S = B A⁻¹ Bᵀ = K⁻¹ and z0 = K⁻¹ b̃ (49), and the cases of
//! the regularised method (43) only change K's diagonal and b̃.

use super::options::SolveOptions;
use super::shared::Stopwatch;
use super::solution::{SolveError, SolveErrorKind, Timing, Warning, WarningCode};
use crate::fem::{Mesh, NodalField, StiffnessMatrix, load_vector_until};
use crate::linalg::blocktri::FrictionLastFactor;
use crate::linalg::dense::{Cholesky, mat_vec};
use crate::linalg::faer_stepwise::{lu_inverse_until, partial_piv_lu_until};
use crate::linalg::stop::Stopped;
use crate::model::{Method, Problem};

/// The stiffness matrix A factored with the friction nodes last, and its Schur complement K and
/// condensed load b̃ on the friction DOFs.
pub(super) struct FactoredStiffness<'m> {
    factor: FrictionLastFactor<StiffnessMatrix<'m>>,
    /// The forward-eliminated right-hand side by node (u-part, u'-part), ends included; it
    /// becomes the solution in place.
    rhs: (Vec<f64>, Vec<f64>),
    /// K, 2k×2k row-major.
    pub friction_stiffness: Vec<f64>,
    /// b̃ (2k).
    pub friction_load: Vec<f64>,
    /// 2k.
    pub friction_dofs: usize,
}

/// Assembles and factors; times the two stages into `timing`. Cancelled inside both sweeps.
pub(super) fn assemble_and_factor<'m>(
    problem: &Problem,
    mesh: &'m Mesh,
    (method, options): (Method, &SolveOptions),
    timing: &mut Timing,
) -> Result<FactoredStiffness<'m>, SolveError> {
    let stop = || options.cancel.is_cancelled();
    let cancelled = |_: Stopped| super::shared::cancelled(method);
    let mut clock = Stopwatch::start();
    let matrix = StiffnessMatrix::new(mesh);
    let (mut u, mut t) = load_vector_until(problem, mesh, &stop).map_err(cancelled)?;
    timing.assembly = clock.lap();
    let boundary: Vec<usize> = mesh.obstacle_nodes.iter().map(|&node| node - 1).collect();
    let n = mesh.elements();
    let rhs = (&mut u[1..n], &mut t[1..n]);
    let (factor, load) = FrictionLastFactor::with_rhs_until(matrix, &boundary, rhs, &stop)
        .map_err(cancelled)?
        .map_err(|b| {
            breakdown(
                method,
                mesh,
                format!("the pivot of node {} is singular", b.block + 1),
            )
        })?;
    timing.factorization = clock.lap();
    Ok(FactoredStiffness {
        friction_stiffness: factor.schur.clone(),
        friction_dofs: factor.friction_dofs(),
        factor,
        rhs: (u, t),
        friction_load: load,
    })
}

/// The right-hand side by node (160 MB at n = 10⁷) is freed off the solving thread, as is the
/// factor's storage (`linalg::release`): a cancelled solve returns without waiting for it.
impl Drop for FactoredStiffness<'_> {
    fn drop(&mut self) {
        crate::linalg::release::release(std::mem::take(&mut self.rhs.0));
        crate::linalg::release::release(std::mem::take(&mut self.rhs.1));
    }
}

impl FactoredStiffness<'_> {
    /// The first node whose pivot was not positive definite, if rounding destroyed A.
    fn first_indefinite_node(&self) -> Option<usize> {
        self.factor.first_indefinite.map(|block| block + 1)
    }

    /// The nodal solution for the given values on the friction DOFs; cancelled inside the
    /// sweep.
    pub fn reconstruct(
        mut self,
        friction_values: &[f64],
        (method, options): (Method, &SolveOptions),
    ) -> Result<NodalField, SolveError> {
        let (mut u, mut t) = std::mem::take(&mut self.rhs);
        let n = u.len() - 1;
        let stop = || options.cancel.is_cancelled();
        let swept = self
            .factor
            .backward_until(&mut u[1..n], &mut t[1..n], friction_values, &stop);
        if swept.is_err() {
            crate::linalg::release::release(u);
            crate::linalg::release::release(t);
            return Err(super::shared::cancelled(method));
        }
        Ok(NodalField {
            deflection: u,
            slope: t,
        })
    }
}

/// S (2k×2k row-major), z0, and a warning when K had to be inverted by LU.
pub(super) type DualMatrices = (Vec<f64>, Vec<f64>, Option<Warning>);

impl FactoredStiffness<'_> {
    /// S = K⁻¹ and z0 = K⁻¹ b̃ of (49). K is SPD in exact arithmetic; when rounding has made it
    /// indefinite, the inverse comes from an LU factorization instead and the warning says so.
    /// Cancelled between columns of the factorization and the inverse (a second of work each
    /// at 2k = 1022).
    pub fn dual_matrices(
        &self,
        method: Method,
        mesh: &Mesh,
        options: &SolveOptions,
    ) -> Result<DualMatrices, SolveError> {
        let dim = self.friction_dofs;
        let stop = || options.cancel.is_cancelled();
        let cancelled = |_: Stopped| super::shared::cancelled(method);
        let cholesky =
            Cholesky::factor_until(&self.friction_stiffness, dim, &stop).map_err(cancelled)?;
        if let Some(k) = cholesky {
            let inverse = k.inverse_until(&stop).map_err(cancelled)?;
            return Ok((inverse, k.solve(&self.friction_load), None));
        }
        // LU with partial pivoting and its inverse, both in steps.
        let k = faer::Mat::from_fn(dim, dim, |i, j| self.friction_stiffness[i * dim + j]);
        let (lu, p) = partial_piv_lu_until(k.as_ref(), &stop).map_err(cancelled)?;
        let inverse =
            lu_inverse_until((lu.as_ref(), lu.as_ref(), p.as_ref()), &stop).map_err(cancelled)?;
        let s: Vec<f64> = (0..dim * dim)
            .map(|ij| inverse[(ij / dim, ij % dim)])
            .collect();
        if s.iter().any(|v| !v.is_finite()) {
            return Err(breakdown(
                method,
                mesh,
                "the condensed stiffness on the friction DOFs is singular".into(),
            ));
        }
        let z0 = mat_vec(&s, &self.friction_load);
        let warning = Warning::new(
            WarningCode::IndefiniteFactorization,
            format!(
                "the condensed stiffness K on the friction DOFs is not positive definite in \
                 floating point at n = {}: rounding has destroyed it and this result means nothing",
                mesh.elements()
            ),
        );
        Ok((s, z0, Some(warning)))
    }
}

/// The warning for a factorization that went on through indefinite pivots.
pub(super) fn indefinite_warning(factored: &FactoredStiffness, mesh: &Mesh) -> Option<Warning> {
    factored.first_indefinite_node().map(|node| {
        Warning::new(
            WarningCode::IndefiniteFactorization,
            format!(
                "A is not positive definite in floating point at n = {} (first at node {node} of \
                 {}): rounding has destroyed the stiffness matrix and this result means nothing",
                mesh.elements(),
                mesh.elements()
            ),
        )
    })
}

/// The error for a factorization that broke down in floating point.
pub(super) fn breakdown(method: Method, mesh: &Mesh, what: String) -> SolveError {
    SolveError {
        method,
        kind: SolveErrorKind::Breakdown,
        reason: format!(
            "{what} at n = {} elements: rounding of the stiffness matrix has destroyed it",
            mesh.elements()
        ),
        suggestion: Method::Condensed,
    }
}
