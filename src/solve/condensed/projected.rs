//! A second start of the friction pattern search, for arrangements where neither the
//! semismooth Newton phases nor the monotone search settle soon: Bertsekas's projected
//! Newton method on the dual of (38), a box QP.
//!
//! About the held beam (every DOF stuck under the load, forces λ_h to about 106 bits, as in
//! `interior`), a change x of the friction forces within the box ±g − λ_h makes the motions
//! c(x) = −F x (F the flexibility of the friction DOFs), and the forces of (38) are those of
//! the point of the box nearest to the held forces in F's norm: x minimises Φ(x) = ½ xᵀF x
//! over the box, with gradient −c(x). Each step:
//!
//! - the active set: DOFs at (or within a hair of) a bound whose motion pushes them out
//!   (at +g moving positive, at −g negative): held there;
//! - the Newton step on the rest: every other DOF stuck (c = 0) with the active forces
//!   given: one solve of the mixed system of `mixed` (one factorisation);
//! - a projected search: y = P(x + α d), α = 1, ½, ¼, … until Φ falls by a fraction of what
//!   the gradient promises (Armijo); Φ(y) − Φ(x) = −½ (y − x)ᵀ(c(y) + c(x)) with c from the
//!   system with every force given, factored once (one back substitution per trial).
//!
//! Unlike a line search along a straight segment, the projection lets every DOF that reaches
//! a bound stop there while the others go on. In practice the full step is rarely taken
//! (its projection is clipped at hundreds of DOFs and Φ rises), the search halves, and a step
//! changes a few DOFs: 83 steps for two crowded scenes of 40 and 60 obstacles together, and on
//! one of 200 it stops after its 60 steps with DOFs wrong. So it is not a solver here but a
//! start the Newton phases have not tried, made after the monotone search has stalled
//! (`search`); the pattern search decides every DOF exactly from it.

use super::CondensedFailure;
use super::mixed::{Mixed, MixedTemplate};
use super::system::{BAND_LOWER, BAND_UPPER, Pattern, ShootingSystem};
use crate::linalg::banded_lu::BandedSystem;
use crate::linalg::double_double::DoubleDouble;

/// Most projected Newton steps. Measured on ties with obstacle k/3's swivel threshold two
/// notches down at k = 4000 (`cargo bench --bench many_obstacles -- lowered`), the pattern
/// solves of the whole search with a cap of 0, 3, 15, 30, 60 and 120 steps: 7284, 5716, 967,
/// 1058, 841 and 975 (with the restart after 64 monotone solves).
const MOST_STEPS: usize = 60;
/// Most halvings of one projected search.
const MOST_HALVINGS: usize = 40;
/// Fraction of the decrease the gradient promises that a step must achieve.
const ARMIJO: f64 = 1e-4;
/// A DOF this fraction of its box's width from a bound, pushed towards it, is active.
const NEAR_BOUND: f64 = 1e-12;

impl ShootingSystem {
    /// The projected Newton guess of the friction pattern about the held beam, whose forces
    /// `held` are given to about 106 bits (`None` when a system is singular); its
    /// factorisations and back substitutions go to the counts. `keep_going` is asked before
    /// every step.
    pub(super) fn projected_newton_pattern(
        &self,
        held: &[DoubleDouble],
        keep_going: &mut dyn FnMut() -> bool,
    ) -> Result<Option<Vec<Pattern>>, CondensedFailure> {
        let (bounds, fixed) = self.held_bounds(held);
        let template = self.mixed_template();
        let given = |x: &[f64]| -> Vec<Mixed> {
            fixed
                .iter()
                .zip(&bounds)
                .zip(x)
                .map(|((&fixed, bound), &force)| match bound {
                    Some(_) => Mixed { force, ..fixed },
                    None => fixed,
                })
                .collect()
        };
        let project = |i: usize, value: f64| match bounds[i] {
            Some((lower, upper)) => value.clamp(lower, upper),
            None => 0.0,
        };
        let mut x: Vec<f64> = (0..held.len()).map(|i| project(i, 0.0)).collect();
        let (mut all_given, mut given_holds_force) = (Self::empty_band(), Vec::new());
        let Ok((mut motion, _)) = self.solve_mixed(
            &template,
            &given(&x),
            &mut all_given,
            &mut given_holds_force,
        ) else {
            return Ok(None);
        };
        let (mut newton, mut newton_holds_force) = (Self::empty_band(), Vec::new());
        let (mut factorizations, mut back_solves) = (1, 0);
        let mut last_active: Option<Vec<Pattern>> = None;
        let mut last_full = false;
        for _ in 0..MOST_STEPS {
            if !keep_going() {
                return Err(CondensedFailure::Stopped);
            }
            let active = self.active_set(&bounds, &x, &motion);
            if last_full && last_active.as_ref() == Some(&active) {
                break;
            }
            // The Newton step: active forces at their bounds, every other DOF stuck.
            let mut conditions = given(&x);
            for (i, state) in active.iter().enumerate() {
                if let Some((lower, upper)) = bounds[i] {
                    match state {
                        Pattern::Positive => conditions[i].force = upper,
                        Pattern::Negative => conditions[i].force = lower,
                        Pattern::Stuck => {
                            conditions[i] = Mixed {
                                weight: 0.0,
                                force: 0.0,
                                motion: 0.0,
                            }
                        }
                    }
                }
            }
            let Ok((_, newton_forces)) =
                self.solve_mixed(&template, &conditions, &mut newton, &mut newton_holds_force)
            else {
                break;
            };
            factorizations += 1;
            let target: Vec<f64> = (0..x.len())
                .map(|i| match active[i] {
                    Pattern::Stuck if bounds[i].is_some() => newton_forces[i],
                    _ => conditions[i].force,
                })
                .collect();
            let Some((next, next_motion, full)) = self.projected_search(
                (&x, &motion, &target),
                &template,
                &project,
                &given,
                (&all_given, &given_holds_force),
                &mut back_solves,
            ) else {
                break;
            };
            let moved = next != x;
            x = next;
            motion = next_motion;
            last_full = full;
            last_active = Some(active);
            if !moved {
                break;
            }
        }
        self.count(|c| {
            c.factorizations += factorizations;
            c.back_solves += back_solves;
        });
        Ok(Some(self.active_set(&bounds, &x, &motion)))
    }

