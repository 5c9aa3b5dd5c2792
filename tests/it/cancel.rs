//! Issue 11: a solve whose result is no longer wanted stops inside its long loops (here the
//! box QP of 256 obstacles, seconds of work) as soon as its `Cancellation` says so.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use beamfric::fem::Mesh;
use beamfric::scene::Scene;
use beamfric::solve::{Cancellation, Method, SolveErrorKind, SolveOptions, solve};

use crate::harness::scenes;

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
        let running = scope.spawn(|| solve(&problem, &mesh, Method::Dual, &options));
        // Let the QP get going, then replace the request.
        std::thread::sleep(std::time::Duration::from_millis(200));
        newest.store(2, Ordering::Relaxed);
        running.join().unwrap()
    });
    let error = outcome.expect_err("the solve was cancelled mid-way");
    assert_eq!(error.kind, SolveErrorKind::Cancelled);
    assert_eq!(error.kind.name(), "cancelled");
}
