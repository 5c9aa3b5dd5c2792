//! The reference solver: the discrete friction problem (38) on the program's own mesh, solved
//! in multi-precision arithmetic, written independently of `src/solve` and `src/linalg`.
//!
//! 1. Assembly. From the mesh it takes only the node positions (f64, converted exactly) and
//!    E·J per element. Element lengths are exact differences of the nodes; the Hermite cubic
//!    stiffness EJ/h³·[12, 6h, −12, 6h; …] and the consistent load of the linear load
//!    f(x) = f0 + (f1 − f0)·x/l, integrated exactly (h·[7/20 fa + 3/20 fb, h(fa/20 + fb/30),
//!    3/20 fa + 7/20 fb, −h(fa/30 + fb/20)]), are formed in the working precision. A is stored as
//!    a symmetric band (half-bandwidth 3).
//! 2. Friction. The dual box QP min ½λᵀSλ − z0ᵀλ, |λ_i| ≤ g_i (S = B A⁻¹ Bᵀ) is solved by the
//!    classical primal active-set method, which terminates finitely for a strictly convex QP
//!    with bound constraints, but every step is carried out in the primal: with the working set
//!    W (forces fixed at ±g, "moving") and the free set F (forces free, "stuck"), the subspace
//!    minimiser is the solution of A c = b − Bᵀλ with c_p = 0 on F and λ = ±g on W, one banded
//!    LDLᵀ solve of the full system with the stuck DOFs held at zero; the free forces are then
//!    the residuals λ_p = (b − A c)_p and the dual gradient on W is −c_p (the motion). S is
//!    never formed. A primal–dual active-set pass gives the starting working set.
//! 3. Certificate. Stationarity b − A c − Bᵀλ in the working precision, |λ_i| ≤ g_i, and the
//!    sign of the motion against the sign of the force. A motion within 2^(−precision/2) of
//!    zero (relative to max |u| resp. max |u'| over the nodes) with the force at its bound, or a
//!    stuck force within that relative distance of its bound, is reported as
//!    [`FrictionState::AtThreshold`] rather than decided by rounding.
//!
//! Sign convention as in the program: A c = b − Bᵀλ, so λ_i = g_i·sign(c_{p_i}) when the point
//! moves.

use beamfric::fem::Mesh;
use beamfric::model::Problem;

use super::mp::{DEFAULT_PRECISION, F, Mp, abs, is_negative, is_zero, max_abs, to_f64};

mod active_set;

use active_set::{ActiveSet, Outcome, Slot};

/// The friction state of one DOF (sliding or swivel) of one obstacle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrictionState {
    /// No motion, |λ| < g.
    Stuck,
    /// Motion, λ = g·sign(motion).
    Moves,
    /// |λ| = g and no motion (a tie: either answer of a stuck/moves flag is right).
    AtThreshold,
}

impl FrictionState {
    /// Is a program's moving flag right for this state?
    pub fn accepts(self, moving: bool) -> bool {
        match self {
            FrictionState::Stuck => !moving,
            FrictionState::Moves => moving,
            FrictionState::AtThreshold => true,
        }
    }

    /// A short word for reports.
    pub fn word(self) -> &'static str {
        match self {
            FrictionState::Stuck => "stuck",
            FrictionState::Moves => "moves",
            FrictionState::AtThreshold => "at-threshold",
        }
    }
}

/// What the reference checked about its own answer, in the working precision.
#[derive(Debug, Clone, PartialEq)]
pub struct Certificate {
    /// max_j |b − A c − Bᵀλ|_j / max_j (|b_j| + Σ_m |A_jm c_m| + |Bᵀλ|_j).
    pub stationarity: f64,
    /// max over obstacles of (|λ_i| − g_i)/g_i where positive (0 when every force is inside).
    pub bound_excess: f64,
    /// Every moving force has the sign of its motion, every stuck DOF has zero motion.
    pub complementarity: bool,
    /// All of the above within 2^(−precision/2).
    pub verified: bool,
}

