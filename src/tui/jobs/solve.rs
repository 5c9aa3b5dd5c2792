//! The keystroke's own solve: the scene's method on its mesh, with the reference solution
//! (`condensed` on the same mesh, solved once for both the certificate and the chart) that the
//! deflection panel draws under it. A [`SolveRequest`] says what a solve depends on; a
//! [`Solved`] carries the request it answers, so an answer to an outdated request is dropped.
//! After a change the request starts the condensed search from the final friction pattern of
//! the solve shown ([`SolveRequest::starting_from`], a warm start): less work, the same answer.

use std::sync::Arc;

use crate::fem::Mesh;
use crate::model::Problem;
use crate::scene::{Scene, Settings};
use crate::solve::{
    ConditionLevel, FrictionPattern, Method, Solution, SolveError, SolveErrorKind, SolveOptions,
    WarmStart, solve_with_condensed,
};

/// What a solve depends on: the keystroke's re-solve is asked for by this, computed off the
/// UI thread, and its result kept only while it is still the one wanted.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveRequest {
    pub problem: Problem,
    pub elements: usize,
    pub method: Method,
    pub options: SolveOptions,
}

/// The most elements of a solve that [`SolveRequest::takes_milliseconds`].
const QUICK_ELEMENTS: usize = 2000;
/// The most obstacles of such a solve (the enumeration: 9² cases).
const QUICK_OBSTACLES: usize = 4;
const QUICK_ENUMERATED_OBSTACLES: usize = 2;
/// The most elements of such a `dual-inverse` solve (its dense inverse grows as n³).
const QUICK_DENSE_INVERSE_ELEMENTS: usize = 200;

impl SolveRequest {
    /// A solve of a few milliseconds at most (Benchmark 1 and its like, with its reference):
    /// few obstacles on a coarse mesh, whatever the method. Served sessions run such solves
    /// beside heavy ones instead of waiting for them to end.
    pub fn takes_milliseconds(&self) -> bool {
        let obstacles = self.problem.obstacles.len();
        match self.method {
            Method::Regularized => {
                obstacles <= QUICK_ENUMERATED_OBSTACLES && self.elements <= QUICK_ELEMENTS
            }
            Method::DualInverse => {
                obstacles <= QUICK_OBSTACLES && self.elements <= QUICK_DENSE_INVERSE_ELEMENTS
            }
            _ => obstacles <= QUICK_OBSTACLES && self.elements <= QUICK_ELEMENTS,
        }
    }

    /// This request with the condensed search starting from the final friction pattern of
    /// `solved` (the solve shown before a small change), if it has one: its own when the
    /// method is `condensed`, else its reference's. The answer is the same, the work less.
    pub fn starting_from(mut self, solved: Option<&Solved>) -> SolveRequest {
        if let Some(pattern) = solved.and_then(Solved::friction_pattern) {
            self.options.warm_start = WarmStart::from_pattern(pattern);
        }
        self
    }

    /// The solve a scene needs, with the problem and settings its validation built.
    pub fn for_scene(scene: &Scene, problem: &Problem, settings: Settings) -> SolveRequest {
        SolveRequest {
            problem: problem.clone(),
            elements: settings.elements,
            method: settings.method,
            options: solve_options(scene),
        }
    }
}

/// Solve options of the explorer: no condition numbers on the per-keystroke path, the
/// reference error for the status line.
pub fn solve_options(scene: &Scene) -> SolveOptions {
    SolveOptions {
        epsilon: scene.solver.epsilon,
        condition: ConditionLevel::Off,
        ..SolveOptions::default()
    }
}

/// A finished solve: what it was computed for, its mesh and its solution.
#[derive(Debug, Clone)]
pub struct Solved {
    pub request: SolveRequest,
    pub mesh: Mesh,
    pub solution: Result<Solution, SolveError>,
    /// max |u| over the nodes, found once on the worker (an O(n) scan has no place in a
    /// frame: 10⁷ nodes take milliseconds).
    pub max_deflection: f64,
    /// The reference (the `condensed` method on the same mesh), solved on the worker too, when
    /// the method is another one and the reference gave a solution.
    pub reference: Option<Solution>,
}

impl Solved {
    /// The final friction pattern of the condensed solve in this answer (the method's own or
    /// its reference's), to start the next solve from.
    pub fn friction_pattern(&self) -> Option<Arc<FrictionPattern>> {
        let own = self.solution.as_ref().ok();
        own.and_then(|s| s.friction_pattern.clone())
            .or_else(|| self.reference.as_ref()?.friction_pattern.clone())
    }

    /// Was the solve stopped by its cancellation (a newer request), its own or its
    /// reference's? Such a result answers nothing and is dropped.
    pub fn was_cancelled(&self) -> bool {
        self.request.options.cancel.is_cancelled()
            || matches!(&self.solution, Err(e) if e.kind == SolveErrorKind::Cancelled)
    }
}

/// Computes a request (headless rendering and tests on the spot, the solve worker off the UI
/// thread); `request.options.cancel` stops it inside its loops.
pub fn solve(request: &SolveRequest) -> Solved {
    let mesh = Mesh::new(&request.problem, request.elements);
    // With the reference curve of the deflection panel: the stable method on the same mesh,
    // the same solve the certificate graded with (none when the method is condensed).
    let (solution, reference) =
        solve_with_condensed(&request.problem, &mesh, request.method, &request.options);
    let max_deflection = solution.as_ref().map_or(f64::NAN, |s| s.max_deflection());
    Solved {
        request: request.clone(),
        mesh,
        solution,
        max_deflection,
        reference,
    }
}
