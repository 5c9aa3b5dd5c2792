//! The selected iterate's field behind the deflection panel's extra curve: while the
//! iterations panel is on screen and an iterate other than the last is selected (`<` `>`),
//! u(x) for that iterate's friction forces (`crate::solve::iterate_field`: A u = F − Bᵀλ), to
//! be drawn over the final solution.

use std::sync::Arc;

use super::sweep::{PanelSweep, SweepContext, SweepData, SweepInputs};
use crate::fem::{Mesh, NodalField};
use crate::scene::Panel;
use crate::study::{Cancel, Cancelled};

/// The field of one iterate, on the mesh it was computed on.
#[derive(Debug, Clone)]
pub struct IterateField {
    pub iteration: usize,
    pub mesh: Mesh,
    pub field: NodalField,
}

/// The selected iterate's field; its data is an [`IterateField`].
pub struct IterateSweep;

impl PanelSweep for IterateSweep {
    fn panels(&self) -> &'static [Panel] {
        // Drawn on the deflection; selected on the iterations panel.
        &[Panel::Iterations, Panel::Deflection]
    }

    fn computing(&self) -> &'static str {
        "computing the iterate's u(x)…"
    }

    fn needed(&self, context: &SweepContext) -> bool {
        context.iterate.is_some()
    }

    fn inputs(&self, context: SweepContext) -> SweepInputs {
        SweepInputs {
            iterate: context.iterate.clone(),
            ..SweepInputs::of_problem(context)
        }
    }

    fn compute(
        &self,
        inputs: &SweepInputs,
        cancel: &Cancel,
    ) -> Result<Result<SweepData, String>, Cancelled> {
        let Some((iteration, forces)) = &inputs.iterate else {
            return Ok(Err("the last iterate is the solution drawn".into()));
        };
        if cancel.is_cancelled() {
            return Err(Cancelled);
        }
        let mesh = Mesh::new(&inputs.problem, inputs.elements);
        Ok(
            crate::solve::iterate_field(&inputs.problem, &mesh, forces).map(|field| {
                Arc::new(IterateField {
                    iteration: *iteration,
                    mesh,
                    field,
                }) as SweepData
            }),
        )
    }
}
