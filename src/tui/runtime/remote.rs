//! The explorer on a remote terminal (an SSH channel): the same event loop, state, update and
//! drawing as the local explorer, drawn through any `Write` into a ratatui viewport of the
//! size the client reports (`Viewport::Fixed`: nothing asks the terminal anything), with the
//! client's bytes, window changes and hangup fed in through a [`Feed`].

use std::io::{self, Write};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use crossterm::cursor::{Hide, Show};
use crossterm::event::{DisableBracketedPaste, EnableBracketedPaste};
use crossterm::queue;
use crossterm::terminal::{EnterAlternateScreen, LeaveAlternateScreen};
use ratatui::backend::CrosstermBackend;
use ratatui::layout::Rect;
use ratatui::{Terminal, TerminalOptions, Viewport};

use crate::format::printable;
use crate::tui::state::{App, Ending, Mode};

pub use super::event_loop::AfterFrame;
use super::event_loop::{LoopOptions, event_loop};
use super::screen::Screen;

pub use super::feed::{Events, Feed, MAX_SIZE, UNKNOWN_SIZE, clamp_size, events};

/// The share of one core a remote explorer's own thread may use on average (drawing and
/// applying input; its solves run on the shared cores): a flood is slowed to it.
pub const UI_SHARE: f64 = 0.5;

/// A remote terminal: a fixed viewport of the client's size.
struct RemoteScreen<W: Write> {
    terminal: Terminal<CrosstermBackend<W>>,
    size: (u16, u16),
    frames_lost: Option<Arc<AtomicBool>>,
    /// The client's main screen shows text ([`Screen::show_text`]): nothing clears it (a
    /// resize or a whole redraw waits until the explorer is back).
    showing_text: bool,
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
        self.redraw_all()
    }

    fn suspend(&mut self) -> io::Result<bool> {
        Ok(false)
    }

    fn redraw_all(&mut self) -> io::Result<()> {
        if self.showing_text {
            return Ok(());
        }
        let (width, height) = self.size;
        self.terminal.resize(Rect::new(0, 0, width, height))
    }

    /// The text on the client's main screen, where its terminal keeps it whole (long lines
    /// unwrapped by us, all of it in the scrollback) for the mouse to select.
    fn show_text(&mut self, lines: &[String]) -> io::Result<bool> {
        let output = self.terminal.backend_mut();
        queue!(output, LeaveAlternateScreen, Show)?;
        write!(output, "\r\n")?;
        for line in lines {
            write!(output, "{line}\r\n")?;
        }
        write!(
            output,
            "\r\n(beamfric: the scene as TOML above, to copy; any key returns to the explorer)\r\n"
        )?;
        output.flush()?;
        self.showing_text = true;
        Ok(true)
    }

    fn end_text(&mut self) -> io::Result<()> {
        queue!(self.terminal.backend_mut(), EnterAlternateScreen, Hide)?;
        self.showing_text = false;
        self.redraw_all()
    }

    fn before_frame(&mut self) -> io::Result<bool> {
        // A frame the client never got: what it shows is not what ratatui remembers.
        if let Some(lost) = &self.frames_lost
            && lost.swap(false, Ordering::AcqRel)
        {
            // Not `Terminal::clear`: it asks the terminal where its cursor is.
            self.redraw_all()?;
            return Ok(true);
        }
        Ok(false)
    }
}

/// How a remote explorer runs beyond its terminal.
#[derive(Default)]
pub struct RemoteOptions {
    /// End the session after this long without input.
    pub idle_timeout: Option<Duration>,
    /// Sees the state after every frame (a presenter publishes it).
    pub after_frame: Option<AfterFrame>,
    /// The session's turn on the server's shared cores.
    pub cores: Option<super::cores::Share>,
    /// Set by the output when it dropped a frame for a client that does not read: the next
    /// frame is then drawn whole.
    pub frames_lost: Option<Arc<AtomicBool>>,
    /// Told (the server's log) when the session ended for its user with work that a save
    /// directory did not take: printed on their terminal instead, or lost with the connection.
    pub work_not_saved: Option<Box<dyn FnOnce(String) + Send>>,
}

