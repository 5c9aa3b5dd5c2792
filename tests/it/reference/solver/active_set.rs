//! Step 2 of the reference solver (`super`): the classical primal active-set method on the dual
//! box QP, every step carried out in the primal as one banded solve of the full system with the
//! stuck DOFs held, in the working precision.

use super::*;

/// Where a friction DOF is in the active-set method: force free (stuck) or fixed at ±g.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Slot {
    Free,
    Bound(bool), // true: +g
}

pub(super) struct Outcome {
    pub(super) c: Vec<F>,
    pub(super) lambda: Vec<F>,
    pub(super) slots: Vec<Slot>,
}

pub(super) struct ActiveSet<'a> {
    pub(super) system: &'a System,
    pub(super) friction: &'a Friction,
    pub(super) mp: Mp,
    pub(super) solves: usize,
}

impl ActiveSet<'_> {
    fn bound_value(&self, i: usize, plus: bool) -> F {
        if plus {
            self.friction.g[i].clone()
        } else {
            -self.friction.g[i].clone()
        }
    }

    /// The subspace solution for `slots`: c, and λ (bound values on W, residuals on F).
    fn solve_slots(&mut self, slots: &[Slot]) -> Result<(Vec<F>, Vec<F>), String> {
        self.solves += 1;
        let n = self.system.dofs();
        let mut fixed = vec![false; n];
        let mut rhs = self.system.b.clone();
        for (i, slot) in slots.iter().enumerate() {
            let p = self.friction.dof[i];
            match *slot {
                Slot::Free => fixed[p] = true,
                Slot::Bound(plus) => rhs[p] -= self.bound_value(i, plus),
            }
        }
        let c = solve_masked(self.system, &fixed, &rhs, &self.mp)?;
        let lambda = slots
            .iter()
            .enumerate()
            .map(|(i, slot)| match *slot {
                Slot::Bound(plus) => self.bound_value(i, plus),
                Slot::Free => {
                    let p = self.friction.dof[i];
                    &self.system.b[p] - self.system.row_product(p, &c, &self.mp).0
                }
            })
            .collect();
        Ok((c, lambda))
    }

    /// max |c| over the DOFs of each kind (value, slope), times the tie tolerance.
    fn motion_tolerance(&self, c: &[F]) -> [F; 2] {
        let tau = self.mp.tie_tolerance();
        let scale = |kind: usize| max_abs(c.iter().skip(kind).step_by(2), &self.mp);
        [&tau * scale(0), &tau * scale(1)]
    }

    fn is_zero_threshold(&self, i: usize) -> bool {
        is_zero(&self.friction.g[i])
    }

    pub(super) fn run(&mut self) -> Result<Outcome, String> {
        let m = self.friction.len();
        // Zero thresholds: the force is 0 whatever the motion, permanently "bound".
        let initial: Vec<Slot> = (0..m)
            .map(|i| {
                if self.is_zero_threshold(i) {
                    Slot::Bound(true)
                } else {
                    Slot::Free
                }
            })
            .collect();
        let (mut slots, mut lambda) = self.warm_start(initial)?;
        let limit = 50 * m + 100;
        for _ in 0..limit {
            let (c, target) = self.solve_slots(&slots)?;
            // Step from λ towards the subspace minimiser, stopping at the first bound.
            let mut step = self.mp.num(1.0);
            let mut blocking: Option<(usize, bool)> = None;
            for i in 0..m {
                if slots[i] != Slot::Free {
                    continue;
                }
                let g = &self.friction.g[i];
                let d = &target[i] - &lambda[i];
                let (outside, plus) = if target[i] > *g {
                    (true, true)
                } else if target[i] < -g.clone() {
                    (true, false)
                } else {
                    (false, false)
                };
                if outside {
                    let to_bound = self.bound_value(i, plus) - &lambda[i];
                    let t = to_bound / &d;
                    let t = if is_negative(&t) { self.mp.zero() } else { t };
                    if t < step {
                        step = t;
                        blocking = Some((i, plus));
                    }
                }
            }
            if let Some((i, plus)) = blocking {
                for j in 0..m {
                    if slots[j] == Slot::Free {
                        let next = &lambda[j] + &step * (&target[j] - &lambda[j]);
                        lambda[j] = next;
                    }
                }
                lambda[i] = self.bound_value(i, plus);
                slots[i] = Slot::Bound(plus);
                continue;
            }
            lambda = target;
            // Multipliers of the bounds: the motion must have the sign of the force.
            let tolerance = self.motion_tolerance(&c);
            let mut worst: Option<(usize, F)> = None;
            for i in 0..m {
                let Slot::Bound(plus) = slots[i] else {
                    continue;
                };
                if self.is_zero_threshold(i) {
                    continue;
                }
                let y = &c[self.friction.dof[i]];
                let signed = if plus { y.clone() } else { -y.clone() };
                let kind = self.friction.kind[i];
                if signed < -tolerance[kind].clone() {
                    // Compare across kinds relative to each kind's scale.
                    let scale = max_abs(c.iter().skip(kind).step_by(2), &self.mp);
                    let relative = signed / scale;
                    if worst.as_ref().is_none_or(|(_, w)| relative < *w) {
                        worst = Some((i, relative));
                    }
                }
            }
            match worst {
                Some((i, _)) => slots[i] = Slot::Free,
                None => return Ok(Outcome { c, lambda, slots }),
            }
        }
        Err(format!(
            "active set did not terminate in {limit} iterations"
        ))
    }

    /// A primal–dual active-set pass (at most 30 solves) for a starting working set, then a
    /// feasible λ on it.
    fn warm_start(&mut self, mut slots: Vec<Slot>) -> Result<(Vec<Slot>, Vec<F>), String> {
        let m = self.friction.len();
        let mut lambda: Vec<F> = (0..m).map(|_| self.mp.zero()).collect();
        for _ in 0..30 {
            let (c, l) = self.solve_slots(&slots)?;
            lambda = l;
            let mut changed = false;
            for i in 0..m {
                if self.is_zero_threshold(i) {
                    continue;
                }
                let g = &self.friction.g[i];
                match slots[i] {
                    Slot::Free => {
                        if abs(&lambda[i]) > *g {
                            slots[i] = Slot::Bound(!is_negative(&lambda[i]));
                            changed = true;
                        }
                    }
                    Slot::Bound(plus) => {
                        let y = &c[self.friction.dof[i]];
                        if !is_zero(y) && is_negative(y) == plus {
                            slots[i] = Slot::Free;
                            changed = true;
                        }
                    }
                }
            }
            if !changed {
                break;
            }
        }
        // Feasible λ: bound values on W, the last free values clipped into the box on F.
        for i in 0..m {
            lambda[i] = match slots[i] {
                Slot::Bound(plus) => self.bound_value(i, plus),
                Slot::Free => {
                    let g = &self.friction.g[i];
                    if lambda[i] > *g {
                        g.clone()
                    } else if lambda[i] < -g.clone() {
                        -g.clone()
                    } else {
                        lambda[i].clone()
                    }
                }
            };
        }
        Ok((slots, lambda))
    }
}
