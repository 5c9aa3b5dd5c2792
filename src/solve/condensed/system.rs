//! The multiple-shooting system on the special points: the unknowns (the state at the start of
//! every piece, the reactions of stuck DOFs), one banded solve per friction pattern, and what a
//! solve says about each DOF (its motion, its force, the state it wants).

use super::CondensedFailure;
use super::scaling::{ExactPiece, Piece, Scales};
use crate::fem::Mesh;
use crate::linalg::banded_lu::{BandedSystem, times_power_of_two};
use crate::linalg::banded_lu_dd::DoubleDoubleBanded;
use crate::linalg::double_double::DoubleDouble;
use crate::model::Problem;

/// The band of the multiple-shooting system: piece p's rows 4p..4p+3 (u, u', m, m') reach
/// the columns 4p − 2 ..= 4p + 1 of its start point (u and u' rows all four, m and m' rows only
/// m, m') and 4p + 2 ..= 4p + 5 of its end point (u, u' rows only a, b; the m row b and m; the
/// m' row a and m'), which bounds the band by (3, 3).
pub(super) const BAND_LOWER: usize = 3;
pub(super) const BAND_UPPER: usize = 3;

/// What elimination without refinement is trusted to resolve, relative to the largest value
/// of a kind (generous: a short piece next to long ones makes the system ill-conditioned).
pub(super) const PLAIN_RESOLUTION: f64 = 1e-6;

/// How accurately a pattern is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Accuracy {
    /// Elimination alone: each value to rounding of the largest ones.
    Plain,
    /// The pattern of the previous solve again (the system is unchanged), refined from its
    /// factors with the exact piece relations: each value to its own last bits.
    RefineLast,
}

/// How a friction DOF enters the linear system.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(super) enum Pattern {
    Stuck,
    /// Moves with λ = +g.
    Positive,
    /// Moves with λ = −g.
    Negative,
}

/// The dimensionless problem on the special points.
pub(super) struct Condensed {
    pub(super) pieces: Vec<Piece>,
    /// The same pieces' coefficients in double-double, for the refinement's residual.
    exact_pieces: Vec<ExactPiece>,
    /// For every special point 1..P−1: the obstacle there, if any.
    pub(super) obstacle_at_point: Vec<Option<usize>>,
    /// For every obstacle: its special point.
    pub(super) point_of_obstacle: Vec<usize>,
    /// Dimensionless thresholds (g1, g2) per obstacle.
    pub(super) thresholds: Vec<[f64; 2]>,
    /// σ / diagonal stiffness in the reversal prediction of the current Newton phase.
    pub(super) reversal_fraction: std::cell::Cell<f64>,
}

/// The states of one solve of a fixed pattern.
pub(super) struct PatternSolution {
    /// State just right of every special point 0..P−1 (u, u', m, m').
    pub(super) start: Vec<[f64; 4]>,
    /// State at the end of every piece (just left of point p + 1).
    pub(super) end: Vec<[f64; 4]>,
    /// λ per friction DOF (given for moving DOFs, solved for stuck ones).
    pub(super) lambda: Vec<f64>,
    /// After refinement: every friction DOF's value and force to about 106 bits, and what
    /// the refinement says of their accuracy.
    pub(super) exact: Option<ExactValues>,
    /// The largest deflection and slope the pieces carry (their end values, t·u' and their
    /// own response to the load): with every special point's deflection at zero or at noise
    /// level, the largest end value alone would be noise.
    pub(super) largest_motion: [f64; 2],
    /// The largest shear m' and moment m at the special points (what λ1, λ2 jump).
    pub(super) largest_force: [f64; 2],
}

/// The friction DOFs of a refined solve, in double-double.
pub(super) struct ExactValues {
    /// λ_i (±g for a moving DOF).
    pub(super) force: Vec<DoubleDouble>,
    /// |last correction| of the motion of DOF i (0 when stuck: it is zero by construction):
    /// the refinement's own estimate of the error left.
    pub(super) motion_error: Vec<f64>,
    /// |last correction| of the force of DOF i (0 when moving: it is ±g exactly).
    pub(super) force_error: Vec<f64>,
}

