//! The first guess of the friction pattern: a primal–dual interior-point method (Mehrotra's
//! predictor–corrector) on (38), whose number of steps does not depend on how many obstacles
//! there are or how they are arranged (issue 26), where an active-set search changes a few
//! DOFs per solve.
//!
//! It works on the change from the held beam (every DOF stuck under the load, its forces
//! λ_h refined to about 106 bits): force changes δλ within ±g − λ_h, motions c. At a friction
//! DOF with c_i = p_i − q_i (p, q ≥ 0) and slacks s⁺ = (g − λ_h) − δλ, s⁻ = δλ − (−g − λ_h),
//! (38) asks for p s⁺ = q s⁻ = 0; the method follows p s⁺ = q s⁻ = μ → 0. Eliminating p and
//! q from one Newton step leaves, per DOF, c_i = D_i δλ_i + r_i with D_i = p_i/s⁺_i + q_i/s⁻_i:
//! a mixed condition in place of "c = 0" (stuck) or "λ = ±g" (moving), so every step is one
//! solve of the (unloaded) multiple-shooting system of `system` — the same band, the same
//! stability on short pieces (`ShootingSystem::solve_mixed`).
//!
//! Why about the held beam: where a threshold equals the held force to rounding (the ties
//! family of issue 26), g − λ is below what f64 resolves of g, and an iteration on λ itself
//! can only call the DOF a tie; g − λ_h, taken in double-double, is a number of its own, and
//! the iteration decides it like any other. The iteration stops when μ is 1e-12 of the
//! smallest DOF's own scale (its nearest bound times the motions), so that a DOF whose bound
//! is 1e-9 of the others' (the moments at equally spaced obstacles) is decided too: 14–25
//! steps on the random and clustered families, 33–48 on ties; where more than 8 DOFs (or 1 %)
//! are still not clearly on their side there, it goes on while their number keeps falling
//! (`centrality::IterationEnd`: clusters at ties, stop 62).
//!
//! Two things keep the iteration within what its f64 steps resolve
//! (docs/many-obstacles/monotone-search.md, stop 48). The slacks s⁺ and s⁻ are variables of their
//! own, each stepped by its own update, not differences g − λ_h − δλ of the force: a moving DOF's
//! slack falls to μ/p (1e-18 of the force by the last steps), below the rounding of δλ, and as a
//! difference it became exactly zero, its weight infinite and the step NaN, which ended the
//! iteration with a pattern two DOFs off (at two pairs of obstacles 2e-6·l and 2e-5·l apart; random
//! k = 1000, seed 5) and cost the search 146 pattern solves. And a bound nearer zero than a few
//! ulps of the largest force change is widened to that (`held_bounds::widen_unresolved`): no step
//! resolves it, and the iteration stalled on it.
//!
//! Its pattern is usually right long before μ is that small. Where the pattern stays the same
//! over two steps with every DOF clearly on its side after the second, the iteration offers it
//! to the search ([`Crossover`]), which solves it once and ends everything there if it is
//! consistent, as interior-point methods for linear programs cross over to a vertex: on the
//! clustered family 4–5 steps instead of 14–15.
//!
//! Where the iteration stalls instead (all [`MOST_STEPS`] taken, μ still [`STALLED_SHORT_OF`]
//! times short: thresholds equal to the held forces among others that move, stop 53), a second
//! iteration starts with those near ties widened to 1e-6 of their range
//! (`held_bounds::WIDENED_TIE`); the search weighs both guesses (`search::stalled_first`).
//!
//! The result is only a guess: the search (`search`) starts from it and decides every DOF
//! exactly; where the guess is poor, it costs solves, never the answer. With it comes the same
//! pattern with the DOFs the iteration leaves unclear held stuck ([`Guess`]), which the search
//! tries where the guess's own pattern is inconsistent (near-coincident obstacles, clusters at
//! ties: docs/many-obstacles/close-obstacles-and-near-ties.md, stop 49). Where that search runs
//! long, it asks for a second guess from steps refined with the exact relations
//! (`mixed_refinement`, `search::second_guess`; stop 61).

