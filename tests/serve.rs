//! `beamfric serve` (issue 14) through real SSH: each test starts the server on an ephemeral
//! loopback port with a temporary host key, connects with russh's client (and once with
//! OpenSSH's `ssh` where installed), asks for a pty, and reads the screen through the `vt100`
//! terminal emulator.

#![cfg(unix)]

use std::sync::Arc;
use std::time::{Duration, Instant};

use beamfric::serve::{ServeOptions, Server};
use russh::client::{self, AuthResult, Handle};
use russh::keys::ssh_key::private::Ed25519Keypair;
use russh::keys::{PrivateKey, PrivateKeyWithHashAlg, PublicKeyOrCertificate};
use russh::{Channel, ChannelMsg};

/// A guard against a hung server, not a measurement.
const PATIENCE: Duration = Duration::from_secs(30);

/// The client accepts the server's key (a fresh one per test).
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

/// A server on a free loopback port with its host key in a temporary directory.
struct TestServer {
    server: Server,
    _dir: tempfile::TempDir,
}

fn options(dir: &tempfile::TempDir) -> ServeOptions {
    ServeOptions {
        listen: "127.0.0.1:0".into(),
        host_key: Some(dir.path().join("host_key")),
        open: true,
        ..ServeOptions::default()
    }
}

fn open_server() -> TestServer {
    let dir = tempfile::tempdir().unwrap();
    let server = Server::start(&options(&dir)).unwrap();
    TestServer { server, _dir: dir }
}

fn user_key(seed: u8) -> PrivateKey {
    PrivateKey::from(Ed25519Keypair::from_seed(&[seed; 32]))
}

fn runtime() -> tokio::runtime::Runtime {
    tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .unwrap()
}

async fn connect(server: &Server) -> Handle<TrustingClient> {
    let config = Arc::new(client::Config::default());
    client::connect(config, server.address(), TrustingClient)
        .await
        .unwrap()
}

/// Connected and logged in with "none" (an `--open` server).
async fn logged_in(server: &Server) -> Handle<TrustingClient> {
    let mut handle = connect(server).await;
    let result = handle.authenticate_none("student").await.unwrap();
    assert_eq!(result, AuthResult::Success);
    handle
}

/// Connected and logged in with `key`.
async fn logged_in_with(server: &Server, key: PrivateKey) -> Handle<TrustingClient> {
    let mut handle = connect(server).await;
    let key = PrivateKeyWithHashAlg::new(Arc::new(key), None);
    let result = handle.authenticate_publickey("someone", key).await.unwrap();
    assert_eq!(result, AuthResult::Success);
    handle
}

/// A served explorer as the client sees it.
struct Explorer {
    channel: Channel<client::Msg>,
    screen: vt100::Parser,
    /// Everything received, raw.
    raw: Vec<u8>,
    closed: bool,
    exit_status: Option<u32>,
}

impl Explorer {
    async fn open(
        handle: &Handle<TrustingClient>,
        size: (u16, u16),
        env: &[(&str, &str)],
    ) -> Explorer {
        let channel = handle.channel_open_session().await.unwrap();
        channel
            .request_pty(
                true,
                "xterm-256color",
                size.0.into(),
                size.1.into(),
                0,
                0,
                &[],
            )
            .await
            .unwrap();
        for (name, value) in env {
            channel.set_env(true, *name, *value).await.unwrap();
        }
        channel.request_shell(true).await.unwrap();
        Explorer {
            channel,
            screen: vt100::Parser::new(size.1, size.0, 0),
            raw: Vec::new(),
            closed: false,
            exit_status: None,
        }
    }

    fn text(&self) -> String {
        self.screen.screen().contents()
    }

    /// Reads until the screen shows `needle` (panics after [`PATIENCE`]).
    async fn wait_for(&mut self, needle: &str) {
        let deadline = Instant::now() + PATIENCE;
        while !self.text().contains(needle) {
            assert!(
                self.read_once(deadline).await,
                "the channel ended before {needle:?} was shown; screen:\n{}",
                self.text()
            );
        }
    }

