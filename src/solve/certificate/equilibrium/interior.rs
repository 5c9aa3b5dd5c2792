//! The interior nodes of every piece against the piece's exact local solution: the Hermite
//! cubic of its end values (in factored form, each basis function to a few ulps of its own
//! value) plus its exact clamped–clamped response to the linear load (docs/design.md fact 1).

use super::dimensionless::{Dimensionless, Units};
use crate::fem::Mesh;
use crate::linalg::parallel::run_jobs;
use crate::linalg::stop::Stop;
use crate::model::Problem;

/// The largest relative difference between an interior node and its piece's exact local
/// solution (Hermite interpolation of the end values plus the clamped–clamped response to
/// the linear load), value and slope.
/// `None` when `stop` says so (asked before every stretch of [`CHUNK`] nodes).
pub(super) fn interior_residual(
    mesh: &Mesh,
    (u, t): (&Dimensionless, &Dimensionless),
    (magnitude, units): (&[[f64; 2]], &Units),
    problem: &Problem,
    stop: Stop,
) -> Option<f64> {
    // Stretches of at most CHUNK interior nodes of one piece, shared out over two threads when
    // there are many (linalg::parallel decides).
    let jobs: Vec<(usize, std::ops::Range<usize>)> = mesh
        .pieces
        .iter()
        .enumerate()
        .filter(|(_, p)| p.elements() >= 2)
        .flat_map(|(piece, p)| {
            (p.first_node + 1..p.last_node)
                .step_by(CHUNK)
                .map(move |start| (piece, start..(start + CHUNK).min(p.last_node)))
        })
        .collect();
    let results = run_jobs(
        jobs,
        |(_, range)| range.len(),
        |(piece, range)| {
            (!stop()).then(|| {
                stretch_residual(
                    mesh,
                    (u, t),
                    magnitude[piece],
                    units,
                    problem,
                    (piece, range),
                )
            })
        },
    );
    let results: Vec<(f64, bool)> = results.into_iter().collect::<Option<_>>()?;
    let overflow = results.iter().any(|&(_, overflow)| overflow);
    let worst = results.iter().fold(0.0f64, |m, &(w, _)| m.max(w));
    Some(if overflow { 1.0 } else { worst.min(1.0) })
}

/// The most interior nodes checked in one job (a millisecond of work).
const CHUNK: usize = 1 << 16;

/// [`interior_residual`] on the interior nodes `range` of piece `piece`: the largest relative
/// difference, and whether a scale overflowed (the residual is then 1, as `relative` says).
fn stretch_residual(
    mesh: &Mesh,
    (u, t): (&Dimensionless, &Dimensionless),
    [u_piece, t_piece]: [f64; 2],
    units: &Units,
    problem: &Problem,
    (piece, range): (usize, std::ops::Range<usize>),
) -> (f64, bool) {
    let mut worst = 0.0f64;
    let mut overflow = false;
    let p = &mesh.pieces[piece];
    let (a, b) = (p.first_node, p.last_node);
    let (xa, xb) = (mesh.nodes[a], mesh.nodes[b]);
    let length = units.x(xb) - units.x(xa);
    let ej = units.ej(p.bending_stiffness);
    let (fa, fb) = (units.f(problem.load_at(xa)), units.f(problem.load_at(xb)));
    let (ua, ta, ub, tb) = (u.at(a), t.at(a), u.at(b), t.at(b));
    // Clamped–clamped response to f = fa (1 − ξ) + fb ξ: L⁴/EJ (fa P(1 − ξ) + fb P(ξ)),
    // P(s) = s²(1 − s)²(s + 2)/120, P'(s) = −s(1 − s)(5s² + 5s − 4)/120: below with the
    // constant factors taken out of the loop.
    let l4 = (length * length) * (length * length) / ej;
    let (value_a, value_b) = (l4 / 120.0 * fa, l4 / 120.0 * fb);
    let (slope_a, slope_b) = (value_a / length, value_b / length);
    let (six_per_length, h) = (6.0 / length, length);
    let per_length = 1.0 / (xb - xa);
    let (u_raw, u_scale) = u.raw(range.clone());
    let (t_raw, t_scale) = t.raw(range.clone());
    let nodes = &mesh.nodes[range];
    for ((&x, &u_si), &t_si) in nodes.iter().zip(u_raw).zip(t_raw) {
        // ξ and 1 − ξ each from its own end: no cancellation next to either end. The
        // Hermite basis in factored form: each function to a few ulps of its own value.
        let (xi, eta) = ((x - xa) * per_length, (xb - x) * per_length);
        let (xi2, eta2, xe) = (xi * xi, eta * eta, xi * eta);
        let value_terms = [
            eta2 * (1.0 + 2.0 * xi) * ua,
            h * xe * eta * ta,
            xi2 * (1.0 + 2.0 * eta) * ub,
            -h * xe * xi * tb,
            value_a * xe * xe * (eta + 2.0),
            value_b * xe * xe * (xi + 2.0),
        ];
        let slope_terms = [
            -six_per_length * xe * ua,
            eta * (eta - 2.0 * xi) * ta,
            six_per_length * xe * ub,
            xi * (xi - 2.0 * eta) * tb,
            slope_a * xe * (5.0 * eta2 + 5.0 * eta - 4.0),
            -slope_b * xe * (5.0 * xi2 + 5.0 * xi - 4.0),
        ];
        for (terms, value, piece_scale) in [
            (value_terms, u_si * u_scale, u_piece),
            (slope_terms, t_si * t_scale, t_piece),
        ] {
            let exact: f64 = terms.iter().sum();
            // Relative to the piece's own magnitude too: a method resolves a value near a
            // clamped end to an ulp of the piece's values, not of that small value.
            let scale: f64 = terms.iter().map(|v| v.abs()).sum::<f64>() + value.abs() + piece_scale;
            overflow |= !scale.is_finite();
            // 0/0 (everything zero) is NaN, which max ignores: a residual of 0.
            worst = worst.max((value - exact).abs() / scale);
        }
    }
    (worst, overflow)
}
