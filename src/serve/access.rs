//! Who may log in and how (`--authorized-keys`, `--presenter-keys`, `--password-file`,
//! `--open`), the ranges of the server's numeric options, and the SSH configuration that
//! follows from them.

use std::sync::Arc;
use std::time::Duration;

use russh::MethodKind;
use russh::keys::PublicKey;

use super::memory::MAX_MEMORY_BUDGET_MIB;
use super::{DEFAULT_IDLE_TIMEOUT, ServeError, ServeOptions, keys};

/// Who may log in.
#[derive(Debug)]
pub(crate) struct Access {
    pub open: bool,
    pub keys: Vec<PublicKey>,
    pub presenter_keys: Vec<PublicKey>,
    pub password: Option<String>,
}

/// Who may log in, from the options; refuses an open server unless `--open` says so.
pub(super) fn access(options: &ServeOptions) -> Result<Access, ServeError> {
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
    let students_limited = !keys.is_empty() || password.is_some();
    if options.open && students_limited {
        return Err(ServeError::Option(
            "--open lets anyone log in: it cannot go with --authorized-keys or --password-file, \
             which say who may; give one or the other"
                .into(),
        ));
    }
    if !options.open && !students_limited && presenter_keys.is_empty() {
        return Err(ServeError::Option(
            "no --authorized-keys or --password-file: anyone could log in; give one, or --open \
             to allow that"
                .into(),
        ));
    }
    if !options.open && !students_limited {
        return Err(ServeError::Option(
            "--presenter-keys alone lets only the presenters in: give --authorized-keys or \
             --password-file for the students, or --open to let them in without a password"
                .into(),
        ));
    }
    Ok(Access {
        open: options.open,
        keys,
        presenter_keys,
        password,
    })
}

/// The longest idle timeout accepted: a week (0 means none).
pub const MAX_IDLE_TIMEOUT: Duration = Duration::from_secs(7 * 24 * 3600);
/// The most sessions a server may be asked for.
pub const MAX_SESSIONS_LIMIT: usize = 4096;

/// The numeric options within their ranges, each named with the rule it broke.
pub(super) fn check_ranges(options: &ServeOptions) -> Result<(), ServeError> {
    if !(1..=MAX_SESSIONS_LIMIT).contains(&options.max_sessions) {
        return Err(ServeError::Option(format!(
            "--max-sessions {}: must be from 1 to {MAX_SESSIONS_LIMIT}",
            options.max_sessions
        )));
    }
    if !(1..=MAX_MEMORY_BUDGET_MIB).contains(&options.memory_budget_mib) {
        return Err(ServeError::Option(format!(
            "--memory-budget {}: must be from 1 to {MAX_MEMORY_BUDGET_MIB} MiB",
            options.memory_budget_mib
        )));
    }
    if options.max_elements == 0 {
        return Err(ServeError::Option(
            "--max-elements 0: must be at least 1".into(),
        ));
    }
    if let Some(idle) = options.idle_timeout
        && idle > MAX_IDLE_TIMEOUT
    {
        return Err(ServeError::Option(format!(
            "--idle-timeout {}: at most {} s (a week); 0 means never",
            idle.as_secs(),
            MAX_IDLE_TIMEOUT.as_secs()
        )));
    }
    Ok(())
}

pub(super) fn russh_config(
    options: &ServeOptions,
    access: &Access,
    host_key: russh::keys::PrivateKey,
) -> Arc<russh::server::Config> {
    let mut methods = Vec::new();
    // An open server with presenters does not take `none`: a client would be in as a
    // student before it offered the presenter's key. Keyboard-interactive with no question
    // lets students without a key in as quietly.
    if access.open && access.presenter_keys.is_empty() {
        methods.push(MethodKind::None);
    }
    if access.open || !access.keys.is_empty() || !access.presenter_keys.is_empty() {
        methods.push(MethodKind::PublicKey);
    }
    if access.open {
        methods.push(MethodKind::KeyboardInteractive);
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
