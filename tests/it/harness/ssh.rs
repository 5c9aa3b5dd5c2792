//! The SSH side of `beamfric serve`: a russh client that trusts the server's key, logins, and
//! a served explorer as the client sees it (its channel's bytes fed to a `vt100` emulator).

use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Instant;

use russh::client::{self, AuthResult, Handle};
use russh::keys::ssh_key::private::Ed25519Keypair;
use russh::keys::{PrivateKey, PrivateKeyWithHashAlg, PublicKeyOrCertificate};
use russh::{Channel, ChannelMsg};

use super::wait::{PATIENCE, deadline};

/// The client accepts the server's key (a fresh one per test).
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

/// The Ed25519 key made from `seed` (the same seed, the same key).
pub fn user_key(seed: u8) -> PrivateKey {
    PrivateKey::from(Ed25519Keypair::from_seed(&[seed; 32]))
}

/// A runtime for the clients of one test.
pub fn runtime() -> tokio::runtime::Runtime {
    tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .unwrap()
}

/// Connected to `address`, not logged in.
pub async fn connect(address: SocketAddr) -> Handle<TrustingClient> {
    let config = Arc::new(client::Config::default());
    client::connect(config, address, TrustingClient)
        .await
        .unwrap()
}

/// Connected and logged in as `student` with "none" (an `--open` server).
pub async fn logged_in(address: SocketAddr) -> Handle<TrustingClient> {
    logged_in_as(address, "student").await
}

/// Connected and logged in as `user` without credentials (an `--open` server).
pub async fn logged_in_as(address: SocketAddr, user: &str) -> Handle<TrustingClient> {
    let mut handle = connect(address).await;
    let result = handle.authenticate_none(user).await.unwrap();
    assert_eq!(result, AuthResult::Success);
    handle
}

/// Connected and logged in as `user` with `key`.
pub async fn logged_in_with(
    address: SocketAddr,
    user: &str,
    key: PrivateKey,
) -> Handle<TrustingClient> {
    let mut handle = connect(address).await;
    let key = PrivateKeyWithHashAlg::new(Arc::new(key), None);
    let result = handle.authenticate_publickey(user, key).await.unwrap();
    assert_eq!(result, AuthResult::Success);
    handle
}

/// Whether the first reply to a request was a success (data before it skipped).
pub async fn succeeded(channel: &mut Channel<client::Msg>) -> bool {
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

/// A served explorer as the client sees it.
pub struct Explorer {
    pub channel: Channel<client::Msg>,
    pub screen: vt100::Parser,
    /// Everything received, raw.
    pub raw: Vec<u8>,
    pub closed: bool,
    pub exit_status: Option<u32>,
}

impl Explorer {
    /// Opens a session channel with a pty of `size` (columns, rows), sends `env`, and asks for
    /// a shell: the explorer.
    pub async fn open(
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

    /// The screen as the client's terminal shows it now.
    pub fn text(&self) -> String {
        self.screen.screen().contents()
    }

    /// Reads until the screen shows `needle` (fails after [`PATIENCE`]).
    pub async fn wait_for(&mut self, needle: &str) {
        let deadline = deadline();
        while !self.text().contains(needle) {
            assert!(
                Instant::now() < deadline,
                "{needle:?} never shown; screen:\n{}",
                self.text()
            );
            assert!(
                self.read_once(deadline).await,
                "the channel ended before {needle:?} was shown; screen:\n{}",
                self.text()
            );
        }
    }

    /// Reads until the channel closes (fails after [`PATIENCE`]).
    pub async fn wait_for_close(&mut self) {
        let deadline = deadline();
        while self.read_once(deadline).await {
            assert!(
                Instant::now() < deadline,
                "the channel never closed; screen:\n{}",
                self.text()
            );
        }
    }

    /// One message, or nothing by `deadline`; false once the channel is closed.
    pub async fn read_once(&mut self, deadline: Instant) -> bool {
        if self.closed {
            return false;
        }
        let left = deadline.saturating_duration_since(Instant::now());
        let Ok(message) = tokio::time::timeout(left, self.channel.wait()).await else {
            // The caller says what it waited for.
            return true;
        };
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

    pub async fn send(&self, bytes: &[u8]) {
        self.channel.data_bytes(bytes.to_vec()).await.unwrap();
    }

    /// The client's window changes to `size` (columns, rows).
    pub async fn resize(&mut self, size: (u16, u16)) {
        self.screen.screen_mut().set_size(size.1, size.0);
        self.channel
            .window_change(size.0.into(), size.1.into(), 0, 0)
            .await
            .unwrap();
    }
}

/// Ends the connection the way a client that goes away does.
pub async fn disconnect(handle: &Handle<TrustingClient>) {
    handle
        .disconnect(russh::Disconnect::ByApplication, "", "en")
        .await
        .unwrap();
}
