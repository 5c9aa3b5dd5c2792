//! `condensed` on many obstacles in every arrangement of issue 26 (`check::families`), at
//! n = 10⁴ elements:
//!
//! ```text
//! cargo bench --bench many_obstacles                 # criterion: median solve per family and k
//! cargo bench --bench many_obstacles -- report       # the table: time, solves, growth in k
//! cargo bench --bench many_obstacles -- warm         # a one-notch change, from the last pattern
//! cargo bench --bench many_obstacles -- explorer     # the explorer's whole re-solve, cold and warm
//! cargo bench --bench many_obstacles -- lowered      # ties with one threshold lowered
//! cargo bench --bench many_obstacles -- clustered-ties  # clusters at ties, one swivel lowered
//! cargo bench --bench many_obstacles -- dense        # half the obstacles in 1e-4·l (worst found)
//! cargo bench --bench many_obstacles -- pairs        # obstacles in pairs 1e-9·l to 1e-5·l apart
//! cargo bench --bench many_obstacles -- partial-ties # some thresholds at the stuck forces
//! cargo bench --bench many_obstacles -- tight-clusters # clusters 1e-7·l wide at ties
//! cargo bench --bench many_obstacles -- scenes DIR   # the scenes as TOML (for other solvers)
//! ```
//!
//! `report` prints, per family and k, the fastest of three solves and what the search did
//! (pattern solves, factorisations, back solves, refinements in double-double, interior-point
//! steps), then the growth exponent of the time in k between consecutive sizes. Settings:
//! `BEAMFRIC_FAMILY_K` (comma-separated sizes, default 128,1000,4000), `BEAMFRIC_FAMILY`
//! (one family's name), `BEAMFRIC_FAMILY_SEED` (default 1).
//!
//! Both the criterion run and `report` go on after issue 26's four families with the slowest
//! generated arrangements measured (stop 62, seed 1, the fastest of three solves in one
//! process, k = 128 / 1000 / 4000; criterion's medians, from other runs, are in
//! docs/numerics.md): every other obstacle's thresholds at its stuck forces
//! (`half-ties`, 0.75 / 18 / 54 ms), every sliding threshold at its stuck force
//! (`sliding-ties`, 1.1 / 9.2 / 64 ms) and clusters at ties with one swivel threshold three
//! notches down (`clustered-ties-lowered`, 1.1 / 15 / 38 ms; 1.1 / 21 / 98 ms before that
//! stop's end of the interior-point iteration). Slower arrangements exist (clusters of 100
//! obstacles 1e-9·l apart at ties, graded ties: 1–5 s a solve, stop 61's hostile pass), too
//! slow for a median of ten.

use std::time::{Duration, Instant};

use beamfric::check::families::{
    Family, NOTCH, dense_stretch_scene, family_problem, family_scene, half_ties_scene,
    lowered_clustered_ties_scene, lowered_ties_scene_at, pairs_scene, sliding_ties_scene,
    tight_clusters_ties_scene,
};
use beamfric::fem::Mesh;
use beamfric::model::Problem;
use beamfric::scene::Scene;
use beamfric::solve::{CondensedSolution, solve_condensed, solve_condensed_from};
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

/// A generated arrangement's scene at k from a seed.
type SceneOf = fn(usize, u64) -> Scene;

/// The slowest generated arrangements measured, after issue 26's four families (see the
/// module's documentation): name and scene at k from a seed.
const HARDER: [(&str, SceneOf); 3] = [
    ("half-ties", |k, seed| half_ties_scene(k, seed, ELEMENTS)),
    ("sliding-ties", |k, seed| {
        sliding_ties_scene(k, seed, ELEMENTS)
    }),
    ("clustered-ties-lowered", |k, seed| {
        lowered_clustered_ties_scene(k, seed, 3, ELEMENTS)
    }),
];

