//! Unit tests of the condensed method's search: the monotone search alone and each Newton
//! variant first find the same solution of (38).

use super::*;
use crate::model::{LinearLoad, Obstacle, StiffnessPiece};

/// `k` obstacles with thresholds around the fixed-end forces (every state occurs).
fn crowded(k: usize, seed: u64) -> Problem {
    let mut state = seed;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let (load, h) = (1e5, 1.0 / (k + 1) as f64);
    let obstacles = (1..=k)
        .map(|j| Obstacle {
            x: (j as f64 + 0.8 * (next() - 0.5)) * h,
            sliding_threshold: 3.0 * load * h * next(),
            swivel_threshold: 0.2 * load * h * h * next(),
        })
        .collect();
    Problem {
        length: 1.0,
        stiffness: vec![StiffnessPiece {
            from: 0.0,
            to: 1.0,
            bending_stiffness: 2866.0,
        }],
        load: LinearLoad {
            f0: load,
            f1: -0.5 * load,
        },
        obstacles,
    }
}

#[test]
fn the_monotone_search_alone_finds_the_same_solution() {
    for (k, seed) in [(5, 1), (40, 2), (200, 3)] {
        let problem = crowded(k, seed);
        let mesh = Mesh::new(&problem, 4 * (k + 1));
        let newton = solve_condensed(&problem, &mesh).unwrap();
        let monotone =
            solve_with_newton_phases(&problem, &mesh, &[], &mut || true, None, None).unwrap();
        assert!(newton.converged && monotone.converged, "k = {k}");
        assert_eq!(newton.states, monotone.states, "k = {k}");
        let scale = newton
            .field
            .deflection
            .iter()
            .fold(0.0f64, |m, u| m.max(u.abs()));
        for (a, b) in newton
            .field
            .deflection
            .iter()
            .zip(&monotone.field.deflection)
        {
            assert!((a - b).abs() <= 1e-13 * scale, "k = {k}: {a} vs {b}");
        }
    }
}

#[test]
fn each_newton_variant_first_gives_the_same_solution() {
    let problem = crowded(60, 7);
    let mesh = Mesh::new(&problem, 400);
    let reference = solve_condensed(&problem, &mesh).unwrap();
    for fraction in NEWTON_REVERSAL_FRACTIONS {
        let solution =
            solve_with_newton_phases(&problem, &mesh, &[fraction], &mut || true, None, None)
                .unwrap();
        assert!(solution.converged);
        assert_eq!(solution.states, reference.states, "σ fraction {fraction}");
    }
}

#[test]
fn the_projected_newton_guess_is_the_answer_on_small_crowded_scenes() {
    // Within its 60 steps (83 for the two scenes together); at k = 200 (crowded(200, 3)) it
    // stops at 60 with some DOFs wrong: a guess.
    use super::system::{Accuracy, BAND_LOWER, BAND_UPPER, Pattern, ShootingSystem};
    use crate::linalg::banded_lu::BandedSystem;
    for (k, seed) in [(40, 2), (60, 7)] {
        let problem = crowded(k, seed);
        let mesh = Mesh::new(&problem, 4 * (k + 1));
        let answer = solve_condensed(&problem, &mesh).unwrap();
        assert!(answer.converged);
        let scales = scaling::Scales::of(&problem);
        let system = ShootingSystem::new(&problem, &mesh, &scales, NEWTON_REVERSAL_FRACTIONS[0]);
        let held = vec![Pattern::Stuck; 2 * k];
        let mut banded = BandedSystem::new(0, BAND_LOWER, BAND_UPPER);
        system
            .solve_pattern(&held, Accuracy::Plain, &mut banded)
            .unwrap();
        let refined = system
            .solve_pattern(&held, Accuracy::RefineLast, &mut banded)
            .unwrap();
        let forces = refined.exact.unwrap().force;
        let guess = system
            .projected_newton_pattern(&forces, &mut || true)
            .unwrap()
            .unwrap();
        let moving = guess.iter().filter(|&&p| p != Pattern::Stuck).count();
        assert!(moving > 0 && moving < 2 * k, "k = {k}: {moving} moving");
        assert_eq!(guess, answer.pattern.0, "k = {k}");
    }
}

