//! The explorer: a live terminal UI (ratatui + crossterm) that re-solves on every keystroke and
//! charts the trade-offs, built like ratatui's "Elm architecture" recipe in layers, each
//! importing only those below it:
//!
//! - [`jobs`]: what the workers compute (the keystroke's solve, the charts' sweeps), pure
//!   functions of a request;
//! - [`state`]: the explorer's state ([`state::App`] around the presenter's shareable
//!   [`state::Exploration`]);
//! - [`input`]: bytes decoded into keys, pastes and mouse events, and the keymap;
//! - [`layout`]: where everything goes on the screen, and what is under a cell;
//! - [`view`]: drawing, which reads the state and changes nothing;
//! - [`update`]: the only writer of the state, taking [`update::Msg`]s;
//! - [`runtime`]: the event loop, the local and remote terminals, the workers, the headless
//!   explorer.
//!
//! The same state, update and drawing serve the terminal ([`explore`]), a served session
//! (`crate::serve`) and headless rendering ([`render`]). `docs/architecture.md` draws the
//! layers and follows a key to a frame.

pub mod input;
pub mod jobs;
pub mod layout;
pub mod runtime;
pub mod state;
pub mod update;
pub mod view;

pub use runtime::event_loop::INJECT_PANIC;
pub use runtime::headless::{
    RenderOptions, draw_to_buffer, finish_sweeps, prepare, press, render, settle, settled,
};
pub use runtime::local::TerminalError;
pub use state::Ending;

use crate::scene::LoadedScene;
use state::{App, Options};

/// Runs the explorer on `loaded` in the local terminal until the user quits, a signal arrives
/// or the terminal hangs up. The terminal is restored on return, on a panic, on SIGINT,
/// SIGTERM and SIGHUP, and around a suspension. `options` say how it looks and what it may
/// do (the mouse, run times, saving).
pub fn explore(loaded: LoadedScene, options: Options) -> Result<Ending, ExploreError> {
    let app = App::new(loaded, options)?;
    Ok(runtime::local::run_local(app, |_| None, None)?)
}

/// Why the local explorer could not run.
#[derive(Debug)]
pub enum ExploreError {
    /// The scene is not valid (its obstacles put in order broke a rule).
    Scene(crate::scene::SceneError),
    /// The terminal failed.
    Terminal(TerminalError),
}

impl std::fmt::Display for ExploreError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ExploreError::Scene(e) => e.fmt(f),
            ExploreError::Terminal(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for ExploreError {}

impl From<crate::scene::SceneError> for ExploreError {
    fn from(e: crate::scene::SceneError) -> Self {
        ExploreError::Scene(e)
    }
}

impl From<TerminalError> for ExploreError {
    fn from(e: TerminalError) -> Self {
        ExploreError::Terminal(e)
    }
}
