//! Exact power-of-two scaling (length, stiffness, load) and the exact transfer of the state
//! (u, u', m, m') across one piece of constant E·J and linear load.

#![allow(clippy::needless_range_loop)]

use crate::linalg::double_double::DoubleDouble;
use crate::model::Problem;

/// Scale factors: every scale is a power of two, so scaling is exact.
#[derive(Debug, Clone, Copy)]
pub(super) struct Scales {
    /// log2 of the length scale.
    pub(super) length: i32,
    /// log2 of the stiffness scale.
    pub(super) stiffness: i32,
    /// log2 of the load scale.
    pub(super) load: i32,
}

impl Scales {
    pub(super) fn of(problem: &Problem) -> Scales {
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
    pub(super) fn deflection(&self) -> i32 {
        self.load + 4 * self.length - self.stiffness
    }
    /// u' = ũ'·2^this.
    pub(super) fn slope(&self) -> i32 {
        self.load + 3 * self.length - self.stiffness
    }
    /// λ1 = λ̃1·2^this.
    pub(super) fn force(&self) -> i32 {
        self.load + self.length
    }
    /// λ2 = λ̃2·2^this.
    pub(super) fn moment(&self) -> i32 {
        self.load + 2 * self.length
    }
}

/// One piece in dimensionless units, with what every pattern solve reads of it computed once
/// ([`Piece::new`]): a solve used to divide for them anew per piece, about fifteen divisions
/// per piece for its matrix, right-hand side and end states.
#[derive(Debug, Clone, Copy)]
pub(super) struct Piece {
    pub(super) length: f64,
    pub(super) stiffness: f64,
    pub(super) load_start: f64,
    pub(super) load_end: f64,
    /// t²/(2e), t³/(6e), t/e: the entries of Φ ([`Piece::transfer_matrix`]).
    flexibility: [f64; 3],
    /// [`Piece::load_terms`].
    load: [f64; 4],
}

impl Piece {
    /// The piece of length t, stiffness e and load from `load_start` to `load_end`.
    pub(super) fn new(length: f64, stiffness: f64, load_start: f64, load_end: f64) -> Piece {
        let (t, e, fa, fb) = (length, stiffness, load_start, load_end);
        Piece {
            length,
            stiffness,
            load_start,
            load_end,
            flexibility: [t * t / (2.0 * e), t * t * t / (6.0 * e), t / e],
            load: [
                t * t * t * t * (4.0 * fa + fb) / (120.0 * e),
                t * t * t * (3.0 * fa + fb) / (24.0 * e),
                t * t * (2.0 * fa + fb) / 6.0,
                t * (fa + fb) / 2.0,
            ],
        }
    }

    /// The state at the end of the piece from the state at its start (exact).
    pub(super) fn transfer(&self, y: [f64; 4]) -> [f64; 4] {
        let [u, du, m, v] = y;
        let (t, e) = (self.length, self.stiffness);
        let q = self.load;
        [
            u + t * du + t * t * (m / 2.0 + t * v / 6.0) / e + q[0],
            du + t * (m + t * v / 2.0) / e + q[1],
            m + t * v + q[2],
            v + q[3],
        ]
    }

    /// The state at the end of the piece for a zero start state: the load's own contribution
    /// (u, u', m, m').
    pub(super) fn load_terms(&self) -> [f64; 4] {
        self.load
    }

    /// d(end state)/d(start state): row r of Φ.
    pub(super) fn transfer_matrix(&self) -> [[f64; 4]; 4] {
        let t = self.length;
        let [t2_2e, t3_6e, t_e] = self.flexibility;
        [
            [1.0, t, t2_2e, t3_6e],
            [0.0, 1.0, t_e, t2_2e],
            [0.0, 0.0, 1.0, t],
            [0.0, 0.0, 0.0, 1.0],
        ]
    }