/// Most refinement steps with the exact residual.
const EXACT_REFINEMENT_STEPS: usize = 8;

/// A component whose correction is below this fraction of its value has converged (2⁻¹⁰⁰:
/// the double-double noise of the residual, about 2⁻¹⁰⁶ of the terms, moves corrections
/// around 2⁻¹⁰³ of the value from step to step).
const CONVERGED: f64 = 1.0 / (1u128 << 100) as f64;

/// The jumps at an obstacle, (DOF kind, transfer row, sign): m'⁺ = m'⁻ − λ1 (row 3),
/// m⁺ = m⁻ + λ2 (row 2).
const JUMPS: [(usize, usize, f64); 2] = [(0, 3, -1.0), (1, 2, 1.0)];

/// How a run of refinement steps ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Refinement {
    /// Converged, or stopped gaining.
    Settled,
    /// The corrections grew (or could not be computed): the factors are too inaccurate.
    Diverged,
}

/// What a refined solve resolves at best, relative to the values around a DOF: a few hundred
/// units in the last place of double-double (2⁻¹⁰⁶).
const REFINED_RESOLUTION: f64 = 1.0 / (1u128 << 98) as f64;

impl Condensed {
    /// The system of `problem` on `mesh` in the units of `scales`, with σ / diagonal stiffness
    /// `reversal_fraction` in the reversal prediction until the search sets another.
    pub(super) fn new(
        problem: &Problem,
        mesh: &Mesh,
        scales: &Scales,
        reversal_fraction: f64,
    ) -> Condensed {
        let length = |x: f64| times_power_of_two(x, -scales.length);
        let load = |f: f64| times_power_of_two(f, -scales.load);
        let (f0, f1) = (load(problem.load.f0), load(problem.load.f1));
        // f0 + (f1 − f0)·x/l in double-double, from the scaled f64 data.
        let exact_load = |x: f64| {
            if f0 == f1 {
                DoubleDouble::from(f0)
            } else {
                DoubleDouble::difference(f1, f0) * (DoubleDouble::from(x) / problem.length.into())
                    + f0.into()
            }
        };
        let exact_pieces: Vec<ExactPiece> = mesh
            .pieces
            .iter()
            .map(|piece| {
                let (a, b) = (mesh.nodes[piece.first_node], mesh.nodes[piece.last_node]);
                let exact = DoubleDouble::difference(b, a);
                ExactPiece::new(
                    DoubleDouble {
                        hi: length(exact.hi),
                        lo: length(exact.lo),
                    },
                    times_power_of_two(piece.bending_stiffness, -scales.stiffness),
                    exact_load(a),
                    exact_load(b),
                )
            })
            .collect();
        let pieces: Vec<Piece> = mesh
            .pieces
            .iter()
            .map(|piece| {
                let (a, b) = (mesh.nodes[piece.first_node], mesh.nodes[piece.last_node]);
                Piece {
                    length: length(b - a),
                    stiffness: times_power_of_two(piece.bending_stiffness, -scales.stiffness),
                    load_start: load(problem.load_at(a)),
                    load_end: load(problem.load_at(b)),
                }
            })
            .collect();
        let mut obstacle_at_point = vec![None; pieces.len() + 1];
        let point_of_obstacle: Vec<usize> = mesh
            .obstacle_nodes
            .iter()
            .enumerate()
            .map(|(j, &node)| {
                let point = mesh.pieces.partition_point(|p| p.first_node < node);
                obstacle_at_point[point] = Some(j);
                point
            })
            .collect();
        let thresholds = problem
            .obstacles
            .iter()
            .map(|o| {
                [
                    times_power_of_two(o.sliding_threshold, -scales.force()),
                    times_power_of_two(o.swivel_threshold, -scales.moment()),
                ]
            })
            .collect();
        Condensed {
            pieces,
            exact_pieces,
            obstacle_at_point,
            point_of_obstacle,
            thresholds,
            reversal_fraction: std::cell::Cell::new(reversal_fraction),
        }
    }

