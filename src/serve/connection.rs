//! One SSH connection (a russh `Handler`): authentication, then one session channel with a
//! pty, whose shell request starts that connection's own explorer. Everything else — exec,
//! subsystems, X11, agent and port forwarding, a shell without a pty — is refused. When the
//! connection ends, its explorer hears a hangup and one log line goes to stderr (address, user,
//! key fingerprint, duration; never a password).

use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Instant;

use russh::keys::PublicKey;
use russh::server::{Auth, ChannelOpenHandle, Handler, Msg, Session};
use russh::{Channel, ChannelId, ChannelOpenFailure, Pty};

use super::Shared;
use super::admission::Gate;
use super::explorer::{self, ACCEPTED_ENV, ClientTerminal, ENV_COUNT_LIMIT, ENV_VALUE_LIMIT};
use super::keys::{fingerprint, same_secret};
use super::limits::{INPUT_BYTES_PER_SECOND, InputBudget, WINDOW_CHANGE_BYTES};
use crate::tui::runtime::remote::Feed;

/// Said to a client that asks for a shell without a terminal, or for a command.
const EXPLORER_ONLY: &str = "beamfric serve offers the explorer only, in a terminal: connect with plain `ssh -p PORT HOST` (or `ssh -t`).\r\n";

/// The state of one connection.
pub struct Connection {
    shared: Arc<Shared>,
    peer: Option<SocketAddr>,
    started: Instant,
    user: Option<String>,
    /// The fingerprint of the key the user logged in with.
    key: Option<String>,
    /// Logged in with a presenter key.
    presenter: bool,
    /// The session channel (one per connection).
    channel: Option<ChannelId>,
    /// The pty asked for, and the environment sent so far.
    terminal: ClientTerminal,
    has_pty: bool,
    /// The running explorer, once the shell request started it.
    feed: Option<Feed>,
    budget: InputBudget,
    /// A window change the budget has not let through yet.
    resize_waiting: bool,
    /// Its place before login.
    gate: Arc<Gate>,
    _counted: super::ConnectionCount,
}

impl Connection {
    pub(super) fn new(
        shared: Arc<Shared>,
        peer: Option<SocketAddr>,
        gate: Arc<Gate>,
    ) -> Connection {
        let counted = super::ConnectionCount::new(&shared);
        Connection {
            shared,
            peer,
            started: Instant::now(),
            user: None,
            key: None,
            presenter: false,
            channel: None,
            terminal: ClientTerminal::default(),
            has_pty: false,
            feed: None,
            budget: InputBudget::new(INPUT_BYTES_PER_SECOND),
            resize_waiting: false,
            gate,
            _counted: counted,
        }
    }

    fn accepted(&mut self, user: &str, key: Option<&PublicKey>) -> Auth {
        self.user = Some(shown_user(user));
        self.key = key.map(fingerprint);
        self.shared.admission.logged_in(&self.gate);
        Auth::Accept
    }

    /// A login request arrived: the handshake is done.
    fn logging_in(&self) {
        self.shared.admission.logging_in(&self.gate);
    }

    fn key_allowed(&self, key: &PublicKey) -> bool {
        let access = &self.shared.access;
        access.open
            || access
                .keys
                .iter()
                .chain(&access.presenter_keys)
                .any(|k| k.key_data() == key.key_data())
    }

    fn is_presenter_key(&self, key: &PublicKey) -> bool {
        let access = &self.shared.access;
        access
            .presenter_keys
            .iter()
            .any(|k| k.key_data() == key.key_data())
    }

    /// Hands the newest window size to the explorer, if one is waiting.
    fn pass_resize(&mut self) {
        if let (true, Some(feed)) = (self.resize_waiting, &self.feed) {
            feed.resize(self.terminal.width, self.terminal.height);
            self.resize_waiting = false;
        }
    }

    fn is_ours(&self, channel: ChannelId) -> bool {
        self.channel == Some(channel)
    }

    /// Refuses a request on `channel`, with a word to the client on stderr.
    fn refuse(&self, channel: ChannelId, session: &mut Session) -> Result<(), russh::Error> {
        let _ = session.extended_data(channel, 1, EXPLORER_ONLY.as_bytes().to_vec());
        session.channel_failure(channel)
    }
}

impl Handler for Connection {
    type Error = russh::Error;

    async fn auth_none(&mut self, user: &str) -> Result<Auth, Self::Error> {
        self.logging_in();
        let access = &self.shared.access;
        Ok(if access.open && access.presenter_keys.is_empty() {
            self.accepted(user, None)
        } else {
            Auth::reject()
        })
    }