/// The reference solution on the mesh, SI units.
#[derive(Debug, Clone)]
pub struct RefSolution {
    /// Working precision [bits].
    pub precision: usize,
    /// Node positions of the mesh [m].
    pub nodes: Vec<f64>,
    /// u at every node, ends included [m].
    pub u: Vec<F>,
    /// u' at every node, ends included [rad].
    pub slope: Vec<F>,
    /// (force [N], moment [N m]) per obstacle, A c = b − Bᵀλ.
    pub lambda: Vec<[F; 2]>,
    /// (u(x̂), u'(x̂)) per obstacle.
    pub motion: Vec<[F; 2]>,
    /// (sliding, swivel) state per obstacle.
    pub states: Vec<[FrictionState; 2]>,
    /// The regularisation ε of the problem solved (0: the exact problem (38); > 0: the
    /// ε-problem of [`super::epsilon`], where "moves" means |motion| > ε).
    pub epsilon: f64,
    pub certificate: Certificate,
    /// Linear solves used (warm start and active set).
    pub solves: usize,
}

impl RefSolution {
    /// The solution from the DOF vector `c` (u, u' of the interior nodes; the clamped ends
    /// are zero) and the friction forces `lambda` (force, moment per obstacle, in order).
    pub(super) fn package(
        (mesh, mp): (&Mesh, &Mp),
        c: &[F],
        lambda: &[F],
        (motion, states): (Vec<[F; 2]>, Vec<[FrictionState; 2]>),
        epsilon: f64,
        certificate: Certificate,
        solves: usize,
    ) -> RefSolution {
        let nodes = mesh.nodes.len();
        let at = |node: usize, kind: usize| {
            if node == 0 || node == nodes - 1 {
                mp.zero()
            } else {
                c[dof(node, kind)].clone()
            }
        };
        RefSolution {
            precision: mp.precision,
            nodes: mesh.nodes.clone(),
            u: (0..nodes).map(|node| at(node, 0)).collect(),
            slope: (0..nodes).map(|node| at(node, 1)).collect(),
            lambda: (0..motion.len())
                .map(|o| [lambda[2 * o].clone(), lambda[2 * o + 1].clone()])
                .collect(),
            motion,
            states,
            epsilon,
            certificate,
            solves,
        }
    }

    /// u at the nodes, rounded to f64.
    pub fn u_f64(&self) -> Vec<f64> {
        self.u.iter().map(to_f64).collect()
    }

    /// u' at the nodes, rounded to f64.
    pub fn slope_f64(&self) -> Vec<f64> {
        self.slope.iter().map(to_f64).collect()
    }

    /// (force, moment) per obstacle, rounded to f64.
    pub fn lambda_f64(&self) -> Vec<[f64; 2]> {
        self.lambda
            .iter()
            .map(|[a, b]| [to_f64(a), to_f64(b)])
            .collect()
    }

    /// (u(x̂), u'(x̂)) per obstacle, rounded to f64.
    pub fn motion_f64(&self) -> Vec<[f64; 2]> {
        self.motion
            .iter()
            .map(|[a, b]| [to_f64(a), to_f64(b)])
            .collect()
    }

    /// Is any obstacle DOF exactly at its threshold?
    pub fn has_tie(&self) -> bool {
        self.states
            .iter()
            .flatten()
            .any(|&s| s == FrictionState::AtThreshold)
    }
}

/// Solves `problem` on the mesh of `elements` elements in the default precision.
pub fn solve_reference(problem: &Problem, elements: usize) -> RefSolution {
    solve_reference_with(problem, &Mesh::new(problem, elements), DEFAULT_PRECISION)
        .unwrap_or_else(|e| panic!("reference solver failed: {e}"))
}

/// Solves `problem` on `mesh` in `precision` bits. Fails only if the active-set method does
/// not terminate or the band factorization meets a non-positive pivot (neither should happen).
pub fn solve_reference_with(
    problem: &Problem,
    mesh: &Mesh,
    precision: usize,
) -> Result<RefSolution, String> {
    let mp = Mp { precision };
    let system = assemble(problem, mesh, &mp);
    let friction = Friction::new(problem, mesh, &mp);
    let mut solver = ActiveSet {
        system: &system,
        friction: &friction,
        mp,
        solves: 0,
    };
    let outcome = solver.run()?;
    Ok(finish(
        problem,
        mesh,
        &system,
        &friction,
        outcome,
        &mp,
        solver.solves,
    ))
}