use super::CondensedFailure;
use super::centrality::{IterationEnd, centrality_scales};
use super::held_bounds::{WIDENED_TIE, nearest, start_force, widen_unresolved};
use super::mixed::{Mixed, MixedTemplate, StepSolves};
use super::mixed_refinement::REFINED_FROM_STEP;
use super::offers::{Crossover, Offers};
use super::system::{Pattern, ShootingSystem};
use crate::linalg::banded_lu::BandedSystem;
use crate::linalg::double_double::DoubleDouble;

/// Most interior-point steps. Measured on the ties family (`cargo bench --bench
/// many_obstacles -- report`): at k = 4000 it reaches its μ in 48 steps (64 when the forces
/// and the motions took one step length), and there a cap of 40 or 50 left a guess that cost
/// 1037 or 443 pattern solves.
const MOST_STEPS: usize = 80;

/// An iteration that took all its steps and ended with μ above this many times the μ it was
/// to reach has stalled, and a second one starts with near ties widened
/// (`held_bounds::WIDENED_TIE`). Measured in stop 53
/// (docs/many-obstacles/close-obstacles-and-near-ties.md, "Near ties that the answer moves away
/// from"): on 60 scenes with some thresholds at the stuck forces and others not, the iterations at
/// the cap ended 1e5–1e22 times short of their μ (μ at 1e-15–1e-12 from about step 11 on, each step
/// going 0.1–10 % of the way), their guesses a hundred DOFs off (up to 1887 pattern solves); the
/// lowered ties that run to the cap end 0.9–3.2 times their μ, their guesses right or nearly.
const STALLED_SHORT_OF: f64 = 1e3;

/// A motion (as the force it makes) and a slack both below this fraction of the DOF's
/// nearest bound: the iteration cannot tell the DOF's side (about √ of its final μ).
const TIE_RESOLUTION: f64 = 1e-5;

/// A motion below this fraction of the largest of its kind is below what the iteration's f64
/// steps resolve; where the DOF's slack is more than [`CLEAR_SLACK`] of its range as well,
/// the guess holds it stuck. Judged by its diagonal stiffness instead, such noise looked
/// like a large force on obstacles 1e-9·l to 1e-7·l apart (stiffnesses of 1e20–1e27), and
/// the guess moved hundreds of DOFs that are stuck in the answer. Traced on 17 scenes of
/// pairs and dense stretches (docs/many-obstacles/close-obstacles-and-near-ties.md, stop 52): of
/// the DOFs the guess moved with a slack above 1e-4 of their range (all of them sliding DOFs),
/// those with a motion below 3e-18 of the largest were stuck in the answer 2787 times and moving
/// 37, those between 3e-18 and 3e-16 stuck 147 times and moving 155. With ε/8 = 2.8e-17, the
/// guesses of those scenes were 147 DOFs from their answers in all instead of 2962.
const UNRESOLVED_MOTION: f64 = f64::EPSILON / 8.0;

/// See [`UNRESOLVED_MOTION`]: a slack that far from its bound, relative to the DOF's range,
/// is the iteration's own, not the rounding of a tie.
const CLEAR_SLACK: f64 = 1e-4;

/// Fraction of the way to the boundary a step may go.
const TO_BOUNDARY: f64 = 0.99;

/// A pattern is offered only when every DOF is clearly on its side: its motion (as the force
/// its diagonal stiffness makes of it) and its slack differ by at least this factor. Without
/// this condition (two equal patterns in a row alone), the random family at k = 4000 offered
/// patterns with two and then one DOF wrong before the right one, and took 39 ms where it
/// had taken 33 (`cargo bench --bench many_obstacles -- report`, fastest of three
/// alternating runs); with it, 29 ms, one offer, right.
const CLEAR_SIDE: f64 = 100.0;

