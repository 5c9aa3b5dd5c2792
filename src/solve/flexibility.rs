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
//! The shooting carries the sums of the absolute values of its terms alongside, so the method
//! knows what its single shooting lost in every entry of S and z0 (`fit`); the certificate
//! judges the friction states with that (`super::friction_accuracy`).
//!
//! Because the finite-element solution is exact at the nodes (docs/design.md fact 1), these
//! nodal values are the discrete solution of (38) itself, for any mesh.

use super::friction_accuracy::EntryErrors;
use super::options::SolveOptions;
use super::shared::{MethodOutput, Stopwatch, check_cancel, dual_output};
use super::solution::{SolveError, Timing};
use crate::fem::{Mesh, NodalField};
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

/// The columns of the superposition carried to every obstacle and to l, each value with the
/// sum of the absolute values of the terms it was computed from (its rounding is relative to
/// that). Columns: 0 the load, 1 unit m(0), 2 unit m'(0), 3 + q unit λ_q.
struct Shooting {
    /// (u, u', m, m') of every column at l.
    end: Vec<State>,
    /// Their term magnitudes.
    end_magnitude: Vec<State>,
    /// (u, u') of every column at every obstacle: values[c * dim + q].
    values: Vec<f64>,
    /// Their term magnitudes.
    value_magnitude: Vec<f64>,
    /// Roundings in a row from x = 0 to any value: 12 per piece (the depth of `propagate`).
    depth: usize,
}

/// Carries every column across the pieces (cancelled between pieces).
fn shoot(problem: &Problem, mesh: &Mesh, options: &SolveOptions) -> Result<Shooting, SolveError> {
    let dim = 2 * problem.obstacles.len();
    let slope = problem.load_slope();
    let columns = 3 + dim;
    let mut states = vec![[0.0; 4]; columns];
    states[1][2] = 1.0;
    states[2][3] = 1.0;
    let mut magnitudes = states.clone();
    let mut values = vec![0.0; columns * dim];
    let mut value_magnitude = vec![0.0; columns * dim];
    for piece in &mesh.pieces {
        check_cancel(options, Method::Flexibility)?;
        if let Ok(j) = mesh.obstacle_nodes.binary_search(&piece.first_node) {
            for (c, (s, m)) in states.iter().zip(&magnitudes).enumerate() {
                for d in 0..2 {
                    values[c * dim + 2 * j + d] = s[d];
                    value_magnitude[c * dim + 2 * j + d] = m[d];
                }
            }
            states[3 + 2 * j][3] -= 1.0;
            states[3 + 2 * j + 1][2] += 1.0;
            magnitudes[3 + 2 * j][3] += 1.0;
            magnitudes[3 + 2 * j + 1][2] += 1.0;
        }
        let a = mesh.nodes[piece.first_node];
        let t = mesh.nodes[piece.last_node] - a;
        let ej = piece.bending_stiffness;
        let f0 = problem.load_at(a);
        states[0] = propagate(states[0], t, ej, f0, slope);
        magnitudes[0] = propagate(magnitudes[0], t, ej, f0.abs(), slope.abs());
        for (s, m) in states.iter_mut().zip(&mut magnitudes).skip(1) {
            *s = propagate(*s, t, ej, 0.0, 0.0);
            *m = propagate(*m, t, ej, 0.0, 0.0);
        }
    }
    Ok(Shooting {
        end: states,
        end_magnitude: magnitudes,
        values,
        value_magnitude,
        depth: 12 * mesh.pieces.len(),
    })
}

/// S, z0 of (49) and the reactions (m(0), m'(0)) of every column from the shooting: u(l) =
/// u'(l) = 0 gives [u_M u_V; u'_M u'_V] (m0, v0) = −(u_c(l), u'_c(l)) for every column c.
struct Fitted {
    s: Vec<f64>,
    z0: Vec<f64>,
    reactions: Vec<[f64; 2]>,
    /// The rounding the shooting and the fit may have left in S and z0 (first order).
    lost: EntryErrors,
}

