//! Lessons: a lecture written down. A lesson file (TOML, `lessons/*.toml`) is a list of steps;
//! each names a scene (a preset or a scene file) or goes on from the step before, with its
//! own method, ε, number of elements and panels, and a caption of a few lines that the
//! explorer shows in a strip above the panels. `beamfric --lesson FILE` and `beamfric present
//! --lesson FILE` step through it with Space and Backspace (or `n` and `N`); followers see the
//! step and its caption.
//!
//! Every step is loaded and validated when the lesson is read, so a lesson that opens cannot
//! fail half-way through a lecture. A malformed lesson is a [`LessonError`] naming the file,
//! the step, the field and the rule, in the scene rules' words (`lessons/a.toml: step 3:
//! epsilon = -1: ε must be a finite number greater than zero`).

mod caption;
mod read;

use std::fmt;
use std::path::PathBuf;

use crate::scene::LoadedScene;

pub use caption::{
    CAPTION_LINES, CAPTION_WIDTH, columns, fit_columns, paragraphs, prefix_in_columns, wrap,
};
pub use read::{MAX_STEP_TITLE, MAX_STEPS, MAX_TITLE, read_lesson};

/// A lesson, every step of it loaded and valid.
#[derive(Debug, Clone, PartialEq)]
pub struct Lesson {
    /// Shown with the step in the caption strip.
    pub title: String,
    /// What the lesson teaches (for the help and the lesson's list).
    pub description: String,
    /// The file, as the user named it.
    pub path: PathBuf,
    /// At least one.
    pub steps: Vec<Step>,
}

/// One step: the scene it shows (its method, ε, elements and panels set) and its words.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    pub title: String,
    /// The caption's paragraphs (see [`paragraphs`]).
    pub caption: Vec<String>,
    /// The scene of the step, validated.
    pub scene: LoadedScene,
    /// The panel shown when only one fits: an index into the scene's panels in display order
    /// (as `Exploration::panels` lists them).
    pub focus: usize,
}

/// A rejected lesson: the file, the step (counted from 1) if the error is in one, the field
/// (or a place in the file), and the rule it broke.
#[derive(Debug, Clone, PartialEq)]
pub struct LessonError {
    pub file: String,
    pub step: Option<usize>,
    pub field: String,
    pub rule: String,
}

impl fmt::Display for LessonError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: ", crate::format::printable(&self.file))?;
        if let Some(step) = self.step {
            write!(f, "step {step}: ")?;
        }
        if !self.field.is_empty() {
            write!(f, "{}: ", self.field)?;
        }
        write!(f, "{}", self.rule)
    }
}

impl std::error::Error for LessonError {}

impl Lesson {
    /// The step `index` (counted from 0), the last one beyond the end.
    pub fn step(&self, index: usize) -> &Step {
        &self.steps[index.min(self.steps.len() - 1)]
    }
}