/// A friction DOF with a positive threshold in the interior-point method: the bounds of its
/// force change, ±g − λ_h, each to its own last bits, and the iterate (s⁺, s⁻, p, q), δλ
/// following from the nearer bound and its slack.
#[derive(Debug, Clone, Copy)]
struct FrictionVariable {
    /// Index of the DOF in the pattern (2·obstacle + kind).
    dof: usize,
    lower: f64,
    upper: f64,
    /// A motion (as the force it makes) and a slack both below this: a tie, held.
    resolution: f64,
    /// s⁺ = (g − λ_h) − δλ, kept as a variable of its own (to its own last bits, where the
    /// difference from δλ would be rounded to zero).
    slack_above: f64,
    /// s⁻ = δλ − (−g − λ_h), likewise.
    slack_below: f64,
    positive: f64,
    negative: f64,
}

impl FrictionVariable {
    /// δλ, from the nearer bound and its slack (the base force of a step's mixed condition).
    fn force(&self) -> f64 {
        if self.slack_above <= self.slack_below {
            self.upper - self.slack_above
        } else {
            self.lower + self.slack_below
        }
    }
    fn complementarity(&self) -> f64 {
        self.positive * self.slack_above + self.negative * self.slack_below
    }
    fn motion(&self) -> f64 {
        self.positive - self.negative
    }
    /// Is the DOF clearly on its side ([`CLEAR_SIDE`]): its motion (as the force its
    /// `diagonal_stiffness` makes of it) and its slack differ by that factor?
    fn clearly_on_its_side(&self, diagonal_stiffness: f64) -> bool {
        let slack = self.slack_above.min(self.slack_below);
        let motion = self.motion().abs() * diagonal_stiffness;
        motion > CLEAR_SIDE * slack || slack > CLEAR_SIDE * motion
    }
}

/// Lowers `length` (finite, ≥ 0) to `distance / rate` (`rate` > 0, finite) where that is
/// shorter: the bits of `length.min(distance / rate)`, with the division only where the
/// product test (with a margin of 8 ulps for its rounding) says the quotient may be shorter.
/// Most variables do not limit a step, so most of the step lengths' divisions go (unit tests
/// `step_lengths::*`; docs/many-obstacles/monotone-search.md, "Fewer divisions per interior-point
/// step").
#[inline(always)]
pub(super) fn shorten(length: &mut f64, distance: f64, rate: f64) {
    const MARGIN: f64 = 1.0 + 8.0 * f64::EPSILON;
    if distance <= *length * rate * MARGIN {
        *length = length.min(distance / rate);
    }
}

/// The Newton step of every friction variable: (Δλ, Δp, Δq).
type Step = Vec<[f64; 3]>;

/// The interior-point iteration: the variables and the system their steps are solved with.
struct InteriorPoint<'a> {
    system: &'a ShootingSystem,
    /// What every step's system shares with the others.
    template: MixedTemplate,
    /// The caller's system (its memory already in use), factored anew by every step.
    banded: &'a mut BandedSystem,
    /// What its solves keep between them (whether each DOF's column holds its force, the
    /// force changes found).
    solves: StepSolves,
    variables: Vec<FrictionVariable>,
    /// The condition of every DOF: those without a variable (no friction) give their force,
    /// the others are set by every step.
    mixed: Vec<Mixed>,
    /// μ at which the guess is taken.
    final_centrality: f64,
    /// The motions of the start (the pattern of a DOF without friction).
    free_motion: Vec<f64>,
    /// Per friction variable, D = p/s⁺ + q/s⁻ at the iterate of the step under way (set by
    /// its factoring solve, [`InteriorPoint::step`]).
    weights: Vec<f64>,
}

