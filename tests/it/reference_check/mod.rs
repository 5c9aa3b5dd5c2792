//! The independent high-precision reference (tests/it/reference) checked against closed
//! forms, the shared reference values and its own invariances; then the program's methods
//! checked against it on hard scenes (issue 10).
//!
//! - The reference is right (Benchmark 1 to 1e-25, the CSV reference values, zero load, exact
//!   scaling, precision independence, certificates on the hard scenes) and the harness agrees
//!   with an ordinary method on ordinary scenes.
//! - The ε-reference (tests/it/reference/epsilon.rs, the regularised problem (40)–(43) of
//!   paper 2.7.1): precision independence, convergence to the exact reference as ε → 0,
//!   Benchmark 1 by a 2×2 hand solve; `regularized_methods_agree_with_the_epsilon_reference_*`:
//!   issue 10's acceptance for `regularized` and `regularized-newton` (1e-8 or a warning) on
//!   the regression scenes and presets at ε = 1e-10 and 1e-6.
//! - `stable_method_*`: [`STABLE_METHOD`] (the condensed method)
//!   within 1e-12 (u, slope) and 1e-10 (forces), right flags, no warnings; cases from
//!   `BEAMFRIC_PROPTEST_CASES` (default 32).
//!
//! The measurements on thousands of hard scenes (every method, the regularised methods' silent
//! failures, a scan of the stable method, one scene in detail, writing regression scenes) are
//! tools, not tests: `cargo bench --bench reference -- measure|silent|scan|write|diagnose`
//! (benches/reference.rs).
//!
//! The ε-reference's own checks are in `epsilon`.

use beamfric::fem::Mesh;
use beamfric::scene::{self, Scene};
use beamfric::solve::{Method, SolveOptions, solve};
use proptest::prelude::*;

use crate::harness::scenes::{preset_scene, problem, reference_values};
use crate::harness::seed;
use crate::reference::epsilon::{Start, solve_epsilon_reference_from};
use crate::reference::mp::{F, Mp, abs, is_zero, to_f64};
use crate::reference::{self, *};

mod epsilon;

/// |a − b| / |b| in the working precision (|a − b| when b = 0).
fn relative(a: &F, b: &F) -> f64 {
    let difference = abs(&(a - b));
    if is_zero(b) {
        to_f64(&difference)
    } else {
        to_f64(&(difference / abs(b)))
    }
}

/// Benchmark 1 by the closed form (50), evaluated in the working precision: the point slides
/// (λ1 = g1) and does not swivel (u'(x̂) = 0), so u(x̂) = (r0 − g1)/K11 and λ2 = r1 − K21 u(x̂),
/// K the exact 2×2 stiffness of the two clamped stretches a = 0.8, b = 0.2 seen from x̂ and r
/// their fixed-end load.
fn benchmark_1_closed_form(mp: &Mp) -> (F, F) {
    let n = |x: f64| mp.num(x);
    // E·J as the validated problem has it (the f64 product E·w·h³/12).
    let problem = problem(&preset_scene("benchmark-1"));
    let ej = n(problem.stiffness[0].bending_stiffness);
    // The stretch lengths as the mesh has them: x̂ and l − x̂ (not the f64 0.2).
    let (a, b, f, g1) = (n(0.8), n(1.0) - n(0.8), n(5e4), n(1e2));
    let cube = |x: &F| x * x * x;
    let k11 = &ej * (n(12.0) / cube(&a) + n(12.0) / cube(&b));
    let k21 = &ej * (n(6.0) / (&b * &b) - n(6.0) / (&a * &a));
    let r0 = &f * (&a + &b) / n(2.0);
    let r1 = &f * (&b * &b - &a * &a) / n(12.0);
    let u = (r0 - g1) / k11;
    let moment = r1 - k21 * &u;
    (u, moment)
}

