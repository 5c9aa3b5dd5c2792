//! The independent half of the certificate: the KKT conditions of (38) checked from the exact
//! local solutions of the pieces between special points, and the friction state of every DOF
//! decided from the force at its bound and the motion (issue 10).
//!
//! **Why not the method's own matrix.** A residual A c − b + Bᵀλ computed with the rounded A a
//! method used cannot see the error that rounding caused, and relative to ‖A‖‖c‖ it is tiny
//! whenever one short or stiff piece makes ‖A‖ huge. Here every piece between special points
//! (supports, obstacles, segment ends) is one exact macro element: EJ is constant and f linear
//! on it, so the Hermite element on the whole piece gives the exact end forces of the exact
//! local solution from the piece's end values (docs/design.md fact 1). Equilibrium is then
//! checked at every special point, and as a rigid-body balance (force, and moment about its
//! left end) of every run of up to `CLUSTER` (3) consecutive special points, in which the forces
//! inside the run cancel algebraically: the internal force of a piece 1e-9·l long is a
//! difference of nearly equal values times 1e27 and pure noise, the balance of its two ends is
//! not. Every check is relative to the sum of the absolute values of its own terms (including
//! |K||c|, what one rounding of c moves the forces by), so it lies in [0, 1] and is never a
//! ratio of noise to noise. Interior nodes are checked against their piece's exact solution.
//! Everything is made dimensionless first by powers of two (exact), so loads of 1e-300 or
//! 1e300 neither underflow to a zero residual nor overflow.
//!
//! **States.** A DOF moves when |c| exceeds what rounding resolves: a few ulps of the local
//! magnitudes (the values on the two adjacent pieces), or more when the method's own rounding
//! is known to be larger: a dual method's bound on the error of that motion from the errors of
//! its S and z0 (`solve::friction_accuracy`), else `motion_resolution`, relative to the largest
//! value of its kind. A DOF that does not move is stuck when |λ| is below its threshold by more
//! than rounding of the local forces and than a dual method's bound on the error of that force,
//! and "at the threshold" otherwise: both descriptions fit. For the regularised methods the
//! motion must also exceed ε and what ε explains (the exact problem with every obstacle
//! displaced by clamp(c, −ε, ε) moves by at most that), and complementarity is that of the
//! ε-problem, λ = g·clamp(c/ε, −1, 1); a DOF below ε is "at the threshold" when |λ| = g is within both
//! the unresolved motion turned into force (g/ε times it) and the method's relative loss on
//! the forces meeting there; the smaller of the two, relative to the largest force of its
//! kind, is what the certificate reports as the regularised forces' uncertainty
//! (`accuracy-loss` above 1e-8).
//!
//! **Stages** of [`check`]: the solution in dimensionless units (`dimensionless`), the scales
//! and exact end forces of every piece and the balance at the special points (`pieces`), the
//! interior nodes (`interior`), the friction states (`states`).

mod dimensionless;
mod interior;
mod pieces;
mod states;

use crate::fem::{Mesh, NodalField};
use crate::linalg::stop::Stop;
use crate::model::Problem;
use crate::solve::FrictionState;
use dimensionless::DimensionlessSolution;
use interior::interior_residual;
use pieces::{balance_residual, piece_forces, piece_scales};
use states::friction_states;

pub(in crate::solve) use states::Judging;
pub(crate) use states::{FORCE_ULPS, MOTION_ULPS};

/// What the certificate learns from the pieces.
#[derive(Debug, Clone, PartialEq)]
pub(in crate::solve) struct Equilibrium {
    /// Relative KKT residual in [0, 1]; NaN when the field or forces are not finite.
    pub residual: f64,
    /// (sliding, swivel) state per obstacle.
    pub states: Vec<[FrictionState; 2]>,
    /// For a regularised method: the largest uncertainty of a force g·c/ε of a DOF inside ε
    /// (the unresolved part of c turned into force, at most the method's relative loss on the
    /// forces meeting there), relative to the largest force of its kind (or |f|·l, |f|·l²);
    /// 0 for the exact methods.
    pub unresolved_force: f64,
}

/// Checks (38) piece by piece and decides the friction states (module doc), stage by stage;
/// `None` when `stop` says so (asked between the stages and inside the O(n) ones).
pub(in crate::solve) fn check(
    problem: &Problem,
    mesh: &Mesh,
    (field, lambda): (&NodalField, &[[f64; 2]]),
    judging: Judging<'_>,
    stop: Stop,
) -> Option<Equilibrium> {
    let still_wanted = || (!stop()).then_some(());
    let k = problem.obstacles.len();
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    if !finite(&field.deflection) || !finite(&field.slope) || !lambda.iter().all(|l| finite(l)) {
        return Some(Equilibrium {
            residual: f64::NAN,
            states: vec![[FrictionState::AtThreshold; 2]; k],
            unresolved_force: 0.0,
        });
    }
    still_wanted()?;
    let data = DimensionlessSolution::new(problem, mesh, field, lambda);
    let scales = piece_scales(&data);
    still_wanted()?;
    let pieces = piece_forces(&data, &scales.special_noise);
    let mut residual = balance_residual(&data, &pieces);
    residual = residual.max(interior_residual(
        mesh,
        (&data.deflection, &data.slope),
        (&scales.magnitude, &data.units),
        problem,
        stop,
    )?);
    let (states, unresolved_force) =
        friction_states(&data, &pieces, &scales.largest, judging, &mut residual);
    Some(Equilibrium {
        residual,
        states,
        unresolved_force,
    })
}
