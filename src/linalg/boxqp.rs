//! The dual problem (49): minimise ½ λᵀ S λ − z0ᵀ λ subject to −g ≤ λ ≤ g, with S SPD.
//!
//! Small problems (2k ≤ [`ACTIVE_SET_LIMIT`]) are solved by a primal active-set method, which
//! ends after finitely many steps with the exact solution of the final equality-constrained
//! subproblem (a Cholesky solve). Larger ones run Bertsekas' projected Newton method, which
//! changes many bounds per step and reaches the right face in a few dozen Cholesky solves of
//! the free block; the primal active-set method then certifies its answer exactly (usually one
//! more solve). Should projected Newton fail, MPRGP (Dostál's modified proportioning with
//! reduced gradient projections) finds an active set and the primal method finishes from there.
//! The problem is first scaled to unit diagonal, since S mixes deflection (m/N) and rotation
//! (rad/(N m)) entries.
//!
//! At 2k = 1022 one Cholesky factorization of a free block is up to a second of work: the
//! factorizations and the line search ask `stop` as they go (`linalg::stop`), not only once
//! per iteration.
//!
//! [`solve_box_qp_observed`] hands every iterate to a [`QpObserver`] (the convergence history
//! of `solve::history`); without one ([`solve_box_qp_until`]) nothing extra is computed.

mod mprgp;
mod watch;

use super::dense::Cholesky;
use super::stop::{Stop, Stopped};
use mprgp::mprgp;
use watch::Watch;

/// Largest dimension solved by the active-set method alone.
pub const ACTIVE_SET_LIMIT: usize = 32;

/// Where a variable ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BoundState {
    /// Strictly between the bounds.
    Free,
    /// At −g.
    Lower,
    /// At +g.
    Upper,
}

/// The solution of the box QP.
#[derive(Debug, Clone, PartialEq)]
pub struct QpResult {
    /// λ.
    pub x: Vec<f64>,
    /// Bound state of each λ_i.
    pub state: Vec<BoundState>,
    /// Iterations (active-set changes, plus MPRGP steps).
    pub iterations: usize,
    /// Whether the KKT conditions hold to working precision.
    pub converged: bool,
}

/// Sees the iterates of the box QP, in the caller's variables.
pub trait QpObserver {
    /// One iterate: x, the bound state of each variable (the active-set method's working set
    /// where it has one, else where x lies), the projected-gradient norm
    /// ‖y − P(y − ∇f(y))‖∞ / ‖D z‖∞ of the problem scaled to unit diagonal (x = D y; 0 at the
    /// solution) and the objective ½xᵀHx − zᵀx.
    fn iterate(&mut self, x: &[f64], state: &[BoundState], projected_gradient: f64, value: f64);
}

/// Solves min ½ xᵀHx − zᵀx, |x_i| ≤ g_i (`h` row-major n×n SPD, `g` ≥ 0), giving up
/// (unconverged) as soon as `stop` says so, asked every millisecond or so of work: the explorer
/// cancels a solve whose result is no longer wanted.
pub fn solve_box_qp_until(h: &[f64], z: &[f64], g: &[f64], stop: Stop) -> QpResult {
    solve_box_qp_observed(h, z, g, stop, None)
}

/// [`solve_box_qp_until`], showing `observer` the starting point x = 0 and every iterate after
/// it (active-set changes, projected Newton and MPRGP steps; a fallback to MPRGP restarts from
/// x = 0 without showing it again). The last one shown is the answer.
pub fn solve_box_qp_observed(
    h: &[f64],
    z: &[f64],
    g: &[f64],
    stop: Stop,
    observer: Option<&mut dyn QpObserver>,
) -> QpResult {
    let n = z.len();
    if n == 0 {
        if let Some(observer) = observer {
            observer.iterate(&[], &[], 0.0, 0.0);
        }
        return QpResult {
            x: vec![],
            state: vec![],
            iterations: 0,
            converged: true,
        };
    }
    // Scale to unit diagonal: x = D y, D = diag(1/√h_ii).
    let d: Vec<f64> = (0..n).map(|i| 1.0 / h[i * n + i].sqrt()).collect();
    let hs: Vec<f64> = (0..n * n).map(|ij| h[ij] * d[ij / n] * d[ij % n]).collect();
    let zs: Vec<f64> = (0..n).map(|i| z[i] * d[i]).collect();
    let gs: Vec<f64> = (0..n).map(|i| g[i] / d[i]).collect();
    if hs.iter().chain(&zs).chain(&gs).any(|v| !v.is_finite()) {
        return QpResult {
            x: vec![f64::NAN; n],
            state: vec![BoundState::Free; n],
            iterations: 0,
            converged: false,
        };
    }
    let scaled = Scaled {
        h: &hs,
        z: &zs,
        g: &gs,
    };
    let watch = &mut Watch {
        observer,
        scaling: &d,
    };
    if watch.observer.is_some() {
        watch.see(&scaled, &vec![0.0; n], None);
    }
    let mut finished = if n <= ACTIVE_SET_LIMIT {
        active_set(&scaled, vec![0.0; n], stop, watch)
    } else if let Some((start, steps)) = projected_newton(&scaled, stop, watch)
        && let certified = active_set(&scaled, start, stop, watch)
        && certified.converged
    {
        QpResult {
            iterations: certified.iterations + steps,
            ..certified
        }
    } else {
        // MPRGP finds the active set; the active-set method finishes exactly from there.
        let (start, steps) = mprgp(&hs, &zs, &gs, stop, &mut |x| watch.see(&scaled, x, None));
        let mut polished = active_set(&scaled, start, stop, watch);
        polished.iterations += steps;
        polished
    };
    for (x, d) in finished.x.iter_mut().zip(&d) {
        *x *= d;
    }
    finished
}

