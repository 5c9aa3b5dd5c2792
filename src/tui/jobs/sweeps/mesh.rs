//! The mesh sweep behind the error-vs-run-time panel: every method over mesh sizes 10 … 10⁵
//! and the scene's own n.

use std::sync::Arc;

use super::sweep::{PanelSweep, SweepContext, SweepData, SweepInputs};
use crate::scene::Panel;
use crate::study::{self, Cancel, Cancelled};

/// The largest mesh in the error-vs-run-time panel.
pub const MESH_MAX: usize = 100_000;
/// How many log-spaced sizes from 10 to [`MESH_MAX`] the panel sweeps (and the scene's n).
pub const MESH_POINTS: usize = 9;

/// The mesh sweep; its data is a `Vec<MeshPoint>`.
pub struct MeshSweep;

impl PanelSweep for MeshSweep {
    fn panels(&self) -> &'static [Panel] {
        &[Panel::ErrorTime]
    }

    fn computing(&self) -> &'static str {
        "computing the mesh sweep…"
    }

    fn inputs(&self, context: SweepContext) -> SweepInputs {
        SweepInputs {
            epsilon: Some(context.epsilon),
            repeat: Some(if context.show_timings { 3 } else { 1 }),
            ..SweepInputs::of_problem(context)
        }
    }

    fn compute(
        &self,
        inputs: &SweepInputs,
        cancel: &Cancel,
    ) -> Result<Result<SweepData, String>, Cancelled> {
        let points = study::error_study(
            &inputs.problem,
            &study::mesh_sizes(10, MESH_MAX, MESH_POINTS),
            inputs.elements,
            inputs.repeat.unwrap_or(1),
            inputs.epsilon.unwrap_or(1e-6),
            cancel,
            &study::silent,
        )?;
        Ok(Ok(Arc::new(points) as SweepData))
    }
}
