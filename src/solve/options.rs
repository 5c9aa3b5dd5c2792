//! How to solve: the options every method reads (ε of (40) for the regularised methods, the
//! limits of the enumeration of (43) and of the dense inverse of (49), which condition numbers
//! and whether a reference, whether to record the convergence history) and their default
//! limits, the cancellation of a solve and where the condensed search may start.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use serde::Serialize;

use super::condensed::pattern::FrictionPattern;

/// Which condition numbers to compute.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ConditionLevel {
    /// None (the explorer's per-keystroke path).
    Off,
    /// Exact for N ≤ 200, a cheap lower bound above.
    #[default]
    Auto,
    /// Exact for N ≤ 200, Lanczos estimates above (slow at very large n).
    Full,
}

impl ConditionLevel {
    /// Every level, from none to the most work.
    pub const ALL: [ConditionLevel; 3] = [
        ConditionLevel::Off,
        ConditionLevel::Auto,
        ConditionLevel::Full,
    ];

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            ConditionLevel::Off => "off",
            ConditionLevel::Auto => "auto",
            ConditionLevel::Full => "full",
        }
    }

    /// What the level computes, in one line.
    pub fn description(self) -> &'static str {
        match self {
            ConditionLevel::Off => "None (the explorer's per-keystroke path)",
            ConditionLevel::Auto => "Exact for N ≤ 200, a cheap lower bound above",
            ConditionLevel::Full => {
                "Exact for N ≤ 200, Lanczos estimates above (slow at very large n)"
            }
        }
    }
}

/// How to solve.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveOptions {
    /// ε of (40) for the regularised methods.
    pub epsilon: f64,
    /// The enumeration refuses when 9^k exceeds this.
    pub max_cases: u64,
    /// `dual-inverse` refuses when N = 2(n − 1) exceeds this (the inverse is N² doubles).
    pub max_dense_unknowns: usize,
    pub condition: ConditionLevel,
    /// Compare against a reference (closed form or flexibility) and report the error.
    pub reference: bool,
    /// Record the iterative methods' convergence history ([`super::History`]); when false
    /// nothing is recorded or allocated for it.
    pub history: bool,
    /// Stops a solve whose result is no longer wanted, from inside its long loops.
    pub cancel: Cancellation,
    /// Where the `condensed` search may start (the explorer's re-solve after a small change).
    pub warm_start: WarmStart,
}

/// The friction pattern of an earlier `condensed` solve, for the next solve's search to start
/// from ([`super::solve_condensed_from`]): after a one-notch change at 4000 obstacles in
/// clusters it settles in one pattern solve instead of an interior-point guess and two
/// (`cargo bench --bench many_obstacles -- warm`). The search decides every DOF exactly
/// whatever it starts from: the answer is the one without a start (on every scene of that
/// benchmark and of the tests to the last bit), only the work differs. Not used while the
/// convergence history is recorded (the iterations panel shows the search from its own
/// start), and ignored when it is for another number of obstacles.
#[derive(Debug, Clone, Default)]
pub struct WarmStart(Option<Arc<FrictionPattern>>);

impl WarmStart {
    /// Start from `pattern`.
    pub fn from_pattern(pattern: Arc<FrictionPattern>) -> WarmStart {
        WarmStart(Some(pattern))
    }

    /// The pattern to start from, if any.
    pub fn pattern(&self) -> Option<&FrictionPattern> {
        self.0.as_deref()
    }
}

/// Equal always: a start changes the work of a solve, not its result.
impl PartialEq for WarmStart {
    fn eq(&self, _: &WarmStart) -> bool {
        true
    }
}

/// Whether a solve is still wanted: the explorer's solver sets a generation counter when a
/// newer request arrives, and the methods look at it inside their long loops (QP iterations,
/// the enumeration, Newton steps, per-piece sweeps) and give up with
/// [`super::SolveErrorKind::Cancelled`]. It never changes a result that is computed to the
/// end, so two options that differ only here compare equal.
#[derive(Debug, Clone, Default)]
pub struct Cancellation {
    /// (the newest generation, this solve's generation)
    watch: Option<(Arc<AtomicU64>, u64)>,
}

impl Cancellation {
    /// Never cancelled.
    pub const NEVER: Cancellation = Cancellation { watch: None };

    /// Cancelled as soon as `newest` no longer holds `generation`.
    pub fn watching(newest: Arc<AtomicU64>, generation: u64) -> Self {
        Cancellation {
            watch: Some((newest, generation)),
        }
    }

    /// Has a newer request made this solve pointless?
    pub fn is_cancelled(&self) -> bool {
        self.watch
            .as_ref()
            .is_some_and(|(newest, generation)| newest.load(Ordering::Relaxed) != *generation)
    }
}

/// Equal always: cancellation is not an input of the result.
impl PartialEq for Cancellation {
    fn eq(&self, _: &Cancellation) -> bool {
        true
    }
}

/// Default limit of the enumeration: 9^6 = 531 441 cases (k ≤ 6 obstacles).
pub const MAX_CASES: u64 = 531_441;
/// Default limit of `dual-inverse`: N ≤ 4000 unknowns, a 128 MB inverse.
pub const MAX_DENSE_UNKNOWNS: usize = 4000;

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            epsilon: 1e-6,
            max_cases: MAX_CASES,
            max_dense_unknowns: MAX_DENSE_UNKNOWNS,
            condition: ConditionLevel::Auto,
            reference: true,
            history: false,
            cancel: Cancellation::NEVER,
            warm_start: WarmStart::default(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_level_name_is_its_serialized_form() {
        for level in ConditionLevel::ALL {
            let json = serde_json::to_value(level).unwrap();
            assert_eq!(json.as_str(), Some(level.name()));
        }
    }
}
