//! Who may connect to `beamfric serve` and what a connection may ask for: credentials, refused
//! channel requests, the session cap, OpenSSH as a client, the element cap, the cores all sessions
//! share, and the connection log.

use super::*;

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
