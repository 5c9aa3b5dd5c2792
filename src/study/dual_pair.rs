//! The dual problem (49) restricted to one obstacle's pair of forces (λ1, λ2), the others held
//! at given forces, for the explorer's picture of the dual: the box [−g1, g1] × [−g2, g2], the
//! level curves of the restricted quadratic, its unconstrained minimiser and where the given
//! forces sit on the box.
//!
//! The dual methods minimise ½ λᵀ S λ − z0ᵀ λ over |λ| ≤ g with S = B A⁻¹ Bᵀ (`linalg::boxqp`);
//! with every λ_j, j ≠ i, fixed this is q_i(λ_i) = ½ λ_iᵀ S_ii λ_i − r_iᵀ λ_i + const with
//! r_i = z0_i − Σ_{j≠i} S_ij λ_j. The motion of obstacle i's DOFs is c_i = z0_i − (S λ)_i =
//! r_i − S_ii λ_i = −∇q_i, and a moving DOF carries λ = g·sign c (`FrictionState`): at the
//! solution, a DOF on the edge of the box moves outward, an interior one is stuck.
//!
//! Where the forces sit is decided as the certificate decides the states
//! (`solve::certificate`'s `states`, with `solve::friction_accuracy`): the motion's
//! uncertainty is the dual method's own error bound with its data's rounding (or 64 ulps of
//! the terms of c, the larger), the force's likewise; a force within its uncertainty of the
//! threshold whose motion is not resolved fits both "stuck" and "moves", and the position is
//! [`BoxPosition::Undecided`].

use serde::Serialize;

use super::condensation::condense;
use super::{Cancel, Cancelled};
use crate::fem::{Mesh, StiffnessMatrix, stiffness_condition_bounds_until};
use crate::linalg::BlockMatrix;
use crate::linalg::boxqp::{BoundState, QpResult};
use crate::linalg::condition::{
    ConditionKind, ConditionNumber, DENSE_LIMIT, block_condition_until, jacobi_scaled,
};
use crate::linalg::stop::{NEVER, Stop, Stopped};
use crate::model::{Method, Problem};
use crate::solve::internals::{
    FORCE_ULPS, FrictionErrors, MOTION_ULPS, friction_accuracy, friction_data_rounding,
};

/// Where the forces of one obstacle sit on its box.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum BoxPosition {
    /// |λ1| < g1 and |λ2| < g2: stuck.
    Interior,
    /// |λ1| = g1 only: slides.
    SlidingEdge,
    /// |λ2| = g2 only: swivels.
    SwivelEdge,
    /// Both: slides and swivels.
    Corner,
    /// Rounding cannot decide: a force within rounding of its threshold with a motion that
    /// rounding cannot tell from zero (the certificate's "at the threshold").
    Undecided,
}

/// (49) restricted to one obstacle's pair.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DualPair {
    pub obstacle: usize,
    /// S_ii = B_i A⁻¹ B_iᵀ, the 2×2 block of S [m/N, m/(N m); rad/N, rad/(N m)].
    pub flexibility: [[f64; 2]; 2],
    /// r_i = z0_i − Σ_{j≠i} S_ij λ_j: the motion of obstacle i's DOFs with its own friction
    /// removed [m, rad].
    pub linear: [f64; 2],
    /// g1, g2: the box [−g1, g1] × [−g2, g2].
    pub thresholds: [f64; 2],
    /// S_ii⁻¹ r_i, the unconstrained minimiser.
    pub minimiser: [f64; 2],
    /// The forces given for obstacle i.
    pub solution: [f64; 2],
    /// Where `solution` is on the box.
    pub position: BoxPosition,
    /// The motion c_i = r_i − S_ii λ_i at `solution` [m, rad] (−∇q_i).
    pub motion: [f64; 2],
}

impl DualPair {
    /// q_i(λ) = ½ λᵀ S_ii λ − r_iᵀ λ, the restriction of (49) (up to a constant).
    pub fn value(&self, lambda: [f64; 2]) -> f64 {
        let s = &self.flexibility;
        let quadratic = lambda[0] * (s[0][0] * lambda[0] + s[0][1] * lambda[1])
            + lambda[1] * (s[1][0] * lambda[0] + s[1][1] * lambda[1]);
        0.5 * quadratic - self.linear[0] * lambda[0] - self.linear[1] * lambda[1]
    }

    /// The smallest value of q_i, at the unconstrained minimiser.
    pub fn minimum(&self) -> f64 {
        self.value(self.minimiser)
    }

