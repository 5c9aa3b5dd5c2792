//! Run time of the methods (issue 2's targets), measured with criterion in a release build:
//!
//! - `methods`: `dual` and `flexibility` at n = 10², 10⁴, 10⁶ with 1 obstacle (Benchmark 1) and
//!   4 obstacles (Benchmark 3), through `solve` with its certificate (KKT residual, friction
//!   states, the conditioning bound) but without the reference comparison;
//! - `keystroke-n20`: Benchmark 1 at n = 20, every method but `dual-inverse`, with and without
//!   the reference error — what the explorer does on a keystroke;
//! - `regularized-vs-k`: the 9^k enumeration against semismooth Newton on the same ε-problem;
//! - `factorization`: the hand-written block-tridiagonal factorization with the friction nodes
//!   last against faer's general sparse Cholesky doing the same job (factor A, then S and z0 of
//!   (49) from 2k + 1 solves). This is why the banded solver is written by hand.
//! - `dual-inverse`: the paper's explicit inverse, for the O(N³) curve.
//! - `many-obstacles`: k = 16 … 128 obstacles at n = 1000, where the box QP has 2k > 32
//!   unknowns and runs projected Newton before the active-set method certifies its answer.
//! - `condensed-many-obstacles`: the `condensed` method (issue 10) on k = 16 … 4000 obstacles
//!   at n = 10⁴ with thresholds around the fixed-end forces (every friction state occurs), and
//!   on Benchmark 1 at n = 10⁶ (the accuracy target's mesh).

use std::hint::black_box;
use std::time::Duration;

use beamfric::fem::{Mesh, StiffnessMatrix, load_vector};
use beamfric::linalg::BlockMatrix;
use beamfric::linalg::blocktri::FrictionLastFactor;
use beamfric::model::Problem;
use beamfric::scene::{ObstacleSpec, Scene, preset};
use beamfric::solve::{ConditionLevel, Method, SolveOptions, solve};
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};

fn scene(name: &str) -> Scene {
    Scene::from_toml(preset(name).unwrap().text, name).unwrap()
}

fn problem(name: &str) -> Problem {
    scene(name).validate(name).unwrap().0
}

fn options(reference: bool) -> SolveOptions {
    SolveOptions {
        condition: ConditionLevel::Off,
        reference,
        ..SolveOptions::default()
    }
}

fn methods(c: &mut Criterion) {
    let mut group = c.benchmark_group("methods");
    for (name, k) in [("benchmark-1", 1), ("benchmark-3", 4)] {
        let problem = problem(name);
        for n in [100usize, 10_000, 1_000_000] {
            let mesh = Mesh::new(&problem, n);
            if n == 1_000_000 {
                group.sample_size(10);
                group.measurement_time(Duration::from_secs(8));
            } else {
                group.sample_size(50);
                group.measurement_time(Duration::from_secs(3));
            }
            for method in [Method::Dual, Method::Flexibility] {
                group.bench_with_input(
                    BenchmarkId::new(format!("{method}/k={k}"), n),
                    &mesh,
                    |b, mesh| b.iter(|| solve(&problem, mesh, method, &options(false)).unwrap()),
                );
            }
        }
    }
    group.finish();
}

fn keystroke(c: &mut Criterion) {
    let mut group = c.benchmark_group("keystroke-n20");
    let problem = problem("benchmark-1");
    let mesh = Mesh::new(&problem, 20);
    for method in Method::ALL {
        if method == Method::DualInverse {
            continue;
        }
        group.bench_function(format!("{method}"), |b| {
            b.iter(|| solve(&problem, &mesh, method, &options(false)).unwrap())
        });
        group.bench_function(format!("{method}+reference"), |b| {
            b.iter(|| solve(&problem, &mesh, method, &options(true)).unwrap())
        });
    }
    group.finish();
}

