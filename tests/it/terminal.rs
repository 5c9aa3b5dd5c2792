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
use std::os::fd::{AsFd, AsRawFd, FromRawFd, IntoRawFd, OwnedFd};
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use nix::pty::Winsize;
use nix::sys::signal::{Signal, kill};
use nix::sys::termios::{LocalFlags, tcgetattr};
use nix::unistd::Pid;

use crate::harness::scenes;

const ENTER_ALTERNATE: &str = "\x1b[?1049h";
const LEAVE_ALTERNATE: &str = "\x1b[?1049l";
const SHOW_CURSOR: &str = "\x1b[?25h";

/// A guard against a hung child, not a measurement: a healthy run takes well under a second.
const PATIENCE: Duration = Duration::from_secs(60);
/// The pty's size: (rows, columns).
const SIZE: (u16, u16) = (30, 100);

/// A pty whose two sides are closed on exec, so that an explorer started by a test running
/// at the same time cannot keep this one's terminal open (`openpty` leaves both inheritable).
struct Pty {
    master: OwnedFd,
    slave: OwnedFd,
}

fn cloexec_pty(size: &Winsize) -> Pty {
    use nix::fcntl::OFlag;
    use nix::pty::{grantpt, posix_openpt, unlockpt};
    use std::os::unix::fs::OpenOptionsExt;
    let master = posix_openpt(OFlag::O_RDWR | OFlag::O_NOCTTY | OFlag::O_CLOEXEC).unwrap();
    grantpt(&master).unwrap();
    unlockpt(&master).unwrap();
    let name = nix::pty::ptsname_r(&master).unwrap();
    // The standard library opens with O_CLOEXEC.
    let slave = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .custom_flags(nix::libc::O_NOCTTY)
        .open(name)
        .unwrap();
    // SAFETY: TIOCSWINSZ reads one `winsize` from the pointer.
    let set = unsafe { nix::libc::ioctl(slave.as_raw_fd(), nix::libc::TIOCSWINSZ, size) };
    assert_eq!(set, 0, "set the window size");
    // SAFETY: the master fd is open and owned by nothing else from here on.
    let master = unsafe { OwnedFd::from_raw_fd(master.into_raw_fd()) };
    Pty {
        master,
        slave: slave.into(),
    }
}

struct Explorer {
    child: Child,
    master: Option<OwnedFd>,
    writer: Option<std::fs::File>,
    output: Arc<Mutex<Vec<u8>>>,
    stop: Arc<std::sync::atomic::AtomicBool>,
}

impl Explorer {
    /// Starts `beamfric` (the explorer on the default scene) on a 100×30 pty.
    fn start(env: &[(&str, &str)]) -> Explorer {
        Explorer::start_with(&[], env)
    }

