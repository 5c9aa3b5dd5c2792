//! The multiple-shooting system on the special points (the "Multiple shooting" of the module
//! `condensed`): the unknowns (the state at the start of every piece, the reactions of stuck
//! DOFs), the banded matrix of a friction pattern — each piece's exact transfer, the jumps
//! (3)–(6) at the obstacles, the clamped ends — and one banded solve per pattern. Refinement
//! is in `refinement`, what a solve says about each DOF in `decisions`.

pub(super) use super::pattern::Pattern;
use super::scaling::{ExactPiece, Piece, Scales};
use super::{CondensedFailure, SolveCounts};
use crate::fem::Mesh;
use crate::linalg::banded_lu::{BandedSystem, times_power_of_two};
use crate::linalg::double_double::DoubleDouble;
use crate::model::Problem;
use std::cell::Cell;

/// The band of the multiple-shooting system: piece p's rows 4p..4p+3 (u, u', m, m') reach
/// the columns 4p − 2 ..= 4p + 1 of its start point (u and u' rows all four, m and m' rows only
/// m, m') and 4p + 2 ..= 4p + 5 of its end point (u, u' rows only a, b; the m row b and m; the
/// m' row a and m'), which bounds the band by (3, 3).
pub(super) const BAND_LOWER: usize = 3;
pub(super) const BAND_UPPER: usize = 3;

thread_local! {
    /// The search's system of the last solve on this thread ([`BandedSystem::keep`]): its
    /// memory (2.6 MB at 4000 obstacles) is faulted in only once, and while it is held the
    /// allocator does not trim its heap between solves, so the next solve finds the rest of
    /// its working set in place too (clustered and random at k = 4000: 2112 → 1172 page
    /// faults per solve in a loop of solves, ties 1970 → 647).
    /// At most one system per thread, as large as the largest solved on it.
    static KEPT: Cell<Option<BandedSystem>> = const { Cell::new(None) };
}

impl BandedSystem {
    /// A system of no unknowns in the multiple-shooting band, holding no memory.
    pub(super) fn empty() -> BandedSystem {
        BandedSystem::new(0, BAND_LOWER, BAND_UPPER)
    }

    /// The system the last solve on this thread kept, or an empty one.
    pub(super) fn kept() -> BandedSystem {
        KEPT.take().unwrap_or_else(BandedSystem::empty)
    }

    /// Keeps this system's memory for the next solve on this thread (its values are stale).
    pub(super) fn keep(&mut self) {
        KEPT.set(Some(std::mem::replace(self, BandedSystem::empty())));
    }
}

/// How accurately a pattern is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Accuracy {
    /// Elimination alone: each value to rounding of the largest ones.
    Plain,
    /// The pattern of the previous solve again (the system is unchanged), refined from its
    /// factors with the exact piece relations: each value to its own last bits.
    RefineLast,
    /// As [`Accuracy::RefineLast`], but refinement stops as soon as every friction DOF's
    /// decision is settled (its motion, or its force's excess over the threshold, beyond four
    /// times its last correction): enough to choose the next pattern, not to answer with.
    RefineForDecisions,
    /// As [`Accuracy::RefineForDecisions`], and on until the largest correction is the noise
    /// of the residual: what the monotone search steps on.
    RefineForSearch,
}

/// The dimensionless multiple-shooting system on the special points: the pieces (in f64 and
/// in double-double), where the obstacles sit and their thresholds.
pub(super) struct ShootingSystem {
    pub(super) pieces: Vec<Piece>,
    /// The same pieces' coefficients in double-double, for the refinement's residual.
    pub(super) exact_pieces: Vec<ExactPiece>,
    /// For every special point 1..P−1: the obstacle there, if any.
    pub(super) obstacle_at_point: Vec<Option<usize>>,
    /// For every obstacle: its special point.
    pub(super) point_of_obstacle: Vec<usize>,
    /// Dimensionless thresholds (g1, g2) per obstacle.
    pub(super) thresholds: Vec<[f64; 2]>,
    /// σ / diagonal stiffness in the reversal prediction of the current Newton phase.
    pub(super) reversal_fraction: std::cell::Cell<f64>,
    /// The work done so far.
    pub(super) counts: std::cell::Cell<SolveCounts>,
    /// Refine every interior-point step's solve with the exact relations
    /// (`mixed_refinement`): set for the search's second guess only.
    pub(super) refined_steps: std::cell::Cell<bool>,
    /// Per friction DOF: its diagonal stiffness ([`ShootingSystem::diagonal_stiffness`]).
    pub(super) friction_stiffness: Vec<f64>,
}

/// The states of one solve of a fixed pattern.
#[derive(Clone)]
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
#[derive(Clone)]
pub(super) struct ExactValues {
    /// λ_i (±g for a moving DOF).
    pub(super) force: Vec<DoubleDouble>,
    /// |last correction| of the motion of DOF i (0 when stuck: it is zero by construction):
    /// the refinement's own estimate of the error left.
    pub(super) motion_error: Vec<f64>,
    /// |last correction| of the force of DOF i (0 when moving: it is ±g exactly).
    pub(super) force_error: Vec<f64>,
}

/// The jumps at an obstacle, (DOF kind, transfer row, sign): m'⁺ = m'⁻ − λ1 (row 3),
/// m⁺ = m⁻ + λ2 (row 2).
pub(super) const JUMPS: [(usize, usize, f64); 2] = [(0, 3, -1.0), (1, 2, 1.0)];

