//! `beamfric serve`: the explorer over SSH (russh). Every connection that asks for a pty gets
//! its own explorer — the local explorer's state, update, drawing and event loop, on its own
//! threads — sized to the client's window. [`Server::start`] checks the options, prepares the
//! host key and the list of who may log in, binds, and runs the server on a runtime thread of
//! its own; [`serve_until_stopped`] is the command line's way in (`beamfric serve`), and
//! [`present`] runs the server behind the lecturer's own explorer, which presents (`beamfric
//! present`). The solves and sweeps of all sessions share the machine's cores fairly
//! (`crate::tui::runtime::cores`).
//!
//! - `access`: who may log in, the options' ranges, the SSH configuration;
//! - [`admission`]: connections before login, bounded without locking students out;
//! - [`keys`]: host key, authorized keys, password;
//! - [`connection`]: one connection's SSH handler (what is allowed, what is refused);
//! - [`explorer`]: one served explorer and the output path to its client;
//! - [`follow`]: the presenter's state handed to the students who follow;
//! - `present`: the lecturer's own explorer in front of the server, the join screen's words
//!   and the end of the class;
//! - [`limits`]: the cap on sessions and the input budget.

mod access;
pub mod admission;
pub mod connection;
mod error;
pub mod explorer;
pub mod follow;
pub mod keys;
pub mod limits;
pub mod memory;
mod present;

use std::collections::VecDeque;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::sync::oneshot;

use crate::tui::runtime::cores::Cores;
use crate::tui::runtime::remote::Feed;
use access::{Access, access, check_ranges, russh_config};
pub use access::{MAX_IDLE_TIMEOUT, MAX_SESSIONS_LIMIT};
pub use error::ServeError;
use explorer::ExplorerSettings;
use limits::SessionSlots;
pub use present::present;

/// Default listening address: loopback only.
pub const DEFAULT_LISTEN: &str = "127.0.0.1:2222";
/// Default cap on explorers running at once.
pub const DEFAULT_MAX_SESSIONS: usize = 64;
/// Default cap on a served session's elements.
pub const DEFAULT_MAX_ELEMENTS: usize = 100_000;
/// Default idle timeout.
pub const DEFAULT_IDLE_TIMEOUT: Duration = Duration::from_secs(30 * 60);
/// Logged-in connections allowed per allowed explorer, beyond which new connections are
/// dropped at once (those waiting to log in are bounded by [`admission`]).
const CONNECTIONS_PER_SESSION: usize = 4;
/// How long a stopping server gives its explorers to leave their clients' screens.
const STOP_GRACE: Duration = Duration::from_secs(1);
/// Log lines kept while the lecturer's explorer has the terminal (`present`), the newest.
const KEPT_LOG_LINES: usize = 10_000;

/// What `beamfric serve` was asked for.
#[derive(Debug, Clone)]
pub struct ServeOptions {
    pub listen: String,
    /// `None`: [`keys::default_host_key_path`].
    pub host_key: Option<PathBuf>,
    pub authorized_keys: Option<PathBuf>,
    /// Keys whose sessions present (follow mode); they may log in too.
    pub presenter_keys: Option<PathBuf>,
    pub password_file: Option<PathBuf>,
    /// Anyone may log in (only when neither keys nor a password are given).
    pub open: bool,
    pub max_sessions: usize,
    /// The server's memory budget in MiB: the session cap is derived from it too
    /// ([`memory::plan`]).
    pub memory_budget_mib: usize,
    pub max_elements: usize,
    /// `None`: sessions never time out.
    pub idle_timeout: Option<Duration>,
    /// The scene every session starts with (a preset name or the lecturer's file).
    pub scene: String,
    /// A lesson (`--lesson`): its first step's scene replaces `scene`; the presenter steps
    /// through it, and sessions without a presenter step on their own.
    pub lesson: Option<PathBuf>,
    /// Sessions ask the client's terminal for mouse reports (`--no-mouse`: they do not).
    pub mouse: bool,
    /// Every session draws in ASCII (`--ascii`), whatever its client's locale.
    pub ascii: bool,
    /// Sessions may use colours (`--no-color`: none, whatever the client sends).
    pub color: bool,
    /// The sessions' colours at start (`--theme`; `T` cycles them).
    pub palette: crate::plot::Palette,
    /// The sessions' chart markers at start (`--marker`; `M` cycles them).
    pub markers: crate::plot::MarkerSet,
    /// The only directory served sessions may save to; `None`: `s` shows the TOML to copy.
    pub save_dir: Option<PathBuf>,
}

