//! `beamfric serve` (issue 14) through real SSH: each test starts the server on an ephemeral
//! loopback port with a temporary host key, connects with russh's client (and once with
//! OpenSSH's `ssh` where installed), asks for a pty, and reads the screen through the `vt100`
//! terminal emulator.
//!
//! Here: a session's screen, keys, saves, limits and ending; who may connect in `access`; the
//! idle timeout and the work of a session closed for its user in `idle`; the lecture
//! (`present`, followers) in `lecture`; who leads a class with `--presenter-keys` in
//! `presenters`.

#![cfg(unix)]

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use beamfric::serve::{ServeError, ServeOptions, Server};
use russh::keys::{PrivateKey, PrivateKeyWithHashAlg};

use crate::harness::cpu;
use crate::harness::lecture::{past_the_join_screen, present};
use crate::harness::pty::{ENTER_ALTERNATE, LEAVE_ALTERNATE, PtyProcess, SHOW_CURSOR};
use crate::harness::screen::{find, rows, sgr};
use crate::harness::serve_process::{ServeProcess, port_in};
use crate::harness::ssh::{
    Explorer, connect, disconnect, logged_in, logged_in_as, logged_in_with, runtime, succeeded,
    user_key,
};
use crate::harness::wait::{deadline, eventually, until};

mod access;
mod idle;
mod lecture;
mod presenters;

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

/// A file of `keys`' public halves, one per line (`--authorized-keys`, `--presenter-keys`).
fn keys_file(dir: &tempfile::TempDir, name: &str, keys: &[&PrivateKey]) -> std::path::PathBuf {
    let path = dir.path().join(name);
    let lines: Vec<String> = keys
        .iter()
        .map(|key| key.public_key().to_openssh().unwrap())
        .collect();
    std::fs::write(&path, lines.join("\n")).unwrap();
    path
}

/// `user` logged in with `key`, and its explorer at 120×40.
async fn session_of(
    address: std::net::SocketAddr,
    user: &str,
    key: PrivateKey,
) -> (
    russh::client::Handle<crate::harness::ssh::TrustingClient>,
    Explorer,
) {
    let handle = logged_in_with(address, user, key).await;
    let explorer = Explorer::open(&handle, (120, 40), &[]).await;
    (handle, explorer)
}

fn open_server() -> TestServer {
    let dir = tempfile::tempdir().unwrap();
    let server = Server::start(&options(&dir)).unwrap();
    TestServer { server, _dir: dir }
}

#[test]
fn a_session_shows_the_explorer_follows_keys_and_resizes_and_ends_on_disconnect() {
    let test = open_server();
    let server = &test.server;
    runtime().block_on(async {
        let handle = logged_in(server.address()).await;
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

        disconnect(&handle).await;
    });
    // The session, its workers and its output are gone.
    eventually("the session ends after a disconnect", || {
        server.sessions() == 0
    });
    eventually("the connection is gone", || server.connections() == 0);
}