impl ShootingSystem {
    /// The interior-point guess of the friction pattern about the held beam, whose forces
    /// `held` are given to about 106 bits (`None` when a system is singular), solving in
    /// `banded` (the search's, so that one system's memory serves both); its steps go to
    /// the counts. `keep_going` is asked before every step (one banded factorisation, about
    /// 1.5 ms at 4000 obstacles) and [`CondensedFailure::Stopped`] returned when it says no.
    pub(super) fn interior_point_pattern(
        &self,
        held: &[DoubleDouble],
        banded: &mut BandedSystem,
        keep_going: &mut dyn FnMut() -> bool,
        crossover: &mut Crossover,
    ) -> Result<Option<Guess>, CondensedFailure> {
        let (bounds, fixed) = self.held_bounds(held);
        // Every held force within its threshold: the held beam is the answer.
        if bounds
            .iter()
            .flatten()
            .all(|&(lower, upper)| lower < 0.0 && upper > 0.0)
        {
            return Ok(Some(Guess {
                pattern: vec![Pattern::Stuck; held.len()],
                unclear_held: None,
                stalled_first: None,
            }));
        }
        // A first iteration about the bounds as they are; where it stalls, a second with
        // near ties widened to a fraction of their range.
        let (mut steps, mut range_fraction) = (0, 0.0);
        // Each step: a factorisation with its solve, and one more solve with its factors.
        let count_steps = |steps| {
            self.count(|c| {
                c.interior_steps += steps;
                c.factorizations += steps;
                c.back_solves += steps;
            })
        };
        // One template for both: the moving pattern's matrix does not depend on the bounds.
        let mut template = self.mixed_template();
        let mut stalled_first = None;
        loop {
            let widened = widen_unresolved(bounds.clone(), &fixed, range_fraction);
            let Some(mut method) = self.start_interior_point(widened, &fixed, template, banded)
            else {
                count_steps(steps);
                return Ok(stalled_first);
            };
            let taken = method.run(keep_going, crossover)?;
            steps += taken;
            let mut guess = method.guess();
            if range_fraction == 0.0 && method.stalled(taken) {
                template = method.template;
                range_fraction = WIDENED_TIE;
                stalled_first = Some(guess);
                continue;
            }
            method.template.keep();
            count_steps(steps);
            guess.stalled_first = stalled_first.map(Box::new);
            return Ok(Some(guess));
        }
    }

    /// The interior-point iteration within `bounds` (the held beam's, widened), on
    /// `template` ([`ShootingSystem::mixed_template`]), started from one solve in `banded`;
    /// `None` when that system is singular.
    fn start_interior_point<'a>(
        &'a self,
        bounds: Vec<Option<(f64, f64)>>,
        fixed: &[Mixed],
        template: MixedTemplate,
        banded: &'a mut BandedSystem,
    ) -> Option<InteriorPoint<'a>> {
        let mut start = fixed.to_vec();
        for (condition, bound) in start.iter_mut().zip(&bounds) {
            if let Some(bound) = *bound {
                condition.force = start_force(bound);
            }
        }
        let mut holds_force = Vec::new();
        let (motion, _) = self
            .solve_mixed(&template, &start, banded, &mut holds_force)
            .ok()?;
        let (mean, final_centrality) = centrality_scales(&bounds, &motion);
        // Centred at the mean scale: every complementarity product at least that.
        let variables = bounds
            .iter()
            .enumerate()
            .filter_map(|(dof, bound)| {
                let (lower, upper) = (*bound)?;
                let force = start[dof].force;
                let (slack_above, slack_below) = (upper - force, force - lower);
                Some(FrictionVariable {
                    dof,
                    lower,
                    upper,
                    resolution: TIE_RESOLUTION * nearest((lower, upper)),
                    slack_above,
                    slack_below,
                    positive: motion[dof].max(0.0) + mean / slack_above,
                    negative: (-motion[dof]).max(0.0) + mean / slack_below,
                })
            })
            .collect();
        Some(InteriorPoint {
            system: self,
            template,
            banded,
            solves: StepSolves::new(holds_force),
            variables,
            mixed: fixed.to_vec(),
            final_centrality,
            free_motion: motion,
            weights: Vec::new(),
        })
    }
}

