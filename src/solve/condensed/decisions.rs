//! What one solve of a pattern says about each friction DOF: what rounding resolves there, how
//! far its force is from the threshold, whether a decision must wait for refinement, the
//! pattern it wants (semismooth Newton's prediction for a reversal) and its final friction
//! state.

use super::system::{Pattern, PatternSolution, ShootingSystem};
use crate::solve::FrictionState;

/// What elimination without refinement is trusted to resolve, relative to the largest value
/// of a kind (generous: a short piece next to long ones makes the system ill-conditioned).
const PLAIN_RESOLUTION: f64 = 1e-6;

/// What a refined solve resolves at best, relative to the values around a DOF: a few hundred
/// units in the last place of double-double (2⁻¹⁰⁶).
const REFINED_RESOLUTION: f64 = 1.0 / (1u128 << 98) as f64;

impl ShootingSystem {
    /// What rounding can resolve at friction DOF i: (motion, force) below which a value is
    /// indistinguishable from zero, resp. a force from its threshold. After elimination alone:
    /// 64 ulps of the values around the DOF (the adjacent pieces' own values of its kind, the
    /// shear or moment on both sides). After refinement: a few hundred double-double ulps of
    /// them, or four times the refinement's last correction where that is larger.
    fn resolution(&self, solution: &PatternSolution, i: usize) -> (f64, f64) {
        const ULPS: f64 = 64.0 * f64::EPSILON;
        let (j, d) = (i / 2, i % 2);
        let p = self.point_of_obstacle[j];
        let [left, right] = [p - 1, p].map(|q| {
            let piece = &self.pieces[q];
            piece.magnitude(
                self.point_values(solution, q),
                self.point_values(solution, q + 1),
                d,
            )
        });
        let motion_scale = left.min(right);
        // m' for the force, m for the moment, on both sides of the obstacle.
        let component = if d == 0 { 3 } else { 2 };
        let force_scale = solution.end[p - 1][component]
            .abs()
            .max(solution.start[p][component].abs());
        match &solution.exact {
            None => (ULPS * motion_scale, ULPS * force_scale),
            Some(exact) => (
                (REFINED_RESOLUTION * motion_scale).max(4.0 * exact.motion_error[i]),
                (REFINED_RESOLUTION * force_scale).max(4.0 * exact.force_error[i]),
            ),
        }
    }

    /// |λ_i| − g_i, in double-double after refinement.
    pub(super) fn force_excess(&self, solution: &PatternSolution, i: usize) -> f64 {
        let g = self.thresholds[i / 2][i % 2];
        match &solution.exact {
            Some(exact) => (exact.force[i].abs() - g.into()).value(),
            None => solution.lambda[i].abs() - g,
        }
    }

    /// Which decisions of this solve are within what elimination without refinement resolves:
    /// a motion within [`PLAIN_RESOLUTION`] of the largest value of its kind, or a stuck force
    /// that close to its threshold, relative to the largest internal force of its kind.
    pub(super) fn uncertain(&self, solution: &PatternSolution, pattern: &[Pattern]) -> Vec<bool> {
        let motion_scale = solution.largest_motion.map(|v| PLAIN_RESOLUTION * v);
        let force_scale = solution.largest_force.map(|v| PLAIN_RESOLUTION * v);
        pattern
            .iter()
            .enumerate()
            .map(|(i, state)| {
                let d = i % 2;
                match state {
                    Pattern::Stuck => {
                        let g = self.thresholds[i / 2][d];
                        (solution.lambda[i].abs() - g).abs() <= force_scale[d]
                    }
                    _ => self.friction_value(solution, i).abs() <= motion_scale[d],
                }
            })
            .collect()
    }

