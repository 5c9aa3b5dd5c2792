//! `condensed`: the exact solution of (38) from the exact relations of every piece between
//! special points (supports, obstacles, segment ends), condensed onto the friction DOFs, with
//! the friction solved in the primal. It is the method meant to grade the others.
//!
//! **Pieces.** On a piece between consecutive special points E·J is constant and f linear, so
//! the beam equation (EJ u'')'' = f has the exact transfer y(b) = Φ y(a) + q for the state
//! y = (u, u', m, m') with m = EJ u'' (the force formulation of DESIGN.md fact 3, but applied
//! to one piece at a time). Because the finite-element solution is exact at the nodes
//! (DESIGN.md fact 1), the states at the special points determine the discrete solution of (38)
//! on any mesh.
//!
//! **Multiple shooting instead of single shooting.** The unknowns are the state at the start of
//! every piece and the reactions of the stuck friction DOFs; the equations are each piece's
//! transfer, the jumps at the obstacles (m' jumps by −λ1, m by +λ2: conditions (3)–(6)), the
//! clamped ends and c_i = 0 for stuck DOFs. That is a banded system with about 4 unknowns per
//! special point, solved by Gaussian elimination with row equilibration and partial pivoting
//! (`linalg::banded_lu`). Each equation involves one piece only, so no rounding is carried from
//! one end of the beam to the other (the failure of `flexibility`, issue 10 item 1–2); a piece
//! 1e-9·l long is an almost-identity transfer, not a stiffness of 1e27 added to one of 1 (which
//! is what makes the assembled stiffness lose the rigid motion of a short piece between two
//! sliding obstacles); and the forces of stuck DOFs are unknowns of the system, not differences
//! of large displacements times large stiffnesses. The problem is first made dimensionless by
//! powers of two (length, stiffness, load), which is exact, so a beam of 1 mm or 1 km and loads
//! of 1e-300 or 1e300 run the same arithmetic.
//!
//! **Friction.** (38) is min ½cᵀAc − bᵀc + Σ g_i|c_i|; each friction DOF is stuck (c_i = 0,
//! |λ_i| ≤ g_i) or moves (λ_i = g_i·sign c_i). Given the pattern of states, one banded solve
//! gives c and the stuck λ. The pattern is found by semismooth Newton (the primal–dual active
//! set method): every inconsistent DOF changes at once — a stuck force above its threshold
//! starts to move its way, a moving DOF that reverses is held (or, by the prediction λ + σc
//! with σ a fraction of its diagonal stiffness, sent to the other bound). Two variants of σ
//! are tried in turn, each abandoned on a repeated pattern or when it stops improving; then a
//! monotone search takes over that can neither cycle nor stall: an exact line search on the
//! convex, piecewise quadratic J between the current point and the optimum of the next
//! pattern, adding stuck DOFs only at the optimum of a pattern, and only the worst one when
//! adding all of them gives no descent (feature-sign search). The answer is the solve of the
//! final pattern, confirmed by a refined solve, so it satisfies (38) up to the rounding of
//! that one solve.
//!
//! **States.** A decision is made only where the number is computed accurately: the motion at
//! the DOF itself and the force at the DOF itself. When |motion| is within what rounding can
//! resolve locally (a few ulps of the adjacent pieces' own magnitudes), or |force| is within
//! rounding of the threshold, the DOF is reported [`FrictionState::AtThreshold`] rather than a
//! coin toss.
//!
//! **Nodes.** Every node inside a piece is evaluated from that piece's end values (Hermite
//! cubic) plus the piece's exact clamped–clamped response to its linear load: O(n) in total,
//! and the error does not grow with n.

use std::collections::HashSet;

use super::{
    Method, MethodDetails, MethodOutput, SolveError, SolveErrorKind, SolveOptions, Stopwatch,
    Timing, Warning, WarningCode,
};
use crate::fem::{Mesh, NodalField};
use crate::linalg::banded_lu::{BandedSystem, times_power_of_two};
use crate::model::Problem;

/// The friction state of one DOF (value or slope) of an obstacle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FrictionState {
    /// c = 0 and |λ| < g by more than rounding.
    Stuck,
    /// c ≠ 0 by more than rounding, λ = g·sign c.
    Moves,
    /// c = 0 within rounding and |λ| = g within rounding: both descriptions fit.
    AtThreshold,
}

/// The result of the condensed method, in SI units.
#[derive(Debug, Clone, PartialEq)]
pub struct CondensedSolution {
    /// u and u' at every mesh node.
    pub field: NodalField,
    /// (force [N], moment [N m]) per obstacle, in the convention A c = b − Bᵀλ.
    pub friction: Vec<[f64; 2]>,
    /// (sliding, swivel) state per obstacle.
    pub states: Vec<[FrictionState; 2]>,
    /// Linear solves (one per active-set step).
    pub solves: usize,
    /// Did the active-set iteration end with a consistent pattern?
    pub converged: bool,
}

