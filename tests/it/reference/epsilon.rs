//! The ε-reference: the regularised problem of paper 2.7.1 on the program's own mesh, solved in
//! multi-precision arithmetic, so that the regularised methods (`regularized`,
//! `regularized-newton`) can be graded against the problem they actually solve rather than
//! against the exact problem (38).
//!
//! **The problem.** |z| in (38) is replaced by the Huber-type ω̃_ε of (40), the same ε (SI
//! units) for the value DOF (u, m) and the slope DOF (u', rad) of every obstacle, as
//! `src/solve/regularized.rs` does. The minimiser of the strictly convex, piecewise quadratic
//! φ(c) = ½cᵀAc − bᵀc + Σ_p g_p ω̃_ε(c_p) satisfies A c = b − λ(c) with the force
//! λ_p = g_p ω̃'_ε(c_p) = g_p·clamp(c_p/ε, −1, 1) of (41) (the sign convention of the
//! program, A c = b − Bᵀλ). For a fixed pattern of regions (Table 1: c_p < −ε, |c_p| ≤ ε,
//! c_p > ε) this is the linear system (43), (A + Σ_middle (g/ε) e_p e_pᵀ) c = b − Σ_outer
//! (±g) e_p, solved here by the band LDLᵀ of [`super::solver`] on the full system (the
//! friction DOFs are ordinary DOFs in the band, so the diagonal additions keep the band).
//!
//! **The method.** Semismooth Newton on φ, started at the exact reference's solution (any
//! start gives the same answer; [`Start::Zero`] is kept for the self-tests): at c, with its pattern R, the Newton
//! point c_N is the solution of the R-system (Newton's matrix A + D_R is the generalised
//! Hessian, and ∇φ is affine on the closed piece of R). If c_N lies in the closure of R (up
//! to the tie tolerance below) it is stationary for φ, hence the minimiser, and the method
//! stops. Otherwise it steps from c towards c_N with the *exact* minimiser of the convex
//! piecewise quadratic φ along the line (φ' along the line is piecewise linear and
//! nondecreasing, with breaks where some c_p crosses ±ε: walk the breaks, solve the linear
//! piece).
//!
//! **Why it terminates.** (i) A ≤ A + D_R ≤ A + max(g/ε)·I, so every Newton direction is a
//! descent direction at an angle to −∇φ bounded away from 90°, and ∇φ is Lipschitz: with
//! exact line searches Zoutendijk's condition gives ∇φ(c_k) → 0, and strong convexity gives
//! c_k → c*, the unique minimiser. (ii) The pieces are finitely many closed boxes in the
//! friction coordinates, so once c_k is close enough to c* every piece containing c_k also
//! contains c*; then ∇φ(c*) = 0 makes c* the minimiser of that piece's quadratic, c_N = c*,
//! and the stopping test succeeds. So the iteration stops after finitely many steps (in
//! working precision: once c_N is within rounding of c*, which the tie tolerance absorbs).
//! It is capped at [`MAX_ITERATIONS`] all the same, and fails with an error past it. The
//! argument says nothing about speed: from c = 0 it crawled on hard scenes (up to 465 steps,
//! more than 500 on 9 of 2058 at ε = 1e-10), so it starts from the exact solution, within
//! O(ε) of the answer, and then needed at most 7 steps on the same 2058 scenes (5 at
//! ε = 1e-6).
//!
//! **Certificate and states.** Stationarity b − A c − λ(c) relative to its terms, in the
//! working precision, with λ(c) = g·clamp(c/ε, −1, 1) from the final c; every friction DOF in
//! the closure of the region whose system it solves (`complementarity`). For the ε-problem a
//! DOF *moves* when |c| > ε (`src/solve/equilibrium.rs`: `moves = |c| > motion_tolerance +
//! ε`), is *stuck* when |c| < ε (then |λ| < g), and is [`FrictionState::AtThreshold`] — a tie,
//! either flag right — when | |c| − ε | ≤ 2^(−precision/2)·ε (or, for a zero threshold,
//! whenever |c| ≤ ε: λ = 0 = g). The tolerance is relative to ε, not to max |c|: a middle DOF
//! is c_p = ε λ_p/g_p, as accurate relative to ε as λ_p is relative to g_p.

