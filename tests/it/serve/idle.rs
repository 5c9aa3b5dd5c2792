//! A session closed for its user (issue 14, stops 58–59): the idle timeout, its warning a
//! minute before (half the timeout, if shorter), and the unsaved changes of a session closed
//! idle or hung up, printed on the client's screen or saved under `--save-dir`.

use std::time::Duration;

use beamfric::serve::{ServeOptions, Server};

use super::options;
use crate::harness::ssh::{Explorer, disconnect, logged_in, runtime};
use crate::harness::wait::eventually;

#[test]
fn an_idle_session_is_closed_with_a_word() {
    let dir = tempfile::tempdir().unwrap();
    let server = Server::start(&ServeOptions {
        idle_timeout: Some(Duration::from_secs(1)),
        ..options(&dir)
    })
    .unwrap();
    runtime().block_on(async {
        let handle = logged_in(server.address()).await;
        let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
        explorer.wait_for("Parameters").await;
        explorer.wait_for_close().await;
        let raw = String::from_utf8_lossy(&explorer.raw);
        assert!(raw.contains("closed after 1 s without input"), "{raw:?}");
    });
    eventually("the session ends", || server.sessions() == 0);
}

#[test]
fn an_idle_session_is_warned_and_a_key_keeps_it() {
    let dir = tempfile::tempdir().unwrap();
    let server = Server::start(&ServeOptions {
        idle_timeout: Some(Duration::from_secs(6)),
        ..options(&dir)
    })
    .unwrap();
    let warning = "idle: this session ends in 3 s without a key";
    runtime().block_on(async {
        let handle = logged_in(server.address()).await;
        let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
        explorer.wait_for("Parameters").await;
        explorer.wait_for(warning).await;
        assert!(!explorer.text().contains("unsaved"), "{}", explorer.text());
        // A key (the selection moves down): the warning goes, and the session stays.
        explorer.send(b"\x1b[B").await;
        let deadline = std::time::Instant::now() + Duration::from_secs(60);
        while explorer.text().contains(warning) {
            assert!(explorer.read_once(deadline).await, "closed after a key");
            assert!(std::time::Instant::now() < deadline, "{}", explorer.text());
        }
        // Idle again from that key: warned again, then closed.
        explorer.wait_for(warning).await;
        explorer.wait_for_close().await;
        let raw = String::from_utf8_lossy(&explorer.raw);
        assert!(raw.contains("closed after 6 s without input"), "{raw:?}");
    });
    eventually("the session ends", || server.sessions() == 0);
}

/// A served session of `server` that changes the scene (→ on the first parameter) and
/// waits until the change shows.
async fn changed_session(
    server: &Server,
) -> (
    russh::client::Handle<crate::harness::ssh::TrustingClient>,
    Explorer,
) {
    changed_session_at(server.address()).await
}

/// [`changed_session`] on the server at `address`.
async fn changed_session_at(
    address: std::net::SocketAddr,
) -> (
    russh::client::Handle<crate::harness::ssh::TrustingClient>,
    Explorer,
) {
    let handle = logged_in(address).await;
    let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
    explorer.wait_for("Parameters").await;
    explorer.send(b"\x1b[C").await;
    explorer.wait_for("[modified]").await;
    (handle, explorer)
}

#[test]
fn a_session_closed_for_its_user_hands_over_their_unsaved_changes() {
    // Stop 58's hostile pass: the idle timeout closed a session with changes, said only
    // "closed after 3 s without input", and the changes were gone.
    let preset = beamfric::scene::load("benchmark-1").unwrap().scene;
    let idle = Some(Duration::from_secs(2));
    // Without a save directory: the scene as TOML on the client's own screen, after the
    // explorer has left it.
    let dir = tempfile::tempdir().unwrap();
    let server = Server::start(&ServeOptions {
        idle_timeout: idle,
        ..options(&dir)
    })
    .unwrap();
    runtime().block_on(async {
        let (_handle, mut explorer) = changed_session(&server).await;
        // Warned half the timeout before (a minute before, for longer ones).
        explorer
            .wait_for("idle: this session ends in 1 s without a key; your unsaved")
            .await;
        explorer.wait_for_close().await;
        let raw = String::from_utf8_lossy(&explorer.raw).into_owned();
        let marker = "the scene as TOML, to copy into a file:\r\n\r\n";
        let at = raw.find(marker).unwrap_or_else(|| panic!("{raw:?}")) + marker.len();
        let text = raw[at..].replace("\r\n", "\n");
        let scene = beamfric::scene::Scene::from_toml(&text, "printed").unwrap();
        assert_ne!(scene, preset, "the change is in what was printed");
        assert_eq!(scene.obstacles, preset.obstacles);
    });
    // With one: saved there, on an idle end and on a hang-up alike.
    let dir = tempfile::tempdir().unwrap();
    let saves = dir.path().join("saves");
    std::fs::create_dir_all(&saves).unwrap();
    let server = Server::start(&ServeOptions {
        idle_timeout: idle,
        save_dir: Some(saves.clone()),
        ..options(&dir)
    })
    .unwrap();
    runtime().block_on(async {
        let (_handle, mut explorer) = changed_session(&server).await;
        explorer.wait_for_close().await;
        let raw = String::from_utf8_lossy(&explorer.raw);
        assert!(raw.contains("your changes are saved as "), "{raw:?}");
        let (handle, _explorer) = changed_session(&server).await;
        disconnect(&handle).await;
    });
    eventually("both sessions' changes are saved", || {
        std::fs::read_dir(&saves).unwrap().count() == 2
    });
    for entry in std::fs::read_dir(&saves).unwrap() {
        let path = entry.unwrap().path();
        let saved = beamfric::scene::load(path.to_str().unwrap()).unwrap().scene;
        assert_ne!(saved, preset, "{}", path.display());
    }
}

