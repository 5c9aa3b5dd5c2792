//! How far the friction stage of a dual method (`dual`, `dual-inverse`, `flexibility`) may be
//! off at every friction DOF, from its own data: the box QP of (49) decides each DOF from
//! S and z0 as the method computed them, so their errors are its errors.
//!
//! With λ from the QP and F its free (stuck) DOFs, a motion is c = z0 − S λ and a stuck force
//! λ_F = S_FF⁻¹ (z0 − S λ_B)_F (λ_B = ±g on the bound ones). An error δS, δz0 in the entries
//! moves c by at most δc = |δz0| + |δS| |λ|, the stuck forces by |S_FF⁻¹| δc_F, and the motion of
//! a bound DOF further by |S_BF| times that (first order, at the QP's own active set). Two
//! kinds of entry error: a relative rounding ρ of every entry, which the certificate knows (the
//! QP's stopping tolerance, the stiffness route's loss with cond(A)); and what the method knows
//! it lost itself, absolutely (the single shooting of `flexibility`).
//!
//! The regularised methods (`regularized`, `regularized-newton`) are off by what ε does
//! ([`regularization_accuracy`]): their answer is the exact solution of (38) with every
//! obstacle displaced by δ_j = clamp(c_j, −ε, ε), and the solution of (38) moves by at most
//! 2 √(S_ii) ‖δ‖_K at DOF i when its obstacles are displaced by δ (the solution map of the
//! convex problem is non-expansive in the energy norm; the displacement costs ‖δ‖_K once as
//! the lifted field and once as the load it makes, K = S⁻¹ the stiffness on the friction
//! DOFs). A motion within that of zero is not one of the exact problem.

use crate::linalg::boxqp::{BoundState, QpResult};
use crate::linalg::dense::Cholesky;
use crate::linalg::stop::{Stop, Stopped};

/// Errors at every obstacle, (sliding, swivel), in SI units.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct FrictionErrors {
    /// Of the motion c (m, rad).
    pub motion: Vec<[f64; 2]>,
    /// Of a stuck force (N, N m); 0 where the QP holds the force at its bound.
    pub force: Vec<[f64; 2]>,
}

impl FrictionErrors {
    /// `self` scaled by `factor` plus `other`.
    fn scaled_plus(&self, factor: f64, other: &FrictionErrors) -> FrictionErrors {
        let combine = |a: &[[f64; 2]], b: &[[f64; 2]]| -> Vec<[f64; 2]> {
            a.iter()
                .zip(b)
                .map(|(a, b)| [factor * a[0] + b[0], factor * a[1] + b[1]])
                .collect()
        };
        FrictionErrors {
            motion: combine(&self.motion, &other.motion),
            force: combine(&self.force, &other.force),
        }
    }
}

/// A dual method's own account of its friction stage's accuracy.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FrictionAccuracy {
    /// Per unit of relative rounding of every entry of S and z0.
    pub per_rounding: FrictionErrors,
    /// What the method's computation of S and z0 lost, as it measured it itself.
    pub lost: FrictionErrors,
}

impl FrictionAccuracy {
    /// The errors when every entry of S and z0 is rounded by `rounding` (relative) on top of
    /// what the method lost itself.
    pub(crate) fn with_rounding(&self, rounding: f64) -> FrictionErrors {
        self.per_rounding.scaled_plus(rounding, &self.lost)
    }
}

/// Absolute errors of the entries of S (row-major) and z0, as a method measured them.
pub(crate) struct EntryErrors {
    pub s: Vec<f64>,
    pub z0: Vec<f64>,
}

/// The accuracy of the QP's answer `qp` on `s` (2k×2k row-major) and `z0`, with the entry
/// errors the method measured itself (`None`: only rounding). `Ok(None)` when the QP's free
/// block is not positive definite in floating point (the QP then did not converge and says
/// so); [`Stopped`] when `stop` said so.
pub(crate) fn friction_accuracy(
    s: &[f64],
    z0: &[f64],
    qp: &QpResult,
    lost: Option<&EntryErrors>,
    stop: Stop,
) -> Result<Option<FrictionAccuracy>, Stopped> {
    let dim = z0.len();
    let lambda = &qp.x;
    // δc per unit of relative rounding: the terms of z0 − S λ.
    let terms: Vec<f64> = (0..dim)
        .map(|i| {
            z0[i].abs()
                + (0..dim)
                    .map(|j| (s[i * dim + j] * lambda[j]).abs())
                    .sum::<f64>()
        })
        .collect();
    let measured: Vec<f64> = match lost {
        Some(e) => (0..dim)
            .map(|i| {
                e.z0[i]
                    + (0..dim)
                        .map(|j| e.s[i * dim + j] * lambda[j].abs())
                        .sum::<f64>()
            })
            .collect(),
        None => vec![0.0; dim],
    };
    let free: Vec<usize> = (0..dim)
        .filter(|&i| qp.state[i] == BoundState::Free)
        .collect();
    let Some(inverse) = free_block_inverse(s, dim, &free, stop)? else {
        return Ok(None);
    };
    let spread = |motion: Vec<f64>| -> FrictionErrors {
        spread_to_forces(s, dim, (&free, &inverse), motion)
    };
    Ok(Some(FrictionAccuracy {
        per_rounding: spread(terms),
        lost: spread(measured),
    }))
}

