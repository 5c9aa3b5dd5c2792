//! Issues 11 and 22: a solve whose result is no longer wanted stops inside its long loops as
//! soon as its `Cancellation` says so — every method, in the stage where it spends its time
//! (the box QP of 256 obstacles, the N = 4000 dense inverse, Newton's 1022 × 1022 Cholesky, the
//! 9⁶ cases, the pattern search of 4000 obstacles, millions of nodes) — and a solve that is
//! not cancelled gives the same result, bit for bit, as one that cannot be.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

use beamfric::fem::Mesh;
use beamfric::model::Problem;
use beamfric::scene::{Scene, preset};
use beamfric::solve::{
    Cancellation, Method, Solution, SolveError, SolveErrorKind, SolveOptions, Timing, solve,
};

use crate::harness::wait::eventually;
use crate::harness::{cpu, scenes};

fn crowded_scene() -> Scene {
    Scene::from_toml(&scenes::crowded_scene_text(), "crowded").unwrap()
}

/// Solves on a thread of its own and replaces the request once that thread has used `work` of
/// CPU time (so the solve is provably under way, however busy the machine); the outcome.
fn solve_replaced_after(
    (problem, mesh): (&Problem, &Mesh),
    method: Method,
    options: SolveOptions,
    work: Duration,
) -> Result<Solution, SolveError> {
    try_replacing_after((problem, mesh), method, options, work).unwrap_or_else(|| {
        panic!("the {method} solve ended before it was cancelled: the scene is too light")
    })
}

/// As [`solve_replaced_after`]; `None` when the solve ended before the request was replaced
/// (on a loaded machine the check of its CPU time may come only after a short solve's end).
fn try_replacing_after(
    (problem, mesh): (&Problem, &Mesh),
    method: Method,
    options: SolveOptions,
    work: Duration,
) -> Option<Result<Solution, SolveError>> {
    let newest = Arc::new(AtomicU64::new(1));
    let options = SolveOptions {
        cancel: Cancellation::watching(Arc::clone(&newest), 1),
        ..options
    };
    std::thread::scope(|scope| {
        let (tell, told) = std::sync::mpsc::channel();
        let options = &options;
        let running = scope.spawn(move || {
            tell.send(cpu::this_thread()).unwrap();
            solve(problem, mesh, method, options)
        });
        let solver = told.recv().expect("the solving thread starts");
        eventually(
            &format!("the {method} solve has used {work:?} of CPU"),
            || running.is_finished() || cpu::thread_time(solver).is_some_and(|t| t >= work),
        );
        if running.is_finished() {
            let _ = running.join();
            return None;
        }
        newest.store(2, Ordering::Relaxed);
        Some(running.join().unwrap())
    })
}

#[test]
fn a_cancelled_solve_stops_inside_its_loops() {
    let (problem, settings) = crowded_scene().validate("crowded").unwrap();
    let mesh = Mesh::new(&problem, settings.elements);
    // Replace the request once the solve is provably under way: its thread has used 100 ms of
    // CPU, of the seconds the solve takes.
    let outcome = solve_replaced_after(
        (&problem, &mesh),
        Method::Dual,
        SolveOptions::default(),
        Duration::from_millis(100),
    );
    let error = outcome.expect_err("the solve was cancelled mid-way");
    assert_eq!(error.kind, SolveErrorKind::Cancelled);
    assert_eq!(error.kind.name(), "cancelled");
}