/// Runs the explorer on a remote terminal of `size` (columns, rows) that `output` writes to,
/// until the user quits, the feed hangs up, or nothing arrives for the idle timeout. The
/// alternate screen is entered first and left at the end (a write error there is ignored:
/// the client may be gone). Its workers have ended when it returns. Returns how it ended.
pub fn run_remote(
    mut app: App,
    mut output: impl Write,
    size: (u32, u32),
    events: Events,
    remote: RemoteOptions,
) -> io::Result<Ending> {
    let RemoteOptions {
        idle_timeout,
        after_frame,
        cores,
        frames_lost,
        work_not_saved,
    } = remote;
    let (width, height) = clamp_size(size.0, size.1);
    // The session's colours are its look's (its client's NO_COLOR, its terminal): crossterm
    // would otherwise drop every colour code when the server's own process has NO_COLOR.
    crossterm::style::force_color_output(true);
    // Bracketed paste as locally (`terminal`): without it the client's terminal sends a paste
    // as keys, and every `s`, `d` or `q` in the text would run.
    queue!(output, EnterAlternateScreen, EnableBracketedPaste, Hide)?;
    let options = TerminalOptions {
        viewport: Viewport::Fixed(Rect::new(0, 0, width, height)),
    };
    let terminal = Terminal::with_options(CrosstermBackend::new(output), options)?;
    let mut screen = RemoteScreen {
        terminal,
        size: (width, height),
        frames_lost,
        showing_text: false,
    };
    // Start on a clean screen: the client's shell prompt may be on it.
    screen.redraw_all()?;
    let loop_options = LoopOptions {
        idle_timeout,
        inject_panic: String::new(),
        after_frame,
        cores,
        wait_for_workers: true,
        ui_share: Some(UI_SHARE),
    };
    let ending = event_loop(&mut screen, &mut app, &events, loop_options);
    // Shows the cursor, so that ratatui's `Drop` has nothing left to do (it would print on
    // the server's stderr on failure).
    let _ = screen.terminal.show_cursor();
    let output = screen.terminal.backend_mut();
    let _ = queue!(output, DisableBracketedPaste, LeaveAlternateScreen, Show);
    if let (Ok(Ending::Idle), Some(limit)) = (&ending, idle_timeout) {
        let _ = write!(
            output,
            "beamfric: closed after {} s without input\r\n",
            limit.as_secs()
        );
        let _ = write_unsaved_work(output, &app, app.saved_at_closing.as_deref());
    } else if let Mode::ClassEnded { by, saved } = &app.mode {
        // However the closing screen was left (a key, the server's grace, a key already on its
        // way), the work stays on the client's own screen, whole and unwrapped.
        let _ = write!(
            output,
            "beamfric: the class was ended by {}\r\n",
            printable(by)
        );
        let _ = write_unsaved_work(output, &app, saved.as_deref());
    }
    if let (Some(tell), Some(note)) = (work_not_saved, work_not_saved_note(&app, &ending)) {
        tell(note);
    }
    // Not flushed here: the output sends what is left when it is dropped, with the patience
    // a last frame deserves (a served session's output drops frames a client does not read).
    ending
}

/// After an idle session's end or the class's, on the client's own screen (it stays in the
/// scrollback): where its unsaved changes went (`saved`, the names in the save directory),
/// and what was not saved as TOML to copy: the scene shown, and every lesson step left with
/// changes. Nothing when there were none.
fn write_unsaved_work(output: &mut impl Write, app: &App, saved: Option<&str>) -> io::Result<()> {
    if let Some(names) = saved {
        write!(
            output,
            "beamfric: your changes are saved as {} in the server's save directory\r\n",
            printable(names)
        )?;
    }
    if app.modified() {
        write!(
            output,
            "beamfric: your changes are not saved on the server; the scene as TOML, to copy \
             into a file:\r\n\r\n"
        )?;
        write_toml(output, app.scene())?;
    }
    for step in app.changed_steps() {
        let (Some(edits), Some(place)) = (app.step_edits.get(&step), &app.exploration.lesson)
        else {
            continue;
        };
        write!(
            output,
            "\r\nbeamfric: your changes to lesson step {} ({}) are not saved on the server; as \
             TOML, to copy into a file:\r\n\r\n",
            step + 1,
            printable(&place.lesson.step(step).title)
        )?;
        write_toml(output, &edits.scene)?;
    }
    Ok(())
}

/// Where a session closed for its user (idle, hung up, the class ended) still holds unsaved
/// work although a save directory was there to take it (full, gone, unwritable): what the
/// server's log says of it.
fn work_not_saved_note(app: &App, ending: &io::Result<Ending>) -> Option<String> {
    let under_save_dir = matches!(app.save_policy, crate::tui::state::SavePolicy::Within(_));
    if !under_save_dir || !app.has_unsaved_work() {
        return None;
    }
    let who = app.owner.as_deref().unwrap_or("(no name)");
    let fate = match ending {
        Ok(Ending::Hangup) => "lost with the connection",
        Ok(Ending::Idle) => "printed on their terminal instead",
        _ if matches!(app.mode, Mode::ClassEnded { .. }) => "printed on their terminal instead",
        _ => return None,
    };
    Some(format!(
        "{}: unsaved changes not saved in the save directory; {fate}",
        printable(who)
    ))
}

/// `scene` as TOML, line by line, each line's controls made visible.
fn write_toml(output: &mut impl Write, scene: &crate::scene::Scene) -> io::Result<()> {
    for line in scene.to_toml().lines() {
        write!(output, "{}\r\n", printable(line))?;
    }
    Ok(())
}
