//! A hostile pass against `beamfric serve`, measured from outside (issue 22): the server runs
//! as its own process (`BEAMFRIC_BIN=/path/to/beamfric` measures another build, e.g. an older
//! commit's), the attackers and students are russh clients or bare TCP connections, and the
//! server's CPU time, threads and memory are read from `/proc`. A measured harness, not a
//! test: `cargo bench --bench attacks [-- NAME…]` with NAME among `silent`, `resize`, `keys`,
//! `memory`, `unread`, `heavy` (default: all). `ATTACK_SESSIONS` (64), `ATTACK_ELEMENTS`
//! (10⁴) and `ATTACK_UNDO_KEYS` (100) size the memory pass.

use std::io::Write;
use std::net::TcpStream;
use std::time::{Duration, Instant};

mod support;
use support::{
    PATIENCE, ServerProcess, Student, logged_in, percentile, process_cpu, runtime, threads_named,
    try_logged_in,
};

/// A scene of `k` obstacles on Benchmark 3's beam at `elements` elements solved by `method`.
fn many_obstacles(dir: &std::path::Path, k: usize, elements: usize, method: &str) -> String {
    let mut text = String::from(
        "title = \"Many obstacles\"\n[beam]\nlength = 1.0\nyoung = 2.15e11\nsection = { shape = \
         \"circle\", radius = 0.01 }\n[load]\nf0 = 1e5\nf1 = 1.5e5\n",
    );
    for i in 0..k {
        let x = (i + 1) as f64 / (k + 1) as f64;
        text.push_str(&format!(
            "[[obstacle]]\nx = {x:.12}\nsliding = 20\nswivel = 5\n"
        ));
    }
    text.push_str(&format!(
        "[mesh]\nelements = {elements}\n[solver]\nmethod = \"{method}\"\nepsilon = 1e-6\n"
    ));
    let path = dir.join(format!("k{k}-{method}.toml"));
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

/// Ends the connection as a client that goes away does: a disconnect message if it can be
/// sent within a second (a client that stopped reading may be unable to), then the socket is
/// dropped.
async fn hang_up<H: russh::client::Handler>(handle: russh::client::Handle<H>) {
    let _ = tokio::time::timeout(
        Duration::from_secs(1),
        handle.disconnect(russh::Disconnect::ByApplication, "", ""),
    )
    .await;
    drop(handle);
}

/// Waits until the server runs no session thread; how long that took.
fn sessions_gone(server: &ServerProcess, since: Instant) -> Option<Duration> {
    let pid = server.child.id();
    while threads_named(pid, "session") > 0 {
        if since.elapsed() > PATIENCE * 10 {
            return None;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    Some(since.elapsed())
}

/// CPU the server used in each of the `seconds` seconds after `since`.
fn cpu_per_second(server: &ServerProcess, since: Instant, seconds: u32) -> Vec<Duration> {
    let pid = server.child.id();
    let mut last = process_cpu(pid);
    (1..=seconds)
        .map(|s| {
            let at = since + Duration::from_secs(s.into());
            std::thread::sleep(at.saturating_duration_since(Instant::now()));
            let now = process_cpu(pid);
            let used = now.saturating_sub(last);
            last = now;
            used
        })
        .collect()
}

fn report_after_hangup(what: &str, server: &ServerProcess, hung_up: Instant) {
    let (gone, cpu) = std::thread::scope(|scope| {
        let gone = scope.spawn(|| sessions_gone(server, hung_up));
        let cpu = cpu_per_second(server, hung_up, 3);
        (gone.join().unwrap(), cpu)
    });
    println!(
        "{what}: session thread gone {} after the hang-up; server CPU in the 1st, 2nd, 3rd second \
         after it: {:?}",
        gone.map_or("never (10 min)".to_string(), |d| format!("{d:.2?}")),
        cpu
    );
}

/// 300 silent TCP connections, then a student: how long until their first frame.
fn silent() {
    let server = ServerProcess::start();
    let silent: Vec<TcpStream> = (0..300)
        .filter_map(|_| TcpStream::connect(server.address).ok())
        .collect();
    std::thread::sleep(Duration::from_millis(500));
    let start = Instant::now();
    let address = server.address;
    let result = runtime().block_on(async move {
        tokio::time::timeout(PATIENCE, async move {
            loop {
                // A student retries, as a person would, when the connection is refused.
                let attempt = tokio::time::timeout(Duration::from_secs(10), async {
                    let handle = try_logged_in(address).await?;
                    let mut student = Student::open(&handle).await;
                    student.wait_for("Parameters").await;
                    Some(())
                })
                .await;
                if let Ok(Some(())) = attempt {
                    return;
                }
                tokio::time::sleep(Duration::from_millis(100)).await;
            }
        })
        .await
    });
    println!(
        "silent: {} silent connections open; a student's first frame {}",
        silent.len(),
        match result {
            Ok(()) => format!("after {:.2?}", start.elapsed()),
            Err(_) => format!("never within {PATIENCE:?} (locked out)"),
        }
    );
    drop(silent);
}

/// Two seconds of window changes at the largest size, then a hang-up.
fn resize() {
    let server = ServerProcess::start();
    let address = server.address;
    let (changes, hung_up) = runtime().block_on(async move {
        let handle = logged_in(address).await;
        let mut student = Student::open(&handle).await;
        student.wait_for("Parameters").await;
        let start = Instant::now();
        let mut changes = 0u32;
        while start.elapsed() < Duration::from_secs(2) {
            let (w, h) = if changes.is_multiple_of(2) {
                (1000, 500)
            } else {
                (999, 499)
            };
            // This client does not read meanwhile: its own buffers may fill and hold it up.
            let change = student.channel.window_change(w, h, 0, 0);
            match tokio::time::timeout(Duration::from_millis(100), change).await {
                Ok(Ok(())) => changes += 1,
                Ok(Err(_)) => break,
                Err(_) => {}
            }
        }
        drop(student);
        hang_up(handle).await;
        let hung_up = Instant::now();
        (changes, hung_up)
    });
    report_after_hangup(
        &format!("resize: {changes} window changes in 2 s"),
        &server,
        hung_up,
    );
}

/// 32 000 bytes of `][` on a 4000-obstacle scene, then a hang-up.
fn keys(dir: &std::path::Path) {
    let scene = many_obstacles(dir, 4000, 10_000, "condensed");
    let server = ServerProcess::start_with(&["--scene", &scene]);
    let address = server.address;
    let hung_up = runtime().block_on(async move {
        let handle = logged_in(address).await;
        let mut student = Student::open(&handle).await;
        student.wait_for("Parameters").await;
        student
            .channel
            .data_bytes(b"][".repeat(16_000))
            .await
            .unwrap();
        // Long enough for the bytes to reach the server, not for it to apply them.
        tokio::time::sleep(Duration::from_millis(200)).await;
        drop(student);
        hang_up(handle).await;
        Instant::now()
    });
    report_after_hangup("keys: 32000 bytes of ][ at k = 4000", &server, hung_up);
}

/// `sessions` sessions at `size` on a 4000-obstacle scene at `elements` elements, each with
/// `undo_keys` changes kept for undo: the server's memory per session.
fn memory(
    dir: &std::path::Path,
    size: (u16, u16),
    (sessions, elements): (usize, usize),
    undo_keys: usize,
) {
    let scene = many_obstacles(dir, 4000, elements, "condensed");
    // No cap from the budget: what the sessions really take is measured.
    let server = ServerProcess::start_with(&[
        "--scene",
        &scene,
        "--max-sessions",
        "4096",
        "--memory-budget",
        "1048576",
    ]);
    let idle = server.resident_kib();
    let address = server.address;
    let pid = server.child.id();
    let during = runtime().block_on(async move {
        let mut students = Vec::new();
        for _ in 0..sessions {
            let handle = logged_in(address).await;
            let mut student = Student::open_sized(&handle, size).await;
            student.wait_for("Parameters").await;
            students.push((handle, student));
        }
        // Each change of the load a step up then down: one undo step each.
        for round in 0..undo_keys {
            for (_, student) in &students {
                let key: &[u8] = if round.is_multiple_of(2) { b"l" } else { b"h" };
                student.channel.data_bytes(key.to_vec()).await.unwrap();
            }
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
        // Every key applied: a last one's frame shows the undo count.
        for (_, student) in &mut students {
            student.channel.data_bytes(b"u".to_vec()).await.unwrap();
            student.wait_for("undone").await;
        }
        let during = support::process_status(pid, "VmRSS");
        drop(students);
        during
    });
    println!(
        "memory: {sessions} sessions at {}x{} on k = 4000, n = {elements} with {undo_keys} changes each: server \
         {idle} KiB idle, {during} KiB with them: {:.1} MiB per session (the budget reserves {} \
         MiB per session at the default --max-elements)",
        size.0,
        size.1,
        (during.saturating_sub(idle)) as f64 / sessions as f64 / 1024.0,
        beamfric::serve::memory::per_session(100_000) >> 20
    );
}

/// A client that floods window changes and keys and never reads what the server sends.
fn unread() {
    let server = ServerProcess::start();
    let idle = server.resident_kib();
    let address = server.address;
    let pid = server.child.id();
    let peak = runtime().block_on(async move {
        let handle = logged_in(address).await;
        let student = Student::open_sized(&handle, (400, 150)).await;
        let start = Instant::now();
        let mut peak = 0;
        let mut changes = 0u32;
        while start.elapsed() < Duration::from_secs(10) {
            let (w, h) = if changes.is_multiple_of(2) {
                (1000, 500)
            } else {
                (999, 499)
            };
            // The client's own buffers fill up too: it stops sending after a while.
            let change = student.channel.window_change(w, h, 0, 0);
            match tokio::time::timeout(Duration::from_millis(100), change).await {
                Ok(Ok(())) => changes += 1,
                Ok(Err(_)) => break,
                Err(_) => {}
            }
            if changes.is_multiple_of(100) {
                peak = peak.max(support::process_status(pid, "VmRSS"));
            }
        }
        peak = peak.max(support::process_status(pid, "VmRSS"));
        std::mem::forget(student);
        std::mem::forget(handle);
        peak
    });
    println!(
        "unread: a client that never reads, 10 s of window changes: server {idle} KiB idle, \
         {peak} KiB at most"
    );
}

/// Two students at 511 obstacles on `dual` keep the cores busy; a third on Benchmark 1 times
/// its solves.
fn heavy(dir: &std::path::Path) {
    let scene = many_obstacles(dir, 511, 2000, "dual");
    let server = ServerProcess::start_with(&["--scene", &scene]);
    let address = server.address;
    let mut times = runtime().block_on(async move {
        let mut heavy = Vec::new();
        // ATTACK_HEAVY students at work (2): 0 measures the light student alone.
        let heavy_students = std::env::var("ATTACK_HEAVY")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(2);
        for _ in 0..heavy_students {
            let handle = logged_in(address).await;
            let mut student = Student::open(&handle).await;
            student.wait_for("Parameters").await;
            heavy.push((handle, student));
        }
        let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let mut tasks = Vec::new();
        for (handle, mut student) in heavy {
            let stop = stop.clone();
            tasks.push(tokio::spawn(async move {
                let mut round = 0u32;
                while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                    let key: &[u8] = if round.is_multiple_of(2) { b"l" } else { b"h" };
                    let _ = student.channel.data_bytes(key.to_vec()).await;
                    round += 1;
                    // Read what it drew, as a client does, until the next key is due.
                    let next = tokio::time::Instant::now() + Duration::from_millis(300);
                    while let Ok(Some(message)) =
                        tokio::time::timeout_at(next, student.channel.wait()).await
                    {
                        if let russh::ChannelMsg::Data { data } = message {
                            student.screen.process(&data);
                        }
                    }
                }
                drop(student);
                hang_up(handle).await;
            }));
        }
        let handle = logged_in(address).await;
        let mut light = Student::open(&handle).await;
        light.wait_for("Parameters").await;
        // The light student loads Benchmark 1 from the picker.
        light
            .channel
            .data_bytes(b"pbenchmark-1\r".to_vec())
            .await
            .unwrap();
        light.wait_for("Benchmark 1").await;
        tokio::time::sleep(Duration::from_secs(2)).await;
        let mut times = Vec::new();
        for round in 0..30u32 {
            let key: &[u8] = if round.is_multiple_of(2) { b"l" } else { b"h" };
            let sent = Instant::now();
            light.channel.data_bytes(key.to_vec()).await.unwrap();
            // The frame after the key, then the one without "solving".
            let deadline = sent + PATIENCE;
            loop {
                let left = deadline.saturating_duration_since(Instant::now());
                match tokio::time::timeout(left, light.channel.wait()).await {
                    Ok(Some(russh::ChannelMsg::Data { data })) => light.screen.process(&data),
                    Ok(Some(_)) => continue,
                    _ => break,
                }
                if !light.screen.screen().contents().contains("solving") {
                    break;
                }
            }
            times.push(sent.elapsed());
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
        for task in tasks {
            let _ = task.await;
        }
        times
    });
    println!(
        "heavy: two students at k = 511 on dual, a third on Benchmark 1: key to solved frame \
         p50 {:.1?}, p99 {:.1?}",
        percentile(&mut times, 0.5),
        percentile(&mut times, 0.99)
    );
}

fn main() {
    // Each line as soon as it is measured, also into a file.
    let wanted: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let run = |name: &str| wanted.is_empty() || wanted.iter().any(|w| w == name);
    let dir = tempfile::tempdir().unwrap();
    let number = |name: &str, default: usize| {
        std::env::var(name)
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    if run("silent") {
        silent();
    }
    if run("resize") {
        resize();
    }
    if run("keys") {
        keys(dir.path());
    }
    if run("memory") {
        let sessions = number("ATTACK_SESSIONS", 64);
        let undo_keys = number("ATTACK_UNDO_KEYS", 100);
        let elements = number("ATTACK_ELEMENTS", 10_000);
        for size in [(80, 24), (200, 60), beamfric::tui::runtime::feed::MAX_SIZE] {
            memory(dir.path(), size, (sessions, elements), undo_keys);
        }
    }
    if run("unread") {
        unread();
    }
    if run("heavy") {
        heavy(dir.path());
    }
    let _ = std::io::stdout().flush();
}