fn regularized_vs_k(c: &mut Criterion) {
    let mut group = c.benchmark_group("regularized-vs-k");
    group.sample_size(10);
    for k in 1..=5 {
        let mut scene = scene("benchmark-2");
        scene.obstacles = (1..=k)
            .map(|j| ObstacleSpec {
                x: j as f64 / (k + 1) as f64,
                sliding: 1e4,
                swivel: 5e4,
            })
            .collect();
        let problem = scene.validate("k").unwrap().0;
        let mesh = Mesh::new(&problem, 60);
        for method in [Method::Regularized, Method::RegularizedNewton] {
            group.bench_with_input(BenchmarkId::new(method.name(), k), &mesh, |b, mesh| {
                b.iter(|| solve(&problem, mesh, method, &options(false)).unwrap())
            });
        }
    }
    group.finish();
}

/// faer's sparse Cholesky (AMD ordering, symbolic + numeric) and 2k + 1 solves for z0 and the
/// columns of S.
fn faer_dual_matrices(problem: &Problem, mesh: &Mesh) -> f64 {
    use faer::prelude::*;
    use faer::sparse::{SparseColMat, Triplet};
    let matrix = StiffnessMatrix::new(mesh);
    let m = matrix.blocks();
    let n = 2 * m;
    let mut triplets = Vec::with_capacity(7 * m);
    for i in 0..m {
        let d = matrix.diag(i);
        triplets.push(Triplet::new(2 * i, 2 * i, d[0]));
        triplets.push(Triplet::new(2 * i + 1, 2 * i, d[1]));
        triplets.push(Triplet::new(2 * i + 1, 2 * i + 1, d[2]));
        if i + 1 < m {
            let u = matrix.upper(i);
            for r in 0..2 {
                for col in 0..2 {
                    triplets.push(Triplet::new(2 * i + 2 + col, 2 * i + r, u[2 * r + col]));
                }
            }
        }
    }
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &triplets).unwrap();
    let llt = a.sp_cholesky(faer::Side::Lower).unwrap();
    let (u, t) = load_vector(problem, mesh);
    let dofs: Vec<usize> = mesh
        .obstacle_nodes
        .iter()
        .flat_map(|&node| [2 * (node - 1), 2 * (node - 1) + 1])
        .collect();
    let mut rhs = Mat::<f64>::zeros(n, dofs.len() + 1);
    for i in 0..m {
        rhs[(2 * i, 0)] = u[i + 1];
        rhs[(2 * i + 1, 0)] = t[i + 1];
    }
    for (j, &d) in dofs.iter().enumerate() {
        rhs[(d, j + 1)] = 1.0;
    }
    llt.solve_in_place(&mut rhs);
    // S and z0 are the rows of the solution at the friction DOFs.
    dofs.iter().map(|&d| rhs[(d, 0)] + rhs[(d, 1)]).sum()
}

fn own_dual_matrices(problem: &Problem, mesh: &Mesh) -> f64 {
    let boundary: Vec<usize> = mesh.obstacle_nodes.iter().map(|&n| n - 1).collect();
    let factor = FrictionLastFactor::new(StiffnessMatrix::new(mesh), &boundary).unwrap();
    let (mut u, mut t) = load_vector(problem, mesh);
    let n = mesh.elements();
    let condensed = factor.forward(&mut u[1..n], &mut t[1..n]);
    condensed.iter().sum::<f64>() + factor.schur.iter().sum::<f64>()
}

fn factorization(c: &mut Criterion) {
    let mut group = c.benchmark_group("factorization");
    let problem = problem("benchmark-3");
    for n in [10_000usize, 100_000] {
        let mesh = Mesh::new(&problem, n);
        group.sample_size(10);
        group.bench_with_input(
            BenchmarkId::new("faer-sparse-cholesky", n),
            &mesh,
            |b, mesh| b.iter(|| black_box(faer_dual_matrices(&problem, mesh))),
        );
        group.bench_with_input(
            BenchmarkId::new("friction-last-banded", n),
            &mesh,
            |b, mesh| b.iter(|| black_box(own_dual_matrices(&problem, mesh))),
        );
    }
    group.finish();
}