/// A c = b with A symmetric banded: `band[j][d]` = A[j][j + d], d = 0..=3.
pub(super) struct System {
    pub(super) band: Vec<[F; 4]>,
    pub(super) b: Vec<F>,
}

impl System {
    pub(super) fn dofs(&self) -> usize {
        self.b.len()
    }

    fn entry(&self, i: usize, j: usize) -> Option<&F> {
        let (r, c) = if i <= j { (i, j) } else { (j, i) };
        (c - r <= 3 && c < self.dofs()).then(|| &self.band[r][c - r])
    }

    /// (A c)_i and Σ_m |A_im c_m|.
    pub(super) fn row_product(&self, i: usize, c: &[F], mp: &Mp) -> (F, F) {
        let mut sum = mp.zero();
        let mut magnitude = mp.zero();
        let lo = i.saturating_sub(3);
        let hi = (i + 3).min(self.dofs() - 1);
        for j in lo..=hi {
            let term = self.entry(i, j).expect("inside the band") * &c[j];
            magnitude += abs(&term);
            sum += term;
        }
        (sum, magnitude)
    }
}

/// Index of the DOF (`kind` 0: value, 1: slope) of interior node `node`.
pub(super) fn dof(node: usize, kind: usize) -> usize {
    2 * (node - 1) + kind
}

pub(super) fn assemble(problem: &Problem, mesh: &Mesh, mp: &Mp) -> System {
    let nodes = mesh.nodes.len();
    let dofs = 2 * (nodes - 2);
    let mut band: Vec<[F; 4]> = (0..dofs)
        .map(|_| std::array::from_fn(|_| mp.zero()))
        .collect();
    let mut b: Vec<F> = (0..dofs).map(|_| mp.zero()).collect();
    let length = mp.num(problem.length);
    let f0 = mp.num(problem.load.f0);
    let df = mp.num(problem.load.f1) - &f0;
    let load = |x: &F| &f0 + &df * x / &length;
    let c = |p: f64, q: f64| mp.num(p) / mp.num(q);
    let (c12, c6, c4, c2) = (mp.num(12.0), mp.num(6.0), mp.num(4.0), mp.num(2.0));

    for e in 0..nodes - 1 {
        let (xa, xb) = (mp.num(mesh.nodes[e]), mp.num(mesh.nodes[e + 1]));
        let h = &xb - &xa;
        let ej = mp.num(mesh.bending_stiffness_of_element(e));
        let k = &ej / (&h * &h * &h);
        let (kh, kh2) = (&k * &h, &k * &h * &h);
        let m12 = &c12 * &k;
        let m6 = &c6 * &kh;
        let local: [[F; 4]; 4] = [
            [m12.clone(), m6.clone(), -m12.clone(), m6.clone()],
            [m6.clone(), &c4 * &kh2, -m6.clone(), &c2 * &kh2],
            [-m12.clone(), -m6.clone(), m12.clone(), -m6.clone()],
            [m6.clone(), &c2 * &kh2, -m6.clone(), &c4 * &kh2],
        ];
        let (fa, fb) = (load(&xa), load(&xb));
        let local_b: [F; 4] = [
            &h * (&c(7.0, 20.0) * &fa + &c(3.0, 20.0) * &fb),
            &h * &h * (&fa / mp.num(20.0) + &fb / mp.num(30.0)),
            &h * (&c(3.0, 20.0) * &fa + &c(7.0, 20.0) * &fb),
            -(&h * &h * (&fa / mp.num(30.0) + &fb / mp.num(20.0))),
        ];
        let global: [Option<usize>; 4] = [
            (e >= 1).then(|| dof(e, 0)),
            (e >= 1).then(|| dof(e, 1)),
            (e < nodes - 2).then(|| dof(e + 1, 0)),
            (e < nodes - 2).then(|| dof(e + 1, 1)),
        ];
        for a in 0..4 {
            let Some(i) = global[a] else { continue };
            b[i] += &local_b[a];
            for bb in 0..4 {
                let Some(j) = global[bb] else { continue };
                if i <= j {
                    band[i][j - i] += &local[a][bb];
                }
            }
        }
    }
    System { band, b }
}