    /// Size of the deflections (kind 0) or slopes (kind 1) this piece carries: its end
    /// values and its own clamped–clamped response to the load. The refined solve gives each
    /// of them to a few ulps of this size.
    pub(super) fn magnitude(&self, start: [f64; 2], end: [f64; 2], kind: usize) -> f64 {
        let (t, load) = (self.length, self.load_start.abs().max(self.load_end.abs()));
        if kind == 0 {
            let own = t.powi(4) * load / (384.0 * self.stiffness);
            start[0]
                .abs()
                .max(end[0].abs())
                .max(t * start[1].abs())
                .max(t * end[1].abs())
                .max(own)
        } else {
            let own = t.powi(3) * load / (24.0 * self.stiffness);
            start[1].abs().max(end[1].abs()).max(own)
        }
    }
}

/// One piece's transfer coefficients in double-double, computed from the f64 data exactly
/// (the piece length as the exact difference of its end nodes, the load at the nodes as
/// f0 + (f1 − f0)·x/l): the residual of the refinement is formed with these, so that the
/// refined solution is that of the exact relations, not of their rounded coefficients.
#[derive(Debug, Clone, Copy)]
pub(super) struct ExactPiece {
    /// t, t²/2EJ, t³/6EJ, t/EJ in the first rows of Φ.
    t: DoubleDouble,
    t2_2e: DoubleDouble,
    t3_6e: DoubleDouble,
    t_e: DoubleDouble,
    /// The end state for a zero start state.
    load_terms: [DoubleDouble; 4],
}

impl ExactPiece {
    /// `length` the exact dimensionless length, `stiffness` E·J (dimensionless, a double),
    /// `load_start`, `load_end` the dimensionless load at the ends.
    pub(super) fn new(
        length: DoubleDouble,
        stiffness: f64,
        load_start: DoubleDouble,
        load_end: DoubleDouble,
    ) -> ExactPiece {
        let t = length;
        let e = DoubleDouble::from(stiffness);
        let t2 = t * t;
        let t3 = t2 * t;
        let t4 = t3 * t;
        let (fa, fb) = (load_start, load_end);
        let n = DoubleDouble::from;
        ExactPiece {
            t,
            t2_2e: t2 / (e.times(2.0)),
            t3_6e: t3 / (e.times(6.0)),
            t_e: t / e,
            load_terms: [
                t4 * (fa.times(4.0) + fb) / e.times(120.0),
                t3 * (fa.times(3.0) + fb) / e.times(24.0),
                t2 * (fa.times(2.0) + fb) / n(6.0),
                // Halved exactly: the bits of the division by 2, without its long division.
                (t * (fa + fb)).scaled(0.5),
            ],
        }
    }

    /// Φ of [`ExactPiece::transfer`]: the end state is Φ y + the load terms.
    pub(super) fn transfer_matrix(&self) -> [[DoubleDouble; 4]; 4] {
        let (zero, one) = (DoubleDouble::ZERO, DoubleDouble::from(1.0));
        [
            [one, self.t, self.t2_2e, self.t3_6e],
            [zero, one, self.t_e, self.t2_2e],
            [zero, zero, one, self.t],
            [zero, zero, zero, one],
        ]
    }

    /// Φ y alone (the unloaded beam's end state), in double-double.
    pub(super) fn transfer_unloaded(&self, y: [DoubleDouble; 4]) -> [DoubleDouble; 4] {
        let [u, du, m, v] = y;
        [
            u + self.t * du + self.t2_2e * m + self.t3_6e * v,
            du + self.t_e * m + self.t2_2e * v,
            m + self.t * v,
            v,
        ]
    }

    /// The end state from the start state y = (u, u', m, m'), in double-double: Φ y, then the
    /// load terms (each row summed left to right, as written out in full before stop 61).
    pub(super) fn transfer(&self, y: [DoubleDouble; 4]) -> [DoubleDouble; 4] {
        let end = self.transfer_unloaded(y);
        std::array::from_fn(|r| end[r] + self.load_terms[r])
    }
}