/// The scaled problem: H with unit diagonal, z and the bounds g.
struct Scaled<'a> {
    h: &'a [f64],
    z: &'a [f64],
    g: &'a [f64],
}

fn gradient(h: &[f64], z: &[f64], x: &[f64]) -> Vec<f64> {
    let n = x.len();
    (0..n)
        .map(|i| {
            h[i * n..(i + 1) * n]
                .iter()
                .zip(x)
                .map(|(a, b)| a * b)
                .sum::<f64>()
                - z[i]
        })
        .collect()
}

/// Tolerance on the gradient component i: rounding in computing (Hx − z)_i.
fn gradient_tolerance(h: &[f64], z: &[f64], x: &[f64], i: usize) -> f64 {
    let n = x.len();
    let magnitude: f64 = h[i * n..(i + 1) * n]
        .iter()
        .zip(x)
        .map(|(a, b)| (a * b).abs())
        .sum::<f64>()
        + z[i].abs();
    64.0 * n as f64 * f64::EPSILON * magnitude
}

/// The primal active-set method from `start`: minimise on the face of the current free
/// variables, stop at the first bound in the way, and release the bound with the worst
/// multiplier once at the face's minimiser.
fn active_set(problem: &Scaled, start: Vec<f64>, stop: Stop, watch: &mut Watch) -> QpResult {
    let Scaled { h, z, g } = *problem;
    let n = z.len();
    let mut x = start;
    let mut state = clamp_to_box(g, &mut x);
    let max_iterations = 20 * n + 50;
    for iteration in 1..=max_iterations {
        if stop() {
            return QpResult {
                x,
                state,
                iterations: iteration,
                converged: false,
            };
        }
        let free: Vec<usize> = (0..n).filter(|&i| state[i] == BoundState::Free).collect();
        if !free.is_empty() {
            let Ok(Some(minimiser)) = face_minimiser(h, z, &x, &state, &free, stop) else {
                // Not positive definite, or stopped.
                return QpResult {
                    x,
                    state,
                    iterations: iteration,
                    converged: false,
                };
            };
            if let Some((i, bound)) = step_towards(g, &mut x, &free, &minimiser) {
                state[i] = bound;
                x[i] = if bound == BoundState::Upper {
                    g[i]
                } else {
                    -g[i]
                };
                watch.see(problem, &x, Some(&state));
                continue;
            }
        }
        // At the subproblem's minimiser: release the bound with the worst multiplier.
        match worst_multiplier(h, z, g, &x, &state) {
            Some(i) => {
                state[i] = BoundState::Free;
                watch.see(problem, &x, Some(&state));
            }
            None => {
                watch.see(problem, &x, Some(&state));
                return QpResult {
                    x,
                    state,
                    iterations: iteration,
                    converged: true,
                };
            }
        }
    }
    QpResult {
        x,
        state,
        iterations: max_iterations,
        converged: false,
    }
}

/// Puts `x` into the box and says where each variable is; a zero threshold pins it at 0.
fn clamp_to_box(g: &[f64], x: &mut [f64]) -> Vec<BoundState> {
    (0..g.len())
        .map(|i| {
            if g[i] == 0.0 {
                x[i] = 0.0;
                BoundState::Lower
            } else if x[i] >= g[i] {
                x[i] = g[i];
                BoundState::Upper
            } else if x[i] <= -g[i] {
                x[i] = -g[i];
                BoundState::Lower
            } else {
                BoundState::Free
            }
        })
        .collect()
}

