//! `beamfric serve` (issue 14) through real SSH: each test starts the server on an ephemeral
//! loopback port with a temporary host key, connects with russh's client (and once with
//! OpenSSH's `ssh` where installed), asks for a pty, and reads the screen through the `vt100`
//! terminal emulator.

#![cfg(unix)]

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use beamfric::serve::{ServeError, ServeOptions, Server};
use russh::keys::{PrivateKey, PrivateKeyWithHashAlg};

use crate::harness::cpu;
use crate::harness::lecture::{past_the_join_screen, present};
use crate::harness::pty::{LEAVE_ALTERNATE, PtyProcess};
use crate::harness::screen::{find, rows, sgr};
use crate::harness::serve_process::{ServeProcess, port_in};
use crate::harness::ssh::{
    Explorer, connect, disconnect, logged_in, logged_in_as, logged_in_with, runtime, succeeded,
    user_key,
};
use crate::harness::wait::{deadline, eventually, until};

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

#[test]
fn saving_in_a_served_session_shows_the_toml_and_writes_nothing() {
    let test = open_server();
    let cwd_before = std::fs::read_dir(".").unwrap().count();
    runtime().block_on(async {
        let handle = logged_in(test.server.address()).await;
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
        let mut handle = connect(server.address()).await;
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

        let mut handle = connect(server.address()).await;
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
        let handle = logged_in(test.server.address()).await;
        let mut exec = handle.channel_open_session().await.unwrap();
        exec.exec(true, "cat /etc/passwd").await.unwrap();
        assert!(!succeeded(&mut exec).await, "exec was accepted");

        let handle = logged_in(test.server.address()).await;
        let mut subsystem = handle.channel_open_session().await.unwrap();
        subsystem.request_subsystem(true, "sftp").await.unwrap();
        assert!(!succeeded(&mut subsystem).await, "subsystem was accepted");

        let handle = logged_in(test.server.address()).await;
        let mut shell = handle.channel_open_session().await.unwrap();
        shell.request_shell(true).await.unwrap();
        assert!(!succeeded(&mut shell).await, "shell was accepted");

        let handle = logged_in(test.server.address()).await;
        let mut agent = handle.channel_open_session().await.unwrap();
        agent.agent_forward(true).await.unwrap();
        assert!(
            !succeeded(&mut agent).await,
            "agent forwarding was accepted"
        );
        // One session channel per connection: a second one is refused as well.
        assert!(handle.channel_open_session().await.is_err());
        let handle = logged_in(test.server.address()).await;
        let mut x11 = handle.channel_open_session().await.unwrap();
        x11.request_x11(true, false, "MIT-MAGIC-COOKIE-1", "00", 0)
            .await
            .unwrap();
        assert!(!succeeded(&mut x11).await, "X11 forwarding was accepted");

        let handle = logged_in(test.server.address()).await;
        let forward = handle
            .channel_open_direct_tcpip("127.0.0.1", 22, "127.0.0.1", 5555)
            .await;
        assert!(forward.is_err(), "a direct-tcpip channel was opened");
        assert!(handle.tcpip_forward("127.0.0.1", 0).await.is_err());
        assert!(
            handle
                .streamlocal_forward("/tmp/beamfric.sock")
                .await
                .is_err()
        );
        let unix = handle
            .channel_open_direct_streamlocal("/var/run/docker.sock")
            .await;
        assert!(unix.is_err(), "a direct-streamlocal channel was opened");
    });
    assert_eq!(test.server.sessions(), 0);
}

