//! The friction state of every DOF from the motion at it and the force at its bound, and the
//! feasibility and complementarity of (38) there (the "States" of the module doc): a DOF moves
//! when |c| exceeds what rounding resolves, is stuck when |λ| is below its threshold by more
//! than rounding, and is at the threshold when both descriptions fit. Rounding includes the
//! method's own: a dual method's bounds on the errors of its motions and stuck forces at every
//! DOF (`solve::friction_accuracy`), else its resolution relative to the beam's values. For a
//! regularised method the ε-problem's λ = g·clamp(c/ε, −1, 1) instead, and a motion is one of
//! the exact problem only beyond what ε itself moves the DOF by.

use super::dimensionless::{DimensionlessSolution, relative};
use super::pieces::{PieceForces, special_point};
use crate::solve::FrictionState;
use crate::solve::friction_accuracy::FrictionErrors;

/// Ulps of the local magnitudes within which a motion is not resolved.
pub(crate) const MOTION_ULPS: f64 = 64.0;

/// Ulps of the local forces within which |λ| = g (at the threshold).
pub(crate) const FORCE_ULPS: f64 = 64.0;

/// How a method's answer is judged.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(in crate::solve) struct Judging<'a> {
    /// The method's own rounding of c relative to the largest |u| and |u'| (0 when it is no
    /// more than a few ulps of the local values).
    pub motion_resolution: f64,
    /// ε of a regularised method.
    pub epsilon: Option<f64>,
    /// The method's own bounds at every obstacle (SI units): for a dual method the errors of
    /// its motions and stuck forces (a DOF within them of a tie is at the threshold); for a
    /// regularised one the motion that ε itself explains.
    pub own_errors: Option<&'a FrictionErrors>,
}

/// The friction states per obstacle and, for a regularised method, the largest relative
/// uncertainty of a force inside ε (see [`super::Equilibrium::unresolved_force`]).
pub(super) type States = (Vec<[FrictionState; 2]>, f64);

/// What the states of all obstacles are judged with.
struct StateCheck<'a> {
    data: &'a DimensionlessSolution<'a>,
    pieces: &'a [PieceForces],
    /// The largest |u| and |u'| on each piece.
    piece_largest: &'a [[f64; 2]],
    /// The size of the values of each kind over the whole beam, (u, u').
    global: [f64; 2],
    /// The largest force of each kind (force, moment).
    kind_scale: [f64; 2],
    judging: Judging<'a>,
}

/// One friction DOF at its obstacle, in dimensionless units.
struct Dof {
    /// 0 for the value (sliding), 1 for the slope (swivel).
    kind: usize,
    /// c: the motion.
    motion: f64,
    /// λ: the friction force.
    force: f64,
    /// g: the threshold.
    threshold: f64,
    /// The magnitude of values of this kind around the obstacle.
    local: f64,
    /// The forces of this kind that meet at the obstacle: what λ is computed against.
    meeting: f64,
    /// The same with every term of the two pieces' end forces at its own size.
    meeting_terms: f64,
    /// The method's own bounds here (0 when it has none), see [`Judging::own_errors`]: on c,
    /// and on a stuck λ.
    own_errors: [f64; 2],
}

/// Stage of the check: the friction state of every obstacle, raising `residual` to the
/// feasibility and complementarity residuals of its DOFs.
pub(super) fn friction_states(
    data: &DimensionlessSolution,
    pieces: &[PieceForces],
    piece_largest: &[[f64; 2]],
    judging: Judging,
    residual: &mut f64,
) -> States {
    let (global, kind_scale) = beam_scales(data, piece_largest);
    let check = StateCheck {
        data,
        pieces,
        piece_largest,
        global,
        kind_scale,
        judging,
    };
    let mesh = data.mesh;
    let mut unresolved_force = 0.0f64;
    let mut states = Vec::with_capacity(mesh.obstacle_nodes.len());
    for (j, &node) in mesh.obstacle_nodes.iter().enumerate() {
        let Some(s) = special_point(mesh, node).filter(|&s| s > 0) else {
            states.push([FrictionState::AtThreshold; 2]);
            continue;
        };
        states.push(check.obstacle_states((j, node, s), residual, &mut unresolved_force));
    }
    (states, unresolved_force)
}

