//! What a sweep is to the explorer: the panels that show it, what its result depends on
//! ([`SweepInputs`], from a [`SweepContext`] of the state), how it is computed
//! ([`PanelSweep`]), and the requests and results that travel between the state and the
//! workers.

use std::any::Any;
use std::sync::Arc;

use crate::model::Problem;
use crate::scene::Panel;
use crate::study::{Cancel, Cancelled};

/// A sweep's data, of the type its panel's chart reads (e.g. `Vec<EpsPoint>`).
pub type SweepData = Arc<dyn Any + Send + Sync>;

/// What a sweep's result depends on. Each sweep fills in what it uses and leaves the rest
/// `None`, so a change of anything else does not recompute it.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepInputs {
    pub problem: Problem,
    /// The scene's number of elements.
    pub elements: usize,
    /// The scene's ε.
    pub epsilon: Option<f64>,
    /// Median over this many runs (when run times are shown).
    pub repeat: Option<usize>,
    /// The obstacle a panel looks at (the dual's box: the selected one).
    pub obstacle: Option<usize>,
    /// The enumeration's limit of cases (the cases of Table 1).
    pub max_cases: Option<u64>,
    /// An iterate of the solve shown: its number and its friction forces (N, N m).
    pub iterate: Option<(usize, Vec<[f64; 2]>)>,
}

impl SweepInputs {
    /// Inputs of the problem and mesh alone; a sweep adds what else it depends on.
    pub fn of_problem(context: SweepContext) -> SweepInputs {
        SweepInputs {
            problem: context.problem.clone(),
            elements: context.elements,
            epsilon: None,
            repeat: None,
            obstacle: None,
            max_cases: None,
            iterate: None,
        }
    }
}

/// What a sweep's inputs are taken from: the explorer's current state.
#[derive(Debug, Clone)]
pub struct SweepContext<'a> {
    pub problem: &'a Problem,
    pub elements: usize,
    pub epsilon: f64,
    pub show_timings: bool,
    /// The obstacle of the selected parameter row, if it is one's.
    pub obstacle: Option<usize>,
    /// The enumeration's limit of cases.
    pub max_cases: u64,
    /// The iterate the iterations panel selects, when not the last: number and forces.
    pub iterate: Option<(usize, Vec<[f64; 2]>)>,
}

/// A sweep behind one or more panels.
pub trait PanelSweep: Sync {
    /// The panels that show it; it is computed only while one of them is visible.
    fn panels(&self) -> &'static [Panel];
    /// What it is called while it runs: "computing the … sweep…".
    fn computing(&self) -> &'static str;
    /// What its result depends on, in this state.
    fn inputs(&self, context: SweepContext) -> SweepInputs;
    /// Whether this state needs it at all while one of its panels is visible (by default it
    /// does).
    fn needed(&self, _context: &SweepContext) -> bool {
        true
    }
    /// Computes it; `Ok(Err(why))` when the sweep cannot run for these inputs.
    fn compute(
        &self,
        inputs: &SweepInputs,
        cancel: &Cancel,
    ) -> Result<Result<SweepData, String>, Cancelled>;
}

/// A request for the sweep worker.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepRequest {
    /// Index into [`SWEEPS`].
    pub sweep: usize,
    pub inputs: SweepInputs,
}

/// A finished sweep, tagged with the inputs it was computed for.
#[derive(Debug, Clone)]
pub struct SweepResult {
    pub sweep: usize,
    pub inputs: SweepInputs,
    pub data: Result<SweepData, String>,
}
