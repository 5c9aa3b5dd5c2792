//! The independent half of the certificate: the KKT conditions of (38) checked from the exact
//! local solutions of the pieces between special points, and the friction state of every DOF
//! decided from the force at its bound and the motion (issue 10).
//!
//! **Why not the method's own matrix.** A residual A c − b + Bᵀλ computed with the rounded A a
//! method used cannot see the error that rounding caused, and relative to ‖A‖‖c‖ it is tiny
//! whenever one short or stiff piece makes ‖A‖ huge. Here every piece between special points
//! (supports, obstacles, segment ends) is one exact macro element: EJ is constant and f linear
//! on it, so the Hermite element on the whole piece gives the exact end forces of the exact
//! local solution from the piece's end values (docs/design.md fact 1). Equilibrium is then
//! checked at every special point, and as a rigid-body balance (force, and moment about its
//! left end) of every run of up to [`CLUSTER`] consecutive special points, in which the forces
//! inside the run cancel algebraically: the internal force of a piece 1e-9·l long is a
//! difference of nearly equal values times 1e27 and pure noise, the balance of its two ends is
//! not. Every check is relative to the sum of the absolute values of its own terms (including
//! |K||c|, what one rounding of c moves the forces by), so it lies in [0, 1] and is never a
//! ratio of noise to noise. Interior nodes are checked against their piece's exact solution.
//! Everything is made dimensionless first by powers of two (exact), so loads of 1e-300 or
//! 1e300 neither underflow to a zero residual nor overflow.
//!
//! **States.** A DOF moves when |c| exceeds what rounding resolves: a few ulps of the local
//! magnitudes (the values on the two adjacent pieces), or more when the method's own rounding
//! is known to be larger (`motion_resolution`, relative to the largest value of its kind). A DOF
//! that does not move is stuck when |λ| is below its threshold by more than rounding of the
//! local forces, and "at the threshold" otherwise: both descriptions fit. For the regularised
//! methods the motion must also exceed ε, and complementarity is that of the ε-problem,
//! λ = g·clamp(c/ε, −1, 1); a DOF below ε is "at the threshold" when |λ| = g is within both
//! the unresolved motion turned into force (g/ε times it) and the method's relative loss on
//! the forces meeting there; the smaller of the two, relative to the largest force of its
//! kind, is what the certificate reports as the regularised forces' uncertainty
//! (`accuracy-loss` above 1e-8).

use crate::fem::{Mesh, NodalField};
use crate::fem::{element_load, element_stiffness};
use crate::linalg::parallel::run_jobs;
use crate::model::Problem;
use crate::solve::FrictionState;

/// Longest run of consecutive special points balanced as one rigid body.
const CLUSTER: usize = 3;

/// Ulps of the local magnitudes within which a motion is not resolved.
const MOTION_ULPS: f64 = 64.0;

/// Ulps of the local forces within which |λ| = g (at the threshold).
const FORCE_ULPS: f64 = 64.0;

/// What the certificate learns from the pieces.
#[derive(Debug, Clone, PartialEq)]
pub(in crate::solve) struct Equilibrium {
    /// Relative KKT residual in [0, 1]; NaN when the field or forces are not finite.
    pub residual: f64,
    /// (sliding, swivel) state per obstacle.
    pub states: Vec<[FrictionState; 2]>,
    /// For a regularised method: the largest uncertainty of a force g·c/ε of a DOF inside ε
    /// (the unresolved part of c turned into force, at most the method's relative loss on the
    /// forces meeting there), relative to the largest force of its kind (or |f|·l, |f|·l²);
    /// 0 for the exact methods.
    pub unresolved_force: f64,
}

/// How a method's answer is judged.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(in crate::solve) struct Judging {
    /// The method's own rounding of c relative to the largest |u| and |u'| (0 when it is no
    /// more than a few ulps of the local values).
    pub motion_resolution: f64,
    /// ε of a regularised method.
    pub epsilon: Option<f64>,
}

