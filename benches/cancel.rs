//! How long a replaced solve keeps its core: for every method on its worst scene, a solve runs
//! on a thread, its `Cancellation` is triggered after a delay, and the time from the cancel to
//! `solve`'s return is measured. A measured harness, not a test: `cargo bench --bench cancel
//! [-- FILTER… --repeats N --sweep N --span S --cap S --condition off|auto|full]` (release
//! build).
//!
//! Delays are counted in the solving thread's CPU time (not wall time), so that on a busy
//! machine a delay still lands in the same phase of the solve. First the uncancelled solve's
//! CPU time T is measured (cut at `--cap` seconds, default 60). Then: 50 ms, 200 ms and 1 s,
//! each repeated (`--repeats`, default 3), and a sweep of `--sweep` delays (default 24, one
//! solve each) evenly spread over the first min(T, `--span`) seconds (default 10), so that
//! every phase of the solve is hit. Reported: the latency from the cancel to the return, in
//! wall time and in the solving thread's CPU time, median and max — the CPU time is what the
//! solve takes from its core after the cancel, whatever else the machine runs (its wall time
//! also counts waiting for a core).
//!
//! The scenes: 511 obstacles (the dense methods' limit is 512) on the meshes where each method
//! is slowest (n = 1000 for the stiffness route, whose rounding makes the box QP hard there;
//! n = 2001, N = 4000 unknowns, for `dual-inverse`'s dense inverse), on 10⁵ elements (where
//! rounding makes `dual`'s K indefinite: its LU route) and on 10⁷ elements (the largest mesh:
//! the O(n) stages); 6 obstacles for the enumeration (9⁶ cases, its limit), 4000 obstacles for
//! `condensed`, Benchmark 1 for the closed form. The options are the defaults of
//! `beamfric solve` (condition numbers `auto`, the reference error) unless `--condition`
//! says otherwise.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use beamfric::fem::Mesh;
use beamfric::model::Problem;
use beamfric::scene::{ObstacleSpec, Scene, preset};
use beamfric::solve::{Cancellation, ConditionLevel, Method, SolveErrorKind, SolveOptions, solve};
use nix::libc;

/// A scene of the harness: a method on a problem and a mesh size.
struct Case {
    name: String,
    method: Method,
    problem: Problem,
    elements: usize,
}

/// Benchmark 3's beam (1 m, 20 mm square) under 5e4 → −3e4 N/m with `k` evenly spaced
/// obstacles whose thresholds spread over four decades (a fixed sequence): the crowded scene
/// of tests/it/cancel.rs with `k` obstacles.
fn crowded(k: usize) -> Problem {
    let mut scene = Scene::from_toml(preset("benchmark-3").unwrap().text, "b3").unwrap();
    scene.load.f0 = 5e4;
    scene.load.f1 = Some(-3e4);
    let mut state = 7u64;
    let mut uniform = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let length = scene.beam.length;
    scene.obstacles = (0..k)
        .map(|i| ObstacleSpec {
            x: (i + 1) as f64 / (k + 1) as f64 * length,
            sliding: 10f64.powf(4.0 * uniform()),
            swivel: 10f64.powf(4.0 * uniform()),
        })
        .collect();
    scene.validate("crowded").unwrap().0
}

