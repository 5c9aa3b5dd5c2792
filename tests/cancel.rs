//! Issue 11: a solve whose result is no longer wanted stops inside its long loops (here the
//! box QP of 256 obstacles, seconds of work) as soon as its `Cancellation` says so.

use std::sync::atomic::{AtomicU64, Ordering};

use beamfric::fem::Mesh;
use beamfric::scene::Scene;
use beamfric::solve::{Cancellation, Method, SolveErrorKind, SolveOptions, solve};

fn crowded_scene() -> Scene {
    let mut text = String::from(
        "title = \"256 obstacles\"\n[beam]\nlength = 1.0\nyoung = 2.15e11\n\
         section = { shape = \"rectangle\", width = 0.02, height = 0.02 }\n\
         [load]\nf0 = 5e4\nf1 = -3e4\n",
    );
    let mut state = 7u64;
    let mut uniform = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for i in 0..256 {
        let x = (i + 1) as f64 / 257.0;
        let sliding = 10f64.powf(4.0 * uniform());
        let swivel = 10f64.powf(4.0 * uniform());
        text.push_str(&format!(
            "[[obstacle]]\nx = {x:?}\nsliding = {sliding:?}\nswivel = {swivel:?}\n"
        ));
    }
    text.push_str("[mesh]\nelements = 1000\n");
    Scene::from_toml(&text, "crowded").unwrap()
}

#[test]
fn a_cancelled_solve_stops_inside_its_loops() {
    let (problem, settings) = crowded_scene().validate("crowded").unwrap();
    let mesh = Mesh::new(&problem, settings.elements);
    let newest: &'static AtomicU64 = Box::leak(Box::new(AtomicU64::new(1)));
    let options = SolveOptions {
        cancel: Cancellation::watching(newest, 1),
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
