//! The terminal while the explorer runs: raw mode and the alternate screen on entry, and the
//! way back in every case — on return (a guard's `Drop`), on a panic of the main thread (a
//! panic hook that restores first, then lets the default hook report), and on SIGINT,
//! SIGTERM and SIGHUP (flags the event loop checks between events). A panic on another thread
//! (a study worker) does not touch the terminal: the worker catches it and its panel says so.

use std::io::{self, Stdout, stdout};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use crossterm::cursor::Show;
use crossterm::execute;
use crossterm::terminal::{
    EnterAlternateScreen, LeaveAlternateScreen, disable_raw_mode, enable_raw_mode,
};
use ratatui::Terminal;
use ratatui::backend::CrosstermBackend;

/// Leaves raw mode and the alternate screen; safe to call more than once.
pub fn restore() {
    let _ = disable_raw_mode();
    let _ = execute!(stdout(), LeaveAlternateScreen, Show);
}

/// Restores the terminal on drop.
pub struct Session {
    pub terminal: Terminal<CrosstermBackend<Stdout>>,
    signal: Arc<AtomicUsize>,
}

impl Session {
    /// Enters raw mode and the alternate screen, and arms the panic hook and the signal
    /// handlers.
    pub fn start() -> io::Result<Session> {
        install_panic_hook();
        let signal = Arc::new(AtomicUsize::new(0));
        for sig in [
            signal_hook::consts::SIGINT,
            signal_hook::consts::SIGTERM,
            signal_hook::consts::SIGHUP,
        ] {
            signal_hook::flag::register_usize(sig, Arc::clone(&signal), sig as usize)?;
        }
        enable_raw_mode()?;
        if let Err(e) = execute!(stdout(), EnterAlternateScreen) {
            restore();
            return Err(e);
        }
        match Terminal::new(CrosstermBackend::new(stdout())) {
            Ok(terminal) => Ok(Session { terminal, signal }),
            Err(e) => {
                restore();
                Err(e)
            }
        }
    }

    /// The signal received, if any (its number).
    pub fn signal(&self) -> Option<i32> {
        match self.signal.load(Ordering::Relaxed) {
            0 => None,
            sig => Some(sig as i32),
        }
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
            // Other threads: the study worker catches its panic and reports it in its panel;
            // printing here would scribble over the screen.
        }));
    });
}