/// The yardsticks over the whole beam: the size of the values of each kind, (u, u'), and the
/// largest force of each kind, (force, moment).
fn beam_scales(data: &DimensionlessSolution, piece_largest: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let (problem, units, lam) = (data.problem, &data.units, &data.friction);
    // The largest value of each kind, each kind also seen through the other (u/l, u'·l): in
    // dimensionless units l is 1 up to a power of two.
    // Floored by the natural scales f l⁴/EJ and f l³/EJ (stiffest stretch): when every value
    // of a kind is rounding noise (all stuck), the noise is no yardstick.
    let span = data.x(data.mesh.nodes.len() - 1) - data.x(0);
    let natural = {
        let f = units
            .f(problem.load.f0)
            .abs()
            .max(units.f(problem.load.f1).abs());
        let ej = problem
            .stiffness
            .iter()
            .fold(0.0f64, |m, p| m.max(units.ej(p.bending_stiffness)));
        if ej > 0.0 { f * span.powi(3) / ej } else { 0.0 }
    };
    let [largest_u, largest_t] = piece_largest
        .iter()
        .fold([0.0f64; 2], |m, l| [m[0].max(l[0]), m[1].max(l[1])]);
    let global = [
        largest_u.max(largest_t * span).max(natural * span),
        largest_t.max(largest_u / span).max(natural),
    ];
    // The largest force of each kind, or the load's natural force and moment over the span.
    let kind_scale: [f64; 2] = {
        let f = units
            .f(problem.load.f0)
            .abs()
            .max(units.f(problem.load.f1).abs());
        [0, 1].map(|d| {
            lam.iter()
                .fold(f * span.powi(d as i32 + 1), |m, l| m.max(l[d].abs()))
        })
    };
    (global, kind_scale)
}

