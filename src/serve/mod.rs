//! `beamfric serve`: the explorer over SSH (russh). Every connection that asks for a pty gets
//! its own explorer — the local explorer's state, update, drawing and event loop, on its own
//! threads — sized to the client's window. [`Server::start`] checks the options, prepares the
//! host key and the list of who may log in, binds, and runs the server on a runtime thread of
//! its own; [`run`] is the command line's way in.
//!
//! - [`keys`]: host key, authorized keys, password;
//! - [`connection`]: one connection's SSH handler (what is allowed, what is refused);
//! - [`explorer`]: one served explorer and the output path to its client;
//! - [`follow`]: the presenter's state handed to the students who follow;
//! - [`limits`]: the cap on sessions and the input budget.

pub mod connection;
pub mod explorer;
pub mod follow;
pub mod keys;
pub mod limits;

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::time::Duration;

use russh::MethodKind;
use russh::keys::PublicKey;
use tokio::sync::oneshot;

use explorer::ExplorerSettings;
use limits::SessionSlots;

/// Default listening address: loopback only.
pub const DEFAULT_LISTEN: &str = "127.0.0.1:2222";
/// Default cap on explorers running at once.
pub const DEFAULT_MAX_SESSIONS: usize = 64;
/// Default cap on a served session's elements.
pub const DEFAULT_MAX_ELEMENTS: usize = 100_000;
/// Default idle timeout.
pub const DEFAULT_IDLE_TIMEOUT: Duration = Duration::from_secs(30 * 60);
/// Connections (logged in or not) allowed per allowed explorer, beyond which new ones are
/// dropped at once.
const CONNECTIONS_PER_SESSION: usize = 4;

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
    pub max_elements: usize,
    /// `None`: sessions never time out.
    pub idle_timeout: Option<Duration>,
    /// The scene every session starts with (a preset name or the lecturer's file).
    pub scene: String,
    /// Sessions ask the client's terminal for mouse reports (`--no-mouse`: they do not).
    pub mouse: bool,
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
            max_elements: DEFAULT_MAX_ELEMENTS,
            idle_timeout: Some(DEFAULT_IDLE_TIMEOUT),
            scene: "benchmark-1".into(),
            mouse: true,
        }
    }
}

/// Who may log in.
#[derive(Debug)]
pub(crate) struct Access {
    pub open: bool,
    pub keys: Vec<PublicKey>,
    pub presenter_keys: Vec<PublicKey>,
    pub password: Option<String>,
}