/// 2^k·x without intermediate overflow or underflow.
fn scaled(x: f64, k: i32) -> f64 {
    if (-500..=500).contains(&k) {
        // 2^k from its bits: the same exact factor as powi, without a call per value (this
        // runs for every node).
        return x * f64::from_bits(((k + 1023) as u64) << 52);
    }
    let mut value = x;
    let mut k = k;
    while k > 500 {
        value *= 2f64.powi(500);
        k -= 500;
    }
    while k < -500 {
        value *= 2f64.powi(-500);
        k += 500;
    }
    value * 2f64.powi(k)
}

/// The binary exponent of a positive finite x (0 for anything else).
fn exponent(x: f64) -> i32 {
    if x > 0.0 && x.is_finite() {
        x.log2().round() as i32
    } else {
        0
    }
}

/// Nodal values in dimensionless units: 2^exponent times the SI values, read through one exact
/// factor (or, when 2^exponent is not a normal number, a scaled copy).
struct Dimensionless<'a> {
    values: std::borrow::Cow<'a, [f64]>,
    factor: f64,
}

impl<'a> Dimensionless<'a> {
    fn new(values: &'a [f64], exponent: i32) -> Dimensionless<'a> {
        if (-1000..=1000).contains(&exponent) {
            Dimensionless {
                values: values.into(),
                factor: scaled(1.0, exponent),
            }
        } else {
            Dimensionless {
                values: values.iter().map(|&v| scaled(v, exponent)).collect(),
                factor: 1.0,
            }
        }
    }
    fn at(&self, node: usize) -> f64 {
        self.values[node] * self.factor
    }
    /// The largest |value| over `nodes`.
    fn largest(&self, nodes: std::ops::RangeInclusive<usize>) -> f64 {
        self.values[nodes]
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()))
            * self.factor
    }
    /// The values of `nodes` in SI units and the factor to dimensionless units.
    fn raw(&self, nodes: std::ops::Range<usize>) -> (&[f64], f64) {
        (&self.values[nodes], self.factor)
    }
}

/// The problem in dimensionless units: every scale a power of two.
struct Units {
    length: i32,
    stiffness: i32,
    load: i32,
}

impl Units {
    fn of(problem: &Problem) -> Units {
        let l = problem.length;
        let ej = problem
            .stiffness
            .iter()
            .fold(0.0f64, |m, p| m.max(p.bending_stiffness));
        let f = problem.load.f0.abs().max(problem.load.f1.abs());
        let g = problem.obstacles.iter().fold(0.0f64, |m, o| {
            m.max(o.sliding_threshold / l)
                .max(o.swivel_threshold / (l * l))
        });
        let load = if f > 0.0 { f } else { g };
        Units {
            length: exponent(l),
            stiffness: exponent(ej),
            load: exponent(load),
        }
    }
    fn x(&self, x: f64) -> f64 {
        scaled(x, -self.length)
    }
    fn ej(&self, ej: f64) -> f64 {
        scaled(ej, -self.stiffness)
    }
    fn f(&self, f: f64) -> f64 {
        scaled(f, -self.load)
    }
    fn u_exponent(&self) -> i32 {
        self.stiffness - self.load - 4 * self.length
    }
    fn slope_exponent(&self) -> i32 {
        self.stiffness - self.load - 3 * self.length
    }
    /// u over F L⁴ / EJ.
    fn u(&self, u: f64) -> f64 {
        scaled(u, self.u_exponent())
    }
    /// u' over F L³ / EJ.
    fn slope(&self, t: f64) -> f64 {
        scaled(t, self.slope_exponent())
    }
    /// λ1 over F L, λ2 over F L².
    fn force(&self, v: f64, kind: usize) -> f64 {
        scaled(v, -self.load - (1 + kind as i32) * self.length)
    }
}

