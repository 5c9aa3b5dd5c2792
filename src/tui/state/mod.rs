//! The explorer's state, the bottom of its layers above the jobs: [`app::App`] (one screen's
//! own state around the shared [`exploration::Exploration`]), the parameter rows
//! ([`params`]), the preset picker, the prompt, follow mode, the undo history, the sweeps' slots and the words
//! for an obstacle's motion. Nothing here changes the state after [`app::App::new`] but the
//! update layer (`tui::update`), and nothing here imports the input, layout, view, update or
//! runtime layers.

pub mod app;
pub mod exploration;
pub mod follow;
pub mod history;
pub mod motion;
pub mod params;
pub mod picker;
pub mod prompt;
pub mod sweeps;

pub use app::{
    App, Discard, Drag, Ending, JoinInfo, Look, Mode, Options, Palette, SavePolicy, StepEdits,
};
pub use exploration::{Diagram, Exploration, LessonPlace, PanelSet};
pub use history::{History, UNDO_BYTES, UNDO_LIMIT};