    /// Reads until the channel closes.
    async fn wait_for_close(&mut self) {
        let deadline = Instant::now() + PATIENCE;
        while self.read_once(deadline).await {}
    }

    /// One message; false once the channel is closed.
    async fn read_once(&mut self, deadline: Instant) -> bool {
        if self.closed {
            return false;
        }
        let left = deadline.saturating_duration_since(Instant::now());
        let message = tokio::time::timeout(left, self.channel.wait())
            .await
            .unwrap_or_else(|_| panic!("nothing for {PATIENCE:?}; screen:\n{}", self.text()));
        match message {
            Some(ChannelMsg::Data { data }) => {
                self.raw.extend_from_slice(&data);
                self.screen.process(&data);
            }
            Some(ChannelMsg::ExitStatus { exit_status }) => self.exit_status = Some(exit_status),
            Some(ChannelMsg::Close) | None => self.closed = true,
            Some(_) => {}
        }
        !self.closed
    }

    async fn send(&self, bytes: &[u8]) {
        self.channel.data_bytes(bytes.to_vec()).await.unwrap();
    }

    async fn resize(&mut self, size: (u16, u16)) {
        self.screen.screen_mut().set_size(size.1, size.0);
        self.channel
            .window_change(size.0.into(), size.1.into(), 0, 0)
            .await
            .unwrap();
    }
}

/// Waits until `condition` holds (panics after [`PATIENCE`]); returns how long it took.
fn eventually(what: &str, condition: impl Fn() -> bool) -> Duration {
    let start = Instant::now();
    while !condition() {
        assert!(start.elapsed() < PATIENCE, "never: {what}");
        std::thread::sleep(Duration::from_millis(10));
    }
    start.elapsed()
}

#[test]
fn a_session_shows_the_explorer_follows_keys_and_resizes_and_ends_on_disconnect() {
    let test = open_server();
    let server = &test.server;
    runtime().block_on(async {
        let handle = logged_in(server).await;
        let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
        explorer.wait_for("Parameters").await;
        assert_eq!(server.sessions(), 1);
        // At 100×30 one panel is shown at a time: the ε-condition chart is not on screen.
        assert!(!explorer.text().contains("cond2 of the cases"));

        // A key changes the frame: the help overlay.
        assert!(!explorer.text().contains("change it by a coarse step"));
        explorer.send(b"?").await;
        explorer.wait_for("change it by a coarse step").await;
        explorer.send(b"\x1b").await;

        // Growing the window to 130×42 shows every panel.
        explorer.resize((130, 42)).await;
        explorer.wait_for("cond2 of the cases").await;

        handle
            .disconnect(russh::Disconnect::ByApplication, "", "en")
            .await
            .unwrap();
    });
    // The issue asks for one second; the bound here is generous for a loaded machine.
    let took = eventually("the session ends after a disconnect", || {
        server.sessions() == 0
    });
    assert!(took < Duration::from_secs(3), "took {took:?}");
    eventually("the connection is gone", || server.connections() == 0);
}

#[test]
fn q_quits_and_closes_the_channel_with_status_zero() {
    let test = open_server();
    runtime().block_on(async {
        let handle = logged_in(&test.server).await;
        let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
        explorer.wait_for("Parameters").await;
        explorer.send(b"q").await;
        explorer.wait_for_close().await;
        assert_eq!(explorer.exit_status, Some(0));
        // The alternate screen was left.
        let raw = String::from_utf8_lossy(&explorer.raw);
        assert!(
            raw.ends_with("\x1b[?25h") || raw.contains("\x1b[?1049l"),
            "{raw:?}"
        );
    });
    eventually("the session ends", || test.server.sessions() == 0);
}

