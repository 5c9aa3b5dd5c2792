//! The mesh sweep behind the error-vs-run-time panel: every method over mesh sizes 10 … 10⁵
//! and the scene's own n.

use std::sync::Arc;

use super::sweep::{PanelSweep, SweepContext, SweepData, SweepInputs};
use crate::scene::Panel;
use crate::solve::Method;
use crate::study::{self, Cancel, Cancelled};

/// The largest mesh in the error-vs-run-time panel.
pub const MESH_MAX: usize = 100_000;
/// The largest mesh for `dual-inverse` there: its O(N³) cost shows well before.
pub const DENSE_MAX: usize = 400;

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
            problem: context.problem.clone(),
            elements: context.elements,
            epsilon: Some(context.epsilon),
            repeat: Some(if context.show_timings { 3 } else { 1 }),
        }
    }

    fn compute(
        &self,
        inputs: &SweepInputs,
        cancel: &Cancel,
    ) -> Result<Result<SweepData, String>, Cancelled> {
        let mut sizes = study::mesh_sizes(10, MESH_MAX, 9);
        sizes.push(inputs.elements);
        sizes.sort();
        sizes.dedup();
        let (dense, others): (Vec<Method>, Vec<Method>) = Method::ALL
            .into_iter()
            .partition(|m| *m == Method::DualInverse);
        let small: Vec<usize> = sizes.iter().copied().filter(|&n| n <= DENSE_MAX).collect();
        let problem = &inputs.problem;
        let repeat = inputs.repeat.unwrap_or(1);
        let epsilon = inputs.epsilon.unwrap_or(1e-6);
        let silent = &study::silent;
        let mut points =
            study::mesh_sweep(problem, &others, &sizes, repeat, epsilon, cancel, silent)?;
        points.extend(study::mesh_sweep(
            problem, &dense, &small, repeat, epsilon, cancel, silent,
        )?);
        Ok(Ok(Arc::new(points) as SweepData))
    }
}
