//! One step of iterative refinement of an interior-point step's solve (`interior`, `mixed`)
//! with the residual of the exact piece relations in double-double, as `refinement` does for
//! a pattern's solve: the mixed conditions c − m = D(λ − λ₀) are taken exactly as given (their
//! f64 weights and base values), the pieces' transfers to about 106 bits.
//!
//! Used for the search's second guess only (`search::second_guess`): on tight clusters at ties
//! the f64 steps stalled the iteration at its cap of 80 steps, or ended it on a pattern
//! hundreds of DOFs from the answer, where the refined steps reach the iteration's μ in 61–66
//! steps and leave a guess the search settles in 7–10 pattern solves (stop 61,
//! docs/many-obstacles/refined-steps.md).

use super::mixed::{Mixed, MixedTemplate, StepSolves};
use super::system::ShootingSystem;
use crate::linalg::banded_lu::BandedSystem;
use crate::linalg::double_double::DoubleDouble;

/// Where the search asks for refined steps (its second guess, `search::second_guess`), the
/// steps from this one on are refined (`mixed_refinement`): the last steps are what the
/// refinement changes. On tight clusters at ties (k = 2000 seeds 1–300, k = 3000 seeds 1–100)
/// refined from step 0, 20, 35, 45 or 52 the searches took the same pattern solves (1756 and
/// 657 in all), from 58 or 64 two or three more; on clusters of 100 obstacles 1e-9·l apart
/// (k = 1000, an iteration of 50 steps) from 35 or 40 the search took 70, from 45 2456.
/// Each refined step costs two exact residuals and two back substitutions more: at k = 2000
/// the five slow seeds' solves took 156–232 ms refined from step 0, 130–209 ms from 30.
pub(super) const REFINED_FROM_STEP: usize = 30;

/// Motion and force change of a friction DOF from its column's value `v` (the force where
/// `force_held`, else the motion), in double-double.
fn motion_and_force(mixed: &Mixed, force_held: bool, v: DoubleDouble) -> [DoubleDouble; 2] {
    if force_held {
        let motion =
            DoubleDouble::from(mixed.motion) + (v - mixed.force.into()).times(mixed.weight);
        [motion, v]
    } else if mixed.weight.is_finite() {
        [
            v,
            DoubleDouble::from(mixed.force) + (v - mixed.motion.into()) / mixed.weight.into(),
        ]
    } else {
        [v, mixed.force.into()]
    }
}

impl ShootingSystem {
    /// b − A x of the mixed system (unloaded) with A the exact piece relations, rounded once
    /// per row (the rows of [`ShootingSystem::piece_residuals`]).
    pub(super) fn exact_mixed_residual(
        &self,
        mixed: &[Mixed],
        holds_force: &[bool],
        x: &[DoubleDouble],
    ) -> Vec<f64> {
        let dof = |p: usize, i: usize| {
            motion_and_force(&mixed[i], holds_force[i], x[Self::column(p, i % 2)])
        };
        let state = |p: usize| -> [DoubleDouble; 4] {
            std::array::from_fn(|c| match self.obstacle_at_point[p] {
                _ if c < 2 && p == 0 => DoubleDouble::ZERO,
                Some(j) if c < 2 => dof(p, 2 * j + c)[0],
                _ => x[Self::column(p, c)],
            })
        };
        self.piece_residuals(false, state, |p, i| dof(p, i)[1])
    }

    /// Refines the last solve of an interior-point step ([`ShootingSystem::solve_step`], whose
    /// factors `banded` holds) by one step with the exact residual, and takes its force
    /// changes from the refined unknowns. One step: on the 300 seeds of tight clusters at ties
    /// at k = 2000, one, two or three steps gave the same pattern-solve count on every seed
    /// (1256 in all, every step refined); the first correction is about 1e-16 of the largest
    /// unknown, the second 1e-30.
    pub(super) fn refine_step(
        &self,
        template: &MixedTemplate,
        mixed: &[Mixed],
        banded: &BandedSystem,
        solves: &mut StepSolves,
    ) {
        let Some(x) = self.refined_unknowns(mixed, banded, solves) else {
            return;
        };
        for (i, condition) in mixed.iter().enumerate() {
            let value = x[template.dof_columns[i]];
            let force = motion_and_force(condition, solves.holds_force[i], value)[1];
            solves.force_changes[i] = (force - condition.force.into()).value();
        }
    }

    /// The unknowns of the last solve in `solves`, refined by one step with the exact
    /// residual (`None` without factors).
    pub(super) fn refined_unknowns(
        &self,
        mixed: &[Mixed],
        banded: &BandedSystem,
        solves: &StepSolves,
    ) -> Option<Vec<DoubleDouble>> {
        let mut x: Vec<DoubleDouble> = solves.unknowns.iter().map(|&v| v.into()).collect();
        let mut correction = self.exact_mixed_residual(mixed, &solves.holds_force, &x);
        if !banded.apply_inverse(&mut correction) {
            return None;
        }
        self.count(|c| c.back_solves += 1);
        for (value, d) in x.iter_mut().zip(&correction) {
            *value = value.plus(*d);
        }
        Some(x)
    }
}