use beamfric::fem::Mesh;
use beamfric::model::Problem;

use super::mp::{F, Mp, abs, is_negative, is_zero, to_f64};
use super::solver::{
    Certificate, Friction, FrictionState, RefSolution, System, assemble, dof, solve_banded,
    solve_reference_with, stationarity,
};

/// Most Newton steps (each one band solve) before the solver gives up.
pub const MAX_ITERATIONS: usize = 500;

/// The region of a friction DOF (Table 1 of the paper).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Region {
    /// c < −ε: λ = −g.
    Negative,
    /// |c| ≤ ε: λ = g c/ε.
    Middle,
    /// c > ε: λ = +g.
    Positive,
}

/// The ε-problem on one mesh, in one precision.
struct EpsilonProblem<'a> {
    system: &'a System,
    friction: &'a Friction,
    mp: Mp,
    epsilon: F,
    /// g_p/ε per friction DOF.
    stiffening: Vec<F>,
}

impl EpsilonProblem<'_> {
    fn region(&self, c: &F) -> Region {
        if *c > self.epsilon {
            Region::Positive
        } else if *c < -self.epsilon.clone() {
            Region::Negative
        } else {
            Region::Middle
        }
    }

    /// λ_i(c) = g·clamp(c_p/ε, −1, 1), (41).
    fn force(&self, i: usize, c: &[F]) -> F {
        self.force_of(i, &c[self.friction.dof[i]])
    }

    /// λ_i as a function of the value x of its DOF.
    fn force_of(&self, i: usize, x: &F) -> F {
        let g = &self.friction.g[i];
        match self.region(x) {
            Region::Positive => g.clone(),
            Region::Negative => -g.clone(),
            Region::Middle => x * &self.stiffening[i],
        }
    }

    /// The solution of the linear system (43) of the pattern `regions`.
    fn solve_regions(&self, regions: &[Region]) -> Result<Vec<F>, String> {
        let n = self.system.dofs();
        let mut added: Vec<F> = (0..n).map(|_| self.mp.zero()).collect();
        let mut rhs = self.system.b.clone();
        for (i, region) in regions.iter().enumerate() {
            let p = self.friction.dof[i];
            let g = &self.friction.g[i];
            match region {
                Region::Middle => added[p] = self.stiffening[i].clone(),
                Region::Positive => rhs[p] -= g,
                Region::Negative => rhs[p] += g,
            }
        }
        solve_banded(self.system, &vec![false; n], Some(&added), &rhs, &self.mp)
    }

    /// Per kind (value, slope): the tie tolerance 2^(−precision/2)·ε.
    fn tolerance(&self) -> [F; 2] {
        let tol = self.mp.tie_tolerance() * &self.epsilon;
        [tol.clone(), tol]
    }

    /// Does every friction DOF of c lie in the closure of its region, up to the tolerance?
    fn in_regions(&self, c: &[F], regions: &[Region]) -> bool {
        let tolerance = self.tolerance();
        regions.iter().enumerate().all(|(i, region)| {
            let x = &c[self.friction.dof[i]];
            let tol = &tolerance[self.friction.kind[i]];
            match region {
                Region::Positive => *x >= &self.epsilon - tol,
                Region::Negative => *x <= -(&self.epsilon - tol),
                Region::Middle => abs(x) <= &self.epsilon + tol,
            }
        })
    }

    /// (A v) and the gradient ∇φ(c) = A c − b + λ(c) on the full vector.
    fn product(&self, v: &[F]) -> Vec<F> {
        (0..self.system.dofs())
            .map(|j| self.system.row_product(j, v, &self.mp).0)
            .collect()
    }

    fn gradient(&self, c: &[F]) -> Vec<F> {
        let mut gradient: Vec<F> = self
            .product(c)
            .into_iter()
            .zip(&self.system.b)
            .map(|(ac, b)| ac - b)
            .collect();
        for i in 0..self.friction.len() {
            gradient[self.friction.dof[i]] += self.force(i, c);
        }
        gradient
    }

    /// The t ≥ 0 minimising φ(c + t d): φ'(t) = dᵀ∇φ(c) + t dᵀAd + Σ_p d_p (λ_p(c + t d) −
    /// λ_p(c)) is piecewise linear and nondecreasing with breaks where c_p + t d_p = ±ε.
    fn exact_line_search(&self, c: &[F], d: &[F]) -> Result<F, String> {
        let mp = &self.mp;
        let dot = |a: &[F], b: &[F]| a.iter().zip(b).fold(mp.zero(), |s, (x, y)| s + x * y);
        let slope0 = dot(d, &self.gradient(c));
        if !is_negative(&slope0) {
            return Err("the Newton direction is not a descent direction".into());
        }
        let curvature = dot(d, &self.product(d));
        let m = self.friction.len();
        let base: Vec<F> = (0..m).map(|i| self.force(i, c)).collect();
        let derivative = |t: &F| -> F {
            let mut value = &slope0 + t * &curvature;
            for i in 0..m {
                let p = self.friction.dof[i];
                let moved = &c[p] + t * &d[p];
                value += &d[p] * (self.force_of(i, &moved) - &base[i]);
            }
            value
        };
        let mut breaks: Vec<F> = Vec::new();
        for i in 0..m {
            let p = self.friction.dof[i];
            if is_zero(&d[p]) || is_zero(&self.friction.g[i]) {
                continue;
            }
            for edge in [self.epsilon.clone(), -self.epsilon.clone()] {
                let t = (edge - &c[p]) / &d[p];
                if !is_negative(&t) && !is_zero(&t) {
                    breaks.push(t);
                }
            }
        }
        breaks.sort_by(|a, b| a.partial_cmp(b).expect("finite"));
        let (mut t0, mut f0) = (mp.zero(), slope0.clone());
        for t1 in breaks {
            let f1 = derivative(&t1);
            if !is_negative(&f1) {
                // φ' is linear on [t0, t1]: its zero.
                if f1 == f0 {
                    return Ok(t1);
                }
                return Ok(&t0 + (&t1 - &t0) * (-f0.clone()) / (&f1 - &f0));
            }
            (t0, f0) = (t1, f1);
        }
        // Past every break no DOF with d_p ≠ 0 is in the middle region: slope dᵀAd.
        Ok(t0 - f0 / curvature)
    }
}