    /// The ellipse q_i = `level` as `points` points, the first repeated as the last (a closed
    /// polyline); empty below the minimum or when S_ii is not positive definite.
    pub fn level_curve(&self, level: f64, points: usize) -> Vec<[f64; 2]> {
        let radius_squared = 2.0 * (level - self.minimum());
        let s = &self.flexibility;
        // S_ii = L Lᵀ; λ − m = L⁻ᵀ ρ (cos θ, sin θ) traces (λ − m)ᵀ S_ii (λ − m) = ρ².
        let l11 = s[0][0].sqrt();
        let l21 = s[0][1] / l11;
        let l22 = (s[1][1] - l21 * l21).sqrt();
        if !(radius_squared >= 0.0 && l11 > 0.0 && l22 > 0.0) || points == 0 {
            return Vec::new();
        }
        let radius = radius_squared.sqrt();
        let steps = points.saturating_sub(1).max(1) as f64;
        (0..points)
            .map(|j| {
                // The last point is the first again, exactly.
                let turn = if j + 1 == points && points > 1 { 0 } else { j };
                let theta = std::f64::consts::TAU * turn as f64 / steps;
                let (w1, w2) = (radius * theta.cos(), radius * theta.sin());
                let y2 = w2 / l22;
                let y1 = (w1 - l21 * y2) / l11;
                [self.minimiser[0] + y1, self.minimiser[1] + y2]
            })
            .collect()
    }

    /// The minimiser of q_i over the box, exactly: the unconstrained one when it is inside,
    /// else the best of the four edges' one-dimensional minimisers (q_i is convex).
    pub fn box_minimiser(&self) -> [f64; 2] {
        let (s, r, g) = (&self.flexibility, &self.linear, &self.thresholds);
        let inside = |l: [f64; 2]| l[0].abs() <= g[0] && l[1].abs() <= g[1];
        let mut best = (f64::INFINITY, [0.0, 0.0]);
        let mut consider = |l: [f64; 2]| {
            let v = self.value(l);
            if v < best.0 {
                best = (v, l);
            }
        };
        if inside(self.minimiser) {
            consider(self.minimiser);
        }
        for fixed in 0..2 {
            let other = 1 - fixed;
            for sign in [-1.0, 1.0] {
                let at = sign * g[fixed];
                let free = if s[other][other] > 0.0 {
                    (r[other] - s[other][fixed] * at) / s[other][other]
                } else {
                    0.0
                };
                let mut l = [0.0; 2];
                l[fixed] = at;
                l[other] = free.clamp(-g[other], g[other]);
                consider(l);
            }
        }
        best.1
    }
}

/// (49) restricted to obstacle `obstacle`'s pair, the others held at `forces` (force, moment
/// per obstacle, as [`crate::solve::ObstacleResult`] gives them; obstacle `obstacle`'s own
/// pair is the `solution`). An error in words for an obstacle or forces that do not fit the
/// problem, or when S cannot be formed.
pub fn dual_pair(
    problem: &Problem,
    mesh: &Mesh,
    forces: &[[f64; 2]],
    obstacle: usize,
) -> Result<DualPair, String> {
    dual_pair_stopping(problem, mesh, forces, obstacle, NEVER)
        .unwrap_or_else(|Stopped| Err("stopped".into()))
}

/// [`dual_pair`], stopping as soon as `cancel` says so (asked inside the factorization of A,
/// of S and the condition estimate, each O(n) or O(k³)).
pub fn dual_pair_until(
    problem: &Problem,
    mesh: &Mesh,
    forces: &[[f64; 2]],
    obstacle: usize,
    cancel: &Cancel,
) -> Result<Result<DualPair, String>, Cancelled> {
    let stop = || cancel.is_cancelled();
    dual_pair_stopping(problem, mesh, forces, obstacle, &stop).map_err(|Stopped| Cancelled)
}

fn dual_pair_stopping(
    problem: &Problem,
    mesh: &Mesh,
    forces: &[[f64; 2]],
    obstacle: usize,
    stop: Stop,
) -> Result<Result<DualPair, String>, Stopped> {
    let k = problem.obstacles.len();
    if obstacle >= k {
        return Ok(Err(format!(
            "there is no obstacle {} (the scene has {k})",
            obstacle + 1
        )));
    }
    if forces.len() != k || forces.iter().flatten().any(|f| !f.is_finite()) {
        return Ok(Err(format!(
            "{k} obstacles need {k} finite force pairs, not {}",
            forces.len()
        )));
    }
    if k > super::DUAL_OBSTACLES_LIMIT {
        return Ok(Err(format!(
            "S = B A⁻¹ Bᵀ is not formed for {k} obstacles (the dual methods' limit is {})",
            super::DUAL_OBSTACLES_LIMIT
        )));
    }
    let matrices = match condense(problem, mesh, stop)? {
        Ok(condensation) => condensation.dual_matrices(stop)?,
        Err(why) => Err(why),
    };
    let (s, z0) = match matrices {
        Ok(m) => m,
        Err(why) => return Ok(Err(why)),
    };
    let lambda: Vec<f64> = forces.iter().flatten().copied().collect();
    let g = problem.thresholds();
    let errors = own_errors(problem, mesh, (&s, &z0), (&lambda, &g), stop)?;
    Ok(restrict(obstacle, (&s, &z0), (&lambda, &g), &errors))
}

