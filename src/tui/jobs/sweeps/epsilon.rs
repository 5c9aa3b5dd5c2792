//! The ε sweep behind the error-vs-ε and cond-vs-ε panels (paper Figure 5): the regularised
//! method at the scene's n for ε = 1e-16 … 1 and at the scene's own ε, whose values the panels
//! print.

use std::sync::Arc;

use super::sweep::{PanelSweep, SweepContext, SweepData, SweepInputs};
use crate::scene::Panel;
use crate::solve::Method;
use crate::study::{self, Cancel, Cancelled};

/// Points of the ε sweep drawn in the panels: ε = 1e-16 … 1, two per decade (and the scene's ε).
pub const EPS_POINTS: usize = 33;

/// The ε sweep; its data is a `Vec<EpsPoint>`.
pub struct EpsilonSweep;

impl PanelSweep for EpsilonSweep {
    fn panels(&self) -> &'static [Panel] {
        &[Panel::EpsError, Panel::EpsCond, Panel::Figure5]
    }

    fn computing(&self) -> &'static str {
        "computing the ε sweep…"
    }

    fn inputs(&self, context: SweepContext) -> SweepInputs {
        SweepInputs {
            epsilon: Some(context.epsilon),
            ..SweepInputs::of_problem(context)
        }
    }

    fn compute(
        &self,
        inputs: &SweepInputs,
        cancel: &Cancel,
    ) -> Result<Result<SweepData, String>, Cancelled> {
        let mut epsilons = study::log_space(1e-16, 1.0, EPS_POINTS);
        // The scene's ε exactly, so that the panels print its values rather than a neighbour's.
        if let Some(current) = inputs.epsilon.filter(|e| e.is_finite() && *e > 0.0) {
            epsilons.push(current);
            epsilons.sort_by(f64::total_cmp);
            epsilons.dedup();
        }
        let sweep = |method| {
            study::epsilon_sweep(
                &inputs.problem,
                inputs.elements,
                method,
                &epsilons,
                cancel,
                &study::silent,
            )
        };
        // The enumeration gives the case matrices the cond panel shows; where it refuses (too
        // many obstacles for 9^k cases) Newton's method still gives the error curve.
        let result = match sweep(Method::Regularized)? {
            Err(_) => sweep(Method::RegularizedNewton)?,
            enumerated => enumerated,
        };
        Ok(result
            .map(|points| Arc::new(points) as SweepData)
            .map_err(|e| crate::study::sweep_refusal(&e)))
    }
}
