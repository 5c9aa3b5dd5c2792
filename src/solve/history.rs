//! The convergence history of an iterative method, recorded only when
//! [`SolveOptions::history`](super::SolveOptions::history) asks for it: per iterate the
//! method's own measure of progress, the objective it decreases, how many friction DOFs
//! changed state and the friction forces λ of (38) at that iterate — what the explorer's
//! iterations panel and `beamfric solve --history` show.
//!
//! The measures, all dimensionless so that one log axis fits every scene:
//! - the box QP of the dual problem (49) (`dual`, `dual-inverse`, `flexibility`):
//!   [`ProgressMeasure::ProjectedGradient`], ‖y − P(y − ∇f(y))‖∞ / ‖z‖∞ of the problem scaled to
//!   unit diagonal (y = D⁻¹λ), zero exactly at the solution of (49); the objective is
//!   ½λᵀSλ − z0ᵀλ of (49) in J;
//! - `regularized-newton`: [`ProgressMeasure::SemismoothResidual`], the largest row of the
//!   gradient of the ε-problem (40)–(43), K c − b̃ + g ω̃'_ε(c), relative to the sum of its
//!   terms' sizes (the method's own stopping test); the objective is
//!   ½cᵀKc − b̃ᵀc + Σ gᵢ ω̃_ε(cᵢ) in J;
//! - `condensed`: [`ProgressMeasure::KktResidual`], the worst violation of the friction
//!   conditions of (38) by a pattern solve — a stuck force above its threshold, relative to the
//!   largest force of its kind, or a motion against the sign of its force, relative to the
//!   largest motion of its kind; one iterate per pattern solve (the interior-point steps that
//!   may give the first pattern are not recorded), no objective.
//!
//! The enumeration `regularized` and `closed-form` do not iterate: their history is `None`
//! even when asked for.
//!
//! When history is not asked for, nothing is recorded or allocated: the methods take an
//! `Option<&mut Recorder>` and do no extra work on `None`.

use serde::Serialize;

use crate::fem::{Mesh, NodalField, StiffnessMatrix, load_vector};
use crate::linalg::blocktri::FrictionLastFactor;
use crate::linalg::boxqp::{BoundState, QpObserver};
use crate::model::{Method, Problem};

/// What a method measures its own progress by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ProgressMeasure {
    /// The box QP of (49): the projected gradient.
    ProjectedGradient,
    /// Semismooth Newton on the ε-problem: the gradient of its objective.
    SemismoothResidual,
    /// The friction conditions of (38), checked on a pattern solve.
    KktResidual,
    /// The fall of the objective from one iterate to the next.
    ObjectiveDecrease,
}

impl ProgressMeasure {
    /// The name in JSON and CSV, e.g. `projected-gradient`.
    pub fn name(self) -> &'static str {
        match self {
            ProgressMeasure::ProjectedGradient => "projected-gradient",
            ProgressMeasure::SemismoothResidual => "semismooth-residual",
            ProgressMeasure::KktResidual => "kkt-residual",
            ProgressMeasure::ObjectiveDecrease => "objective-decrease",
        }
    }

    /// Words for a chart axis, e.g. `projected-gradient norm`.
    pub fn label(self) -> &'static str {
        match self {
            ProgressMeasure::ProjectedGradient => "projected-gradient norm",
            ProgressMeasure::SemismoothResidual => "semismooth residual",
            ProgressMeasure::KktResidual => "KKT residual",
            ProgressMeasure::ObjectiveDecrease => "objective decrease",
        }
    }
}

/// One iterate of a method.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IterationRecord {
    /// 0 = the starting point.
    pub iteration: usize,
    /// The method's own measure at this iterate (finite, ≥ 0, dimensionless).
    pub measure: f64,
    /// The objective the method decreases [J], when it has one.
    pub objective: Option<f64>,
    /// Friction DOFs whose state (free / at −g / at +g, or stuck / sliding) changed from the
    /// previous iterate (0 at the starting point).
    pub changed: usize,
    /// (force [N], moment [N m]) per obstacle at this iterate.
    pub forces: Vec<[f64; 2]>,
}

/// The convergence history of one solve.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct History {
    pub method: Method,
    pub measure: ProgressMeasure,
    /// In order; the last one is the answer's iterate.
    pub iterations: Vec<IterationRecord>,
    /// More than [`MAX_RECORDED_ITERATIONS`] iterates: the middle ones were dropped (the
    /// `iteration` numbers show the gap).
    pub truncated: bool,
}

