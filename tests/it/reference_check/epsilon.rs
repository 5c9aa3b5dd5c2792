//! The ε-reference (tests/it/reference/epsilon.rs, the regularised problem (40)–(43) of paper
//! 2.7.1) checked: precision and start independence, convergence to the exact reference as
//! ε → 0, and Benchmark 1 by a 2×2 hand solve.

use super::*;

/// The ordinary presets the harness and the ε-reference are tried on.
const ORDINARY_PRESETS: [&str; 4] = [
    "benchmark-1",
    "benchmark-2",
    "benchmark-3",
    "eight-obstacles",
];

#[test]
fn ordinary_presets_agree_with_the_dual_method() {
    // The harness itself: on ordinary scenes the exact methods agree to the 1e-10
    // (measured: flexibility 3e-15 … 2.8e-13, dual 4e-15 … 2.7e-12).
    for name in ORDINARY_PRESETS {
        let scene = preset_scene(name);
        let (p, n) = problem_of(&scene);
        let r = solve_reference(&p, n);
        let mesh = Mesh::new(&p, n);
        for method in [Method::Flexibility, Method::Dual] {
            let solution = solve(&p, &mesh, method, &SolveOptions::default()).unwrap();
            let c = compare(&p, &solution, &r);
            assert!(c.agrees(1e-10, 1e-10), "{name}, {method}: {c:?}");
        }
    }
}

/// The scenes of the ε-reference self-tests: the regression scenes, a few generated ones and
/// the four ordinary presets.
fn epsilon_self_test_scenes() -> Vec<(String, Scene)> {
    let mut scenes = regression_scenes();
    scenes.extend((100..104).map(|s| (format!("seed {s}"), hard_scene(s))));
    for name in ORDINARY_PRESETS {
        scenes.push((name.to_string(), preset_scene(name)));
    }
    scenes
}

/// max |a − b| / max |b| in the working precision (0 when b is all zero and a = b).
fn relative_vector(a: &[F], b: &[F], mp: &Mp) -> f64 {
    let scale = b
        .iter()
        .map(abs)
        .fold(mp.zero(), |m, x| if x > m { x } else { m });
    let worst = a
        .iter()
        .zip(b)
        .map(|(x, y)| abs(&(x - y)))
        .fold(mp.zero(), |m, x| if x > m { x } else { m });
    if is_zero(&worst) {
        0.0
    } else if is_zero(&scale) {
        f64::INFINITY
    } else {
        to_f64(&(worst / scale))
    }
}

#[test]
fn the_epsilon_reference_does_not_depend_on_the_precision() {
    // 384 against 768 bits, certified at both, same states, the same 60 digits.
    for (name, scene) in epsilon_self_test_scenes() {
        let (p, n) = problem_of(&scene);
        let mesh = Mesh::new(&p, n);
        for epsilon in [1e-10, 1e-6] {
            let low = solve_epsilon_reference(&p, &mesh, epsilon, 384)
                .unwrap_or_else(|e| panic!("{name}, ε = {epsilon:e}: {e}"));
            let high = solve_epsilon_reference(&p, &mesh, epsilon, 768)
                .unwrap_or_else(|e| panic!("{name}, ε = {epsilon:e}: {e}"));
            assert!(
                low.certificate.verified && high.certificate.verified,
                "{name}, ε = {epsilon:e}: {:?} / {:?}",
                low.certificate,
                high.certificate
            );
            assert_eq!(low.states, high.states, "{name}, ε = {epsilon:e}");
            let mp = Mp { precision: 384 };
            let flat = |l: &[[F; 2]], k: usize| l.iter().map(|x| x[k].clone()).collect::<Vec<F>>();
            for (what, a, b) in [
                ("u", low.u.clone(), high.u.clone()),
                ("slope", low.slope.clone(), high.slope.clone()),
                ("force", flat(&low.lambda, 0), flat(&high.lambda, 0)),
                ("moment", flat(&low.lambda, 1), flat(&high.lambda, 1)),
            ] {
                let error = relative_vector(&a, &b, &mp);
                assert!(error < 1e-60, "{name}, ε = {epsilon:e}, {what}: {error:e}");
            }
        }
    }
}

