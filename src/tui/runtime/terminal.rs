//! The terminal while the explorer runs: raw mode and the alternate screen on entry, and the
//! way back in every case — on return (a guard's `Drop`), on a panic of the main thread (a
//! panic hook that restores first, then lets the default hook report), on a signal (the event
//! loop hears SIGINT, SIGTERM and SIGHUP through [`Signals`] and returns), on a hangup (end of
//! input), and around a suspension (Ctrl-Z or SIGTSTP: leave, stop, come back and redraw).
//! Mouse reports are asked for by the event loop (the same for a remote terminal) and stopped
//! here too.
//! A panic on another thread (a worker) does not touch the terminal: the worker catches it.

use std::io::{self, stdout};

use crossterm::cursor::Show;
use crossterm::event::{DisableBracketedPaste, EnableBracketedPaste};
use crossterm::execute;
use crossterm::terminal::{
    EnterAlternateScreen, LeaveAlternateScreen, disable_raw_mode, enable_raw_mode,
};
use ratatui::Terminal;
use ratatui::backend::CrosstermBackend;

use super::record::{Output, RecordTap};
use super::screen::{MOUSE_OFF, Screen};

/// The signals the explorer handles: the three that end it, the window size, and job control.
pub const SIGNALS: [i32; 6] = [
    signal_hook::consts::SIGINT,
    signal_hook::consts::SIGTERM,
    signal_hook::consts::SIGHUP,
    signal_hook::consts::SIGWINCH,
    signal_hook::consts::SIGTSTP,
    signal_hook::consts::SIGCONT,
];

/// Leaves raw mode and the alternate screen and stops mouse reports; safe to call more than
/// once, and when the terminal is gone.
pub fn restore() {
    let _ = disable_raw_mode();
    let mut out = stdout();
    // The event loop asks for the mouse while it runs.
    let _ = io::Write::write_all(&mut out, MOUSE_OFF.as_bytes());
    let _ = execute!(out, DisableBracketedPaste, LeaveAlternateScreen, Show);
}

fn enter() -> io::Result<()> {
    enable_raw_mode()?;
    // Pasted text arrives marked, so that a paste is never run as commands.
    if let Err(e) = execute!(stdout(), EnterAlternateScreen, EnableBracketedPaste) {
        restore();
        return Err(e);
    }
    Ok(())
}

/// The terminal in raw mode on the alternate screen; restored on drop.
pub struct Session {
    /// Never dropped: ratatui's `Drop` shows the cursor and, when that fails because the
    /// terminal is gone, prints with `eprintln!` — which panics on a closed terminal.
    /// [`restore`] shows the cursor instead, ignoring failures.
    pub terminal: std::mem::ManuallyDrop<Terminal<CrosstermBackend<Output>>>,
    /// Where a recording's events go (a new size), when one is made.
    record: Option<RecordTap>,
    /// Ctrl-Z and SIGTSTP stop the process: not where it serves a class (`present`), whose
    /// students would all stop with it.
    pub may_suspend: bool,
}

impl Session {
    /// Enters raw mode and the alternate screen, and arms the panic hook; what is drawn also
    /// goes to `record` when a recording is made.
    pub fn start(record: Option<RecordTap>) -> io::Result<Session> {
        install_panic_hook();
        enter()?;
        match Terminal::new(CrosstermBackend::new(Output::new(record.clone()))) {
            Ok(terminal) => Ok(Session {
                terminal: std::mem::ManuallyDrop::new(terminal),
                record,
                may_suspend: true,
            }),
            Err(e) => {
                restore();
                Err(e)
            }
        }
    }

    /// Ctrl-Z or SIGTSTP: gives the terminal back, stops the process until SIGCONT, then takes
    /// the terminal again; the caller redraws everything.
    pub fn suspend(&mut self) -> io::Result<()> {
        restore();
        // SIGSTOP cannot be caught, so the stop happens even though SIGTSTP is handled.
        signal_hook::low_level::raise(signal_hook::consts::SIGSTOP)?;
        enter()?;
        self.redraw_all()
    }

    /// Clears the screen and forgets what was drawn, so the next frame is drawn whole (after a
    /// suspension, or when another program drew over the screen). Unlike ratatui's `clear`, it
    /// does not ask the terminal for the cursor position: the answer would arrive on the input
    /// the explorer reads itself.
    pub fn redraw_all(&mut self) -> io::Result<()> {
        let size = self.terminal.size()?;
        self.terminal
            .resize(ratatui::layout::Rect::new(0, 0, size.width, size.height))
    }
}

impl Screen for Session {
    type Out = Output;

    fn terminal(&mut self) -> &mut Terminal<CrosstermBackend<Output>> {
        &mut self.terminal
    }

    fn size(&mut self) -> io::Result<(u16, u16)> {
        let size = self.terminal.size()?;
        Ok((size.width, size.height))
    }

    /// The local terminal follows its size by itself (ratatui resizes on the next draw); a
    /// recording notes the new size before that frame (each frame's output is sent whole at
    /// its flush, so nothing of the last one comes after).
    fn resize(&mut self, width: u16, height: u16) -> io::Result<()> {
        if let Some(tap) = &self.record {
            tap.resize(width, height);
        }
        Ok(())
    }

    fn suspend(&mut self) -> io::Result<bool> {
        if !self.may_suspend {
            return Ok(false);
        }
        Session::suspend(self)?;
        Ok(true)
    }

    fn redraw_all(&mut self) -> io::Result<()> {
        Session::redraw_all(self)
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        restore();
    }
}

fn install_panic_hook() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if std::thread::current().name() == Some("main") {
                restore();
                default(info);
            }
            // Other threads: workers catch their panic and report it in the frame; printing
            // here would scribble over the screen.
        }));
    });
}
