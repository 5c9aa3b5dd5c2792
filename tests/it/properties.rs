//! Property tests over random valid scenes (issue 2): 1–6 obstacles, random thresholds from
//! zero to clamping, linear loads of either sign, stretches with their own modulus and
//! section. Every applicable method must agree with the condensed method, within what its
//! conditioning allows, and certify itself with a small KKT residual; flexibility (single
//! shooting) agrees to 1e-10 or warns, the contract of issue 10 for an exact method.

use beamfric::fem::{Mesh, StiffnessMatrix, stiffness_condition_bounds};
use beamfric::linalg::BlockMatrix;
use beamfric::linalg::condition::{dense_condition, jacobi_scaled};
use beamfric::scene::{
    BeamSpec, LoadSpec, MeshSpec, ObstacleSpec, Scene, Section, SegmentSpec, SolverSpec, ViewSpec,
};
use beamfric::solve::{ConditionLevel, Method, SolveOptions, solve};
use proptest::prelude::*;

use crate::harness::{scenes, seed};

fn section() -> impl Strategy<Value = Section> {
    prop_oneof![
        (0.005f64..0.05, 0.005f64..0.05)
            .prop_map(|(width, height)| Section::Rectangle { width, height }),
        (0.003f64..0.03).prop_map(|radius| Section::Circle { radius }),
        (1e-9f64..1e-6).prop_map(|inertia| Section::Custom { inertia }),
    ]
}

/// A threshold on the scale of the load's resultant: zero, small, comparable or clamping.
fn threshold(scale: f64) -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(0.0),
        (1e-3f64..0.1).prop_map(move |t| t * scale),
        (0.1f64..1.0).prop_map(move |t| t * scale),
        (10.0f64..100.0).prop_map(move |t| t * scale),
    ]
}

prop_compose! {
    fn scene()(
        length in 0.5f64..3.0,
        young in 1e10f64..3e11,
        section in section(),
        f0 in -2e5f64..2e5,
        f1 in -2e5f64..2e5,
        positions in prop::collection::btree_set(1u32..99, 1..=6),
        segment in prop::option::of((5u32..45, 55u32..95, 0.1f64..10.0, section())),
        elements in 8usize..60,
        seed in any::<u64>(),
    )(
        thresholds in prop::collection::vec(
            (threshold((f0.abs() + f1.abs()) * length), threshold((f0.abs() + f1.abs()) * length * length)),
            positions.len()
        ),
        length in Just(length), young in Just(young), section in Just(section), f0 in Just(f0),
        f1 in Just(f1), positions in Just(positions), segment in Just(segment),
        elements in Just(elements), seed in Just(seed),
    ) -> Scene {
        let _ = seed;
        let obstacles = positions
            .iter()
            .zip(&thresholds)
            .map(|(&p, &(sliding, swivel))| ObstacleSpec {
                x: f64::from(p) / 100.0 * length,
                sliding,
                swivel,
            })
            .collect();
        let segments = segment
            .map(|(from, to, contrast, section)| SegmentSpec {
                from: f64::from(from) / 100.0 * length + 0.003 * length,
                to: f64::from(to) / 100.0 * length + 0.003 * length,
                young: Some(young * contrast),
                section: Some(section),
            })
            .into_iter()
            .collect();
        Scene {
            title: "random".into(),
            description: String::new(),
            beam: BeamSpec { length, young, section, segments },
            load: LoadSpec { f0, f1: Some(f1) },
            obstacles,
            mesh: MeshSpec { elements },
            solver: SolverSpec::default(),
            view: ViewSpec::default(),
        }
    }
}

prop_compose! {
    /// Enough obstacles (17–80) that the dual QP has more than 32 unknowns and runs projected
    /// Newton rather than the plain active-set method.
    fn crowded_scene()(
        base in scene(),
        positions in prop::collection::btree_set(1u32..999, 17..=80),
        seed in any::<u64>(),
    ) -> Scene {
        let mut scene = base;
        let length = scene.beam.length;
        let load = (scene.load.f0.abs() + scene.load.f1().abs()) * length;
        let mut state = seed | 1;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % 1000) as f64 / 1000.0
        };
        scene.obstacles = positions
            .iter()
            .map(|&p| ObstacleSpec {
                // Half-way between the thousandths that segment ends sit on.
                x: (f64::from(p) + 0.5) / 1000.0 * length,
                // Zero, small or large thresholds, so that some obstacles stick and some slide.
                sliding: [0.0, 0.01, 0.1, 10.0][(next() * 4.0) as usize] * next() * load,
                swivel: [0.0, 0.01, 0.1, 10.0][(next() * 4.0) as usize] * next() * load * length,
            })
            .collect();
        scene.mesh.elements = scene.mesh.elements.max(100);
        scene
    }
}

