//! The `condensed` method (issue 10): against the closed form, the reference files, `dual` on
//! ordinary scenes, and exact expectations on the hard scenes that broke `flexibility` and
//! `dual` (clamped spans when every obstacle sticks, scaling invariance, merged obstacles).

mod common;

use beamfric::fem::{Mesh, element_load};
use beamfric::model::{LinearLoad, Obstacle, Problem, StiffnessPiece};
use beamfric::scene::{ObstacleSpec, Scene};
use beamfric::solve::{
    ConditionLevel, FrictionState, Method, SolveOptions, closed_form, solve, solve_condensed,
};
use common::*;

/// u(x̂) of Benchmark 1, 0.0057016100178890876565 m, rounded to double precision.
const BENCHMARK_1_U: f64 = 0.005_701_610_017_889_088;
const BENCHMARK_1_MOMENT: f64 = -4_798.461_538_461_538;

fn fast_options() -> SolveOptions {
    SolveOptions {
        condition: ConditionLevel::Off,
        reference: false,
        ..SolveOptions::default()
    }
}

fn benchmark(name: &str) -> Problem {
    problem(&preset_scene(name))
}

/// A problem with uniform E·J and the given load and obstacles (x, g1, g2).
fn beam(length: f64, stiffness: f64, load: [f64; 2], obstacles: &[(f64, f64, f64)]) -> Problem {
    Problem {
        length,
        stiffness: vec![StiffnessPiece {
            from: 0.0,
            to: length,
            bending_stiffness: stiffness,
        }],
        load: LinearLoad {
            f0: load[0],
            f1: load[1],
        },
        obstacles: obstacles
            .iter()
            .map(|&(x, g1, g2)| Obstacle {
                x,
                sliding_threshold: g1,
                swivel_threshold: g2,
            })
            .collect(),
    }
}

/// max |a − b| / max(|b|).
fn max_relative(a: &[f64], b: &[f64]) -> f64 {
    relative_difference(a, b)
}

#[test]
fn benchmark_1_matches_the_closed_form_at_20_1000_and_a_million_elements() {
    let problem = benchmark("benchmark-1");
    let exact = closed_form(&problem).unwrap();
    for n in [20usize, 1000, 1_000_000] {
        let mesh = Mesh::new(&problem, n);
        let solution = solve_condensed(&problem, &mesh).unwrap();
        let reference = exact.nodal_field(&mesh);
        let u_error = max_relative(&solution.field.deflection, &reference.deflection);
        let slope_error = max_relative(&solution.field.slope, &reference.slope);
        assert!(u_error <= 1e-13, "n = {n}: u error {u_error:e}");
        assert!(slope_error <= 1e-13, "n = {n}: slope error {slope_error:e}");
        let node = mesh.obstacle_nodes[0];
        assert!(
            (solution.field.deflection[node] - BENCHMARK_1_U).abs() <= 1e-14 * BENCHMARK_1_U,
            "n = {n}: u(0.8) = {:e}",
            solution.field.deflection[node]
        );
        assert_eq!(solution.field.slope[node], 0.0);
        let [force, moment] = solution.friction[0];
        assert_eq!(force, 100.0);
        assert!(
            (moment - BENCHMARK_1_MOMENT).abs() <= 1e-11 * BENCHMARK_1_MOMENT.abs(),
            "moment {moment}"
        );
        assert_eq!(
            solution.states[0],
            [FrictionState::Moves, FrictionState::Stuck]
        );
    }
}

#[test]
fn benchmarks_match_the_reference_files() {
    for name in ["benchmark-1", "benchmark-2", "benchmark-3"] {
        let problem = benchmark(name);
        let reference = reference_values(name);
        let mesh = Mesh::new(&problem, 20);
        let solution = solve_condensed(&problem, &mesh).unwrap();
        let u_error = max_relative(&solution.field.deflection, &reference.u);
        let slope_error = max_relative(&solution.field.slope, &reference.slope);
        assert!(u_error < 1e-12, "{name}: u {u_error:e}");
        assert!(slope_error < 1e-12, "{name}: slope {slope_error:e}");
        for (got, want) in solution.friction.iter().zip(&reference.friction) {
            for d in 0..2 {
                // The files print 13 significant digits.
                assert!(
                    (got[d] - want[d]).abs() <= 1e-12 * want[d].abs().max(1.0) + 1e-9,
                    "{name}: {got:?} vs {want:?}"
                );
            }
        }
    }
}

#[test]
fn certify_accepts_benchmark_1_through_solve() {
    let problem = benchmark("benchmark-1");
    let mesh = Mesh::new(&problem, 20);
    let solution = solve(&problem, &mesh, Method::Condensed, &options(1e-6)).unwrap();
    assert!(solution.kkt_residual < 1e-13, "{}", solution.kkt_residual);
    assert!(solution.warnings.is_empty(), "{:?}", solution.warnings);
    let o = solution.obstacles[0];
    assert!(o.sliding && !o.swivel);
    assert_eq!(o.force, 100.0);
    let error = solution.error.unwrap().max_rel.unwrap();
    assert!(error < 1e-14, "{error:e} against the closed form");
}