#[test]
fn benchmark_1_matches_the_closed_form_to_25_digits_on_any_mesh() {
    let scene = preset_scene("benchmark-1");
    let problem = problem(&scene);
    let mp = Mp {
        precision: reference::mp::DEFAULT_PRECISION,
    };
    let (u_exact, moment_exact) = benchmark_1_closed_form(&mp);
    let design = mp.decimal("0.0057016100178890876565");
    // The design value is for decimal inputs; 0.8, 0.2, 0.02 as f64 differ from them by 1e-17.
    let error = relative(&u_exact, &design);
    assert!(error < 1e-15, "the closed form itself: {error:e}");
    for elements in [1, 2, 3, 20, 57, 200] {
        let r = solve_reference(&problem, elements);
        assert!(r.certificate.verified, "{:?}", r.certificate);
        let [u, slope] = &r.motion[0];
        let error = relative(u, &u_exact);
        assert!(error < 1e-25, "n = {elements}: u(x̂) off by {error:e}");
        assert!(is_zero(slope), "n = {elements}: the swivel is stuck");
        assert_eq!(to_f64(&r.lambda[0][0]), 100.0);
        let error = relative(&r.lambda[0][1], &moment_exact);
        assert!(error < 1e-25, "n = {elements}: moment off by {error:e}");
        assert!((to_f64(&r.lambda[0][1]) + 4_798.461_538_461_538).abs() < 1e-9);
        assert_eq!(
            r.states[0],
            [FrictionState::Moves, FrictionState::Stuck],
            "n = {elements}"
        );
    }
    // max u on 20 elements is at x = 0.4 (docs/design.md, section 2).
    let r = solve_reference(&problem, 20);
    let u = r.u_f64();
    assert!((u[8] - 0.021_455_456_171_7).abs() < 1e-13);
    assert_eq!(r.nodes[8], 0.4);
}

#[test]
fn nodal_values_do_not_depend_on_the_mesh() {
    // Fact 1 of docs/design.md: the FEM solution is exact at every node, so two meshes that share a
    // node position (as the same f64) give the same values there, although their matrices
    // differ. This checks the assembly away from the obstacles.
    for name in ["benchmark-3", "eight-obstacles"] {
        let problem = problem(&preset_scene(name));
        let coarse = solve_reference(&problem, 20);
        let mut shared = 0;
        for elements in [40, 60, 33] {
            let fine = solve_reference(&problem, elements);
            for (i, x) in coarse.nodes.iter().enumerate() {
                if let Some(j) = fine.nodes.iter().position(|y| y == x) {
                    shared += 1;
                    for (a, b) in [
                        (&coarse.u[i], &fine.u[j]),
                        (&coarse.slope[i], &fine.slope[j]),
                    ] {
                        let error = relative(a, b);
                        assert!(error < 1e-60 || is_zero(b), "{name} at x = {x}: {error:e}");
                    }
                }
            }
        }
        assert!(shared > 40, "{name}: {shared} shared nodes");
    }
}

#[test]
fn reference_values_of_the_three_benchmarks() {
    for name in ["benchmark-1", "benchmark-2", "benchmark-3"] {
        let problem = problem(&preset_scene(name));
        let r = solve_reference(&problem, 20);
        assert!(r.certificate.verified, "{name}: {:?}", r.certificate);
        let expected = reference_values(name);
        assert_eq!(r.nodes.len(), expected.x.len());
        let error = |a: &[f64], b: &[f64]| {
            let scale = b.iter().fold(0f64, |m, v| m.max(v.abs()));
            a.iter().zip(b).fold(0f64, |m, (x, y)| m.max((x - y).abs())) / scale
        };
        let (u, slope) = (
            error(&r.u_f64(), &expected.u),
            error(&r.slope_f64(), &expected.slope),
        );
        assert!(
            u < 1e-12 && slope < 1e-12,
            "{name}: u {u:e}, slope {slope:e}"
        );
        for (mine, theirs) in r.lambda_f64().iter().zip(&expected.friction) {
            for k in 0..2 {
                let error = (mine[k] - theirs[k]).abs() / theirs[k].abs();
                assert!(error < 1e-11, "{name}: {mine:?} against {theirs:?}");
            }
        }
    }
}

