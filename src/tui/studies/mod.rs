//! The studies behind the chart panels, through one mechanism: each study is a [`PanelStudy`]
//! in the registry [`STUDIES`] that says which panels need it, what its result depends on
//! ([`StudyInputs`]) and how to compute it. The app keeps one slot per registered study
//! ([`StudySlot`]); a [`Worker`] thread computes them for the interactive explorer (a keystroke
//! never waits), [`run_now`] to completion for headless rendering. A result carries the inputs
//! it was computed for; the app keeps it only if they are still current, and a newer request
//! cancels the work on an outdated one. A new study-backed panel is one module implementing
//! [`PanelStudy`], one line in [`STUDIES`], and one chart.

mod epsilon;
mod mesh;
mod worker;

use std::any::Any;
use std::sync::Arc;

use crate::model::Problem;
use crate::scene::Panel;
use crate::study::{Cancel, Cancelled};

pub use epsilon::{EPS_POINTS, EpsilonSweep};
pub use mesh::{DENSE_MAX, MESH_MAX, MeshSweep};
pub use worker::Worker;

/// A study's data, of the type its panel's chart reads (e.g. `Vec<EpsPoint>`).
pub type StudyData = Arc<dyn Any + Send + Sync>;

/// What a study's result depends on. Each study fills in what it uses and leaves the rest
/// `None`, so a change of anything else does not recompute it.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyInputs {
    pub problem: Problem,
    /// The scene's number of elements.
    pub elements: usize,
    /// The scene's ε.
    pub epsilon: Option<f64>,
    /// Median over this many runs (when run times are shown).
    pub repeat: Option<usize>,
}

/// What a study's inputs are taken from: the explorer's current state.
#[derive(Debug, Clone, Copy)]
pub struct StudyContext<'a> {
    pub problem: &'a Problem,
    pub elements: usize,
    pub epsilon: f64,
    pub show_timings: bool,
}

/// A study behind one or more panels.
pub trait PanelStudy: Sync {
    /// The panels that show it; it is computed only while one of them is visible.
    fn panels(&self) -> &'static [Panel];
    /// What it is called while it runs: "computing the … sweep…".
    fn computing(&self) -> &'static str;
    /// What its result depends on, in this state.
    fn inputs(&self, context: StudyContext) -> StudyInputs;
    /// Computes it; `Ok(Err(why))` when the study cannot run for these inputs.
    fn run(
        &self,
        inputs: &StudyInputs,
        cancel: Cancel,
    ) -> Result<Result<StudyData, String>, Cancelled>;
}

/// Every study, by index: the app's slots and the worker's requests use the same index.
pub static STUDIES: [&dyn PanelStudy; 2] = [&EpsilonSweep, &MeshSweep];

/// The study a panel shows, if any.
pub fn study_of(panel: Panel) -> Option<usize> {
    STUDIES.iter().position(|s| s.panels().contains(&panel))
}

/// A study's data for the state it was computed for.
#[derive(Debug, Clone)]
pub enum StudyState {
    /// Not needed: no visible panel shows it.
    Idle,
    /// Being computed for the current state; the data of the state before, if any, is kept to
    /// be drawn (marked as out of date) until the new data arrives.
    Pending(Option<StudyData>),
    /// Done, for the current state.
    Ready(StudyData),
    /// The study cannot run for this state (e.g. the enumeration refuses).
    Failed(String),
}

/// A study slot of the app: the inputs its data belongs to and the data.
#[derive(Debug, Clone)]
pub struct StudySlot {
    pub inputs: Option<StudyInputs>,
    pub state: StudyState,
}

impl Default for StudySlot {
    fn default() -> Self {
        StudySlot {
            inputs: None,
            state: StudyState::Idle,
        }
    }
}

impl StudySlot {
    /// Marks the slot pending for new `inputs` when `needed` (its older data is dropped: it is
    /// never drawn as current), or idle when no visible panel needs it.
    pub fn refresh(&mut self, needed: bool, inputs: StudyInputs) {
        if !needed {
            *self = StudySlot::default();
        } else if self.inputs.as_ref() != Some(&inputs) {
            let previous = match std::mem::replace(&mut self.state, StudyState::Idle) {
                StudyState::Ready(data) | StudyState::Pending(Some(data)) => Some(data),
                _ => None,
            };
            *self = StudySlot {
                inputs: Some(inputs),
                state: StudyState::Pending(previous),
            };
        }
    }

    /// Takes a finished result if it belongs to the slot's current inputs.
    pub fn accept(&mut self, inputs: &StudyInputs, data: Result<StudyData, String>) -> bool {
        if self.inputs.as_ref() != Some(inputs) || !matches!(self.state, StudyState::Pending(_)) {
            return false;
        }
        self.state = match data {
            Ok(d) => StudyState::Ready(d),
            Err(e) => StudyState::Failed(e),
        };
        true
    }
}

/// A request for the study runner.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyRequest {
    /// Index into [`STUDIES`].
    pub study: usize,
    pub inputs: StudyInputs,
}

/// A finished study, tagged with the inputs it was computed for.
#[derive(Debug, Clone)]
pub struct StudyResult {
    pub study: usize,
    pub inputs: StudyInputs,
    pub data: Result<StudyData, String>,
}

/// What a panel draws of its study: the data, the data of the state before while the new one
/// is computed, or a notice in its place.
pub enum StudyView<'a, T> {
    Ready(&'a T),
    Outdated(&'a T),
    Notice(String),
}

/// Runs one request, to completion unless `cancel` says stop.
pub fn run(request: &StudyRequest, cancel: Cancel) -> Result<StudyResult, Cancelled> {
    let data = STUDIES[request.study].run(&request.inputs, cancel)?;
    Ok(StudyResult {
        study: request.study,
        inputs: request.inputs.clone(),
        data,
    })
}

/// Runs one request to completion.
pub fn run_now(request: &StudyRequest) -> StudyResult {
    run(request, crate::solve::Cancellation::NEVER)
        .expect("a study that is never cancelled finishes")
}