/// The arrangements of [`HARDER`] asked for (`BEAMFRIC_FAMILY` unset, or one's name), each
/// with its scene and mesh at k from the seed asked for.
fn harder() -> Vec<(&'static str, impl Fn(usize) -> (Problem, Mesh))> {
    let asked = std::env::var("BEAMFRIC_FAMILY").ok();
    HARDER
        .into_iter()
        .filter(|(name, _)| asked.as_deref().is_none_or(|asked| asked == *name))
        .map(|(name, scene_of)| (name, move |k| with_mesh(&scene_of(k, seed()))))
        .collect()
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
    for (name, problem_of) in harder() {
        for k in sizes() {
            let (problem, mesh) = problem_of(k);
            group.bench_with_input(BenchmarkId::new(name, k), &mesh, |b, mesh| {
                b.iter(|| solve_condensed(&problem, mesh).unwrap())
            });
        }
    }
    group.finish();
    // The explorer's re-solve after one notch of the middle obstacle's sliding threshold,
    // from the pattern before the change.
    let mut warm = c.benchmark_group("warm");
    warm.sample_size(10);
    warm.measurement_time(Duration::from_secs(4));
    for family in families() {
        for k in sizes() {
            let ((problem, mesh), (changed, changed_mesh)) = notched(family, k, 1);
            let before = solve_condensed(&problem, &mesh).unwrap();
            warm.bench_function(BenchmarkId::new(family.name(), k), |b| {
                b.iter(|| {
                    solve_condensed_from(&changed, &changed_mesh, &before.pattern, &mut || true)
                        .unwrap()
                })
            });
        }
    }
    warm.finish();
    c.final_summary();
}

fn report() {
    println!(
        "| family | k | time | pattern solves | factorisations | back solves | refinements | \
         of them with double-double factors | interior steps | converged |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for family in families() {
        family_rows(family.name(), &|k| {
            family_problem(family, k, seed(), ELEMENTS)
        });
    }
    for (name, problem_of) in harder() {
        family_rows(name, &problem_of);
    }
}

