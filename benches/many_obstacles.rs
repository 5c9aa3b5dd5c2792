//! `condensed` on many obstacles in every arrangement of issue 26 (`check::families`), at
//! n = 10⁴ elements:
//!
//! ```text
//! cargo bench --bench many_obstacles                 # criterion: median solve per family and k
//! cargo bench --bench many_obstacles -- report       # the table: time, solves, growth in k
//! ```
//!
//! `report` prints, per family and k, the fastest of three solves and what the search did
//! (pattern solves, factorisations, back solves, refinements in double-double, interior-point
//! steps), then the growth exponent of the time in k between consecutive sizes. Settings:
//! `BEAMFRIC_FAMILY_K` (comma-separated sizes, default 128,1000,4000), `BEAMFRIC_FAMILY`
//! (one family's name), `BEAMFRIC_FAMILY_SEED` (default 1).

use std::time::{Duration, Instant};

use beamfric::check::families::{Family, family_problem};
use beamfric::solve::solve_condensed;
use criterion::{BenchmarkId, Criterion};

const ELEMENTS: usize = 10_000;
const SIZES: [usize; 3] = [128, 1000, 4000];

fn sizes() -> Vec<usize> {
    std::env::var("BEAMFRIC_FAMILY_K")
        .ok()
        .map(|text| {
            text.split(',')
                .map(|k| {
                    k.trim()
                        .parse()
                        .expect("BEAMFRIC_FAMILY_K: sizes like 128,1000")
                })
                .collect()
        })
        .unwrap_or_else(|| SIZES.to_vec())
}

fn families() -> Vec<Family> {
    match std::env::var("BEAMFRIC_FAMILY") {
        Ok(name) => Family::ALL
            .into_iter()
            .filter(|f| f.name() == name)
            .collect(),
        Err(_) => Family::ALL.to_vec(),
    }
}

fn seed() -> u64 {
    std::env::var("BEAMFRIC_FAMILY_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1)
}

fn criterion_runs() {
    let mut c = Criterion::default().configure_from_args();
    let mut group = c.benchmark_group("families");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(4));
    for family in families() {
        for k in sizes() {
            let (problem, mesh) = family_problem(family, k, seed(), ELEMENTS);
            group.bench_with_input(BenchmarkId::new(family.name(), k), &mesh, |b, mesh| {
                b.iter(|| solve_condensed(&problem, mesh).unwrap())
            });
        }
    }
    group.finish();
    c.final_summary();
}

fn report() {
    println!(
        "| family | k | time | pattern solves | factorisations | back solves | refinements | \
         interior steps | converged |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for family in families() {
        let mut previous: Option<(usize, f64)> = None;
        let mut exponents = Vec::new();
        for k in sizes() {
            let (problem, mesh) = family_problem(family, k, seed(), ELEMENTS);
            let mut fastest = f64::INFINITY;
            let mut last = None;
            for _ in 0..3 {
                let start = Instant::now();
                let solution = solve_condensed(&problem, &mesh).unwrap();
                fastest = fastest.min(start.elapsed().as_secs_f64());
                last = Some(solution);
            }
            let solution = last.unwrap();
            let counts = solution.counts;
            println!(
                "| {} | {k} | {:.2} ms | {} | {} | {} | {} | {} | {} |",
                family.name(),
                1e3 * fastest,
                counts.pattern_solves,
                counts.factorizations,
                counts.back_solves,
                counts.refinements,
                counts.interior_steps,
                solution.converged,
            );
            if let Some((k0, t0)) = previous {
                exponents.push(format!(
                    "{k0}→{k}: {:.2}",
                    (fastest / t0).ln() / (k as f64 / k0 as f64).ln()
                ));
            }
            previous = Some((k, fastest));
        }
        println!(
            "growth exponent of {}: {}",
            family.name(),
            exponents.join(", ")
        );
    }
}

fn main() {
    let tool = std::env::args().skip(1).find(|arg| !arg.starts_with('-'));
    match tool.as_deref() {
        Some("report") => report(),
        _ => criterion_runs(),
    }
}
