//! The monotone search's step: a point on the friction DOFs (motions and forces), the exact
//! line search on the convex, piecewise quadratic J of (38) between two points, and the pattern
//! of a point.

use super::system::{Pattern, PatternSolution, ShootingSystem};
use crate::linalg::double_double::DoubleDouble;

/// A point of the monotone search on the friction DOFs: the motions c and the forces
/// r = b − K c there (K c = b − Bᵀλ, so r is λ at an optimum of a pattern). Both are linear in
/// the point, so a point between two solves carries the same combination of their forces:
/// no stiffness (1e27 for a piece 1e-9·l long) is ever multiplied by a displacement.
///
/// The forces are kept in double-double, as the refined solves give them: at ties every
/// force is its threshold to a few ulps, and the line search's slope Σ (g·sign − r)·d and
/// curvature Σ d·(r − r') are made of those differences. Rounded to f64 first, rounding
/// decided them, and on clusters at ties with a swivel threshold lowered the search went back
/// and forth between two patterns (k = 4000: 32 385 solves, 102 s, not converged) or stopped
/// lowering J (k = 3000: 24 384 solves, not converged); with the forces' own bits, 2067 and
/// 4966 solves (docs/many-obstacles/monotone-search.md, "Clusters at ties with one threshold
/// lowered").
#[derive(Debug, Clone, PartialEq)]
pub(super) struct SearchPoint {
    pub(super) motion: Vec<f64>,
    pub(super) force: Vec<DoubleDouble>,
}

impl ShootingSystem {
    /// The friction DOFs' motions and forces of a solve (the forces to about 106 bits where
    /// the solve was refined).
    pub(super) fn search_point(&self, solution: &PatternSolution) -> SearchPoint {
        SearchPoint {
            motion: (0..solution.lambda.len())
                .map(|i| self.friction_value(solution, i))
                .collect(),
            force: match &solution.exact {
                Some(exact) => exact.force.clone(),
                None => solution.lambda.iter().map(|&l| l.into()).collect(),
            },
        }
    }

    /// Exact minimisation of J(c + t d), d = target − c, over t ∈ [0, 1]: J is convex and
    /// piecewise quadratic along the segment, with kinks where a friction DOF crosses zero.
    /// The slope of its smooth part is −rᵀd and its curvature dᵀK d = dᵀ(r(c) − r(target)).
    /// Returns the new point (DOFs that stop at their kink set to exactly zero) and whether
    /// it is the target itself.
    pub(super) fn line_search(
        &self,
        current: &SearchPoint,
        target: &SearchPoint,
    ) -> (SearchPoint, bool) {
        let (c, r) = (&current.motion, &current.force);
        let d: Vec<f64> = target.motion.iter().zip(c).map(|(t, c)| t - c).collect();
        let q: f64 = d
            .iter()
            .zip(r.iter().zip(&target.force))
            .map(|(d, (a, b))| d * (*a - *b).value())
            .sum();
        let sign = |v: f64| {
            if v > 0.0 {
                1.0
            } else if v < 0.0 {
                -1.0
            } else {
                0.0
            }
        };
        // Slope of J at t = 0⁺ and the kinks ahead.
        let mut slope = 0.0;
        let mut kinks = Vec::new();
        for (i, (&ci, &di)) in c.iter().zip(&d).enumerate() {
            let g = self.thresholds[i / 2][i % 2];
            if di == 0.0 {
                continue;
            }
            if g == 0.0 {
                slope -= r[i].value() * di;
                continue;
            }
            let direction = if ci != 0.0 { sign(ci) } else { sign(di) };
            // One term per DOF, (g·sign − r)·d: exactly zero for a DOF that moves on at its
            // threshold, so a large moving DOF cannot round away the slope of the others.
            slope += (-r[i]).plus(g * direction).value() * di;
            if ci != 0.0 && sign(ci) != sign(di) {
                let t = -ci / di;
                if t < 1.0 {
                    kinks.push((t, i, 2.0 * g * di.abs()));
                }
            }
        }
        kinks.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut at = 0.0;
        let mut stop = None;
        if slope >= 0.0 {
            stop = Some((0.0, None));
        } else {
            for &(t, i, jump) in &kinks {
                // J'(s) = slope + q (s − at) on [at, t].
                if q > 0.0 && slope + q * (t - at) >= 0.0 {
                    stop = Some((at - slope / q, None));
                    break;
                }
                // The jump first: past a DOF's own kink it often cancels the slope.
                slope = (slope + jump) + q * (t - at);
                at = t;
                if slope >= 0.0 {
                    stop = Some((t, Some(i)));
                    break;
                }
            }
            if stop.is_none() && q > 0.0 && slope + q * (1.0 - at) >= 0.0 {
                stop = Some((at - slope / q, None));
            }
        }
        match stop {
            None => (target.clone(), true),
            Some((t, kink)) => {
                let t = t.clamp(0.0, 1.0);
                let mut next = SearchPoint {
                    motion: c
                        .iter()
                        .zip(&target.motion)
                        .map(|(a, b)| a + t * (b - a))
                        .collect(),
                    force: r
                        .iter()
                        .zip(&target.force)
                        .map(|(&a, &b)| a + (b - a).times(t))
                        .collect(),
                };
                if let Some(i) = kink {
                    next.motion[i] = 0.0;
                }
                // Every DOF whose kink lies at or before t has crossed or stopped at zero.
                for &(tk, i, _) in &kinks {
                    if tk == t {
                        next.motion[i] = 0.0;
                    }
                }
                (next, false)
            }
        }
    }

    /// J of (38) at a point, up to a constant: ½ cᵀK c − bᵀc + Σ g|c| with K c = b − r, so
    /// −½ cᵀ(b + r) + Σ g|c|, where b (`held`) are the forces with every DOF held.
    pub(super) fn objective(&self, point: &SearchPoint, held: &[DoubleDouble]) -> f64 {
        point
            .motion
            .iter()
            .zip(point.force.iter().zip(held))
            .enumerate()
            .map(|(i, (&c, (&r, b)))| {
                -0.5 * c * (*b + r).value() + self.thresholds[i / 2][i % 2] * c.abs()
            })
            .sum()
    }

    /// The pattern of a point: moving DOFs with their sign, zeros stuck.
    pub(super) fn signs_of(&self, point: &SearchPoint) -> Vec<Pattern> {
        point
            .motion
            .iter()
            .map(|&v| {
                if v > 0.0 {
                    Pattern::Positive
                } else if v < 0.0 {
                    Pattern::Negative
                } else {
                    Pattern::Stuck
                }
            })
            .collect()
    }
}