    /// The DOFs whose state `solution` contradicts, with the pattern each wants.
    pub(super) fn inconsistent_dofs(
        &self,
        solution: &PatternSolution,
        pattern: &[Pattern],
    ) -> Vec<(usize, Pattern)> {
        (0..pattern.len())
            .filter_map(|i| {
                let wanted = self.wanted(solution, pattern, i);
                (wanted != pattern[i]).then_some((i, wanted))
            })
            .collect()
    }

    /// The pattern each DOF should have given this solution (the same when consistent).
    pub(super) fn wanted(
        &self,
        solution: &PatternSolution,
        pattern: &[Pattern],
        i: usize,
    ) -> Pattern {
        // The resolution is asked for only when the value itself does not settle it.
        match pattern[i] {
            Pattern::Stuck => {
                let l = solution.lambda[i];
                let excess = self.force_excess(solution, i);
                if excess > 0.0 && excess > self.resolution(solution, i).1 {
                    if l > 0.0 {
                        Pattern::Positive
                    } else {
                        Pattern::Negative
                    }
                } else {
                    Pattern::Stuck
                }
            }
            moving => match self.reversal(solution, pattern, i) {
                None => moving,
                // Semismooth Newton's prediction λ + σc: a large reversal goes straight to the
                // other bound.
                Some((sign, c))
                    if self.reverses_across(i, sign, c, self.reversal_fraction.get()) =>
                {
                    if moving == Pattern::Positive {
                        Pattern::Negative
                    } else {
                        Pattern::Positive
                    }
                }
                Some(_) => Pattern::Stuck,
            },
        }
    }

    /// A moving DOF whose motion c runs against its sign by more than the solve resolves:
    /// (sign, c); `None` for a stuck DOF or one that moves on.
    fn reversal(
        &self,
        solution: &PatternSolution,
        pattern: &[Pattern],
        i: usize,
    ) -> Option<(f64, f64)> {
        let sign = match pattern[i] {
            Pattern::Stuck => return None,
            Pattern::Positive => 1.0,
            Pattern::Negative => -1.0,
        };
        let c = self.friction_value(solution, i);
        // The resolution is asked for only when the value itself does not settle it.
        let moves_on = sign * c >= 0.0 || sign * c >= -self.resolution(solution, i).0;
        (!moves_on).then_some((sign, c))
    }

    /// Does the semismooth Newton prediction λ + σc take moving DOF i (moving with `sign`,
    /// now at c against it) across to the other bound? σ is `fraction` of its diagonal
    /// stiffness (12EJ/L³ per adjacent piece for a deflection, 4EJ/L for a slope); with σ = 0
    /// a reversing DOF is first held stuck.
    fn reverses_across(&self, i: usize, sign: f64, c: f64, fraction: f64) -> bool {
        let g = self.thresholds[i / 2][i % 2];
        sign * (sign * g + fraction * self.diagonal_stiffness(i) * c) < -g
    }

    /// Would σ = `fraction` of the diagonal stiffness decide DOF i otherwise than the present
    /// σ ([`ShootingSystem::wanted`])? Only a moving DOF that reverses depends on σ.
    pub(super) fn decision_depends_on_fraction(
        &self,
        solution: &PatternSolution,
        pattern: &[Pattern],
        i: usize,
        fraction: f64,
    ) -> bool {
        self.reversal(solution, pattern, i)
            .is_some_and(|(sign, c)| {
                self.reverses_across(i, sign, c, fraction)
                    != self.reverses_across(i, sign, c, self.reversal_fraction.get())
            })
    }

    pub(super) fn state(
        &self,
        solution: &PatternSolution,
        pattern: &[Pattern],
        i: usize,
    ) -> FrictionState {
        let (motion_noise, force_noise) = self.resolution(solution, i);
        match pattern[i] {
            Pattern::Stuck if self.force_excess(solution, i) < -force_noise => FrictionState::Stuck,
            Pattern::Stuck => FrictionState::AtThreshold,
            _ if self.friction_value(solution, i).abs() > motion_noise => FrictionState::Moves,
            _ => FrictionState::AtThreshold,
        }
    }
}