fn fit(shooting: &Shooting, dim: usize) -> Fitted {
    let Shooting {
        end,
        end_magnitude,
        values,
        value_magnitude,
        depth,
    } = shooting;
    let eps = f64::EPSILON;
    // Every value computed along the beam is off by up to depth·eps of its terms; Cramer's
    // rule on 2×2 is forward stable, so the reactions are off by |M⁻¹| (δe + δM |r|) with a
    // few more roundings in δ.
    let rounding = (*depth as f64 + 4.0) * eps;
    let (um, uv, dm, dv) = (end[1][0], end[2][0], end[1][1], end[2][1]);
    let det = um * dv - uv * dm;
    let inverse_magnitude =
        [[dv.abs(), uv.abs()], [dm.abs(), um.abs()]].map(|r| r.map(|v| v / det.abs()));
    let matrix_error = [
        [end_magnitude[1][0], end_magnitude[2][0]],
        [end_magnitude[1][1], end_magnitude[2][1]],
    ]
    .map(|r| r.map(|v| rounding * v));
    let columns = end.len();
    let mut reactions = Vec::with_capacity(columns);
    let mut reaction_error = Vec::with_capacity(columns);
    for (state, magnitude) in end.iter().zip(end_magnitude) {
        let (u, du) = (state[0], state[1]);
        let r = [-(dv * u - uv * du) / det, -(um * du - dm * u) / det];
        let rhs_error: [f64; 2] = std::array::from_fn(|i| {
            rounding * magnitude[i]
                + matrix_error[i][0] * r[0].abs()
                + matrix_error[i][1] * r[1].abs()
        });
        reaction_error.push(std::array::from_fn(|i| {
            inverse_magnitude[i][0] * rhs_error[0] + inverse_magnitude[i][1] * rhs_error[1]
        }));
        reactions.push(r);
    }
    // The value of column c at friction DOF q once its reactions are fitted, and its error.
    let value_rounding = *depth as f64 * eps;
    let fitted = |c: usize, q: usize| -> (f64, f64) {
        let [m0, v0] = reactions[c];
        let [dm0, dv0] = reaction_error[c];
        let (v, vm, vv) = (values[c * dim + q], values[dim + q], values[2 * dim + q]);
        let magnitude = |c: usize| value_magnitude[c * dim + q];
        let terms = v.abs() + (m0 * vm).abs() + (v0 * vv).abs();
        let error = value_rounding
            * (magnitude(c) + m0.abs() * magnitude(1) + v0.abs() * magnitude(2))
            + dm0 * vm.abs()
            + dv0 * vv.abs()
            + 2.0 * eps * terms;
        (v + m0 * vm + v0 * vv, error)
    };
    let (z0, z0_error): (Vec<f64>, Vec<f64>) = (0..dim).map(|q| fitted(0, q)).unzip();
    let mut s = vec![0.0; dim * dim];
    let mut s_error = vec![0.0; dim * dim];
    for q in 0..dim {
        for p in 0..dim {
            let (value, error) = fitted(3 + p, q);
            s[q * dim + p] = -value;
            s_error[q * dim + p] = error;
        }
    }
    // S is symmetric: the mean of the two computed entries, off by at most the larger error
    // and half their difference.
    for q in 0..dim {
        for p in 0..q {
            let (a, b) = (s[q * dim + p], s[p * dim + q]);
            let error = s_error[q * dim + p].max(s_error[p * dim + q]) + 0.5 * (a - b).abs();
            s[q * dim + p] = 0.5 * (a + b);
            s[p * dim + q] = s[q * dim + p];
            s_error[q * dim + p] = error;
            s_error[p * dim + q] = error;
        }
    }
    Fitted {
        s,
        z0,
        reactions,
        lost: EntryErrors {
            s: s_error,
            z0: z0_error,
        },
    }
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
    let dim = 2 * problem.obstacles.len();
    let slope = problem.load_slope();
    let obstacle_at = |node: usize| mesh.obstacle_nodes.binary_search(&node).ok();
    let shooting = shoot(problem, mesh, options)?;
    timing.assembly = clock.lap();
    check_cancel(options, Method::Flexibility)?;
    let Fitted {
        s,
        z0,
        reactions,
        lost,
    } = fit(&shooting, dim);
    timing.factorization = clock.lap();

    let (qp, history) = super::shared::dual_box_qp(
        (&s, &z0, &problem.thresholds()),
        Method::Flexibility,
        options,
    );
    check_cancel(options, Method::Flexibility)?;
    let lambda = qp.x.clone();
    timing.friction_stage = clock.lap();

    // The actual state, piece by piece, and every node from the start of its piece.
    let mut reaction = reactions[0];
    for (q, l) in lambda.iter().enumerate() {
        let r = reactions[3 + q];
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

    Ok(MethodOutput {
        history,
        ..dual_output(
            field,
            (&qp, &s, &z0),
            Some(&lost),
            (timing, Vec::new()),
            options,
        )
    })
}