impl StateCheck<'_> {
    /// The (sliding, swivel) state of obstacle `j` at `node`, interior special point `s`: the
    /// local magnitudes around it, then each DOF.
    fn obstacle_states(
        &self,
        (j, node, s): (usize, usize, usize),
        residual: &mut f64,
        unresolved_force: &mut f64,
    ) -> [FrictionState; 2] {
        let data = self.data;
        let (units, piece_largest) = (&data.units, self.piece_largest);
        let around = [&data.mesh.pieces[s - 1], &data.mesh.pieces[s]];
        let (mut local_u, mut local_t, mut longest) = (0.0f64, 0.0f64, 0.0f64);
        for (p, [mu, mt]) in around
            .into_iter()
            .zip([piece_largest[s - 1], piece_largest[s]])
        {
            local_u = local_u.max(mu);
            local_t = local_t.max(mt);
            longest = longest.max(data.x(p.last_node) - data.x(p.first_node));
        }
        let f = data.load_at(node).abs();
        let ej = units.ej(around[0].bending_stiffness.min(around[1].bending_stiffness));
        let subnormal = data.subnormal;
        let local = [
            local_u
                .max(local_t * longest)
                .max(f * longest.powi(4) / ej / 384.0)
                .max(subnormal[0] / f64::EPSILON),
            local_t
                .max(local_u / longest)
                .max(f * longest.powi(3) / ej / 120.0)
                .max(subnormal[1] / f64::EPSILON),
        ];
        // The forces that meet at the point: what λ is computed against.
        let (left, right) = (&self.pieces[s - 1], &self.pieces[s]);
        let meeting = [
            left.forces[2].abs() + right.forces[0].abs(),
            left.forces[3].abs() + right.forces[1].abs(),
        ];
        // The same with every term of the two pieces' end forces at its own size (K c and the
        // load before they cancel): what a relative loss of the method is a loss of.
        let meeting_terms = [
            left.magnitude[2] + right.magnitude[0],
            left.magnitude[3] + right.magnitude[1],
        ];
        let c = [data.deflection.at(node), data.slope.at(node)];
        let own_errors = |d: usize| -> [f64; 2] {
            self.judging.own_errors.map_or([0.0; 2], |e| {
                let motion = e.motion[j][d];
                let motion = if d == 0 {
                    units.u(motion)
                } else {
                    units.slope(motion)
                };
                [motion, units.force(e.force[j][d], d)]
            })
        };
        let mut pair = [FrictionState::Stuck; 2];
        for d in 0..2 {
            let dof = Dof {
                kind: d,
                motion: c[d],
                force: data.friction[j][d],
                threshold: data.thresholds[j][d],
                local: local[d],
                meeting: meeting[d],
                meeting_terms: meeting_terms[d],
                own_errors: own_errors(d),
            };
            pair[d] = self.dof_state(&dof, residual, unresolved_force);
        }
        pair
    }

    /// The state of one DOF, raising `residual` to its feasibility |λ| ≤ g and
    /// complementarity residuals and `unresolved_force` to the uncertainty of a regularised
    /// force inside ε.
    fn dof_state(
        &self,
        dof: &Dof,
        residual: &mut f64,
        unresolved_force: &mut f64,
    ) -> FrictionState {
        let (judging, units, d) = (self.judging, &self.data.units, dof.kind);
        let (c, l, g) = (dof.motion, dof.force, dof.threshold);
        // A dual method's rounding of c: its own bound at this DOF where it has one, else
        // the resolution relative to the beam's values.
        let method_motion = match (judging.own_errors, judging.epsilon) {
            (Some(_), None) => dof.own_errors[0],
            _ => judging.motion_resolution * self.global[d],
        };
        let motion_tolerance = (MOTION_ULPS * f64::EPSILON * dof.local).max(method_motion);
        let epsilon = judging
            .epsilon
            .map_or(0.0, |e| [units.u(e), units.slope(e)][d]);
        let force_scale = g
            .max(l.abs())
            .max(dof.meeting)
            .max(self.data.subnormal_force[d] / f64::EPSILON);
        let mut force_tolerance = (FORCE_ULPS * f64::EPSILON * force_scale).max(dof.own_errors[1]);
        if epsilon > 0.0 {
            // A regularised method's λ = g·c/ε is as uncertain as its c near ε (the unresolved
            // motion turned into force) and as its equilibrium (its relative loss on the
            // forces meeting here). Only when both leave |λ| = g open is a stuck DOF "at the
            // threshold": each alone is pessimistic, for large deflections or large forces.
            let through_motion = g / epsilon * motion_tolerance;
            let through_forces = judging.motion_resolution * force_scale;
            force_tolerance = force_tolerance.max(through_motion.min(through_forces));
            if c.abs() <= epsilon + motion_tolerance && self.kind_scale[d] > 0.0 {
                // Inside ε the force is g·c/ε: as uncertain as c, and as the equilibrium
                // of the forces meeting here (not of g, which may be far larger).
                let uncertain =
                    through_motion.min(judging.motion_resolution * dof.meeting_terms.max(l.abs()));
                *unresolved_force = unresolved_force.max(uncertain / self.kind_scale[d]);
            }
        }
        // Feasibility |λ| ≤ g.
        *residual = residual.max(relative((l.abs() - g).max(0.0), force_scale));
        // A regularised motion is one of the exact problem only beyond what ε itself moves
        // the DOF by (`friction_accuracy::regularization_accuracy`).
        let explained_by_epsilon = if epsilon > 0.0 {
            dof.own_errors[0]
        } else {
            0.0
        };
        let moves = c.abs() > (motion_tolerance + epsilon).max(explained_by_epsilon);
        // Complementarity: the force a moving DOF (or the ε-problem) prescribes.
        let prescribed = if judging.epsilon.is_some() && epsilon > 0.0 {
            Some(g * (c / epsilon).clamp(-1.0, 1.0))
        } else if moves {
            Some(g * c.signum())
        } else {
            None
        };
        if let Some(p) = prescribed {
            let violation = if epsilon > 0.0 {
                // g·c/ε turns the unresolved part of c into a force of (g/ε)·tolerance.
                let unresolved = g / epsilon * motion_tolerance;
                relative(((l - p).abs() - unresolved).max(0.0), force_scale)
            } else {
                // The natural residual of complementarity: the smaller relative change, of
                // λ to g·sign c or of c to zero (then |λ| ≤ g, checked above, is enough),
                // that makes the pair consistent. A motion of a few ulps with the other
                // sign than λ is then a residual of a few ulps, not of 2g; a real wrong
                // state (a motion well above rounding against λ, or a force off its bound)
                // is as large as before.
                relative((l - p).abs(), force_scale).min(relative(c, dof.local))
            };
            *residual = residual.max(violation);
        }
        if moves {
            FrictionState::Moves
        } else if g - l.abs() <= force_tolerance {
            FrictionState::AtThreshold
        } else {
            FrictionState::Stuck
        }
    }
}