/// The exact end forces of one piece (rows u_a, u'_a, u_b, u'_b of K c − f) and the sums of
/// the absolute values of their terms, in dimensionless units.
struct PieceForces {
    forces: [f64; 4],
    magnitude: [f64; 4],
    /// The rows of the load alone.
    load: [f64; 4],
    a: f64,
    b: f64,
}

/// A relative residual: |r| / scale, in [0, 1]; 1 when the numbers overflowed.
fn relative(r: f64, scale: f64) -> f64 {
    if !r.is_finite() || !scale.is_finite() {
        1.0
    } else if scale > 0.0 {
        (r.abs() / scale).min(1.0)
    } else {
        0.0
    }
}

/// Checks (38) piece by piece and decides the friction states (module doc).
pub(in crate::solve) fn check(
    problem: &Problem,
    mesh: &Mesh,
    field: &NodalField,
    lambda: &[[f64; 2]],
    judging: Judging,
) -> Equilibrium {
    let k = problem.obstacles.len();
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    if !finite(&field.deflection) || !finite(&field.slope) || !lambda.iter().all(|l| finite(l)) {
        return Equilibrium {
            residual: f64::NAN,
            states: vec![[FrictionState::AtThreshold; 2]; k],
            unresolved_force: 0.0,
        };
    }
    let units = Units::of(problem);
    // The nodal values in dimensionless units, read through one exact factor each (no copies
    // of 10⁶ values: allocating them cost more than the check).
    let u = Dimensionless::new(&field.deflection, units.u_exponent());
    let t = Dimensionless::new(&field.slope, units.slope_exponent());
    let x = |node: usize| units.x(mesh.nodes[node]);
    let lam: Vec<[f64; 2]> = lambda
        .iter()
        .map(|l| [units.force(l[0], 0), units.force(l[1], 1)])
        .collect();
    let g: Vec<[f64; 2]> = problem
        .obstacles
        .iter()
        .map(|o| {
            [
                units.force(o.sliding_threshold, 0),
                units.force(o.swivel_threshold, 1),
            ]
            // A threshold past the largest double in these units (1e20 N against loads of
            // 1e-300) is one no force reaches: the largest double says the same without an
            // infinity that would make every scale infinite.
            .map(|g| g.min(f64::MAX))
        })
        .collect();
    // What the SI values themselves can carry: below the smallest normal double (2^-1022 m,
    // rad, N, N m) a value has fewer than 53 bits, so an absolute 2^-1022 is its rounding.
    let subnormal = [units.u(f64::MIN_POSITIVE), units.slope(f64::MIN_POSITIVE)];
    let subnormal_force = [
        units.force(f64::MIN_POSITIVE, 0),
        units.force(f64::MIN_POSITIVE, 1),
    ];
    let load_at = |node: usize| units.f(problem.load_at(mesh.nodes[node]));

    // The largest |u| and |u'| on each piece, in one pass over its nodes.
    let piece_largest: Vec<[f64; 2]> = mesh
        .pieces
        .iter()
        .map(|p| {
            let nodes = p.first_node..=p.last_node;
            [u.largest(nodes.clone()), t.largest(nodes)]
        })
        .collect();
    // The magnitude of (u, u') on each piece, each kind also seen through the other.
    let piece_magnitude: Vec<[f64; 2]> = mesh
        .pieces
        .iter()
        .zip(&piece_largest)
        .map(|(p, &[mu, mt])| {
            let length = x(p.last_node) - x(p.first_node);
            // Never below what the SI values carry: an ulp of it is their subnormal rounding.
            [
                mu.max(mt * length).max(subnormal[0] / f64::EPSILON),
                mt.max(mu / length).max(subnormal[1] / f64::EPSILON),
            ]
        })
        .collect();
    // What rounding leaves unresolved in (u, u') at each special point: an ulp of the local
    // magnitudes on both sides (a value of 1e-20 next to values of 1 is not known to 1e-36).
    let special_noise: Vec<[f64; 2]> = (0..=mesh.pieces.len())
        .map(|s| {
            let left = s.checked_sub(1).map_or([0.0; 2], |p| piece_magnitude[p]);
            let right = piece_magnitude.get(s).copied().unwrap_or([0.0; 2]);
            [
                f64::EPSILON * left[0].max(right[0]),
                f64::EPSILON * left[1].max(right[1]),
            ]
        })
        .collect();
    let pieces: Vec<PieceForces> = mesh
        .pieces
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let (a, b) = (p.first_node, p.last_node);
            let length = x(b) - x(a);
            let stiffness = element_stiffness(units.ej(p.bending_stiffness), length);
            let load = element_load(length, load_at(a), load_at(b));
            let c = [u.at(a), t.at(a), u.at(b), t.at(b)];
            let (na, nb) = (special_noise[i], special_noise[i + 1]);
            let noise = [na[0], na[1], nb[0], nb[1]];
            let mut forces = [0.0; 4];
            let mut magnitude = [0.0; 4];
            for r in 0..4 {
                let mut sum = -load[r];
                let mut abs = load[r].abs();
                for j in 0..4 {
                    sum += stiffness[r][j] * c[j];
                    abs += stiffness[r][j].abs() * (c[j].abs() + noise[j]);
                }
                forces[r] = sum;
                magnitude[r] = abs;
            }
            PieceForces {
                forces,
                magnitude,
                load,
                a: x(a),
                b: x(b),
            }
        })
        .collect();

    // Special point s (1..pieces.len() − 1 are interior) is the start of piece s.
    let special_of = |node: usize| {
        let s = mesh.pieces.partition_point(|p| p.first_node < node);
        (s < mesh.pieces.len() && mesh.pieces[s].first_node == node).then_some(s)
    };
    let mut obstacle_at: Vec<Option<usize>> = vec![None; mesh.pieces.len() + 1];
    for (j, &node) in mesh.obstacle_nodes.iter().enumerate() {
        if let Some(s) = special_of(node) {
            obstacle_at[s] = Some(j);
        }
    }
    let mut residual = 0.0f64;
    let specials = mesh.pieces.len() + 1;
    for first in 1..specials.saturating_sub(1) {
        for last in first..(first + CLUSTER).min(specials - 1) {
            let (left, right) = (&pieces[first - 1], &pieces[last]);
            let x0 = left.b;
            let arm = right.a - x0;
            let mut force = left.forces[2] + right.forces[0];
            let mut force_scale = left.magnitude[2] + right.magnitude[0];
            let mut moment = left.forces[3] + right.forces[1] + arm * right.forces[0];
            let mut moment_scale =
                left.magnitude[3] + right.magnitude[1] + arm * right.magnitude[0];
            for inner in &pieces[first..last] {
                let l = &inner.load;
                force -= l[0] + l[2];
                force_scale += l[0].abs() + l[2].abs();
                let terms = [l[1], l[3], (inner.a - x0) * l[0], (inner.b - x0) * l[2]];
                moment -= terms.iter().sum::<f64>();
                moment_scale += terms.iter().map(|v| v.abs()).sum::<f64>();
            }
            for (s, at) in obstacle_at.iter().enumerate().take(last + 1).skip(first) {
                if let Some(j) = *at {
                    let arm = pieces[s].a - x0;
                    force += lam[j][0];
                    force_scale += lam[j][0].abs() + subnormal_force[0];
                    moment += lam[j][1] + arm * lam[j][0];
                    moment_scale += lam[j][1].abs()
                        + subnormal_force[1]
                        + (arm * (lam[j][0].abs() + subnormal_force[0]));
                }
            }
            residual = residual
                .max(relative(force, force_scale))
                .max(relative(moment, moment_scale));
        }
    }
    residual = residual.max(interior_residual(
        mesh,
        (&u, &t),
        &piece_magnitude,
        &units,
        problem,
    ));

    // Local magnitudes of each kind around every special point.
    // The largest value of each kind, each kind also seen through the other (u/l, u'·l): in
    // dimensionless units l is 1 up to a power of two.
    // Floored by the natural scales f l⁴/EJ and f l³/EJ (stiffest stretch): when every value
    // of a kind is rounding noise (all stuck), the noise is no yardstick.
    let span = x(mesh.nodes.len() - 1) - x(0);
    let natural = {
        let f = units
            .f(problem.load.f0)
            .abs()
            .max(units.f(problem.load.f1).abs());
        let ej = problem
            .stiffness
            .iter()
            .fold(0.0f64, |m, p| m.max(units.ej(p.bending_stiffness)));
        if ej > 0.0 { f * span.powi(3) / ej } else { 0.0 }
    };
    let [largest_u, largest_t] = piece_largest
        .iter()
        .fold([0.0f64; 2], |m, l| [m[0].max(l[0]), m[1].max(l[1])]);
    let global = [
        largest_u.max(largest_t * span).max(natural * span),
        largest_t.max(largest_u / span).max(natural),
    ];
    // The largest force of each kind, or the load's natural force and moment over the span.
    let kind_scale: [f64; 2] = {
        let f = units
            .f(problem.load.f0)
            .abs()
            .max(units.f(problem.load.f1).abs());
        [0, 1].map(|d| {
            lam.iter()
                .fold(f * span.powi(d as i32 + 1), |m, l| m.max(l[d].abs()))
        })
    };
    let mut unresolved_force = 0.0f64;
    let mut states = Vec::with_capacity(k);
    for (j, &node) in mesh.obstacle_nodes.iter().enumerate() {
        let Some(s) = special_of(node).filter(|&s| s > 0) else {
            states.push([FrictionState::AtThreshold; 2]);
            continue;
        };
        let around = [&mesh.pieces[s - 1], &mesh.pieces[s]];
        let (mut local_u, mut local_t, mut longest) = (0.0f64, 0.0f64, 0.0f64);
        for (p, [mu, mt]) in around
            .into_iter()
            .zip([piece_largest[s - 1], piece_largest[s]])
        {
            local_u = local_u.max(mu);
            local_t = local_t.max(mt);
            longest = longest.max(x(p.last_node) - x(p.first_node));
        }
        let f = load_at(node).abs();
        let ej = units.ej(around[0].bending_stiffness.min(around[1].bending_stiffness));
        let local = [
            local_u
                .max(local_t * longest)
                .max(f * longest.powi(4) / ej / 384.0)
                .max(subnormal[0] / f64::EPSILON),
            local_t
                .max(local_u / longest)
                .max(f * longest.powi(3) / ej / 120.0)
                .max(subnormal[1] / f64::EPSILON),
        ];
        // The forces that meet at the point: what λ is computed against.
        let (left, right) = (&pieces[s - 1], &pieces[s]);
        let meeting = [
            left.forces[2].abs() + right.forces[0].abs(),
            left.forces[3].abs() + right.forces[1].abs(),
        ];
        // The same with every term of the two pieces' end forces at its own size (K c and the
        // load before they cancel): what a relative loss of the method is a loss of.
        let meeting_terms = [
            left.magnitude[2] + right.magnitude[0],
            left.magnitude[3] + right.magnitude[1],
        ];
        let c = [u.at(node), t.at(node)];
        let mut pair = [FrictionState::Stuck; 2];
        for d in 0..2 {
            let (c, l, g) = (c[d], lam[j][d], g[j][d]);
            let motion_tolerance =
                (MOTION_ULPS * f64::EPSILON * local[d]).max(judging.motion_resolution * global[d]);
            let epsilon = judging
                .epsilon
                .map_or(0.0, |e| [units.u(e), units.slope(e)][d]);
            let force_scale = g
                .max(l.abs())
                .max(meeting[d])
                .max(subnormal_force[d] / f64::EPSILON);
            let mut force_tolerance = FORCE_ULPS * f64::EPSILON * force_scale;
            if epsilon > 0.0 {
                // A regularised method's λ = g·c/ε is as uncertain as its c near ε (the unresolved
                // motion turned into force) and as its equilibrium (its relative loss on the
                // forces meeting here). Only when both leave |λ| = g open is a stuck DOF "at the
                // threshold": each alone is pessimistic, for large deflections or large forces.
                let through_motion = g / epsilon * motion_tolerance;
                let through_forces = judging.motion_resolution * force_scale;
                force_tolerance = force_tolerance.max(through_motion.min(through_forces));
                if c.abs() <= epsilon + motion_tolerance && kind_scale[d] > 0.0 {
                    // Inside ε the force is g·c/ε: as uncertain as c, and as the equilibrium
                    // of the forces meeting here (not of g, which may be far larger).
                    let uncertain = through_motion
                        .min(judging.motion_resolution * meeting_terms[d].max(l.abs()));
                    unresolved_force = unresolved_force.max(uncertain / kind_scale[d]);
                }
            }
            // Feasibility |λ| ≤ g.
            residual = residual.max(relative((l.abs() - g).max(0.0), force_scale));
            let moves = c.abs() > motion_tolerance + epsilon;
            // Complementarity: the force a moving DOF (or the ε-problem) prescribes.
            let prescribed = if judging.epsilon.is_some() && epsilon > 0.0 {
                Some(g * (c / epsilon).clamp(-1.0, 1.0))
            } else if moves {
                Some(g * c.signum())
            } else {
                None
            };
            if let Some(p) = prescribed {
                let violation = if epsilon > 0.0 {
                    // g·c/ε turns the unresolved part of c into a force of (g/ε)·tolerance.
                    let unresolved = g / epsilon * motion_tolerance;
                    relative(((l - p).abs() - unresolved).max(0.0), force_scale)
                } else {
                    // The natural residual of complementarity: the smaller relative change, of
                    // λ to g·sign c or of c to zero (then |λ| ≤ g, checked above, is enough),
                    // that makes the pair consistent. A motion of a few ulps with the other
                    // sign than λ is then a residual of a few ulps, not of 2g; a real wrong
                    // state (a motion well above rounding against λ, or a force off its bound)
                    // is as large as before.
                    relative((l - p).abs(), force_scale).min(relative(c, local[d]))
                };
                residual = residual.max(violation);
            }
            pair[d] = if moves {
                FrictionState::Moves
            } else if g - l.abs() <= force_tolerance {
                FrictionState::AtThreshold
            } else {
                FrictionState::Stuck
            };
        }
        states.push(pair);
    }
    Equilibrium {
        residual,
        states,
        unresolved_force,
    }
}