    /// Starts `beamfric ARGS` on a 100×30 pty.
    fn start_with(args: &[&str], env: &[(&str, &str)]) -> Explorer {
        let size = Winsize {
            ws_row: SIZE.0,
            ws_col: SIZE.1,
            ws_xpixel: 0,
            ws_ypixel: 0,
        };
        let pty = cloexec_pty(&size);
        let before = tcgetattr(pty.slave.as_fd()).unwrap();
        assert!(
            before
                .local_flags
                .contains(LocalFlags::ICANON | LocalFlags::ECHO),
            "a new pty starts in cooked mode"
        );
        let mut command = Command::new(env!("CARGO_BIN_EXE_beamfric"));
        command
            .args(args)
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
        let stop = Arc::new(std::sync::atomic::AtomicBool::new(false));
        let stopped = Arc::clone(&stop);
        std::thread::spawn(move || {
            use nix::poll::{PollFd, PollFlags, PollTimeout, poll};
            let mut buffer = [0u8; 4096];
            // Ends with EIO once the child and every copy of the slave side are gone, or when
            // told to (`hang_up`), which closes this copy of the master.
            while !stopped.load(std::sync::atomic::Ordering::Relaxed) {
                let mut fds = [PollFd::new(reader.as_fd(), PollFlags::POLLIN)];
                match poll(&mut fds, PollTimeout::from(50u16)) {
                    Ok(0) => continue,
                    Ok(_) => {}
                    Err(_) => break,
                }
                match reader.read(&mut buffer) {
                    Ok(0) | Err(_) => break,
                    Ok(n) => sink.lock().unwrap().extend_from_slice(&buffer[..n]),
                }
            }
        });
        let writer = std::fs::File::from(pty.master.try_clone().unwrap());
        Explorer {
            child,
            master: Some(pty.master),
            writer: Some(writer),
            output,
            stop,
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

    /// The alternate screen as it last was before the explorer left it.
    fn last_frame(&self) -> String {
        let output = self.output.lock().unwrap();
        let text = String::from_utf8_lossy(&output).into_owned();
        let end = text.rfind(LEAVE_ALTERNATE).unwrap_or(text.len());
        let mut parser = vt100::Parser::new(SIZE.0, SIZE.1, 0);
        parser.process(&text.as_bytes()[..end]);
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
        let writer = self.writer.as_mut().expect("the terminal is open");
        writer.write_all(bytes).unwrap();
        writer.flush().unwrap();
    }

    /// Closes every copy of the pty's master side: the terminal is gone, as when a terminal
    /// window or an SSH connection closes.
    fn hang_up(&mut self) {
        self.stop.store(true, std::sync::atomic::Ordering::Relaxed);
        self.writer = None;
        self.master = None;
        // The reader notices within its poll interval and drops its copy.
        std::thread::sleep(Duration::from_millis(100));
    }

    /// Waits for the exit without looking at the terminal; returns the status and how long
    /// it took from the call.
    fn exit_status(&mut self) -> (ExitStatus, Duration) {
        let start = Instant::now();
        loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                return (status, start.elapsed());
            }
            if start.elapsed() > PATIENCE {
                let _ = self.child.kill();
                panic!("the explorer did not exit");
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    /// The pty's line discipline as the program left it.
    fn local_flags(&self) -> LocalFlags {
        tcgetattr(self.master.as_ref().expect("open").as_fd())
            .unwrap()
            .local_flags
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
        let after = tcgetattr(self.master.as_ref().expect("open").as_fd()).unwrap();
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

// ---- Issue 11: never blocks, never orphans itself, quits at once. ----

/// The crowded scene of the harness, written to a file: its `dual` solve takes seconds.
fn slow_scene(dir: &std::path::Path) -> std::path::PathBuf {
    let path = dir.join("slow.toml");
    std::fs::write(&path, scenes::crowded_scene_text()).unwrap();
    path
}

#[test]
fn a_closed_terminal_ends_the_explorer_within_a_second() {
    let mut explorer = Explorer::start(&[]);
    explorer.wait_for_screen("Parameters");
    explorer.hang_up();
    let (status, took) = explorer.exit_status();
    assert!(took < Duration::from_secs(1), "took {took:?} to notice");
    // Ended by its own hand (SIGHUP handled, or end of input), not killed.
    assert_eq!(status.signal(), None, "{status:?}");
    assert_eq!(status.code(), Some(129), "{status:?}");
}

#[test]
fn a_paste_of_ten_thousand_keys_is_read_to_the_end() {
    let mut explorer = Explorer::start(&[]);
    explorer.wait_for_screen("Parameters");
    // Selection moves, arrows and Tab (none changes the scene), then q: 10 000 bytes.
    let mut keys = Vec::new();
    while keys.len() < 9_990 {
        keys.extend_from_slice(b"jk\x1b[A\x1b[B\t");
    }
    keys.truncate(9_990);
    // End on whole keys.
    while keys.last() == Some(&0x1b) || keys.ends_with(b"\x1b[") {
        keys.pop();
    }
    keys.extend(std::iter::repeat_n(b'j', 9_999 - keys.len()));
    keys.push(b'q');
    assert_eq!(keys.len(), 10_000);
    explorer.type_bytes(&keys);
    let (status, _) = explorer.finish();
    assert_eq!(status.code(), Some(0), "{status:?}");
}

#[test]
fn quitting_or_sigterm_during_a_long_solve_is_immediate() {
    let dir = tempfile::tempdir().unwrap();
    let scene = slow_scene(dir.path());
    for (how, code) in [("q", 0), ("SIGTERM", 143)] {
        let mut explorer = Explorer::start_with(&[scene.to_str().unwrap()], &[]);
        explorer.wait_for_screen("solving n = 1000 with dual");
        // The frame is up while the solve runs: the UI thread does not wait for it.
        assert!(explorer.screen().contains("Parameters"));
        if how == "q" {
            explorer.type_bytes(b"q");
        } else {
            explorer.signal(Signal::SIGTERM);
        }
        let (status, took) = explorer.exit_status();
        assert!(
            took < Duration::from_millis(500),
            "{how}: {took:?} to exit during a solve"
        );
        assert!(
            explorer.last_frame().contains("solving"),
            "{how}: the solve had finished"
        );
        let (status_again, _) = explorer.finish();
        assert_eq!(status.code(), Some(code), "{how}: {status:?}");
        assert_eq!(status_again.code(), Some(code));
    }
}

#[test]
fn ctrl_z_and_sigtstp_suspend_and_sigcont_resumes_with_a_redraw() {
    use nix::sys::wait::{WaitPidFlag, WaitStatus, waitpid};
    let mut explorer = Explorer::start(&[]);
    explorer.wait_for_screen("Parameters");
    let pid = Pid::from_raw(explorer.child.id() as i32);
    for how in ["Ctrl-Z", "SIGTSTP"] {
        let mark = explorer.output.lock().unwrap().len();
        if how == "Ctrl-Z" {
            explorer.type_bytes(b"\x1a");
        } else {
            explorer.signal(Signal::SIGTSTP);
        }
        match waitpid(pid, Some(WaitPidFlag::WUNTRACED)).unwrap() {
            WaitStatus::Stopped(_, _) => {}
            other => panic!("{how}: not stopped: {other:?}"),
        }
        // While stopped, the terminal is the shell's: line mode, normal screen.
        std::thread::sleep(Duration::from_millis(100));
        assert!(
            explorer
                .local_flags()
                .contains(LocalFlags::ICANON | LocalFlags::ECHO),
            "{how}: raw mode left on while stopped"
        );
        let since = String::from_utf8_lossy(&explorer.output.lock().unwrap()[mark..]).into_owned();
        assert!(
            since.contains(LEAVE_ALTERNATE),
            "{how}: alternate screen left up"
        );
        explorer.signal(Signal::SIGCONT);
        // Back: raw mode, the alternate screen, and a full frame.
        let start = Instant::now();
        loop {
            let since =
                String::from_utf8_lossy(&explorer.output.lock().unwrap()[mark..]).into_owned();
            let back = since
                .rfind(ENTER_ALTERNATE)
                .is_some_and(|at| since[at..].contains("Parameters"));
            if back && !explorer.local_flags().contains(LocalFlags::ICANON) {
                break;
            }
            assert!(start.elapsed() < PATIENCE, "{how}: not resumed:\n{since:?}");
            std::thread::sleep(Duration::from_millis(20));
        }
    }
    explorer.type_bytes(b"q");
    let (status, _) = explorer.finish();
    assert_eq!(status.code(), Some(0));
}

#[test]
fn a_bracketed_paste_is_never_run_as_commands() {
    let mut explorer = Explorer::start(&[]);
    explorer.wait_for_screen("Parameters");
    // A paste of commands in normal mode: noted, not run.
    explorer.type_bytes(b"\x1b[200~dq\rq\x1b[201~");
    explorer.wait_for_screen("a paste is typed only into a prompt");
    assert!(
        explorer.child.try_wait().unwrap().is_none(),
        "the paste quit"
    );
    assert!(!explorer.screen().contains("[modified]"));
    explorer.type_bytes(b"q");
    let (status, _) = explorer.finish();
    assert_eq!(status.code(), Some(0));
}

/// The screen as cells: `cells[row][column]` is what that cell shows, and whether it is in
/// reverse video (the selected row without colours).
fn cells(explorer: &Explorer) -> Vec<Vec<(String, bool)>> {
    let mut parser = vt100::Parser::new(SIZE.0, SIZE.1, 0);
    parser.process(&explorer.output.lock().unwrap());
    let screen = parser.screen();
    (0..SIZE.0)
        .map(|row| {
            (0..SIZE.1)
                .map(|column| {
                    screen
                        .cell(row, column)
                        .map_or((" ".into(), false), |cell| {
                            (cell.contents().to_string(), cell.inverse())
                        })
                })
                .collect()
        })
        .collect()
}

/// The text of one row of cells.
fn row_text(row: &[(String, bool)]) -> String {
    row.iter()
        .map(|(c, _)| if c.is_empty() { " " } else { c.as_str() })
        .collect()
}

/// The cell (column, row) where `needle` starts, the first from the top.
fn cell_of(cells: &[Vec<(String, bool)>], needle: &str) -> Option<(u16, u16)> {
    cells.iter().enumerate().find_map(|(y, row)| {
        let text = row_text(row);
        let at = text.find(needle)?;
        Some((text[..at].chars().count() as u16, y as u16))
    })
}

/// The number after `label` on its row, e.g. `2.15e11` after `modulus E`.
fn value_after(cells: &[Vec<(String, bool)>], label: &str) -> Option<f64> {
    let (x, y) = cell_of(cells, label)?;
    let text = row_text(&cells[y as usize]);
    let rest: String = text
        .chars()
        .skip(x as usize + label.chars().count())
        .collect();
    rest.split_whitespace().next()?.parse().ok()
}

/// An SGR mouse report of button code `code` at 0-based cell (x, y); `press` or release.
fn sgr(code: u8, (x, y): (u16, u16), press: bool) -> Vec<u8> {
    let end = if press { 'M' } else { 'm' };
    format!("\x1b[<{code};{};{}{end}", x + 1, y + 1).into_bytes()
}

/// Waits until `condition` holds for the screen's cells.
fn wait_until(explorer: &Explorer, what: &str, condition: impl Fn(&[Vec<(String, bool)>]) -> bool) {
    let start = Instant::now();
    loop {
        let cells = cells(explorer);
        if condition(&cells) {
            return;
        }
        assert!(
            start.elapsed() < PATIENCE,
            "{what} never happened; the screen:\n{}",
            explorer.screen()
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn mouse_clicks_the_wheel_and_an_obstacle_drag_change_the_state() {
    let mut explorer = Explorer::start(&[("NO_COLOR", "1")]);
    explorer.wait_for_screen("Parameters");
    explorer.wait_for_screen("slides");
    {
        // The explorer asked for presses, drags and releases, SGR-encoded.
        let mut parser = vt100::Parser::new(SIZE.0, SIZE.1, 0);
        parser.process(&explorer.output.lock().unwrap());
        assert_eq!(
            parser.screen().mouse_protocol_mode(),
            vt100::MouseProtocolMode::ButtonMotion
        );
        assert_eq!(
            parser.screen().mouse_protocol_encoding(),
            vt100::MouseProtocolEncoding::Sgr
        );
    }
    // A click on the "modulus E" row selects it (drawn in reverse video).
    let screen = cells(&explorer);
    let (x, y) = cell_of(&screen, "modulus E").expect("the row is drawn");
    assert!(!screen[y as usize][x as usize].1, "not selected yet");
    let young = value_after(&screen, "modulus E").unwrap();
    explorer.type_bytes(&[sgr(0, (x + 2, y), true), sgr(0, (x + 2, y), false)].concat());
    wait_until(&explorer, "the row selected", |cells| {
        cells[y as usize][x as usize].1
    });
    // The wheel over the parameters steps the selected value: one fine step, ×10^0.1.
    explorer.type_bytes(&sgr(64, (x + 2, y + 1), true));
    wait_until(&explorer, "the modulus stepped up", |cells| {
        value_after(cells, "modulus E").is_some_and(|v| (v / young - 10f64.powf(0.1)).abs() < 0.01)
    });
    explorer.type_bytes(&sgr(65, (x + 2, y + 1), true));
    wait_until(&explorer, "the modulus stepped back", |cells| {
        value_after(cells, "modulus E").is_some_and(|v| (v / young - 1.0).abs() < 0.01)
    });
    // Drag the sliding obstacle's marker (↕, on the deflection chart) ten columns left.
    let screen = cells(&explorer);
    let x0 = value_after(&screen, "obstacle 1 x").unwrap();
    let (mx, my) = screen
        .iter()
        .enumerate()
        .take(SIZE.0 as usize - 8)
        .find_map(|(y, row)| {
            let column = row.iter().position(|(c, _)| c == "↕")?;
            Some((column as u16, y as u16))
        })
        .expect("the marker is drawn");
    let mut drag = sgr(0, (mx, my), true);
    for dx in 1..=10 {
        drag.extend(sgr(32, (mx - dx, my), true));
    }
    drag.extend(sgr(0, (mx - 10, my), false));
    explorer.type_bytes(&drag);
    wait_until(&explorer, "the obstacle moved left", |cells| {
        value_after(cells, "obstacle 1 x").is_some_and(|x| x < x0 - 0.05)
    });
    // ... and its marker is drawn where the pointer let go, once the new solution is in.
    wait_until(&explorer, "the marker redrawn", |cells| {
        cells[..SIZE.0 as usize - 8].iter().any(|row| {
            row.get(mx as usize - 10)
                .is_some_and(|(c, _)| "↕●↻✱".contains(c.as_str()) && !c.is_empty())
        })
    });
    explorer.type_bytes(b"u");
    wait_until(&explorer, "the drag undone", |cells| {
        value_after(cells, "obstacle 1 x") == Some(x0)
    });
    explorer.type_bytes(b"q");
    explorer.type_bytes(b"y");
    let output = Arc::clone(&explorer.output);
    let (status, _) = explorer.finish();
    assert_eq!(status.code(), Some(0));
    // The mouse is given back to the terminal.
    let text = String::from_utf8_lossy(&output.lock().unwrap()).into_owned();
    let on = text.rfind("\x1b[?1000h").expect("asked for the mouse");
    assert!(
        text.rfind("\x1b[?1000l") > Some(on),
        "never gave the mouse back"
    );
}

#[test]
fn no_mouse_leaves_the_mouse_to_the_terminal() {
    let mut explorer = Explorer::start_with(&["--no-mouse"], &[("NO_COLOR", "1")]);
    explorer.wait_for_screen("Parameters");
    let screen = cells(&explorer);
    let (x, y) = cell_of(&screen, "modulus E").expect("the row is drawn");
    // A client that sends mouse reports anyway changes nothing.
    explorer.type_bytes(&[sgr(0, (x + 2, y), true), sgr(0, (x + 2, y), false)].concat());
    explorer.type_bytes(b"?");
    explorer.wait_for_screen("Keys (any key closes)");
    assert!(
        !cells(&explorer)[y as usize][x as usize].1,
        "selected by a click"
    );
    assert!(
        !explorer.text().contains("\x1b[?1000h"),
        "asked for the mouse"
    );
    explorer.type_bytes(b"q");
    explorer.type_bytes(b"q");
    let (status, _) = explorer.finish();
    assert_eq!(status.code(), Some(0));
}

/// Issue 13: a locale that is not UTF-8 gets ASCII by itself (LC_ALL, then LC_CTYPE, then
/// LANG, as tmux decides), a UTF-8 one Unicode; `--ascii` forces ASCII; `T` cycles the theme.
#[test]
fn the_locale_decides_ascii_and_t_cycles_the_theme() {
    for (env, ascii) in [
        (&[("LC_ALL", ""), ("LC_CTYPE", ""), ("LANG", "C")][..], true),
        (&[("LC_ALL", "POSIX"), ("LANG", "en_US.UTF-8")][..], true),
        (
            &[("LC_ALL", ""), ("LC_CTYPE", ""), ("LANG", "en_US.UTF-8")][..],
            false,
        ),
    ] {
        let mut explorer = Explorer::start(env);
        // Waits for the whole parameter panel: the first frame may arrive in pieces.
        if ascii {
            explorer.wait_for_screen("+ Parameters -");
            explorer.wait_for_screen("epsilon eps");
            let screen = explorer.screen();
            assert!(!screen.contains('┌'), "{env:?}\n{screen}");
        } else {
            explorer.wait_for_screen("┌ Parameters ─");
            explorer.wait_for_screen("epsilon ε");
        }
        explorer.type_bytes(b"T");
        explorer.wait_for_screen("theme light");
        explorer.type_bytes(b"q");
        let (status, _) = explorer.finish();
        assert_eq!(status.code(), Some(0), "{env:?}");
    }
    let mut explorer = Explorer::start_with(&["--ascii"], &[("LANG", "en_US.UTF-8")]);
    explorer.wait_for_screen("+ Parameters -");
    explorer.type_bytes(b"q");
    let (status, _) = explorer.finish();
    assert_eq!(status.code(), Some(0));
}
