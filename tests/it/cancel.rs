//! Issue 11: a solve whose result is no longer wanted stops inside its long loops (here the
//! box QP of 256 obstacles, seconds of work) as soon as its `Cancellation` says so.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

use beamfric::fem::Mesh;
use beamfric::scene::Scene;
use beamfric::solve::{Cancellation, Method, SolveErrorKind, SolveOptions, solve};

use crate::harness::wait::eventually;
use crate::harness::{cpu, scenes};

fn crowded_scene() -> Scene {
    Scene::from_toml(&scenes::crowded_scene_text(), "crowded").unwrap()
}

#[test]
fn a_cancelled_solve_stops_inside_its_loops() {
    let (problem, settings) = crowded_scene().validate("crowded").unwrap();
    let mesh = Mesh::new(&problem, settings.elements);
    let newest = Arc::new(AtomicU64::new(1));
    let options = SolveOptions {
        cancel: Cancellation::watching(Arc::clone(&newest), 1),
        ..SolveOptions::default()
    };
    let outcome = std::thread::scope(|scope| {
        let (tell, told) = std::sync::mpsc::channel();
        let (problem, mesh, options) = (&problem, &mesh, &options);
        let running = scope.spawn(move || {
            tell.send(cpu::this_thread()).unwrap();
            solve(problem, mesh, Method::Dual, options)
        });
        let solver = told.recv().expect("the solving thread starts");
        // Replace the request once the solve is provably under way: its thread has used 100 ms
        // of CPU, of the seconds the solve takes.
        eventually("the solve has used 100 ms of CPU", || {
            running.is_finished()
                || cpu::thread_time(solver).is_some_and(|t| t >= Duration::from_millis(100))
        });
        assert!(
            !running.is_finished(),
            "the solve ended before it was cancelled"
        );
        newest.store(2, Ordering::Relaxed);
        running.join().unwrap()
    });
    let error = outcome.expect_err("the solve was cancelled mid-way");
    assert_eq!(error.kind, SolveErrorKind::Cancelled);
    assert_eq!(error.kind.name(), "cancelled");
}
