//! The explorer: a live terminal UI (ratatui + crossterm) that re-solves on every keystroke and
//! charts the trade-offs. Built like ratatui's "Elm architecture" recipe: [`app::App`] is the
//! state, [`update::update`] the only function that changes it (it takes
//! [`keymap::Action`]s, which [`keymap::action_for`] makes of keys), and [`view::draw`] draws it
//! without changing anything. The same state, update and drawing serve the terminal ([`run`])
//! and headless rendering ([`render`]).

pub mod app;
pub mod keymap;
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

use crate::scene::LoadedScene;
use app::{App, Look};
use keymap::{Action, Key, action_for};

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
pub fn run(loaded: LoadedScene, look: Look) -> Result<Ending, String> {
    let app = App::new(loaded, look, true)?;
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
                    Event::Key(event) => {
                        if let Some(key) = Key::from_event(event) {
                            press(&mut app, key);
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
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RenderOptions {
    pub width: u16,
    pub height: u16,
    pub look: Look,
    /// Show run times (frames then depend on the clock).
    pub timings: bool,
    /// The only directory a save in the keys may write to; `None`: saves are only simulated.
    pub allow_save: Option<std::path::PathBuf>,
}

/// Applies what `key` means in the app's current mode.
pub fn press(app: &mut App, key: Key) {
    if let Some(action) = action_for(&app.mode, key) {
        update::update(app, action);
    }
}

/// The explorer's frame after `keys`, with every study run to completion: exactly what the
/// terminal would show, drawn by the same code into an in-memory buffer.
pub fn render(loaded: LoadedScene, keys: &[Key], options: RenderOptions) -> Result<Buffer, String> {
    let (width, height) = (options.width, options.height);
    let app = prepare(loaded, keys, options)?;
    draw_to_buffer(&app, width, height)
}

/// The explorer's state after `keys` (stopping at a quit), with every study the visible
/// panels need run to completion.
pub fn prepare(loaded: LoadedScene, keys: &[Key], options: RenderOptions) -> Result<App, String> {
    let mut app = App::new(loaded, options.look, options.timings)?;
    // A render is for snapshots: it touches the file system only where it was allowed to.
    app.save_policy = match options.allow_save {
        None => app::SavePolicy::Simulate,
        Some(dir) => {
            app.set_save_directory(dir.clone());
            app::SavePolicy::Within(dir)
        }
    };
    update::update(&mut app, Action::Resize(options.width, options.height));
    for key in keys {
        if app.quit {
            break;
        }
        press(&mut app, *key);
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