#[test]
fn the_epsilon_reference_does_not_depend_on_the_start() {
    // φ is strictly convex: Newton from c = 0 must find what it finds from the exact solution
    // (on scenes where it stops within its cap from zero; on some hard scenes it needs more
    // than 500 steps, so the reference starts from the exact solution).
    let mut scenes: Vec<(String, Scene)> = (5..8)
        .map(|s| (format!("seed {s}"), hard_scene(s)))
        .collect();
    for name in ORDINARY_PRESETS {
        scenes.push((name.to_string(), preset_scene(name)));
    }
    let mp = Mp {
        precision: reference::mp::DEFAULT_PRECISION,
    };
    for (name, scene) in scenes {
        let (p, n) = problem_of(&scene);
        let mesh = Mesh::new(&p, n);
        for epsilon in [1e-10, 1e-6] {
            let [a, b] = [Start::Exact, Start::Zero].map(|start| {
                solve_epsilon_reference_from(&p, &mesh, epsilon, mp.precision, start)
                    .unwrap_or_else(|e| panic!("{name}, ε = {epsilon:e}, {start:?}: {e}"))
            });
            assert!(a.certificate.verified && b.certificate.verified, "{name}");
            assert_eq!(a.states, b.states, "{name}, ε = {epsilon:e}");
            let flat = |l: &[[F; 2]]| l.iter().flatten().cloned().collect::<Vec<F>>();
            for (what, x, y) in [
                ("u", &a.u, &b.u),
                ("slope", &a.slope, &b.slope),
                ("forces", &flat(&a.lambda), &flat(&b.lambda)),
            ] {
                let error = relative_vector(x, y, &mp);
                assert!(error < 1e-60, "{name}, ε = {epsilon:e}, {what}: {error:e}");
            }
        }
    }
}

#[test]
fn the_epsilon_reference_tends_to_the_exact_one() {
    // The ε-solution differs from the exact one by O(ε): a stuck DOF moves by |λ|ε/g ≤ ε, a
    // moving one keeps its force ±g while it moves by more than ε. So the nodal error is at
    // most about ε and never grows as ε shrinks, and the states are the exact ones wherever ε
    // is below the exact motion.
    let mut scenes: Vec<(String, Scene)> = ORDINARY_PRESETS
        .iter()
        .map(|name| (name.to_string(), preset_scene(name)))
        .collect();
    scenes.extend(
        regression_scenes()
            .into_iter()
            .filter(|(name, _)| name == "sign-change-symmetric" || name == "near-right-support"),
    );
    for (name, scene) in scenes {
        let (p, n) = problem_of(&scene);
        let mesh = Mesh::new(&p, n);
        let exact = solve_reference(&p, n);
        let mp = Mp {
            precision: exact.precision,
        };
        let mut previous = f64::INFINITY;
        for epsilon in [1e-4, 1e-6, 1e-8, 1e-10, 1e-12] {
            let r = solve_epsilon_reference(&p, &mesh, epsilon, exact.precision).unwrap();
            assert!(r.certificate.verified, "{name}: {:?}", r.certificate);
            let error = relative_vector(&r.u, &exact.u, &mp).max(relative_vector(
                &r.slope,
                &exact.slope,
                &mp,
            ));
            let absolute = |a: &[F], b: &[F]| {
                a.iter()
                    .zip(b)
                    .map(|(x, y)| to_f64(&abs(&(x - y))))
                    .fold(0f64, f64::max)
            };
            let (du, dt) = (absolute(&r.u, &exact.u), absolute(&r.slope, &exact.slope));
            // Measured: |Δu| ≤ 0.047 ε, |Δu'| ≤ 0.25 ε on these (l = 1); the relative error
            // shrinks exactly in proportion on the presets, and stays at rounding on
            // near-right-support until ε falls below its tiny exact slide (~1e-8 m).
            assert!(
                du <= epsilon && dt <= epsilon && error <= previous * (1.0 + 1e-6),
                "{name}, ε = {epsilon:e}: |Δu| {du:e}, |Δu'| {dt:e}, relative {error:e} after \
                 {previous:e}"
            );
            previous = error;
            // The states of the exact problem, wherever ε does not hide them: a motion above
            // 10 ε moves, a force clearly below its threshold stays stuck.
            let motion = exact.motion_f64();
            let lambda = exact.lambda_f64();
            for (j, (a, b)) in r.states.iter().zip(&exact.states).enumerate() {
                for k in 0..2 {
                    let g = [
                        p.obstacles[j].sliding_threshold,
                        p.obstacles[j].swivel_threshold,
                    ][k];
                    let decided = match b[k] {
                        FrictionState::Moves => motion[j][k].abs() > 10.0 * epsilon,
                        FrictionState::Stuck => epsilon <= 1e-8 && lambda[j][k].abs() < 0.999 * g,
                        FrictionState::AtThreshold => false,
                    };
                    assert!(
                        !decided || a[k] == b[k],
                        "{name}, ε = {epsilon:e}, obstacle {j}: {a:?} / {b:?}"
                    );
                }
            }
        }
        assert!(previous < 1e-9, "{name}: {previous:e} at ε = 1e-12");
    }
}

