//! Iterative refinement of a pattern's solve with the residual of the exact piece relations in
//! double-double (`linalg::double_double`), and, where refinement with the f64 factors
//! diverges, the exact relations themselves factored in double-double
//! (`linalg::banded_lu_dd`): every friction DOF's motion and force to about 106 bits, with the
//! refinement's own estimate of the error left (the "Decisions" of the module `condensed`).

use super::CondensedFailure;
use super::system::{
    Accuracy, BAND_LOWER, BAND_UPPER, ExactValues, JUMPS, Pattern, PatternSolution, ShootingSystem,
};
use crate::linalg::banded_lu::BandedSystem;
use crate::linalg::banded_lu_dd::DoubleDoubleBanded;
use crate::linalg::double_double::DoubleDouble;

/// Most refinement steps with the exact residual.
const EXACT_REFINEMENT_STEPS: usize = 8;

/// A component whose correction is below this fraction of its value has converged (2⁻¹⁰⁰:
/// the double-double noise of the residual, about 2⁻¹⁰⁶ of the terms, moves corrections
/// around 2⁻¹⁰³ of the value from step to step).
const CONVERGED: f64 = 1.0 / (1u128 << 100) as f64;

/// Below this fraction of the iterate's largest component, the largest correction is the
/// noise of the double-double residual (it then wanders between 2⁻¹⁰⁷ and 2⁻¹⁰¹·⁶ of it on
/// ties at k = 4096 with the last swivel threshold ten notches down): the monotone search's
/// values ([`Accuracy::RefineForSearch`]) are refined until their largest correction is
/// below it. The small components go on converging by two or three digits a step there, so
/// full refinement ran to the cap of eight steps in 619 of that scene's 930 runs, and in
/// 174 the wander looked like divergence and sent it on with factors in double-double
/// (stop 43).
const RESIDUAL_NOISE: f64 = 1.0 / (1u128 << 96) as f64;

/// Pieces within this factor of one another in length: a growth of the largest correction
/// from the noise of the residual is that noise's wander, and refinement stops there instead
/// of going on with factors in double-double. On ties at k = 1000 the final refinement took
/// that turn at 8e-32 of the largest component (the corrections of the components not yet
/// converged all below 1e-34 of it), and the factors in double-double cost a fifth of the
/// solve; stopping there changes the nodal values by at most 2e-26 of max |u|, the forces and
/// states not at all (docs/many-obstacles/monotone-search.md, "The noise's wander on even pieces").
/// With pieces 1e-9 to 1e-8 long among others 0.3 long (wide seed 5269794724525844341) the same
/// stop left a force of 4e-44 wrong by 1e-5 of itself and a KKT residual of 1.4e-7: the f64
/// factors' corrections of such small components are not to be trusted, and there the factors in
/// double-double go on as before.
const EVEN_PIECES: f64 = 1e-3;

/// In the search's refinement ([`Accuracy::RefineForSearch`], [`Accuracy::RefineForDecisions`]),
/// a growth of the largest correction from below this many times [`RESIDUAL_NOISE`] is the
/// wander at the floor of the residual's rounding, not divergence, and refinement stops there
/// instead of going on with factors in double-double. On clusters at ties (stop 54's hunt,
/// k = 2000–3000) the f64 refinement reached that floor (at most 50 × [`RESIDUAL_NOISE`]) by
/// its third step, wandered, grew by 2–5 and was refactored in double-double, whose
/// refinement stayed at the same floor (25–135 ×) for up to eight steps: 944 such
/// refactorisations in the 2304 pattern solves of the slowest scene, 1–2 with this stop, the
/// answers the same to the bit (docs/many-obstacles/step-costs.md, stop 55). The answer's own solve
/// ([`Accuracy::RefineLast`]) goes on in double-double as before: with pieces 1e-9·l among
/// others 0.3·l the f64 factors' corrections of the smallest components are not to be
/// trusted ([`EVEN_PIECES`]), and a decision the search takes on them is checked there.
const SEARCH_WANDER: f64 = 1024.0;

/// How a run of refinement steps ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Refinement {
    /// Converged, or stopped gaining.
    Settled,
    /// The corrections grew (or could not be computed): the factors are too inaccurate.
    Diverged,
}

/// The noise of the double-double residual for the iterate `x` ([`RESIDUAL_NOISE`] of its
/// largest component).
fn residual_noise(x: &[DoubleDouble]) -> f64 {
    RESIDUAL_NOISE * x.iter().fold(0.0f64, |m, v| m.max(v.hi.abs()))
}

impl ShootingSystem {
    /// The pattern of the previous solve again ([`Accuracy::RefineLast`]): its system is
    /// unchanged, so `banded` still holds its factors and right-hand side; solved from those
    /// and refined as far as `accuracy` asks.
    pub(super) fn refine_last(
        &self,
        pattern: &[Pattern],
        banded: &BandedSystem,
        accuracy: Accuracy,
    ) -> Result<PatternSolution, CondensedFailure> {
        // The plain solve's own solution where the factors are still its (the same bits as
        // solving again: one substitution fewer per refined solve).
        let x = match banded.first_solve() {
            Some(first) => first.to_vec(),
            None => {
                let mut x = banded.rhs().to_vec();
                if !banded.apply_inverse(&mut x) {
                    return Err(CondensedFailure::Singular { column: 0 });
                }
                x
            }
        };
        Ok(self.refined_solution(pattern, banded, x, accuracy))
    }