/// The largest relative difference between an interior node and its piece's exact local
/// solution (Hermite interpolation of the end values plus the clamped–clamped response to
/// the linear load), value and slope.
fn interior_residual(
    mesh: &Mesh,
    (u, t): (&Dimensionless, &Dimensionless),
    magnitude: &[[f64; 2]],
    units: &Units,
    problem: &Problem,
) -> f64 {
    // Stretches of at most CHUNK interior nodes of one piece, shared out over two threads when
    // there are many (linalg::parallel decides).
    const CHUNK: usize = 1 << 16;
    let jobs: Vec<(usize, std::ops::Range<usize>)> = mesh
        .pieces
        .iter()
        .enumerate()
        .filter(|(_, p)| p.elements() >= 2)
        .flat_map(|(piece, p)| {
            (p.first_node + 1..p.last_node)
                .step_by(CHUNK)
                .map(move |start| (piece, start..(start + CHUNK).min(p.last_node)))
        })
        .collect();
    let results = run_jobs(
        jobs,
        |(_, range)| range.len(),
        |(piece, range)| {
            stretch_residual(
                mesh,
                (u, t),
                magnitude[piece],
                units,
                problem,
                (piece, range),
            )
        },
    );
    let overflow = results.iter().any(|&(_, overflow)| overflow);
    let worst = results.iter().fold(0.0f64, |m, &(w, _)| m.max(w));
    if overflow { 1.0 } else { worst.min(1.0) }
}

