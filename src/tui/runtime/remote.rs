//! The explorer on a remote terminal (an SSH channel): the same event loop, state, update and
//! drawing as the local explorer, drawn through any `Write` into a ratatui viewport of the
//! size the client reports (`Viewport::Fixed`: nothing asks the terminal anything), with the
//! client's bytes, window changes and hangup fed in through a [`Feed`].

use std::io::{self, Write};
use std::sync::mpsc::{Receiver, Sender, channel};
use std::time::Duration;

use crossterm::cursor::{Hide, Show};
use crossterm::queue;
use crossterm::terminal::{EnterAlternateScreen, LeaveAlternateScreen};
use ratatui::backend::CrosstermBackend;
use ratatui::layout::Rect;
use ratatui::{Terminal, TerminalOptions, Viewport};

use crate::tui::state::{App, Ending, Exploration};

pub use super::event_loop::AfterFrame;
use super::event_loop::{Event, LoopOptions, event_loop};
use super::screen::Screen;

/// Largest terminal accepted, in cells (a hostile client could ask for 65535 × 65535).
pub const MAX_SIZE: (u16, u16) = (1000, 500);

/// The size assumed when a client reports none (zero: RFC 4254 says to ignore it).
pub const UNKNOWN_SIZE: (u16, u16) = (80, 24);

/// A size the client reported, within `1..=`[`MAX_SIZE`]; a zero is [`UNKNOWN_SIZE`].
pub fn clamp_size(width: u32, height: u32) -> (u16, u16) {
    let clamp = |v: u32, max: u16, unknown: u16| match v {
        0 => unknown,
        v => v.min(u32::from(max)) as u16,
    };
    (
        clamp(width, MAX_SIZE.0, UNKNOWN_SIZE.0),
        clamp(height, MAX_SIZE.1, UNKNOWN_SIZE.1),
    )
}

/// Where a remote terminal's events come from: its [`Feed`] and the loop's receiver.
pub struct Events {
    sender: Sender<Event>,
    receiver: Receiver<Event>,
}

/// What the connection tells a remote explorer. Cheap to clone; sending to an explorer that
/// has ended does nothing.
#[derive(Clone)]
pub struct Feed(Sender<Event>);

impl std::fmt::Debug for Feed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Feed")
    }
}

impl Feed {
    /// A feed into the loop that `sender` feeds (the local explorer's, see
    /// [`super::local::run_local`]).
    pub(super) fn new(sender: Sender<Event>) -> Feed {
        Feed(sender)
    }

    /// Bytes the client typed.
    pub fn bytes(&self, bytes: &[u8]) {
        let _ = self.0.send(Event::Bytes(bytes.to_vec()));
    }

    /// The client's window changed.
    pub fn resize(&self, width: u32, height: u32) {
        let (width, height) = clamp_size(width, height);
        let _ = self.0.send(Event::Resize(width, height));
    }

    /// The presenter's new state (follow mode).
    pub fn follow(&self, exploration: std::sync::Arc<Exploration>) {
        let _ = self.0.send(Event::Follow(exploration));
    }

    /// Draw again (something the frame shows changed outside the explorer).
    pub fn redraw(&self) {
        let _ = self.0.send(Event::Redraw);
    }

    /// The client went away.
    pub fn hangup(&self) {
        let _ = self.0.send(Event::Hangup);
    }
}

/// A new channel of events, and the feed that writes into it.
pub fn events() -> (Feed, Events) {
    let (sender, receiver) = channel();
    (Feed(sender.clone()), Events { sender, receiver })
}

/// A remote terminal: a fixed viewport of the client's size.
struct RemoteScreen<W: Write> {
    terminal: Terminal<CrosstermBackend<W>>,
    size: (u16, u16),
}

impl<W: Write> Screen for RemoteScreen<W> {
    type Out = W;

    fn terminal(&mut self) -> &mut Terminal<CrosstermBackend<W>> {
        &mut self.terminal
    }

    fn size(&mut self) -> io::Result<(u16, u16)> {
        Ok(self.size)
    }

    fn resize(&mut self, width: u16, height: u16) -> io::Result<()> {
        self.size = (width, height);
        self.terminal.resize(Rect::new(0, 0, width, height))
    }

    fn suspend(&mut self) -> io::Result<bool> {
        Ok(false)
    }

    fn redraw_all(&mut self) -> io::Result<()> {
        let (width, height) = self.size;
        self.terminal.resize(Rect::new(0, 0, width, height))
    }
}

/// Runs the explorer on a remote terminal of `size` (columns, rows) that `output` writes to,
/// until the user quits, the feed hangs up, or nothing arrives for `idle_timeout`. The
/// alternate screen is entered first and left at the end (a write error there is ignored:
/// the client may be gone). `after_frame` sees the state after every frame; `cores` is the
/// session's turn on the server's shared cores. Its workers have ended when it returns.
/// Returns how it ended.
pub fn run_remote(
    mut app: App,
    mut output: impl Write,
    size: (u32, u32),
    events: Events,
    idle_timeout: Option<Duration>,
    after_frame: Option<AfterFrame>,
    cores: Option<super::cores::Share>,
) -> io::Result<Ending> {
    let (width, height) = clamp_size(size.0, size.1);
    queue!(output, EnterAlternateScreen, Hide)?;
    let options = TerminalOptions {
        viewport: Viewport::Fixed(Rect::new(0, 0, width, height)),
    };
    let terminal = Terminal::with_options(CrosstermBackend::new(output), options)?;
    let mut screen = RemoteScreen {
        terminal,
        size: (width, height),
    };
    // Start on a clean screen: the client's shell prompt may be on it.
    screen.redraw_all()?;
    let loop_options = LoopOptions {
        idle_timeout,
        inject_panic: String::new(),
        after_frame,
        cores,
        wait_for_workers: true,
    };
    let ending = event_loop(
        &mut screen,
        &mut app,
        &events.sender,
        &events.receiver,
        loop_options,
    );
    // Shows the cursor, so that ratatui's `Drop` has nothing left to do (it would print on
    // the server's stderr on failure).
    let _ = screen.terminal.show_cursor();
    let output = screen.terminal.backend_mut();
    let _ = queue!(output, LeaveAlternateScreen, Show);
    if let (Ok(Ending::Idle), Some(limit)) = (&ending, idle_timeout) {
        let _ = write!(
            output,
            "beamfric: closed after {} s without input\r\n",
            limit.as_secs()
        );
    }
    let _ = output.flush();
    ending
}
