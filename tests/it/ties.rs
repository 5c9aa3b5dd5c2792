//! Honest flags at ties (issue 26): Benchmark 1 and Benchmark 3 with thresholds set to the
//! stuck forces of the 384-bit reference (`tests/it/reference`), rounded to f64, one ulp above
//! and below, and to six significant digits as a scene file would hold them — every DOF at once
//! (its force with every obstacle stuck) and one DOF at a time (its force with the preset's
//! other thresholds). On each variant the reference decides every state exactly, and every
//! method is held to the acceptance rule, one test per method:
//!
//! - no method claims a motion (`slides`, `swivels`) where the reference is stuck;
//! - no exact method claims `stuck` where the reference moves, however little: its own error
//!   bounds (`solve::friction_accuracy`) leave such a DOF "at the threshold";
//! - a regularised method may hold a motion below its O(ε) accuracy stuck (the ε-problem holds
//!   every motion below ε, by design), never a larger one.
//!
//! And ordinary thresholds keep their states: Benchmark 1 with g1, g2 ∈ {1e2, 5e4} reads
//! stuck, slides, swivels, slides and swivels for every method.

use std::sync::OnceLock;

use beamfric::fem::Mesh;
use beamfric::model::Problem;
use beamfric::solve::{FrictionState as Claimed, Method, Solution, SolveOptions, solve};

use crate::harness::scenes::{preset_scene, problem};
use crate::reference::{FrictionState as Truth, RefSolution, solve_reference};

/// A threshold no force of these scenes reaches: every DOF stuck.
const HUGE: f64 = 1e20;

/// The meshes: small enough for the reference to be quick, large enough for the stiffness
/// route to lose digits (cond(A) grows like n⁴).
const MESHES: [usize; 2] = [20, 200];

/// The regularised methods' stated accuracy on a motion, in units of ε (m for u with l = 1 m,
/// rad for u'): the certificate test's "what ε explains" (tests/it/certificate.rs).
const REGULARIZED_MOTION: f64 = 4.0;

/// How a stuck force becomes a threshold.
#[derive(Debug, Clone, Copy)]
enum Rounding {
    /// The force rounded to f64.
    Nearest,
    /// One ulp above: stuck.
    UlpAbove,
    /// One ulp below: moves, by rounding's worth.
    UlpBelow,
    /// Six significant digits, as a scene file would hold it.
    Decimal,
}

const ROUNDINGS: [Rounding; 4] = [
    Rounding::Nearest,
    Rounding::UlpAbove,
    Rounding::UlpBelow,
    Rounding::Decimal,
];

impl Rounding {
    fn threshold(self, force: f64) -> f64 {
        let force = force.abs();
        match self {
            Rounding::Nearest => force,
            Rounding::UlpAbove => force.next_up(),
            Rounding::UlpBelow => force.next_down(),
            Rounding::Decimal => format!("{force:.5e}").parse().expect("a number"),
        }
    }
}

/// One tie variant and what the reference says about it.
struct TieCase {
    name: String,
    problem: Problem,
    elements: usize,
    reference: RefSolution,
}

fn set_threshold(problem: &mut Problem, (j, d): (usize, usize), g: f64) {
    let o = &mut problem.obstacles[j];
    if d == 0 {
        o.sliding_threshold = g;
    } else {
        o.swivel_threshold = g;
    }
}

/// Every DOF of `problem`, (obstacle, kind).
fn dofs(problem: &Problem) -> Vec<(usize, usize)> {
    (0..problem.obstacles.len())
        .flat_map(|j| [(j, 0), (j, 1)])
        .collect()
}

/// The tie variants of a preset on `elements` elements, each with its reference.
fn tie_cases(preset: &str, elements: usize) -> Vec<TieCase> {
    let base = problem(&preset_scene(preset));
    let mut variants = Vec::new();
    // Every DOF at once, at its force with every obstacle stuck.
    let mut stuck = base.clone();
    for dof in dofs(&base) {
        set_threshold(&mut stuck, dof, HUGE);
    }
    let forces = solve_reference(&stuck, elements).lambda_f64();
    for rounding in ROUNDINGS {
        let mut p = stuck.clone();
        for (j, d) in dofs(&base) {
            set_threshold(&mut p, (j, d), rounding.threshold(forces[j][d]));
        }
        variants.push((format!("{preset}, n = {elements}, all {rounding:?}"), p));
    }
    // One DOF at a time, at its force with the preset's other thresholds.
    for (j, d) in dofs(&base) {
        let mut held = base.clone();
        set_threshold(&mut held, (j, d), HUGE);
        let force = solve_reference(&held, elements).lambda_f64()[j][d];
        for rounding in ROUNDINGS {
            let mut p = held.clone();
            set_threshold(&mut p, (j, d), rounding.threshold(force));
            let what = format!(
                "{preset}, n = {elements}, obstacle {} kind {d} {rounding:?}",
                j + 1
            );
            variants.push((what, p));
        }
    }
    variants
        .into_iter()
        .map(|(name, problem)| TieCase {
            reference: solve_reference(&problem, elements),
            name,
            problem,
            elements,
        })
        .collect()
}

/// Every tie case, solved by the reference once for all the tests.
fn cases() -> &'static [TieCase] {
    static CASES: OnceLock<Vec<TieCase>> = OnceLock::new();
    CASES.get_or_init(|| {
        ["benchmark-1", "benchmark-3"]
            .into_iter()
            .flat_map(|preset| MESHES.map(|n| (preset, n)))
            .flat_map(|(preset, n)| tie_cases(preset, n))
            .collect()
    })
}

