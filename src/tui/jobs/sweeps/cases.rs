//! The regularised method's cases behind the cases panel (paper Table 1, systems (43)):
//! `crate::study::case_study` at the scene's ε and mesh.

use std::sync::Arc;

use super::sweep::{PanelSweep, SweepContext, SweepData, SweepInputs};
use crate::fem::Mesh;
use crate::scene::Panel;
use crate::study::{Cancel, Cancelled, case_study};

/// The cases of Table 1; its data is a [`crate::study::CaseStudy`].
pub struct CasesSweep;

impl PanelSweep for CasesSweep {
    fn panels(&self) -> &'static [Panel] {
        &[Panel::Cases]
    }

    fn computing(&self) -> &'static str {
        "solving the cases of Table 1…"
    }

    fn inputs(&self, context: SweepContext) -> SweepInputs {
        SweepInputs {
            epsilon: Some(context.epsilon),
            max_cases: Some(context.max_cases),
            ..SweepInputs::of_problem(context)
        }
    }

    fn compute(
        &self,
        inputs: &SweepInputs,
        cancel: &Cancel,
    ) -> Result<Result<SweepData, String>, Cancelled> {
        let mesh = Mesh::new(&inputs.problem, inputs.elements);
        let epsilon = inputs.epsilon.unwrap_or(1e-6);
        let max_cases = inputs.max_cases.unwrap_or(crate::solve::MAX_CASES);
        let study = case_study(&inputs.problem, &mesh, epsilon, max_cases, cancel)?;
        Ok(study.map(|s| Arc::new(s) as SweepData))
    }
}
