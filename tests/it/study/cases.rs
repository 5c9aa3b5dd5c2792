//! The case table of the regularised method (Table 1, (43)) against an independent
//! enumeration: every case assembled as a dense finite-element system with its g/ε diagonal
//! additions and ±g right-hand sides, solved by Gaussian elimination, judged here.

use beamfric::fem::Mesh;
use beamfric::model::Problem;
use beamfric::solve::{ConditionLevel, MAX_CASES, Method, SolveOptions, solve};
use beamfric::study::{Cancelled, CaseRow, CaseStudy, CaseTable, Region, case_study};

use super::{
    cancelled, dense_system, eigen_condition, friction_index, gaussian_solve, relative, steel_beam,
};
use crate::harness::scenes::{preset_scene, problem};

/// One case as the test sees it.
struct IndependentCase {
    regions: Vec<Region>,
    consistent: bool,
    violation: f64,
    condition: f64,
}

/// Region of digit q of `case` in base 3: 0 middle, 1 positive, 2 negative.
fn regions_of(case: u64, dofs: usize) -> Vec<Region> {
    let mut code = case;
    (0..dofs)
        .map(|_| {
            let r = match code % 3 {
                0 => Region::Middle,
                1 => Region::Positive,
                _ => Region::Negative,
            };
            code /= 3;
            r
        })
        .collect()
}

/// Every case of (43) solved densely.
fn independent_cases(problem: &Problem, mesh: &Mesh, epsilon: f64) -> Vec<IndependentCase> {
    let (a, b, n) = dense_system(problem, mesh);
    let k = problem.obstacles.len();
    let g = problem.thresholds();
    (0..9u64.pow(k as u32))
        .map(|case| {
            let regions = regions_of(case, 2 * k);
            let (mut matrix, mut rhs) = (a.clone(), b.clone());
            for (q, region) in regions.iter().enumerate() {
                let i = friction_index(mesh, q / 2, q % 2);
                match region {
                    Region::Middle => matrix[i * n + i] += g[q] / epsilon,
                    Region::Positive => rhs[i] -= g[q],
                    Region::Negative => rhs[i] += g[q],
                }
            }
            let c = gaussian_solve(&matrix, &rhs, n).expect("every case matrix is regular");
            let violation = regions
                .iter()
                .enumerate()
                .map(|(q, region)| {
                    let v = c[friction_index(mesh, q / 2, q % 2)];
                    let outside = match region {
                        Region::Negative => v + epsilon,
                        Region::Middle => v.abs() - epsilon,
                        Region::Positive => epsilon - v,
                    };
                    outside.max(0.0) / epsilon
                })
                .fold(0.0, f64::max);
            IndependentCase {
                regions,
                consistent: violation == 0.0,
                violation,
                condition: eigen_condition(&matrix, n),
            }
        })
        .collect()
}

/// The case the method keeps: the first consistent one, else the first of least violation.
fn independent_pick(cases: &[IndependentCase]) -> u64 {
    let mut best = 0;
    for (i, case) in cases.iter().enumerate() {
        if case.violation < cases[best].violation {
            best = i;
        }
    }
    cases.iter().position(|c| c.consistent).unwrap_or(best) as u64
}

/// The regions the regularised solve's friction values lie in.
fn solved_regions(problem: &Problem, mesh: &Mesh, epsilon: f64) -> Vec<Region> {
    let options = SolveOptions {
        epsilon,
        condition: ConditionLevel::Off,
        reference: false,
        ..SolveOptions::default()
    };
    let solution = solve(problem, mesh, Method::Regularized, &options).unwrap();
    solution
        .obstacles
        .iter()
        .flat_map(|o| [o.u, o.slope])
        .map(|c| {
            if c > epsilon {
                Region::Positive
            } else if c < -epsilon {
                Region::Negative
            } else {
                Region::Middle
            }
        })
        .collect()
}

/// Compares the study's table with the independent enumeration, row by row.
fn check_against_independent(problem: &Problem, elements: usize, epsilon: f64) -> CaseStudy {
    let mesh = Mesh::new(problem, elements);
    let study = case_study(problem, &mesh, epsilon, MAX_CASES, &Default::default())
        .unwrap()
        .unwrap();
    let expected = independent_cases(problem, &mesh, epsilon);
    let CaseTable::All { rows, picked } = &study.table else {
        panic!("k ≤ 2 lists every case: {:?}", study.table);
    };
    assert_eq!(rows.len(), expected.len());
    for (i, (row, want)) in rows.iter().zip(&expected).enumerate() {
        assert_eq!(row.index, i as u64);
        assert_eq!(row.regions, want.regions, "case {i}");
        assert_eq!(row.consistent, want.consistent, "case {i}: {row:?}");
        assert!(
            (row.worst_violation - want.violation).abs() <= 1e-6 * want.violation.max(1.0),
            "case {i}: violation {} against {}",
            row.worst_violation,
            want.violation
        );
        let condition = row.condition.expect("N ≤ 200: condition computed");
        assert!(
            relative(condition, want.condition) < 1e-8,
            "case {i}: cond {condition:e} against {:e}",
            want.condition
        );
    }
    let want_pick = independent_pick(&expected);
    assert_eq!(*picked, Some(want_pick));
    assert_eq!(study.picked(), Some(want_pick));
    // The case `solve` keeps: its friction values lie in the picked case's regions.
    assert!(expected[want_pick as usize].consistent);
    assert_eq!(
        solved_regions(problem, &mesh, epsilon),
        expected[want_pick as usize].regions
    );
    study
}

