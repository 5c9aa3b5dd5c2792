//! The dual (49) restricted to one obstacle's pair: where the solution sits on the box
//! against the Results state, and the pair's minimisers against a grid and a projected
//! gradient here.

use beamfric::fem::Mesh;
use beamfric::model::Problem;
use beamfric::solve::{FrictionState, Method, ObstacleResult, SolveOptions, solve};
use beamfric::study::{BoxPosition, DualPair, dual_pair};

use super::steel_beam;
use crate::harness::scenes::{preset_scene, problem};

fn solve_dual(problem: &Problem, mesh: &Mesh) -> Vec<ObstacleResult> {
    solve(problem, mesh, Method::Dual, &SolveOptions::default())
        .unwrap()
        .obstacles
}

/// The position the Results state names.
fn position_of(result: &ObstacleResult) -> BoxPosition {
    use FrictionState::{AtThreshold, Moves, Stuck};
    match (result.sliding_state, result.swivel_state) {
        (Stuck, Stuck) => BoxPosition::Interior,
        (Moves, Stuck) => BoxPosition::SlidingEdge,
        (Stuck, Moves) => BoxPosition::SwivelEdge,
        (Moves, Moves) => BoxPosition::Corner,
        (AtThreshold, _) | (_, AtThreshold) => BoxPosition::Undecided,
    }
}

/// The minimiser over the box by projected gradient in unit-diagonal coordinates.
fn projected_gradient(pair: &DualPair) -> [f64; 2] {
    let (s, r, g) = (pair.flexibility, pair.linear, pair.thresholds);
    let d = [1.0 / s[0][0].sqrt(), 1.0 / s[1][1].sqrt()];
    let h = [[1.0, s[0][1] * d[0] * d[1]], [s[1][0] * d[0] * d[1], 1.0]];
    let z = [r[0] * d[0], r[1] * d[1]];
    let bound = [g[0] / d[0], g[1] / d[1]];
    let mut y = [0.0, 0.0];
    for _ in 0..20_000 {
        let gradient = [
            h[0][0] * y[0] + h[0][1] * y[1] - z[0],
            h[1][0] * y[0] + h[1][1] * y[1] - z[1],
        ];
        for i in 0..2 {
            y[i] = (y[i] - 0.5 * gradient[i]).clamp(-bound[i], bound[i]);
        }
    }
    [y[0] * d[0], y[1] * d[1]]
}

/// Checks the pair's minimisers: the unconstrained one has zero gradient, and the solution
/// is the minimiser over the box (a fine grid finds nothing lower, projected gradient finds
/// the same point).
fn check_minimisers(pair: &DualPair) {
    let (s, r, m) = (pair.flexibility, pair.linear, pair.minimiser);
    for i in 0..2 {
        let gradient = s[i][0] * m[0] + s[i][1] * m[1] - r[i];
        let scale = (s[i][0] * m[0]).abs() + (s[i][1] * m[1]).abs() + r[i].abs();
        assert!(gradient.abs() <= 1e-12 * scale, "{pair:?}");
    }
    for step in [[1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, -1.0]] {
        for h in [1e-3, -1e-3] {
            let near = [m[0] * (1.0 + h * step[0]), m[1] * (1.0 + h * step[1])];
            assert!(pair.value(near) >= pair.value(m));
        }
    }
    let g = pair.thresholds;
    let best = pair.value(pair.solution);
    let scale = pair.value(pair.minimiser).abs().max(best.abs());
    let steps = 200;
    for a in 0..=steps {
        for b in 0..=steps {
            let l = [
                g[0] * (2.0 * a as f64 / steps as f64 - 1.0),
                g[1] * (2.0 * b as f64 / steps as f64 - 1.0),
            ];
            assert!(
                pair.value(l) >= best - 1e-12 * scale,
                "{l:?} below the solution"
            );
        }
    }
    let projected = projected_gradient(pair);
    let exact = pair.box_minimiser();
    for i in 0..2 {
        let tolerance = 1e-8 * g[i].max(pair.solution[i].abs()).max(1e-300);
        assert!(
            (projected[i] - pair.solution[i]).abs() <= tolerance,
            "{pair:?}: {projected:?}"
        );
        assert!(
            (exact[i] - pair.solution[i]).abs() <= tolerance,
            "{pair:?}: {exact:?}"
        );
    }
}

