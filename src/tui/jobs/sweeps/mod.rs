//! The sweeps behind the chart panels (runs of `crate::study` over ε or over mesh sizes),
//! through one mechanism: each sweep is a [`PanelSweep`] in the registry [`SWEEPS`] that says
//! which panels need it, what its result depends on ([`SweepInputs`]) and how to compute it.
//! The explorer's state keeps one slot per registered sweep (`tui::state::sweeps`); a worker
//! computes them for the interactive explorer (a keystroke never waits), [`compute_now`] to
//! completion for headless rendering. A result carries the inputs it was computed for; the
//! state keeps it only if they are still current, and a newer request cancels the work on an
//! outdated one. A new sweep-backed panel is one module implementing [`PanelSweep`], one line
//! in [`SWEEPS`], and one chart.

mod cases;
mod dual_box;
mod epsilon;
mod iterate;
mod matrices;
mod mesh;
mod sweep;

use crate::scene::Panel;
use crate::study::{Cancel, Cancelled};

pub use cases::CasesSweep;
pub use dual_box::{DualBoxSweep, DualPicture};
pub use epsilon::{EPS_POINTS, EpsilonSweep};
pub use iterate::{IterateField, IterateSweep};
pub use matrices::{MatricesSweep, SPY_GRID};
pub use mesh::{MESH_MAX, MESH_POINTS, MeshSweep};
pub use sweep::{PanelSweep, SweepContext, SweepData, SweepInputs, SweepRequest, SweepResult};

/// Every sweep, by index: the state's slots and the worker's lanes use the same index.
pub static SWEEPS: [&dyn PanelSweep; 6] = [
    &EpsilonSweep,
    &MeshSweep,
    &DualBoxSweep,
    &CasesSweep,
    &MatricesSweep,
    &IterateSweep,
];

/// The sweep a panel shows, if any.
pub fn sweep_of(panel: Panel) -> Option<usize> {
    SWEEPS.iter().position(|s| s.panels().contains(&panel))
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