proptest! {
    #![proptest_config(seed::config(ProptestConfig::with_cases(40)))]

    #[test]
    fn crowded_beams_solve_exactly_by_every_dual_route(scene in crowded_scene()) {
        let (problem, settings) = scene.validate("crowded").expect("generated scenes are valid");
        let mesh = Mesh::new(&problem, settings.elements);
        let options = SolveOptions {
            condition: ConditionLevel::Auto,
            reference: false,
            ..SolveOptions::default()
        };
        // The stable method is the reference (issue 10); it certifies itself to a few ulps of
        // the local values, which the piecewise KKT check of the certificate measures.
        let reference = solve(&problem, &mesh, Method::Condensed, &options).unwrap();
        prop_assert!(reference.warnings.is_empty(), "{:?}", reference.warnings);
        prop_assert!(reference.kkt_residual < 1e-12, "condensed KKT {:e}", reference.kkt_residual);
        let flexibility = solve(&problem, &mesh, Method::Flexibility, &options).unwrap();
        let cond_dual = flexibility.conditioning.dual.map_or(1.0, |c| c.value);
        for method in [Method::Dual, Method::DualInverse] {
            let solution = solve(&problem, &mesh, method, &options).unwrap();
            prop_assert!(solution.is_finite(), "{method}");
            let cond_stiffness = solution.conditioning.stiffness.map_or(1.0, |c| c.value);
            let tolerance = 1e-12 + 2.0 * (cond_stiffness + cond_dual) * f64::EPSILON;
            let du = scenes::relative_difference(&solution.field.deflection, &reference.field.deflection);
            prop_assert!(du < tolerance, "{method}: u differs by {du:e} (tolerance {tolerance:e})");
            // The piecewise KKT check measures against the local values: a stiffness-route
            // answer is inconsistent there by no more than its conditioning explains.
            prop_assert!(
                solution.kkt_residual < 1e-9_f64.max(100.0 * tolerance),
                "{method}: KKT {:e}", solution.kkt_residual
            );
        }
    }
}