#[test]
fn zero_load_gives_exactly_zero() {
    for (f0, sliding) in [(0.0, 1e2), (0.0, 0.0)] {
        let mut scene = preset_scene("benchmark-3");
        scene.load.f0 = f0;
        scene.load.f1 = Some(0.0);
        for o in &mut scene.obstacles {
            o.sliding = sliding;
        }
        let (problem, elements) = problem_of(&scene);
        let r = solve_reference(&problem, elements);
        assert!(r.certificate.verified);
        assert!(r.u.iter().chain(&r.slope).all(is_zero));
        assert!(r.lambda.iter().flatten().all(is_zero));
        let sliding_state = if sliding == 0.0 {
            FrictionState::AtThreshold
        } else {
            FrictionState::Stuck
        };
        assert!(
            r.states
                .iter()
                .all(|s| *s == [sliding_state, FrictionState::Stuck])
        );
    }
}

/// Every obstacle scaled: load and thresholds by `load`, positions by `length` (thresholds then
/// by length resp. length² more).
fn scaled(scene: &Scene, load: f64, length: f64) -> Scene {
    let mut s = scene.clone();
    s.beam.length *= length;
    for segment in &mut s.beam.segments {
        segment.from *= length;
        segment.to *= length;
    }
    s.load.f0 *= load;
    s.load.f1 = s.load.f1.map(|f| f * load);
    for o in &mut s.obstacles {
        o.x *= length;
        o.sliding *= load * length;
        o.swivel *= load * length * length;
    }
    s
}

#[test]
fn powers_of_two_scale_the_solution_exactly() {
    // Exact: a power of two commutes with every rounding, so the values scale bit for bit.
    let scenes = [
        preset_scene("benchmark-3"),
        regression_scenes().remove(0).1,
        hard_scene(7),
        hard_scene(11),
    ];
    for scene in &scenes {
        let (p, n) = problem_of(scene);
        let base = solve_reference(&p, n);
        for (load_exp, length_exp) in [(700, 0), (-700, 0), (3, 5), (0, -4)] {
            let (load, length) = (2f64.powi(load_exp), 2f64.powi(length_exp));
            let other = scaled(scene, load, length);
            let (q, m) = problem_of(&other);
            let r = solve_reference(&q, m);
            // EJ is left alone, so u scales by load·length⁴, u' by load·length³.
            let mp = Mp {
                precision: base.precision,
            };
            let factor = |e: i32| mp.num(2f64.powi(e));
            let checks: [(&[F], &[F], i32); 2] = [
                (&base.u, &r.u, load_exp + 4 * length_exp),
                (&base.slope, &r.slope, load_exp + 3 * length_exp),
            ];
            // Exact up to dashu's rounding, which is not always invariant under a shift of the
            // exponent (measured 1.4e-116 = 2^-384 at 2^700).
            for (a, b, e) in checks {
                for (x, y) in a.iter().zip(b) {
                    let expected = x * factor(e);
                    assert!(
                        relative(&expected, y) < 1e-100,
                        "{}: 2^{load_exp}, 2^{length_exp}: relative {:e}",
                        scene.title,
                        relative(&expected, y)
                    );
                }
            }
            for (x, y) in base.lambda.iter().zip(&r.lambda) {
                assert!(relative(&(&x[0] * factor(load_exp + length_exp)), &y[0]) < 1e-100);
                assert!(relative(&(&x[1] * factor(load_exp + 2 * length_exp)), &y[1]) < 1e-100);
            }
            assert_eq!(base.states, r.states);
        }
    }
}

#[test]
fn other_factors_scale_the_solution_to_working_precision() {
    let scene = preset_scene("benchmark-3");
    let (p, n) = problem_of(&scene);
    let base = solve_reference(&p, n);
    let other = scaled(&scene, 3.0, 1.0);
    let (q, m) = problem_of(&other);
    let r = solve_reference(&q, m);
    let mp = Mp {
        precision: base.precision,
    };
    for (x, y) in base.u.iter().zip(&r.u) {
        assert!(relative(&(x * mp.num(3.0)), y) < 1e-100 || is_zero(x));
    }
    assert_eq!(base.states, r.states);
}