/// Why the condensed method has no solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CondensedFailure {
    /// The banded system was singular to working precision in this column.
    Singular { column: usize },
    /// The caller's `keep_going` said stop (a newer request replaced this solve).
    Stopped,
}

/// Scale factors: every scale is a power of two, so scaling is exact.
#[derive(Debug, Clone, Copy)]
struct Scales {
    /// log2 of the length scale.
    length: i32,
    /// log2 of the stiffness scale.
    stiffness: i32,
    /// log2 of the load scale.
    load: i32,
}

impl Scales {
    fn of(problem: &Problem) -> Scales {
        let exponent = |v: f64| v.log2().round() as i32;
        let (smallest, largest) =
            problem
                .stiffness
                .iter()
                .fold((f64::INFINITY, 0.0f64), |(lo, hi), piece| {
                    (
                        lo.min(piece.bending_stiffness),
                        hi.max(piece.bending_stiffness),
                    )
                });
        let load = problem.load.f0.abs().max(problem.load.f1.abs());
        Scales {
            length: exponent(problem.length),
            // The geometric mean keeps both extremes of a large contrast in range.
            stiffness: (0.5 * (smallest.log2() + largest.log2())).round() as i32,
            load: if load > 0.0 { exponent(load) } else { 0 },
        }
    }

    /// u = ũ·2^this.
    fn deflection(&self) -> i32 {
        self.load + 4 * self.length - self.stiffness
    }
    /// u' = ũ'·2^this.
    fn slope(&self) -> i32 {
        self.load + 3 * self.length - self.stiffness
    }
    /// λ1 = λ̃1·2^this.
    fn force(&self) -> i32 {
        self.load + self.length
    }
    /// λ2 = λ̃2·2^this.
    fn moment(&self) -> i32 {
        self.load + 2 * self.length
    }
}

/// One piece in dimensionless units.
#[derive(Debug, Clone, Copy)]
struct Piece {
    length: f64,
    stiffness: f64,
    load_start: f64,
    load_end: f64,
}

impl Piece {
    /// The state at the end of the piece from the state at its start (exact).
    fn transfer(&self, y: [f64; 4]) -> [f64; 4] {
        let [u, du, m, v] = y;
        let (t, e) = (self.length, self.stiffness);
        let q = self.load_terms();
        [
            u + t * du + t * t * (m / 2.0 + t * v / 6.0) / e + q[0],
            du + t * (m + t * v / 2.0) / e + q[1],
            m + t * v + q[2],
            v + q[3],
        ]
    }

    /// The state at the end of the piece for a zero start state: the load's own contribution
    /// (u, u', m, m').
    fn load_terms(&self) -> [f64; 4] {
        let (t, e, fa, fb) = (self.length, self.stiffness, self.load_start, self.load_end);
        [
            t * t * t * t * (4.0 * fa + fb) / (120.0 * e),
            t * t * t * (3.0 * fa + fb) / (24.0 * e),
            t * t * (2.0 * fa + fb) / 6.0,
            t * (fa + fb) / 2.0,
        ]
    }

    /// d(end state)/d(start state): row r of Φ.
    fn transfer_matrix(&self) -> [[f64; 4]; 4] {
        let (t, e) = (self.length, self.stiffness);
        [
            [1.0, t, t * t / (2.0 * e), t * t * t / (6.0 * e)],
            [0.0, 1.0, t / e, t * t / (2.0 * e)],
            [0.0, 0.0, 1.0, t],
            [0.0, 0.0, 0.0, 1.0],
        ]
    }

    /// Size of the deflections this piece carries: its end values and its own clamped–clamped
    /// response to the load. Rounding of anything computed from the piece is a few ulps of it.
    fn magnitude(&self, start: [f64; 2], end: [f64; 2]) -> f64 {
        let own = self.length.powi(4) * self.load_start.abs().max(self.load_end.abs())
            / (384.0 * self.stiffness);
        start[0]
            .abs()
            .max(end[0].abs())
            .max(self.length * start[1].abs())
            .max(self.length * end[1].abs())
            .max(own)
    }
}

/// How a friction DOF enters the linear system.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Pattern {
    Stuck,
    /// Moves with λ = +g.
    Positive,
    /// Moves with λ = −g.
    Negative,
}

/// The dimensionless problem on the special points.
struct Condensed {
    pieces: Vec<Piece>,
    /// For every special point 1..P−1: the obstacle there, if any.
    obstacle_at_point: Vec<Option<usize>>,
    /// For every obstacle: its special point.
    point_of_obstacle: Vec<usize>,
    /// Dimensionless thresholds (g1, g2) per obstacle.
    thresholds: Vec<[f64; 2]>,
    /// σ / diagonal stiffness in the reversal prediction of the current Newton phase.
    reversal_fraction: std::cell::Cell<f64>,
}