/// The minimiser over the `free` variables with the others held at their bounds; `None` if
/// the free block of H is not positive definite, [`Stopped`] when `stop` said so.
fn face_minimiser(
    h: &[f64],
    z: &[f64],
    x: &[f64],
    state: &[BoundState],
    free: &[usize],
    stop: Stop,
) -> Result<Option<Vec<f64>>, Stopped> {
    let n = x.len();
    let m = free.len();
    let mut sub = vec![0.0; m * m];
    let mut rhs = vec![0.0; m];
    for (a, &i) in free.iter().enumerate() {
        for (b, &j) in free.iter().enumerate() {
            sub[a * m + b] = h[i * n + j];
        }
        rhs[a] = z[i]
            - (0..n)
                .filter(|&j| state[j] != BoundState::Free)
                .map(|j| h[i * n + j] * x[j])
                .sum::<f64>();
    }
    let Some(factor) = Cholesky::factor_until(&sub, m, stop)? else {
        return Ok(None);
    };
    factor.solve_in_place(&mut rhs);
    Ok(Some(rhs))
}

/// The longest feasible step of the free variables towards `minimiser`; returns the variable
/// whose bound stopped it, if any.
fn step_towards(
    g: &[f64],
    x: &mut [f64],
    free: &[usize],
    minimiser: &[f64],
) -> Option<(usize, BoundState)> {
    let mut step = 1.0;
    let mut blocking = None;
    for (a, &i) in free.iter().enumerate() {
        let p = minimiser[a] - x[i];
        let limit = if p > 0.0 && minimiser[a] > g[i] {
            Some(((g[i] - x[i]) / p, BoundState::Upper))
        } else if p < 0.0 && minimiser[a] < -g[i] {
            Some(((-g[i] - x[i]) / p, BoundState::Lower))
        } else {
            None
        };
        if let Some((t, bound)) = limit
            && t < step
        {
            step = t.max(0.0);
            blocking = Some((i, bound));
        }
    }
    for (a, &i) in free.iter().enumerate() {
        x[i] += step * (minimiser[a] - x[i]);
        x[i] = x[i].clamp(-g[i], g[i]);
    }
    blocking
}

/// The bound variable whose multiplier has the wrong sign by the most (beyond rounding).
fn worst_multiplier(
    h: &[f64],
    z: &[f64],
    g: &[f64],
    x: &[f64],
    state: &[BoundState],
) -> Option<usize> {
    let grad = gradient(h, z, x);
    let mut worst: Option<(usize, f64)> = None;
    for i in 0..x.len() {
        if g[i] == 0.0 {
            continue;
        }
        let tolerance = gradient_tolerance(h, z, x, i);
        let violation = match state[i] {
            BoundState::Free => 0.0,
            BoundState::Upper => grad[i] - tolerance,
            BoundState::Lower => -grad[i] - tolerance,
        };
        if violation > 0.0 && worst.is_none_or(|(_, w)| violation > w) {
            worst = Some((i, violation));
        }
    }
    worst.map(|(i, _)| i)
}

/// Most projected Newton steps before falling back to MPRGP.
const PROJECTED_NEWTON_MAX_STEPS: usize = 200;