impl Default for ServeOptions {
    fn default() -> ServeOptions {
        ServeOptions {
            listen: DEFAULT_LISTEN.into(),
            host_key: None,
            authorized_keys: None,
            presenter_keys: None,
            password_file: None,
            open: false,
            max_sessions: DEFAULT_MAX_SESSIONS,
            memory_budget_mib: memory::DEFAULT_MEMORY_BUDGET_MIB,
            max_elements: DEFAULT_MAX_ELEMENTS,
            idle_timeout: Some(DEFAULT_IDLE_TIMEOUT),
            scene: "benchmark-1".into(),
            lesson: None,
            mouse: true,
            ascii: false,
            color: true,
            palette: crate::plot::Palette::default(),
            markers: crate::plot::MarkerSet::default(),
            save_dir: None,
        }
    }
}

/// What every connection shares.
#[derive(Debug)]
pub(crate) struct Shared {
    pub access: Access,
    pub explorer: ExplorerSettings,
    pub slots: Arc<SessionSlots>,
    /// How the memory budget is shared out (and whether it sets the session cap).
    pub memory: memory::MemoryPlan,
    /// Connections open, logged in or not.
    pub connections: AtomicUsize,
    /// Connections waiting to log in.
    pub admission: admission::Admission,
    /// Input bytes dropped over the budget, all sessions together.
    pub dropped_input: AtomicU64,
    /// Follow mode, when there are presenter keys or the lecturer presents (`present`).
    pub hub: Option<follow::Hub>,
    /// The solves and sweeps of all sessions share these cores.
    pub cores: Arc<Cores>,
    /// Every running explorer's feed, to end them when the server stops.
    pub explorers: Mutex<Vec<(u64, Feed)>>,
    pub next_explorer: AtomicU64,
    /// Where log lines go.
    pub log: Log,
}

/// Where the server's log lines go: stderr, or kept in memory while the lecturer's explorer
/// draws on the terminal (`present`), to be printed when it ends.
#[derive(Debug)]
pub(crate) enum Log {
    Stderr,
    Kept(Mutex<VecDeque<String>>),
}

impl Shared {
    /// One log line (never a password: no caller has one to give).
    pub fn log(&self, line: &str) {
        match &self.log {
            Log::Stderr => log(line),
            Log::Kept(lines) => {
                let mut lines = lock(lines);
                if lines.len() >= KEPT_LOG_LINES {
                    lines.pop_front();
                }
                lines.push_back(line.to_string());
            }
        }
    }
}

fn lock<T>(mutex: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(|e| e.into_inner())
}

/// Counts a connection while it lives.
#[derive(Debug)]
pub(crate) struct ConnectionCount(Arc<Shared>);

impl ConnectionCount {
    fn new(shared: &Arc<Shared>) -> ConnectionCount {
        shared.connections.fetch_add(1, Ordering::AcqRel);
        ConnectionCount(Arc::clone(shared))
    }
}

impl Drop for ConnectionCount {
    fn drop(&mut self) {
        self.0.connections.fetch_sub(1, Ordering::AcqRel);
    }
}

/// A line on the server's stderr (a closed stderr is no reason to panic).
pub(crate) fn log(line: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "beamfric serve: {line}");
}