/// Most iterates kept: past this, the first and the last half of them, and `truncated`.
pub const MAX_RECORDED_ITERATIONS: usize = 500;

/// Where a friction DOF is at an iterate, in the terms every method shares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum DofState {
    /// Strictly inside its bounds: stuck (or, for the ε-problem, in the middle region).
    Inside,
    /// At −g: moving the negative way.
    AtLower,
    /// At +g: moving the positive way.
    AtUpper,
}

impl From<BoundState> for DofState {
    fn from(state: BoundState) -> DofState {
        match state {
            BoundState::Free => DofState::Inside,
            BoundState::Lower => DofState::AtLower,
            BoundState::Upper => DofState::AtUpper,
        }
    }
}

/// Collects the iterates of one solve: the first half of [`MAX_RECORDED_ITERATIONS`] as they
/// come, then the most recent half in a ring.
#[derive(Debug)]
pub(crate) struct Recorder {
    method: Method,
    measure: ProgressMeasure,
    first: Vec<IterationRecord>,
    last: std::collections::VecDeque<IterationRecord>,
    /// Iterates seen so far (the next one's number).
    seen: usize,
    previous_states: Vec<DofState>,
}

impl Recorder {
    /// A recorder when `wanted`, else `None` (nothing allocated).
    pub fn when(wanted: bool, method: Method, measure: ProgressMeasure) -> Option<Recorder> {
        wanted.then(|| Recorder {
            method,
            measure,
            first: Vec::new(),
            last: std::collections::VecDeque::new(),
            seen: 0,
            previous_states: Vec::new(),
        })
    }

    /// Records the next iterate. A non-finite measure (a broken solve) is not recorded.
    pub fn record(
        &mut self,
        measure: f64,
        objective: Option<f64>,
        states: &[DofState],
        forces: Vec<[f64; 2]>,
    ) {
        if !measure.is_finite() {
            return;
        }
        let changed = if self.seen == 0 {
            0
        } else {
            states
                .iter()
                .zip(&self.previous_states)
                .filter(|(a, b)| a != b)
                .count()
        };
        self.previous_states.clear();
        self.previous_states.extend_from_slice(states);
        let record = IterationRecord {
            iteration: self.seen,
            measure: measure.max(0.0),
            objective: objective.filter(|v| v.is_finite()),
            changed,
            forces,
        };
        self.seen += 1;
        let half = MAX_RECORDED_ITERATIONS / 2;
        if self.first.len() < half {
            self.first.push(record);
        } else {
            if self.last.len() == MAX_RECORDED_ITERATIONS - half {
                self.last.pop_front();
            }
            self.last.push_back(record);
        }
    }

    /// The history recorded.
    pub fn finish(self) -> History {
        let kept = self.first.len() + self.last.len();
        let truncated = self.seen > kept;
        let mut iterations = self.first;
        iterations.extend(self.last);
        History {
            method: self.method,
            measure: self.measure,
            iterations,
            truncated,
        }
    }
}

/// The box QP's iterates, as λ in the caller's units: pairs (force, moment) per obstacle.
impl QpObserver for Recorder {
    fn iterate(&mut self, x: &[f64], states: &[BoundState], projected_gradient: f64, value: f64) {
        let states: Vec<DofState> = states.iter().map(|&s| s.into()).collect();
        let forces = x
            .chunks(2)
            .map(|c| [c[0], c.get(1).copied().unwrap_or(0.0)]);
        self.record(projected_gradient, Some(value), &states, forces.collect());
    }
}