    /// Solves the linear problem of one pattern: stuck DOFs are held at zero with an unknown
    /// reaction, moving DOFs carry the force ±g.
    ///
    /// Unknowns: m, m' at the left support (u = u' = 0 there), then per interior special point
    /// (a, b, m, m') just right of it, where a is u there, or the reaction λ1 when u is stuck
    /// (u = 0 is then known), and b likewise u' or λ2. A known zero never enters the matrix:
    /// the transfer rows of a short piece between stuck DOFs keep only the entries that carry
    /// its flexibility (t u', t² m/2EJ, t³ m'/6EJ), and row equilibration sees them at their
    /// own scale instead of next to the 1 of a value that is zero anyway.
    /// Rows: per piece its four transfer rows (two for the last piece: the far end is
    /// clamped), in the order of the columns, so the band is (3, 3) ([`BAND_LOWER`],
    /// [`BAND_UPPER`]); the matrix is [`Condensed::assemble_matrix`]'s.
    pub(super) fn solve_pattern(
        &self,
        pattern: &[Pattern],
        accuracy: Accuracy,
        system: &mut BandedSystem,
    ) -> Result<PatternSolution, CondensedFailure> {
        let pieces = self.pieces.len();
        if accuracy == Accuracy::RefineLast {
            let mut x = system.rhs().to_vec();
            if !system.apply_inverse(&mut x) {
                return Err(CondensedFailure::Singular { column: 0 });
            }
            return Ok(self.refined_solution(pattern, system, x));
        }
        system.reset(4 * pieces - 2);
        self.assemble_matrix(
            pattern,
            |p| self.pieces[p].transfer_matrix(),
            |v| v,
            |row, column, value| system.add(row, column, value),
        );
        for (p, piece) in self.pieces.iter().enumerate() {
            let q = piece.load_terms();
            let rows = if p + 1 == pieces { 2 } else { 4 };
            for (r, q) in q.iter().enumerate().take(rows) {
                system.add_rhs(4 * p + r, -q);
            }
            // A moving DOF's known force ±g enters its jump row's right-hand side.
            if p + 1 < pieces
                && let Some(j) = self.obstacle_at_point[p + 1]
            {
                for (d, jump_row, sign) in JUMPS {
                    let g = self.thresholds[j][d];
                    match pattern[2 * j + d] {
                        Pattern::Stuck => {}
                        Pattern::Positive => system.add_rhs(4 * p + jump_row, -sign * g),
                        Pattern::Negative => system.add_rhs(4 * p + jump_row, sign * g),
                    }
                }
            }
        }
        let x = system
            .solve_unrefined()
            .map_err(|e| CondensedFailure::Singular { column: e.column })?;
        Ok(self.pattern_solution(pattern, &x))
    }

    /// Column of component c (0..4) of the state at point p; point 0 has only m, m'.
    fn column(p: usize, c: usize) -> usize {
        if p == 0 { c - 2 } else { 4 * p - 2 + c }
    }

