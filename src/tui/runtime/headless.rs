//! The explorer without a terminal (`beamfric render`, snapshot tests, benchmarks): the same
//! state, update and drawing as the interactive explorer, with the jobs run on the spot
//! instead of on workers, so a frame depends only on the scene, the size and the keys.

use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::buffer::Buffer;

use crate::scene::{LoadedScene, SceneError};
use crate::tui::input::keymap::Key;
use crate::tui::jobs::solve::solve;
use crate::tui::jobs::sweeps::compute_now;
use crate::tui::state::{App, Look, Options, Palette, SavePolicy};
use crate::tui::update::{Msg, update};
use crate::tui::view;

/// What a headless render needs besides the scene.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    pub width: u16,
    pub height: u16,
    pub look: Look,
    /// The colours.
    pub palette: Palette,
    /// What the charts' curves are drawn with.
    pub markers: crate::plot::MarkerSet,
    /// Show run times (frames then depend on the clock).
    pub timings: bool,
    /// The only directory a save in the keys may write to; `None`: saves are only simulated.
    pub allow_save: Option<std::path::PathBuf>,
    /// The lesson and step the scene is (`render --lesson FILE --step K`).
    pub lesson: Option<crate::tui::state::LessonPlace>,
}

/// Solves the current state on the spot if it needs a solve (the interactive explorer solves
/// on a worker instead).
pub fn settle(app: &mut App) {
    if let Some(request) = app.exploration.pending_solve() {
        let solved = solve(request);
        update(app, Msg::Solved(Box::new(solved)));
    }
}

/// `app` with its solve done.
pub fn settled(mut app: App) -> App {
    settle(&mut app);
    app
}

/// Computes every sweep the visible panels need, to completion.
pub fn finish_sweeps(app: &mut App) {
    loop {
        let requests = app.exploration.pending_sweeps();
        if requests.is_empty() {
            break;
        }
        for request in &requests {
            update(app, Msg::Swept(compute_now(request)));
        }
    }
}

/// Applies `key` (what it means in the app's current mode) and solves the new state on the
/// spot.
pub fn press(app: &mut App, key: Key) {
    update(app, Msg::Key(key));
    settle(app);
}

/// The explorer's state after `keys` (stopping at a quit), with every sweep the visible
/// panels need run to completion.
pub fn prepare(
    loaded: LoadedScene,
    keys: &[Key],
    options: RenderOptions,
) -> Result<App, SceneError> {
    // A render is for snapshots: it touches the file system only where it was allowed to.
    let (save_policy, save_directory) = match options.allow_save {
        None => (SavePolicy::Simulate, None),
        Some(dir) => (SavePolicy::Within(dir.clone()), Some(dir)),
    };
    let app_options = Options {
        palette: options.palette,
        markers: options.markers,
        show_timings: options.timings,
        save_policy,
        save_directory,
        lesson: options.lesson,
        ..Options::new(options.look)
    };
    let mut app = settled(App::new(loaded, app_options)?);
    update(&mut app, Msg::Resize(options.width, options.height));
    // What is on screen at this size may ask for another solve (the iterations panel asks for
    // the history).
    settle(&mut app);
    for key in keys {
        if app.ending.is_some() {
            break;
        }
        // An export draws the panel's data: the sweeps it shows are finished first, as an
        // interactive user would wait for them to be drawn.
        if crate::tui::input::keymap::action_for(&app.mode, *key)
            == Some(crate::tui::input::keymap::Action::ExportFigure)
        {
            finish_sweeps(&mut app);
        }
        press(&mut app, *key);
    }
    finish_sweeps(&mut app);
    Ok(app)
}

/// The explorer's frame after `keys`, with every sweep run to completion: exactly what the
/// terminal would show, drawn by the same code into an in-memory buffer.
pub fn render(
    loaded: LoadedScene,
    keys: &[Key],
    options: RenderOptions,
) -> Result<Buffer, SceneError> {
    let (width, height) = (options.width, options.height);
    let app = prepare(loaded, keys, options)?;
    Ok(draw_to_buffer(&app, width, height))
}

/// Draws the app into a fresh buffer of the given size.
pub fn draw_to_buffer(app: &App, width: u16, height: u16) -> Buffer {
    let backend = TestBackend::new(width, height);
    // Drawing into memory cannot fail: the test backend's error type has no values.
    let Ok(mut terminal) = Terminal::new(backend);
    let Ok(_) = terminal.draw(|frame| view::draw(frame, app));
    terminal.backend().buffer().clone()
}