#[test]
fn a_solve_after_another_on_the_same_thread_gives_the_same_bits() {
    // The search's banded system is kept between solves on a thread (`BandedSystem::keep`),
    // stale: a solve after a larger and a smaller one must not see anything of theirs.
    let bits = |solution: &CondensedSolution| -> Vec<u64> {
        let field = &solution.field;
        let forces = solution.friction.iter().flatten();
        field
            .deflection
            .iter()
            .chain(&field.slope)
            .chain(forces)
            .map(|v| v.to_bits())
            .collect()
    };
    let solve = |k: usize, seed: u64| {
        let problem = crowded(k, seed);
        let mesh = Mesh::new(&problem, 4 * (k + 1));
        let solution = solve_condensed(&problem, &mesh).unwrap();
        assert!(solution.converged, "k = {k}");
        solution
    };
    // Each on a thread of its own: nothing kept.
    let alone = |k: usize, seed: u64| std::thread::spawn(move || bits(&solve(k, seed)));
    let (small, large) = (alone(40, 2).join().unwrap(), alone(200, 3).join().unwrap());
    let after = std::thread::spawn(move || {
        let first = bits(&solve(200, 3));
        let second = bits(&solve(40, 2));
        let third = bits(&solve(200, 3));
        (first, second, third)
    })
    .join()
    .unwrap();
    assert_eq!(after.0, large);
    assert_eq!(after.1, small, "after a larger solve");
    assert_eq!(after.2, large, "after a smaller solve");
}

/// The step length to the nearest bound (`interior::shorten`) divides only where the product
/// test allows, and must still give the bits of `length.min(distance / rate)` everywhere:
/// on values of any size, and on lengths a few ulps either side of the quotient itself.
mod step_lengths {
    use super::interior::shorten;
    use proptest::num::f64::{NEGATIVE, NORMAL, POSITIVE, SUBNORMAL, ZERO};
    use proptest::prelude::*;

    fn divided(length: f64, distance: f64, rate: f64) -> f64 {
        length.min(distance / rate)
    }

    fn nudged(value: f64, ulps: i64) -> f64 {
        if value == 0.0 || !value.is_finite() {
            return value;
        }
        f64::from_bits((value.to_bits() as i64 + ulps) as u64)
    }

    proptest! {
        #[test]
        fn any_values(
            length in POSITIVE | NORMAL | SUBNORMAL | ZERO,
            distance in POSITIVE | NEGATIVE | NORMAL | SUBNORMAL | ZERO,
            rate in POSITIVE | NORMAL | SUBNORMAL,
        ) {
            let length = length.min(1.0);
            let mut shortened = length;
            shorten(&mut shortened, distance, rate);
            prop_assert_eq!(shortened.to_bits(), divided(length, distance, rate).to_bits());
        }

        #[test]
        fn lengths_next_to_the_quotient(
            distance in POSITIVE | NORMAL | SUBNORMAL,
            rate in POSITIVE | NORMAL | SUBNORMAL,
            ulps in -4i64..=4,
        ) {
            let length = nudged(distance / rate, ulps);
            prop_assume!(length.is_finite() && length > 0.0);
            let mut shortened = length;
            shorten(&mut shortened, distance, rate);
            prop_assert_eq!(shortened.to_bits(), divided(length, distance, rate).to_bits());
        }
    }
}

/// A bound nearer zero than a few ulps of the largest force change at the start is widened to
/// that distance, on the side of "within"; every other bound keeps its bits
/// (`held_bounds::widen_unresolved`).
mod unresolved_bounds {
    use super::held_bounds::{start_force, widen_unresolved};
    use super::mixed::Mixed;