/// The reference's states are exact decisions: a tie of the f64 thresholds is rare but real.
#[test]
fn the_tie_variants_are_decided_by_the_reference() {
    let cases = cases();
    let states: Vec<Truth> = cases
        .iter()
        .flat_map(|c| c.reference.states.iter().flatten().copied())
        .collect();
    for case in cases {
        assert!(case.reference.certificate.verified, "{}", case.name);
    }
    // Both sides of every tie occur: stuck one ulp above, moving one ulp below.
    assert!(states.contains(&Truth::Stuck) && states.contains(&Truth::Moves));
}

/// What went wrong with `solution` on `case`, one line per DOF: a motion claimed where the
/// reference is stuck, or `stuck` claimed where it moves by more than `stuck_allowed` (u, u').
fn dishonest_states(case: &TieCase, solution: &Solution, stuck_allowed: [f64; 2]) -> Vec<String> {
    let reference = &case.reference;
    let motion = reference.motion_f64();
    let mut wrong = Vec::new();
    for (j, o) in solution.obstacles.iter().enumerate() {
        for (d, claimed) in [o.sliding_state, o.swivel_state].into_iter().enumerate() {
            let truth = reference.states[j][d];
            let dishonest = match (claimed, truth) {
                (Claimed::Moves, Truth::Stuck) => true,
                (Claimed::Stuck, Truth::Moves) => motion[j][d].abs() > stuck_allowed[d],
                _ => false,
            };
            if dishonest {
                wrong.push(format!(
                    "{}: {}: obstacle {} kind {d} claims {claimed:?} ({}), reference {} with \
                     motion {:e}",
                    case.name,
                    solution.method,
                    j + 1,
                    o.state(),
                    truth.word(),
                    motion[j][d]
                ));
            }
        }
    }
    wrong
}

/// `method` on every tie case it applies to, with `options`: the acceptance rule (module doc),
/// a `stuck` tolerated only for motions up to `stuck_allowed`. Returns how many cases it solved.
fn check_method(method: Method, options: &SolveOptions, stuck_allowed: [f64; 2]) -> usize {
    let mut wrong = Vec::new();
    let mut solved = 0;
    for case in cases() {
        let mesh = Mesh::new(&case.problem, case.elements);
        match solve(&case.problem, &mesh, method, options) {
            Ok(solution) => {
                solved += 1;
                wrong.extend(dishonest_states(case, &solution, stuck_allowed));
            }
            Err(e) => assert!(
                method == Method::ClosedForm && case.problem.obstacles.len() > 1,
                "{}: {method} failed: {e}",
                case.name
            ),
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    solved
}

/// An exact method never claims `stuck` where the reference moves.
fn check_exact(method: Method) -> usize {
    check_method(method, &SolveOptions::default(), [0.0; 2])
}

/// A regularised method at two ε: a `stuck` only below its O(ε) accuracy.
fn check_regularized(method: Method) {
    for epsilon in [1e-6, 1e-10] {
        let options = SolveOptions {
            epsilon,
            ..SolveOptions::default()
        };
        let allowed = REGULARIZED_MOTION * epsilon;
        let solved = check_method(method, &options, [allowed; 2]);
        assert_eq!(solved, cases().len());
    }
}

#[test]
fn condensed_is_honest_at_ties() {
    assert_eq!(check_exact(Method::Condensed), cases().len());
}

#[test]
fn closed_form_is_honest_at_ties() {
    let one_obstacle = cases()
        .iter()
        .filter(|c| c.problem.obstacles.len() == 1)
        .count();
    assert_eq!(check_exact(Method::ClosedForm), one_obstacle);
}

#[test]
fn flexibility_is_honest_at_ties() {
    assert_eq!(check_exact(Method::Flexibility), cases().len());
}

#[test]
fn dual_is_honest_at_ties() {
    assert_eq!(check_exact(Method::Dual), cases().len());
}

#[test]
fn dual_inverse_is_honest_at_ties() {
    assert_eq!(check_exact(Method::DualInverse), cases().len());
}

#[test]
fn regularized_is_honest_at_ties() {
    check_regularized(Method::Regularized);
}

#[test]
fn regularized_newton_is_honest_at_ties() {
    check_regularized(Method::RegularizedNewton);
}

/// Benchmark 1 with ordinary thresholds: every method reads the state the reference has.
#[test]
fn ordinary_thresholds_keep_their_states() {
    for ((g1, g2), expected) in [
        ((5e4, 5e4), "stuck"),
        ((1e2, 5e4), "slides"),
        ((5e4, 1e2), "swivels"),
        ((1e2, 1e2), "slides and swivels"),
    ] {
        let mut p = problem(&preset_scene("benchmark-1"));
        set_threshold(&mut p, (0, 0), g1);
        set_threshold(&mut p, (0, 1), g2);
        let mesh = Mesh::new(&p, 20);
        let reference = solve_reference(&p, 20);
        let exact = reference.states[0].map(|s| s == Truth::Moves);
        let words = ["stuck", "slides", "swivels", "slides and swivels"];
        assert_eq!(
            words[usize::from(exact[0]) + 2 * usize::from(exact[1])],
            expected
        );
        for method in Method::ALL {
            let s = solve(&p, &mesh, method, &SolveOptions::default()).unwrap();
            assert_eq!(s.obstacles[0].state(), expected, "g = {g1}, {g2}: {method}");
        }
    }
}
