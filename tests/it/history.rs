//! The convergence history of `SolveOptions::history` (issue 24): nothing recorded and no
//! result changed when it is off; when on, the last iterate is the answer, the measures are
//! finite and the box QP's ends at zero; `iterate_field` of the final forces is the solution's
//! field; `solve --history` in JSON and CSV.

use beamfric::fem::Mesh;
use beamfric::model::Problem;
use beamfric::solve::{
    ConditionLevel, History, Method, ProgressMeasure, Solution, SolveError, SolveOptions, Timing,
    iterate_field, solve,
};
use serde_json::Value;

use crate::harness::process::{NO_COLOR, beamfric_with};
use crate::harness::scenes::{preset_scene, problem, relative_difference};

/// Benchmark 1, Benchmark 3 and a stiff preset (a segment 10⁶ times stiffer).
const PRESETS: [&str; 3] = ["benchmark-1", "benchmark-3", "modulus-contrast"];

/// The methods that iterate, and the measure each records.
const ITERATING: [(Method, ProgressMeasure); 5] = [
    (Method::Dual, ProgressMeasure::ProjectedGradient),
    (Method::DualInverse, ProgressMeasure::ProjectedGradient),
    (Method::Flexibility, ProgressMeasure::ProjectedGradient),
    (
        Method::RegularizedNewton,
        ProgressMeasure::SemismoothResidual,
    ),
    (Method::Condensed, ProgressMeasure::KktResidual),
];

/// A preset's problem and mesh, at the preset's own number of elements.
fn scene(name: &str) -> (Problem, Mesh) {
    let scene = preset_scene(name);
    let problem = problem(&scene);
    let mesh = Mesh::new(&problem, scene.mesh.elements);
    (problem, mesh)
}

fn solved(
    (problem, mesh): &(Problem, Mesh),
    method: Method,
    history: bool,
) -> Result<Solution, SolveError> {
    let options = SolveOptions {
        history,
        condition: ConditionLevel::Auto,
        ..SolveOptions::default()
    };
    solve(problem, mesh, method, &options)
}

/// Every f64 a solution reports, as bits (NaN and −0 included).
fn bits(solution: &Solution) -> Vec<u64> {
    let field = &solution.field;
    field
        .deflection
        .iter()
        .chain(&field.slope)
        .copied()
        .chain(
            solution
                .obstacles
                .iter()
                .flat_map(|o| [o.force, o.moment, o.u, o.slope]),
        )
        .chain([solution.kkt_residual])
        .map(f64::to_bits)
        .collect()
}

#[test]
fn history_off_records_nothing_and_on_changes_no_result() {
    for name in PRESETS {
        let scene = scene(name);
        for method in Method::ALL {
            let off = solved(&scene, method, false);
            let on = solved(&scene, method, true);
            match (off, on) {
                (Ok(off), Ok(on)) => {
                    assert_eq!(off.history, None, "{name} {method}");
                    assert_eq!(bits(&off), bits(&on), "{name} {method}");
                    let untimed = |s: Solution| Solution {
                        timing: Timing::default(),
                        history: None,
                        ..s
                    };
                    assert_eq!(untimed(off), untimed(on), "{name} {method}");
                }
                (Err(off), Err(on)) => assert_eq!(off, on, "{name} {method}"),
                (off, on) => panic!("{name} {method}: {off:?} but with history {on:?}"),
            }
        }
    }
}

/// The recorded history of an iterating method.
fn recorded(scene: &(Problem, Mesh), method: Method) -> (Solution, History) {
    let solution = solved(scene, method, true).unwrap_or_else(|e| panic!("{method}: {e}"));
    let history = solution.history.clone().expect("asked for");
    (solution, history)
}

#[test]
fn the_last_recorded_iterate_is_the_answer() {
    for name in PRESETS {
        let scene = scene(name);
        for (method, measure) in ITERATING {
            let (solution, history) = recorded(&scene, method);
            let what = format!("{name} {method}");
            assert_eq!(
                (history.method, history.measure),
                (method, measure),
                "{what}"
            );
            assert!(!history.truncated, "{what}");
            assert_eq!(history.iterations[0].iteration, 0, "{what}");
            for pair in history.iterations.windows(2) {
                assert!(pair[0].iteration < pair[1].iteration, "{what}");
            }
            for record in &history.iterations {
                assert!(
                    record.measure.is_finite() && record.measure >= 0.0,
                    "{what}: {record:?}"
                );
                assert!(record.objective.is_none_or(f64::is_finite), "{what}");
                assert!(record.changed <= 2 * solution.obstacles.len(), "{what}");
                assert_eq!(record.forces.len(), solution.obstacles.len(), "{what}");
            }
            let last = history.iterations.last().expect("an iterate");
            let answer: Vec<[u64; 2]> = solution
                .obstacles
                .iter()
                .map(|o| [o.force.to_bits(), o.moment.to_bits()])
                .collect();
            let recorded: Vec<[u64; 2]> = last
                .forces
                .iter()
                .map(|[f, m]| [f.to_bits(), m.to_bits()])
                .collect();
            assert_eq!(recorded, answer, "{what}");
            // The box QP ends at its solution: a projected gradient of rounding size (the
            // measure is relative to ‖z‖); the others at their own stopping tests.
            let limit = if measure == ProgressMeasure::ProjectedGradient {
                1e-12
            } else {
                1e-9
            };
            assert!(
                last.measure <= limit,
                "{what}: final measure {}",
                last.measure
            );
        }
    }
}