#[test]
fn ascii_and_no_color_follow_the_clients_environment() {
    let test = open_server();
    runtime().block_on(async {
        let handle = logged_in(&test.server).await;
        let mut plain =
            Explorer::open(&handle, (100, 30), &[("LANG", "C"), ("NO_COLOR", "1")]).await;
        plain.wait_for("Parameters").await;
        let text = plain.text();
        assert!(!text.contains('┌') && !text.contains('│'), "{text}");
        let screen = plain.screen.screen();
        for row in 0..30 {
            for col in 0..100 {
                let cell = screen.cell(row, col).unwrap();
                assert_eq!(cell.fgcolor(), vt100::Color::Default, "({row}, {col})");
            }
        }

        let handle = logged_in(&test.server).await;
        let mut fancy = Explorer::open(&handle, (100, 30), &[("LANG", "en_US.UTF-8")]).await;
        fancy.wait_for("Parameters").await;
        assert!(fancy.text().contains('│'));
    });
}

#[test]
fn saving_in_a_served_session_shows_the_toml_and_writes_nothing() {
    let test = open_server();
    let cwd_before = std::fs::read_dir(".").unwrap().count();
    runtime().block_on(async {
        let handle = logged_in(&test.server).await;
        let mut explorer = Explorer::open(&handle, (120, 40), &[]).await;
        explorer.wait_for("Parameters").await;
        explorer.send(b"s").await;
        explorer.wait_for("nothing is saved on the server").await;
        // The scene's own TOML, as `Scene::to_toml` writes it.
        let scene = beamfric::scene::load("benchmark-1").unwrap().scene;
        let toml = scene.to_toml();
        let first_table = toml.lines().find(|l| l.starts_with('[')).unwrap();
        assert!(explorer.text().contains(first_table), "{}", explorer.text());
        // Any key closes it.
        explorer.send(b"x").await;
        explorer.wait_for("Parameters").await;
    });
    assert_eq!(std::fs::read_dir(".").unwrap().count(), cwd_before);
}

#[test]
fn wrong_password_and_unknown_key_are_rejected() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let known = user_key(7);
    let unknown = user_key(8);
    let authorized = dir.path().join("authorized_keys");
    std::fs::write(&authorized, known.public_key().to_openssh().unwrap() + "\n").unwrap();
    let password = dir.path().join("password");
    std::fs::write(&password, "correct horse\n").unwrap();
    std::fs::set_permissions(&password, std::fs::Permissions::from_mode(0o600)).unwrap();
    let server = Server::start(&ServeOptions {
        authorized_keys: Some(authorized),
        password_file: Some(password),
        open: false,
        ..options(&dir)
    })
    .unwrap();
    runtime().block_on(async {
        let mut handle = connect(&server).await;
        assert!(!handle.authenticate_none("eve").await.unwrap().success());
        let wrong = handle.authenticate_password("eve", "battery staple").await;
        assert!(!wrong.unwrap().success());
        let key = PrivateKeyWithHashAlg::new(Arc::new(unknown), None);
        assert!(
            !handle
                .authenticate_publickey("eve", key)
                .await
                .unwrap()
                .success()
        );
        let right = handle.authenticate_password("ann", "correct horse").await;
        assert!(right.unwrap().success());

        let mut handle = connect(&server).await;
        let key = PrivateKeyWithHashAlg::new(Arc::new(known), None);
        assert!(
            handle
                .authenticate_publickey("bob", key)
                .await
                .unwrap()
                .success()
        );
        let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
        explorer.wait_for("Parameters").await;
    });
}

#[test]
fn exec_subsystem_a_shell_without_pty_and_port_forwarding_are_refused() {
    let test = open_server();
    runtime().block_on(async {
        let handle = logged_in(&test.server).await;
        let mut exec = handle.channel_open_session().await.unwrap();
        exec.exec(true, "cat /etc/passwd").await.unwrap();
        assert!(!succeeded(&mut exec).await, "exec was accepted");

        let handle = logged_in(&test.server).await;
        let mut subsystem = handle.channel_open_session().await.unwrap();
        subsystem.request_subsystem(true, "sftp").await.unwrap();
        assert!(!succeeded(&mut subsystem).await, "subsystem was accepted");

        let handle = logged_in(&test.server).await;
        let mut shell = handle.channel_open_session().await.unwrap();
        shell.request_shell(true).await.unwrap();
        assert!(!succeeded(&mut shell).await, "shell was accepted");

        let handle = logged_in(&test.server).await;
        let forward = handle
            .channel_open_direct_tcpip("127.0.0.1", 22, "127.0.0.1", 5555)
            .await;
        assert!(forward.is_err(), "a direct-tcpip channel was opened");
        assert!(handle.tcpip_forward("127.0.0.1", 0).await.is_err());
    });
    assert_eq!(test.server.sessions(), 0);
}