#[test]
fn without_open_or_credentials_the_server_refuses_to_start() {
    let dir = tempfile::tempdir().unwrap();
    let refused = Server::start(&ServeOptions {
        open: false,
        ..options(&dir)
    });
    let error = refused.err().expect("refused");
    assert!(matches!(error, ServeError::Option(_)), "{error:?}");
    let message = error.to_string();
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
        let first = logged_in(server.address()).await;
        let mut running = Explorer::open(&first, (100, 30), &[]).await;
        running.wait_for("Parameters").await;
        let second = logged_in(server.address()).await;
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
            let handle = logged_in(server.address()).await;
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
    let shown = Arc::new(AtomicBool::new(false));
    let seen = Arc::clone(&shown);
    let reader = std::thread::spawn(move || {
        let mut screen = vt100::Parser::new(24, 80, 0);
        let mut buffer = [0u8; 4096];
        while let Ok(n @ 1..) = std::io::Read::read(&mut stdout, &mut buffer) {
            screen.process(&buffer[..n]);
            if screen.screen().contents().contains("Parameters") {
                seen.store(true, Ordering::Release);
            }
        }
    });
    eventually("a session starts", || test.server.sessions() == 1);
    // Quit once the first frame has arrived.
    eventually("OpenSSH shows the explorer", || {
        shown.load(Ordering::Acquire)
    });
    use std::io::Write;
    child.stdin.as_mut().unwrap().write_all(b"q").unwrap();
    let status = until("ssh exits", || child.try_wait().unwrap(), String::new);
    reader.join().unwrap();
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
        let handle = logged_in(server.address()).await;
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
        let lecturer = logged_in_with(server.address(), "someone", presenter_key).await;
        let mut presenter = Explorer::open(&lecturer, (120, 40), &[]).await;
        presenter.wait_for("presenting").await;
        let student = logged_in_with(server.address(), "someone", student_key).await;
        let mut follower = Explorer::open(&student, (120, 40), &[]).await;
        follower.wait_for("following the presenter").await;
        follower.wait_for("load f0 (x=0)  5.0e4").await;
        // The presenter's status line counts the follower at once, without a key.
        presenter.wait_for("1 follow").await;
        // The follow keys are in a student's hint line and help, not in the presenter's.
        follower.wait_for("f:fork F:rejoin").await;
        assert!(!presenter.text().contains("f:fork"), "{}", presenter.text());
        // The student's help lists them too.
        follower.send(b"?").await;
        follower.wait_for("Keys (any key closes)").await;
        follower.wait_for("F  follow the presenter again").await;
        follower.send(b"\x1b").await;
        follower.wait_for("f:fork F:rejoin").await;

        // The presenter's change, seen by the follower.
        presenter.send(b"]").await;
        follower.wait_for("load f0 (x=0)  5.0e5").await;
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

        // Issue 23 item 6: the presenter disconnects; the follower is told, keeps the view
        // and gets its keys back (measured: see docs/classroom.md).
        disconnect(&lecturer).await;
        let left = Instant::now();
        follower.wait_for("the presenter left").await;
        eprintln!(
            "the follower heard the presenter leave after {:?}",
            left.elapsed()
        );
        follower.wait_for("own exploration").await;
        assert!(follower.text().contains("load f0 (x=0)  5.0e4"));
        follower.send(b"]").await;
        follower.wait_for("load f0 (x=0)  5.0e5").await;
        assert_eq!(server.followers(), 0);
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

#[test]
fn the_work_of_all_sessions_never_runs_on_more_than_the_machines_cores() {
    let test = open_server();
    let server = &test.server;
    runtime().block_on(async {
        let mut tasks = Vec::new();
        for index in 0..8u8 {
            let handle = logged_in(server.address()).await;
            tasks.push(tokio::spawn(async move {
                // All panels, so that every key asks for a solve and two studies.
                let mut explorer = Explorer::open(&handle, (130, 42), &[]).await;
                explorer.wait_for("Parameters").await;
                for _ in 0..5 {
                    explorer
                        .send(if index % 2 == 0 { b"]" } else { b"[" })
                        .await;
                    // A load's pace, not a synchronisation: keys 20 ms apart, so that each
                    // asks for work of its own while the other sessions' work runs.
                    tokio::time::sleep(Duration::from_millis(20)).await;
                }
                explorer.wait_for("cond2 of the cases").await;
                (handle, explorer)
            }));
        }
        for task in tasks {
            task.await.unwrap();
        }
    });
    let cores = std::thread::available_parallelism().unwrap().get();
    let peak = server.peak_parallel_work();
    println!("at most {peak} solves and studies ran at once on {cores} cores");
    assert!(peak >= 1, "nothing ran through the shared cores");
    assert!(peak <= cores, "{peak} at once on {cores} cores");
}

#[test]
fn every_connection_is_logged_with_address_user_key_and_duration_never_the_password() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let known = user_key(9);
    let authorized = dir.path().join("authorized_keys");
    std::fs::write(&authorized, known.public_key().to_openssh().unwrap() + "\n").unwrap();
    let password = dir.path().join("password");
    let secret = "zebra-7-crimson";
    std::fs::write(&password, format!("{secret}\n")).unwrap();
    std::fs::set_permissions(&password, std::fs::Permissions::from_mode(0o600)).unwrap();
    let host_key = dir.path().join("host_key");
    let mut serve = ServeProcess::start(&[
        "serve",
        "--listen",
        "127.0.0.1:0",
        "--host-key",
        host_key.to_str().unwrap(),
        "--authorized-keys",
        authorized.to_str().unwrap(),
        "--password-file",
        password.to_str().unwrap(),
    ]);
    let listening = serve.wait_for_line("listening on");
    let address: std::net::SocketAddr = format!("127.0.0.1:{}", port_in(&listening))
        .parse()
        .unwrap();
    let fingerprint = known
        .public_key()
        .fingerprint(Default::default())
        .to_string();
    runtime().block_on(async {
        // A wrong password, then the right one.
        let mut handle = connect(address).await;
        assert!(
            !handle
                .authenticate_password("mallory", "not-it")
                .await
                .unwrap()
                .success()
        );
        assert!(
            handle
                .authenticate_password("ann", secret)
                .await
                .unwrap()
                .success()
        );
        let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
        explorer.wait_for("Parameters").await;
        explorer.send(b"q").await;
        explorer.wait_for_close().await;
        drop(handle);
        // A key.
        let handle = logged_in_with(address, "bob", known).await;
        let mut explorer = Explorer::open(&handle, (100, 30), &[]).await;
        explorer.wait_for("Parameters").await;
        disconnect(&handle).await;
    });
    let ann = serve.wait_for_line("user ann");
    assert!(ann.contains("connection from 127.0.0.1:"), "{ann}");
    assert!(ann.contains("key -"), "{ann}");
    assert!(ann.contains(" s"), "{ann}");
    let bob = serve.wait_for_line("user bob");
    assert!(bob.contains(&fingerprint), "{bob} lacks {fingerprint}");
    assert!(bob.contains("lasted"), "{bob}");
    let everything = serve.seen.join("\n");
    assert!(!everything.contains(secret), "{everything}");
    assert!(!everything.contains("not-it"), "{everything}");
}

