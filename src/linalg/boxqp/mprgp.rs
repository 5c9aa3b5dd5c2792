//! MPRGP (Dostál's modified proportioning with reduced gradient projections) for the box QP of
//! (49), the fallback when projected Newton fails: it finds an active set that the primal
//! active-set method then finishes exactly.

use super::gradient;
use crate::linalg::stop::Stop;

/// MPRGP on the scaled problem; returns the iterate and the number of steps. `seen` is shown
/// every iterate after a step (the caller's watch, which does nothing without an observer).
pub(super) fn mprgp(
    h: &[f64],
    z: &[f64],
    g: &[f64],
    stop: Stop,
    seen: &mut dyn FnMut(&[f64]),
) -> (Vec<f64>, usize) {
    let n = z.len();
    let problem = Mprgp::new(h, g);
    let x = vec![0.0; n];
    let gr = gradient(h, z, &x);
    let phi = problem.free_gradient(&x, &gr);
    let mut it = MprgpIterate {
        p: phi.clone(),
        x,
        gr,
        phi,
    };
    let tolerance = 1e-13 * dot(z, z).sqrt().max(f64::MIN_POSITIVE);
    let max_steps = 50 * n + 200;
    for step in 1..=max_steps {
        if stop() {
            return (it.x, step);
        }
        let beta = problem.chopped_gradient(&it.x, &it.gr);
        let projected: f64 = it.phi.iter().zip(&beta).map(|(a, b)| (a + b).powi(2)).sum();
        if projected.sqrt() <= tolerance {
            return (it.x, step);
        }
        let moved = if dot(&beta, &beta) <= problem.reduced_free_gradient(&it) {
            problem.conjugate_gradient_step(z, &mut it)
        } else {
            problem.proportioning_step(&mut it, &beta)
        };
        if !moved {
            return (it.x, step);
        }
        seen(&it.x);
    }
    (it.x, max_steps)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>()
}

/// The scaled problem as MPRGP sees it: H, the bounds and the fixed step length ᾱ.
struct Mprgp<'a> {
    h: &'a [f64],
    g: &'a [f64],
    alpha_bar: f64,
}

/// An MPRGP iterate: x, the gradient, the free gradient φ and the conjugate direction p.
struct MprgpIterate {
    x: Vec<f64>,
    gr: Vec<f64>,
    phi: Vec<f64>,
    p: Vec<f64>,
}

impl<'a> Mprgp<'a> {
    fn new(h: &'a [f64], g: &'a [f64]) -> Mprgp<'a> {
        let n = g.len();
        // ‖H‖ bound (Gershgorin); step length ᾱ = 1/‖H‖ ∈ (0, 2/‖H‖].
        let norm = (0..n)
            .map(|i| h[i * n..(i + 1) * n].iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0, f64::max);
        Mprgp {
            h,
            g,
            alpha_bar: 1.0 / norm,
        }
    }

    fn mul(&self, v: &[f64]) -> Vec<f64> {
        let n = self.g.len();
        (0..n)
            .map(|i| {
                self.h[i * n..(i + 1) * n]
                    .iter()
                    .zip(v)
                    .map(|(a, b)| a * b)
                    .sum()
            })
            .collect()
    }

    fn free_gradient(&self, x: &[f64], gr: &[f64]) -> Vec<f64> {
        let g = self.g;
        (0..g.len())
            .map(|i| {
                if x[i] > -g[i] && x[i] < g[i] {
                    gr[i]
                } else {
                    0.0
                }
            })
            .collect()
    }

    fn chopped_gradient(&self, x: &[f64], gr: &[f64]) -> Vec<f64> {
        let g = self.g;
        (0..g.len())
            .map(|i| {
                if x[i] <= -g[i] {
                    gr[i].min(0.0)
                } else if x[i] >= g[i] {
                    gr[i].max(0.0)
                } else {
                    0.0
                }
            })
            .collect()
    }

    fn project(&self, x: &mut [f64]) {
        for i in 0..self.g.len() {
            x[i] = x[i].clamp(-self.g[i], self.g[i]);
        }
    }

    /// The reduced free gradient's square for the proportioning test.
    fn reduced_free_gradient(&self, it: &MprgpIterate) -> f64 {
        let (g, alpha_bar) = (self.g, self.alpha_bar);
        (0..g.len())
            .map(|i| {
                let phi = it.phi[i];
                let r = if phi > 0.0 {
                    ((it.x[i] + g[i]) / alpha_bar).min(phi)
                } else {
                    ((it.x[i] - g[i]) / alpha_bar).max(phi)
                };
                r * phi
            })
            .sum()
    }

    /// A conjugate gradient step along −p, or, when the box stops it, the largest feasible
    /// step followed by an expansion step. `false` when p has no curvature left.
    fn conjugate_gradient_step(&self, z: &[f64], it: &mut MprgpIterate) -> bool {
        let n = self.g.len();
        let g = self.g;
        let hp = self.mul(&it.p);
        let php = dot(&it.p, &hp);
        if php <= 0.0 {
            return false;
        }
        let a_cg = dot(&it.gr, &it.p) / php;
        // Largest feasible step along −p.
        let mut a_f = f64::INFINITY;
        for i in 0..n {
            if it.p[i] > 0.0 {
                a_f = a_f.min((it.x[i] + g[i]) / it.p[i]);
            } else if it.p[i] < 0.0 {
                a_f = a_f.min((it.x[i] - g[i]) / it.p[i]);
            }
        }
        if a_cg <= a_f {
            for i in 0..n {
                it.x[i] -= a_cg * it.p[i];
                it.gr[i] -= a_cg * hp[i];
            }
            it.phi = self.free_gradient(&it.x, &it.gr);
            let gamma = dot(&it.phi, &hp) / php;
            for i in 0..n {
                it.p[i] = it.phi[i] - gamma * it.p[i];
            }
        } else {
            for i in 0..n {
                it.x[i] -= a_f * it.p[i];
                it.gr[i] -= a_f * hp[i];
            }
            let phi_half = self.free_gradient(&it.x, &it.gr);
            for i in 0..n {
                it.x[i] -= self.alpha_bar * phi_half[i];
            }
            self.project(&mut it.x);
            it.gr = gradient(self.h, z, &it.x);
            it.phi = self.free_gradient(&it.x, &it.gr);
            it.p = it.phi.clone();
        }
        true
    }

    /// A step along the chopped gradient β that releases variables from their bounds.
    /// `false` when β has no curvature left.
    fn proportioning_step(&self, it: &mut MprgpIterate, beta: &[f64]) -> bool {
        let hd = self.mul(beta);
        let dhd = dot(beta, &hd);
        if dhd <= 0.0 {
            return false;
        }
        let a_cg = dot(&it.gr, beta) / dhd;
        for i in 0..self.g.len() {
            it.x[i] -= a_cg * beta[i];
            it.gr[i] -= a_cg * hd[i];
        }
        self.project(&mut it.x);
        it.phi = self.free_gradient(&it.x, &it.gr);
        it.p = it.phi.clone();
        true
    }
}