#[test]
fn methods_without_iterations_record_no_history() {
    let scene = scene("benchmark-1");
    for method in [Method::Regularized, Method::ClosedForm] {
        let solution = solved(&scene, method, true).expect("solves Benchmark 1");
        assert_eq!(solution.history, None, "{method}");
    }
}

/// Solves A u = F − Bᵀλ the way the stiffness route does, so it agrees with every method to
/// rounding where A is well conditioned (measured: ≤ 1.7e-13 on Benchmarks 1 and 3), and on the
/// stiff preset with the stiffness-route methods to 2e-10 and with the exact ones
/// (flexibility, condensed) to within what the stiffness route loses there itself (1e-3, the
/// `dual` method's own error being 7.4e-4): u(x) for drawing, not a reference.
#[test]
fn iterate_field_of_the_final_forces_is_the_solution() {
    for name in PRESETS {
        let scene = scene(name);
        let (problem, mesh) = &scene;
        let stiffness_route_error = solved(&scene, Method::Dual, false)
            .expect("dual solves")
            .error
            .and_then(|e| e.max_rel)
            .expect("an error against the reference");
        for (method, _) in ITERATING {
            let (solution, history) = recorded(&scene, method);
            let forces = &history.iterations.last().expect("an iterate").forces;
            let field = iterate_field(problem, mesh, forces).expect("a field");
            let deflection = relative_difference(&field.deflection, &solution.field.deflection);
            let slope = relative_difference(&field.slope, &solution.field.slope);
            let limit = match (name, method) {
                ("modulus-contrast", Method::Dual | Method::RegularizedNewton) => 1e-9,
                ("modulus-contrast", _) => 10.0 * stiffness_route_error,
                _ => 1e-12,
            };
            assert!(
                deflection <= limit && slope <= limit,
                "{name} {method}: u off by {deflection:.1e}, u' by {slope:.1e}"
            );
        }
    }
}

#[test]
fn iterate_field_refuses_the_wrong_number_of_forces() {
    let (problem, mesh) = scene("benchmark-3");
    let error = iterate_field(&problem, &mesh, &[[0.0, 0.0]]).unwrap_err();
    assert!(error.contains("1 force pairs for 4 obstacles"), "{error}");
}

fn run(args: &[&str]) -> String {
    let out = beamfric_with(args, NO_COLOR);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("UTF-8")
}

#[test]
fn solve_history_json_holds_every_iterate() {
    let args = ["solve", "--scene", "benchmark-1", "--method", "dual"];
    let text = run(&[&args[..], &["--history", "--format", "json", "--no-nodes"]].concat());
    let doc: Value = serde_json::from_str(&text).expect("JSON");
    let history = &doc["history"];
    assert_eq!(history["method"], "dual");
    assert_eq!(history["measure"], "projected-gradient");
    assert_eq!(history["truncated"], false);
    let iterations = history["iterations"].as_array().expect("iterations");
    assert_eq!(iterations[0]["iteration"], 0);
    let last = iterations.last().expect("an iterate");
    assert_eq!(last["forces"][0]["force"], doc["obstacles"][0]["force"]);
    assert_eq!(last["forces"][0]["moment"], doc["obstacles"][0]["moment"]);
    assert_eq!(last["measure"], 0.0);
    // Without --history there is no history at all.
    let plain: Value =
        serde_json::from_str(&run(
            &[&args[..], &["--format", "json", "--no-nodes"]].concat()
        ))
        .expect("JSON");
    assert!(plain.get("history").is_none());
}

#[test]
fn solve_history_csv_is_one_row_per_iterate() {
    let text = run(&[
        "solve",
        "--scene",
        "benchmark-3",
        "--method",
        "regularized-newton",
        "--history",
        "--format",
        "csv",
    ]);
    let mut lines = text.lines();
    let header = lines.next().expect("a header");
    let mut expected = "iteration,semismooth_residual,objective_J,changed".to_string();
    for j in 1..=4 {
        expected += &format!(",force_N_{j},moment_Nm_{j}");
    }
    assert_eq!(header, expected);
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert!(rows.len() >= 2, "{text}");
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row.len(), 12, "{text}");
        assert_eq!(row[0], i.to_string());
        for value in &row[1..] {
            value.parse::<f64>().expect("a number");
        }
    }
    // Moving DOFs sit at their thresholds: 1e4 N on every obstacle at the end.
    assert_eq!(rows.last().expect("a row")[4], "1e4");
}

#[test]
fn csv_without_history_and_history_in_a_table_are_refused() {
    for extra in [&["--format", "csv"][..], &["--history"][..]] {
        let out = beamfric_with(
            &[&["solve", "--scene", "benchmark-1"][..], extra].concat(),
            NO_COLOR,
        );
        assert_eq!(out.status.code(), Some(2), "{extra:?}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains("--history"), "{stderr}");
    }
}
