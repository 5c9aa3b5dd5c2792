//! The explorer: a live terminal UI (ratatui + crossterm) that re-solves on every keystroke and
//! charts the trade-offs. Built like ratatui's "Elm architecture" recipe: [`app::App`] is the
//! state, [`update::update`] the only function that changes it (it takes
//! [`keymap::Action`]s, which [`keymap::action_for`] makes of keys), and [`view::draw`] draws it
//! without changing anything. The same state, update and drawing serve the terminal ([`run`])
//! and headless rendering ([`render`]).

pub mod app;
pub mod cores;
mod event_loop;
pub mod follow;
pub mod input;
pub mod keymap;
pub mod mouse;
pub mod params;
pub mod picker;
pub mod prompt;
pub mod remote;
pub mod solver;
pub mod studies;
mod terminal;
pub mod update;
pub mod view;

use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::buffer::Buffer;

use crate::scene::LoadedScene;
use app::{App, Look, Palette};
use keymap::{Action, Key, action_for};

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
    /// The terminal went away (end of input or a read error).
    Hangup,
    /// No input for the idle timeout (served sessions only).
    Idle,
}

/// Runs the explorer in the terminal until the user quits, a signal arrives or the terminal
/// hangs up. The terminal is restored on return, on a panic, on SIGINT, SIGTERM and SIGHUP,
/// and around a suspension. `mouse`: ask the terminal for mouse reports (clicks, wheel, drags); `palette`: the colours.
pub fn run(
    loaded: LoadedScene,
    look: Look,
    mouse: bool,
    palette: Palette,
) -> Result<Ending, String> {
    let mut app = App::new(loaded, look, true)?;
    app.mouse = mouse;
    app.palette = palette;
    event_loop::run(app, |_| None)
}

/// Runs `app` in the terminal as [`run`] does; `attach` is given a feed into its loop (for
/// events from elsewhere, e.g. a server's follow hub) and returns what to call after every
/// frame (`beamfric present`: publish the state to the students).
pub fn run_attached(
    app: App,
    attach: impl FnOnce(remote::Feed) -> Option<remote::AfterFrame>,
) -> Result<Ending, String> {
    event_loop::run(app, attach)
}

/// What a headless render needs besides the scene.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RenderOptions {
    pub width: u16,
    pub height: u16,
    pub look: Look,
    /// The colours.
    pub palette: Palette,
    /// Show run times (frames then depend on the clock).
    pub timings: bool,
    /// The only directory a save in the keys may write to; `None`: saves are only simulated.
    pub allow_save: Option<std::path::PathBuf>,
}

/// Applies what `key` means in the app's current mode, and solves the new state on the spot
/// (the headless path; the interactive loop solves on a worker instead).
pub fn press(app: &mut App, key: Key) {
    if let Some(action) = action_for(&app.mode, key) {
        update::update(app, action);
    }
    app.settle();
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
    app.palette = options.palette;
    app.settle();
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
