//! The bounds of every friction DOF's force change about the held beam (every DOF stuck
//! under the load), ±g − λ_h, within which the interior-point guess (`interior`) and the
//! projected Newton guess (`projected`) work; where the interior-point guess starts between
//! them; and the bounds nearer zero than its f64 steps resolve, widened to what they do.

use super::mixed::Mixed;
use super::system::ShootingSystem;
use crate::linalg::double_double::DoubleDouble;

/// A bound nearer zero than this fraction of the largest force change at the start is moved
/// out to it ([`widen_unresolved`]): about four ulps of that change, below which a step's
/// solve does not resolve a slack. Measured on the 80 comparison scenes (the four families
/// at k = 40–4000 and the lowered ties at k = 300–4000): factorisations 6274 without it,
/// 3305, 3328, 3258, 3293 and 3378 with 1e-16, 3e-16, 1e-15, 3e-15 and 1e-14, 3716 with
/// 1e-12; the families' counts the same from 1e-16 to 1e-14.
const UNRESOLVED_BOUND: f64 = 1e-15;

/// The floor of [`widen_unresolved`] for a second interior-point iteration where the first
/// stalled (`interior`): a bound nearer zero than this fraction of its DOF's range (at most
/// of the largest force change at the start) is moved out to it. Measured on the hostile
/// arrangement of stop 53 (every other obstacle's thresholds at its stuck forces, the rest
/// 0–2 × them; `check::families::half_ties_scene`) at k = 1000 and 3000, seeds 1–3, pattern
/// solves after the second iteration: 1e-8: 2–4, 1e-7: 2–3, 1e-6: 2–4, 3e-6: 2–6, 1e-4:
/// 3–54. Taken for the first iteration instead, it cost the lowered ties and the clusters at
/// ties hundreds of solves (4985 and 12 325 on stop 52's sweep, against 164 and 4054): there
/// a tie's decision is the answer's.
pub(super) const WIDENED_TIE: f64 = 1e-6;

/// Per DOF, the bounds of its force change (`None` without friction), and the conditions
/// with those of the frictionless DOFs set (their force back to zero).
pub(super) type HeldBounds = (Vec<Option<(f64, f64)>>, Vec<Mixed>);

impl ShootingSystem {
    /// The bounds ±g − λ_h of every DOF's force change from the held forces `held`, each
    /// taken in double-double and rounded once; a threshold beyond any force the load can
    /// make (1e6 times the total load, times the length for a moment) is capped there, so
    /// that it does not set the scale of μ.
    pub(super) fn held_bounds(&self, held: &[DoubleDouble]) -> HeldBounds {
        let length: f64 = self.pieces.iter().map(|p| p.length).sum();
        let total_load: f64 = self
            .pieces
            .iter()
            .map(|p| p.length * p.load_start.abs().max(p.load_end.abs()))
            .sum();
        let cap = [1e6 * total_load, 1e6 * total_load * length];
        let mut fixed: Vec<Mixed> = (0..held.len()).map(Mixed::free).collect();
        let bounds = (0..held.len())
            .map(|dof| {
                let threshold = self.thresholds[dof / 2][dof % 2].min(cap[dof % 2]);
                if threshold > 0.0 {
                    let threshold = DoubleDouble::from(threshold);
                    Some((
                        (-threshold - held[dof]).value(),
                        (threshold - held[dof]).value(),
                    ))
                } else {
                    fixed[dof].force = -held[dof].value();
                    None
                }
            })
            .collect();
        (bounds, fixed)
    }
}

/// Where the iteration starts a DOF's force change between its bounds: at no change where
/// the held force is within them, else as far inside the bound it breaks as it lies outside.
pub(super) fn start_force((lower, upper): (f64, f64)) -> f64 {
    let middle = 0.5 * (lower + upper);
    if lower < 0.0 && upper > 0.0 {
        0.0
    } else if upper <= 0.0 {
        (upper + upper.min(-f64::MIN_POSITIVE)).max(middle)
    } else {
        (lower + lower.max(f64::MIN_POSITIVE)).min(middle)
    }
}

/// The bounds with every bound nearer zero than [`UNRESOLVED_BOUND`] times the largest force
/// change of the start (a DOF without friction included) moved out to that distance, on the
/// side of "within": a held force that equals its threshold to what the iteration's f64
/// solves resolve is a tie the iteration cannot decide, and keeping its bound (1.6e-27
/// against force changes of 3e-4 on lowered ties) made the iteration stall
/// (docs/many-obstacles/monotone-search.md, "Within what a step resolves (stop 48)"). The exact
/// search decides such a DOF like any other. One floor for forces and moments alike: in the
/// system's units (length scaled to about 1) both kinds of change come out of the same solve, whose
/// rounding is that of its largest value.
///
/// With `range_fraction` > 0 ([`WIDENED_TIE`]), a bound nearer zero than that fraction of
/// its DOF's range (at most of the largest force change) is moved out to it as well.
pub(super) fn widen_unresolved(
    mut bounds: Vec<Option<(f64, f64)>>,
    fixed: &[Mixed],
    range_fraction: f64,
) -> Vec<Option<(f64, f64)>> {
    let largest_change = bounds
        .iter()
        .zip(fixed)
        .map(|(bound, condition)| match *bound {
            Some(bound) => start_force(bound).abs(),
            None => condition.force.abs(),
        })
        .fold(0.0f64, f64::max);
    let floor = UNRESOLVED_BOUND * largest_change;
    for (lower, upper) in bounds.iter_mut().flatten() {
        let floor = floor.max(range_fraction * (*upper - *lower).min(largest_change));
        if lower.abs() < floor {
            *lower = -floor;
        }
        if upper.abs() < floor {
            *upper = floor;
        }
    }
    bounds
}

/// The distance of 0 from the nearer bound.
pub(super) fn nearest((lower, upper): (f64, f64)) -> f64 {
    lower.abs().min(upper.abs())
}