proptest! {
    #![proptest_config(seed::config(ProptestConfig::with_cases(200)))]

    #[test]
    fn all_applicable_methods_agree_and_certify(scene in scene()) {
        let (problem, settings) = scene.validate("random").expect("generated scenes are valid");
        let mesh = Mesh::new(&problem, settings.elements);
        let base = SolveOptions {
            condition: ConditionLevel::Auto,
            reference: false,
            ..SolveOptions::default()
        };
        // The condensed method is the reference (issue 10): exact piece relations, no
        // conditioning of its own to speak of.
        let reference = solve(&problem, &mesh, Method::Condensed, &base).unwrap();
        prop_assert!(reference.is_finite());
        prop_assert!(reference.kkt_residual < 1e-10, "condensed KKT {:e}", reference.kkt_residual);
        let scale_u = reference.max_deflection().max(f64::MIN_POSITIVE);
        let scale_slope = reference.field.slope.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for method in Method::ALL {
            if method == Method::Condensed
                || (method == Method::Regularized && problem.obstacles.len() > 3)
            {
                continue;
            }
            // ε well below the solution's own scale, for both kinds of DOF.
            let epsilon = 1e-10 * scale_u.min(scale_slope.max(f64::MIN_POSITIVE));
            let options = SolveOptions {
                epsilon,
                ..base.clone()
            };
            // Flexibility runs as users run it, with the certificate's comparison against the
            // condensed method: its contract is issue 10's for an exact method, agree to 1e-10
            // or warn (see below).
            let options = SolveOptions {
                reference: method == Method::Flexibility,
                ..options
            };
            let solution = match solve(&problem, &mesh, method, &options) {
                Ok(s) => s,
                Err(e) => {
                    // Only the closed form may decline, and only outside its data.
                    prop_assert_eq!(method, Method::ClosedForm, "{}", e);
                    continue;
                }
            };
            prop_assert!(solution.is_finite(), "{method}");
            // Exact methods solve a QP in the friction forces through A (stiffness route) or S
            // (both dual routes), so each is accurate to about (cond(A) + cond(S))·eps of its
            // own matrices (seen: 1.5e-11 with cond(A) = 4.5e4, cond(S) = 4.4e4 on six
            // obstacles, eight elements); regularised ones: O(ε) on top.
            let cond_stiffness = solution.conditioning.stiffness.map_or(1.0, |c| c.value);
            let cond_dual = solution.conditioning.dual.map_or(1.0, |c| c.value);
            let tolerance = 1e-12
                + 2.0 * (cond_stiffness + cond_dual) * f64::EPSILON
                + if method.is_regularized() { 1e-6 } else { 0.0 };
            let du = scenes::relative_difference(&solution.field.deflection, &reference.field.deflection);
            let ds = scenes::relative_difference(&solution.field.slope, &reference.field.slope);
            if method == Method::Flexibility {
                // Single shooting carries the rounding of the reactions and of S across the
                // beam beyond what cond(S) says: 1.65e-10 in u' on a scene whose KKT residual
                // is 7e-11, 2.2e-9 on one with a soft stretch (issue 10's finding; the
                // regression file keeps both). So it is held to the contract: within 1e-10,
                // or it says so (accuracy-loss from the comparison, or kkt-residual); and
                // even then within 1e-7, far above the 2.2e-9 seen, far below a wrong answer.
                let warned = solution.has_warning(beamfric::solve::WarningCode::AccuracyLoss)
                    || solution.has_warning(beamfric::solve::WarningCode::KktResidual);
                let bound = if warned { 1e-7 } else { tolerance.max(1e-10) };
                prop_assert!(
                    du < bound && ds < bound,
                    "flexibility: u differs by {du:e}, u' by {ds:e} (bound {bound:e}, warned: {warned})"
                );
                prop_assert!(
                    solution.kkt_residual < 1e-9_f64.max(100.0 * tolerance) || warned,
                    "flexibility: KKT residual {:e} without a warning", solution.kkt_residual
                );
            } else {
                prop_assert!(du < tolerance, "{method}: u differs by {du:e} (tolerance {tolerance:e})");
                prop_assert!(ds < tolerance, "{method}: u' differs by {ds:e}");
                // The piecewise KKT check measures against the local values, which the
                // stiffness route resolves to what its conditioning explains.
                let kkt_tolerance = if method.is_regularized() { 1e-6 } else { 1e-9_f64.max(100.0 * tolerance) };
                prop_assert!(
                    solution.kkt_residual < kkt_tolerance,
                    "{method}: KKT residual {:e}", solution.kkt_residual
                );
            }
            for o in &solution.obstacles {
                let g = problem.obstacles.iter().find(|p| p.x == o.x).unwrap();
                prop_assert!(o.force.abs() <= g.sliding_threshold * (1.0 + 1e-9) + 1e-9 * g.sliding_threshold.max(1.0));
                prop_assert!(o.moment.abs() <= g.swivel_threshold * (1.0 + 1e-9) + 1e-9 * g.swivel_threshold.max(1.0));
            }
        }
    }

    #[test]
    fn the_cheap_condition_bounds_are_lower_bounds(scene in scene()) {
        let (problem, settings) = scene.validate("random").expect("generated scenes are valid");
        let mesh = Mesh::new(&problem, settings.elements);
        let a = StiffnessMatrix::new(&mesh).to_block_tridiagonal();
        let n = mesh.unknowns();
        let exact = dense_condition(&a.to_dense(), n).unwrap().value;
        let exact_scaled = dense_condition(&jacobi_scaled(&a).to_dense(), n).unwrap().value;
        let (bound, scaled) = stiffness_condition_bounds(&mesh);
        prop_assert!(bound.is_some() && scaled.is_some(), "no bound: {bound:?} {scaled:?}");
        let (bound, scaled) = (bound.unwrap(), scaled.unwrap());
        // Rounding in the exact eigenvalues and in the energies allows a hair above.
        prop_assert!(bound.value <= exact * (1.0 + 1e-6), "{:e} > {exact:e}", bound.value);
        prop_assert!(scaled.value <= exact_scaled * (1.0 + 1e-6), "{:e} > {exact_scaled:e}", scaled.value);
        prop_assert!(scaled.value >= 1.0);
    }
}