/// The deflection field for given friction forces: solves A u = F − Bᵀλ on `mesh` (the paper's
/// (48)/(49) relation between the dual variables and u), for drawing an iterate's u(x).
/// `forces` holds (force [N], moment [N m]) per obstacle of `problem`, whose mesh `mesh` is.
/// One block-tridiagonal factorization of A: O(n), and accurate to the stiffness route's
/// rounding, cond(A)·eps — 1e-13 of max |u| on the benchmarks, 1e-3 on the `modulus-contrast`
/// preset, whose A has a stiffness contrast of 10⁶ (enough to draw; the methods' answers are
/// [`super::Solution::field`]).
pub fn iterate_field(
    problem: &Problem,
    mesh: &Mesh,
    forces: &[[f64; 2]],
) -> Result<NodalField, String> {
    if forces.len() != mesh.obstacle_nodes.len() {
        return Err(format!(
            "{} force pairs for {} obstacles on the mesh",
            forces.len(),
            mesh.obstacle_nodes.len()
        ));
    }
    let n = mesh.elements();
    if n < 2 || mesh.nodes.len() != n + 1 {
        return Err(format!("a mesh of {n} elements has no interior node"));
    }
    let (mut u, mut t) = load_vector(problem, mesh);
    for (&node, [force, moment]) in mesh.obstacle_nodes.iter().zip(forces) {
        if node == 0 || node >= n {
            return Err(format!("obstacle node {node} is not inside the beam"));
        }
        u[node] -= force;
        t[node] -= moment;
    }
    let factor = FrictionLastFactor::new(StiffnessMatrix::new(mesh), &[])
        .map_err(|b| format!("the pivot of node {} is singular", b.block + 1))?;
    factor.solve(&mut u[1..n], &mut t[1..n], |_| Vec::new());
    Ok(NodalField {
        deflection: u,
        slope: t,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nothing_is_allocated_unless_wanted() {
        let off = Recorder::when(false, Method::Dual, ProgressMeasure::ProjectedGradient);
        assert!(off.is_none());
    }

    #[test]
    fn changes_are_counted_against_the_previous_iterate() {
        let mut recorder =
            Recorder::when(true, Method::Condensed, ProgressMeasure::KktResidual).unwrap();
        let (inside, lower, upper) = (DofState::Inside, DofState::AtLower, DofState::AtUpper);
        recorder.record(1.0, None, &[inside, inside], vec![[0.0, 0.0]]);
        recorder.record(0.5, Some(-1.0), &[upper, inside], vec![[1.0, 0.0]]);
        recorder.record(f64::NAN, None, &[lower, lower], vec![[1.0, 0.0]]);
        recorder.record(
            0.0,
            Some(f64::INFINITY),
            &[lower, lower],
            vec![[-1.0, -2.0]],
        );
        let history = recorder.finish();
        let changed: Vec<usize> = history.iterations.iter().map(|r| r.changed).collect();
        // The non-finite measure is not recorded; the next iterate is compared with the last
        // one recorded, and numbered after it.
        assert_eq!(changed, [0, 1, 2]);
        let numbers: Vec<usize> = history.iterations.iter().map(|r| r.iteration).collect();
        assert_eq!(numbers, [0, 1, 2]);
        assert_eq!(history.iterations[1].objective, Some(-1.0));
        assert_eq!(history.iterations[2].objective, None);
        assert!(!history.truncated);
    }

    #[test]
    fn a_long_history_keeps_its_first_and_last_iterates() {
        let mut recorder =
            Recorder::when(true, Method::Dual, ProgressMeasure::ProjectedGradient).unwrap();
        let total = 1200;
        for i in 0..total {
            recorder.record(i as f64, None, &[DofState::Inside], vec![[i as f64, 0.0]]);
        }
        let history = recorder.finish();
        assert!(history.truncated);
        assert_eq!(history.iterations.len(), MAX_RECORDED_ITERATIONS);
        let numbers: Vec<usize> = history.iterations.iter().map(|r| r.iteration).collect();
        let half = MAX_RECORDED_ITERATIONS / 2;
        let expected: Vec<usize> = (0..half).chain(total - half..total).collect();
        assert_eq!(numbers, expected);

        let mut exact =
            Recorder::when(true, Method::Dual, ProgressMeasure::ProjectedGradient).unwrap();
        for _ in 0..MAX_RECORDED_ITERATIONS {
            exact.record(0.0, None, &[], vec![]);
        }
        let history = exact.finish();
        assert!(!history.truncated);
        assert_eq!(history.iterations.len(), MAX_RECORDED_ITERATIONS);
    }

    #[test]
    fn measure_names_are_their_serialized_form() {
        for measure in [
            ProgressMeasure::ProjectedGradient,
            ProgressMeasure::SemismoothResidual,
            ProgressMeasure::KktResidual,
            ProgressMeasure::ObjectiveDecrease,
        ] {
            let json = serde_json::to_value(measure).unwrap();
            assert_eq!(json.as_str(), Some(measure.name()));
            assert!(!measure.label().is_empty());
        }
    }
}