/// Whether the first reply to a request was a success (data before it skipped).
async fn succeeded(channel: &mut Channel<client::Msg>) -> bool {
    loop {
        let message = tokio::time::timeout(PATIENCE, channel.wait())
            .await
            .expect("a reply")
            .expect("the channel is open");
        match message {
            ChannelMsg::Success => return true,
            ChannelMsg::Failure => return false,
            _ => {}
        }
    }
}

#[test]
fn without_open_or_credentials_the_server_refuses_to_start() {
    let dir = tempfile::tempdir().unwrap();
    let refused = Server::start(&ServeOptions {
        open: false,
        ..options(&dir)
    });
    let message = refused.err().expect("refused");
    assert!(message.contains("--open"), "{message}");

    let output = std::process::Command::new(env!("CARGO_BIN_EXE_beamfric"))
        .args(["serve", "--listen", "127.0.0.1:0", "--host-key"])
        .arg(dir.path().join("host_key"))
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("--open"), "{stderr}");
}

#[test]
fn beyond_the_session_cap_a_client_gets_a_polite_message() {
    let dir = tempfile::tempdir().unwrap();
    let server = Server::start(&ServeOptions {
        max_sessions: 1,
        ..options(&dir)
    })
    .unwrap();
    runtime().block_on(async {
        let first = logged_in(&server).await;
        let mut running = Explorer::open(&first, (100, 30), &[]).await;
        running.wait_for("Parameters").await;
        let second = logged_in(&server).await;
        let mut refused = Explorer::open(&second, (100, 30), &[]).await;
        refused.wait_for("the server is full").await;
        refused.wait_for_close().await;
        assert_eq!(refused.exit_status, Some(1));
    });
}

#[test]
fn forty_concurrent_sessions_each_get_their_first_frame() {
    let test = open_server();
    let server = &test.server;
    runtime().block_on(async {
        let mut tasks = Vec::new();
        for _ in 0..40 {
            let handle = logged_in(server).await;
            tasks.push(tokio::spawn(async move {
                let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
                explorer.wait_for("Parameters").await;
                (handle, explorer)
            }));
        }
        let mut sessions = Vec::new();
        for task in tasks {
            sessions.push(task.await.unwrap());
        }
        assert_eq!(server.sessions(), 40);
        drop(sessions);
    });
    eventually("all 40 sessions end", || server.sessions() == 0);
}

#[test]
fn openssh_reaches_the_explorer() {
    let Ok(ssh) = which("ssh") else {
        println!("skipped: OpenSSH's ssh is not installed");
        return;
    };
    let test = open_server();
    let port = test.server.address().port().to_string();
    let mut child = std::process::Command::new(ssh)
        .args([
            "-tt",
            "-p",
            &port,
            "-o",
            "StrictHostKeyChecking=no",
            "-o",
            "UserKnownHostsFile=/dev/null",
            "-o",
            "BatchMode=yes",
            "-o",
            "LogLevel=ERROR",
            "-F",
            "/dev/null",
            "student@127.0.0.1",
        ])
        .env("TERM", "xterm")
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdout = child.stdout.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut screen = vt100::Parser::new(24, 80, 0);
        let mut buffer = [0u8; 4096];
        let mut seen = false;
        loop {
            match std::io::Read::read(&mut stdout, &mut buffer) {
                Ok(0) | Err(_) => return seen,
                Ok(n) => {
                    screen.process(&buffer[..n]);
                    seen |= screen.screen().contents().contains("Parameters");
                }
            }
        }
    });
    eventually("a session starts", || test.server.sessions() == 1);
    // Give the first frame time to arrive, then quit.
    std::thread::sleep(Duration::from_millis(500));
    use std::io::Write;
    child.stdin.as_mut().unwrap().write_all(b"q").unwrap();
    let status = child.wait().unwrap();
    assert!(reader.join().unwrap(), "OpenSSH showed the explorer");
    assert!(status.success(), "ssh exited with {status}");
}