/// What ε does to the motions of a regularised method's answer `c` on the friction DOFs (K
/// the condensed stiffness there, 2k×2k row-major): 2 √(S_ii) √(δᵀKδ) at DOF i with
/// δ = clamp(c, −ε, ε) (module doc), as `lost`. Its forces are left to the ε-problem's own
/// judgement (a stuck force of the ε-problem is one within that motion of the exact problem's).
/// `Ok(None)` when K is not positive definite in floating point.
pub(crate) fn regularization_accuracy(
    k: &[f64],
    c: &[f64],
    epsilon: f64,
    stop: Stop,
) -> Result<Option<FrictionAccuracy>, Stopped> {
    let dim = c.len();
    let every: Vec<usize> = (0..dim).collect();
    let Some(inverse) = free_block_inverse(k, dim, &every, stop)? else {
        return Ok(None);
    };
    let delta: Vec<f64> = c.iter().map(|v| v.clamp(-epsilon, epsilon)).collect();
    let energy: f64 = (0..dim)
        .map(|i| delta[i] * (0..dim).map(|j| k[i * dim + j] * delta[j]).sum::<f64>())
        .sum();
    let norm = energy.max(0.0).sqrt();
    let motion: Vec<f64> = (0..dim)
        .map(|i| 2.0 * inverse[i * dim + i].sqrt() * norm)
        .collect();
    Ok(Some(FrictionAccuracy {
        per_rounding: FrictionErrors {
            motion: vec![[0.0; 2]; dim / 2],
            force: vec![[0.0; 2]; dim / 2],
        },
        lost: FrictionErrors {
            motion: pairs(&motion),
            force: vec![[0.0; 2]; dim / 2],
        },
    }))
}

/// |S_FF⁻¹| (m×m row-major, m = |F|), from the Cholesky factor of S_FF scaled to unit
/// diagonal (S mixes m/N and rad/(N m)); `None` when it is not positive definite.
fn free_block_inverse(
    s: &[f64],
    dim: usize,
    free: &[usize],
    stop: Stop,
) -> Result<Option<Vec<f64>>, Stopped> {
    let m = free.len();
    let scale: Vec<f64> = free.iter().map(|&i| 1.0 / s[i * dim + i].sqrt()).collect();
    let block: Vec<f64> = (0..m * m)
        .map(|ab| {
            let (a, b) = (ab / m, ab % m);
            s[free[a] * dim + free[b]] * scale[a] * scale[b]
        })
        .collect();
    if block.iter().any(|v| !v.is_finite()) {
        return Ok(None);
    }
    let Some(factor) = Cholesky::factor_until(&block, m, stop)? else {
        return Ok(None);
    };
    let mut inverse = factor.inverse_until(stop)?;
    for (ab, v) in inverse.iter_mut().enumerate() {
        *v = v.abs() * scale[ab / m] * scale[ab % m];
    }
    Ok(Some(inverse))
}

/// The errors that a motion error `motion` of every c_i makes: |S_FF⁻¹| δc_F on the stuck
/// forces, and on the motion of a bound DOF its own δc plus |S_BF| times those forces'.
fn spread_to_forces(
    s: &[f64],
    dim: usize,
    (free, inverse): (&[usize], &[f64]),
    mut motion: Vec<f64>,
) -> FrictionErrors {
    let m = free.len();
    let mut is_free = vec![false; dim];
    for &i in free {
        is_free[i] = true;
    }
    let mut force = vec![0.0; dim];
    for (a, &i) in free.iter().enumerate() {
        force[i] = (0..m).map(|b| inverse[a * m + b] * motion[free[b]]).sum();
    }
    for i in 0..dim {
        if !is_free[i] {
            motion[i] += free
                .iter()
                .map(|&j| (s[i * dim + j] * force[j]).abs())
                .sum::<f64>();
        }
    }
    FrictionErrors {
        motion: pairs(&motion),
        force: pairs(&force),
    }
}

/// Per obstacle (sliding, swivel).
fn pairs(v: &[f64]) -> Vec<[f64; 2]> {
    v.chunks(2).map(|c| [c[0], c[1]]).collect()
}
