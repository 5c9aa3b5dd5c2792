//! What recording the convergence history costs (issue 24): `solve` with
//! `SolveOptions::history` off and on, for `dual`, `regularized-newton` and `condensed` on
//! Benchmark 1 and Benchmark 3 at the presets' n = 20 (the explorer's per-keystroke size) and
//! at n = 10⁴, without condition numbers or the reference comparison (the method alone, with
//! its certificate). With history off the time must be today's: run against the `main`
//! branch with `--save-baseline main` there and `--baseline main` here (the `off` cases only
//! exist there).
//!
//! Measured 2026-12-02 on the shared 2-core machine (load average about 6, so criterion's
//! times scattered by ±30 % from round to round for the same binary, in either direction): seven
//! interleaved rounds of main's and this branch's binaries gave median ratios (history off /
//! main) of 0.91–1.28 with no consistent sign. Instruction counts of one solve under
//! `valgrind --tool=callgrind` (`--bench --test`, inclusive cost of `solve::solve`) are
//! load-free: history off against main +0.0 % to +0.4 % at n = 20 and +0.15 % at most at
//! n = 10⁴ (e.g. Benchmark 3 `dual`: 7 448 087 → 7 457 782; `condensed`: 2 799 537 →
//! 2 790 682); history on adds 3–14 % at n = 20 (Benchmark 3 `regularized-newton`: 227 688 →
//! 260 731) and under 0.5 % at n = 10⁴.

use std::hint::black_box;
use std::time::Duration;

use beamfric::fem::Mesh;
use beamfric::scene::{Scene, preset};
use beamfric::solve::{ConditionLevel, Method, SolveOptions, solve};
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};

fn options(history: bool) -> SolveOptions {
    SolveOptions {
        condition: ConditionLevel::Off,
        reference: false,
        history,
        ..SolveOptions::default()
    }
}

fn history(c: &mut Criterion) {
    let mut group = c.benchmark_group("history");
    group.sample_size(30);
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(2));
    for name in ["benchmark-1", "benchmark-3"] {
        let scene = Scene::from_toml(preset(name).unwrap().text, name).unwrap();
        let problem = scene.validate(name).unwrap().0;
        for n in [20usize, 10_000] {
            let mesh = Mesh::new(&problem, n);
            for method in [Method::Dual, Method::RegularizedNewton, Method::Condensed] {
                for (label, recorded) in [("off", false), ("on", true)] {
                    let options = options(recorded);
                    group.bench_with_input(
                        BenchmarkId::new(format!("{name}/{method}/n={n}"), label),
                        &mesh,
                        |b, mesh| {
                            b.iter(|| black_box(solve(&problem, mesh, method, &options).unwrap()))
                        },
                    );
                }
            }
        }
    }
    group.finish();
}

criterion_group!(benches, history);
criterion_main!(benches);