fn dual_inverse(c: &mut Criterion) {
    let mut group = c.benchmark_group("dual-inverse");
    group.sample_size(10);
    let problem = problem("benchmark-1");
    for n in [20usize, 100, 500] {
        let mesh = Mesh::new(&problem, n);
        group.bench_with_input(BenchmarkId::from_parameter(n), &mesh, |b, mesh| {
            b.iter(|| solve(&problem, mesh, Method::DualInverse, &options(false)).unwrap())
        });
    }
    group.finish();
}

/// Benchmark 3's beam with `k` evenly spaced obstacles whose thresholds cycle from zero to
/// clamping, so that some slide, some swivel and some stick.
fn crowded(k: usize) -> Problem {
    let mut scene = scene("benchmark-3");
    let sliding = [0.0, 1e2, 1e4, 1e7];
    let swivel = [1e6, 0.0, 1e2, 1e4];
    scene.obstacles = (1..=k)
        .map(|j| ObstacleSpec {
            x: j as f64 / (k + 1) as f64 * scene.beam.length,
            sliding: sliding[j % 4],
            swivel: swivel[(j / 4) % 4],
        })
        .collect();
    scene.validate("crowded").unwrap().0
}

fn many_obstacles(c: &mut Criterion) {
    let mut group = c.benchmark_group("many-obstacles");
    group.sample_size(10);
    for k in [16usize, 32, 64, 128] {
        let problem = crowded(k);
        let mesh = Mesh::new(&problem, 1000);
        for method in [Method::Dual, Method::Flexibility, Method::RegularizedNewton] {
            group.bench_with_input(BenchmarkId::new(method.name(), k), &mesh, |b, mesh| {
                b.iter(|| solve(&problem, mesh, method, &options(false)).unwrap())
            });
        }
    }
    group.finish();
}

/// `k` obstacles at jittered positions with thresholds spread around the fixed-end forces of
/// their spans, so that about a third stick, and the rest slide, swivel or both.
fn crowded_condensed(k: usize) -> Problem {
    let mut scene = scene("benchmark-3");
    let load = 1e5;
    let h = scene.beam.length / (k + 1) as f64;
    // A fixed sequence (SplitMix64): the same scene on every run.
    let mut state = 4000u64;
    let mut next = || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    scene.load.f0 = load;
    scene.load.f1 = Some(0.5 * load);
    scene.obstacles = (1..=k)
        .map(|j| ObstacleSpec {
            x: (j as f64 + 0.8 * (next() - 0.5)) * h,
            sliding: 3.0 * load * h * next(),
            swivel: 0.2 * load * h * h * next(),
        })
        .collect();
    scene.validate("crowded-condensed").unwrap().0
}

fn condensed_many_obstacles(c: &mut Criterion) {
    let mut group = c.benchmark_group("condensed-many-obstacles");
    group.sample_size(20);
    for k in [16usize, 128, 1000, 4000] {
        let problem = crowded_condensed(k);
        let mesh = Mesh::new(&problem, 10_000);
        group.bench_with_input(BenchmarkId::new("condensed/n=1e4", k), &mesh, |b, mesh| {
            b.iter(|| solve(&problem, mesh, Method::Condensed, &options(false)).unwrap())
        });
    }
    let problem = problem("benchmark-1");
    let mesh = Mesh::new(&problem, 1_000_000);
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(8));
    for method in [Method::Condensed, Method::Flexibility] {
        group.bench_with_input(
            BenchmarkId::new(format!("{method}/benchmark-1"), 1_000_000),
            &mesh,
            |b, mesh| b.iter(|| solve(&problem, mesh, method, &options(false)).unwrap()),
        );
    }
    group.finish();
}

criterion_group!(
    benches,
    methods,
    keystroke,
    regularized_vs_k,
    factorization,
    dual_inverse,
    many_obstacles,
    condensed_many_obstacles
);
criterion_main!(benches);