#[test]
fn benchmark_1_case_table_matches_an_independent_dense_enumeration() {
    let problem = problem(&preset_scene("benchmark-1"));
    for epsilon in [1e-6, 1e-4] {
        let study = check_against_independent(&problem, 20, epsilon);
        assert_eq!(study.conditioned.cases_conditioned, 9);
        assert_eq!(study.conditioned.cases_total, 9);
    }
}

#[test]
fn two_obstacle_case_table_matches_an_independent_dense_enumeration() {
    // One obstacle that slides and swivels, one that sticks; a stepped beam.
    let problem = steel_beam(&[(0.3, 50.0, 20.0), (0.75, 3e4, 5e4)], true);
    let study = check_against_independent(&problem, 24, 1e-6);
    let CaseTable::All { rows, .. } = &study.table else {
        unreachable!()
    };
    assert_eq!(rows.len(), 81);
    assert_eq!(study.conditioned.cases_conditioned, 2);
    assert_eq!(study.conditioned.cases_total, 81);
    assert!(
        study.conditioned.description.contains("2 of 81"),
        "{}",
        study.conditioned.description
    );
    // Symbols.
    let symbols: String = rows[5].regions.iter().map(|r| r.symbol()).collect();
    let ascii: String = rows[5].regions.iter().map(|r| r.ascii()).collect();
    assert_eq!(symbols, "−+00");
    assert_eq!(ascii, "-+00");
}

#[test]
fn benchmark_3_counts_its_6561_cases_and_says_which_the_chart_conditions() {
    let problem = problem(&preset_scene("benchmark-3"));
    let mesh = Mesh::new(&problem, 20);
    let study = case_study(&problem, &mesh, 1e-6, MAX_CASES, &Default::default())
        .unwrap()
        .unwrap();
    let CaseTable::Counted {
        cases,
        tried,
        consistent,
        refused,
    } = study.table
    else {
        panic!("k = 4 is counted: {:?}", study.table);
    };
    assert_eq!(cases, 6561);
    assert!(!refused);
    assert!(consistent >= 1 && tried >= 1 && tried <= cases);
    let kept: &CaseRow = study.kept.as_ref().unwrap();
    assert_eq!(
        kept.index,
        tried - 1,
        "the method stops at the first consistent case"
    );
    assert!(kept.consistent && kept.condition.is_some());
    assert_eq!(kept.regions, solved_regions(&problem, &mesh, 1e-6));
    assert_eq!(
        study.conditioned.description,
        "cond₂ over 2 of 6561 cases: the kept one and the all-middle one (every g/ε added)"
    );
    // Refused over the limit, and nothing solved.
    let refused = case_study(&problem, &mesh, 1e-6, 100, &Default::default())
        .unwrap()
        .unwrap();
    assert_eq!(
        refused.table,
        CaseTable::Counted {
            cases: 6561,
            tried: 0,
            consistent: 0,
            refused: true
        }
    );
    assert_eq!(refused.kept, None);
}

#[test]
fn the_case_study_is_cancelled_and_refuses_a_bad_epsilon_without_panicking() {
    let problem = problem(&preset_scene("benchmark-3"));
    let mesh = Mesh::new(&problem, 20);
    assert_eq!(
        case_study(&problem, &mesh, 1e-6, MAX_CASES, &cancelled()),
        Err(Cancelled)
    );
    for epsilon in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(
            case_study(&problem, &mesh, epsilon, MAX_CASES, &Default::default())
                .unwrap()
                .is_err()
        );
    }
}

#[test]
fn the_case_study_survives_every_preset() {
    for preset in beamfric::scene::PRESETS {
        let loaded = crate::harness::scenes::loaded_preset(preset.name);
        let mesh = Mesh::new(&loaded.problem, loaded.settings.elements.min(200));
        let study = case_study(
            &loaded.problem,
            &mesh,
            loaded.settings.epsilon,
            9u64.pow(3),
            &Default::default(),
        )
        .unwrap();
        if let Ok(study) = study {
            assert!(!study.conditioned.description.is_empty(), "{}", preset.name);
        }
    }
}
