//! The stiffness route's condensation onto the friction DOFs, for the studies: A of (38)
//! factored with the friction nodes last exactly as `dual` and the regularised methods factor
//! it (the same arithmetic, so the same bits), its Schur complement K and condensed load b̃,
//! and from them S = K⁻¹ and z0 = K⁻¹ b̃ of (49).

use crate::fem::{Mesh, StiffnessMatrix, load_vector_until};
use crate::linalg::blocktri::FrictionLastFactor;
use crate::linalg::dense::Cholesky;
use crate::linalg::stop::{Stop, Stopped};
use crate::model::Problem;

/// S (2k×2k row-major) and z0 (2k) of (49), or why they could not be formed.
pub(super) type DualMatrices = Result<(Vec<f64>, Vec<f64>), String>;

/// K and b̃ on the 2k friction DOFs (ordered (u, u') per obstacle).
pub(super) struct Condensation {
    /// K, 2k×2k row-major.
    pub stiffness: Vec<f64>,
    /// b̃ (2k).
    pub load: Vec<f64>,
    /// 2k.
    pub dofs: usize,
}

/// Factors A with the friction nodes last; `Ok(Err(why))` when a pivot breaks down.
pub(super) fn condense(
    problem: &Problem,
    mesh: &Mesh,
    stop: Stop,
) -> Result<Result<Condensation, String>, Stopped> {
    let (mut u, mut t) = load_vector_until(problem, mesh, stop)?;
    let boundary: Vec<usize> = mesh.obstacle_nodes.iter().map(|&node| node - 1).collect();
    let n = mesh.elements();
    let rhs = (&mut u[1..n], &mut t[1..n]);
    let factored =
        FrictionLastFactor::with_rhs_until(StiffnessMatrix::new(mesh), &boundary, rhs, stop)?;
    Ok(match factored {
        Ok((factor, load)) => Ok(Condensation {
            dofs: factor.friction_dofs(),
            stiffness: factor.schur.clone(),
            load,
        }),
        Err(b) => Err(format!(
            "the stiffness matrix A cannot be factored: the pivot of node {} is singular",
            b.block + 1
        )),
    })
}

impl Condensation {
    /// S = K⁻¹ and z0 = K⁻¹ b̃ (49) by Cholesky, as `dual` computes them when K is positive
    /// definite in floating point; `Ok(Err(why))` when it is not (rounding has destroyed A,
    /// where `dual` goes on with an LU factorization and a warning) or S is not finite.
    pub fn dual_matrices(&self, stop: Stop) -> Result<DualMatrices, Stopped> {
        let Some(k) = Cholesky::factor_until(&self.stiffness, self.dofs, stop)? else {
            return Ok(Err(
                "the condensed stiffness K = S⁻¹ on the friction DOFs is not \
                           positive definite in floating point: rounding has destroyed A here"
                    .into(),
            ));
        };
        let s = k.inverse_until(stop)?;
        let z0 = k.solve(&self.load);
        if s.iter().chain(&z0).any(|v| !v.is_finite()) {
            return Ok(Err(
                "S = B A⁻¹ Bᵀ or z0 is not finite in floating point".into()
            ));
        }
        Ok(Ok((s, z0)))
    }
}