fn which(program: &str) -> Result<std::path::PathBuf, ()> {
    let path = std::env::var_os("PATH").ok_or(())?;
    std::env::split_paths(&path)
        .map(|dir| dir.join(program))
        .find(|candidate| candidate.is_file())
        .ok_or(())
}

#[test]
fn a_served_session_cannot_ask_for_more_elements_than_the_cap() {
    let dir = tempfile::tempdir().unwrap();
    let server = Server::start(&ServeOptions {
        max_elements: 1000,
        ..options(&dir)
    })
    .unwrap();
    runtime().block_on(async {
        let handle = logged_in(&server).await;
        let mut explorer = Explorer::open(&handle, (120, 40), &[]).await;
        explorer.wait_for("Parameters").await;
        // The last row is the method, the one before it the elements.
        explorer.send(&b"j".repeat(30)).await;
        explorer.send(b"k\r200000\r").await;
        explorer.wait_for("at most 1000 here").await;
    });
}

#[test]
fn an_idle_session_is_closed_with_a_word() {
    let dir = tempfile::tempdir().unwrap();
    let server = Server::start(&ServeOptions {
        idle_timeout: Some(Duration::from_secs(1)),
        ..options(&dir)
    })
    .unwrap();
    runtime().block_on(async {
        let handle = logged_in(&server).await;
        let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
        explorer.wait_for("Parameters").await;
        explorer.wait_for_close().await;
        let raw = String::from_utf8_lossy(&explorer.raw);
        assert!(raw.contains("closed after 1 s without input"), "{raw:?}");
    });
    eventually("the session ends", || server.sessions() == 0);
}

#[test]
fn an_absurd_window_size_is_clamped_and_the_session_goes_on() {
    let test = open_server();
    runtime().block_on(async {
        let handle = logged_in(&test.server).await;
        let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
        explorer.wait_for("Parameters").await;
        explorer
            .channel
            .window_change(60_000, 60_000, 0, 0)
            .await
            .unwrap();
        explorer.resize((100, 30)).await;
        explorer.send(b"?").await;
        explorer.wait_for("change it by a coarse step").await;
    });
}

