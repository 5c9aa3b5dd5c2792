//! The explorer in the local terminal: raw mode and the alternate screen ([`super::terminal`]),
//! a thread reading the terminal's bytes, a thread turning signals into events, and the event
//! loop on the UI thread until the explorer ends.

use std::io::{self, Read};
use std::sync::mpsc::Sender;

use crate::tui::state::{App, Ending};

use super::event_loop::{AfterFrame, Event, INJECT_PANIC, LoopOptions, event_loop};
use super::feed::{Feed, events};
use super::record::RecordTap;
use super::terminal::{SIGNALS, Session};

/// Why the local explorer could not run (or stopped on a terminal error).
#[derive(Debug)]
pub enum TerminalError {
    /// Signals could not be handled.
    Signals(io::Error),
    /// The terminal could not be opened (raw mode, the alternate screen).
    Open(io::Error),
    /// The terminal could not be read.
    Read(io::Error),
    /// Drawing or resizing failed while running.
    Io(io::Error),
}

impl std::fmt::Display for TerminalError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TerminalError::Signals(e) => write!(f, "cannot handle signals: {e}"),
            TerminalError::Open(e) => write!(f, "cannot open the terminal: {e}"),
            TerminalError::Read(e) => write!(f, "cannot read the terminal: {e}"),
            TerminalError::Io(e) => write!(f, "terminal error: {e}"),
        }
    }
}

impl std::error::Error for TerminalError {}

/// Runs `app` in the local terminal until the user quits, a signal ends it, or the terminal
/// hangs up. The terminal is restored on return, on a panic, on SIGINT, SIGTERM and SIGHUP,
/// and around a suspension. `attach` is given a feed into the loop (for events from
/// elsewhere: the hub of a server running in the same process, `beamfric present`) and
/// returns what to call after every frame.
pub fn run_local(
    mut app: App,
    attach: impl FnOnce(Feed) -> Option<AfterFrame>,
    record: Option<RecordTap>,
) -> Result<Ending, TerminalError> {
    let (feed, events) = events();
    let sender = events.sender.clone();
    start_signal_thread(sender.clone()).map_err(TerminalError::Signals)?;
    let after_frame = attach(feed);
    let mut session = Session::start(record).map_err(TerminalError::Open)?;
    // A presenter's process serves the class too: stopped, it would stop every student.
    session.may_suspend = app.follow.is_none();
    start_input_thread(sender.clone()).map_err(TerminalError::Read)?;
    let options = LoopOptions {
        idle_timeout: None,
        inject_panic: std::env::var(INJECT_PANIC).unwrap_or_default(),
        after_frame,
        cores: None,
        wait_for_workers: false,
        ui_share: None,
    };
    let result = event_loop(&mut session, &mut app, &events, options);
    drop(session);
    result.map_err(TerminalError::Io)
}

/// Reads the terminal's bytes until end of file or an error, which is a hangup.
fn start_input_thread(sender: Sender<Event>) -> io::Result<()> {
    use std::io::IsTerminal;
    let mut input: Box<dyn Read + Send> = if io::stdin().is_terminal() {
        Box::new(io::stdin())
    } else {
        Box::new(std::fs::File::open("/dev/tty")?)
    };
    std::thread::Builder::new()
        .name("input".into())
        .spawn(move || {
            let mut buffer = [0u8; 4096];
            loop {
                match input.read(&mut buffer) {
                    Ok(0) => break,
                    Ok(n) => {
                        if sender.send(Event::Bytes(buffer[..n].to_vec())).is_err() {
                            return;
                        }
                    }
                    Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                    Err(_) => break,
                }
            }
            let _ = sender.send(Event::Hangup);
        })?;
    Ok(())
}

fn start_signal_thread(sender: Sender<Event>) -> io::Result<()> {
    let mut signals = signal_hook::iterator::Signals::new(SIGNALS)?;
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            for signal in signals.forever() {
                if sender.send(Event::Signal(signal)).is_err() {
                    return;
                }
            }
        })?;
    Ok(())
}