/// The states of one solve of a fixed pattern.
struct PatternSolution {
    /// State just right of every special point 0..P−1 (u, u', m, m').
    start: Vec<[f64; 4]>,
    /// State at the end of every piece (just left of point p + 1).
    end: Vec<[f64; 4]>,
    /// λ per friction DOF (given for moving DOFs, solved for stuck ones).
    lambda: Vec<f64>,
}

impl Condensed {
    fn new(problem: &Problem, mesh: &Mesh, scales: &Scales) -> Condensed {
        let length = |x: f64| times_power_of_two(x, -scales.length);
        let load = |f: f64| times_power_of_two(f, -scales.load);
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
            obstacle_at_point,
            point_of_obstacle,
            thresholds,
            reversal_fraction: std::cell::Cell::new(NEWTON_REVERSAL_FRACTIONS[0]),
        }
    }

    /// Solves the linear problem of one pattern: stuck DOFs are held at zero with an unknown
    /// reaction, moving DOFs carry the force ±g.
    fn solve_pattern(
        &self,
        pattern: &[Pattern],
        refined: bool,
        system: &mut BandedSystem,
    ) -> Result<PatternSolution, CondensedFailure> {
        let pieces = self.pieces.len();
        // Unknown numbering: state of piece p at `state_column[p]`; the reactions of the
        // stuck DOFs at point p (1 ≤ p < P) just before it.
        let mut state_column = vec![0; pieces];
        let mut reaction_column = vec![[None; 2]; pieces + 1];
        let mut next = 0;
        for p in 0..pieces {
            if let Some(j) = self.obstacle_at_point[p] {
                for d in 0..2 {
                    if pattern[2 * j + d] == Pattern::Stuck {
                        reaction_column[p][d] = Some(next);
                        next += 1;
                    }
                }
            }
            state_column[p] = next;
            next += 4;
        }
        let size = next;
        // Rows follow the columns: the two clamping rows, then per piece its four transfer
        // rows and the rows c = 0 of the stuck DOFs at its end (band: BAND_LOWER, BAND_UPPER).
        system.reset(size);
        system.add(0, 0, 1.0);
        system.add(1, 1, 1.0);
        let mut row = 2;
        for (p, piece) in self.pieces.iter().enumerate() {
            let phi = piece.transfer_matrix();
            let q = piece.load_terms();
            let own = state_column[p];
            let last = p + 1 == pieces;
            let rows = if last { 2 } else { 4 };
            for r in 0..rows {
                for (c, &value) in phi[r].iter().enumerate() {
                    if value != 0.0 {
                        system.add(row + r, own + c, value);
                    }
                }
                system.add_rhs(row + r, -q[r]);
                if !last {
                    system.add(row + r, state_column[p + 1] + r, -1.0);
                }
            }
            if !last && let Some(j) = self.obstacle_at_point[p + 1] {
                // Jumps: m⁺ = m⁻ + λ2, m'⁺ = m'⁻ − λ1.
                for (d, jump_row, sign) in [(0, 3, -1.0), (1, 2, 1.0)] {
                    match pattern[2 * j + d] {
                        Pattern::Stuck => {
                            let column = reaction_column[p + 1][d].expect("stuck DOF");
                            system.add(row + jump_row, column, sign);
                        }
                        Pattern::Positive => {
                            system.add_rhs(row + jump_row, -sign * self.thresholds[j][d])
                        }
                        Pattern::Negative => {
                            system.add_rhs(row + jump_row, sign * self.thresholds[j][d])
                        }
                    }
                }
            }
            row += rows;
            if !last {
                for d in 0..2 {
                    if reaction_column[p + 1][d].is_some() {
                        system.add(row, state_column[p + 1] + d, 1.0);
                        row += 1;
                    }
                }
            }
        }
        debug_assert_eq!(row, size);
        let x = if refined {
            system.solve()
        } else {
            system.solve_unrefined()
        }
        .map_err(|e| CondensedFailure::Singular { column: e.column })?;

        let mut start: Vec<[f64; 4]> = state_column
            .iter()
            .map(|&c| [x[c], x[c + 1], x[c + 2], x[c + 3]])
            .collect();
        // A stuck DOF is zero by its own equation; do not let a rounding residue through.
        for (p, reactions) in reaction_column.iter().enumerate() {
            for d in 0..2 {
                if reactions[d].is_some() {
                    start[p][d] = 0.0;
                }
            }
        }
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
                    Pattern::Stuck => {
                        x[reaction_column[self.point_of_obstacle[j]][d]
                            .expect("stuck DOF has a reaction")]
                    }
                    Pattern::Positive => self.thresholds[j][d],
                    Pattern::Negative => -self.thresholds[j][d],
                }
            })
            .collect();
        Ok(PatternSolution { start, end, lambda })
    }

    /// (u, u') at special point p (the far support is clamped).
    fn point_values(&self, solution: &PatternSolution, p: usize) -> [f64; 2] {
        solution.start.get(p).map_or([0.0, 0.0], |y| [y[0], y[1]])
    }

    /// What rounding can resolve at friction DOF i: (motion, force) below which a value is
    /// indistinguishable from zero, resp. a force from its threshold.
    fn resolution(&self, solution: &PatternSolution, i: usize) -> (f64, f64) {
        const ULPS: f64 = 64.0 * f64::EPSILON;
        let (j, d) = (i / 2, i % 2);
        let p = self.point_of_obstacle[j];
        let [left, right] = [p - 1, p].map(|q| {
            let piece = &self.pieces[q];
            let magnitude = piece.magnitude(
                self.point_values(solution, q),
                self.point_values(solution, q + 1),
            );
            // A slope is resolved to the deflection magnitude over the piece length.
            if d == 0 {
                magnitude
            } else {
                magnitude / piece.length
            }
        });
        let motion = ULPS * left.min(right);
        // m' for the force, m for the moment, on both sides of the obstacle.
        let component = if d == 0 { 3 } else { 2 };
        let force = ULPS
            * solution.end[p - 1][component]
                .abs()
                .max(solution.start[p][component].abs());
        (motion, force)
    }

    /// The value c_i of friction DOF i.
    fn friction_value(&self, solution: &PatternSolution, i: usize) -> f64 {
        let p = self.point_of_obstacle[i / 2];
        solution.start[p][i % 2]
    }

    /// The pattern each DOF should have given this solution (the same when consistent).
    fn wanted(&self, solution: &PatternSolution, pattern: &[Pattern], i: usize) -> Pattern {
        let (motion_noise, force_noise) = self.resolution(solution, i);
        let g = self.thresholds[i / 2][i % 2];
        match pattern[i] {
            Pattern::Stuck => {
                let l = solution.lambda[i];
                if l.abs() > g + force_noise {
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
                if sign * c >= -motion_noise {
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

    /// (u, u') at every interior special point 1..P−1, two per point.
    fn point_dofs(&self, solution: &PatternSolution) -> Vec<f64> {
        solution.start[1..]
            .iter()
            .flat_map(|y| [y[0], y[1]])
            .collect()
    }

    /// The threshold of interior DOF q (zero at the ends of segments: no friction there).
    fn dof_threshold(&self, q: usize) -> f64 {
        self.obstacle_at_point[q / 2 + 1].map_or(0.0, |j| self.thresholds[j][q % 2])
    }

    /// b − K c on the interior DOFs, piece by piece with the exact piece stiffness.
    fn residual(&self, c: &[f64]) -> Vec<f64> {
        let mut r = vec![0.0; c.len()];
        let points = self.pieces.len();
        for (p, piece) in self.pieces.iter().enumerate() {
            let (t, e) = (piece.length, piece.stiffness);
            let value = |point: usize, d: usize| {
                if point == 0 || point == points {
                    0.0
                } else {
                    c[2 * (point - 1) + d]
                }
            };
            let v = [value(p, 0), value(p, 1), value(p + 1, 0), value(p + 1, 1)];
            let k = e / (t * t * t);
            // The Hermite element on the whole piece (exact at its ends).
            let s = 6.0 * t * k;
            let stiffness = [
                [12.0 * k, s, -12.0 * k, s],
                [s, 4.0 * t * t * k, -s, 2.0 * t * t * k],
                [-12.0 * k, -s, 12.0 * k, -s],
                [s, 2.0 * t * t * k, -s, 4.0 * t * t * k],
            ];
            let (fa, fb) = (piece.load_start, piece.load_end);
            let load = [
                t * (7.0 * fa + 3.0 * fb) / 20.0,
                t * t * (3.0 * fa + 2.0 * fb) / 60.0,
                t * (3.0 * fa + 7.0 * fb) / 20.0,
                -t * t * (2.0 * fa + 3.0 * fb) / 60.0,
            ];
            for (row, point) in [(0, p), (1, p), (2, p + 1), (3, p + 1)] {
                if point == 0 || point == points {
                    continue;
                }
                let kv: f64 = stiffness[row].iter().zip(&v).map(|(a, b)| a * b).sum();
                r[2 * (point - 1) + row % 2] += load[row] - kv;
            }
        }
        r
    }

    /// dᵀ K d = Σ over pieces of EJ/L·(12 s² + (Δu')²), s = (u_a − u_b)/L + (u'_a + u'_b)/2:
    /// a sum of non-negative terms.
    fn curvature(&self, d: &[f64]) -> f64 {
        let points = self.pieces.len();
        let value = |point: usize, k: usize| {
            if point == 0 || point == points {
                0.0
            } else {
                d[2 * (point - 1) + k]
            }
        };
        self.pieces
            .iter()
            .enumerate()
            .map(|(p, piece)| {
                let (ua, sa, ub, sb) = (value(p, 0), value(p, 1), value(p + 1, 0), value(p + 1, 1));
                let shear = (ua - ub) / piece.length + 0.5 * (sa + sb);
                piece.stiffness / piece.length * (12.0 * shear * shear + (sb - sa) * (sb - sa))
            })
            .sum()
    }

    /// Exact minimisation of J(c + t d), d = target − c, over t ∈ [0, 1]: J is convex and
    /// piecewise quadratic along the segment, with kinks where a friction DOF crosses zero.
    /// Returns the new point (DOFs that stop at their kink set to exactly zero) and whether
    /// it is the target itself.
    fn line_search(&self, c: &[f64], target: &[f64]) -> (Vec<f64>, bool) {
        let d: Vec<f64> = target.iter().zip(c).map(|(t, c)| t - c).collect();
        let r = self.residual(c);
        let q = self.curvature(&d);
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
            slope -= r[i] * di;
            let g = self.dof_threshold(i);
            if di == 0.0 || g == 0.0 {
                continue;
            }
            let direction = if ci != 0.0 { sign(ci) } else { sign(di) };
            slope += g * direction * di;
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
                slope += q * (t - at) + jump;
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
            None => (target.to_vec(), true),
            Some((t, kink)) => {
                let t = t.clamp(0.0, 1.0);
                let mut next: Vec<f64> = c.iter().zip(&d).map(|(c, d)| c + t * d).collect();
                if let Some(i) = kink {
                    next[i] = 0.0;
                }
                // Every DOF whose kink lies at or before t has crossed or stopped at zero.
                for &(tk, i, _) in &kinks {
                    if tk == t {
                        next[i] = 0.0;
                    }
                }
                (next, false)
            }
        }
    }

    /// The pattern of a point: moving DOFs with their sign, zeros stuck.
    fn signs_of(&self, c: &[f64]) -> Vec<Pattern> {
        (0..2 * self.thresholds.len())
            .map(|i| {
                let v = c[2 * (self.point_of_obstacle[i / 2] - 1) + i % 2];
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

    /// σ of the semismooth Newton prediction λ + σc for a DOF that reverses: a fraction of
    /// its diagonal stiffness (12EJ/L³ per adjacent piece for a deflection, 4EJ/L for a slope).
    /// With σ = 0 a reversing DOF is first held stuck.
    fn reversal_stiffness(&self, i: usize) -> f64 {
        let p = self.point_of_obstacle[i / 2];
        let diagonal: f64 = [p - 1, p]
            .iter()
            .map(|&q| {
                let piece = &self.pieces[q];
                if i.is_multiple_of(2) {
                    12.0 * piece.stiffness / piece.length.powi(3)
                } else {
                    4.0 * piece.stiffness / piece.length
                }
            })
            .sum();
        self.reversal_fraction.get() * diagonal
    }

    fn state(&self, solution: &PatternSolution, pattern: &[Pattern], i: usize) -> FrictionState {
        let (motion_noise, force_noise) = self.resolution(solution, i);
        let g = self.thresholds[i / 2][i % 2];
        match pattern[i] {
            Pattern::Stuck if solution.lambda[i].abs() < g - force_noise => FrictionState::Stuck,
            Pattern::Stuck => FrictionState::AtThreshold,
            _ if self.friction_value(solution, i).abs() > motion_noise => FrictionState::Moves,
            _ => FrictionState::AtThreshold,
        }
    }
}

/// Most solves of one semismooth Newton phase.
const NEWTON_STEPS: usize = 40;
/// The Newton phases tried in turn before the monotone search, by σ / diagonal stiffness of
/// the reversal prediction. Measured on 128–4000 obstacles with random thresholds: 0.5 needs
/// 9–15 solves where 0 needs up to 300 (a front of reversals moving one obstacle per step),
/// and 0 needs 13 where 0.5 cycles (neighbours over-react to a jump).
const NEWTON_REVERSAL_FRACTIONS: [f64; 2] = [0.5, 0.0];
/// A Newton phase is abandoned when the number of inconsistent DOFs has not reached a new
/// low for this many solves.
const NEWTON_PATIENCE: usize = 6;

/// The band of the multiple-shooting system: a piece's first transfer row and its first
/// state column differ by 2, which bounds the band by (5, 4).
const BAND_LOWER: usize = 5;
const BAND_UPPER: usize = 4;

/// Solves (38) by the condensed method; see the module documentation.
pub fn solve_condensed(
    problem: &Problem,
    mesh: &Mesh,
) -> Result<CondensedSolution, CondensedFailure> {
    solve_condensed_while(problem, mesh, &mut || true)
}

/// [`solve_condensed`], asking `keep_going` before every linear solve (O(n + k) work each)
/// and stopping with [`CondensedFailure::Stopped`] when it says no.
pub fn solve_condensed_while(
    problem: &Problem,
    mesh: &Mesh,
    keep_going: &mut dyn FnMut() -> bool,
) -> Result<CondensedSolution, CondensedFailure> {
    solve_with_newton_phases(problem, mesh, &NEWTON_REVERSAL_FRACTIONS, keep_going)
}

/// [`solve_condensed_while`] with the given Newton phases (none: the monotone search alone).
fn solve_with_newton_phases(
    problem: &Problem,
    mesh: &Mesh,
    newton_phases: &[f64],
    keep_going: &mut dyn FnMut() -> bool,
) -> Result<CondensedSolution, CondensedFailure> {
    let scales = Scales::of(problem);
    let condensed = Condensed::new(problem, mesh, &scales);
    if let Some(&first) = newton_phases.first() {
        condensed.reversal_fraction.set(first);
    }
    let dofs = 2 * problem.obstacles.len();
    let mut pattern = vec![Pattern::Stuck; dofs];
    let limit = 4 * dofs + 64 + newton_phases.len() * NEWTON_STEPS;
    let mut solves = 0;
    // The iterate (u, u' at every interior special point), which only ever lowers J.
    let mut current: Option<Vec<f64>> = None;
    // After adding DOFs at an optimum: the pattern and the single worst DOF to fall back on.
    let mut fallback: Option<(Vec<Pattern>, usize, Pattern)> = None;
    // The pattern is searched with plain solves; once it is consistent, the refined solve
    // (each value accurate to its own size) confirms it or the search goes on refined.
    let mut refined = false;
    let mut system = BandedSystem::new(0, BAND_LOWER, BAND_UPPER);
    let mut newton_phase = !newton_phases.is_empty();
    let (mut phase, mut phase_start) = (0, 0);
    // The fewest inconsistent DOFs seen in this phase, and when.
    let mut fewest_changes = (usize::MAX, 0);
    let mut seen = HashSet::new();
    let (solution, converged) = loop {
        if !keep_going() {
            return Err(CondensedFailure::Stopped);
        }
        let solution = condensed.solve_pattern(&pattern, refined, &mut system)?;
        solves += 1;
        let changes: Vec<(usize, Pattern)> = (0..dofs)
            .filter_map(|i| {
                let wanted = condensed.wanted(&solution, &pattern, i);
                (wanted != pattern[i]).then_some((i, wanted))
            })
            .collect();
        if changes.is_empty() {
            if refined {
                break (solution, true);
            }
            refined = true;
            continue;
        }
        if solves >= limit {
            break (solution, false);
        }
        if newton_phase {
            // Plain semismooth Newton: every inconsistent DOF changes at once. Fast when it
            // works; on a repeated pattern or too many steps, restart the monotone search.
            seen.insert(pattern.clone());
            for &(i, wanted) in &changes {
                pattern[i] = wanted;
            }
            if changes.len() < fewest_changes.0 {
                fewest_changes = (changes.len(), solves);
            }
            let stalled = solves >= fewest_changes.1 + NEWTON_PATIENCE;
            if seen.contains(&pattern) || stalled || solves >= phase_start + NEWTON_STEPS {
                fewest_changes = (usize::MAX, solves);
                // Next Newton variant, or the monotone search; both from the start.
                phase += 1;
                phase_start = solves;
                seen.clear();
                pattern = vec![Pattern::Stuck; dofs];
                match newton_phases.get(phase) {
                    Some(&fraction) => condensed.reversal_fraction.set(fraction),
                    None => newton_phase = false,
                }
            }
            continue;
        }
        let candidate = condensed.point_dofs(&solution);
        let (c, full_step) = match current.take() {
            None => (candidate, true),
            Some(c) => {
                let (next, full) = condensed.line_search(&c, &candidate);
                if !full && next == c {
                    // No descent towards the optimum of the enlarged pattern.
                    match fallback.take() {
                        Some((base, i, moving))
                            if base.iter().zip(&pattern).any(|(a, b)| a != b) =>
                        {
                            // Several DOFs were freed at once: free only the worst one.
                            let mut single = base;
                            single[i] = moving;
                            if single != pattern {
                                pattern = single;
                                current = Some(c);
                                continue;
                            }
                            (candidate, true)
                        }
                        // Rounding decides the slope here: take the optimum as it is.
                        _ => (candidate, true),
                    }
                } else {
                    (next, full)
                }
            }
        };
        fallback = None;
        // At the optimum of the pattern (full step, every moving DOF with its sign): free the
        // stuck DOFs whose force exceeds the threshold (semismooth Newton / primal–dual active
        // set). Otherwise (the step stopped where a DOF reached zero): take the signs of the
        // new point, with its zeros stuck, and find that pattern's optimum first.
        let at_optimum = full_step && changes.iter().all(|&(i, _)| pattern[i] == Pattern::Stuck);
        if at_optimum {
            let base = pattern.clone();
            let mut worst: Option<(f64, usize, Pattern)> = None;
            for &(i, wanted) in &changes {
                pattern[i] = wanted;
                let l = solution.lambda[i].abs();
                let excess = (l - condensed.thresholds[i / 2][i % 2]) / l;
                if worst.is_none_or(|(e, _, _)| excess > e) {
                    worst = Some((excess, i, wanted));
                }
            }
            if changes.len() > 1
                && let Some((_, i, wanted)) = worst
            {
                fallback = Some((base, i, wanted));
            }
        } else {
            pattern = condensed.signs_of(&c);
        }
        current = Some(c);
    };

    let states: Vec<[FrictionState; 2]> = (0..problem.obstacles.len())
        .map(|j| {
            [
                condensed.state(&solution, &pattern, 2 * j),
                condensed.state(&solution, &pattern, 2 * j + 1),
            ]
        })
        .collect();
    let friction = problem
        .obstacles
        .iter()
        .enumerate()
        .map(|(j, o)| {
            let physical = |d: usize, threshold: f64, exponent: i32| match pattern[2 * j + d] {
                // Exactly the threshold: no round trip through the scaling.
                Pattern::Positive => threshold,
                Pattern::Negative => -threshold,
                Pattern::Stuck => {
                    let l = times_power_of_two(solution.lambda[2 * j + d], exponent);
                    l.clamp(-threshold, threshold)
                }
            };
            [
                physical(0, o.sliding_threshold, scales.force()),
                physical(1, o.swivel_threshold, scales.moment()),
            ]
        })
        .collect();
    let field = nodal_field(mesh, &condensed, &solution, &scales);
    Ok(CondensedSolution {
        field,
        friction,
        states,
        solves,
        converged,
    })
}

/// Every node from its own piece: Hermite interpolation of the piece's end values plus the
/// piece's exact clamped–clamped response to its linear load, in SI units.
fn nodal_field(
    mesh: &Mesh,
    condensed: &Condensed,
    solution: &PatternSolution,
    scales: &Scales,
) -> NodalField {
    let mut field = NodalField::zeros(mesh.nodes.len());
    let (u_exponent, slope_exponent) = (scales.deflection(), scales.slope());
    // 2^e as one factor when it is a normal number; else scale afterwards in steps.
    let factor = |e: i32| (-1000..=1000).contains(&e).then(|| 2f64.powi(e));
    let factors = factor(u_exponent).zip(factor(slope_exponent));
    let (u_factor, slope_factor) = factors.unwrap_or((1.0, 1.0));
    for (p, (mesh_piece, piece)) in mesh.pieces.iter().zip(&condensed.pieces).enumerate() {
        let [ua, sa] = condensed.point_values(solution, p);
        let [ub, sb] = condensed.point_values(solution, p + 1);
        let (first, last) = (mesh_piece.first_node, mesh_piece.last_node);
        let a = mesh.nodes[first];
        let to_local = 1.0 / (mesh.nodes[last] - a);
        let (t, e) = (piece.length, piece.stiffness);
        let (fa, fb) = (piece.load_start, piece.load_end);
        // The Hermite cubic of the end values, ua + ξ(c1 + ξ(c2 + ξ c3)), and the clamped–
        // clamped response P ξ²(1 − ξ)²(α + βξ) to the load f = fa(1 − ξ) + fb ξ.
        let rise = ub - ua;
        let (c1, c2, c3) = (
            t * sa,
            3.0 * rise - t * (2.0 * sa + sb),
            t * (sa + sb) - 2.0 * rise,
        );
        let bubble_scale = t * t * t * t / (120.0 * e);
        let (alpha, beta) = (3.0 * fa + 2.0 * fb, fb - fa);
        let slope_scale = slope_factor / t;
        field.deflection[first] = ua * u_factor;
        field.slope[first] = sa * slope_factor;
        let nodes = &mesh.nodes[first + 1..last];
        let deflection = &mut field.deflection[first + 1..last];
        let slope = &mut field.slope[first + 1..last];
        for ((x, u_out), s_out) in nodes.iter().zip(deflection).zip(slope) {
            let xi = (x - a) * to_local;
            let rest = 1.0 - xi;
            let load = alpha + beta * xi;
            let bubble = xi * xi * rest * rest;
            let u = ua + xi * (c1 + xi * (c2 + xi * c3)) + bubble_scale * bubble * load;
            let du = c1
                + xi * (2.0 * c2 + 3.0 * xi * c3)
                + bubble_scale * (2.0 * xi * rest * (1.0 - 2.0 * xi) * load + bubble * beta);
            *u_out = u * u_factor;
            *s_out = du * slope_scale;
        }
    }
    if factors.is_none() {
        for v in &mut field.deflection {
            *v = times_power_of_two(*v, u_exponent);
        }
        for v in &mut field.slope {
            *v = times_power_of_two(*v, slope_exponent);
        }
    }
    // The far support stays clamped (zeros); node 0 is the first node of piece 0, (0, 0).
    field
}

/// `solve` entry point: the condensed solution as the common [`MethodOutput`].
pub(super) fn solve(
    problem: &Problem,
    mesh: &Mesh,
    _options: &SolveOptions,
) -> Result<MethodOutput, SolveError> {
    let mut timing = Timing::default();
    let mut clock = Stopwatch::start();
    let solution = solve_condensed(problem, mesh).map_err(|failure| SolveError {
        method: Method::Condensed,
        kind: SolveErrorKind::Breakdown,
        reason: match failure {
            CondensedFailure::Singular { column } => format!(
                "the multiple-shooting system is singular to working precision (column \
                 {column})"
            ),
            CondensedFailure::Stopped => "stopped".to_string(),
        },
        suggestion: Method::Flexibility,
    })?;
    timing.dual_solve = clock.lap();
    let mut warnings = Vec::new();
    if !solution.converged {
        warnings.push(Warning::new(
            WarningCode::QpNotConverged,
            format!(
                "the active-set iteration stopped after {} solves with an inconsistent \
                 friction state",
                solution.solves
            ),
        ));
    }
    let moving = solution
        .states
        .iter()
        .map(|s| s.map(|state| state == FrictionState::Moves))
        .collect();
    Ok(MethodOutput {
        field: solution.field,
        lambda: solution.friction,
        moving,
        timing,
        warnings,
        details: MethodDetails {
            newton_iterations: Some(solution.solves),
            ..MethodDetails::default()
        },
        dual_condition: None,
        regularized_cases: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{LinearLoad, Obstacle, StiffnessPiece};

    /// `k` obstacles with thresholds around the fixed-end forces (every state occurs).
    fn crowded(k: usize, seed: u64) -> Problem {
        let mut state = seed;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let (load, h) = (1e5, 1.0 / (k + 1) as f64);
        let obstacles = (1..=k)
            .map(|j| Obstacle {
                x: (j as f64 + 0.8 * (next() - 0.5)) * h,
                sliding_threshold: 3.0 * load * h * next(),
                swivel_threshold: 0.2 * load * h * h * next(),
            })
            .collect();
        Problem {
            length: 1.0,
            stiffness: vec![StiffnessPiece {
                from: 0.0,
                to: 1.0,
                bending_stiffness: 2866.0,
            }],
            load: LinearLoad {
                f0: load,
                f1: -0.5 * load,
            },
            obstacles,
        }
    }

    #[test]
    fn the_monotone_search_alone_finds_the_same_solution() {
        for (k, seed) in [(5, 1), (40, 2), (200, 3)] {
            let problem = crowded(k, seed);
            let mesh = Mesh::new(&problem, 4 * (k + 1));
            let newton = solve_condensed(&problem, &mesh).unwrap();
            let monotone = solve_with_newton_phases(&problem, &mesh, &[], &mut || true).unwrap();
            assert!(newton.converged && monotone.converged, "k = {k}");
            assert_eq!(newton.states, monotone.states, "k = {k}");
            let scale = newton
                .field
                .deflection
                .iter()
                .fold(0.0f64, |m, u| m.max(u.abs()));
            for (a, b) in newton
                .field
                .deflection
                .iter()
                .zip(&monotone.field.deflection)
            {
                assert!((a - b).abs() <= 1e-13 * scale, "k = {k}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn each_newton_variant_first_gives_the_same_solution() {
        let problem = crowded(60, 7);
        let mesh = Mesh::new(&problem, 400);
        let reference = solve_condensed(&problem, &mesh).unwrap();
        for fraction in NEWTON_REVERSAL_FRACTIONS {
            let solution =
                solve_with_newton_phases(&problem, &mesh, &[fraction], &mut || true).unwrap();
            assert!(solution.converged);
            assert_eq!(solution.states, reference.states, "σ fraction {fraction}");
        }
    }
}