    /// Is every friction DOF's decision settled by `x` with the error estimates
    /// `correction_size`: a moving DOF's motion, or a stuck DOF's force excess over its
    /// threshold (in double-double), beyond four times its last correction?
    fn every_decision_settled(
        &self,
        pattern: &[Pattern],
        x: &[DoubleDouble],
        correction_size: &[f64],
    ) -> bool {
        pattern.iter().enumerate().all(|(i, state)| {
            let (j, d) = (i / 2, i % 2);
            let column = Self::column(self.point_of_obstacle[j], d);
            let error = 4.0 * correction_size[column];
            let value = match state {
                Pattern::Stuck => (x[column].abs() - self.thresholds[j][d].into()).value(),
                Pattern::Positive | Pattern::Negative => x[column].hi,
            };
            error.is_finite() && value.abs() > error
        })
    }

    /// Iterative refinement of `x` (a solve of `pattern`'s system, whose factors `banded`
    /// holds) with the residual of the exact piece relations in double-double; the solution
    /// with its friction DOFs in double-double and their error estimates.
    fn refined_solution(
        &self,
        pattern: &[Pattern],
        banded: &BandedSystem,
        x: Vec<f64>,
        accuracy: Accuracy,
    ) -> PatternSolution {
        let mut x: Vec<DoubleDouble> = x.into_iter().map(DoubleDouble::from).collect();
        // Per component: the last correction (the error estimate once it stops shrinking).
        let mut correction_size = vec![f64::INFINITY; x.len()];
        let with_f64_factors = self.refine(pattern, &mut x, &mut correction_size, accuracy, |d| {
            banded.apply_inverse(d)
        });
        if with_f64_factors == Refinement::Diverged {
            // The f64 factors are too far from the exact relations: factor those themselves,
            // in double-double (banded_lu_dd), and go on from the last iterate.
            let mut matrix = self.exact_matrix(pattern);
            self.count(|c| {
                c.factorizations += 1;
                c.double_double_factorizations += 1;
            });
            if matrix.factor().is_ok() {
                correction_size.fill(f64::INFINITY);
                self.refine(pattern, &mut x, &mut correction_size, accuracy, |d| {
                    let solved = matrix.solve(d);
                    for (d, s) in d.iter_mut().zip(solved) {
                        *d = s.value();
                    }
                    true
                });
            }
        }
        let hi: Vec<f64> = x.iter().map(|v| v.hi).collect();
        let mut solution = self.pattern_solution(pattern, &hi);
        let dofs = pattern.len();
        let mut exact = ExactValues {
            force: vec![DoubleDouble::ZERO; dofs],
            motion_error: vec![0.0; dofs],
            force_error: vec![0.0; dofs],
        };
        for (i, state) in pattern.iter().enumerate() {
            let (j, d) = (i / 2, i % 2);
            let column = Self::column(self.point_of_obstacle[j], d);
            let g = self.thresholds[j][d];
            match state {
                Pattern::Stuck => {
                    exact.force[i] = x[column];
                    exact.force_error[i] = correction_size[column];
                }
                Pattern::Positive => {
                    exact.motion_error[i] = correction_size[column];
                    exact.force[i] = g.into();
                }
                Pattern::Negative => {
                    exact.motion_error[i] = correction_size[column];
                    exact.force[i] = (-g).into();
                }
            }
        }
        solution.exact = Some(exact);
        solution
    }