/// A running server; it stops when dropped.
pub struct Server {
    address: SocketAddr,
    fingerprint: String,
    notes: Vec<String>,
    shared: Arc<Shared>,
    stop: Option<oneshot::Sender<()>>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Server {
    /// Checks the options, loads or creates the host key, binds, and starts serving.
    pub fn start(options: &ServeOptions) -> Result<Server, ServeError> {
        Server::start_as(options, false)
    }

    /// As [`Server::start`]; with `presenting`, there is always a follow hub (the lecturer's
    /// own explorer presents) and log lines are kept in memory (see [`present`]).
    fn start_as(options: &ServeOptions, presenting: bool) -> Result<Server, ServeError> {
        check_ranges(options)?;
        let access = access(options)?;
        let mut notes = Vec::new();
        if access.open {
            notes.push(format!(
                "warning: --open: anyone who can reach {} may log in",
                options.listen
            ));
        }
        let (scene, lesson) = match &options.lesson {
            Some(path) => {
                let place = crate::tui::state::LessonPlace {
                    lesson: Arc::new(crate::lesson::read_lesson(path)?),
                    step: 0,
                };
                (place.current().scene.clone(), Some(place))
            }
            None => (crate::scene::load(&options.scene)?, None),
        };
        if scene.scene.mesh.elements > options.max_elements {
            let what = match &options.lesson {
                Some(path) => format!(
                    "{}: step 1: elements = {}",
                    crate::format::printable(&path.display().to_string()),
                    scene.scene.mesh.elements
                ),
                None => format!("the scene has {} elements", scene.scene.mesh.elements),
            };
            return Err(ServeError::Option(format!(
                "{what}: more than --max-elements {} (every session starts there; a later step \
                 beyond it is shown at the limit)",
                options.max_elements
            )));
        }
        let cores = Cores::of_this_machine();
        let memory = memory::plan(
            options.memory_budget_mib,
            options.max_sessions,
            options.max_elements,
            cores.limit(),
        )
        .map_err(ServeError::Option)?;
        notes.push(memory.describe());
        let save_dir = match &options.save_dir {
            Some(dir) => Some(save_directory(dir)?),
            None => None,
        };
        let cannot_listen = |source| ServeError::Listen {
            address: options.listen.clone(),
            source,
        };
        let listener = std::net::TcpListener::bind(&options.listen).map_err(cannot_listen)?;
        let address = listener.local_addr().map_err(cannot_listen)?;
        listener.set_nonblocking(true).map_err(cannot_listen)?;
        let shared = Arc::new(Shared {
            access,
            explorer: ExplorerSettings {
                scene,
                lesson,
                max_elements: options.max_elements,
                idle_timeout: options.idle_timeout,
                mouse: options.mouse,
                ascii: options.ascii,
                color: options.color,
                palette: options.palette,
                markers: options.markers,
                save_dir,
            },
            slots: SessionSlots::new(memory.sessions),
            memory,
            connections: AtomicUsize::new(0),
            admission: admission::Admission::default(),
            dropped_input: AtomicU64::new(0),
            hub: (presenting || options.presenter_keys.is_some()).then(follow::Hub::default),
            cores,
            explorers: Mutex::default(),
            next_explorer: AtomicU64::new(0),
            log: if presenting {
                Log::Kept(Mutex::default())
            } else {
                Log::Stderr
            },
        });
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            .thread_name("serve")
            .enable_all()
            .build()
            .map_err(|e| ServeError::Start(format!("cannot start the server's runtime: {e}")))?;
        // Written only now that everything else is ready: a failed start leaves no key behind.
        let key_path = options
            .host_key
            .clone()
            .unwrap_or_else(keys::default_host_key_path);
        let (host_key, created) = keys::load_or_create_host_key(&key_path)?;
        let fingerprint = keys::fingerprint(host_key.public_key());
        if created {
            notes.push(format!("created the host key {}", key_path.display()));
        }
        let config = russh_config(options, &shared.access, host_key);
        let (stop, stopped) = oneshot::channel();
        let accepting = Arc::clone(&shared);
        let thread = std::thread::Builder::new()
            .name("serve".into())
            .spawn(move || {
                runtime.block_on(accept_loop(listener, config, accepting, stopped));
                // Dropping the runtime ends every connection; their explorers hang up.
                runtime.shutdown_timeout(Duration::from_secs(1));
            })
            .map_err(|e| ServeError::Start(format!("cannot start the server thread: {e}")))?;
        Ok(Server {
            address,
            fingerprint,
            notes,
            shared,
            stop: Some(stop),
            thread: Some(thread),
        })
    }

    /// The address it listens on (the port chosen when asked for port 0).
    pub fn address(&self) -> SocketAddr {
        self.address
    }

    /// The host key's fingerprint (`SHA256:…`).
    pub fn fingerprint(&self) -> &str {
        &self.fingerprint
    }

    /// Warnings and news for the lecturer (e.g. `--open`, a new host key).
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// How the memory budget is shared out: the session cap it sets, the bounds it assumes.
    pub fn memory(&self) -> memory::MemoryPlan {
        self.shared.memory
    }

    /// Explorers running now (a disconnected one counts until its thread has ended).
    pub fn sessions(&self) -> usize {
        self.shared.slots.running()
    }

    /// Students following a presenter now.
    pub fn followers(&self) -> usize {
        self.shared
            .hub
            .as_ref()
            .map_or(0, |hub| hub.followers.count())
    }

    /// The most solves and sweeps that ever ran at once (at most the machine's cores).
    pub fn peak_parallel_work(&self) -> usize {
        self.shared.cores.queue().peak
    }

    /// Input bytes dropped so far because a client typed faster than
    /// [`limits::INPUT_BYTES_PER_SECOND`].
    pub fn dropped_input(&self) -> u64 {
        self.shared.dropped_input.load(Ordering::Acquire)
    }

    /// Connections open now, logged in or not.
    pub fn connections(&self) -> usize {
        self.shared.connections.load(Ordering::Acquire)
    }

    /// Connections waiting to log in now.
    pub fn waiting_to_log_in(&self) -> usize {
        self.shared.admission.waiting()
    }

    /// Serves until the process ends.
    pub fn wait(mut self) {
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

impl Server {
    /// Ends every explorer (each leaves its client's screen and closes its channel) and
    /// waits for that up to [`STOP_GRACE`].
    fn end_explorers(&self) {
        for (_, feed) in lock(&self.shared.explorers).iter() {
            feed.hangup();
        }
        let deadline = std::time::Instant::now() + STOP_GRACE;
        while self.shared.slots.running() > 0 && std::time::Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.end_explorers();
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// `beamfric serve`: start, say where and with which host key, serve.
pub fn serve_until_stopped(options: &ServeOptions) -> Result<(), ServeError> {
    let server = Server::start(options)?;
    for note in server.notes() {
        log(note);
    }
    log(&format!(
        "listening on {} (host key {}); students connect with: ssh -p {} HOST",
        server.address(),
        server.fingerprint(),
        server.address().port()
    ));
    server.wait();
    Ok(())
}

/// The `--save-dir` directory, resolved; it must exist and be a directory.
fn save_directory(dir: &std::path::Path) -> Result<PathBuf, ServeError> {
    let resolved = dir
        .canonicalize()
        .map_err(|e| ServeError::Option(format!("--save-dir {}: {e}", dir.display())))?;
    if !resolved.is_dir() {
        return Err(ServeError::Option(format!(
            "--save-dir {}: not a directory",
            dir.display()
        )));
    }
    Ok(resolved)
}

async fn accept_loop(
    listener: std::net::TcpListener,
    config: Arc<russh::server::Config>,
    shared: Arc<Shared>,
    mut stopped: oneshot::Receiver<()>,
) {
    let listener = match tokio::net::TcpListener::from_std(listener) {
        Ok(listener) => listener,
        Err(e) => {
            shared.log(&format!("cannot listen: {e}"));
            return;
        }
    };
    let max_connections = shared.slots.max().saturating_mul(CONNECTIONS_PER_SESSION);
    loop {
        let accepted = tokio::select! {
            _ = &mut stopped => return,
            accepted = listener.accept() => accepted,
        };
        let (socket, peer) = match accepted {
            Ok(accepted) => accepted,
            Err(e) => {
                // Out of file descriptors and the like: wait a little rather than spin.
                shared.log(&format!("accept failed: {e}"));
                tokio::time::sleep(Duration::from_millis(100)).await;
                continue;
            }
        };
        let logged_in = shared
            .connections
            .load(Ordering::Acquire)
            .saturating_sub(shared.admission.waiting());
        if logged_in >= max_connections {
            shared.log(&format!(
                "connection from {peer} dropped: too many connections"
            ));
            continue;
        }
        let _ = socket.set_nodelay(true);
        let gate = shared.admission.admit();
        let handler =
            connection::Connection::new(Arc::clone(&shared), Some(peer), Arc::clone(&gate));
        let config = Arc::clone(&config);
        tokio::spawn(serve_connection(config, socket, handler, gate));
    }
}

/// One connection, until it ends; before login, ended by its gate (dropped for a newcomer or
/// past its grace).
async fn serve_connection(
    config: Arc<russh::server::Config>,
    socket: tokio::net::TcpStream,
    handler: connection::Connection,
    gate: Arc<admission::Gate>,
) {
    let ended = gate.ended_before_login();
    tokio::pin!(ended);
    let running = tokio::select! {
        started = russh::server::run_stream(config, socket, handler) => match started {
            Ok(running) => running,
            Err(_) => return,
        },
        // The socket and the handler are dropped here: the connection closes.
        () = &mut ended => return,
    };
    let handle = running.handle();
    tokio::select! {
        _ = running => {}
        () = &mut ended => {
            let leaving = handle.disconnect(
                russh::Disconnect::ByApplication,
                "not logged in in time".into(),
                String::new(),
            );
            let _ = tokio::time::timeout(Duration::from_secs(1), leaving).await;
        }
    }
}