/// Key-to-frame latency with 40 students, each pressing a key every 200 ms on Benchmark 1
/// (and then with one of them at n = 10⁵): a benchmark, not a test of the suite. Run it with
/// `cargo test --test serve -- --ignored --nocapture`; it prints p50 and p99 over all keys of
/// the first frame after the key and of the last of its frames, and the memory per session
/// (the process's resident size, which includes the 40 clients; in the second run, what the
/// first left to the allocator too).
#[test]
#[ignore]
fn benchmark_forty_sessions_pressing_a_key_every_200_ms() {
    const SESSIONS: usize = 40;
    const KEYS: usize = 40;
    for heavy in [false, true] {
        let test = open_server();
        let before = resident_kib();
        let (mut first, mut last, during) = runtime().block_on(async {
            let mut tasks = Vec::new();
            for index in 0..SESSIONS {
                let handle = logged_in(&test.server).await;
                let heavy_one = heavy && index == 0;
                tasks.push(tokio::spawn(async move {
                    let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
                    explorer.wait_for("Parameters").await;
                    if heavy_one {
                        explorer.send(&b"j".repeat(30)).await;
                        explorer.send(b"k\r100000\r").await;
                        explorer.wait_for("n = 100000").await;
                    }
                    // Stagger the students over the 200 ms period.
                    tokio::time::sleep(Duration::from_millis(5 * index as u64)).await;
                    let mut latencies = Vec::new();
                    for key in 0..KEYS {
                        // Select up and down on the parameter rows (a heavy student steps the
                        // mesh instead: every key re-solves at n = 10⁵ or near it).
                        let bytes: &[u8] = match (heavy_one, key % 2) {
                            (true, 0) => b"h",
                            (true, _) => b"l",
                            (false, 0) => b"l",
                            (false, _) => b"h",
                        };
                        let sent = Instant::now();
                        explorer.send(bytes).await;
                        // The first frame after the key (however late), then the rest of its
                        // frames: whatever follows within 50 ms of the one before.
                        let (mut first, mut last) = (None, None);
                        let mut wait = PATIENCE;
                        while let Ok(Some(message)) =
                            tokio::time::timeout(wait, explorer.channel.wait()).await
                        {
                            if let ChannelMsg::Data { data } = message {
                                explorer.screen.process(&data);
                                first.get_or_insert(sent.elapsed());
                                last = Some(sent.elapsed());
                                wait = Duration::from_millis(50);
                            }
                        }
                        if !heavy_one {
                            latencies.push((first, last));
                        }
                        let next = sent + Duration::from_millis(200);
                        tokio::time::sleep(next.saturating_duration_since(Instant::now())).await;
                    }
                    (handle, latencies)
                }));
            }
            let during = {
                tokio::time::sleep(Duration::from_secs(4)).await;
                resident_kib()
            };
            let (mut first, mut last) = (Vec::new(), Vec::new());
            let mut handles = Vec::new();
            for task in tasks {
                let (handle, latencies) = task.await.unwrap();
                handles.push(handle);
                for (f, l) in latencies {
                    first.push(f.unwrap_or(Duration::MAX));
                    last.push(l.unwrap_or(Duration::MAX));
                }
            }
            (first, last, during)
        });
        let missed = first.iter().filter(|d| **d == Duration::MAX).count();
        let label = if heavy {
            "with one student at n = 1e5"
        } else {
            "all at n = 20"
        };
        println!(
            "{SESSIONS} sessions, {label}: key to first frame p50 {:?} p99 {:?}; to last frame \
             p50 {:?} p99 {:?}, worst {:?}; {missed} of {} keys without a frame; \
             memory {} KiB before, {} KiB during, {} KiB per session",
            percentile(&mut first, 0.5),
            percentile(&mut first, 0.99),
            percentile(&mut last, 0.5),
            percentile(&mut last, 0.99),
            percentile(&mut last, 1.0),
            first.len(),
            before,
            during,
            during.saturating_sub(before) / SESSIONS as u64,
        );
        assert_eq!(missed, 0, "keys without a frame");
    }
}

fn percentile(values: &mut [Duration], p: f64) -> Duration {
    values.sort();
    values[((values.len() - 1) as f64 * p).round() as usize]
}

/// The process's resident memory (VmRSS) in KiB.
fn resident_kib() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|line| line.strip_prefix("VmRSS:"))
        .and_then(|rest| rest.split_whitespace().next()?.parse().ok())
        .unwrap_or(0)
}

#[test]
fn students_follow_the_presenter_live_and_a_fork_stays_their_own() {
    let dir = tempfile::tempdir().unwrap();
    let (presenter_key, student_key) = (user_key(1), user_key(2));
    let presenters = dir.path().join("presenters");
    std::fs::write(
        &presenters,
        presenter_key.public_key().to_openssh().unwrap(),
    )
    .unwrap();
    let students = dir.path().join("students");
    std::fs::write(&students, student_key.public_key().to_openssh().unwrap()).unwrap();
    let server = Server::start(&ServeOptions {
        authorized_keys: Some(students),
        presenter_keys: Some(presenters),
        open: false,
        ..options(&dir)
    })
    .unwrap();
    runtime().block_on(async {
        let lecturer = logged_in_with(&server, presenter_key).await;
        let mut presenter = Explorer::open(&lecturer, (120, 40), &[]).await;
        presenter.wait_for("presenting").await;
        let student = logged_in_with(&server, student_key).await;
        let mut follower = Explorer::open(&student, (120, 40), &[]).await;
        follower.wait_for("following the presenter").await;
        follower.wait_for("load f0 (x=0)  5.0e4").await;
        // The presenter's status line counts the follower at once, without a key.
        presenter.wait_for("1 follow").await;

        // The presenter's change, seen by the follower.
        let sent = Instant::now();
        presenter.send(b"]").await;
        follower.wait_for("load f0 (x=0)  5.0e5").await;
        let seen = sent.elapsed();
        println!("a presenter's change reached the follower in {seen:?}");
        assert!(seen < Duration::from_secs(1), "{seen:?}");
        presenter.wait_for("load f0 (x=0)  5.0e5").await;
        assert_eq!(server.followers(), 1);

        // While following, a change of the student's own is refused.
        follower.send(b"]").await;
        follower.wait_for("f to explore on your own").await;

        // A fork is the student's own: the presenter never sees it.
        follower.send(b"f").await;
        follower.wait_for("own exploration").await;
        presenter.wait_for("0 follow").await;
        follower.send(b"]").await;
        follower.wait_for("load f0 (x=0)  5.0e6").await;
        presenter.send(b"[").await;
        presenter.wait_for("load f0 (x=0)  5.0e4").await;
        assert!(!String::from_utf8_lossy(&presenter.raw).contains("5.0e6"));
        assert!(follower.text().contains("load f0 (x=0)  5.0e6"));

        // F rejoins at the presenter's current state.
        follower.send(b"F").await;
        follower.wait_for("load f0 (x=0)  5.0e4").await;
        follower.wait_for("following the presenter").await;
        assert_eq!(server.followers(), 1);
    });
}

