//! What the server benches share: the server as its own process (`BEAMFRIC_BIN`, else this
//! build's binary), its memory and threads from `/proc`, and students as russh clients with a
//! pty whose screen a `vt100` parser keeps.
#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};

use russh::client::{self, AuthResult, Handle};
use russh::keys::PublicKeyOrCertificate;
use russh::{Channel, ChannelMsg};

/// A guard against a hung server, not a measurement.
pub const PATIENCE: Duration = Duration::from_secs(60);

pub struct TrustingClient;

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
pub struct ServerProcess {
    pub child: Child,
    pub address: std::net::SocketAddr,
    _dir: tempfile::TempDir,
}

impl ServerProcess {
    pub fn start() -> ServerProcess {
        ServerProcess::start_with(&[])
    }

    /// `beamfric serve --open` on a loopback port with `extra` options.
    pub fn start_with(extra: &[&str]) -> ServerProcess {
        let binary = std::env::var("BEAMFRIC_BIN")
            .unwrap_or_else(|_| env!("CARGO_BIN_EXE_beamfric").to_string());
        let dir = tempfile::tempdir().unwrap();
        let mut child = Command::new(&binary)
            .args(["serve", "--open", "--listen", "127.0.0.1:0", "--host-key"])
            .arg(dir.path().join("host_key"))
            .args(extra)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start {binary}: {e}"));
        // "listening on 127.0.0.1:PORT (host key …)"; the rest of the log is drained (and shown
        // on stderr with BEAMFRIC_SERVER_LOG=1).
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
        let shown = std::env::var_os("BEAMFRIC_SERVER_LOG").is_some();
        std::thread::spawn(move || {
            for line in lines.map_while(Result::ok) {
                if shown {
                    eprintln!("server: {line}");
                }
            }
        });
        ServerProcess {
            child,
            address,
            _dir: dir,
        }
    }

    /// A line of `/proc/PID/status` as a number (`VmRSS` in KiB, `Threads`).
    pub fn status(&self, field: &str) -> u64 {
        process_status(self.child.id(), field)
    }

    pub fn resident_kib(&self) -> u64 {
        self.status("VmRSS")
    }

    /// Waits until the server runs `threads` threads or fewer (its sessions have ended).
    pub fn settle_to(&self, threads: u64) {
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
pub fn process_status(pid: u32, field: &str) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix(field)?.strip_prefix(':'))
        .and_then(|v| v.split_whitespace().next()?.parse().ok())
        .unwrap_or(0)
}

pub async fn logged_in(address: std::net::SocketAddr) -> Handle<TrustingClient> {
    try_logged_in(address)
        .await
        .expect("the server let a student in")
}

/// A student logged in, or `None` when the server closed the connection or refused.
pub async fn try_logged_in(address: std::net::SocketAddr) -> Option<Handle<TrustingClient>> {
    let config = Arc::new(client::Config::default());
    let mut handle = client::connect(config, address, TrustingClient)
        .await
        .ok()?;
    let result = handle.authenticate_none("student").await.ok()?;
    (result == AuthResult::Success).then_some(handle)
}

/// A student's explorer as its client sees it.
pub struct Student {
    pub channel: Channel<client::Msg>,
    pub screen: vt100::Parser,
}

impl Student {
    pub async fn open(handle: &Handle<TrustingClient>) -> Student {
        Student::open_sized(handle, (100, 30)).await
    }

    /// A student whose terminal has `size` (columns, rows).
    pub async fn open_sized(handle: &Handle<TrustingClient>, size: (u16, u16)) -> Student {
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
        channel.request_shell(true).await.unwrap();
        Student {
            channel,
            screen: vt100::Parser::new(size.1, size.0, 0),
        }
    }

    /// Reads until the screen shows `needle`.
    pub async fn wait_for(&mut self, needle: &str) {
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
    pub async fn press(&mut self, key: &[u8]) -> (Option<Duration>, Option<Duration>) {
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

/// User and system time process `pid` has used so far.
pub fn process_cpu(pid: u32) -> Duration {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
    let Some(close) = stat.rfind(')') else {
        return Duration::ZERO;
    };
    let fields: Vec<&str> = stat[close + 1..].split_whitespace().collect();
    let ticks: u64 = fields.get(11).and_then(|t| t.parse().ok()).unwrap_or(0)
        + fields.get(12).and_then(|t| t.parse().ok()).unwrap_or(0);
    // Linux reports clock ticks of 1/100 s (USER_HZ).
    Duration::from_millis(ticks * 10)
}

/// Threads of process `pid` named `name` now.
pub fn threads_named(pid: u32, name: &str) -> usize {
    let Ok(tasks) = std::fs::read_dir(format!("/proc/{pid}/task")) else {
        return 0;
    };
    tasks
        .filter_map(Result::ok)
        .filter(|task| {
            std::fs::read_to_string(task.path().join("comm"))
                .is_ok_and(|comm| comm.trim_end() == name)
        })
        .count()
}

pub fn percentile(values: &mut [Duration], p: f64) -> Duration {
    values.sort();
    values[((values.len() - 1) as f64 * p).round() as usize]
}

pub fn runtime() -> tokio::runtime::Runtime {
    tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .unwrap()
}