/// The lecturer's pty: (columns, rows).
const PTY_SIZE: (u16, u16) = (120, 40);

#[test]
fn present_the_lecturers_own_explorer_leads_and_ending_the_class_keeps_every_students_work() {
    let dir = tempfile::tempdir().unwrap();
    let saves = dir.path().join("saves");
    std::fs::create_dir(&saves).unwrap();
    let mut lecturer = present(
        dir.path(),
        &["--save-dir", saves.to_str().unwrap()],
        PTY_SIZE,
    );
    // Issue 23 item 3: the join screen first; any key closes it.
    let (join, address) = past_the_join_screen(&mut lecturer);
    lecturer.wait_for_screen("Parameters");
    runtime().block_on(async {
        let (alice, bob) = (
            logged_in_as(address, "alice").await,
            logged_in_as(address, "bob").await,
        );
        let mut follower = Explorer::open(&alice, PTY_SIZE, &[]).await;
        let mut forker = Explorer::open(&bob, (80, 24), &[]).await;
        follower.wait_for("following the presenter").await;
        follower.wait_for("load f0 (x=0)  5.0e4").await;
        forker.wait_for("following the presenter").await;
        // The lecturer's status line counts the students, and says it presents.
        lecturer.wait_for_screen("presenting · 2 follow · 2 students");

        // Each change of the lecturer's, up and down a coarse step, reaches the students.
        for (key, shown) in [
            (b"]", "5.0e5"),
            (b"[", "5.0e4"),
            (b"]", "5.0e5"),
            (b"[", "5.0e4"),
            (b"]", "5.0e5"),
        ] {
            lecturer.type_bytes(key);
            follower.wait_for(&format!("load f0 (x=0)  {shown}")).await;
        }
        lecturer.wait_for_screen("load f0 (x=0)  5.0e5");
        forker.wait_for("5.0e5").await;
        // Issue 23 item 2: the follower at 80×24 shows the presenter's error and KKT figures
        // (the follow mode moved to the title line).
        let figure = |screen: &str, word: &str| {
            let at = screen
                .find(word)
                .unwrap_or_else(|| panic!("no {word:?} in\n{screen}"));
            screen[at..].split_whitespace().nth(2).map(str::to_string)
        };
        // Both screens settle on the last solve: the figures must become the same (a frame
        // of either may still show the solve before it).
        let deadline = deadline();
        loop {
            let lecturers = lecturer.screen();
            let followers = forker.text();
            let same = ["· KKT", "· error"].iter().all(|word| {
                lecturers.contains(word)
                    && followers.contains(word)
                    && figure(&lecturers, word) == figure(&followers, word)
            });
            if same {
                assert!(followers.contains("following the presenter"), "{followers}");
                break;
            }
            assert!(
                Instant::now() < deadline,
                "the follower's error and KKT never matched the lecturer's:\n{lecturers}\n{followers}"
            );
            forker
                .read_once(Instant::now() + Duration::from_millis(100))
                .await;
        }

        // Bob forks and changes the load: the lecturer's explorer is not affected, and Bob now
        // holds unsaved work.
        forker.send(b"f").await;
        forker.wait_for("own exploration").await;
        lecturer.wait_for_screen("presenting · 1 follow · 2 students");
        forker.send(b"]").await;
        forker.wait_for("5.0e6").await;
        assert!(lecturer.screen().contains("load f0 (x=0)  5.0e5"));

        // Issue 23 item 1: the lecturer's quit asks first; n keeps teaching.
        lecturer.type_bytes(b"q");
        lecturer.wait_for_screen("2 students (1 with unsaved work): end the class?");
        lecturer.type_bytes(b"n");
        lecturer.wait_for_screen("the class goes on");
        // Yes ends it (and the lecturer's own changed scene is not saved: y).
        lecturer.type_bytes(b"q");
        lecturer.wait_for_screen("end the class?");
        lecturer.type_bytes(b"y");
        lecturer.wait_for_screen("lose them?");
        lecturer.type_bytes(b"y");

        // Each student sees who ended it and their scene as TOML; Bob's fork is saved under
        // --save-dir with his name; Alice (following) had nothing of her own to save.
        follower
            .wait_for("The class was ended by the lecturer")
            .await;
        follower.wait_for("Nothing is saved on the server").await;
        follower.wait_for("[load]").await;
        forker.wait_for("The class was ended by the lecturer").await;
        forker.wait_for("bob-benchmark-1.toml").await;
        let saved = std::fs::read_to_string(saves.join("bob-benchmark-1.toml")).unwrap();
        let scene = beamfric::scene::Scene::from_toml(&saved, "bob").unwrap();
        assert_eq!(scene.load.f0, 5e6, "{saved}");
        assert_eq!(std::fs::read_dir(&saves).unwrap().count(), 1);

        // A key leaves; the channels close and the screens are left.
        follower.send(b"x").await;
        forker.send(b"x").await;
        for student in [&mut follower, &mut forker] {
            student.wait_for_close().await;
            let raw = String::from_utf8_lossy(&student.raw).into_owned();
            assert!(
                raw.contains(LEAVE_ALTERNATE),
                "the student's screen was not left"
            );
        }
    });
    // Its exit, and everything it wrote before it.
    let status = lecturer.exit();
    assert_eq!(status.code(), Some(0), "{status:?}");
    // The lecturer's terminal is restored, and the class's end and the log lines follow.
    let raw = lecturer.text();
    let left = raw
        .rfind(LEAVE_ALTERNATE)
        .expect("the alternate screen was left");
    assert!(
        raw[left..].contains("the class is over: 2 students"),
        "{:?}",
        &raw[left..]
    );
    // The join screen showed the host key's whole fingerprint, and the login.
    let fingerprint = fingerprint_in(&raw);
    assert!(join.contains(&fingerprint), "{fingerprint} not in\n{join}");
    assert!(join.contains("any user name, no password"), "{join}");
    assert!(raw[left..].contains("user bob"), "{:?}", &raw[left..]);
    assert!(raw[left..].contains("stopped"), "{:?}", &raw[left..]);
    let flags = lecturer.local_flags();
    assert!(
        flags.contains(nix::sys::termios::LocalFlags::ICANON | nix::sys::termios::LocalFlags::ECHO)
    );
    // The port is free again: the server is gone.
    assert!(std::net::TcpStream::connect(address).is_err());
}

