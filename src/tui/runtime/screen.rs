//! What the event loop draws on: a [`Screen`] (the local terminal, or a remote one over SSH),
//! and the sequences that switch the terminal's mouse reports on and off.

use std::io::{self, Write};

use ratatui::Terminal;
use ratatui::backend::CrosstermBackend;

/// Asks the terminal to report presses, drags and releases (modes 1000 and 1002, no motion
/// without a button: little traffic over SSH), SGR-encoded (1006, any column); Shift+drag
/// still selects text in the usual terminals.
pub const MOUSE_ON: &str = "\x1b[?1000h\x1b[?1002h\x1b[?1006h";
/// Stops the reports (also the any-motion mode 1003 and the urxvt encoding 1015 that other
/// programs may have left on).
pub const MOUSE_OFF: &str = "\x1b[?1006l\x1b[?1015l\x1b[?1003l\x1b[?1002l\x1b[?1000l";

/// Where the loop draws: the local terminal (`Session`) or a remote one (an SSH channel).
/// Nothing here may query the terminal: its answers would arrive on the input the explorer
/// reads itself, and a remote terminal is known only by what its client said.
pub trait Screen {
    type Out: Write;
    fn terminal(&mut self) -> &mut Terminal<CrosstermBackend<Self::Out>>;
    /// The size in cells (columns, rows), as last known.
    fn size(&mut self) -> io::Result<(u16, u16)>;
    /// The terminal now has this size: draw the next frame whole at it.
    fn resize(&mut self, width: u16, height: u16) -> io::Result<()>;
    /// Ctrl-Z or SIGTSTP: give the terminal back until resumed, then redraw it whole. Returns
    /// `false` when this screen cannot be suspended (a remote one).
    fn suspend(&mut self) -> io::Result<bool>;
    /// Forgets what was drawn, so the next frame is drawn whole.
    fn redraw_all(&mut self) -> io::Result<()>;
    /// Called before every frame; `true` when the frame will be drawn whole (a remote screen
    /// whose client missed a frame).
    fn before_frame(&mut self) -> io::Result<bool> {
        Ok(false)
    }
    /// Shows `lines` as plain text on the terminal's own screen, outside the explorer's, to
    /// select and copy whole (a remote screen: `s` without a save directory). `false` where
    /// the explorer shows it itself instead (the local terminal).
    fn show_text(&mut self, _lines: &[String]) -> io::Result<bool> {
        Ok(false)
    }
    /// Back from [`Screen::show_text`]: the explorer's screen again, drawn whole.
    fn end_text(&mut self) -> io::Result<()> {
        Ok(())
    }
}
