//! The sweeps behind the chart panels (runs of `crate::study` over ε or over mesh sizes),
//! through one mechanism: each sweep is a [`PanelSweep`] in the registry [`SWEEPS`] that says
//! which panels need it, what its result depends on ([`SweepInputs`]) and how to compute it.
//! The explorer's state keeps one slot per registered sweep (`tui::state::sweeps`); a worker
//! computes them for the interactive explorer (a keystroke never waits), [`compute_now`] to
//! completion for headless rendering. A result carries the inputs it was computed for; the
//! state keeps it only if they are still current, and a newer request cancels the work on an
//! outdated one. A new sweep-backed panel is one module implementing [`PanelSweep`], one line
//! in [`SWEEPS`], and one chart.

mod epsilon;
mod mesh;

use std::any::Any;
use std::sync::Arc;

use crate::model::Problem;
use crate::scene::Panel;
use crate::study::{Cancel, Cancelled};

pub use epsilon::{EPS_POINTS, EpsilonSweep};
pub use mesh::{DENSE_MAX, MESH_MAX, MeshSweep};

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
}

/// What a sweep's inputs are taken from: the explorer's current state.
#[derive(Debug, Clone, Copy)]
pub struct SweepContext<'a> {
    pub problem: &'a Problem,
    pub elements: usize,
    pub epsilon: f64,
    pub show_timings: bool,
}

/// A sweep behind one or more panels.
pub trait PanelSweep: Sync {
    /// The panels that show it; it is computed only while one of them is visible.
    fn panels(&self) -> &'static [Panel];
    /// What it is called while it runs: "computing the … sweep…".
    fn computing(&self) -> &'static str;
    /// What its result depends on, in this state.
    fn inputs(&self, context: SweepContext) -> SweepInputs;
    /// Computes it; `Ok(Err(why))` when the sweep cannot run for these inputs.
    fn compute(
        &self,
        inputs: &SweepInputs,
        cancel: &Cancel,
    ) -> Result<Result<SweepData, String>, Cancelled>;
}

/// Every sweep, by index: the state's slots and the worker's lanes use the same index.
pub static SWEEPS: [&dyn PanelSweep; 2] = [&EpsilonSweep, &MeshSweep];

/// The sweep a panel shows, if any.
pub fn sweep_of(panel: Panel) -> Option<usize> {
    SWEEPS.iter().position(|s| s.panels().contains(&panel))
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

/// Computes one request, to completion unless `cancel` says stop.
pub fn compute(request: &SweepRequest, cancel: &Cancel) -> Result<SweepResult, Cancelled> {
    let data = SWEEPS[request.sweep].compute(&request.inputs, cancel)?;
    Ok(SweepResult {
        sweep: request.sweep,
        inputs: request.inputs.clone(),
        data,
    })
}

/// Computes one request to completion.
pub fn compute_now(request: &SweepRequest) -> SweepResult {
    compute(request, &crate::solve::Cancellation::NEVER)
        .expect("a sweep that is never cancelled finishes")
}