/// The diagonal stiffness at point p for a deflection (kind 0: 12EJ/L³ per adjacent piece)
/// or a slope (kind 1: 4EJ/L).
fn diagonal_stiffness(pieces: &[Piece], p: usize, kind: usize) -> f64 {
    [p - 1, p]
        .iter()
        .map(|&q| {
            let piece = &pieces[q];
            if kind == 0 {
                12.0 * piece.stiffness / piece.length.powi(3)
            } else {
                4.0 * piece.stiffness / piece.length
            }
        })
        .sum()
}

impl ShootingSystem {
    /// The diagonal stiffness at friction DOF i: 12EJ/L³ per adjacent piece for a deflection,
    /// 4EJ/L for a slope.
    pub(super) fn diagonal_stiffness(&self, i: usize) -> f64 {
        self.friction_stiffness[i]
    }

    /// The system of `problem` on `mesh` in the units of `scales`, with σ / diagonal stiffness
    /// `reversal_fraction` in the reversal prediction until the search sets another.
    pub(super) fn new(
        problem: &Problem,
        mesh: &Mesh,
        scales: &Scales,
        reversal_fraction: f64,
    ) -> ShootingSystem {
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
                Piece::new(
                    length(b - a),
                    times_power_of_two(piece.bending_stiffness, -scales.stiffness),
                    load(problem.load_at(a)),
                    load(problem.load_at(b)),
                )
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
        let friction_stiffness = (0..2 * point_of_obstacle.len())
            .map(|i| diagonal_stiffness(&pieces, point_of_obstacle[i / 2], i % 2))
            .collect();
        ShootingSystem {
            pieces,
            exact_pieces,
            obstacle_at_point,
            point_of_obstacle,
            thresholds,
            reversal_fraction: std::cell::Cell::new(reversal_fraction),
            counts: std::cell::Cell::new(SolveCounts::default()),
            refined_steps: std::cell::Cell::new(false),
            friction_stiffness,
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
    /// [`BAND_UPPER`]); the matrix is [`ShootingSystem::assemble_matrix`]'s.
    pub(super) fn solve_pattern(
        &self,
        pattern: &[Pattern],
        accuracy: Accuracy,
        banded: &mut BandedSystem,
    ) -> Result<PatternSolution, CondensedFailure> {
        if accuracy != Accuracy::Plain {
            self.count(|c| c.refinements += 1);
            return self.refine_last(pattern, banded, accuracy);
        }
        self.count(|c| {
            c.pattern_solves += 1;
            c.factorizations += 1;
        });
        let pieces = self.pieces.len();
        banded.reset(self.unknowns());
        self.assemble_matrix(
            pattern,
            |p| self.pieces[p].transfer_matrix(),
            |v| v,
            |row, column, value| banded.add(row, column, value),
        );
        for (p, piece) in self.pieces.iter().enumerate() {
            let q = piece.load_terms();
            let rows = if p + 1 == pieces { 2 } else { 4 };
            for (r, q) in q.iter().enumerate().take(rows) {
                banded.add_rhs(4 * p + r, -q);
            }
            // A moving DOF's known force ±g enters its jump row's right-hand side.
            if p + 1 < pieces
                && let Some(j) = self.obstacle_at_point[p + 1]
            {
                for (d, jump_row, sign) in JUMPS {
                    let g = self.thresholds[j][d];
                    match pattern[2 * j + d] {
                        Pattern::Stuck => {}
                        Pattern::Positive => banded.add_rhs(4 * p + jump_row, -sign * g),
                        Pattern::Negative => banded.add_rhs(4 * p + jump_row, sign * g),
                    }
                }
            }
        }
        let x = banded
            .solve_unrefined()
            .map_err(|e| CondensedFailure::Singular { column: e.column })?;
        Ok(self.pattern_solution(pattern, &x))
    }

    /// Adds to the work counts.
    pub(super) fn count(&self, add: impl FnOnce(&mut SolveCounts)) {
        let mut counts = self.counts.get();
        add(&mut counts);
        self.counts.set(counts);
    }

    /// Unknowns (and rows) of the multiple-shooting system: the four state components at
    /// every point between two pieces, and m, m' at the left end ([`ShootingSystem::column`]).
    pub(super) fn unknowns(&self) -> usize {
        4 * self.pieces.len() - 2
    }

    /// Column of component c (0..4) of the state at point p; point 0 has only m, m'.
    pub(super) fn column(p: usize, c: usize) -> usize {
        if p == 0 { c - 2 } else { 4 * p - 2 + c }
    }

    /// The matrix of `pattern`'s system (the layout of `solve_pattern`): `add(row, column,
    /// value)` for every entry, with `transfer(p)` piece p's Φ and `constant` the entry ±1.
    /// Rows: per piece its four transfer rows (two for the last piece: the far end is
    /// clamped), Φ y_p − y_{p+1} + jump; a known zero (u, u' at the left support, a stuck
    /// DOF) has no column, and a stuck DOF's reaction takes the column of its value.
    pub(super) fn assemble_matrix<T: Copy>(
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

    /// The states and forces of a solution `x` of the system of `pattern`.
    pub(super) fn pattern_solution(&self, pattern: &[Pattern], x: &[f64]) -> PatternSolution {
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

    /// The value c_i of friction DOF i.
    pub(super) fn friction_value(&self, solution: &PatternSolution, i: usize) -> f64 {
        let p = self.point_of_obstacle[i / 2];
        solution.start[p][i % 2]
    }
}