/// The dual method's own error bounds at every DOF for forces `lambda`, with the rounding
/// of S and z0 the certificate gives `dual` (`None`: its free block is not positive
/// definite; then only ulps decide).
fn own_errors(
    problem: &Problem,
    mesh: &Mesh,
    (s, z0): (&[f64], &[f64]),
    (lambda, g): (&[f64], &[f64]),
    stop: Stop,
) -> Result<Option<FrictionErrors>, Stopped> {
    let state = lambda
        .iter()
        .zip(g)
        .map(|(&l, &g)| {
            if g - l.abs() > FORCE_ULPS * f64::EPSILON * g.max(l.abs()) {
                BoundState::Free
            } else if l < 0.0 {
                BoundState::Lower
            } else {
                BoundState::Upper
            }
        })
        .collect();
    let qp = QpResult {
        x: lambda.to_vec(),
        state,
        iterations: 0,
        converged: true,
    };
    let Some(accuracy) = friction_accuracy(s, z0, &qp, None, stop)? else {
        return Ok(None);
    };
    let scaled = scaled_stiffness_condition(mesh, stop)?;
    let rounding = friction_data_rounding(problem, Method::Dual, scaled);
    Ok(Some(accuracy.with_rounding(rounding)))
}

/// cond₂ of the Jacobi-scaled A as the certificate takes it at the default condition level:
/// from all eigenvalues for N ≤ [`DENSE_LIMIT`] (an exact number wins over the bound), else
/// the cheap rigorous lower bound.
fn scaled_stiffness_condition(mesh: &Mesh, stop: Stop) -> Result<Option<ConditionNumber>, Stopped> {
    let (_, bound) = stiffness_condition_bounds_until(mesh, stop)?;
    let n = mesh.unknowns();
    let computed = if n > 0 && n <= DENSE_LIMIT {
        let matrix = StiffnessMatrix::new(mesh).to_block_tridiagonal();
        block_condition_until(&jacobi_scaled(&matrix), stop)?
    } else {
        None
    };
    Ok(match (computed, bound) {
        (Some(c), _) if c.kind == ConditionKind::Exact => Some(c),
        (Some(c), Some(b)) => Some(if b.value > c.value { b } else { c }),
        (c, b) => c.or(b),
    })
}

/// The pair of obstacle `i` from S, z0, the forces and the error bounds.
fn restrict(
    i: usize,
    (s, z0): (&[f64], &[f64]),
    (lambda, g): (&[f64], &[f64]),
    errors: &Option<FrictionErrors>,
) -> Result<DualPair, String> {
    let dim = z0.len();
    let dofs = [2 * i, 2 * i + 1];
    let entry = |a: usize, b: usize| s[a * dim + b];
    let flexibility = dofs.map(|a| dofs.map(|b| entry(a, b)));
    let others = |a: usize| -> f64 {
        (0..dim)
            .filter(|j| !dofs.contains(j))
            .map(|j| entry(a, j) * lambda[j])
            .sum()
    };
    let linear = dofs.map(|a| z0[a] - others(a));
    let own = [lambda[2 * i], lambda[2 * i + 1]];
    let motion =
        [0, 1].map(|d| linear[d] - flexibility[d][0] * own[0] - flexibility[d][1] * own[1]);
    let det = flexibility[0][0] * flexibility[1][1] - flexibility[0][1] * flexibility[1][0];
    let minimiser = [
        (flexibility[1][1] * linear[0] - flexibility[0][1] * linear[1]) / det,
        (flexibility[0][0] * linear[1] - flexibility[1][0] * linear[0]) / det,
    ];
    if det.is_nan() || det <= 0.0 || minimiser.iter().chain(&linear).any(|v| !v.is_finite()) {
        return Err(format!(
            "the 2×2 block S_ii of obstacle {} is not positive definite in floating point",
            i + 1
        ));
    }
    // Each DOF: on its bound (Some(true)), inside (Some(false)) or undecided (None).
    let on_bound = [0, 1].map(|d| {
        let a = dofs[d];
        let terms = z0[a].abs()
            + (0..dim)
                .map(|j| (entry(a, j) * lambda[j]).abs())
                .sum::<f64>();
        let (motion_error, force_error) = errors
            .as_ref()
            .map_or((0.0, 0.0), |e| (e.motion[i][d], e.force[i][d]));
        let motion_tolerance = (MOTION_ULPS * f64::EPSILON * terms).max(motion_error);
        let force_tolerance = (FORCE_ULPS * f64::EPSILON * g[a].max(own[d].abs())).max(force_error);
        let at_threshold = g[a] - own[d].abs() <= force_tolerance;
        let moves = motion[d].abs() > motion_tolerance;
        match (at_threshold, moves) {
            (false, _) => Some(false),
            (true, true) => Some(true),
            (true, false) => None,
        }
    });
    let position = match on_bound {
        [Some(false), Some(false)] => BoxPosition::Interior,
        [Some(true), Some(false)] => BoxPosition::SlidingEdge,
        [Some(false), Some(true)] => BoxPosition::SwivelEdge,
        [Some(true), Some(true)] => BoxPosition::Corner,
        _ => BoxPosition::Undecided,
    };
    Ok(DualPair {
        obstacle: i,
        flexibility,
        linear,
        thresholds: [g[2 * i], g[2 * i + 1]],
        minimiser,
        solution: own,
        position,
        motion,
    })
}
