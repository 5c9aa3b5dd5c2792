//! The program on a pseudo-terminal of its own, as a person at a terminal runs it: it is the
//! session leader with the pty as its controlling terminal (so crossterm talks to that pty and
//! nothing else), a thread collects everything it writes, the test types into the master side
//! and reads the screen through the `vt100` terminal emulator.

use std::io::{Read, Write};
use std::os::fd::{AsFd, AsRawFd, FromRawFd, IntoRawFd, OwnedFd};
use std::os::unix::process::CommandExt;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use nix::pty::Winsize;
use nix::sys::signal::{Signal, kill};
use nix::sys::termios::{LocalFlags, tcgetattr};
use nix::unistd::Pid;

use super::wait::{eventually_or, until};

pub const ENTER_ALTERNATE: &str = "\x1b[?1049h";
pub const LEAVE_ALTERNATE: &str = "\x1b[?1049l";
pub const SHOW_CURSOR: &str = "\x1b[?25h";

/// A pty whose two sides are closed on exec, so that a program started by a test running at
/// the same time cannot keep this one's terminal open (`openpty` leaves both inheritable).
struct Pty {
    master: OwnedFd,
    slave: OwnedFd,
}

fn cloexec_pty(size: &Winsize) -> Pty {
    use nix::fcntl::OFlag;
    use nix::pty::{grantpt, posix_openpt, ptsname_r, unlockpt};
    use std::os::unix::fs::OpenOptionsExt;
    let master = posix_openpt(OFlag::O_RDWR | OFlag::O_NOCTTY | OFlag::O_CLOEXEC).unwrap();
    grantpt(&master).unwrap();
    unlockpt(&master).unwrap();
    let name = ptsname_r(&master).unwrap();
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

/// `beamfric ARGS` on a pty of its own.
pub struct PtyProcess {
    child: Child,
    /// (columns, rows).
    size: (u16, u16),
    master: Option<OwnedFd>,
    writer: Option<std::fs::File>,
    output: Arc<Mutex<Vec<u8>>>,
    stop: Arc<AtomicBool>,
    reader: Option<JoinHandle<()>>,
}

impl PtyProcess {
    /// Starts `beamfric ARGS` with `env` on a pty of `size` (columns, rows), `TERM` an xterm's,
    /// without `NO_COLOR` or an injected panic unless `env` says so.
    pub fn start(args: &[&str], env: &[(&str, &str)], size: (u16, u16)) -> PtyProcess {
        let winsize = Winsize {
            ws_row: size.1,
            ws_col: size.0,
            ws_xpixel: 0,
            ws_ypixel: 0,
        };
        let pty = cloexec_pty(&winsize);
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
            .env_remove(beamfric::tui::INJECT_PANIC)
            .envs(env.iter().copied());
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
        let mut source = std::fs::File::from(pty.master.try_clone().unwrap());
        let sink = Arc::clone(&output);
        let stop = Arc::new(AtomicBool::new(false));
        let stopped = Arc::clone(&stop);
        let reader = std::thread::spawn(move || {
            use nix::poll::{PollFd, PollFlags, PollTimeout, poll};
            let mut buffer = [0u8; 4096];
            // Ends with EIO once the child and every copy of the slave side are gone (all it
            // wrote has been read by then), or when told to (`hang_up`), which closes this
            // copy of the master. The poll's timeout is how often it looks whether to stop.
            while !stopped.load(Ordering::Relaxed) {
                let mut fds = [PollFd::new(source.as_fd(), PollFlags::POLLIN)];
                match poll(&mut fds, PollTimeout::from(50u16)) {
                    Ok(0) => continue,
                    Ok(_) => {}
                    Err(_) => break,
                }
                match source.read(&mut buffer) {
                    Ok(0) | Err(_) => break,
                    Ok(n) => sink.lock().unwrap().extend_from_slice(&buffer[..n]),
                }
            }
        });
        let writer = std::fs::File::from(pty.master.try_clone().unwrap());
        PtyProcess {
            child,
            size,
            master: Some(pty.master),
            writer: Some(writer),
            output,
            stop,
            reader: Some(reader),
        }
    }

    /// The terminal's window changes to `size` (columns, rows): the kernel tells the program
    /// (SIGWINCH), and the screen is read at the new size from then on.
    pub fn resize(&mut self, size: (u16, u16)) {
        let winsize = Winsize {
            ws_row: size.1,
            ws_col: size.0,
            ws_xpixel: 0,
            ws_ypixel: 0,
        };
        let master = self.master.as_ref().expect("not hung up").as_raw_fd();
        // SAFETY: TIOCSWINSZ reads one `winsize` from the pointer.
        let set = unsafe { nix::libc::ioctl(master, nix::libc::TIOCSWINSZ, &winsize) };
        assert_eq!(set, 0, "set the window size");
        self.size = size;
    }

    pub fn pid(&self) -> Pid {
        Pid::from_raw(self.child.id() as i32)
    }

    /// How many bytes it has written so far (a mark for [`PtyProcess::text_since`]).
    pub fn written(&self) -> usize {
        self.output.lock().unwrap().len()
    }

    /// Everything written so far, as text.
    pub fn text(&self) -> String {
        text_of(&self.output, 0)
    }

    /// What was written from `mark` (a [`PtyProcess::written`]) on.
    pub fn text_since(&self, mark: usize) -> String {
        text_of(&self.output, mark)
    }

    /// A terminal emulator that has been fed everything written so far.
    pub fn terminal(&self) -> vt100::Parser {
        terminal_of(&self.output, self.size, None)
    }

    /// The screen as a terminal shows it now.
    pub fn screen(&self) -> String {
        self.terminal().screen().contents()
    }

    /// The alternate screen as it last was before the program left it.
    pub fn last_frame(&self) -> String {
        let end = {
            let output = self.output.lock().unwrap();
            let leave = LEAVE_ALTERNATE.as_bytes();
            output.windows(leave.len()).rposition(|w| w == leave)
        };
        terminal_of(&self.output, self.size, end)
            .screen()
            .contents()
    }

    /// Waits until the output contains `needle` after the switch to the alternate screen.
    pub fn wait_for(&self, needle: &str) {
        let output = &self.output;
        eventually_or(
            &format!("{needle:?} is written on the alternate screen"),
            || {
                let text = text_of(output, 0);
                text.find(ENTER_ALTERNATE)
                    .is_some_and(|at| text[at..].contains(needle))
            },
            || format!("the output so far:\n{:?}", text_of(output, 0)),
        );
    }

    /// Waits until the screen shows `needle`.
    pub fn wait_for_screen(&self, needle: &str) {
        let (output, size) = (&self.output, self.size);
        eventually_or(
            &format!("{needle:?} is shown"),
            || screen_of(output, size).contains(needle),
            || format!("the screen:\n{}", screen_of(output, size)),
        );
    }

    pub fn type_bytes(&mut self, bytes: &[u8]) {
        let writer = self.writer.as_mut().expect("the terminal is open");
        writer.write_all(bytes).unwrap();
        writer.flush().unwrap();
    }

    /// Whether it is still running (it has not exited).
    pub fn is_running(&mut self) -> bool {
        self.child.try_wait().unwrap().is_none()
    }

    pub fn signal(&self, signal: Signal) {
        kill(self.pid(), signal).unwrap();
    }

    /// Closes every copy of the pty's master side: the terminal is gone, as when a terminal
    /// window or an SSH connection closes.
    pub fn hang_up(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        self.writer = None;
        self.master = None;
        // The reader drops its copy when it sees the stop.
        self.join_reader();
    }

    /// Waits for the exit and for the reader to have read everything written; returns the
    /// exit status.
    pub fn exit(&mut self) -> ExitStatus {
        let (child, output, size) = (&mut self.child, &self.output, self.size);
        let status = until(
            "the program exits",
            || child.try_wait().unwrap(),
            || format!("the screen:\n{}", screen_of(output, size)),
        );
        self.join_reader();
        status
    }

    /// The pty's line discipline as the program left it.
    pub fn local_flags(&self) -> LocalFlags {
        tcgetattr(self.master.as_ref().expect("open").as_fd())
            .unwrap()
            .local_flags
    }

    /// Waits for the exit, then checks that the terminal was given back (the alternate screen
    /// left, the cursor shown, line mode with echo and signals); returns the status and what
    /// was written from the first restoration on.
    pub fn finish(&mut self) -> (ExitStatus, String) {
        let status = self.exit();
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
        let flags = self.local_flags();
        assert!(
            flags.contains(LocalFlags::ICANON | LocalFlags::ECHO | LocalFlags::ISIG),
            "the pty is still in raw mode: {flags:?}"
        );
        (status, text[left..].to_string())
    }

    /// Waits until the reader has ended (it looks whether to stop at every poll).
    fn join_reader(&mut self) {
        if let Some(reader) = self.reader.take() {
            let output = &self.output;
            eventually_or(
                "the pty's reader ends",
                || reader.is_finished(),
                || format!("the output:\n{:?}", text_of(output, 0)),
            );
            reader.join().expect("the reader does not panic");
        }
    }
}

impl Drop for PtyProcess {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn text_of(output: &Mutex<Vec<u8>>, from: usize) -> String {
    String::from_utf8_lossy(&output.lock().unwrap()[from..]).into_owned()
}

/// A terminal of `size` (columns, rows) fed the output up to byte `end` (all of it: `None`).
fn terminal_of(output: &Mutex<Vec<u8>>, size: (u16, u16), end: Option<usize>) -> vt100::Parser {
    let output = output.lock().unwrap();
    let mut parser = vt100::Parser::new(size.1, size.0, 0);
    parser.process(&output[..end.unwrap_or(output.len())]);
    parser
}

fn screen_of(output: &Mutex<Vec<u8>>, size: (u16, u16)) -> String {
    terminal_of(output, size, None).screen().contents()
}