impl InteriorPoint<'_> {
    /// Has the iteration stalled: `taken` all of its [`MOST_STEPS`] and ended with μ above
    /// [`STALLED_SHORT_OF`] times the μ it was to reach?
    fn stalled(&self, taken: usize) -> bool {
        taken == MOST_STEPS && self.centrality() > STALLED_SHORT_OF * self.final_centrality
    }

    /// μ: the mean complementarity product.
    fn centrality(&self) -> f64 {
        let sum: f64 = self.variables.iter().map(|v| v.complementarity()).sum();
        sum / (2 * self.variables.len()).max(1) as f64
    }

    /// Predictor–corrector steps until μ is at its end with few DOFs unclear there
    /// ([`IterationEnd`]), a solve fails, a step is not finite
    /// or `crossover` settles the search from a pattern offered to it (the iterate's
    /// own); the number of steps taken, or [`CondensedFailure::Stopped`] when `keep_going`,
    /// asked before every step, says no.
    fn run(
        &mut self,
        keep_going: &mut dyn FnMut() -> bool,
        crossover: &mut Crossover,
    ) -> Result<usize, CondensedFailure> {
        if self.variables.is_empty() {
            return Ok(0);
        }
        let mut offers = Offers::new(self.pattern());
        // Every step's vectors, reused (at 4000 obstacles each is 128–192 KB).
        let zero = vec![[0.0; 2]; self.variables.len()];
        let (mut affine, mut step, mut targets) = (Vec::new(), Vec::new(), Vec::new());
        let mut mu = self.centrality();
        let mut end = IterationEnd::new(self.final_centrality, self.variables.len());
        for done in 0..MOST_STEPS {
            if mu.is_nan() || end.reached(mu, done) {
                return Ok(done);
            }
            if !keep_going() {
                return Err(CondensedFailure::Stopped);
            }
            let refine = self.system.refined_steps.get() && done >= REFINED_FROM_STEP;
            if !self.step(&zero, (true, refine), &mut affine) {
                return Ok(done);
            }
            let reach = self.largest_step(&affine);
            let predicted: f64 = self
                .variables
                .iter()
                .zip(&affine)
                .map(|(v, [dl, dp, dq])| {
                    (v.positive + reach * dp) * (v.slack_above - reach * dl)
                        + (v.negative + reach * dq) * (v.slack_below + reach * dl)
                })
                .sum();
            let predicted = predicted / (2 * self.variables.len()) as f64;
            let centring = (predicted / mu).powi(3).clamp(0.0, 1.0);
            let target = centring * mu;
            targets.clear();
            targets.extend(
                affine
                    .iter()
                    .map(|&[dl, dp, dq]| [target + dp * dl, target - dq * dl]),
            );
            if !self.step(&targets, (false, refine), &mut step) {
                return Ok(done + 1);
            }
            // The forces and the motions each go as far as their own bounds allow.
            let Some((force_reach, motion_reach)) = self.largest_steps(&step) else {
                // A step that is not finite: the iterate so far is the guess.
                return Ok(done + 1);
            };
            let force_length = (TO_BOUNDARY * force_reach).min(1.0);
            let motion_length = (TO_BOUNDARY * motion_reach).min(1.0);
            // One pass: the step, the next μ (summed in the same order as
            // [`InteriorPoint::centrality`]) and how many DOFs are not clearly on their side.
            let (mut sum, mut unclear, mut largest) = (0.0, 0, [0.0f64; 2]);
            let system = self.system;
            for (v, [dl, dp, dq]) in self.variables.iter_mut().zip(&step) {
                v.slack_above -= force_length * dl;
                v.slack_below += force_length * dl;
                v.positive += motion_length * dp;
                v.negative += motion_length * dq;
                sum += v.complementarity();
                unclear += usize::from(!v.clearly_on_its_side(system.diagonal_stiffness(v.dof)));
                let largest = &mut largest[v.dof % 2];
                *largest = largest.max(v.motion().abs());
            }
            mu = sum / (2 * self.variables.len()) as f64;
            end.stepped(done + 1, unclear);
            let pattern = self.pattern_given(largest);
            if offers.settled(pattern, unclear == 0, self.banded, keep_going, crossover)? {
                return Ok(done + 1);
            }
        }
        Ok(MOST_STEPS)
    }

    /// The Newton step for complementarity targets (T⁺, T⁻) per friction variable: each
    /// DOF's c_new = D λ_new + r with r = c + ρ − D λ, ρ = (T⁺ − p s⁺)/s⁺ − (T⁻ − q s⁻)/s⁻,
    /// solved by the shooting system (factored anew when `factor`, else with the last
    /// factors), into `step`; false when it is singular. The weights D are those of the
    /// factors: computed with them, once for both of a step's solves (the iterate moves after
    /// both).
    fn step(
        &mut self,
        targets: &[[f64; 2]],
        (factor, refine): (bool, bool),
        step: &mut Step,
    ) -> bool {
        if factor {
            self.weights.clear();
            self.weights.extend(
                self.variables
                    .iter()
                    .map(|v| v.positive / v.slack_above + v.negative / v.slack_below),
            );
        }
        let mixed = &mut self.mixed;
        for ((v, [target_above, target_below]), &weight) in
            self.variables.iter().zip(targets).zip(&self.weights)
        {
            let rho = (target_above - v.positive * v.slack_above) / v.slack_above
                - (target_below - v.negative * v.slack_below) / v.slack_below;
            mixed[v.dof] = Mixed {
                weight,
                force: v.force(),
                motion: v.motion() + rho,
            };
        }
        let (template, mixed) = (&self.template, &self.mixed);
        let (system, banded, solves) = (self.system, &mut *self.banded, &mut self.solves);
        if !system.solve_step(template, mixed, banded, (factor, refine), solves) {
            return false;
        }
        let force_changes = &solves.force_changes;
        step.clear();
        step.extend(
            self.variables
                .iter()
                .zip(targets)
                .map(|(v, [target_above, target_below])| {
                    let dl = force_changes[v.dof];
                    let dp = (target_above - v.positive * v.slack_above + v.positive * dl)
                        / v.slack_above;
                    let dq = (target_below - v.negative * v.slack_below - v.negative * dl)
                        / v.slack_below;
                    [dl, dp, dq]
                }),
        );
        true
    }

    /// The largest α ≤ 1 keeping p, q, s⁺ and s⁻ non-negative along `step`.
    fn largest_step(&self, step: &Step) -> f64 {
        let mut alpha: f64 = 1.0;
        let mut limit = |value: f64, change: f64| {
            if change < 0.0 {
                shorten(&mut alpha, value, -change);
            }
        };
        for (v, &[dl, dp, dq]) in self.variables.iter().zip(step) {
            limit(v.positive, dp);
            limit(v.negative, dq);
            limit(v.slack_above, -dl);
            limit(v.slack_below, dl);
        }
        alpha.max(0.0)
    }

    /// The largest α ≤ 1 keeping s⁺ and s⁻ non-negative along `step`, and the largest keeping
    /// p and q non-negative. The iteration takes the two lengths separately, as interior-point
    /// methods for linear programs take the primal and the dual one: each step's system asks
    /// for c = D λ + r whatever the iterate's p − q is, so the motions may lag the forces for a
    /// step. Measured against one common length (`cargo bench --bench many_obstacles --
    /// report`, k = 128, 1000, 4000): 19, 27, 27 → 16, 25, 21 steps on the random family,
    /// 15, 16, 16 → 14, 15, 15 on clustered, 19, 21, 27 → 18, 21, 21 on mixed and 44, 53,
    /// 64 → 33, 43, 48 on ties, with the same 2 pattern solves each.
    /// `None` where the step is not finite.
    fn largest_steps(&self, step: &Step) -> Option<(f64, f64)> {
        let (mut forces, mut motions) = (1.0f64, 1.0f64);
        for (v, &[dl, dp, dq]) in self.variables.iter().zip(step) {
            if !(dl.is_finite() && dp.is_finite() && dq.is_finite()) {
                return None;
            }
            if dp < 0.0 {
                shorten(&mut motions, v.positive, -dp);
            }
            if dq < 0.0 {
                shorten(&mut motions, v.negative, -dq);
            }
            if dl > 0.0 {
                shorten(&mut forces, v.slack_above, dl);
            } else if dl < 0.0 {
                shorten(&mut forces, v.slack_below, -dl);
            }
        }
        Some((forces.max(0.0), motions.max(0.0)))
    }

    /// The pattern the iterate describes: a DOF moves where its motion (as the force its
    /// diagonal stiffness makes of it) exceeds its slack; a DOF without friction moves the
    /// way it does at the start.
    fn pattern(&self) -> Vec<Pattern> {
        let mut largest_motion = [0.0f64; 2];
        for v in &self.variables {
            let largest = &mut largest_motion[v.dof % 2];
            *largest = largest.max(v.motion().abs());
        }
        self.pattern_given(largest_motion)
    }

    /// [`InteriorPoint::pattern`] given the largest |motion| of each kind (even and odd DOFs).
    fn pattern_given(&self, largest_motion: [f64; 2]) -> Vec<Pattern> {
        let sign = |c: f64| {
            if c >= 0.0 {
                Pattern::Positive
            } else {
                Pattern::Negative
            }
        };
        let mut pattern: Vec<Pattern> = self.free_motion.iter().map(|&c| sign(c)).collect();
        for v in &self.variables {
            let slack = v.slack_above.min(v.slack_below);
            let stiffness = self.system.diagonal_stiffness(v.dof);
            // Both within what the iteration has settled (a tie): held, for the exact
            // decisions to take.
            let tie = v.motion().abs() * stiffness < v.resolution && slack < v.resolution;
            // A motion below what the steps resolve, with the force clearly inside its
            // bounds: held, whatever the stiffness makes of that noise.
            let unresolved = v.motion().abs() < UNRESOLVED_MOTION * largest_motion[v.dof % 2]
                && slack > CLEAR_SLACK * (v.upper - v.lower);
            pattern[v.dof] = if !tie && !unresolved && v.motion().abs() * stiffness > slack {
                sign(v.motion())
            } else {
                Pattern::Stuck
            };
        }
        pattern
    }

    /// The iterate's guess: its pattern, and that pattern with every DOF that is not clearly
    /// on its side ([`CLEAR_SIDE`]) held stuck (`None` where that changes nothing).
    fn guess(&self) -> Guess {
        let pattern = self.pattern();
        let mut held = pattern.clone();
        for v in &self.variables {
            if !v.clearly_on_its_side(self.system.diagonal_stiffness(v.dof)) {
                held[v.dof] = Pattern::Stuck;
            }
        }
        let unclear_held = (held != pattern).then_some(held);
        Guess {
            pattern,
            unclear_held,
            stalled_first: None,
        }
    }
}

/// The interior-point guess ([`InteriorPoint::guess`]).
#[derive(Clone, PartialEq)]
pub(super) struct Guess {
    pub(super) pattern: Vec<Pattern>,
    pub(super) unclear_held: Option<Vec<Pattern>>,
    /// Where this is a second iteration's guess: the first's, which stalled (the search
    /// weighs the two, `search::stalled_first`).
    pub(super) stalled_first: Option<Box<Guess>>,
}
