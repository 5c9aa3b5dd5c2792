//! The dual's picture behind the dual-box panel: the `dual` method solved with its box-QP
//! history, and the dual (49) restricted to the selected obstacle's pair of forces
//! (`crate::study::dual_pair`), the other obstacles held at their solution forces.

use std::sync::Arc;

use super::sweep::{PanelSweep, SweepContext, SweepData, SweepInputs};
use crate::fem::Mesh;
use crate::scene::Panel;
use crate::solve::{ConditionLevel, Method, SolveOptions, solve};
use crate::study::{Cancel, Cancelled, DualPair, dual_pair_until};

/// What the dual-box panel draws.
#[derive(Debug, Clone)]
pub struct DualPicture {
    pub pair: DualPair,
    /// The box QP's iterates of this obstacle's pair (N, N m), the last the solution.
    pub iterates: Vec<[f64; 2]>,
    /// The state the Results panel names for this obstacle under the dual method.
    pub state: &'static str,
    /// How many obstacles the scene has.
    pub obstacles: usize,
}

/// The dual's picture; its data is a [`DualPicture`].
pub struct DualBoxSweep;

impl PanelSweep for DualBoxSweep {
    fn panels(&self) -> &'static [Panel] {
        &[Panel::DualBox]
    }

    fn computing(&self) -> &'static str {
        "solving the dual (49) with its iterates…"
    }

    fn inputs(&self, context: SweepContext) -> SweepInputs {
        let last = context.problem.obstacles.len().saturating_sub(1);
        SweepInputs {
            obstacle: Some(context.obstacle.unwrap_or(0).min(last)),
            ..SweepInputs::of_problem(context)
        }
    }

    fn compute(
        &self,
        inputs: &SweepInputs,
        cancel: &Cancel,
    ) -> Result<Result<SweepData, String>, Cancelled> {
        let problem = &inputs.problem;
        if problem.obstacles.is_empty() {
            return Ok(Err(
                "no obstacle: the dual (49) has no forces to picture".into()
            ));
        }
        let mesh = Mesh::new(problem, inputs.elements);
        let options = SolveOptions {
            condition: ConditionLevel::Off,
            reference: false,
            history: true,
            cancel: cancel.clone(),
            ..SolveOptions::default()
        };
        let solution = match solve(problem, &mesh, Method::Dual, &options) {
            Ok(solution) => solution,
            Err(_) if cancel.is_cancelled() => return Err(Cancelled),
            Err(error) => return Ok(Err(format!("the dual method: {}", error.reason))),
        };
        let obstacle = inputs.obstacle.unwrap_or(0);
        let forces: Vec<[f64; 2]> = solution
            .obstacles
            .iter()
            .map(|o| [o.force, o.moment])
            .collect();
        let pair = match dual_pair_until(problem, &mesh, &forces, obstacle, cancel)? {
            Ok(pair) => pair,
            Err(why) => return Ok(Err(why)),
        };
        let iterates = solution.history.as_ref().map_or_else(Vec::new, |history| {
            history
                .iterations
                .iter()
                .filter_map(|r| r.forces.get(obstacle).copied())
                .collect()
        });
        let picture = DualPicture {
            pair,
            iterates,
            state: solution.obstacles[obstacle].state(),
            obstacles: problem.obstacles.len(),
        };
        Ok(Ok(Arc::new(picture) as SweepData))
    }
}
