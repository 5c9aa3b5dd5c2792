//! What the box QP shows its observer: every iterate, taken back to the caller's units, with
//! its bound states, projected-gradient norm and objective — computed only when there is an
//! observer.

use super::{BoundState, QpObserver, Scaled, gradient};

/// The observer, if any, and the scaling x = D y that takes an iterate back to its units.
pub(super) struct Watch<'s, 'o> {
    pub(super) observer: Option<&'o mut dyn QpObserver>,
    pub(super) scaling: &'s [f64],
}

impl Watch<'_, '_> {
    /// Shows the scaled iterate `y` (with the method's working set, if it has one) to the
    /// observer; nothing at all without one.
    pub(super) fn see(&mut self, problem: &Scaled, y: &[f64], working_set: Option<&[BoundState]>) {
        let Some(observer) = self.observer.as_deref_mut() else {
            return;
        };
        let Scaled { h, z, g } = *problem;
        let grad = gradient(h, z, y);
        let largest = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let projected = (0..y.len())
            .map(|i| (y[i] - (y[i] - grad[i]).clamp(-g[i], g[i])).abs())
            .fold(0.0f64, f64::max);
        let scale = largest(z);
        let measure = if scale > 0.0 {
            projected / scale
        } else {
            projected
        };
        // ½yᵀHy − zᵀy = ½yᵀ(∇f − z) with ∇f = Hy − z; the same value in the caller's units.
        let value: f64 = 0.5 * (0..y.len()).map(|i| y[i] * (grad[i] - z[i])).sum::<f64>();
        let located: Vec<BoundState>;
        let state = match working_set {
            Some(state) => state,
            None => {
                located = (0..y.len())
                    .map(|i| {
                        if y[i] <= -g[i] {
                            BoundState::Lower
                        } else if y[i] >= g[i] {
                            BoundState::Upper
                        } else {
                            BoundState::Free
                        }
                    })
                    .collect();
                &located
            }
        };
        let x: Vec<f64> = y.iter().zip(self.scaling).map(|(y, d)| y * d).collect();
        observer.iterate(&x, state, measure, value);
    }
}
