//! The structure of the matrices behind the matrices panel: A, S = B A⁻¹ Bᵀ and the condensed
//! system of the scene on screen (`crate::study::matrix_structures`), each as a grid of blocks
//! the panel draws at its own size.

use std::sync::Arc;

use super::sweep::{PanelSweep, SweepContext, SweepData, SweepInputs};
use crate::fem::Mesh;
use crate::scene::Panel;
use crate::study::{Cancel, Cancelled, matrix_structures};

/// Blocks of each matrix's grid, across and down: enough for a 120-column terminal's panel.
pub const SPY_GRID: (usize, usize) = (64, 64);

/// The matrices; its data is a `Vec<crate::study::MatrixStructure>`.
pub struct MatricesSweep;

impl PanelSweep for MatricesSweep {
    fn panels(&self) -> &'static [Panel] {
        &[Panel::Matrices]
    }

    fn computing(&self) -> &'static str {
        "looking at the matrices…"
    }

    fn inputs(&self, context: SweepContext) -> SweepInputs {
        SweepInputs::of_problem(context)
    }

    fn compute(
        &self,
        inputs: &SweepInputs,
        cancel: &Cancel,
    ) -> Result<Result<SweepData, String>, Cancelled> {
        let mesh = Mesh::new(&inputs.problem, inputs.elements);
        let matrices = matrix_structures(&inputs.problem, &mesh, SPY_GRID, cancel)?;
        Ok(Ok(Arc::new(matrices) as SweepData))
    }
}
