//! Every node from its own piece: the piece's end values (Hermite cubic) plus its exact
//! clamped–clamped response to the linear load — O(n), with no sum running along the beam.

use super::scaling::Scales;
use super::system::{Condensed, PatternSolution};
use crate::fem::{Mesh, NodalField};
use crate::linalg::banded_lu::times_power_of_two;

/// Every node from its own piece: Hermite interpolation of the piece's end values plus the
/// piece's exact clamped–clamped response to its linear load, in SI units.
pub(super) fn nodal_field(
    mesh: &Mesh,
    condensed: &Condensed,
    solution: &PatternSolution,
    scales: &Scales,
) -> NodalField {
    let mut field = NodalField::zeros(mesh.nodes.len());
    let (u_exponent, slope_exponent) = (scales.deflection(), scales.slope());
    // 2^e as one factor when it is a normal number; else scale afterwards in steps.
    let factor = |e: i32| (-1000..=1000).contains(&e).then(|| 2f64.powi(e));
    let factors = factor(u_exponent).zip(factor(slope_exponent));
    let (u_factor, slope_factor) = factors.unwrap_or((1.0, 1.0));
    for (p, (mesh_piece, piece)) in mesh.pieces.iter().zip(&condensed.pieces).enumerate() {
        let [ua, sa] = condensed.point_values(solution, p);
        let [ub, sb] = condensed.point_values(solution, p + 1);
        let (first, last) = (mesh_piece.first_node, mesh_piece.last_node);
        let a = mesh.nodes[first];
        let to_local = 1.0 / (mesh.nodes[last] - a);
        let (t, e) = (piece.length, piece.stiffness);
        let (fa, fb) = (piece.load_start, piece.load_end);
        // The Hermite cubic of the end values, ua + ξ(c1 + ξ(c2 + ξ c3)), and the clamped–
        // clamped response P ξ²(1 − ξ)²(α + βξ) to the load f = fa(1 − ξ) + fb ξ.
        let rise = ub - ua;
        let (c1, c2, c3) = (
            t * sa,
            3.0 * rise - t * (2.0 * sa + sb),
            t * (sa + sb) - 2.0 * rise,
        );
        let bubble_scale = t * t * t * t / (120.0 * e);
        let (alpha, beta) = (3.0 * fa + 2.0 * fb, fb - fa);
        let slope_scale = slope_factor / t;
        field.deflection[first] = ua * u_factor;
        field.slope[first] = sa * slope_factor;
        let nodes = &mesh.nodes[first + 1..last];
        let deflection = &mut field.deflection[first + 1..last];
        let slope = &mut field.slope[first + 1..last];
        for ((x, u_out), s_out) in nodes.iter().zip(deflection).zip(slope) {
            let xi = (x - a) * to_local;
            let rest = 1.0 - xi;
            let load = alpha + beta * xi;
            let bubble = xi * xi * rest * rest;
            let u = ua + xi * (c1 + xi * (c2 + xi * c3)) + bubble_scale * bubble * load;
            let du = c1
                + xi * (2.0 * c2 + 3.0 * xi * c3)
                + bubble_scale * (2.0 * xi * rest * (1.0 - 2.0 * xi) * load + bubble * beta);
            *u_out = u * u_factor;
            *s_out = du * slope_scale;
        }
    }
    if factors.is_none() {
        for v in &mut field.deflection {
            *v = times_power_of_two(*v, u_exponent);
        }
        for v in &mut field.slope {
            *v = times_power_of_two(*v, slope_exponent);
        }
    }
    // The far support stays clamped (zeros); node 0 is the first node of piece 0, (0, 0).
    field
}