/// What every connection shares.
#[derive(Debug)]
pub(crate) struct Shared {
    pub access: Access,
    pub explorer: ExplorerSettings,
    pub slots: Arc<SessionSlots>,
    pub connections: AtomicUsize,
    /// Input bytes dropped over the budget, all sessions together.
    pub dropped_input: AtomicU64,
    /// Follow mode, when there are presenter keys.
    pub hub: Option<follow::Hub>,
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
    pub fn start(options: &ServeOptions) -> Result<Server, String> {
        let access = access(options)?;
        let mut notes = Vec::new();
        if access.open {
            notes.push(format!(
                "warning: --open: anyone who can reach {} may log in",
                options.listen
            ));
        }
        let scene = crate::scene::load(&options.scene).map_err(|e| e.to_string())?;
        if scene.scene.mesh.elements > options.max_elements {
            return Err(format!(
                "the scene has {} elements, more than --max-elements {}",
                scene.scene.mesh.elements, options.max_elements
            ));
        }
        if options.max_sessions == 0 {
            return Err("--max-sessions must be at least 1".into());
        }
        let key_path = options
            .host_key
            .clone()
            .unwrap_or_else(keys::default_host_key_path);
        let (host_key, created) = keys::load_or_create_host_key(&key_path)?;
        let fingerprint = keys::fingerprint(host_key.public_key());
        if created {
            notes.push(format!("created the host key {}", key_path.display()));
        }
        let config = russh_config(options, &access, host_key);
        let listener = std::net::TcpListener::bind(&options.listen)
            .map_err(|e| format!("cannot listen on {}: {e}", options.listen))?;
        let address = listener.local_addr().map_err(|e| e.to_string())?;
        listener.set_nonblocking(true).map_err(|e| e.to_string())?;
        let shared = Arc::new(Shared {
            access,
            explorer: ExplorerSettings {
                scene,
                max_elements: options.max_elements,
                idle_timeout: options.idle_timeout,
                mouse: options.mouse,
            },
            slots: SessionSlots::new(options.max_sessions),
            connections: AtomicUsize::new(0),
            dropped_input: AtomicU64::new(0),
            hub: options.presenter_keys.is_some().then(follow::Hub::default),
        });
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            .thread_name("serve")
            .enable_all()
            .build()
            .map_err(|e| format!("cannot start the server's runtime: {e}"))?;
        let (stop, stopped) = oneshot::channel();
        let accepting = Arc::clone(&shared);
        let thread = std::thread::Builder::new()
            .name("serve".into())
            .spawn(move || {
                runtime.block_on(accept_loop(listener, config, accepting, stopped));
                // Dropping the runtime ends every connection; their explorers hang up.
                runtime.shutdown_timeout(Duration::from_secs(1));
            })
            .map_err(|e| format!("cannot start the server thread: {e}"))?;
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

    /// Input bytes dropped so far because a client typed faster than
    /// [`limits::INPUT_BYTES_PER_SECOND`].
    pub fn dropped_input(&self) -> u64 {
        self.shared.dropped_input.load(Ordering::Acquire)
    }

    /// Connections open now, logged in or not.
    pub fn connections(&self) -> usize {
        self.shared.connections.load(Ordering::Acquire)
    }

    /// Serves until the process ends.
    pub fn wait(mut self) {
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// `beamfric serve`: start, say where and with which host key, serve.
pub fn run(options: &ServeOptions) -> Result<(), String> {
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

/// Who may log in, from the options; refuses an open server unless `--open` says so.
fn access(options: &ServeOptions) -> Result<Access, String> {
    let keys = match &options.authorized_keys {
        Some(path) => keys::read_authorized_keys(path)?,
        None => Vec::new(),
    };
    let presenter_keys = match &options.presenter_keys {
        Some(path) => keys::read_authorized_keys(path)?,
        None => Vec::new(),
    };
    let password = match &options.password_file {
        Some(path) => Some(keys::read_password(path)?),
        None => None,
    };
    let anyone = keys.is_empty() && presenter_keys.is_empty() && password.is_none();
    if anyone && !options.open {
        return Err(
            "no --authorized-keys or --password-file: anyone could log in; give one, or --open \
             to allow that"
                .into(),
        );
    }
    Ok(Access {
        open: anyone,
        keys,
        presenter_keys,
        password,
    })
}

fn russh_config(
    options: &ServeOptions,
    access: &Access,
    host_key: russh::keys::PrivateKey,
) -> Arc<russh::server::Config> {
    let mut methods = Vec::new();
    if access.open {
        methods.push(MethodKind::None);
    }
    if access.open || !access.keys.is_empty() || !access.presenter_keys.is_empty() {
        methods.push(MethodKind::PublicKey);
    }
    if access.open || access.password.is_some() {
        methods.push(MethodKind::Password);
    }
    Arc::new(russh::server::Config {
        methods: methods.as_slice().into(),
        keys: vec![host_key],
        auth_rejection_time: Duration::from_millis(500),
        auth_rejection_time_initial: Some(Duration::ZERO),
        // The explorer's own idle timeout ends a session politely; this only collects
        // connections that never get that far.
        inactivity_timeout: Some(
            options
                .idle_timeout
                .unwrap_or(DEFAULT_IDLE_TIMEOUT)
                .saturating_add(Duration::from_secs(60)),
        ),
        // A client that vanished without a word (a closed laptop) is noticed within a minute.
        keepalive_interval: Some(Duration::from_secs(15)),
        keepalive_max: 3,
        max_auth_attempts: 6,
        nodelay: true,
        ..Default::default()
    })
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
            log(&format!("cannot listen: {e}"));
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
                log(&format!("accept failed: {e}"));
                tokio::time::sleep(Duration::from_millis(100)).await;
                continue;
            }
        };
        if shared.connections.load(Ordering::Acquire) >= max_connections {
            log(&format!(
                "connection from {peer} dropped: too many connections"
            ));
            continue;
        }
        let _ = socket.set_nodelay(true);
        let handler = connection::Connection::new(Arc::clone(&shared), Some(peer));
        let config = Arc::clone(&config);
        tokio::spawn(async move {
            if let Ok(session) = russh::server::run_stream(config, socket, handler).await {
                let _ = session.await;
            }
        });
    }
}