/// The `SHA256:…` fingerprint after "host key " in `text`.
fn fingerprint_in(text: &str) -> String {
    let at = text
        .find("host key SHA256:")
        .expect("a host key in the log")
        + "host key ".len();
    text[at..]
        .chars()
        .take_while(|c| !c.is_whitespace() && *c != ')')
        .collect()
}

/// Issue 23 item 3: on the lecturer's 80×24 screen the join screen (at start, and on `J`)
/// shows the host key's whole fingerprint — it was cut at `(host key S` before — the command
/// and how students log in.
#[test]
fn the_join_screen_shows_the_whole_fingerprint_at_80x24() {
    let dir = tempfile::tempdir().unwrap();
    let host_key = dir.path().join("host_key");
    let password = dir.path().join("password");
    std::fs::write(&password, "class secret\n").unwrap();
    std::fs::set_permissions(
        &password,
        std::os::unix::fs::PermissionsExt::from_mode(0o600),
    )
    .unwrap();
    let mut lecturer = PtyProcess::start(
        &[
            "present",
            "--password-file",
            password.to_str().unwrap(),
            "--listen",
            "127.0.0.1:0",
            "--host-key",
            host_key.to_str().unwrap(),
        ],
        &[],
        (80, 24),
    );
    lecturer.wait_for_screen("Students join the class with");
    let first = lecturer.screen();
    lecturer.type_bytes(b"x");
    lecturer.wait_for_screen("Parameters");
    lecturer.wait_for_screen("J:join");
    lecturer.type_bytes(b"J");
    lecturer.wait_for_screen("Students join the class with");
    let again = lecturer.screen();
    lecturer.type_bytes(b"x");
    lecturer.wait_for_screen("Parameters");
    lecturer.type_bytes(b"q");
    let status = lecturer.exit();
    assert_eq!(status.code(), Some(0), "{status:?}");
    let fingerprint = fingerprint_in(&lecturer.text());
    for screen in [&first, &again] {
        assert!(
            screen.contains(&fingerprint),
            "{fingerprint} not in\n{screen}"
        );
        assert!(
            screen.contains(&format!("ssh -p {} 127.0.0.1", port_in(screen))),
            "{screen}"
        );
        assert!(screen.contains("the class password"), "{screen}");
    }
}

