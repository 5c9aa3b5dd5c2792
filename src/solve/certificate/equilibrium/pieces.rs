//! Equilibrium of (38) at the special points from the exact end forces of every piece between
//! them (docs/design.md fact 1: the Hermite element on a whole piece gives the exact local
//! solution's end forces), checked at every special point and as the rigid-body balance of
//! every run of up to [`CLUSTER`] consecutive special points.

use super::dimensionless::{DimensionlessSolution, relative};
use crate::fem::{Mesh, element_load, element_stiffness};

/// Longest run of consecutive special points balanced as one rigid body.
const CLUSTER: usize = 3;

/// How large the values on every piece are, and what rounding leaves unresolved at every
/// special point, in dimensionless units.
pub(super) struct PieceScales {
    /// The largest |u| and |u'| on each piece.
    pub(super) largest: Vec<[f64; 2]>,
    /// The magnitude of (u, u') on each piece, each kind also seen through the other.
    pub(super) magnitude: Vec<[f64; 2]>,
    /// What rounding leaves unresolved in (u, u') at each special point.
    pub(super) special_noise: Vec<[f64; 2]>,
}

/// The exact end forces of one piece (rows u_a, u'_a, u_b, u'_b of K c − f) and the sums of
/// the absolute values of their terms, in dimensionless units.
pub(super) struct PieceForces {
    pub(super) forces: [f64; 4],
    pub(super) magnitude: [f64; 4],
    /// The rows of the load alone.
    pub(super) load: [f64; 4],
    pub(super) a: f64,
    pub(super) b: f64,
}

/// The special point at `node` (point s is the start of piece s; 1..pieces − 1 are interior),
/// if there is one.
pub(super) fn special_point(mesh: &Mesh, node: usize) -> Option<usize> {
    let s = mesh.pieces.partition_point(|p| p.first_node < node);
    (s < mesh.pieces.len() && mesh.pieces[s].first_node == node).then_some(s)
}

/// Stage of the check: the scales of the values on every piece, in one pass over its nodes.
pub(super) fn piece_scales(data: &DimensionlessSolution) -> PieceScales {
    let mesh = data.mesh;
    let (u, t, subnormal) = (&data.deflection, &data.slope, data.subnormal);
    // The largest |u| and |u'| on each piece, in one pass over its nodes.
    let piece_largest: Vec<[f64; 2]> = mesh
        .pieces
        .iter()
        .map(|p| {
            let nodes = p.first_node..=p.last_node;
            [u.largest(nodes.clone()), t.largest(nodes)]
        })
        .collect();
    // The magnitude of (u, u') on each piece, each kind also seen through the other.
    let piece_magnitude: Vec<[f64; 2]> = mesh
        .pieces
        .iter()
        .zip(&piece_largest)
        .map(|(p, &[mu, mt])| {
            let length = data.x(p.last_node) - data.x(p.first_node);
            // Never below what the SI values carry: an ulp of it is their subnormal rounding.
            [
                mu.max(mt * length).max(subnormal[0] / f64::EPSILON),
                mt.max(mu / length).max(subnormal[1] / f64::EPSILON),
            ]
        })
        .collect();
    // What rounding leaves unresolved in (u, u') at each special point: an ulp of the local
    // magnitudes on both sides (a value of 1e-20 next to values of 1 is not known to 1e-36).
    let special_noise: Vec<[f64; 2]> = (0..=mesh.pieces.len())
        .map(|s| {
            let left = s.checked_sub(1).map_or([0.0; 2], |p| piece_magnitude[p]);
            let right = piece_magnitude.get(s).copied().unwrap_or([0.0; 2]);
            [
                f64::EPSILON * left[0].max(right[0]),
                f64::EPSILON * left[1].max(right[1]),
            ]
        })
        .collect();
    PieceScales {
        largest: piece_largest,
        magnitude: piece_magnitude,
        special_noise,
    }
}