/// Where Newton starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Start {
    /// At the exact reference's solution (ε = 0), which is within O(ε) of the answer: its
    /// pattern of regions is then right but for the DOFs whose exact motion is below ε, and
    /// Newton needs a few steps (from zero it needed up to 465 on the 2000 hard scenes and
    /// more than 500 on 9 of them).
    Exact,
    /// At c = 0 (every DOF in the middle region).
    Zero,
}

/// Solves the ε-problem of `problem` on `mesh` in `precision` bits (ε > 0, SI units, the same
/// for value and slope DOFs), Newton started at the exact reference's solution. Fails if ε is
/// not positive and finite, if Newton does not stop within [`MAX_ITERATIONS`] steps, or if a
/// band factorization meets a non-positive pivot.
pub fn solve_epsilon_reference(
    problem: &Problem,
    mesh: &Mesh,
    epsilon: f64,
    precision: usize,
) -> Result<RefSolution, String> {
    solve_epsilon_reference_from(problem, mesh, epsilon, precision, Start::Exact)
}

/// [`solve_epsilon_reference`] with the start chosen. The answer does not depend on it (φ is
/// strictly convex); only the number of steps does.
pub fn solve_epsilon_reference_from(
    problem: &Problem,
    mesh: &Mesh,
    epsilon: f64,
    precision: usize,
    start: Start,
) -> Result<RefSolution, String> {
    if !(epsilon > 0.0 && epsilon.is_finite()) {
        return Err(format!("ε must be positive and finite, got {epsilon:e}"));
    }
    let mp = Mp { precision };
    let system = assemble(problem, mesh, &mp);
    let friction = Friction::new(problem, mesh, &mp);
    let eps = mp.num(epsilon);
    let stiffening = friction.g.iter().map(|g| g / &eps).collect();
    let eps_problem = EpsilonProblem {
        system: &system,
        friction: &friction,
        mp,
        epsilon: eps,
        stiffening,
    };
    let m = friction.len();
    let mut c: Vec<F> = (0..system.dofs()).map(|_| mp.zero()).collect();
    if start == Start::Exact {
        let exact = solve_reference_with(problem, mesh, precision)?;
        for node in 1..mesh.nodes.len() - 1 {
            c[dof(node, 0)] = exact.u[node].clone();
            c[dof(node, 1)] = exact.slope[node].clone();
        }
    }
    for iteration in 1..=MAX_ITERATIONS {
        let regions: Vec<Region> = (0..m)
            .map(|i| eps_problem.region(&c[friction.dof[i]]))
            .collect();
        let newton = eps_problem.solve_regions(&regions)?;
        if eps_problem.in_regions(&newton, &regions) {
            return Ok(finish(
                problem,
                mesh,
                &eps_problem,
                newton,
                &regions,
                iteration,
            ));
        }
        let direction: Vec<F> = newton.iter().zip(&c).map(|(a, b)| a - b).collect();
        let t = eps_problem.exact_line_search(&c, &direction)?;
        c = c.iter().zip(&direction).map(|(x, d)| x + &t * d).collect();
    }
    Err(format!(
        "semismooth Newton did not stop in {MAX_ITERATIONS} steps"
    ))
}

