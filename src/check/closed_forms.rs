//! Closed forms the stability suite compares the condensed method against, written
//! independently of it: the paper's (50) (through [`crate::solve::closed_form`]), the plain
//! clamped beam when every threshold is zero, and clamped-clamped spans between the obstacles
//! when every obstacle is stuck. Constant E·J only; the load may be linear.

use crate::fem::{Mesh, NodalField};
use crate::model::Problem;
use crate::solve::closed_form;

/// u and u' of a beam clamped at both ends of the span [a, b] under the load
/// f(a) + s (x − a): EJ u'''' = f with u = u' = 0 at a and b, i.e.
/// u(t) = (f_a t⁴/24 + s t⁵/120)/EJ + c2 t² + c3 t³ with c2, c3 from the right end.
fn clamped_span(x: f64, (a, b): (f64, f64), f_a: f64, s: f64, ej: f64) -> (f64, f64) {
    let length = b - a;
    let p = (f_a * length.powi(4) / 24.0 + s * length.powi(5) / 120.0) / ej;
    let q = (f_a * length.powi(3) / 6.0 + s * length.powi(4) / 24.0) / ej;
    let c3 = (2.0 * p / length - q) / (length * length);
    let c2 = (q * length - 3.0 * p) / (length * length);
    let t = x - a;
    let u = (f_a * t.powi(4) / 24.0 + s * t.powi(5) / 120.0) / ej + c2 * t * t + c3 * t.powi(3);
    let du = (f_a * t.powi(3) / 6.0 + s * t.powi(4) / 24.0) / ej + 2.0 * c2 * t + 3.0 * c3 * t * t;
    (u, du)
}

fn spans_field(problem: &Problem, mesh: &Mesh, supports: &[f64]) -> NodalField {
    let ej = problem.stiffness[0].bending_stiffness;
    let s = problem.load_slope();
    let mut field = NodalField::zeros(mesh.nodes.len());
    for (i, &x) in mesh.nodes.iter().enumerate() {
        let span = supports
            .partition_point(|&p| p <= x)
            .clamp(1, supports.len() - 1);
        let (a, b) = (supports[span - 1], supports[span]);
        let (u, du) = clamped_span(x, (a, b), problem.load_at(a), s, ej);
        field.deflection[i] = u;
        field.slope[i] = du;
    }
    for (i, &x) in mesh.nodes.iter().enumerate() {
        if supports.contains(&x) {
            field.deflection[i] = 0.0;
            field.slope[i] = 0.0;
        }
    }
    field
}

/// The closed forms that apply to `problem`, given whether every obstacle ended stuck in both
/// directions: (name, nodal field).
pub fn closed_forms(
    problem: &Problem,
    mesh: &Mesh,
    all_stuck: bool,
) -> Vec<(&'static str, NodalField)> {
    let mut forms = Vec::new();
    if let Ok(exact) = closed_form(problem) {
        forms.push(("paper (50)", exact.nodal_field(mesh)));
    }
    if !problem.has_uniform_stiffness() {
        return forms;
    }
    let free = problem
        .obstacles
        .iter()
        .all(|o| o.sliding_threshold == 0.0 && o.swivel_threshold == 0.0);
    if free {
        forms.push((
            "clamped beam",
            spans_field(problem, mesh, &[0.0, problem.length]),
        ));
    }
    if all_stuck && !problem.obstacles.is_empty() {
        let mut supports = vec![0.0];
        supports.extend(problem.obstacles.iter().map(|o| o.x));
        supports.push(problem.length);
        forms.push(("clamped spans", spans_field(problem, mesh, &supports)));
    }
    forms
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_span_solution_satisfies_its_equation_and_ends() {
        let (a, b, f, s, ej) = (0.2, 1.7, 3.0, -1.5, 2.0);
        let (u0, d0) = clamped_span(a, (a, b), f, s, ej);
        let (u1, d1) = clamped_span(b, (a, b), f, s, ej);
        assert!(u0.abs() < 1e-15 && d0.abs() < 1e-15);
        assert!(u1.abs() < 1e-14 && d1.abs() < 1e-14);
        // Fourth difference of u ≈ f(x)/EJ.
        let h = 1e-2;
        let x = 0.9;
        let u = |x| clamped_span(x, (a, b), f, s, ej).0;
        let fourth = (u(x + 2.0 * h) - 4.0 * u(x + h) + 6.0 * u(x) - 4.0 * u(x - h)
            + u(x - 2.0 * h))
            / h.powi(4);
        let expected = (f + s * (x - a)) / ej;
        assert!((fourth - expected).abs() < 1e-6, "{fourth} vs {expected}");
    }
}