/// `report`'s rows for one family (`problem_of(k)` at every size), then its growth exponents.
fn family_rows(name: &str, problem_of: &dyn Fn(usize) -> (Problem, Mesh)) {
    let mut previous: Option<(usize, f64)> = None;
    let mut exponents = Vec::new();
    for k in sizes() {
        let (problem, mesh) = problem_of(k);
        let (fastest, solution) =
            fastest_of_three(&mut || solve_condensed(&problem, &mesh).unwrap());
        let counts = solution.counts;
        println!(
            "| {name} | {k} | {:.2} ms | {} | {} | {} | {} | {} | {} | {} |",
            1e3 * fastest,
            counts.pattern_solves,
            counts.factorizations,
            counts.back_solves,
            counts.refinements,
            counts.double_double_factorizations,
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
    println!("growth exponent of {name}: {}", exponents.join(", "));
}

/// The family's scene at k, and the same scene with the middle obstacle's sliding threshold
/// stepped one notch `direction` (+1 up, −1 down), both with their meshes.
fn notched(family: Family, k: usize, direction: i32) -> ((Problem, Mesh), (Problem, Mesh)) {
    let scene = family_scene(family, k, seed(), ELEMENTS);
    let mut changed = scene.clone();
    changed.obstacles[k / 2].sliding *= NOTCH.powi(direction);
    (with_mesh(&scene), with_mesh(&changed))
}

/// A generated `scene`'s problem and its mesh of [`ELEMENTS`] elements.
fn with_mesh(scene: &Scene) -> (Problem, Mesh) {
    let problem = scene.problem().expect("a generated scene is valid");
    let mesh = Mesh::new(&problem, ELEMENTS);
    (problem, mesh)
}

/// The fastest of three runs of `solve`, and its last solution.
fn fastest_of_three(solve: &mut dyn FnMut() -> CondensedSolution) -> (f64, CondensedSolution) {
    let mut fastest = f64::INFINITY;
    let mut last = None;
    for _ in 0..3 {
        let start = Instant::now();
        let solution = solve();
        fastest = fastest.min(start.elapsed().as_secs_f64());
        last = Some(solution);
    }
    (fastest, last.expect("three runs"))
}

/// The warm-start table: per family and k, one threshold stepped one notch up and one down,
/// solved from scratch and from the pattern before the change; the two answers must agree.
fn warm_report() {
    println!(
        "| family | k | notch | cold time | cold pattern solves + interior steps | warm time | \
         warm pattern solves | warm refinements | same states | max |Δu| / max |u| |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for family in families() {
        for k in sizes() {
            for direction in [1, -1] {
                let ((problem, mesh), (changed, changed_mesh)) = notched(family, k, direction);
                let before = solve_condensed(&problem, &mesh).expect("the scene solves");
                let (cold_time, cold) =
                    fastest_of_three(&mut || solve_condensed(&changed, &changed_mesh).unwrap());
                let (warm_time, warm) = fastest_of_three(&mut || {
                    solve_condensed_from(&changed, &changed_mesh, &before.pattern, &mut || true)
                        .unwrap()
                });
                let largest = cold
                    .field
                    .deflection
                    .iter()
                    .fold(0f64, |m, u| m.max(u.abs()));
                let difference = cold
                    .field
                    .deflection
                    .iter()
                    .zip(&warm.field.deflection)
                    .fold(0f64, |m, (a, b)| m.max((a - b).abs()));
                println!(
                    "| {} | {k} | {} | {:.2} ms | {} + {} | {:.2} ms | {} | {} | {} | {:.1e} |",
                    family.name(),
                    if direction > 0 { "up" } else { "down" },
                    1e3 * cold_time,
                    cold.counts.pattern_solves,
                    cold.counts.interior_steps,
                    1e3 * warm_time,
                    warm.counts.pattern_solves,
                    warm.counts.refinements,
                    cold.states == warm.states && warm.converged,
                    difference / largest,
                );
            }
        }
    }
}

/// Writes every family's scene at every k to `DIR/<family>-<k>.toml`, for `beamfric export`
/// and another solver (docs/many-obstacles/guess-and-warm-starts.md compares Clarabel on them).
/// The explorer's whole re-solve (`condensed` with its certificate, as the worker runs it)
/// after one notch up of the middle obstacle's sliding threshold: from scratch, and from the
/// pattern of the solve shown before (what the explorer does).
fn explorer_report() {
    use beamfric::scene::{Scene, Settings};
    use beamfric::solve::Method;
    use beamfric::tui::jobs::solve::{SolveRequest, solve};
    println!("| family | k | cold re-solve | warm re-solve | same answer |");
    println!("|---|---|---|---|---|");
    let request = |scene: &Scene| {
        let problem = scene.problem().expect("a generated scene is valid");
        let settings = Settings {
            elements: ELEMENTS,
            method: Method::Condensed,
            epsilon: scene.solver.epsilon,
        };
        SolveRequest::for_scene(scene, &problem, settings)
    };
    for family in families() {
        for k in sizes() {
            let scene = family_scene(family, k, seed(), ELEMENTS);
            let shown = solve(&request(&scene));
            let mut changed = scene.clone();
            changed.obstacles[k / 2].sliding *= NOTCH;
            let fastest = |request: &SolveRequest| {
                let mut best = f64::INFINITY;
                let mut last = None;
                for _ in 0..3 {
                    let start = Instant::now();
                    last = Some(solve(request));
                    best = best.min(start.elapsed().as_secs_f64());
                }
                (best, last.expect("three runs"))
            };
            let (cold_time, cold) = fastest(&request(&changed));
            let (warm_time, warm) = fastest(&request(&changed).starting_from(Some(&shown)));
            let (c, w) = (cold.solution.unwrap(), warm.solution.unwrap());
            println!(
                "| {} | {k} | {:.2} ms | {:.2} ms | {} |",
                family.name(),
                1e3 * cold_time,
                1e3 * warm_time,
                c.field == w.field && c.obstacles == w.obstacles,
            );
        }
    }
}

/// The arrangement found slow in stop 34 ([`lowered_ties_scene_at`]), solved cold. Sizes
/// from `BEAMFRIC_FAMILY_K` (default 100,300,1000), the number of notches from
/// `BEAMFRIC_NOTCHES` (default 1), the threshold from `BEAMFRIC_LOWERED` (default
/// `sliding:first`; `sliding` or `swivel`, then `first`, `last`, `third` (obstacle k/3) or an
/// obstacle's index).
fn lowered_report() {
    println!("| k | time | pattern solves | interior steps | converged |");
    println!("|---|---|---|---|---|");
    let sizes = std::env::var("BEAMFRIC_FAMILY_K")
        .map(|_| sizes())
        .unwrap_or_else(|_| vec![100, 300, 1000]);
    let notches = notches(1);
    let lowered = std::env::var("BEAMFRIC_LOWERED").unwrap_or_else(|_| "sliding:first".into());
    let usage = "BEAMFRIC_LOWERED: sliding or swivel, a colon, then first, last, third or an \
                 obstacle's index, like swivel:third";
    let (kind, which) = lowered.trim().split_once(':').expect(usage);
    let swivel = match kind {
        "sliding" => false,
        "swivel" => true,
        _ => panic!("{usage}"),
    };
    for k in sizes {
        let obstacle = match which {
            "first" => 0,
            "last" => k - 1,
            "third" => k / 3,
            index => index.parse().ok().filter(|&i| i < k).expect(usage),
        };
        let scene = lowered_ties_scene_at(k, (obstacle, swivel), notches, ELEMENTS);
        println!("| {k} | {} |", cold_solve_row(&scene));
    }
}

/// One cold solve of `scene` on [`ELEMENTS`] elements, as table cells: time, pattern solves,
/// interior steps, converged.
fn cold_solve_row(scene: &Scene) -> String {
    let (problem, mesh) = with_mesh(scene);
    let start = Instant::now();
    let solution = solve_condensed(&problem, &mesh).expect("the scene solves");
    format!(
        "{:.1} ms | {} | {} | {}",
        1e3 * start.elapsed().as_secs_f64(),
        solution.counts.pattern_solves,
        solution.counts.interior_steps,
        solution.converged
    )
}

/// `BEAMFRIC_NOTCHES`, or `default`.
fn notches(default: i32) -> i32 {
    std::env::var("BEAMFRIC_NOTCHES").map_or(default, |v| {
        v.trim()
            .parse()
            .expect("BEAMFRIC_NOTCHES: a whole number of notches like 1 or 5")
    })
}

/// Clusters at ties with one swivel threshold lowered ([`lowered_clustered_ties_scene`], the
/// slowest arrangement measured in stop 45), solved cold once each. Sizes from
/// `BEAMFRIC_FAMILY_K` (default 1000,2000,3000,4000), seeds 1 to `BEAMFRIC_SEEDS` (default 4),
/// notches from `BEAMFRIC_NOTCHES` (default 3).
fn clustered_ties_report() {
    let notches = notches(3);
    seeded_report(&[1000, 2000, 3000, 4000], 4, |k, seed| {
        lowered_clustered_ties_scene(k, seed, notches, ELEMENTS)
    });
}

/// Half the obstacles in a stretch 1e-4·l wide ([`dense_stretch_scene`], found in stop 48's
/// hostile pass; the slowest arrangement measured since stop 49), solved cold once each.
/// Sizes from `BEAMFRIC_FAMILY_K` (default 1000,2000,3000), seeds 1 to `BEAMFRIC_SEEDS`
/// (default 6).
fn dense_report() {
    seeded_report(&[1000, 2000, 3000], 6, |k, seed| {
        dense_stretch_scene(k, seed, ELEMENTS)
    });
}

/// Obstacles in pairs 1e-9·l to 1e-5·l apart ([`pairs_scene`], found in stop 48's hostile
/// pass), solved cold once each. Sizes from `BEAMFRIC_FAMILY_K` (default 1000,2000,3000),
/// seeds 1 to `BEAMFRIC_SEEDS` (default 6).
fn pairs_report() {
    seeded_report(&[1000, 2000, 3000], 6, |k, seed| {
        pairs_scene(k, seed, ELEMENTS)
    });
}

/// Some thresholds at the stuck forces, the others 0–2 × them: every other obstacle's
/// ([`half_ties_scene`]) and every sliding threshold ([`sliding_ties_scene`]), found in stop
/// 53's hostile pass; solved cold once each. Sizes from `BEAMFRIC_FAMILY_K` (default
/// 1000,3000), seeds 1 to `BEAMFRIC_SEEDS` (default 6).
fn partial_ties_report() {
    println!("Every other obstacle's thresholds at its stuck forces:\n");
    seeded_report(&[1000, 3000], 6, |k, seed| {
        half_ties_scene(k, seed, ELEMENTS)
    });
    println!("\nEvery sliding threshold at its stuck force:\n");
    seeded_report(&[1000, 3000], 6, |k, seed| {
        sliding_ties_scene(k, seed, ELEMENTS)
    });
}

/// Tight clusters at ties ([`tight_clusters_ties_scene`]: ten obstacles 1e-7·l apart per
/// cluster, every threshold at its stuck force), found in stop 54's hostile pass; solved cold
/// once each. Most seeds settle in a few pattern solves; a few in a hundred take hundreds
/// (scan with `BEAMFRIC_SEEDS=300`). Sizes from `BEAMFRIC_FAMILY_K` (default 1000,2000),
/// seeds 1 to `BEAMFRIC_SEEDS` (default 6).
fn tight_clusters_report() {
    seeded_report(&[1000, 2000], 6, |k, seed| {
        tight_clusters_ties_scene(k, seed, ELEMENTS)
    });
}

/// One cold solve of `scene_of(k, seed)` per size (`BEAMFRIC_FAMILY_K`, else `sizes`) and
/// seed (1 to `BEAMFRIC_SEEDS`, else `seeds`), as a table.
fn seeded_report(sizes: &[usize], seeds: u64, scene_of: impl Fn(usize, u64) -> Scene) {
    println!("| k | seed | time | pattern solves | interior steps | converged |");
    println!("|---|---|---|---|---|---|");
    let sizes = std::env::var("BEAMFRIC_FAMILY_K")
        .map(|_| self::sizes())
        .unwrap_or_else(|_| sizes.to_vec());
    for k in sizes {
        for seed in 1..=self::seeds(seeds) {
            println!("| {k} | {seed} | {} |", cold_solve_row(&scene_of(k, seed)));
        }
    }
}

/// `BEAMFRIC_SEEDS`, or `default`.
fn seeds(default: u64) -> u64 {
    std::env::var("BEAMFRIC_SEEDS").map_or(default, |v| {
        v.trim()
            .parse()
            .expect("BEAMFRIC_SEEDS: how many seeds, like 4")
    })
}

fn write_scenes(dir: &str) {
    std::fs::create_dir_all(dir).expect("the directory can be made");
    for family in families() {
        for k in sizes() {
            let scene = family_scene(family, k, seed(), ELEMENTS);
            let path = format!("{dir}/{}-{k}.toml", family.name());
            std::fs::write(&path, scene.to_toml()).expect("the scene can be written");
            println!("{path}");
        }
    }
}

fn main() {
    // As the binary does: a solve's freed memory is kept for the next (`beamfric::memory`).
    // SAFETY: first thing in main, no other thread runs yet.
    unsafe { beamfric::memory::keep_freed_memory() };
    let mut tools = std::env::args().skip(1).filter(|arg| !arg.starts_with('-'));
    let tool = tools.next();
    match tool.as_deref() {
        Some("scenes") => {
            write_scenes(&tools.next().unwrap_or_else(|| "target/tmp/families".into()))
        }
        Some("report") => report(),
        Some("warm") => warm_report(),
        Some("explorer") => explorer_report(),
        Some("lowered") => lowered_report(),
        Some("clustered-ties") => clustered_ties_report(),
        Some("dense") => dense_report(),
        Some("pairs") => pairs_report(),
        Some("partial-ties") => partial_ties_report(),
        Some("tight-clusters") => tight_clusters_report(),
        _ => criterion_runs(),
    }
}