    /// Refinement steps x += A⁻¹ (b − A x) with the exact residual and `apply_inverse` for
    /// A⁻¹, until no component converges any more or the corrections grow, or `accuracy`
    /// asks for no more ([`Accuracy::RefineForDecisions`], [`Accuracy::RefineForSearch`]).
    fn refine(
        &self,
        pattern: &[Pattern],
        x: &mut [DoubleDouble],
        correction_size: &mut [f64],
        accuracy: Accuracy,
        mut apply_inverse: impl FnMut(&mut [f64]) -> bool,
    ) -> Refinement {
        let mut previous_largest = f64::INFINITY;
        for _ in 0..EXACT_REFINEMENT_STEPS {
            let mut d = self.exact_residual(pattern, x);
            self.count(|c| c.back_solves += 1);
            if !apply_inverse(&mut d) {
                return Refinement::Diverged;
            }
            let largest = d.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            if !largest.is_finite() || largest > 2.0 * previous_largest {
                // A growth from the floor of the residual's rounding is its wander: as far as
                // refinement goes. For the search below [`SEARCH_WANDER`] times the noise; for
                // the answer from the noise itself, on even pieces only ([`EVEN_PIECES`]).
                let wander_below = match accuracy {
                    Accuracy::RefineLast => self.pieces_are_even().then_some(1.0),
                    _ => Some(SEARCH_WANDER),
                };
                if largest.is_finite()
                    && wander_below.is_some_and(|f| previous_largest <= f * residual_noise(x))
                {
                    return Refinement::Settled;
                }
                // Diverging (singular to working precision): keep the last iterate.
                return Refinement::Diverged;
            }
            previous_largest = largest;
            // A component needs another step while its correction shrinks fast (refinement
            // gains digits geometrically; at the noise floor of its rows corrections only
            // wander, shrinking by 2 or 3 now and then) and the next one, predicted from that
            // rate, is still above the double-double resolution of its value. Small
            // components converge on their own scale, so the largest correction alone is no
            // stopping rule.
            let mut converging = false;
            for ((xi, di), last) in x.iter_mut().zip(&d).zip(correction_size.iter_mut()) {
                let size = di.abs();
                let next = if last.is_finite() {
                    size * (size / *last)
                } else {
                    size
                };
                converging |= size < *last / 16.0 && next > CONVERGED * xi.hi.abs();
                *last = size;
                *xi = xi.plus(*di);
            }
            let enough = match accuracy {
                Accuracy::RefineForDecisions => {
                    self.every_decision_settled(pattern, x, correction_size)
                }
                Accuracy::RefineForSearch => {
                    largest <= residual_noise(x)
                        && self.every_decision_settled(pattern, x, correction_size)
                }
                Accuracy::Plain | Accuracy::RefineLast => false,
            };
            if !converging || enough {
                break;
            }
        }
        Refinement::Settled
    }

    /// Are the beam's pieces within [`EVEN_PIECES`] of one another in length?
    fn pieces_are_even(&self) -> bool {
        let (shortest, longest) = self
            .pieces
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(s, l), p| {
                (s.min(p.length), l.max(p.length))
            });
        shortest >= EVEN_PIECES * longest
    }

    /// The matrix of `solve_pattern` with the exact piece relations' coefficients, in
    /// double-double.
    fn exact_matrix(&self, pattern: &[Pattern]) -> DoubleDoubleBanded {
        let mut matrix = DoubleDoubleBanded::new(self.unknowns(), BAND_LOWER, BAND_UPPER);
        self.assemble_matrix(
            pattern,
            |p| self.exact_pieces[p].transfer_matrix(),
            DoubleDouble::from,
            |row, column, value| matrix.add(row, column, value),
        );
        matrix
    }

    /// b − A x for the system of `pattern`, with A and b the exact piece relations (each
    /// piece's coefficients in double-double), rounded once per row: −(Φ y_p + q − y_{p+1}
    /// + jump) for every transfer row.
    fn exact_residual(&self, pattern: &[Pattern], x: &[DoubleDouble]) -> Vec<f64> {
        let stuck = |p: usize, d: usize| {
            self.obstacle_at_point[p].is_some_and(|j| pattern[2 * j + d] == Pattern::Stuck)
        };
        let state = |p: usize| -> [DoubleDouble; 4] {
            std::array::from_fn(|c| {
                if c < 2 && (p == 0 || stuck(p, c)) {
                    DoubleDouble::ZERO
                } else {
                    x[Self::column(p, c)]
                }
            })
        };
        let force = |p: usize, i: usize| {
            let g = self.thresholds[i / 2][i % 2];
            match pattern[i] {
                Pattern::Stuck => x[Self::column(p, i % 2)],
                Pattern::Positive => g.into(),
                Pattern::Negative => (-g).into(),
            }
        };
        self.piece_residuals(true, state, force)
    }

    /// The rows of every piece's exact relation, rounded once each: −(Φ y_p (+ q where
    /// `loaded`) − y_{p+1} + jump), with `state(p)` the state just right of point p and
    /// `force(p, i)` friction DOF i's force at point p (m'⁺ = m'⁻ − λ1, m⁺ = m⁻ + λ2, as in
    /// `solve_pattern`); the last piece's two rows of its clamped end.
    pub(super) fn piece_residuals(
        &self,
        loaded: bool,
        state: impl Fn(usize) -> [DoubleDouble; 4],
        force: impl Fn(usize, usize) -> DoubleDouble,
    ) -> Vec<f64> {
        let pieces = self.pieces.len();
        let mut residual = vec![0.0; self.unknowns()];
        for (p, piece) in self.exact_pieces.iter().enumerate() {
            let last = p + 1 == pieces;
            let mut end = if loaded {
                piece.transfer(state(p))
            } else {
                piece.transfer_unloaded(state(p))
            };
            if !last {
                let next = state(p + 1);
                for (e, n) in end.iter_mut().zip(next) {
                    *e = *e - n;
                }
                if let Some(j) = self.obstacle_at_point[p + 1] {
                    for (d, jump_row, sign) in JUMPS {
                        end[jump_row] = end[jump_row] + force(p + 1, 2 * j + d).times(sign);
                    }
                }
            }
            let rows = if last { 2 } else { 4 };
            for r in 0..rows {
                residual[4 * p + r] = -end[r].value();
            }
        }
        residual
    }
}