    /// An open server with presenters: a student without a key is let in without a question.
    async fn auth_keyboard_interactive<'a>(
        &'a mut self,
        user: &str,
        _submethods: &str,
        _response: Option<russh::server::Response<'a>>,
    ) -> Result<Auth, Self::Error> {
        self.logging_in();
        Ok(if self.shared.access.open {
            self.accepted(user, None)
        } else {
            Auth::reject()
        })
    }

    async fn auth_password(&mut self, user: &str, password: &str) -> Result<Auth, Self::Error> {
        self.logging_in();
        let access = &self.shared.access;
        let right = access.open
            || access
                .password
                .as_deref()
                .is_some_and(|expected| same_secret(password, expected));
        Ok(if right {
            self.accepted(user, None)
        } else {
            Auth::reject()
        })
    }

    async fn auth_publickey_offered(
        &mut self,
        _user: &str,
        key: &PublicKey,
    ) -> Result<Auth, Self::Error> {
        self.logging_in();
        Ok(if self.key_allowed(key) {
            Auth::Accept
        } else {
            Auth::reject()
        })
    }

    async fn auth_publickey(&mut self, user: &str, key: &PublicKey) -> Result<Auth, Self::Error> {
        self.logging_in();
        Ok(if self.key_allowed(key) {
            self.presenter = self.is_presenter_key(key);
            self.accepted(user, Some(key))
        } else {
            Auth::reject()
        })
    }

    async fn channel_open_session(
        &mut self,
        channel: Channel<Msg>,
        reply: ChannelOpenHandle,
        _session: &mut Session,
    ) -> Result<(), Self::Error> {
        if self.channel.is_some() {
            reply
                .reject(ChannelOpenFailure::AdministrativelyProhibited)
                .await;
        } else {
            // Requests and data arrive through this handler; the channel object is not read.
            self.channel = Some(channel.id());
            reply.accept().await;
        }
        Ok(())
    }

    async fn channel_open_direct_tcpip(
        &mut self,
        _channel: Channel<Msg>,
        _host: &str,
        _port: u32,
        _originator: &str,
        _originator_port: u32,
        reply: ChannelOpenHandle,
        _session: &mut Session,
    ) -> Result<(), Self::Error> {
        reply
            .reject(ChannelOpenFailure::AdministrativelyProhibited)
            .await;
        Ok(())
    }

    async fn tcpip_forward(
        &mut self,
        _address: &str,
        _port: &mut u32,
        _session: &mut Session,
    ) -> Result<bool, Self::Error> {
        Ok(false)
    }

    async fn agent_request(
        &mut self,
        channel: ChannelId,
        session: &mut Session,
    ) -> Result<bool, Self::Error> {
        // russh answers a refusal with a global REQUEST_FAILURE, which a client waiting on its
        // channel never sees: say it on the channel too.
        session.channel_failure(channel)?;
        Ok(false)
    }

    async fn pty_request(
        &mut self,
        channel: ChannelId,
        term: &str,
        width: u32,
        height: u32,
        _pix_width: u32,
        _pix_height: u32,
        _modes: &[(Pty, u32)],
        session: &mut Session,
    ) -> Result<(), Self::Error> {
        if !self.is_ours(channel) || self.feed.is_some() {
            return session.channel_failure(channel);
        }
        self.has_pty = true;
        self.terminal.term = term.chars().take(ENV_VALUE_LIMIT).collect();
        self.terminal.width = width;
        self.terminal.height = height;
        session.channel_success(channel)
    }

    async fn env_request(
        &mut self,
        channel: ChannelId,
        name: &str,
        value: &str,
        session: &mut Session,
    ) -> Result<(), Self::Error> {
        let wanted = ACCEPTED_ENV.contains(&name)
            && value.len() <= ENV_VALUE_LIMIT
            && self.terminal.env.len() < ENV_COUNT_LIMIT;
        if !self.is_ours(channel) || self.feed.is_some() || !wanted {
            return session.channel_failure(channel);
        }
        self.terminal.env.push((name.into(), value.into()));
        session.channel_success(channel)
    }

    async fn shell_request(
        &mut self,
        channel: ChannelId,
        session: &mut Session,
    ) -> Result<(), Self::Error> {
        if !self.is_ours(channel) || self.feed.is_some() {
            return session.channel_failure(channel);
        }
        if !self.has_pty {
            self.refuse(channel, session)?;
            return session.close(channel);
        }
        let Some(slot) = self.shared.slots.take() else {
            session.channel_success(channel)?;
            let message = full_message(&self.shared);
            session.data(channel, message.into_bytes())?;
            session.exit_status_request(channel, 1)?;
            session.eof(channel)?;
            return session.close(channel);
        };
        let handle = session.handle();
        match explorer::start(
            &self.shared,
            self.presenter,
            slot,
            handle,
            channel,
            (&self.terminal, self.user.as_deref()),
        ) {
            Ok(feed) => {
                self.feed = Some(feed);
                session.channel_success(channel)
            }
            Err(message) => {
                let _ = session.extended_data(channel, 1, format!("beamfric: {message}\r\n"));
                session.channel_failure(channel)?;
                session.close(channel)
            }
        }
    }

    async fn exec_request(
        &mut self,
        channel: ChannelId,
        _command: &[u8],
        session: &mut Session,
    ) -> Result<(), Self::Error> {
        self.refuse(channel, session)
    }

    async fn subsystem_request(
        &mut self,
        channel: ChannelId,
        _name: &str,
        session: &mut Session,
    ) -> Result<(), Self::Error> {
        session.channel_failure(channel)
    }

    async fn x11_request(
        &mut self,
        channel: ChannelId,
        _single_connection: bool,
        _protocol: &str,
        _cookie: &str,
        _screen: u32,
        session: &mut Session,
    ) -> Result<(), Self::Error> {
        session.channel_failure(channel)
    }

    async fn window_change_request(
        &mut self,
        channel: ChannelId,
        width: u32,
        height: u32,
        _pix_width: u32,
        _pix_height: u32,
        _session: &mut Session,
    ) -> Result<(), Self::Error> {
        if self.is_ours(channel) {
            self.terminal.width = width;
            self.terminal.height = height;
            // A window change costs the input budget like a short key sequence; one beyond it
            // is kept and applied with the next input the budget lets through. However many
            // pass, the explorer applies only the newest, once per frame.
            self.resize_waiting = true;
            if self.budget.take(WINDOW_CHANGE_BYTES) > 0 {
                self.pass_resize();
            }
        }
        Ok(())
    }

    async fn data(
        &mut self,
        channel: ChannelId,
        data: &[u8],
        _session: &mut Session,
    ) -> Result<(), Self::Error> {
        if let (true, Some(feed)) = (self.is_ours(channel), &self.feed) {
            let allowed = self.budget.take(data.len());
            if allowed > 0 {
                feed.bytes(&data[..allowed]);
                self.pass_resize();
            }
            let dropped = (data.len() - allowed) as u64;
            self.shared
                .dropped_input
                .fetch_add(dropped, std::sync::atomic::Ordering::Relaxed);
        }
        Ok(())
    }

    async fn channel_eof(
        &mut self,
        channel: ChannelId,
        _session: &mut Session,
    ) -> Result<(), Self::Error> {
        if let (true, Some(feed)) = (self.is_ours(channel), &self.feed) {
            feed.hangup();
        }
        Ok(())
    }

    async fn channel_close(
        &mut self,
        channel: ChannelId,
        _session: &mut Session,
    ) -> Result<(), Self::Error> {
        if let (true, Some(feed)) = (self.is_ours(channel), self.feed.take()) {
            feed.hangup();
        }
        Ok(())
    }
}