#[test]
fn the_precision_does_not_change_the_answer() {
    // 384 against 768 bits on the regression scenes and a few generated ones: the digits that
    // matter do not depend on the working precision, and neither do the states.
    let mut scenes: Vec<Scene> = regression_scenes().into_iter().map(|(_, s)| s).collect();
    scenes.extend((100..106).map(hard_scene));
    for scene in &scenes {
        let (p, n) = problem_of(scene);
        let mesh = Mesh::new(&p, n);
        let low = solve_reference_with(&p, &mesh, 384).unwrap();
        let high = solve_reference_with(&p, &mesh, 768).unwrap();
        assert!(low.certificate.verified && high.certificate.verified);
        assert_eq!(low.states, high.states, "{}", scene.title);
        let scale = |v: &[F]| {
            v.iter().map(abs).fold(
                Mp { precision: 384 }.zero(),
                |a, b| if b > a { b } else { a },
            )
        };
        for (a, b) in [(&low.u, &high.u), (&low.slope, &high.slope)] {
            let s = scale(b);
            for (x, y) in a.iter().zip(b.iter()) {
                let error = if is_zero(&s) {
                    0.0
                } else {
                    to_f64(&(abs(&(x - y)) / &s))
                };
                assert!(error < 1e-60, "{}: {error:e}", scene.title);
            }
        }
    }
}

#[test]
fn the_reference_certifies_itself_on_hard_scenes() {
    let count = env_number("BEAMFRIC_REFERENCE_SCENES", 40);
    let mut ties = 0;
    for (name, scene) in regression_scenes()
        .into_iter()
        .chain((0..count).map(|i| (format!("seed {i}"), hard_scene(i))))
    {
        let (p, n) = problem_of(&scene);
        let r = solve_reference(&p, n);
        assert!(r.certificate.verified, "{name}: {:?}", r.certificate);
        assert!(r.u_f64().iter().all(|v| v.is_finite()), "{name}");
        ties += usize::from(r.has_tie());
    }
    // The antisymmetric regression scene has an exact tie by construction.
    assert!(ties >= 1);
}

#[test]
fn the_regression_scenes_are_valid_and_the_symmetric_one_ties() {
    let scenes = regression_scenes();
    assert!(scenes.len() >= 15);
    let (_, scene) = scenes
        .iter()
        .find(|(name, _)| name == "sign-change-symmetric")
        .unwrap();
    let (p, n) = problem_of(scene);
    let r = solve_reference(&p, n);
    assert_eq!(r.states[1][0], FrictionState::AtThreshold);
    assert_eq!(r.states[0][0], FrictionState::Moves);
    // Near the right support the exact force is +g (issue 10, finding 2).
    let (_, scene) = scenes
        .iter()
        .find(|(name, _)| name == "near-right-support")
        .unwrap();
    let (p, n) = problem_of(scene);
    let r = solve_reference(&p, n);
    assert_eq!(r.lambda_f64()[0][0], 1e-3);
    assert!(r.motion_f64()[0][0] > 0.0);
}

