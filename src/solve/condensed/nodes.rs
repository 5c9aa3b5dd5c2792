//! Every node from its own piece: the piece's end values (Hermite cubic) plus its exact
//! clamped–clamped response to the linear load — O(n), with no sum running along the beam.

use super::CondensedFailure;
use super::scaling::Scales;
use super::system::{PatternSolution, ShootingSystem};
use crate::fem::{Mesh, NodalField};
use crate::linalg::banded_lu::times_power_of_two;
use crate::linalg::double_double::DoubleDouble;

/// Nodes computed between two questions to `keep_going`: about a millisecond.
const NODES_BETWEEN_QUESTIONS: usize = 1 << 16;

/// Every node from its own piece: Hermite interpolation of the piece's end values plus the
/// piece's exact clamped–clamped response to its linear load, in SI units. `keep_going` is
/// asked every [`NODES_BETWEEN_QUESTIONS`] nodes (10⁷ nodes are a fraction of a second).
pub(super) fn nodal_field(
    mesh: &Mesh,
    system: &ShootingSystem,
    solution: &PatternSolution,
    scales: &Scales,
    keep_going: &mut dyn FnMut() -> bool,
) -> Result<NodalField, CondensedFailure> {
    let mut field = NodalField::zeros(mesh.nodes.len());
    let (u_exponent, slope_exponent) = (scales.deflection(), scales.slope());
    // 2^e as one factor when it is a normal number; else scale afterwards in steps.
    let factor = |e: i32| (-1000..=1000).contains(&e).then(|| 2f64.powi(e));
    let factors = factor(u_exponent).zip(factor(slope_exponent));
    let (u_factor, slope_factor) = factors.unwrap_or((1.0, 1.0));
    for (p, (mesh_piece, piece)) in mesh.pieces.iter().zip(&system.pieces).enumerate() {
        let [ua, sa] = system.point_values(solution, p);
        let [ub, sb] = system.point_values(solution, p + 1);
        let (first, last) = (mesh_piece.first_node, mesh_piece.last_node);
        let (a, b) = (mesh.nodes[first], mesh.nodes[last]);
        let to_local = 1.0 / (b - a);
        // a + b as an unevaluated sum: 1 − 2ξ = (a + b − 2x)/(b − a) to a few ulps of itself,
        // where the load's bubble has its largest curvature (issue 10: a slope there is a
        // difference of terms up to 10⁴ times larger when computed from a rounded ξ).
        let ends_sum = DoubleDouble::difference(a, -b);
        let (t, e) = (piece.length, piece.stiffness);
        let (fa, fb) = (piece.load_start, piece.load_end);
        // The Hermite cubic of the end values in factored form (each basis function to a few
        // ulps of itself, ξ and η = 1 − ξ each from its own end), plus the clamped–clamped
        // response P ξ²η²(α + βξ) to the load f = fa η + fb ξ.
        let bubble_scale = t * t * t * t / (120.0 * e);
        let (alpha, beta) = (3.0 * fa + 2.0 * fb, fb - fa);
        let (slope_a, slope_b) = (t * sa, t * sb);
        let rise = ub - ua;
        let slope_scale = slope_factor / t;
        field.deflection[first] = ua * u_factor;
        field.slope[first] = sa * slope_factor;
        let nodes = &mesh.nodes[first + 1..last];
        let deflection = &mut field.deflection[first + 1..last];
        let slope = &mut field.slope[first + 1..last];
        for (i, ((&x, u_out), s_out)) in nodes.iter().zip(deflection).zip(slope).enumerate() {
            if (first + i) % NODES_BETWEEN_QUESTIONS == 0 && !keep_going() {
                return Err(CondensedFailure::Stopped);
            }
            let (xi, eta) = ((x - a) * to_local, (b - x) * to_local);
            // s − 2x is exact where it is small (Sterbenz): one rounding of a + b − 2x.
            let eta_minus_xi = ((ends_sum.hi - 2.0 * x) + ends_sum.lo) * to_local;
            let (xi2, eta2, xe) = (xi * xi, eta * eta, xi * eta);
            let load = alpha + beta * xi;
            let bubble = xe * xe;
            let u = eta2 * (1.0 + 2.0 * xi) * ua
                + xe * (eta * slope_a - xi * slope_b)
                + xi2 * (1.0 + 2.0 * eta) * ub
                + bubble_scale * bubble * load;
            let du = 6.0 * xe * rise
                + eta * (eta - 2.0 * xi) * slope_a
                + xi * (xi - 2.0 * eta) * slope_b
                + bubble_scale * (2.0 * xe * eta_minus_xi * load + bubble * beta);
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
    Ok(field)
}