impl Drop for Connection {
    fn drop(&mut self) {
        if let Some(feed) = self.feed.take() {
            feed.hangup();
        }
        self.shared.admission.left(&self.gate);
        let peer = self
            .peer
            .map_or_else(|| "unknown address".to_string(), |p| p.to_string());
        let user = self.user.as_deref().unwrap_or("- (not authenticated)");
        let key = self.key.as_deref().unwrap_or("-");
        self.shared.log(&format!(
            "connection from {peer} user {user} key {key} lasted {:.1} s",
            self.started.elapsed().as_secs_f64()
        ));
    }
}

/// What a student beyond the session cap reads: which limit it is, and what to do.
fn full_message(shared: &Shared) -> String {
    let running = shared.slots.max();
    if shared.memory.limited_by_budget {
        format!(
            "beamfric: the server is full: {running} explorers use its memory budget of {} MiB; \
             please try again in a moment.\r\n",
            shared.memory.budget >> 20
        )
    } else {
        format!(
            "beamfric: the server is full ({running} explorers running); please try again in a \
             moment.\r\n"
        )
    }
}

/// A user name as the log and the lecturer's list show it: at most 64 characters; letters
/// (any script), digits, ASCII punctuation and spaces as they are, anything else — control
/// and format characters that could move the cursor or turn text around — escaped (`\u{1b}`);
/// an empty name as `(no name)`.
fn shown_user(user: &str) -> String {
    if user.is_empty() {
        return "(no name)".into();
    }
    user.chars()
        .take(64)
        .flat_map(|c| {
            let kept = c.is_alphanumeric() || c.is_ascii_punctuation() || c == ' ';
            let escaped: Vec<char> = if kept {
                vec![c]
            } else {
                c.escape_default().collect()
            };
            escaped
        })
        .collect()
}

#[cfg(test)]
mod user_name_tests {
    use super::shown_user;

    #[test]
    fn user_names_keep_their_letters_and_lose_what_moves_the_cursor() {
        assert_eq!(shown_user("José"), "José");
        assert_eq!(shown_user("漢字"), "漢字");
        assert_eq!(shown_user("a\u{1b}[2J"), "a\\u{1b}[2J");
        assert_eq!(shown_user("evil\u{202e}txt"), "evil\\u{202e}txt");
        assert_eq!(shown_user(""), "(no name)");
        assert_eq!(shown_user(&"x".repeat(100)).len(), 64);
    }
}