#[test]
fn stable_method_agrees_on_regression_scenes_and_presets() {
    let mut failures = Vec::new();
    for (name, scene) in regression_scenes() {
        failures.extend(check_stable(&name, &scene).err());
    }
    for preset in scene::PRESETS {
        let scene = preset_scene(preset.name);
        if scene.mesh.elements <= 2000 && scene.obstacles.len() <= 40 {
            failures.extend(check_stable(preset.name, &scene).err());
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The two regularised methods on one scene at `epsilon`, against the ε-reference: within
/// [`REGULARIZED_TOLERANCE`] in u, u', forces and moments with every flag f64 can resolve
/// right, or a warning. A refusal is an answer too (the enumeration refuses 9^k cases above
/// `max_cases`, 6561 here to keep the test fast). Returns the failures, one line each, and
/// how many solves were refused.
fn check_regularized(name: &str, scene: &Scene, epsilon: f64) -> (Vec<String>, usize) {
    let (p, n) = problem_of(scene);
    let mesh = Mesh::new(&p, n);
    let r = match solve_epsilon_reference(&p, &mesh, epsilon, reference::mp::DEFAULT_PRECISION) {
        Ok(r) if r.certificate.verified => r,
        Ok(r) => {
            return (
                vec![format!(
                    "{name}, ε = {epsilon:e}: ε-reference {:?}",
                    r.certificate
                )],
                0,
            );
        }
        Err(e) => {
            return (
                vec![format!("{name}, ε = {epsilon:e}: ε-reference: {e}")],
                0,
            );
        }
    };
    let options = SolveOptions {
        epsilon,
        max_cases: 6561,
        ..SolveOptions::default()
    };
    let (mut failures, mut refused) = (Vec::new(), 0);
    for method in [Method::RegularizedNewton, Method::Regularized] {
        match run_method(&p, &mesh, method, &options) {
            Ok(solution) => {
                let c = compare(&p, &solution, &r);
                let accepted = c.agrees_to_resolution(REGULARIZED_TOLERANCE, REGULARIZED_TOLERANCE);
                if !accepted && !c.warned() {
                    failures.push(format!(
                        "{name}, ε = {epsilon:e}, {method}: u {:.1e} slope {:.1e} force {:.1e} \
                         moment {:.1e}, gross flags {} {:?}, kkt {:.1e}, details {:?}",
                        c.u,
                        c.slope,
                        c.force,
                        c.moment,
                        c.gross_flag_errors,
                        c.flag_errors,
                        solution.kkt_residual,
                        solution.details
                    ));
                }
            }
            Err(why) if why.starts_with("refused") => refused += 1,
            Err(why) => failures.push(format!("{name}, ε = {epsilon:e}, {method}: {why}")),
        }
    }
    (failures, refused)
}

#[test]
fn regularized_methods_agree_with_the_epsilon_reference_on_regression_scenes_and_presets() {
    // Issue 10: "the regularised methods agree with the exact ε-solution to 1e-8 or warn".
    let mut scenes = regression_scenes();
    for preset in scene::PRESETS {
        let scene = preset_scene(preset.name);
        if scene.mesh.elements <= 2000 && scene.obstacles.len() <= 40 {
            scenes.push((preset.name.to_string(), scene));
        }
    }
    let (mut failures, mut refused) = (Vec::new(), 0);
    for (name, scene) in &scenes {
        for epsilon in [1e-10, 1e-6] {
            let (f, r) = check_regularized(name, scene, epsilon);
            failures.extend(f);
            refused += r;
        }
    }
    assert!(refused < 2 * scenes.len(), "every solve refused");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

proptest! {
    // Fresh random scenes on every run (BEAMFRIC_SEED=N repeats a draw, harness::seed): the stable method
    // failed 0 of 10 000 random scenes and 0 of the 2000 fixed seeds at the last measurement
    // (issue 10 note), so a failure here is a new case; its message names the seed, to be
    // kept in `tests/scenes/hard/` once fixed.
    #![proptest_config(seed::config(ProptestConfig {
        cases: env_number("BEAMFRIC_PROPTEST_CASES", 32) as u32,
        failure_persistence: None,
        ..ProptestConfig::default()
    }))]

    /// The acceptance property of issue 10 (`BEAMFRIC_PROPTEST_CASES` cases, default 32; the
    /// scan below runs 2000 fixed seeds and any number of random ones). Every seed that once
    /// failed is a regression scene in `tests/scenes/hard/`.
    #[test]
    fn stable_method_agrees_on_hard_scenes(scene in hard_scenes()) {
        let result = check_stable(&scene.title, &scene);
        prop_assert!(result.is_ok(), "{}", result.unwrap_err());
    }
}