/// Every method on a scene where it works for a while, cancelled in its longest stage: the
/// outcome is the cancelled error, never a solution or another error.
#[test]
fn every_method_gives_up_when_cancelled_in_its_longest_stage() {
    let benchmark_1 = scenes::problem(&scenes::preset_scene("benchmark-1"));
    // (method, problem, elements, CPU time before the cancel)
    let heavy = [
        // faer's factorization and inverse of a 4000 × 4000 A: seconds, in steps.
        (Method::DualInverse, scenes::crowded_problem(64), 2001, 200),
        // Newton's Cholesky of a 1022 × 1022 case matrix, then the 10⁶-node sweeps.
        (
            Method::RegularizedNewton,
            scenes::crowded_problem(511),
            1000,
            100,
        ),
        // The box QP of 512 unknowns.
        (Method::Flexibility, scenes::crowded_problem(256), 1000, 200),
        // 9⁶ cases on 2·10⁶ elements.
        (
            Method::Regularized,
            scenes::crowded_problem(6),
            2_000_000,
            50,
        ),
        // The pattern search of 4000 obstacles and the nodes.
        (
            Method::Condensed,
            scenes::crowded_problem(4000),
            2_000_000,
            50,
        ),
        // Four million nodes of the closed form and the certificate's sweeps over them.
        (Method::ClosedForm, benchmark_1, 4_000_000, 30),
    ];
    for (method, problem, elements, work) in heavy {
        // A solve may end before a starved test thread sees its CPU time: then again on a
        // mesh twice as fine (the dense inverse, whose size is at its limit, as it is).
        let mut elements = elements;
        let mut outcome = None;
        for _ in 0..4 {
            let mesh = Mesh::new(&problem, elements);
            outcome = try_replacing_after(
                (&problem, &mesh),
                method,
                SolveOptions::default(),
                Duration::from_millis(work),
            );
            if outcome.is_some() {
                break;
            }
            if method != Method::DualInverse {
                elements = (elements * 2).min(beamfric::scene::MAX_ELEMENTS);
            }
        }
        let Some(outcome) = outcome else {
            panic!("the {method} solve always ended before it was cancelled: too light");
        };
        match outcome {
            Err(e) => assert_eq!(e.kind, SolveErrorKind::Cancelled, "{method}: {e}"),
            Ok(_) => panic!("{method}: a cancelled solve gave a solution"),
        }
    }
}

/// `solution` with its run time taken out: what must not depend on how the solve was run.
fn without_timing(solution: &Result<Solution, SolveError>) -> String {
    match solution {
        Ok(s) => format!(
            "{:?}",
            Solution {
                timing: Timing::default(),
                ..s.clone()
            }
        ),
        Err(e) => format!("{e:?}"),
    }
}

/// The checks change nothing: a solve watching a cancellation that never comes gives what a
/// solve that cannot be cancelled gives, bit for bit (Debug prints every f64 to its last bit),
/// for every preset and method, and on scenes that take the interruptible dense kernels' cut-up
/// paths (the stepwise faer inverse of `dual-inverse`, the LU route of an indefinite K, the
/// 1022 × 1022 Cholesky of Newton and of the QP).
#[test]
fn checks_for_cancellation_change_no_result() {
    let newest = Arc::new(AtomicU64::new(1));
    let watched = SolveOptions {
        cancel: Cancellation::watching(Arc::clone(&newest), 1),
        ..SolveOptions::default()
    };
    let mut cases: Vec<(String, Problem, usize)> = beamfric::scene::PRESETS
        .iter()
        .filter(|p| p.name != "fine-mesh")
        .map(|p| {
            let scene = Scene::from_toml(preset(p.name).unwrap().text, p.name).unwrap();
            let (problem, settings) = scene.validate(p.name).unwrap();
            (p.name.to_string(), problem, settings.elements)
        })
        .collect();
    cases.push((
        "crowded 16, N = 1198".into(),
        scenes::crowded_problem(16),
        600,
    ));
    cases.push((
        "crowded 511, K indefinite".into(),
        scenes::crowded_problem(511),
        100_000,
    ));
    for (name, problem, elements) in &cases {
        let mesh = Mesh::new(problem, elements.to_owned());
        for method in Method::ALL {
            if *elements == 100_000 && method != Method::Dual {
                continue;
            }
            let never = solve(problem, &mesh, method, &SolveOptions::default());
            let watching = solve(problem, &mesh, method, &watched);
            assert_eq!(
                without_timing(&watching),
                without_timing(&never),
                "{name}, {method}: a cancellation that never came changed the result"
            );
        }
    }
    let crowded = scenes::crowded_problem(511);
    let mesh = Mesh::new(&crowded, 1000);
    let never = solve(
        &crowded,
        &mesh,
        Method::RegularizedNewton,
        &SolveOptions::default(),
    );
    let watching = solve(&crowded, &mesh, Method::RegularizedNewton, &watched);
    assert_eq!(without_timing(&watching), without_timing(&never));
    assert_eq!(newest.load(Ordering::Relaxed), 1);
}
