//! The explorer in a real pseudo-terminal (issue 6): whatever ends it — `q`, Ctrl-C typed,
//! SIGINT, SIGTERM, SIGHUP or a panic on the main thread — the terminal comes back out of the
//! alternate screen and raw mode, and the exit status says what happened. A panic in a study
//! worker leaves the explorer running with the failure shown in its panel.
//!
//! Each test starts the real binary as the session leader of a fresh pty (so crossterm talks
//! to that pty and nothing else), reads everything it writes, and after it exits reads the
//! pty's line discipline back: canonical mode and echo must be on again.

#![cfg(unix)]

use std::io::{Read, Write};
use std::os::fd::{AsFd, OwnedFd};
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use nix::pty::{Winsize, openpty};
use nix::sys::signal::{Signal, kill};
use nix::sys::termios::{LocalFlags, tcgetattr};
use nix::unistd::Pid;

const ENTER_ALTERNATE: &str = "\x1b[?1049h";
const LEAVE_ALTERNATE: &str = "\x1b[?1049l";
const SHOW_CURSOR: &str = "\x1b[?25h";

/// A guard against a hung child, not a measurement: a healthy run takes well under a second.
const PATIENCE: Duration = Duration::from_secs(60);
/// The pty's size: (rows, columns).
const SIZE: (u16, u16) = (30, 100);

struct Explorer {
    child: Child,
    master: OwnedFd,
    writer: std::fs::File,
    output: Arc<Mutex<Vec<u8>>>,
}

impl Explorer {
    /// Starts `beamfric` (the explorer on the default scene) on a 100×30 pty.
    fn start(env: &[(&str, &str)]) -> Explorer {
        let size = Winsize {
            ws_row: SIZE.0,
            ws_col: SIZE.1,
            ws_xpixel: 0,
            ws_ypixel: 0,
        };
        let pty = openpty(&size, None).expect("a pseudo-terminal");
        let before = tcgetattr(pty.slave.as_fd()).unwrap();
        assert!(
            before
                .local_flags
                .contains(LocalFlags::ICANON | LocalFlags::ECHO),
            "a new pty starts in cooked mode"
        );
        let mut command = Command::new(env!("CARGO_BIN_EXE_beamfric"));
        command
            .stdin(Stdio::from(pty.slave.try_clone().unwrap()))
            .stdout(Stdio::from(pty.slave.try_clone().unwrap()))
            .stderr(Stdio::from(pty.slave.try_clone().unwrap()))
            .env("TERM", "xterm-256color")
            .env_remove("NO_COLOR")
            .env_remove(beamfric::tui::INJECT_PANIC);
        for (key, value) in env {
            command.env(key, value);
        }
        // SAFETY: only async-signal-safe calls between fork and exec.
        unsafe {
            command.pre_exec(|| {
                // A new session whose controlling terminal is the pty (stdin, set up by now).
                if nix::libc::setsid() < 0 || nix::libc::ioctl(0, nix::libc::TIOCSCTTY, 0) < 0 {
                    return Err(std::io::Error::last_os_error());
                }
                Ok(())
            });
        }
        let child = command.spawn().expect("the binary starts");
        drop(command);
        drop(pty.slave);
        let output = Arc::new(Mutex::new(Vec::new()));
        let mut reader = std::fs::File::from(pty.master.try_clone().unwrap());
        let sink = Arc::clone(&output);
        std::thread::spawn(move || {
            let mut buffer = [0u8; 4096];
            // Ends with EIO once the child and every copy of the slave side are gone.
            while let Ok(n) = reader.read(&mut buffer) {
                if n == 0 {
                    break;
                }
                sink.lock().unwrap().extend_from_slice(&buffer[..n]);
            }
        });
        let writer = std::fs::File::from(pty.master.try_clone().unwrap());
        Explorer {
            child,
            master: pty.master,
            writer,
            output,
        }
    }

    fn text(&self) -> String {
        String::from_utf8_lossy(&self.output.lock().unwrap()).into_owned()
    }