    /// An empty banded system of the multiple-shooting band.
    fn empty_band() -> BandedSystem {
        BandedSystem::new(0, BAND_LOWER, BAND_UPPER)
    }

    /// Per DOF: moving (`Positive`/`Negative`) where its force is at (or within
    /// [`NEAR_BOUND`] of) a bound and its motion pushes it out, else stuck; a DOF without
    /// friction moves with its motion's sign.
    fn active_set(&self, bounds: &[Option<(f64, f64)>], x: &[f64], motion: &[f64]) -> Vec<Pattern> {
        (0..x.len())
            .map(|i| {
                let Some((lower, upper)) = bounds[i] else {
                    return if motion[i] >= 0.0 {
                        Pattern::Positive
                    } else {
                        Pattern::Negative
                    };
                };
                let near = NEAR_BOUND * (upper - lower);
                if x[i] >= upper - near && motion[i] > 0.0 {
                    Pattern::Positive
                } else if x[i] <= lower + near && motion[i] < 0.0 {
                    Pattern::Negative
                } else {
                    Pattern::Stuck
                }
            })
            .collect()
    }

    /// The projected search from x (motions `motion`) towards `target`: the first of
    /// y = P(x + α (target − x)), α = 1, ½, …, where Φ falls by [`ARMIJO`] of what the
    /// gradient promises; with its motions and whether α = 1 reached the target unclipped.
    /// `None` when no α gives descent (rounding decides Φ there).
    #[allow(clippy::type_complexity)]
    fn projected_search(
        &self,
        (x, motion, target): (&[f64], &[f64], &[f64]),
        template: &MixedTemplate,
        project: &dyn Fn(usize, f64) -> f64,
        given: &dyn Fn(&[f64]) -> Vec<Mixed>,
        (all_given, given_holds_force): (&BandedSystem, &[bool]),
        back_solves: &mut usize,
    ) -> Option<(Vec<f64>, Vec<f64>, bool)> {
        let trials = (0..MOST_HALVINGS).map(|h| 0.5f64.powi(h as i32));
        for alpha in trials {
            let y: Vec<f64> = (0..x.len())
                .map(|i| project(i, x[i] + alpha * (target[i] - x[i])))
                .collect();
            let (y_motion, _) =
                self.resolve_mixed(template, &given(&y), all_given, given_holds_force)?;
            *back_solves += 1;
            // Φ(y) − Φ(x), and what the gradient −c(x) promises.
            let change: f64 = -0.5
                * (0..x.len())
                    .map(|i| (y[i] - x[i]) * (y_motion[i] + motion[i]))
                    .sum::<f64>();
            let promised: f64 = -(0..x.len()).map(|i| (y[i] - x[i]) * motion[i]).sum::<f64>();
            if promised < 0.0 && change <= ARMIJO * promised {
                let full = alpha == 1.0 && (0..x.len()).all(|i| y[i] == target[i]);
                return Some((y, y_motion, full));
            }
        }
        None
    }
}