/// Bertsekas' projected Newton method (1982) on the scaled problem. Each step splits the
/// variables into binding ones (at or within ε of a bound, gradient pushing outwards), which
/// take a projected gradient step, and the rest, which take a Newton step with the Cholesky
/// factor of their block of H; an Armijo search along the projected arc keeps the objective
/// falling. Many bounds change per step, so it identifies the active set in a few dozen
/// Cholesky solves where the primal active-set method needs one solve per bound. Returns the
/// iterate at the first step that reached the minimiser of its face (the caller certifies it),
/// with the number of steps, or `None` on a singular block or after too many steps.
fn projected_newton(problem: &Scaled, stop: Stop, watch: &mut Watch) -> Option<(Vec<f64>, usize)> {
    let Scaled { h, z, g } = *problem;
    let n = z.len();
    let objective = |x: &[f64]| -> f64 {
        let hx: f64 = (0..n)
            .map(|i| {
                x[i] * h[i * n..(i + 1) * n]
                    .iter()
                    .zip(x)
                    .map(|(a, b)| a * b)
                    .sum::<f64>()
            })
            .sum();
        0.5 * hx - z.iter().zip(x).map(|(a, b)| a * b).sum::<f64>()
    };
    let g_max = g.iter().fold(0.0f64, |m, v| m.max(*v));
    let mut x = vec![0.0; n];
    let mut value = objective(&x);
    for step in 1..=PROJECTED_NEWTON_MAX_STEPS {
        if stop() {
            return None;
        }
        let grad = gradient(h, z, &x);
        // ‖x − P(x − ∇f)‖, the size of the projected gradient, sets the ε of "near a bound".
        let projected_gradient = (0..n)
            .map(|i| (x[i] - (x[i] - grad[i]).clamp(-g[i], g[i])).abs())
            .fold(0.0f64, f64::max);
        let near = (1e-3 * g_max).min(projected_gradient);
        let binding: Vec<bool> = (0..n)
            .map(|i| {
                g[i] == 0.0
                    || (x[i] <= -g[i] + near && grad[i] > 0.0)
                    || (x[i] >= g[i] - near && grad[i] < 0.0)
            })
            .collect();
        let free: Vec<usize> = (0..n).filter(|&i| !binding[i]).collect();
        let mut direction: Vec<f64> = grad.iter().map(|v| -v).collect();
        if !free.is_empty() {
            let m = free.len();
            let mut sub = vec![0.0; m * m];
            let mut rhs = vec![0.0; m];
            for (a, &i) in free.iter().enumerate() {
                for (b, &j) in free.iter().enumerate() {
                    sub[a * m + b] = h[i * n + j];
                }
                rhs[a] = -grad[i];
            }
            // Singular, or stopped.
            let factor = Cholesky::factor_until(&sub, m, stop).ok()??;
            factor.solve_in_place(&mut rhs);
            for (a, &i) in free.iter().enumerate() {
                direction[i] = rhs[a];
            }
        }
        // A full step that stays inside the box lands on the minimiser of the face.
        let face_minimum = free.iter().all(|&i| (x[i] + direction[i]).abs() <= g[i])
            && (0..n).all(|i| !binding[i] || (x[i] + direction[i]).abs() >= g[i]);
        let mut length = 1.0;
        let mut accepted = None;
        for _ in 0..60 {
            // Each trial is n² multiply-adds: a millisecond at n = 1022.
            if stop() {
                return None;
            }
            let trial: Vec<f64> = (0..n)
                .map(|i| (x[i] + length * direction[i]).clamp(-g[i], g[i]))
                .collect();
            let predicted: f64 = (0..n)
                .map(|i| {
                    if binding[i] {
                        grad[i] * (x[i] - trial[i])
                    } else {
                        -length * grad[i] * direction[i]
                    }
                })
                .sum();
            let trial_value = objective(&trial);
            if value - trial_value >= 1e-4 * predicted {
                accepted = Some((trial, trial_value));
                break;
            }
            length *= 0.5;
        }
        let Some((trial, trial_value)) = accepted else {
            // No decrease left to find at working precision: hand over what we have.
            return Some((x, step));
        };
        x = trial;
        value = trial_value;
        if x.iter().any(|v| !v.is_finite()) {
            return None;
        }
        watch.see(problem, &x, None);
        if face_minimum && length == 1.0 {
            return Some((x, step));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn random_problem(n: usize, seed: u64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let mut state = seed;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let m: Vec<f64> = (0..n * n).map(|_| next()).collect();
        let mut h = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                h[i * n + j] = (0..n).map(|k| m[i * n + k] * m[j * n + k]).sum::<f64>()
                    + if i == j { 0.1 } else { 0.0 };
            }
        }
        let z = (0..n).map(|_| 3.0 * next()).collect();
        let g = (0..n)
            .map(|i| if i % 7 == 3 { 0.0 } else { next().abs() })
            .collect();
        (h, z, g)
    }

    /// KKT of the box QP: stationarity on free variables, sign of multipliers on bound ones.
    fn assert_kkt(h: &[f64], z: &[f64], g: &[f64], r: &QpResult) {
        assert!(r.converged);
        let grad = gradient(h, z, &r.x);
        for i in 0..z.len() {
            assert!(r.x[i].abs() <= g[i] * (1.0 + 1e-15));
            let scale = 1e-9 * (1.0 + z[i].abs());
            if g[i] == 0.0 {
                continue;
            }
            match r.state[i] {
                BoundState::Free => assert!(grad[i].abs() < scale, "free grad {}", grad[i]),
                BoundState::Upper => assert!(grad[i] < scale),
                BoundState::Lower => assert!(grad[i] > -scale),
            }
        }
    }

    #[test]
    fn active_set_and_mprgp_satisfy_kkt() {
        for (n, seed) in [(1, 1), (2, 2), (8, 3), (20, 4), (33, 5), (80, 6), (200, 7)] {
            let (h, z, g) = random_problem(n, seed);
            let r = solve_box_qp_until(&h, &z, &g, &|| false);
            assert_kkt(&h, &z, &g, &r);
        }
    }

    #[test]
    fn unconstrained_minimiser_when_bounds_are_loose() {
        let h = [2.0, 0.5, 0.5, 1.0];
        let z = [1.0, -1.0];
        let r = solve_box_qp_until(&h, &z, &[100.0, 100.0], &|| false);
        // H x = z by Cramer's rule.
        let det = 2.0 - 0.25;
        let expected = [(1.0 + 0.5) / det, (-2.0 - 0.5) / det];
        assert!((r.x[0] - expected[0]).abs() < 1e-15);
        assert!((r.x[1] - expected[1]).abs() < 1e-15);
        assert_eq!(r.state, vec![BoundState::Free; 2]);
    }
}
