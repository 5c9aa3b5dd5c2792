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

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};

use russh::client::{self, AuthResult, Handle};
use russh::keys::PublicKeyOrCertificate;
use russh::{Channel, ChannelMsg};

/// A guard against a hung server, not a measurement.
const PATIENCE: Duration = Duration::from_secs(60);
const SESSIONS: usize = 40;
const KEYS: usize = 40;

struct TrustingClient;

impl client::Handler for TrustingClient {
    type Error = russh::Error;

    async fn check_server_key(
        &mut self,
        _key: &PublicKeyOrCertificate,
    ) -> Result<bool, Self::Error> {
        Ok(true)
    }
}

/// The server process and the address it listens on.
struct ServerProcess {
    child: Child,
    address: std::net::SocketAddr,
    _dir: tempfile::TempDir,
}

impl ServerProcess {
    fn start() -> ServerProcess {
        let binary = std::env::var("BEAMFRIC_BIN")
            .unwrap_or_else(|_| env!("CARGO_BIN_EXE_beamfric").to_string());
        let dir = tempfile::tempdir().unwrap();
        let mut child = Command::new(&binary)
            .args(["serve", "--open", "--listen", "127.0.0.1:0", "--host-key"])
            .arg(dir.path().join("host_key"))
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start {binary}: {e}"));
        // "listening on 127.0.0.1:PORT (host key …)"; the rest of the log is drained.
        let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
        let address = loop {
            let line = lines
                .next()
                .expect("the server said where it listens")
                .unwrap();
            if let Some(rest) = line.split("listening on ").nth(1) {
                break rest.split_whitespace().next().unwrap().parse().unwrap();
            }
        };
        std::thread::spawn(move || lines.for_each(drop));
        ServerProcess {
            child,
            address,
            _dir: dir,
        }
    }

    /// A line of `/proc/PID/status` as a number (`VmRSS` in KiB, `Threads`).
    fn status(&self, field: &str) -> u64 {
        process_status(self.child.id(), field)
    }

    fn resident_kib(&self) -> u64 {
        self.status("VmRSS")
    }

    /// Waits until the server runs `threads` threads or fewer (its sessions have ended).
    fn settle_to(&self, threads: u64) {
        let start = Instant::now();
        while self.status("Threads") > threads {
            assert!(start.elapsed() < PATIENCE, "sessions never ended");
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

impl Drop for ServerProcess {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A line of `/proc/PID/status` of process `pid` as a number.
fn process_status(pid: u32, field: &str) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix(field)?.strip_prefix(':'))
        .and_then(|v| v.split_whitespace().next()?.parse().ok())
        .unwrap_or(0)
}

async fn logged_in(address: std::net::SocketAddr) -> Handle<TrustingClient> {
    let config = Arc::new(client::Config::default());
    let mut handle = client::connect(config, address, TrustingClient)
        .await
        .unwrap();
    let result = handle.authenticate_none("student").await.unwrap();
    assert_eq!(result, AuthResult::Success);
    handle
}

/// A student's explorer as its client sees it.
struct Student {
    channel: Channel<client::Msg>,
    screen: vt100::Parser,
}

impl Student {
    async fn open(handle: &Handle<TrustingClient>) -> Student {
        let channel = handle.channel_open_session().await.unwrap();
        channel
            .request_pty(true, "xterm-256color", 100, 30, 0, 0, &[])
            .await
            .unwrap();
        channel.request_shell(true).await.unwrap();
        Student {
            channel,
            screen: vt100::Parser::new(30, 100, 0),
        }
    }

    /// Reads until the screen shows `needle`.
    async fn wait_for(&mut self, needle: &str) {
        let deadline = Instant::now() + PATIENCE;
        while !self.screen.screen().contents().contains(needle) {
            let left = deadline.saturating_duration_since(Instant::now());
            match tokio::time::timeout(left, self.channel.wait()).await {
                Ok(Some(ChannelMsg::Data { data })) => self.screen.process(&data),
                Ok(Some(_)) => {}
                Ok(None) => panic!("the channel closed before {needle:?}"),
                Err(_) => panic!("{needle:?} never shown"),
            }
        }
    }

    /// Presses `key`; returns when the first frame after it came and when the last (whatever
    /// follows within 50 ms of the one before).
    async fn press(&mut self, key: &[u8]) -> (Option<Duration>, Option<Duration>) {
        let sent = Instant::now();
        self.channel.data_bytes(key.to_vec()).await.unwrap();
        let (mut first, mut last) = (None, None);
        let mut wait = PATIENCE;
        while let Ok(Some(message)) = tokio::time::timeout(wait, self.channel.wait()).await {
            if let ChannelMsg::Data { data } = message {
                self.screen.process(&data);
                first.get_or_insert(sent.elapsed());
                last = Some(sent.elapsed());
                wait = Duration::from_millis(50);
            }
        }
        (first, last)
    }
}

fn percentile(values: &mut [Duration], p: f64) -> Duration {
    values.sort();
    values[((values.len() - 1) as f64 * p).round() as usize]
}

fn runtime() -> tokio::runtime::Runtime {
    tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .unwrap()
}

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