    #[test]
    fn bounds_below_what_a_step_resolves_are_widened_and_no_other() {
        // DOF 0 breaks its upper bound by 0.2 (its start force is −0.4: the largest change);
        // DOF 1's upper bound is 1e-20 (a held force equal to its threshold to 20 digits),
        // DOF 2's lower one −1e-20 the other way, DOF 3 has no friction (held force 0.1).
        let bounds = vec![
            Some((-2.2, -0.2)),
            Some((-2.0, 1e-20)),
            Some((-1e-20, 3.0)),
            None,
            Some((-0.5, 0.5)),
        ];
        let mut fixed: Vec<Mixed> = (0..5).map(Mixed::free).collect();
        fixed[3].force = -0.1;
        assert_eq!(start_force((-2.2, -0.2)), -0.4);
        let widened = widen_unresolved(bounds.clone(), &fixed, 0.0);
        let floor = 1e-15 * 0.4;
        assert_eq!(widened[0], bounds[0]);
        assert_eq!(widened[1], Some((-2.0, floor)));
        assert_eq!(widened[2], Some((-floor, 3.0)));
        assert_eq!(widened[3], None);
        assert_eq!(widened[4], bounds[4]);
        // A frictionless DOF's change counts too: with a held force of 10 there, the floor is
        // 1e-14 and a bound of 5e-15 below zero is moved to "within".
        fixed[3].force = -10.0;
        let widened = widen_unresolved(vec![Some((-1.0, -5e-15)), None], &fixed[2..4], 0.0);
        assert_eq!(widened[0], Some((-1.0, 1e-15 * 10.0)));
    }

    #[test]
    fn a_range_fraction_widens_ties_to_a_fraction_of_their_range() {
        // Largest change 0.4 (DOF 0). With a fraction of 1e-6: DOF 1 (range 2) is floored at
        // 1e-6 · min(2, 0.4), DOF 2 (range 3e-3) at 1e-6 · 3e-3; DOF 3's bounds (2e-8 from
        // zero, above its floor of 1e-6 · 1e-2) and DOF 0's stay.
        let bounds = vec![
            Some((-2.2, -0.2)),
            Some((-2.0, 1e-20)),
            Some((-1e-20, 3e-3)),
            Some((-1e-2, 2e-8)),
        ];
        let fixed: Vec<Mixed> = (0..4).map(Mixed::free).collect();
        let widened = widen_unresolved(bounds.clone(), &fixed, 1e-6);
        assert_eq!(widened[0], bounds[0]);
        assert_eq!(widened[1], Some((-2.0, 1e-6 * 0.4)));
        assert_eq!(widened[2], Some((-(1e-6 * (3e-3 + 1e-20)), 3e-3)));
        assert_eq!(widened[3], bounds[3]);
    }
}