#[test]
fn an_open_server_warns_and_prints_its_address_and_host_key_fingerprint() {
    let dir = tempfile::tempdir().unwrap();
    let host_key = dir.path().join("keys").join("host_key");
    let mut serve = ServeProcess::start(&[
        "serve",
        "--open",
        "--listen",
        "127.0.0.1:0",
        "--host-key",
        host_key.to_str().unwrap(),
    ]);
    let warning = serve.wait_for_line("warning: --open");
    assert!(warning.contains("anyone"), "{warning}");
    serve.wait_for_line("created the host key");
    let listening = serve.wait_for_line("listening on 127.0.0.1:");
    // The fingerprint printed is the one of the key stored (mode 0600).
    let text = std::fs::read_to_string(&host_key).unwrap();
    let key = PrivateKey::from_openssh(text).unwrap();
    let fingerprint = key.public_key().fingerprint(Default::default()).to_string();
    assert!(
        listening.contains(&fingerprint),
        "{listening} lacks {fingerprint}"
    );
    assert!(listening.contains(&format!("ssh -p {}", port_in(&listening))));
    use std::os::unix::fs::PermissionsExt;
    let mode = std::fs::metadata(&host_key).unwrap().permissions().mode();
    assert_eq!(mode & 0o777, 0o600);
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

#[test]
fn present_refuses_without_a_terminal_and_without_credentials_or_open() {
    let dir = tempfile::tempdir().unwrap();
    let host_key = dir.path().join("host_key");
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_beamfric"))
        .args(["present", "--open", "--listen", "127.0.0.1:0", "--host-key"])
        .arg(&host_key)
        // The explorer's display options are `present`'s too (issue 23 item 7).
        .args([
            "--theme",
            "high-contrast",
            "--ascii",
            "--no-color",
            "--no-mouse",
        ])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("standard output is not one; `beamfric serve`"),
        "{stderr}"
    );

    let mut lecturer = PtyProcess::start(
        &[
            "present",
            "--listen",
            "127.0.0.1:0",
            "--host-key",
            host_key.to_str().unwrap(),
        ],
        &[],
        PTY_SIZE,
    );
    // Its exit, and everything it wrote before it.
    let status = lecturer.exit();
    assert_eq!(status.code(), Some(2), "{status:?}");
    assert!(lecturer.text().contains("--open"), "{}", lecturer.text());
    assert!(!host_key.exists(), "a refused start created a host key");
}