#[test]
fn benchmark_1_solution_sits_on_the_box_where_its_state_says() {
    let base = problem(&preset_scene("benchmark-1"));
    let mut seen = Vec::new();
    for g1 in [1e2, 5e4] {
        for g2 in [1e2, 5e4] {
            let mut problem = base.clone();
            problem.obstacles[0].sliding_threshold = g1;
            problem.obstacles[0].swivel_threshold = g2;
            let mesh = Mesh::new(&problem, 20);
            let results = solve_dual(&problem, &mesh);
            let forces: Vec<[f64; 2]> = results.iter().map(|o| [o.force, o.moment]).collect();
            let pair = dual_pair(&problem, &mesh, &forces, 0).unwrap();
            assert_eq!(pair.thresholds, [g1, g2]);
            assert_eq!(pair.solution, forces[0]);
            assert_eq!(
                pair.position,
                position_of(&results[0]),
                "g = ({g1}, {g2}): {} — {pair:?}",
                results[0].state()
            );
            // The motion is the solution's own (to rounding of the terms of z0 − S λ).
            for (motion, value) in pair.motion.iter().zip([results[0].u, results[0].slope]) {
                assert!(
                    (motion - value).abs() <= 1e-9 * value.abs() + 1e-15,
                    "{pair:?}"
                );
            }
            check_minimisers(&pair);
            seen.push(pair.position);
        }
    }
    // The paper's case slides; a small swivel threshold makes it swivel too.
    assert_eq!(seen[1], BoxPosition::SlidingEdge, "{seen:?}");
    assert!(
        seen.contains(&BoxPosition::Corner) || seen.contains(&BoxPosition::SwivelEdge),
        "{seen:?}"
    );
}

#[test]
fn with_two_obstacles_each_pair_is_the_minimiser_given_the_other() {
    let problem = steel_beam(&[(0.3, 50.0, 20.0), (0.75, 3e4, 5e4)], true);
    let mesh = Mesh::new(&problem, 40);
    let results = solve_dual(&problem, &mesh);
    let forces: Vec<[f64; 2]> = results.iter().map(|o| [o.force, o.moment]).collect();
    for (j, result) in results.iter().enumerate() {
        let pair = dual_pair(&problem, &mesh, &forces, j).unwrap();
        assert_eq!(pair.obstacle, j);
        assert_eq!(pair.position, position_of(result), "{pair:?}");
        check_minimisers(&pair);
        // The level curve through the solution passes through it and stays on its level.
        let level = pair.value(pair.solution);
        let curve = pair.level_curve(level, 65);
        assert_eq!(curve.len(), 65);
        assert_eq!(curve[0], curve[64]);
        let spread = level - pair.minimum();
        for p in &curve {
            assert!((pair.value(*p) - level).abs() <= 1e-9 * spread.abs().max(level.abs()));
        }
        assert!(
            pair.level_curve(pair.minimum() - spread.abs() - 1.0, 10)
                .is_empty()
        );
    }
}

#[test]
fn dual_pair_refuses_what_does_not_fit_and_survives_every_preset() {
    let problem = problem(&preset_scene("benchmark-1"));
    let mesh = Mesh::new(&problem, 20);
    assert!(dual_pair(&problem, &mesh, &[[0.0, 0.0]], 1).is_err());
    assert!(dual_pair(&problem, &mesh, &[], 0).is_err());
    assert!(dual_pair(&problem, &mesh, &[[f64::NAN, 0.0]], 0).is_err());
    for preset in beamfric::scene::PRESETS {
        let loaded = crate::harness::scenes::loaded_preset(preset.name);
        let mesh = Mesh::new(&loaded.problem, loaded.settings.elements.min(2000));
        let Ok(solution) = solve(
            &loaded.problem,
            &mesh,
            Method::Dual,
            &SolveOptions::default(),
        ) else {
            continue;
        };
        let forces: Vec<[f64; 2]> = solution
            .obstacles
            .iter()
            .map(|o| [o.force, o.moment])
            .collect();
        for (j, result) in solution.obstacles.iter().enumerate() {
            if let Ok(pair) = dual_pair(&loaded.problem, &mesh, &forces, j) {
                assert_eq!(
                    pair.position,
                    position_of(result),
                    "{} obstacle {j}: {pair:?}",
                    preset.name
                );
                let _ = pair.level_curve(pair.value(pair.solution), 16);
                let _ = pair.box_minimiser();
            }
        }
    }
}