/// Benchmark 1 seen from the obstacle: the exact 2×2 stiffness of the two clamped stretches
/// a = 0.8, b = l − 0.8 and their fixed-end load, in the working precision (K11, K12, K22,
/// r0, r1) — as in [`benchmark_1_closed_form`], with K22 = EJ (4/a + 4/b).
fn benchmark_1_stiffness(mp: &Mp) -> [F; 5] {
    let n = |x: f64| mp.num(x);
    let problem = problem(&preset_scene("benchmark-1"));
    let ej = n(problem.stiffness[0].bending_stiffness);
    let (a, b, f) = (n(0.8), n(1.0) - n(0.8), n(5e4));
    let cube = |x: &F| x * x * x;
    [
        &ej * (n(12.0) / cube(&a) + n(12.0) / cube(&b)),
        &ej * (n(6.0) / (&b * &b) - n(6.0) / (&a * &a)),
        &ej * (n(4.0) / &a + n(4.0) / &b),
        &f * (&a + &b) / n(2.0),
        &f * (&b * &b - &a * &a) / n(12.0),
    ]
}

#[test]
fn the_epsilon_reference_solves_benchmark_1_by_hand() {
    // With the pattern of regions known, (43) seen from the obstacle is a 2×2 system, solved
    // here by Cramer's rule: (K + D) (u, u') = r − d, D = g/ε on middle DOFs, d = ±g on outer
    // ones. The preset slides (u ≈ 5.7e-3 > ε, d1 = g1) with the swivel in the middle region;
    // with thresholds of 1e20 both DOFs are in the middle; with zero thresholds the beam is
    // unconstrained (u = f x²(l − x)²/(24 EJ) at every node).
    let mp = Mp {
        precision: reference::mp::DEFAULT_PRECISION,
    };
    let n = |x: f64| mp.num(x);
    let [k11, k12, k22, r0, r1] = benchmark_1_stiffness(&mp);
    for (g1, g2) in [(1e2, 5e4), (1e20, 1e20), (0.0, 0.0)] {
        let mut scene = preset_scene("benchmark-1");
        scene.obstacles[0].sliding = g1;
        scene.obstacles[0].swivel = g2;
        let p = problem(&scene);
        for epsilon in [1e-10, 1e-6, 1e-3] {
            let eps = n(epsilon);
            let (g1, g2) = (n(g1), n(g2));
            // Sliding outside (positive) unless g1 is huge, swivel in the middle.
            let sliding_outside = g1 < n(1e10);
            let (a11, rhs0) = if sliding_outside {
                (k11.clone(), &r0 - &g1)
            } else {
                (&k11 + &g1 / &eps, r0.clone())
            };
            let a22 = &k22 + &g2 / &eps;
            let det = &a11 * &a22 - &k12 * &k12;
            let u = (&rhs0 * &a22 - &k12 * &r1) / &det;
            let t = (&a11 * &r1 - &k12 * &rhs0) / &det;
            // (A zero threshold adds nothing in any region.)
            assert!(
                (is_zero(&g2) || abs(&t) <= eps) && (u > eps) == sliding_outside,
                "the pattern assumed"
            );
            for elements in [1, 2, 3, 20, 57] {
                let mesh = Mesh::new(&p, elements);
                let r = solve_epsilon_reference(&p, &mesh, epsilon, mp.precision).unwrap();
                assert!(r.certificate.verified, "{:?}", r.certificate);
                let [ru, rt] = &r.motion[0];
                let what = format!("g = {g1}, {g2}, ε = {epsilon:e}, n = {elements}");
                assert!(relative(ru, &u) < 1e-25, "{what}: u {:e}", relative(ru, &u));
                if is_zero(&g2) {
                    assert!(
                        relative(rt, &t) < 1e-25,
                        "{what}: u' {:e}",
                        relative(rt, &t)
                    );
                } else {
                    // u' is ε λ2/g2: compare the moment, relative to its size.
                    let moment = &g2 * &t / &eps;
                    let error = relative(&r.lambda[0][1], &moment);
                    assert!(error < 1e-25, "{what}: moment {error:e}");
                }
                let force = if sliding_outside {
                    g1.clone()
                } else {
                    &g1 * &u / &eps
                };
                assert!(
                    relative(&r.lambda[0][0], &force) < 1e-25 || is_zero(&g1),
                    "{what}: force"
                );
                let expected = if is_zero(&g1) {
                    [FrictionState::Moves, FrictionState::Moves]
                } else if sliding_outside {
                    [FrictionState::Moves, FrictionState::Stuck]
                } else {
                    [FrictionState::Stuck, FrictionState::Stuck]
                };
                assert_eq!(r.states[0], expected, "{what}");
                if is_zero(&g1) {
                    // Unconstrained: the clamped beam under a uniform load at every node.
                    let ej = n(p.stiffness[0].bending_stiffness);
                    let f = n(5e4);
                    for (i, x) in r.nodes.iter().enumerate() {
                        let x = n(*x);
                        let y = n(1.0) - &x;
                        let exact_u = &f * &x * &x * &y * &y / (n(24.0) * &ej);
                        let exact_t = &f * &x * &y * (&y - &x) / (n(12.0) * &ej);
                        assert!(relative(&r.u[i], &exact_u) < 1e-25 || is_zero(&exact_u));
                        assert!(relative(&r.slope[i], &exact_t) < 1e-25 || is_zero(&exact_t));
                    }
                }
            }
        }
    }
}