/// The interior-point steps solve for the force changes alone
/// (`ShootingSystem::solve_mixed_forces`, `resolve_mixed_forces`: no motions, the right-hand
/// side assembled in the system's own, buffers kept): the same bits as the full solves, for
/// every kind of condition (a column holding the force or the motion, D = 0, D infinite).
#[test]
fn the_steps_force_changes_are_the_full_solves_bits() {
    use super::mixed::{Mixed, StepSolves};
    use super::scaling::Scales;
    use super::system::ShootingSystem;
    use crate::linalg::banded_lu::BandedSystem;
    for (k, seed) in [(12, 1), (40, 2), (90, 3)] {
        let problem = crowded(k, seed);
        let mesh = Mesh::new(&problem, 4 * (k + 1));
        let system = ShootingSystem::new(&problem, &mesh, &Scales::of(&problem), 0.0);
        let template = system.mixed_template();
        // Weights from 0 to infinite, over about 40 decades, forces and motions of both signs.
        let conditions = |shift: f64| -> Vec<Mixed> {
            (0..2 * k)
                .map(|i| {
                    let weight = match i % 5 {
                        0 => 0.0,
                        1 => f64::INFINITY,
                        _ => 10f64.powf((i % 41) as f64 - 20.0),
                    };
                    Mixed {
                        weight,
                        force: (i as f64 - k as f64) * 0.37 + shift,
                        motion: ((i * 7) % 13) as f64 * 1e-3 - 4e-3 + shift,
                    }
                })
                .collect()
        };
        let (first, second) = (conditions(0.0), conditions(0.25));
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        let (mut full, mut lean) = (BandedSystem::new(0, 3, 3), BandedSystem::new(0, 3, 3));
        let mut full_holds = Vec::new();
        let (_, forces) = system
            .solve_mixed(&template, &first, &mut full, &mut full_holds)
            .unwrap();
        assert!(full_holds.contains(&true) && full_holds.contains(&false));
        // Kept vectors of other lengths and contents: overwritten.
        let mut solves = StepSolves::new(vec![false; 3]);
        solves.force_changes = vec![f64::NAN; 5];
        assert!(system.solve_step(&template, &first, &mut lean, (true, false), &mut solves));
        assert_eq!(
            bits(&forces),
            bits(&solves.force_changes),
            "k = {k}, factoring solve"
        );
        let (_, forces) = system
            .resolve_mixed(&template, &second, &full, &full_holds)
            .unwrap();
        assert!(system.solve_step(&template, &second, &mut lean, (false, false), &mut solves));
        let lean_forces = &solves.force_changes;
        assert_eq!(bits(&forces), bits(lean_forces), "k = {k}, second solve");
    }
}

/// A refined interior-point step (`mixed_refinement`): the residual of the exact relations
/// at the f64 solve is that solve's rounding (so the residual agrees with the assembled
/// system: with a sign of a jump flipped it is of the size of the unknowns), and one step of
/// refinement shrinks it (measured: 1.6e2 to 1.1e-2, unknowns up to 1.4e18, on clusters of
/// obstacles 1e-7·l apart with weights over 20 decades).
#[test]
fn a_refined_step_satisfies_the_exact_relations() {
    use super::mixed::{Mixed, StepSolves};
    use super::scaling::Scales;
    use super::system::ShootingSystem;
    use crate::check::families::tight_clusters_ties_scene;
    use crate::linalg::banded_lu::BandedSystem;
    let scene = tight_clusters_ties_scene(60, 3, 600);
    let problem = scene.problem().unwrap();
    let mesh = Mesh::new(&problem, 600);
    let system = ShootingSystem::new(&problem, &mesh, &Scales::of(&problem), 0.0);
    let template = system.mixed_template();
    // Weights from 0 to infinite, 1e-10 to 1e10 between, both kinds of column.
    let conditions: Vec<Mixed> = (0..120)
        .map(|i| Mixed {
            weight: match i % 5 {
                0 => 0.0,
                1 => f64::INFINITY,
                _ => 10f64.powf((i % 21) as f64 - 10.0),
            },
            force: (i as f64 - 60.0) * 0.37,
            motion: ((i * 7) % 13) as f64 * 1e-3 - 4e-3,
        })
        .collect();
    let mut banded = BandedSystem::new(0, 3, 3);
    let mut solves = StepSolves::new(Vec::new());
    assert!(system.solve_step(
        &template,
        &conditions,
        &mut banded,
        (true, false),
        &mut solves
    ));
    let largest = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let unknowns: Vec<_> = solves.unknowns.iter().map(|&v| v.into()).collect();
    let scale = largest(&solves.unknowns);
    let before = largest(&system.exact_mixed_residual(&conditions, &solves.holds_force, &unknowns));
    let refined = system
        .refined_unknowns(&conditions, &banded, &solves)
        .unwrap();
    let after = largest(&system.exact_mixed_residual(&conditions, &solves.holds_force, &refined));
    assert!(
        before > 0.0 && before <= 1e-8 * scale,
        "f64 solve: {before:e} of {scale:e}"
    );
    assert!(
        after <= 1e-3 * before,
        "refined: {after:e}, before {before:e}"
    );
}