/// Solves A c = rhs with the DOFs in `fixed` held at zero (their rows and columns replaced by
/// the identity), by a banded LDLᵀ factorization without pivoting (A is SPD).
fn solve_masked(system: &System, fixed: &[bool], rhs: &[F], mp: &Mp) -> Result<Vec<F>, String> {
    solve_banded(system, fixed, None, rhs, mp)
}

/// Solves (A + diag(`added`)) c = rhs with the DOFs in `fixed` held at zero, by the banded
/// LDLᵀ factorization of [`solve_masked`] (`added` ≥ 0 keeps the matrix SPD and the band:
/// the ε-reference adds g/ε on the diagonal of the friction DOFs in the middle region).
pub(super) fn solve_banded(
    system: &System,
    fixed: &[bool],
    added: Option<&[F]>,
    rhs: &[F],
    mp: &Mp,
) -> Result<Vec<F>, String> {
    let n = system.dofs();
    let entry = |i: usize, j: usize| -> F {
        // i ≤ j ≤ i + 3
        if fixed[i] || fixed[j] {
            if i == j { mp.num(1.0) } else { mp.zero() }
        } else {
            match added {
                Some(added) if i == j => &system.band[i][0] + &added[i],
                _ => system.band[i][j - i].clone(),
            }
        }
    };
    // lower[i][d] = L[i][i − d], d = 1..=3 (index 0 unused).
    let mut lower: Vec<[F; 4]> = (0..n).map(|_| std::array::from_fn(|_| mp.zero())).collect();
    let mut diag: Vec<F> = Vec::with_capacity(n);
    for j in 0..n {
        let mut d = entry(j, j);
        for k in j.saturating_sub(3)..j {
            let l = &lower[j][j - k];
            d -= l * l * &diag[k];
        }
        if is_negative(&d) || is_zero(&d) {
            return Err(format!("non-positive pivot at DOF {j} of {n}"));
        }
        for i in j + 1..(j + 4).min(n) {
            let mut s = entry(j, i);
            for k in i.saturating_sub(3)..j {
                s -= &lower[i][i - k] * &lower[j][j - k] * &diag[k];
            }
            lower[i][i - j] = s / &d;
        }
        diag.push(d);
    }
    let mut z: Vec<F> = Vec::with_capacity(n);
    for i in 0..n {
        let mut s = if fixed[i] { mp.zero() } else { rhs[i].clone() };
        for k in i.saturating_sub(3)..i {
            s -= &lower[i][i - k] * &z[k];
        }
        z.push(s);
    }
    let mut c: Vec<F> = (0..n).map(|_| mp.zero()).collect();
    for i in (0..n).rev() {
        let mut s = &z[i] / &diag[i];
        for m in i + 1..(i + 4).min(n) {
            s -= &lower[m][m - i] * &c[m];
        }
        c[i] = s;
    }
    Ok(c)
}

/// The 2k friction DOFs in the paper's order (g1, g2 of obstacle 1, …).
pub(super) struct Friction {
    pub(super) dof: Vec<usize>,
    pub(super) kind: Vec<usize>,
    pub(super) g: Vec<F>,
}

impl Friction {
    pub(super) fn new(problem: &Problem, mesh: &Mesh, mp: &Mp) -> Friction {
        let mut friction = Friction {
            dof: Vec::new(),
            kind: Vec::new(),
            g: Vec::new(),
        };
        for (o, &node) in problem.obstacles.iter().zip(&mesh.obstacle_nodes) {
            assert!(
                node >= 1 && node + 1 < mesh.nodes.len(),
                "obstacle on a support"
            );
            assert_eq!(mesh.nodes[node], o.x, "obstacle node is the obstacle");
            for (kind, g) in [(0, o.sliding_threshold), (1, o.swivel_threshold)] {
                friction.dof.push(dof(node, kind));
                friction.kind.push(kind);
                friction.g.push(mp.num(g));
            }
        }
        friction
    }