fn finish(
    problem: &Problem,
    mesh: &Mesh,
    eps_problem: &EpsilonProblem,
    c: Vec<F>,
    regions: &[Region],
    solves: usize,
) -> RefSolution {
    let EpsilonProblem {
        system,
        friction,
        mp,
        epsilon,
        ..
    } = eps_problem;
    let lambda: Vec<F> = (0..friction.len())
        .map(|i| {
            let x = &c[friction.dof[i]];
            let g = &friction.g[i];
            // g·clamp(c/ε, −1, 1), also for a tie just outside its region.
            if abs(x) >= *epsilon {
                if is_negative(x) {
                    -g.clone()
                } else {
                    g.clone()
                }
            } else {
                x * &eps_problem.stiffening[i]
            }
        })
        .collect();

    // Stationarity b − A c − λ(c).
    let stationarity = stationarity(system, friction, &c, &lambda, mp);
    let complementarity = eps_problem.in_regions(&c, regions);
    let tolerance = eps_problem.tolerance();

    let mut states = Vec::with_capacity(problem.obstacles.len());
    let mut motion = Vec::with_capacity(problem.obstacles.len());
    for o in 0..problem.obstacles.len() {
        let mut pair = [FrictionState::Stuck; 2];
        for kind in 0..2 {
            let i = 2 * o + kind;
            let size = abs(&c[friction.dof[i]]);
            let tol = &tolerance[friction.kind[i]];
            pair[kind] = if size > epsilon + tol {
                FrictionState::Moves
            } else if is_zero(&friction.g[i]) || size >= epsilon - tol {
                FrictionState::AtThreshold
            } else {
                FrictionState::Stuck
            };
        }
        states.push(pair);
        let node = mesh.obstacle_nodes[o];
        motion.push([c[dof(node, 0)].clone(), c[dof(node, 1)].clone()]);
    }
    let tau = to_f64(&mp.tie_tolerance());
    let verified = stationarity <= tau && complementarity;

    RefSolution::package(
        (mesh, mp),
        &c,
        &lambda,
        (motion, states),
        to_f64(epsilon),
        Certificate {
            stationarity,
            bound_excess: 0.0,
            complementarity,
            verified,
        },
        solves,
    )
}