/// `k` obstacles at jittered positions with thresholds around the fixed-end forces of their
/// spans (benches/solve.rs's `condensed-many-obstacles` scene).
fn crowded_condensed(k: usize) -> Problem {
    let mut scene = Scene::from_toml(preset("benchmark-3").unwrap().text, "b3").unwrap();
    let load = 1e5;
    let h = scene.beam.length / (k + 1) as f64;
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

fn cases() -> Vec<Case> {
    let benchmark_1 = Scene::from_toml(preset("benchmark-1").unwrap().text, "b1")
        .unwrap()
        .validate("b1")
        .unwrap()
        .0;
    let case = |method: Method, problem: &Problem, elements: usize| {
        let k = problem.obstacles.len();
        let n = if elements == 10_000_000 {
            "1e7".to_string()
        } else {
            elements.to_string()
        };
        Case {
            name: format!("{method}/k={k}/n={n}"),
            method,
            problem: problem.clone(),
            elements,
        }
    };
    let dense = crowded(511);
    let six = crowded(6);
    vec![
        case(Method::Dual, &dense, 1000),
        case(Method::Dual, &dense, 100_000),
        case(Method::Dual, &dense, 10_000_000),
        case(Method::DualInverse, &dense, 2001),
        case(Method::Flexibility, &dense, 1000),
        case(Method::Flexibility, &dense, 10_000_000),
        case(Method::RegularizedNewton, &dense, 1000),
        case(Method::RegularizedNewton, &dense, 10_000_000),
        case(Method::Regularized, &six, 1000),
        case(Method::Regularized, &six, 10_000_000),
        case(Method::Condensed, &crowded_condensed(4000), 10_000_000),
        case(Method::ClosedForm, &benchmark_1, 10_000_000),
    ]
}

/// The CPU time of the thread whose CPU clock is `clock`.
fn cpu_time(clock: libc::clockid_t) -> Duration {
    let mut now = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes into the timespec it is given.
    let status = unsafe { libc::clock_gettime(clock, &mut now) };
    assert_eq!(status, 0, "the thread's CPU clock can be read");
    Duration::new(now.tv_sec as u64, now.tv_nsec as u32)
}

/// The calling thread's CPU clock.
fn this_thread_clock() -> libc::clockid_t {
    let mut clock: libc::clockid_t = 0;
    // SAFETY: pthread_getcpuclockid writes the id of the calling thread's clock.
    let status = unsafe { libc::pthread_getcpuclockid(libc::pthread_self(), &mut clock) };
    assert_eq!(status, 0, "the thread has a CPU clock");
    clock
}

/// One solve cancelled once its thread has used `delay` of CPU time (never when `None`).
struct Run {
    /// The solve's CPU time when it returned.
    cpu: Duration,
    /// (wall, CPU) from the cancel to the return; `None` when it returned first.
    latency: Option<(Duration, Duration)>,
    /// The solve's outcome: "cancelled", "solved" or the error kind.
    outcome: &'static str,
}

fn run(case: &Case, mesh: &Mesh, delay: Option<Duration>, condition: ConditionLevel) -> Run {
    let newest = Arc::new(AtomicU64::new(1));
    let options = SolveOptions {
        condition,
        cancel: Cancellation::watching(Arc::clone(&newest), 1),
        ..SolveOptions::default()
    };
    std::thread::scope(|scope| {
        let (tell_clock, clock) = mpsc::channel();
        let (tell_end, end) = mpsc::channel();
        let options = &options;
        scope.spawn(move || {
            let clock = this_thread_clock();
            tell_clock.send(clock).unwrap();
            let outcome = match solve(&case.problem, mesh, case.method, options) {
                Ok(_) => "solved",
                Err(e) if e.kind == SolveErrorKind::Cancelled => "cancelled",
                Err(e) => e.kind.name(),
            };
            tell_end
                .send((Instant::now(), cpu_time(clock), outcome))
                .unwrap();
        });
        let clock = clock.recv().unwrap();
        let mut cancelled_at = None;
        loop {
            if let Ok((returned, cpu, outcome)) = end.try_recv() {
                let latency = cancelled_at
                    .map(|(wall, cpu_then): (Instant, Duration)| (returned - wall, cpu - cpu_then));
                return Run {
                    cpu,
                    latency,
                    outcome,
                };
            }
            if cancelled_at.is_none()
                && let Some(delay) = delay
            {
                let used = cpu_time(clock);
                if used >= delay {
                    newest.store(2, Ordering::Relaxed);
                    cancelled_at = Some((Instant::now(), cpu_time(clock)));
                }
            }
            std::thread::sleep(Duration::from_micros(500));
        }
    })
}

/// (median, max) of a non-empty list.
fn median_max(mut values: Vec<Duration>) -> (Duration, Duration) {
    values.sort();
    (values[values.len() / 2], values[values.len() - 1])
}

fn ms(d: Duration) -> String {
    format!("{:.1}", d.as_secs_f64() * 1e3)
}

struct Settings {
    filters: Vec<String>,
    repeats: usize,
    sweep: usize,
    span: Duration,
    cap: Duration,
    condition: ConditionLevel,
}

fn settings() -> Settings {
    let mut settings = Settings {
        filters: Vec::new(),
        repeats: 3,
        sweep: 24,
        span: Duration::from_secs(10),
        cap: Duration::from_secs(60),
        condition: ConditionLevel::Auto,
    };
    let mut args = std::env::args().skip(1);
    let value = |args: &mut std::iter::Skip<std::env::Args>| args.next().unwrap();
    while let Some(arg) = args.next() {
        let seconds = |text: String| Duration::from_secs_f64(text.parse().unwrap());
        match arg.as_str() {
            "--repeats" => settings.repeats = value(&mut args).parse().unwrap(),
            "--sweep" => settings.sweep = value(&mut args).parse().unwrap(),
            "--span" => settings.span = seconds(value(&mut args)),
            "--cap" => settings.cap = seconds(value(&mut args)),
            "--condition" => {
                let name = value(&mut args);
                settings.condition = ConditionLevel::ALL
                    .into_iter()
                    .find(|level| level.name() == name)
                    .unwrap_or_else(|| panic!("no condition level {name}"));
            }
            // What `cargo bench` passes to every bench target.
            "--bench" => {}
            filter => settings.filters.push(filter.to_string()),
        }
    }
    settings
}

/// One row of the table: the latencies of `runs` cancelled after `label`.
fn row(label: &str, runs: &[(Duration, Run)]) -> (Duration, Duration) {
    let latencies: Vec<(Duration, Duration)> = runs.iter().filter_map(|r| r.1.latency).collect();
    let mut outcomes: Vec<&str> = runs.iter().map(|r| r.1.outcome).collect();
    outcomes.sort();
    outcomes.dedup();
    if latencies.is_empty() {
        println!("| {label} | – | – | – | – | {} |", outcomes.join(", "));
        return (Duration::ZERO, Duration::ZERO);
    }
    let (wall_median, wall_max) = median_max(latencies.iter().map(|l| l.0).collect());
    let (cpu_median, cpu_max) = median_max(latencies.iter().map(|l| l.1).collect());
    // Where the slowest cancel came.
    let slowest = runs
        .iter()
        .filter_map(|(delay, r)| r.latency.map(|l| (l.1, *delay)))
        .max()
        .map_or(0.0, |(_, delay)| delay.as_secs_f64() * 1e3);
    println!(
        "| {label} | {} | {} | {} | {} (at {slowest:.0}) | {} |",
        ms(wall_median),
        ms(wall_max),
        ms(cpu_median),
        ms(cpu_max),
        outcomes.join(", ")
    );
    (wall_max, cpu_max)
}

fn measure(case: &Case, settings: &Settings) {
    let mesh = Mesh::new(&case.problem, case.elements);
    let solve_after = |delay: Duration| (delay, run(case, &mesh, Some(delay), settings.condition));
    let baseline = run(case, &mesh, Some(settings.cap), settings.condition);
    let whole = (baseline.latency.is_none()).then_some(baseline.cpu);
    match whole {
        Some(cpu) => println!(
            "{}: uncancelled {} ({} ms CPU)",
            case.name,
            baseline.outcome,
            ms(cpu)
        ),
        None => println!(
            "{}: longer than {} s of CPU (cut there, {} ms after the cancel)",
            case.name,
            settings.cap.as_secs(),
            ms(baseline.latency.unwrap().1)
        ),
    }
    let total = whole.unwrap_or(settings.cap);
    println!(
        "| delay (CPU ms) | wall median | wall max | CPU median | CPU max (at delay) | outcomes |"
    );
    println!("|---:|---:|---:|---:|---:|---|");
    let mut worst = (Duration::ZERO, Duration::ZERO);
    for delay in [50, 200, 1000].map(Duration::from_millis) {
        if delay >= total {
            continue;
        }
        let runs: Vec<(Duration, Run)> =
            (0..settings.repeats).map(|_| solve_after(delay)).collect();
        let (wall, cpu) = row(&ms(delay), &runs);
        worst = (worst.0.max(wall), worst.1.max(cpu));
    }
    let span = total.min(settings.span);
    let runs: Vec<(Duration, Run)> = (0..settings.sweep)
        .map(|i| solve_after(span.mul_f64((i as f64 + 0.5) / settings.sweep as f64)))
        .collect();
    let label = format!("sweep of {} over {} ms", settings.sweep, span.as_millis());
    let (wall, cpu) = row(&label, &runs);
    worst = (worst.0.max(wall), worst.1.max(cpu));
    println!(
        "{}: worst latency {} ms wall, {} ms CPU\n",
        case.name,
        ms(worst.0),
        ms(worst.1)
    );
}

fn main() {
    let settings = settings();
    for case in cases() {
        if !settings.filters.is_empty() && !settings.filters.iter().any(|f| case.name.contains(f)) {
            continue;
        }
        measure(&case, &settings);
    }
}
