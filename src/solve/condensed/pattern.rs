//! The friction pattern of the condensed method: how each friction DOF of (38) enters the
//! multiple-shooting system (held, or moving either way with |λ| = g), and the pattern a solve
//! ended with, which the next solve after a small change may start from (a warm start). A
//! leaf: the certificate, the options and the solution carry a pattern without depending on
//! the method.

/// How a friction DOF enters the linear system.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(in crate::solve) enum Pattern {
    Stuck,
    /// Moves with λ = +g.
    Positive,
    /// Moves with λ = −g.
    Negative,
}

/// The friction pattern a condensed solve ended with (which DOFs are held, which move and
/// their way), to start the next solve from ([`super::solve_condensed_from`]). Any pattern is
/// a valid start: the search decides every DOF exactly whatever it starts from, so a start
/// changes the number of solves, never what they converge to beyond rounding.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct FrictionPattern(pub(in crate::solve) Vec<Pattern>);

impl FrictionPattern {
    /// The number of friction DOFs (two per obstacle).
    pub fn dofs(&self) -> usize {
        self.0.len()
    }
}
