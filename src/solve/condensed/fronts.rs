//! Fronts of freeing in the semismooth Newton phases of `search`: where every force along a
//! stretch of the beam sits at its threshold (the ties family of issue 26 with one threshold
//! lowered), freeing one obstacle pushes its neighbour over, and semismooth Newton frees the
//! stretch one obstacle per solve from each end, like dominoes (4000 obstacles: 1196 pattern
//! solves for one stretch). A front is a DOF freed next to a DOF of the same kind that the
//! previous step freed; the step frees that many more stuck DOFs of the same kind beyond it,
//! with the same sign, doubling the reach after every step that extended a front (1, 2, 4,
//! …): a stretch of m obstacles takes about 2 log₂ m solves. A front that overshoots (a
//! freed DOF whose force then reverses) is held again by the next Newton step like any
//! other inconsistent DOF; nothing is decided here, the pattern search decides every DOF.

use std::collections::HashSet;

use super::pattern::Pattern;

/// The fronts of the last Newton step that only freed stuck DOFs.
#[derive(Debug, Default)]
pub(super) struct Fronts {
    /// The DOFs that step freed (and those it freed beyond its fronts).
    last_freed: HashSet<usize>,
    /// How many stuck DOFs the next step frees beyond each front (0 before the first step).
    reach: usize,
}

impl Fronts {
    /// A step that did not only free stuck DOFs: no front goes on.
    pub(super) fn reset(&mut self) {
        self.last_freed.clear();
        self.reach = 0;
    }

    /// After a Newton step whose `changes` (already in `pattern`) all free stuck DOFs: frees
    /// up to `reach` stuck DOFs of the same kind beyond every front, in its direction and
    /// with its sign; the reach doubles when a front went on.
    pub(super) fn extend(&mut self, pattern: &mut [Pattern], changes: &[(usize, Pattern)]) {
        let mut freed: HashSet<usize> = changes.iter().map(|&(i, _)| i).collect();
        let mut extended = false;
        for &(i, wanted) in changes {
            // Same kind, next obstacle: 2·obstacle + kind ± 2.
            for (behind, ahead) in [(i.checked_sub(2), 1isize), (i.checked_add(2), -1)] {
                if !behind.is_some_and(|b| self.last_freed.contains(&b)) {
                    continue;
                }
                let mut next = i.checked_add_signed(2 * ahead);
                for _ in 0..self.reach {
                    match next {
                        Some(j) if j < pattern.len() && pattern[j] == Pattern::Stuck => {
                            pattern[j] = wanted;
                            freed.insert(j);
                            extended = true;
                            next = j.checked_add_signed(2 * ahead);
                        }
                        _ => break,
                    }
                }
            }
        }
        if extended || self.reach == 0 {
            self.reach = (2 * self.reach).max(1);
        }
        self.last_freed = freed;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_front_goes_on_twice_as_far_each_step_and_stops_at_a_moving_dof() {
        use Pattern::{Negative, Positive, Stuck};
        // Obstacles 0..20; the moments (odd DOFs) of obstacles 2..=19 stuck, obstacle 19's
        // moment moving the other way; the forces (even DOFs) all moving.
        let mut pattern = vec![Positive; 40];
        for obstacle in 2..19 {
            pattern[2 * obstacle + 1] = Stuck;
        }
        pattern[39] = Negative;
        let mut fronts = Fronts::default();
        let step = |pattern: &mut [Pattern], fronts: &mut Fronts, dof: usize| {
            pattern[dof] = Positive;
            fronts.extend(pattern, &[(dof, Positive)]);
        };
        let moving = |pattern: &[Pattern]| {
            (0..20)
                .filter(|o| pattern[2 * o + 1] != Stuck)
                .collect::<Vec<_>>()
        };
        // The first freeing step has no front behind it: nothing more.
        step(&mut pattern, &mut fronts, 5);
        assert_eq!(moving(&pattern), [0, 1, 2, 19]);
        // Obstacle 3 next to 2: a front, one more (4); then two more beyond 5 (6, 7); then
        // four beyond 8 (9..=12).
        step(&mut pattern, &mut fronts, 7);
        assert_eq!(moving(&pattern), [0, 1, 2, 3, 4, 19]);
        step(&mut pattern, &mut fronts, 11);
        assert_eq!(moving(&pattern), [0, 1, 2, 3, 4, 5, 6, 7, 19]);
        step(&mut pattern, &mut fronts, 17);
        assert_eq!(moving(&pattern), (0..13).chain([19]).collect::<Vec<_>>());
        // Eight would reach past obstacle 18: the front stops at the moving DOF of 19, whose
        // sign it leaves alone.
        step(&mut pattern, &mut fronts, 27);
        assert_eq!(moving(&pattern), (0..20).collect::<Vec<_>>());
        assert_eq!(pattern[39], Negative);
        assert!(pattern.iter().step_by(2).all(|&p| p == Positive));
        // A DOF freed away from every front frees nothing more.
        let mut lone = vec![Stuck; 40];
        let mut fronts = Fronts::default();
        step(&mut lone, &mut fronts, 20);
        step(&mut lone, &mut fronts, 30);
        assert_eq!(lone.iter().filter(|&&p| p != Stuck).count(), 2);
    }
}
