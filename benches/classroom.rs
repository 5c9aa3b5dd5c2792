//! A classroom against `beamfric serve`, measured from outside: the server runs as its own
//! process (`beamfric serve --open` on a loopback port), students are russh clients with a
//! pty, and the server's memory is read from `/proc/PID/status`, so nothing of the clients
//! counts. A measured harness, not a test: `cargo bench --bench classroom` (release build);
//! `BEAMFRIC_BIN=/path/to/beamfric` measures another build of the program (e.g. an older
//! commit's), `CLASSROOM_CONNECTS=N` sets the connect-and-leave rounds.
//!
//! It prints, for 40 students each pressing a key every 200 ms on Benchmark 1, the key-to-frame
//! latency (p50 and p99 of the first frame after a key, and of the last frame it caused) and
//! the server's resident memory per session; then the server's resident memory before and
//! after 1000 students each connect, see their first frame and leave.

use std::time::{Duration, Instant};

mod support;
use support::{ServerProcess, Student, logged_in, percentile, process_status, runtime};

const SESSIONS: usize = 40;
const KEYS: usize = 40;

/// 40 students pressing a key every 200 ms: latency, and memory per session.
fn forty_students(server: &ServerProcess) {
    let before = server.resident_kib();
    let address = server.address;
    let pid = server.child.id();
    let (mut first, mut last, during) = runtime().block_on(async move {
        let mut tasks = Vec::new();
        for index in 0..SESSIONS {
            let handle = logged_in(address).await;
            tasks.push(tokio::spawn(async move {
                let mut student = Student::open(&handle).await;
                student.wait_for("Parameters").await;
                // Stagger the students over the 200 ms period.
                tokio::time::sleep(Duration::from_millis(5 * index as u64)).await;
                let mut latencies = Vec::new();
                for key in 0..KEYS {
                    let sent = Instant::now();
                    // The load one fine step up and down: a solve every key.
                    let bytes: &[u8] = if key % 2 == 0 { b"l" } else { b"h" };
                    latencies.push(student.press(bytes).await);
                    let next = sent + Duration::from_millis(200);
                    tokio::time::sleep(next.saturating_duration_since(Instant::now())).await;
                }
                (handle, latencies)
            }));
        }
        // Four seconds into the keys: every session open and working.
        tokio::time::sleep(Duration::from_secs(4)).await;
        let during = process_status(pid, "VmRSS");
        let (mut first, mut last) = (Vec::new(), Vec::new());
        for task in tasks {
            let (_handle, latencies) = task.await.unwrap();
            for (f, l) in latencies {
                first.push(f.unwrap_or(Duration::MAX));
                last.push(l.unwrap_or(Duration::MAX));
            }
        }
        (first, last, during)
    });
    let missed = first.iter().filter(|d| **d == Duration::MAX).count();
    println!(
        "{SESSIONS} students at Benchmark 1, a key each every 200 ms: key to first frame p50 \
         {:.2?} p99 {:.2?}; to last frame p50 {:.2?} p99 {:.2?}; {missed} of {} keys without \
         a frame",
        percentile(&mut first, 0.5),
        percentile(&mut first, 0.99),
        percentile(&mut last, 0.5),
        percentile(&mut last, 0.99),
        first.len(),
    );
    println!(
        "server memory: {before} KiB idle, {during} KiB with {SESSIONS} sessions at work: {:.2} \
         MiB per session",
        (during.saturating_sub(before)) as f64 / SESSIONS as f64 / 1024.0
    );
}

/// Students who connect, see their first frame and leave, one after the other.
fn connect_and_leave(server: &ServerProcess, rounds: usize) {
    let address = server.address;
    let round = move || async move {
        let handle = logged_in(address).await;
        let mut student = Student::open(&handle).await;
        student.wait_for("Parameters").await;
        drop(student);
        let _ = handle
            .disconnect(russh::Disconnect::ByApplication, "", "")
            .await;
    };
    let runtime = runtime();
    let idle_threads = server.status("Threads");
    // Warm up the allocator and the runtime with a few rounds first.
    for _ in 0..10 {
        runtime.block_on(round());
    }
    server.settle_to(idle_threads);
    let before = server.resident_kib();
    let start = Instant::now();
    let mut along = Vec::new();
    for done in 1..=rounds {
        runtime.block_on(round());
        if done % (rounds / 4).max(1) == 0 {
            server.settle_to(idle_threads);
            along.push(format!("{done}: {} KiB", server.resident_kib()));
        }
    }
    server.settle_to(idle_threads);
    let after = server.resident_kib();
    println!("server memory along the way: {}", along.join(", "));
    println!(
        "{rounds} students connected, saw their first frame and left in {:.1?}: server memory \
         {before} KiB before, {after} KiB after ({:+} KiB)",
        start.elapsed(),
        after as i64 - before as i64
    );
}

fn main() {
    // `cargo bench` passes `--bench`; nothing else is read from the arguments.
    let rounds = std::env::var("CLASSROOM_CONNECTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1000);
    let server = ServerProcess::start();
    forty_students(&server);
    drop(server);
    let server = ServerProcess::start();
    connect_and_leave(&server, rounds);
}