    /// Waits until the output contains `needle` after the switch to the alternate screen.
    fn wait_for(&self, needle: &str) {
        let start = Instant::now();
        loop {
            let text = self.text();
            if let Some(at) = text.find(ENTER_ALTERNATE)
                && text[at..].contains(needle)
            {
                return;
            }
            assert!(
                start.elapsed() < PATIENCE,
                "{needle:?} never appeared; output so far:\n{text:?}"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// The screen as a terminal shows it now (a vt100 emulator fed everything written).
    fn screen(&self) -> String {
        let mut parser = vt100::Parser::new(SIZE.0, SIZE.1, 0);
        parser.process(&self.output.lock().unwrap());
        parser.screen().contents()
    }

    /// Waits until the screen shows `needle`.
    fn wait_for_screen(&self, needle: &str) {
        let start = Instant::now();
        while !self.screen().contains(needle) {
            assert!(
                start.elapsed() < PATIENCE,
                "{needle:?} never shown; the screen:\n{}",
                self.screen()
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    fn type_bytes(&mut self, bytes: &[u8]) {
        self.writer.write_all(bytes).unwrap();
        self.writer.flush().unwrap();
    }

    fn signal(&self, signal: Signal) {
        kill(Pid::from_raw(self.child.id() as i32), signal).unwrap();
    }

    /// Waits for the exit, then checks that the terminal was given back; returns the status and
    /// what was written from the first restoration on.
    fn finish(mut self) -> (ExitStatus, String) {
        let start = Instant::now();
        let status = loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                break status;
            }
            if start.elapsed() > PATIENCE {
                let _ = self.child.kill();
                panic!("the explorer did not exit; output:\n{:?}", self.text());
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        // Let the reader drain what is left in the pty.
        std::thread::sleep(Duration::from_millis(200));
        let text = self.text();
        let entered = text
            .find(ENTER_ALTERNATE)
            .unwrap_or_else(|| panic!("never entered the alternate screen:\n{text:?}"));
        let left = entered
            + text[entered..]
                .find(LEAVE_ALTERNATE)
                .unwrap_or_else(|| panic!("never left the alternate screen:\n{text:?}"));
        assert!(
            text[left..].contains(SHOW_CURSOR),
            "cursor not shown again:\n{text:?}"
        );
        let after = tcgetattr(self.master.as_fd()).unwrap();
        assert!(
            after
                .local_flags
                .contains(LocalFlags::ICANON | LocalFlags::ECHO | LocalFlags::ISIG),
            "the pty is still in raw mode: {:?}",
            after.local_flags
        );
        (status, text[left..].to_string())
    }
}

#[test]
fn quitting_by_key_restores_the_terminal_and_exits_zero() {
    // `q`, and Ctrl-C, which in raw mode arrives as a key, not as SIGINT.
    for key in [&b"q"[..], b"\x03"] {
        let mut explorer = Explorer::start(&[]);
        explorer.wait_for("Parameters");
        explorer.type_bytes(key);
        let (status, _) = explorer.finish();
        assert_eq!(status.code(), Some(0), "{key:?}");
    }
}

#[test]
fn signals_restore_the_terminal_and_exit_with_128_plus_the_signal() {
    for (signal, code) in [
        (Signal::SIGINT, 130),
        (Signal::SIGTERM, 143),
        (Signal::SIGHUP, 129),
    ] {
        let explorer = Explorer::start(&[]);
        explorer.wait_for("Parameters");
        explorer.signal(signal);
        let (status, _) = explorer.finish();
        assert_eq!(status.code(), Some(code), "{signal}: {status:?}");
        assert_eq!(status.signal(), None, "{signal} was handled, not fatal");
    }
}

#[test]
fn a_panic_restores_the_terminal_first_then_reports() {
    let explorer = Explorer::start(&[(beamfric::tui::INJECT_PANIC, "main")]);
    explorer.wait_for("Parameters");
    let (status, after) = explorer.finish();
    assert_eq!(status.code(), Some(101), "{status:?}");
    // The report comes after the restoration, on the normal screen where it stays readable.
    assert!(after.contains("injected panic"), "{after:?}");
}

#[test]
fn a_panic_in_a_study_is_shown_and_the_explorer_goes_on() {
    let mut explorer = Explorer::start(&[(beamfric::tui::INJECT_PANIC, "worker")]);
    explorer.wait_for("internal error");
    // Still alive and answering keys.
    explorer.type_bytes(b"?");
    explorer.wait_for("Keys");
    // Any key closes the help; then quit.
    explorer.type_bytes(b"?q");
    let (status, after) = explorer.finish();
    assert_eq!(status.code(), Some(0));
    assert!(!after.contains("panicked"), "{after:?}");
}

#[test]
fn unsaved_changes_make_q_ask_and_esc_in_the_save_prompt_goes_back() {
    let mut explorer = Explorer::start(&[]);
    explorer.wait_for_screen("Parameters");
    // An edit: the load one step up.
    explorer.type_bytes(b"l");
    explorer.wait_for_screen("[modified]");
    explorer.type_bytes(b"q");
    explorer.wait_for_screen("quit and lose them?");
    // No: back to the explorer with the edit.
    explorer.type_bytes(b"n");
    explorer.wait_for_screen("kept the unsaved changes");
    // Esc in the save prompt, then Esc again in normal mode: still running.
    explorer.type_bytes(b"s");
    explorer.wait_for_screen("save the scene to");
    explorer.type_bytes(b"\x1b");
    explorer.wait_for_screen("not saved");
    std::thread::sleep(Duration::from_millis(300));
    assert!(explorer.child.try_wait().unwrap().is_none(), "Esc quit");
    // Then quit for real: q, y.
    explorer.type_bytes(b"qy");
    let (status, _) = explorer.finish();
    assert_eq!(status.code(), Some(0));
}