/// Stop 60's pass: a session closed idle on another lesson step than the one it changed said
/// "your unsaved changes are kept", then printed nothing: the step's changes were lost. Every
/// changed step is printed as TOML now (and saved, under `--save-dir`: `explorer::class_work`).
#[test]
fn a_session_closed_idle_prints_the_changes_left_on_another_lesson_step() {
    let dir = tempfile::tempdir().unwrap();
    let server = Server::start(&ServeOptions {
        idle_timeout: Some(Duration::from_secs(2)),
        lesson: Some("lessons/regularisation.toml".into()),
        ..options(&dir)
    })
    .unwrap();
    let lesson =
        beamfric::lesson::read_lesson(std::path::Path::new("lessons/regularisation.toml")).unwrap();
    runtime().block_on(async {
        let handle = logged_in(server.address()).await;
        let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
        explorer.wait_for("step 1/7").await;
        explorer.send(b" ").await;
        explorer.wait_for("step 2/7").await;
        explorer.send(b"]").await;
        explorer.wait_for("[modified]").await;
        explorer.send(b" ").await;
        explorer.wait_for("step 3/7").await;
        explorer.wait_for("your unsaved changes are kept").await;
        explorer.wait_for_close().await;
        let raw = String::from_utf8_lossy(&explorer.raw).into_owned();
        let marker = "your changes to lesson step 2 (";
        let at = raw.find(marker).unwrap_or_else(|| panic!("{raw:?}"));
        let toml_at = raw[at..].find("\r\n\r\n").unwrap() + at + 4;
        let text = raw[toml_at..].replace("\r\n", "\n");
        let scene = beamfric::scene::Scene::from_toml(&text, "printed").unwrap();
        let written = &lesson.step(1).scene.scene;
        assert_ne!(
            scene.load, written.load,
            "the change is in what was printed"
        );
        assert_eq!(scene.obstacles, written.obstacles);
    });
}

/// Stop 59's leftover: where the save directory did not take a closed session's work (gone,
/// full), the student got it printed, and the lecturer's log said nothing.
#[test]
fn the_log_says_when_a_closed_sessions_work_missed_the_save_directory() {
    use crate::harness::serve_process::{ServeProcess, port_in};
    let dir = tempfile::tempdir().unwrap();
    let saves = dir.path().join("saves");
    std::fs::create_dir_all(&saves).unwrap();
    let host_key = dir.path().join("host_key");
    let mut server = ServeProcess::start(&[
        "serve",
        "--listen",
        "127.0.0.1:0",
        "--host-key",
        host_key.to_str().unwrap(),
        "--open",
        "--save-dir",
        saves.to_str().unwrap(),
        "--idle-timeout",
        "2",
    ]);
    let port = port_in(&server.wait_for_line("listening on"));
    std::fs::remove_dir_all(&saves).unwrap();
    runtime().block_on(async {
        let (_handle, mut explorer) = changed_session_at(([127, 0, 0, 1], port).into()).await;
        explorer.wait_for_close().await;
        let raw = String::from_utf8_lossy(&explorer.raw);
        assert!(
            raw.contains("the scene as TOML, to copy into a file:"),
            "{raw:?}"
        );
    });
    let line = server.wait_for_line("unsaved changes not saved in the save directory");
    assert!(line.contains("printed on their terminal instead"), "{line}");
}