    pub(super) fn len(&self) -> usize {
        self.dof.len()
    }
}

/// Relative stationarity max_j |b − A c − Bᵀλ|_j / max_j (|b_j| + |A_j||c| + |λ at j|): the
/// residual of the exact problem (λ the friction forces) or of the ε-problem (λ = λ(c)).
pub(super) fn stationarity(
    system: &System,
    friction: &Friction,
    c: &[F],
    lambda: &[F],
    mp: &Mp,
) -> f64 {
    let n = system.dofs();
    let mut force_at: Vec<F> = (0..n).map(|_| mp.zero()).collect();
    for (i, l) in lambda.iter().enumerate() {
        force_at[friction.dof[i]] = l.clone();
    }
    let mut worst_residual = mp.zero();
    let mut worst_scale = mp.zero();
    for j in 0..n {
        let (product, magnitude) = system.row_product(j, c, mp);
        let residual = abs(&(&system.b[j] - product - &force_at[j]));
        let size = abs(&system.b[j]) + magnitude + abs(&force_at[j]);
        if residual > worst_residual {
            worst_residual = residual;
        }
        if size > worst_scale {
            worst_scale = size;
        }
    }
    if is_zero(&worst_residual) {
        0.0
    } else {
        to_f64(&(worst_residual / worst_scale))
    }
}

fn finish(
    problem: &Problem,
    mesh: &Mesh,
    system: &System,
    friction: &Friction,
    outcome: Outcome,
    mp: &Mp,
    solves: usize,
) -> RefSolution {
    let Outcome { c, lambda, slots } = outcome;
    let tau = mp.tie_tolerance();
    let scale = |kind: usize| max_abs(c.iter().skip(kind).step_by(2), mp);
    let motion_tolerance = [&tau * scale(0), &tau * scale(1)];

    let stationarity = stationarity(system, friction, &c, &lambda, mp);

    let mut bound_excess = 0f64;
    let mut complementarity = true;
    let mut states = Vec::with_capacity(problem.obstacles.len());
    let mut motion = Vec::with_capacity(problem.obstacles.len());
    for o in 0..problem.obstacles.len() {
        let mut pair = [FrictionState::Stuck; 2];
        for kind in 0..2 {
            let i = 2 * o + kind;
            let g = &friction.g[i];
            let y = &c[friction.dof[i]];
            let l = &lambda[i];
            let excess = abs(l) - g;
            if !is_negative(&excess) && !is_zero(&excess) {
                let relative = if is_zero(g) {
                    f64::INFINITY
                } else {
                    to_f64(&(&excess / g))
                };
                bound_excess = bound_excess.max(relative);
            }
            let tiny_motion = abs(y) <= motion_tolerance[kind];
            pair[kind] = match slots[i] {
                Slot::Bound(plus) => {
                    if tiny_motion {
                        FrictionState::AtThreshold
                    } else {
                        // A zero threshold takes any sign of motion (λ = 0).
                        if is_negative(y) == plus && !is_zero(g) {
                            complementarity = false;
                        }
                        FrictionState::Moves
                    }
                }
                Slot::Free => {
                    if !is_zero(y) {
                        complementarity = false;
                    }
                    if abs(l) >= g - &tau * g {
                        FrictionState::AtThreshold
                    } else {
                        FrictionState::Stuck
                    }
                }
            };
        }
        states.push(pair);
        let node = mesh.obstacle_nodes[o];
        motion.push([c[dof(node, 0)].clone(), c[dof(node, 1)].clone()]);
    }
    let tolerance = to_f64(&tau);
    let verified = stationarity <= tolerance && bound_excess <= tolerance && complementarity;

    RefSolution::package(
        (mesh, mp),
        &c,
        &lambda,
        (motion, states),
        0.0,
        Certificate {
            stationarity,
            bound_excess,
            complementarity,
            verified,
        },
        solves,
    )
}