#[test]
fn q_quits_and_closes_the_channel_with_status_zero() {
    let test = open_server();
    runtime().block_on(async {
        let handle = logged_in(test.server.address()).await;
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
fn a_served_session_asks_for_bracketed_paste_and_never_runs_a_paste() {
    // A hostile pass (stop 58): served sessions did not ask the client's terminal for
    // bracketed paste, so a student's paste arrived as keys and its `s` opened the save prompt.
    let test = open_server();
    runtime().block_on(async {
        let handle = logged_in(test.server.address()).await;
        let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
        explorer.wait_for("Parameters").await;
        let raw = String::from_utf8_lossy(&explorer.raw).into_owned();
        let asked = raw.find("\x1b[?2004h").expect("bracketed paste asked for");
        let first_frame = raw.find("Parameters").unwrap();
        assert!(asked < first_frame, "{raw:?}");
        // What the client's terminal then sends for a paste of commands: noted, not run.
        explorer
            .send(b"\x1b[200~see section 5.2 and eq (40)\rdq\x1b[201~")
            .await;
        explorer
            .wait_for("a paste is typed only into a prompt")
            .await;
        let text = explorer.text();
        assert!(!text.contains("save the scene to"), "{text}");
        assert!(!text.contains("[modified]"), "{text}");
        explorer.send(b"q").await;
        explorer.wait_for_close().await;
        assert_eq!(explorer.exit_status, Some(0));
        // And it is asked to stop again on the way out.
        let raw = String::from_utf8_lossy(&explorer.raw);
        assert!(
            raw.rfind("\x1b[?2004l") > raw.rfind("\x1b[?2004h"),
            "{raw:?}"
        );
    });
    eventually("the session ends", || test.server.sessions() == 0);
}

/// A 100×30 session drawn in ASCII (no box drawing) and without colours.
fn assert_plain(explorer: &Explorer) {
    let text = explorer.text();
    assert!(!text.contains('┌') && !text.contains('│'), "{text}");
    let screen = explorer.screen.screen();
    for row in 0..30 {
        for col in 0..100 {
            let cell = screen.cell(row, col).unwrap();
            assert_eq!(cell.fgcolor(), vt100::Color::Default, "({row}, {col})");
        }
    }
}

#[test]
fn ascii_and_no_color_follow_the_clients_environment() {
    let test = open_server();
    runtime().block_on(async {
        let handle = logged_in(test.server.address()).await;
        let mut plain =
            Explorer::open(&handle, (100, 30), &[("LANG", "C"), ("NO_COLOR", "1")]).await;
        plain.wait_for("Parameters").await;
        assert_plain(&plain);

        let handle = logged_in(test.server.address()).await;
        let mut fancy = Explorer::open(&handle, (100, 30), &[("LANG", "en_US.UTF-8")]).await;
        fancy.wait_for("Parameters").await;
        assert!(fancy.text().contains('│'));
    });
    // Issue 23 item 7: the server's --ascii and --no-color hold for every session, whatever
    // its client sends.
    let dir = tempfile::tempdir().unwrap();
    let server = Server::start(&ServeOptions {
        ascii: true,
        color: false,
        ..options(&dir)
    })
    .unwrap();
    runtime().block_on(async {
        let handle = logged_in(server.address()).await;
        let mut plain = Explorer::open(&handle, (100, 30), &[("LANG", "en_US.UTF-8")]).await;
        plain.wait_for("Parameters").await;
        assert_plain(&plain);
    });
}

/// The line after the scene's text that `s` writes outside the explorer.
const CLOSING_TEXT: &str = "\r\n\r\n(beamfric: the scene as TOML above";

/// The scene's text `explorer` was last shown by `s`, once `count` of them have come since
/// byte `from` of its output.
async fn text_shown(explorer: &mut Explorer, from: usize, count: usize) -> String {
    let deadline = deadline();
    loop {
        let raw = String::from_utf8_lossy(&explorer.raw[from..]).into_owned();
        if raw.matches(CLOSING_TEXT).count() >= count {
            let end = raw.rfind(CLOSING_TEXT).unwrap();
            let at = raw[..end].rfind(LEAVE_ALTERNATE).unwrap() + LEAVE_ALTERNATE.len();
            let text = raw[at..end]
                .strip_prefix(SHOW_CURSOR)
                .unwrap_or(&raw[at..end]);
            return text.strip_prefix("\r\n").unwrap().replace("\r\n", "\n");
        }
        assert!(Instant::now() < deadline, "{raw:?}");
        assert!(explorer.read_once(deadline).await, "closed: {raw:?}");
    }
}

#[test]
fn saving_in_a_served_session_shows_the_toml_and_writes_nothing() {
    // Stop 59's lecture pass: the TOML was drawn in the explorer's screen, cut at its width
    // and height (eight-obstacles at 80×24: 22 of its lines, the description cut without its
    // closing quote). It is now written on the client's own screen, whole, to select there.
    let dir = tempfile::tempdir().unwrap();
    let server = Server::start(&ServeOptions {
        scene: "eight-obstacles".into(),
        ..options(&dir)
    })
    .unwrap();
    let cwd_before = std::fs::read_dir(".").unwrap().count();
    runtime().block_on(async {
        let handle = logged_in(server.address()).await;
        let mut explorer = Explorer::open(&handle, (80, 24), &[]).await;
        explorer.wait_for("Parameters").await;
        let before = explorer.raw.len();
        explorer.send(b"s").await;
        let text = text_shown(&mut explorer, before, 1).await;
        // The scene's own TOML, whole: it reads back as the scene shown.
        let scene = beamfric::scene::Scene::from_toml(&text, "copied").unwrap();
        let preset = beamfric::scene::load("eight-obstacles").unwrap().scene;
        assert_eq!(scene, preset);
        assert!(text.lines().count() > 24 && text.lines().any(|l| l.chars().count() > 80));
        // A window change meanwhile does not clear the text; any key brings the explorer back.
        explorer.resize((100, 30)).await;
        explorer.send(b"x").await;
        explorer.wait_for("Parameters").await;
        let raw = String::from_utf8_lossy(&explorer.raw[before..]).into_owned();
        let end = raw.find(CLOSING_TEXT).unwrap();
        let back = raw.find(ENTER_ALTERNATE).unwrap();
        // Nothing written over it (a clear, a frame) before the explorer's screen is back.
        assert!(!raw[end..back].contains('\x1b'), "{:?}", &raw[end..back]);
        // Keys in one burst close it, change the load and open it again before a frame: the
        // text shown is the changed scene's, not the one on screen before.
        let before = explorer.raw.len();
        explorer.send(b"s").await;
        text_shown(&mut explorer, before, 1).await;
        explorer.send(b"x\x1b[Cs").await;
        let text = text_shown(&mut explorer, before, 2).await;
        let scene = beamfric::scene::Scene::from_toml(&text, "copied").unwrap();
        assert!(scene.load.f0 > preset.load.f0, "{text}");
    });
    assert_eq!(std::fs::read_dir(".").unwrap().count(), cwd_before);
}

#[test]
fn an_absurd_window_size_is_clamped_and_the_session_goes_on() {
    let test = open_server();
    runtime().block_on(async {
        let handle = logged_in(test.server.address()).await;
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

#[test]
fn a_flood_of_input_is_cut_to_the_budget_and_the_session_goes_on() {
    let test = open_server();
    let server = &test.server;
    runtime().block_on(async {
        let handle = logged_in(server.address()).await;
        let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
        explorer.wait_for("Parameters").await;
        // 256 KiB of "select the next row" at once: far beyond 32 KiB per second.
        let flood = 256 * 1024;
        explorer.send(&b"j".repeat(flood)).await;
        eventually("most of the flood is dropped", || {
            server.dropped_input() >= (flood - 2 * 32 * 1024) as u64
        });
        // Once the budget refills, keys work again: "?" until the help is shown (a key typed
        // while the budget is empty is dropped, so it is typed again if not answered soon).
        let deadline = deadline();
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
            let handle = logged_in(server.address()).await;
            let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
            explorer.wait_for("2.15e11").await;
            let expected = if mouse {
                vt100::MouseProtocolMode::ButtonMotion
            } else {
                vt100::MouseProtocolMode::None
            };
            assert_eq!(explorer.screen.screen().mouse_protocol_mode(), expected);
            // Click the modulus row, then turn the wheel up over it.
            let (x, y) = find(&rows(explorer.screen.screen()), "modulus E").unwrap();
            let at = (x + 2, y);
            explorer
                .send(&[sgr(0, at, true), sgr(0, at, false), sgr(64, at, true)].concat())
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
            disconnect(&handle).await;
        });
    }
}
/// Types a file name into the save prompt (after clearing what it proposes) and saves.
async fn save_as(explorer: &mut Explorer, name: &str) {
    explorer.send(b"s").await;
    explorer.wait_for("save the scene to").await;
    explorer.send(&b"\x7f".repeat(400)).await;
    explorer.send(name.as_bytes()).await;
    explorer.send(b"\r").await;
}

#[test]
fn with_a_save_dir_sessions_save_there_and_file_names_cannot_leave_it() {
    let dir = tempfile::tempdir().unwrap();
    let saves = dir.path().join("saves");
    let outside = dir.path().join("outside");
    std::fs::create_dir_all(&saves).unwrap();
    std::fs::create_dir_all(&outside).unwrap();
    // Ways out that a student might try: a link to a directory outside, and a link to a file.
    std::os::unix::fs::symlink(&outside, saves.join("escape")).unwrap();
    std::os::unix::fs::symlink(outside.join("target.toml"), saves.join("link.toml")).unwrap();
    let server = Server::start(&ServeOptions {
        save_dir: Some(saves.clone()),
        ..options(&dir)
    })
    .unwrap();
    let absolute = outside.join("absolute.toml").display().to_string();
    runtime().block_on(async {
        let handle = logged_in(server.address()).await;
        let mut explorer = Explorer::open(&handle, (160, 40), &[]).await;
        explorer.wait_for("Parameters").await;
        for escape in [
            "../outside/up.toml",
            "escape/through-link.toml",
            "link.toml",
            absolute.as_str(),
            "/etc/beamfric.toml",
        ] {
            save_as(&mut explorer, escape).await;
            explorer.wait_for("not saved").await;
            let text = explorer.text();
            assert!(
                text.contains("is outside") || text.contains("exists: overwrite"),
                "{escape}: {text}"
            );
            if text.contains("exists: overwrite") {
                // The link's name exists: even a yes must not follow it out.
                explorer.send(b"y").await;
                explorer.wait_for("is outside").await;
            }
            // Stop 59's lecture pass: the refusal named the server's own directory.
            let text = explorer.text();
            assert!(text.contains("the class's save directory"), "{text}");
            assert!(!text.contains(saves.to_str().unwrap()), "{text}");
        }
        // A plain name is saved in the directory, as a scene that loads back.
        explorer.send(b"l").await;
        save_as(&mut explorer, "mine.toml").await;
        explorer.wait_for("saved to mine.toml").await;
    });
    assert_eq!(
        std::fs::read_dir(&outside).unwrap().count(),
        0,
        "something was written outside the save directory"
    );
    let saved = beamfric::scene::load(saves.join("mine.toml").to_str().unwrap()).unwrap();
    let preset = beamfric::scene::load("benchmark-1").unwrap();
    assert_ne!(saved.scene, preset.scene, "the change was saved");
    assert_eq!(saved.scene.obstacles, preset.scene.obstacles);
}

#[test]
fn a_save_dir_that_does_not_exist_is_refused_at_start() {
    let dir = tempfile::tempdir().unwrap();
    let refused = Server::start(&ServeOptions {
        save_dir: Some(dir.path().join("missing")),
        ..options(&dir)
    });
    let error = refused.err().expect("refused");
    assert!(matches!(error, ServeError::Option(_)), "{error:?}");
    let message = error.to_string();
    assert!(message.contains("--save-dir"), "{message}");
}

/// A session whose worker is inside `dual-inverse`'s explicit inverse (N = 3998, seconds of
/// work in faer, which once ran on for seconds after a hang-up) is freed after a disconnect,
/// and its solver thread ends after at most a fraction of a second more work: the inverse runs
/// in steps that ask for cancellation (`linalg::faer_stepwise`).
#[test]
fn a_disconnect_during_the_dense_inverse_frees_the_session_and_stops_the_solve() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("dense.toml");
    let text = beamfric::scene::load("benchmark-1")
        .unwrap()
        .scene
        .to_toml()
        .replace("elements = 20", "elements = 2000")
        .replace("method = \"dual\"", "method = \"dual-inverse\"");
    assert!(
        text.contains("dual-inverse") && text.contains("2000"),
        "{text}"
    );
    std::fs::write(&scene, text).unwrap();
    // The workers of explorers are threads named "solver"; this server's is one not there yet.
    let others = cpu::threads_named("solver");
    let server = Server::start(&ServeOptions {
        scene: scene.display().to_string(),
        ..options(&dir)
    })
    .unwrap();
    let (solver, at_hang_up) = runtime().block_on(async {
        let handle = logged_in(server.address()).await;
        let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
        explorer.wait_for("solving n = 2000").await;
        // Well inside the inverse: the worker has spent 300 ms of CPU on it.
        let solver = until(
            "the session's solver works for 300 ms of CPU",
            || {
                cpu::threads_named("solver")
                    .into_iter()
                    .filter(|tid| !others.contains(tid))
                    .find(|&tid| {
                        cpu::thread_time(tid).is_some_and(|t| t >= Duration::from_millis(300))
                    })
            },
            || format!("solver threads: {:?}", cpu::threads_named("solver")),
        );
        let at_hang_up = cpu::thread_time(solver).unwrap_or_default();
        disconnect(&handle).await;
        (solver, at_hang_up)
    });
    eventually("the session ends", || server.sessions() == 0);
    // The solver's CPU time until its thread is gone.
    let mut last = at_hang_up;
    eventually("the solver thread ends", || {
        match cpu::thread_time(solver) {
            Some(t) => {
                last = t;
                false
            }
            None => true,
        }
    });
    let after = last.saturating_sub(at_hang_up);
    assert!(
        after < Duration::from_millis(500),
        "the solve worked {after:?} of CPU after the hang-up"
    );
}