    /// Iterative refinement of `x` (a solve of `pattern`'s system, whose factors `system`
    /// holds) with the residual of the exact piece relations in double-double; the solution
    /// with its friction DOFs in double-double and their error estimates.
    fn refined_solution(
        &self,
        pattern: &[Pattern],
        system: &BandedSystem,
        x: Vec<f64>,
    ) -> PatternSolution {
        let mut x: Vec<DoubleDouble> = x.into_iter().map(DoubleDouble::from).collect();
        // Per component: the last correction (the error estimate once it stops shrinking).
        let mut correction_size = vec![f64::INFINITY; x.len()];
        let with_f64_factors = self.refine(pattern, &mut x, &mut correction_size, |d| {
            system.apply_inverse(d)
        });
        if with_f64_factors == Refinement::Diverged {
            // The f64 factors are too far from the exact relations: factor those themselves,
            // in double-double (banded_lu_dd), and go on from the last iterate.
            let mut matrix = self.exact_matrix(pattern);
            if matrix.factor().is_ok() {
                correction_size.fill(f64::INFINITY);
                self.refine(pattern, &mut x, &mut correction_size, |d| {
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
    /// A⁻¹, until no component converges any more or the corrections grow.
    fn refine(
        &self,
        pattern: &[Pattern],
        x: &mut [DoubleDouble],
        correction_size: &mut [f64],
        mut apply_inverse: impl FnMut(&mut [f64]) -> bool,
    ) -> Refinement {
        let mut previous_largest = f64::INFINITY;
        for _ in 0..EXACT_REFINEMENT_STEPS {
            let mut d = self.exact_residual(pattern, x);
            if !apply_inverse(&mut d) {
                return Refinement::Diverged;
            }
            let largest = d.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            if !largest.is_finite() || largest > 2.0 * previous_largest {
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
            if !converging {
                break;
            }
        }
        Refinement::Settled
    }

    /// The matrix of `solve_pattern` with the exact piece relations' coefficients, in
    /// double-double.
    fn exact_matrix(&self, pattern: &[Pattern]) -> DoubleDoubleBanded {
        let mut matrix = DoubleDoubleBanded::new(4 * self.pieces.len() - 2, BAND_LOWER, BAND_UPPER);
        self.assemble_matrix(
            pattern,
            |p| self.exact_pieces[p].transfer_matrix(),
            DoubleDouble::from,
            |row, column, value| matrix.add(row, column, value),
        );
        matrix
    }

    /// The matrix of `pattern`'s system (the layout of `solve_pattern`): `add(row, column,
    /// value)` for every entry, with `transfer(p)` piece p's Φ and `constant` the entry ±1.
    /// Rows: per piece its four transfer rows (two for the last piece: the far end is
    /// clamped), Φ y_p − y_{p+1} + jump; a known zero (u, u' at the left support, a stuck
    /// DOF) has no column, and a stuck DOF's reaction takes the column of its value.
    fn assemble_matrix<T: Copy>(
        &self,
        pattern: &[Pattern],
        transfer: impl Fn(usize) -> [[T; 4]; 4],
        constant: impl Fn(f64) -> T,
        mut add: impl FnMut(usize, usize, T),
    ) {
        let pieces = self.pieces.len();
        let column = Self::column;
        let stuck = |p: usize, d: usize| {
            self.obstacle_at_point[p].is_some_and(|j| pattern[2 * j + d] == Pattern::Stuck)
        };
        for p in 0..pieces {
            let phi = transfer(p);
            let row = 4 * p;
            let last = p + 1 == pieces;
            let rows = if last { 2 } else { 4 };
            for r in 0..rows {
                // Φ is upper triangular.
                for c in r..4 {
                    let known_zero = c < 2 && (p == 0 || stuck(p, c));
                    if !known_zero {
                        add(row + r, column(p, c), phi[r][c]);
                    }
                }
                let next_is_known_zero = r < 2 && !last && stuck(p + 1, r);
                if !last && !next_is_known_zero {
                    add(row + r, column(p + 1, r), constant(-1.0));
                }
            }
            if !last && let Some(j) = self.obstacle_at_point[p + 1] {
                for (d, jump_row, sign) in JUMPS {
                    if pattern[2 * j + d] == Pattern::Stuck {
                        add(row + jump_row, column(p + 1, d), constant(sign));
                    }
                }
            }
        }
    }

    /// b − A x for the system of `pattern`, with A and b the exact piece relations (each
    /// piece's coefficients in double-double), rounded once per row: −(Φ y_p + q − y_{p+1}
    /// + jump) for every transfer row.
    fn exact_residual(&self, pattern: &[Pattern], x: &[DoubleDouble]) -> Vec<f64> {
        let pieces = self.pieces.len();
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
        let mut residual = vec![0.0; x.len()];
        for (p, piece) in self.exact_pieces.iter().enumerate() {
            let last = p + 1 == pieces;
            let mut end = piece.transfer(state(p));
            if !last {
                let next = state(p + 1);
                for (e, n) in end.iter_mut().zip(next) {
                    *e = *e - n;
                }
                if let Some(j) = self.obstacle_at_point[p + 1] {
                    // m'⁺ = m'⁻ − λ1, m⁺ = m⁻ + λ2 (as in `solve_pattern`).
                    for (d, jump_row, sign) in JUMPS {
                        let g = self.thresholds[j][d];
                        let force = match pattern[2 * j + d] {
                            Pattern::Stuck => x[Self::column(p + 1, d)],
                            Pattern::Positive => g.into(),
                            Pattern::Negative => (-g).into(),
                        };
                        end[jump_row] = end[jump_row] + force.times(sign);
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

    /// The states and forces of a solution `x` of the system of `pattern`.
    fn pattern_solution(&self, pattern: &[Pattern], x: &[f64]) -> PatternSolution {
        let pieces = self.pieces.len();
        let column = Self::column;
        let stuck = |p: usize, d: usize| {
            self.obstacle_at_point[p].is_some_and(|j| pattern[2 * j + d] == Pattern::Stuck)
        };
        let start: Vec<[f64; 4]> = (0..pieces)
            .map(|p| {
                let value = |c: usize| {
                    if c < 2 && (p == 0 || stuck(p, c)) {
                        0.0
                    } else {
                        x[column(p, c)]
                    }
                };
                [value(0), value(1), value(2), value(3)]
            })
            .collect();
        let end = self
            .pieces
            .iter()
            .zip(&start)
            .map(|(piece, &y)| piece.transfer(y))
            .collect();
        let lambda = pattern
            .iter()
            .enumerate()
            .map(|(i, state)| {
                let (j, d) = (i / 2, i % 2);
                match state {
                    Pattern::Stuck => x[column(self.point_of_obstacle[j], d)],
                    Pattern::Positive => self.thresholds[j][d],
                    Pattern::Negative => -self.thresholds[j][d],
                }
            })
            .collect();
        let mut solution = PatternSolution {
            start,
            end,
            lambda,
            exact: None,
            largest_motion: [0.0; 2],
            largest_force: [0.0; 2],
        };
        solution.largest_motion = [0, 1].map(|d| {
            self.pieces
                .iter()
                .enumerate()
                .fold(0.0f64, |m, (p, piece)| {
                    m.max(piece.magnitude(
                        self.point_values(&solution, p),
                        self.point_values(&solution, p + 1),
                        d,
                    ))
                })
        });
        // λ1 is a jump of m', λ2 a jump of m.
        solution.largest_force = [3, 2].map(|c| {
            solution
                .start
                .iter()
                .chain(&solution.end)
                .fold(0.0f64, |m, y| m.max(y[c].abs()))
        });
        solution
    }

    /// (u, u') at special point p (the far support is clamped).
    pub(super) fn point_values(&self, solution: &PatternSolution, p: usize) -> [f64; 2] {
        solution.start.get(p).map_or([0.0, 0.0], |y| [y[0], y[1]])
    }

    /// What rounding can resolve at friction DOF i: (motion, force) below which a value is
    /// indistinguishable from zero, resp. a force from its threshold. After elimination alone:
    /// 64 ulps of the values around the DOF (the adjacent pieces' own values of its kind, the
    /// shear or moment on both sides). After refinement: a few hundred double-double ulps of
    /// them, or four times the refinement's last correction where that is larger.
    pub(super) fn resolution(&self, solution: &PatternSolution, i: usize) -> (f64, f64) {
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

    /// The value c_i of friction DOF i.
    pub(super) fn friction_value(&self, solution: &PatternSolution, i: usize) -> f64 {
        let p = self.point_of_obstacle[i / 2];
        solution.start[p][i % 2]
    }

    /// The pattern each DOF should have given this solution (the same when consistent).
    pub(super) fn wanted(
        &self,
        solution: &PatternSolution,
        pattern: &[Pattern],
        i: usize,
    ) -> Pattern {
        // The resolution is asked for only when the value itself does not settle it.
        let g = self.thresholds[i / 2][i % 2];
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
            moving => {
                let sign = if moving == Pattern::Positive {
                    1.0
                } else {
                    -1.0
                };
                let c = self.friction_value(solution, i);
                if sign * c >= 0.0 || sign * c >= -self.resolution(solution, i).0 {
                    moving
                } else if sign * (sign * g + self.reversal_stiffness(i) * c) < -g {
                    // Semismooth Newton's prediction λ + σc: a large reversal goes straight to
                    // the other bound.
                    if moving == Pattern::Positive {
                        Pattern::Negative
                    } else {
                        Pattern::Positive
                    }
                } else {
                    Pattern::Stuck
                }
            }
        }
    }
}
