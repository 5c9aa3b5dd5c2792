//! `flexibility`: the force formulation of docs/design.md fact 3, the stable route and the
//! reference.
//!
//! With m = EJ u'' the equilibrium reads m'' = f − Σ λ1_j δ(x − x̂_j) + Σ λ2_j δ'(x − x̂_j), so
//! on every piece between special points (obstacles, segment ends) m is a cubic known up to the
//! end reactions (m(0), m'(0)) and the friction forces λ; at an obstacle m' jumps by −λ1 and m
//! by +λ2. The state (u, u', m, m') is carried across each piece in closed form (EJ is constant
//! and f linear there), starting from the clamped end u(0) = u'(0) = 0. By superposition the
//! state is affine in (m(0), m'(0), λ); u(l) = u'(l) = 0 fixes the reactions, which gives
//! S = B A⁻¹ Bᵀ and z0 = B A⁻¹ b of (49) without the stiffness matrix, in O(k²) work.
//! After the box QP, every node is evaluated from the state at the start of its piece by the
//! exact Taylor polynomial: no sum runs over the elements, so rounding does not grow with n.
//!
//! Because the finite-element solution is exact at the nodes (docs/design.md fact 1), these
//! nodal values are the discrete solution of (38) itself, for any mesh.

use super::options::SolveOptions;
use super::shared::{MethodOutput, Stopwatch, check_cancel, dual_output};
use super::solution::{SolveError, Timing};
use crate::fem::{Mesh, NodalField};
use crate::linalg::boxqp::solve_box_qp_until;
use crate::model::Method;
use crate::model::Problem;

/// (u, u', m, m') at a point.
type State = [f64; 4];

/// Carries a state over a length `t` of constant `ej`, with the load f0 + slope·s at the start
/// of the stretch (pass zeros for a homogeneous column).
fn propagate(s: State, t: f64, ej: f64, f0: f64, slope: f64) -> State {
    let [u, du, m, v] = s;
    // Polynomial parts of m, ∫m, ∬m in t (Horner form).
    let m_t = m + t * (v + t * (f0 / 2.0 + t * slope / 6.0));
    let v_t = v + t * (f0 + t * slope / 2.0);
    let int_m = t * (m + t * (v / 2.0 + t * (f0 / 6.0 + t * slope / 24.0)));
    let int2_m = t * t * (m / 2.0 + t * (v / 6.0 + t * (f0 / 24.0 + t * slope / 120.0)));
    [u + t * du + int2_m / ej, du + int_m / ej, m_t, v_t]
}

/// Solves by the force formulation.
pub(super) fn solve(
    problem: &Problem,
    mesh: &Mesh,
    options: &SolveOptions,
) -> Result<MethodOutput, SolveError> {
    super::shared::refuse_many_obstacles(problem, Method::Flexibility)?;
    let mut timing = Timing::default();
    let mut clock = Stopwatch::start();
    let k = problem.obstacles.len();
    let dim = 2 * k;
    let slope = problem.load_slope();
    let obstacle_at = |node: usize| mesh.obstacle_nodes.binary_search(&node).ok();

    // Columns: 0 the load, 1 unit m(0), 2 unit m'(0), 3 + q unit λ_q.
    let columns = 3 + dim;
    let mut states = vec![[0.0; 4]; columns];
    states[1][2] = 1.0;
    states[2][3] = 1.0;
    // (u, u') of every column at every obstacle: values[c * dim + q].
    let mut values = vec![0.0; columns * dim];
    for piece in &mesh.pieces {
        check_cancel(options, Method::Flexibility)?;
        if let Some(j) = obstacle_at(piece.first_node) {
            for (c, s) in states.iter().enumerate() {
                values[c * dim + 2 * j] = s[0];
                values[c * dim + 2 * j + 1] = s[1];
            }
            states[3 + 2 * j][3] -= 1.0;
            states[3 + 2 * j + 1][2] += 1.0;
        }
        let a = mesh.nodes[piece.first_node];
        let t = mesh.nodes[piece.last_node] - a;
        let ej = piece.bending_stiffness;
        let f0 = problem.load_at(a);
        states[0] = propagate(states[0], t, ej, f0, slope);
        for s in states.iter_mut().skip(1) {
            *s = propagate(*s, t, ej, 0.0, 0.0);
        }
    }
    timing.assembly = clock.lap();

    // u(l) = u'(l) = 0: [u_M u_V; u'_M u'_V] (m0, v0) = −(u_c(l), u'_c(l)) for every column c.
    let (um, uv, dm, dv) = (states[1][0], states[2][0], states[1][1], states[2][1]);
    let det = um * dv - uv * dm;
    let reactions = |c: usize| -> [f64; 2] {
        let (u, du) = (states[c][0], states[c][1]);
        [-(dv * u - uv * du) / det, -(um * du - dm * u) / det]
    };
    // The value of column c at friction DOF q once its reactions are fitted.
    let fitted = |c: usize, q: usize| -> f64 {
        let [m0, v0] = reactions(c);
        values[c * dim + q] + m0 * values[dim + q] + v0 * values[2 * dim + q]
    };
    let z0: Vec<f64> = (0..dim).map(|q| fitted(0, q)).collect();
    let mut s = vec![0.0; dim * dim];
    for q in 0..dim {
        check_cancel(options, Method::Flexibility)?;
        for p in 0..dim {
            s[q * dim + p] = -fitted(3 + p, q);
        }
    }
    for q in 0..dim {
        for p in 0..q {
            let mean = 0.5 * (s[q * dim + p] + s[p * dim + q]);
            s[q * dim + p] = mean;
            s[p * dim + q] = mean;
        }
    }
    timing.factorization = clock.lap();

    let qp = solve_box_qp_until(&s, &z0, &problem.thresholds(), &|| {
        options.cancel.is_cancelled()
    });
    check_cancel(options, Method::Flexibility)?;
    let lambda = qp.x.clone();
    timing.friction_stage = clock.lap();

    // The actual state, piece by piece, and every node from the start of its piece.
    let mut reaction = reactions(0);
    for (q, l) in lambda.iter().enumerate() {
        let r = reactions(3 + q);
        reaction[0] += l * r[0];
        reaction[1] += l * r[1];
    }
    let mut field = NodalField::zeros(mesh.nodes.len());
    let mut state: State = [0.0, 0.0, reaction[0], reaction[1]];
    for piece in &mesh.pieces {
        check_cancel(options, Method::Flexibility)?;
        if let Some(j) = obstacle_at(piece.first_node) {
            state[3] -= lambda[2 * j];
            state[2] += lambda[2 * j + 1];
        }
        let a = mesh.nodes[piece.first_node];
        let ej = piece.bending_stiffness;
        let f0 = problem.load_at(a);
        for node in piece.first_node..piece.last_node {
            // Ten million nodes are a fraction of a second: asked every 2¹⁶.
            if node % (1 << 16) == 0 {
                check_cancel(options, Method::Flexibility)?;
            }
            let s = propagate(state, mesh.nodes[node] - a, ej, f0, slope);
            field.deflection[node] = s[0];
            field.slope[node] = s[1];
        }
        state = propagate(state, mesh.nodes[piece.last_node] - a, ej, f0, slope);
    }
    // The clamped ends carry no unknowns.
    field.deflection[0] = 0.0;
    field.slope[0] = 0.0;
    let last = mesh.nodes.len() - 1;
    field.deflection[last] = 0.0;
    field.slope[last] = 0.0;
    timing.reconstruction = clock.lap();

    Ok(dual_output(field, &qp, &s, timing, Vec::new(), options))
}