/// [`interior_residual`] on the interior nodes `range` of piece `piece`: the largest relative
/// difference, and whether a scale overflowed (the residual is then 1, as `relative` says).
fn stretch_residual(
    mesh: &Mesh,
    (u, t): (&Dimensionless, &Dimensionless),
    [u_piece, t_piece]: [f64; 2],
    units: &Units,
    problem: &Problem,
    (piece, range): (usize, std::ops::Range<usize>),
) -> (f64, bool) {
    let mut worst = 0.0f64;
    let mut overflow = false;
    let p = &mesh.pieces[piece];
    let (a, b) = (p.first_node, p.last_node);
    let (xa, xb) = (mesh.nodes[a], mesh.nodes[b]);
    let length = units.x(xb) - units.x(xa);
    let ej = units.ej(p.bending_stiffness);
    let (fa, fb) = (units.f(problem.load_at(xa)), units.f(problem.load_at(xb)));
    let (ua, ta, ub, tb) = (u.at(a), t.at(a), u.at(b), t.at(b));
    // Clamped–clamped response to f = fa (1 − ξ) + fb ξ: L⁴/EJ (fa P(1 − ξ) + fb P(ξ)),
    // P(s) = s²(1 − s)²(s + 2)/120, P'(s) = −s(1 − s)(5s² + 5s − 4)/120: below with the
    // constant factors taken out of the loop.
    let l4 = (length * length) * (length * length) / ej;
    let (value_a, value_b) = (l4 / 120.0 * fa, l4 / 120.0 * fb);
    let (slope_a, slope_b) = (value_a / length, value_b / length);
    let (six_per_length, h) = (6.0 / length, length);
    let per_length = 1.0 / (xb - xa);
    let (u_raw, u_scale) = u.raw(range.clone());
    let (t_raw, t_scale) = t.raw(range.clone());
    let nodes = &mesh.nodes[range];
    for ((&x, &u_si), &t_si) in nodes.iter().zip(u_raw).zip(t_raw) {
        // ξ and 1 − ξ each from its own end: no cancellation next to either end. The
        // Hermite basis in factored form: each function to a few ulps of its own value.
        let (xi, eta) = ((x - xa) * per_length, (xb - x) * per_length);
        let (xi2, eta2, xe) = (xi * xi, eta * eta, xi * eta);
        let value_terms = [
            eta2 * (1.0 + 2.0 * xi) * ua,
            h * xe * eta * ta,
            xi2 * (1.0 + 2.0 * eta) * ub,
            -h * xe * xi * tb,
            value_a * xe * xe * (eta + 2.0),
            value_b * xe * xe * (xi + 2.0),
        ];
        let slope_terms = [
            -six_per_length * xe * ua,
            eta * (eta - 2.0 * xi) * ta,
            six_per_length * xe * ub,
            xi * (xi - 2.0 * eta) * tb,
            slope_a * xe * (5.0 * eta2 + 5.0 * eta - 4.0),
            -slope_b * xe * (5.0 * xi2 + 5.0 * xi - 4.0),
        ];
        for (terms, value, piece_scale) in [
            (value_terms, u_si * u_scale, u_piece),
            (slope_terms, t_si * t_scale, t_piece),
        ] {
            let exact: f64 = terms.iter().sum();
            // Relative to the piece's own magnitude too: a method resolves a value near a
            // clamped end to an ulp of the piece's values, not of that small value.
            let scale: f64 = terms.iter().map(|v| v.abs()).sum::<f64>() + value.abs() + piece_scale;
            overflow |= !scale.is_finite();
            // 0/0 (everything zero) is NaN, which max ignores: a residual of 0.
            worst = worst.max((value - exact).abs() / scale);
        }
    }
    (worst, overflow)
}