#[test]
fn a_flood_of_input_is_cut_to_the_budget_and_the_session_goes_on() {
    let test = open_server();
    let server = &test.server;
    runtime().block_on(async {
        let handle = logged_in(server).await;
        let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
        explorer.wait_for("Parameters").await;
        // 256 KiB of "select the next row" at once: far beyond 32 KiB per second.
        let flood = 256 * 1024;
        explorer.send(&b"j".repeat(flood)).await;
        eventually("most of the flood is dropped", || {
            server.dropped_input() >= (flood - 2 * 32 * 1024) as u64
        });
        // Once the budget refills, keys work again.
        let deadline = Instant::now() + PATIENCE;
        while !explorer.text().contains("change it by a coarse step") {
            assert!(
                Instant::now() < deadline,
                "the session never answered again"
            );
            explorer.send(b"?").await;
            let _ = tokio::time::timeout(Duration::from_millis(200), async {
                explorer.wait_for("change it by a coarse step").await
            })
            .await;
        }
    });
}

/// Where `needle` starts on the client's screen: (column, row), 0-based.
fn cell_of(screen: &vt100::Screen, needle: &str) -> Option<(u16, u16)> {
    let (_, width) = screen.size();
    screen.rows(0, width).enumerate().find_map(|(y, row)| {
        let at = row.find(needle)?;
        Some((row[..at].chars().count() as u16, y as u16))
    })
}

#[test]
fn served_sessions_take_the_mouse_unless_the_server_says_no_mouse() {
    for mouse in [true, false] {
        let dir = tempfile::tempdir().unwrap();
        let server = Server::start(&ServeOptions {
            mouse,
            ..options(&dir)
        })
        .unwrap();
        runtime().block_on(async {
            let handle = logged_in(&server).await;
            let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
            explorer.wait_for("2.15e11").await;
            let expected = if mouse {
                vt100::MouseProtocolMode::ButtonMotion
            } else {
                vt100::MouseProtocolMode::None
            };
            assert_eq!(explorer.screen.screen().mouse_protocol_mode(), expected);
            // Click the modulus row, then turn the wheel up over it.
            let (x, y) = cell_of(explorer.screen.screen(), "modulus E").unwrap();
            let (x, y) = (x + 3, y + 1);
            explorer
                .send(format!("\x1b[<0;{x};{y}M\x1b[<0;{x};{y}m\x1b[<64;{x};{y}M").as_bytes())
                .await;
            if mouse {
                // One fine step up: 2.15e11 × 10^0.1.
                explorer.wait_for("2.71e11").await;
            } else {
                // Nothing changed by the time a key after it is answered.
                explorer.send(b"x").await;
                explorer.wait_for("no command on 'x'").await;
                assert!(explorer.text().contains("2.15e11"), "{}", explorer.text());
            }
            handle
                .disconnect(russh::Disconnect::ByApplication, "", "en")
                .await
                .unwrap();
        });
    }
}