/// Stage of the check: every piece as one exact macro element, its end forces from its end
/// values, each with the sum of the absolute values of its terms (the noise of the end values
/// included).
pub(super) fn piece_forces(
    data: &DimensionlessSolution,
    special_noise: &[[f64; 2]],
) -> Vec<PieceForces> {
    let (units, u, t) = (&data.units, &data.deflection, &data.slope);
    data.mesh
        .pieces
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let (a, b) = (p.first_node, p.last_node);
            let length = data.x(b) - data.x(a);
            let stiffness = element_stiffness(units.ej(p.bending_stiffness), length);
            let load = element_load(length, data.load_at(a), data.load_at(b));
            let c = [u.at(a), t.at(a), u.at(b), t.at(b)];
            let (na, nb) = (special_noise[i], special_noise[i + 1]);
            let noise = [na[0], na[1], nb[0], nb[1]];
            let mut forces = [0.0; 4];
            let mut magnitude = [0.0; 4];
            for r in 0..4 {
                let mut sum = -load[r];
                let mut abs = load[r].abs();
                for j in 0..4 {
                    sum += stiffness[r][j] * c[j];
                    abs += stiffness[r][j].abs() * (c[j].abs() + noise[j]);
                }
                forces[r] = sum;
                magnitude[r] = abs;
            }
            PieceForces {
                forces,
                magnitude,
                load,
                a: data.x(a),
                b: data.x(b),
            }
        })
        .collect()
}

/// Stage of the check: the largest relative residual of the force and moment balance of every
/// run of one to [`CLUSTER`] consecutive interior special points, as a rigid body (the forces
/// inside the run cancel algebraically; the loads of the pieces inside and the friction forces
/// at the obstacles in it enter).
pub(super) fn balance_residual(data: &DimensionlessSolution, pieces: &[PieceForces]) -> f64 {
    let mesh = data.mesh;
    let (lam, subnormal_force) = (&data.friction, data.subnormal_force);
    let mut obstacle_at: Vec<Option<usize>> = vec![None; mesh.pieces.len() + 1];
    for (j, &node) in mesh.obstacle_nodes.iter().enumerate() {
        if let Some(s) = special_point(mesh, node) {
            obstacle_at[s] = Some(j);
        }
    }
    let mut residual = 0.0f64;
    let specials = mesh.pieces.len() + 1;
    for first in 1..specials.saturating_sub(1) {
        for last in first..(first + CLUSTER).min(specials - 1) {
            let (left, right) = (&pieces[first - 1], &pieces[last]);
            let x0 = left.b;
            let arm = right.a - x0;
            let mut force = left.forces[2] + right.forces[0];
            let mut force_scale = left.magnitude[2] + right.magnitude[0];
            let mut moment = left.forces[3] + right.forces[1] + arm * right.forces[0];
            let mut moment_scale =
                left.magnitude[3] + right.magnitude[1] + arm * right.magnitude[0];
            for inner in &pieces[first..last] {
                let l = &inner.load;
                force -= l[0] + l[2];
                force_scale += l[0].abs() + l[2].abs();
                let terms = [l[1], l[3], (inner.a - x0) * l[0], (inner.b - x0) * l[2]];
                moment -= terms.iter().sum::<f64>();
                moment_scale += terms.iter().map(|v| v.abs()).sum::<f64>();
            }
            for (s, at) in obstacle_at.iter().enumerate().take(last + 1).skip(first) {
                if let Some(j) = *at {
                    let arm = pieces[s].a - x0;
                    force += lam[j][0];
                    force_scale += lam[j][0].abs() + subnormal_force[0];
                    moment += lam[j][1] + arm * lam[j][0];
                    moment_scale += lam[j][1].abs()
                        + subnormal_force[1]
                        + (arm * (lam[j][0].abs() + subnormal_force[0]));
                }
            }
            residual = residual
                .max(relative(force, force_scale))
                .max(relative(moment, moment_scale));
        }
    }
    residual
}
