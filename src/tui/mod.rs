//! The explorer: a live terminal UI (ratatui + crossterm) that re-solves on every keystroke and
//! charts the trade-offs. Built like ratatui's "Elm architecture" recipe: [`app::App`] is the
//! state, [`update::update`] the only function that changes it (it takes [`action::Action`]s),
//! and [`view::draw`] draws it without changing anything. The same state, update and drawing
//! serve the terminal ([`run`]) and headless rendering ([`render`]).

pub mod action;
pub mod app;
mod ascii;
pub mod params;
pub mod studies;
mod terminal;
pub mod update;
pub mod view;

use std::io;
use std::time::Duration;

use crossterm::event::{self, Event};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::buffer::Buffer;
use ratatui::style::{Color, Modifier};

use crate::scene::Scene;
use action::{Action, from_key};
use app::{App, Look};

pub use ascii::ascii_char;

/// How long the loop waits for a key before looking for study results.
const POLL: Duration = Duration::from_millis(50);

/// Set to `main` or `worker` to make the explorer panic after its first frame (on the main
/// thread or in a study), to test that the terminal is restored.
pub const INJECT_PANIC: &str = "BEAMFRIC_INJECT_PANIC";

/// How the explorer ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ending {
    /// The user quit.
    Quit,
    /// A signal (its number) ended it; the terminal was restored.
    Signal(i32),
}

/// Runs the explorer in the terminal until the user quits or a signal arrives. The terminal is
/// restored on return, on a panic and on SIGINT, SIGTERM and SIGHUP.
pub fn run(scene: Scene, source: String, look: Look) -> Result<Ending, String> {
    let app = App::new(scene, source, look, true)?;
    let mut session =
        terminal::Session::start().map_err(|e| format!("cannot open the terminal: {e}"))?;
    let result = event_loop(&mut session, app);
    drop(session);
    result.map_err(|e| format!("terminal error: {e}"))
}

fn event_loop(session: &mut terminal::Session, mut app: App) -> io::Result<Ending> {
    let injected = std::env::var(INJECT_PANIC).unwrap_or_default();
    let size = session.terminal.size()?;
    update::update(&mut app, Action::Resize(size.width, size.height));
    let mut worker = studies::Worker::start(injected == "worker");
    loop {
        worker.request(app.pending_studies());
        session.terminal.draw(|frame| view::draw(frame, &app))?;
        if injected == "main" {
            panic!("injected panic ({INJECT_PANIC}=main)");
        }
        if app.quit {
            return Ok(Ending::Quit);
        }
        if let Some(signal) = session.signal() {
            return Ok(Ending::Signal(signal));
        }
        if event::poll(POLL)? {
            // Apply every event that is waiting, then draw once.
            loop {
                match event::read()? {
                    Event::Key(key) => {
                        if let Some(action) = from_key(key) {
                            update::update(&mut app, action);
                        }
                    }
                    Event::Resize(width, height) => {
                        update::update(&mut app, Action::Resize(width, height))
                    }
                    _ => {}
                }
                if app.quit || !event::poll(Duration::ZERO)? {
                    break;
                }
            }
        }
        for result in worker.poll() {
            app.accept(result);
        }
    }
}

/// What a headless render needs besides the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RenderOptions {
    pub width: u16,
    pub height: u16,
    pub look: Look,
    /// Show run times (frames then depend on the clock).
    pub timings: bool,
}

/// The explorer's frame after `actions`, with every study run to completion: exactly what the
/// terminal would show, drawn by the same code into an in-memory buffer.
pub fn render(
    scene: Scene,
    source: String,
    actions: &[Action],
    options: RenderOptions,
) -> Result<Buffer, String> {
    let app = prepare(scene, source, actions, options)?;
    draw_to_buffer(&app, options.width, options.height)
}

/// The explorer's state after `actions` (stopping at a quit), with every study the visible
/// panels need run to completion.
pub fn prepare(
    scene: Scene,
    source: String,
    actions: &[Action],
    options: RenderOptions,
) -> Result<App, String> {
    let mut app = App::new(scene, source, options.look, options.timings)?;
    update::update(&mut app, Action::Resize(options.width, options.height));
    for action in actions {
        if app.quit {
            break;
        }
        update::update(&mut app, action.clone());
    }
    loop {
        let requests = app.pending_studies();
        if requests.is_empty() {
            break;
        }
        for request in &requests {
            app.accept(studies::run_now(request));
        }
    }
    Ok(app)
}

/// Draws the app into a fresh buffer of the given size.
pub fn draw_to_buffer(app: &App, width: u16, height: u16) -> Result<Buffer, String> {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).map_err(|e| e.to_string())?;
    terminal
        .draw(|frame| view::draw(frame, app))
        .map_err(|e| e.to_string())?;
    Ok(terminal.backend().buffer().clone())
}

/// The buffer as text: one line per row, each exactly as wide as the buffer; with `color`,
/// ANSI escapes for the styles.
pub fn buffer_to_text(buffer: &Buffer, color: bool) -> String {
    let area = buffer.area;
    let mut out = String::with_capacity((area.width as usize + 8) * area.height as usize);
    for y in 0..area.height {
        let mut current: Option<(Color, Color, Modifier)> = None;
        for x in 0..area.width {
            let cell = &buffer[(x, y)];
            if color {
                let style = (cell.fg, cell.bg, cell.modifier);
                if current != Some(style) {
                    out.push_str(&sgr(style));
                    current = Some(style);
                }
            }
            out.push_str(cell.symbol());
        }
        if color {
            out.push_str("\x1b[0m");
        }
        out.push('\n');
    }
    out
}

fn sgr((fg, bg, modifier): (Color, Color, Modifier)) -> String {
    let mut codes = vec!["0".to_string()];
    if modifier.contains(Modifier::BOLD) {
        codes.push("1".into());
    }
    if modifier.contains(Modifier::REVERSED) {
        codes.push("7".into());
    }
    let color_code = |c: Color, base: u8| -> Option<String> {
        let index = match c {
            Color::Black => 0,
            Color::Red => 1,
            Color::Green => 2,
            Color::Yellow => 3,
            Color::Blue => 4,
            Color::Magenta => 5,
            Color::Cyan => 6,
            Color::Gray | Color::White => 7,
            Color::DarkGray => return Some(format!("{}", base + 60)),
            _ => return None,
        };
        Some(format!("{}", base + index))
    };
    codes.extend(color_code(fg, 30));
    codes.extend(color_code(bg, 40));
    format!("\x1b[{}m", codes.join(";"))
}
