//! What a presenter shares with the students who follow: the scene being explored, as loaded
//! and as validated, the solve it needs and the last one received, the sweeps behind its
//! charts, and the view of it (diagram, focused panel, selected row). Following is one clone
//! of this value (`tui::update::follow`); everything else of the explorer's state is one
//! screen's own.

use std::sync::Arc;

use crate::lesson::{Lesson, Step};
use crate::model::Problem;
use crate::scene::{LoadedScene, Panel, Scene, SceneSource, Settings};
use crate::solve::{Solution, SolveError};

use super::super::jobs::solve::{SolveRequest, Solved};
use super::super::jobs::sweeps::{SWEEPS, SweepRequest, sweep_of};
use super::params::{Row, rows};
use super::sweeps::{SweepSlot, SweepState, SweepView};

/// Which diagram the deflection panel shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Diagram {
    Deflection,
    Moment,
    Shear,
}

/// A set of panels the explorer can show instead of the scene's own (`v` cycles them): how
/// the method works rather than what it answers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PanelSet {
    /// The method's iterations, with the deflection (where a selected iterate's u(x) shows).
    Iterations,
    /// The dual's box for the selected obstacle, beside the iterations.
    DualBox,
    /// The regularised method's cases of Table 1, beside Figure 5.
    Cases,
    /// The paper's Figure 5 in one panel, with the deflection.
    Figure5,
    /// What the matrices look like.
    Matrices,
}

impl PanelSet {
    /// Every set, in the order `v` shows them after the scene's own panels.
    pub const ALL: [PanelSet; 5] = [
        PanelSet::Iterations,
        PanelSet::DualBox,
        PanelSet::Cases,
        PanelSet::Figure5,
        PanelSet::Matrices,
    ];

    /// The scene's own panels, then each set in turn, then the scene's again.
    pub fn after(set: Option<PanelSet>) -> Option<PanelSet> {
        match set {
            None => Some(PanelSet::ALL[0]),
            Some(set) => {
                let index = PanelSet::ALL.iter().position(|s| *s == set).unwrap_or(0);
                PanelSet::ALL.get(index + 1).copied()
            }
        }
    }

    /// The panels shown, the first focused when one fits at a time.
    pub fn panels(self) -> &'static [Panel] {
        match self {
            PanelSet::Iterations => &[Panel::Iterations, Panel::Deflection],
            PanelSet::DualBox => &[Panel::DualBox, Panel::Iterations],
            PanelSet::Cases => &[Panel::Cases, Panel::Figure5],
            PanelSet::Figure5 => &[Panel::Figure5, Panel::Deflection],
            PanelSet::Matrices => &[Panel::Matrices],
        }
    }

    /// What the set shows, for the message when it comes up.
    pub fn description(set: Option<PanelSet>) -> &'static str {
        match set {
            None => "the scene's own panels",
            Some(PanelSet::Iterations) => "the method's iterations",
            Some(PanelSet::DualBox) => "the dual's box (49) and the iterations",
            Some(PanelSet::Cases) => "the cases of Table 1 and Figure 5",
            Some(PanelSet::Figure5) => "Figure 5 in one panel",
            Some(PanelSet::Matrices) => "the matrices A, S and the condensed system",
        }
    }
}

/// The shared part of the explorer's state.
#[derive(Debug, Clone)]
pub struct Exploration {
    /// The scene being explored (always valid).
    pub scene: Scene,
    /// The scene as loaded, for reset.
    pub loaded: Scene,
    /// The problem and settings the loaded scene validated to.
    pub loaded_problem: (Problem, Settings),
    /// Where the scene came from.
    pub source: SceneSource,
    /// The problem the scene validated to.
    pub problem: Problem,
    /// The solve the current state needs.
    pub wanted: SolveRequest,
    /// The last solve received: for the current state, or an earlier one while the new one
    /// runs (then drawn as out of date). `None` before the first one arrives.
    pub shown: Option<Solved>,
    /// One slot per sweep of [`SWEEPS`], by the same index.
    pub sweeps: Vec<SweepSlot>,
    pub diagram: Diagram,
    /// The panel shown when only one fits (index into [`Exploration::panels`]).
    pub focus: usize,
    /// A set of panels shown instead of the scene's own, if one was chosen (`v`).
    pub panel_set: Option<PanelSet>,
    /// The iterate the iterations panel selects (`<` `>`), counted from the starting point;
    /// `None` for the last one, whatever their number.
    pub iterate: Option<usize>,
    /// Index into [`Exploration::rows`].
    pub selected: usize,
    /// The lesson and its step shown (`--lesson`): followers see it, a fork keeps it.
    pub lesson: Option<LessonPlace>,
}

/// Where a lesson stands: the lesson, and the step shown (counted from 0).
#[derive(Debug, Clone)]
pub struct LessonPlace {
    pub lesson: Arc<Lesson>,
    pub step: usize,
}

impl PartialEq for LessonPlace {
    fn eq(&self, other: &LessonPlace) -> bool {
        self.step == other.step
            && (Arc::ptr_eq(&self.lesson, &other.lesson) || self.lesson == other.lesson)
    }
}

impl LessonPlace {
    /// The step shown.
    pub fn current(&self) -> &Step {
        self.lesson.step(self.step)
    }
}

impl Exploration {
    /// A loaded scene (its obstacles in order), nothing solved yet.
    pub fn new(loaded: LoadedScene) -> Exploration {
        let wanted = SolveRequest::for_scene(&loaded.scene, &loaded.problem, loaded.settings);
        let selected = loaded
            .scene
            .view
            .select
            .as_ref()
            .and_then(|field| rows(&loaded.scene).iter().position(|r| r.field() == *field))
            .unwrap_or(0);
        Exploration {
            loaded: loaded.scene.clone(),
            loaded_problem: (loaded.problem.clone(), loaded.settings),
            scene: loaded.scene,
            source: loaded.source,
            problem: loaded.problem,
            wanted,
            shown: None,
            sweeps: vec![SweepSlot::default(); SWEEPS.len()],
            diagram: Diagram::Deflection,
            focus: 0,
            panel_set: None,
            iterate: None,
            selected,
            lesson: None,
        }
    }

    /// The parameter rows of the current scene.
    pub fn rows(&self) -> Vec<Row> {
        rows(&self.scene)
    }

    /// The selected row.
    pub fn selected_row(&self) -> Row {
        let rows = self.rows();
        rows[self.selected.min(rows.len() - 1)]
    }

    /// The panels shown: the chosen set's, in its order, or those the scene asks for, in
    /// display order, without repeats.
    pub fn panels(&self) -> Vec<Panel> {
        if let Some(set) = self.panel_set {
            return set.panels().to_vec();
        }
        let mut panels: Vec<Panel> = Panel::ALL
            .into_iter()
            .filter(|p| self.scene.view.panels.contains(p))
            .collect();
        panels.dedup();
        panels
    }

    /// The solve still to be done for the current state, if any.
    pub fn pending_solve(&self) -> Option<&SolveRequest> {
        match &self.shown {
            Some(shown) if shown.request == self.wanted => None,
            _ => Some(&self.wanted),
        }
    }

    /// Is what is shown the solution of the current state?
    pub fn is_current(&self) -> bool {
        self.pending_solve().is_none()
    }

    /// The solution shown, if one has arrived.
    pub fn solution(&self) -> Option<&Result<Solution, SolveError>> {
        self.shown.as_ref().map(|s| &s.solution)
    }

    /// The sweeps that must be computed for the current state.
    pub fn pending_sweeps(&self) -> Vec<SweepRequest> {
        self.sweeps
            .iter()
            .enumerate()
            .filter_map(|(sweep, slot)| match (&slot.state, &slot.inputs) {
                (SweepState::Pending(_), Some(inputs)) => Some(SweepRequest {
                    sweep,
                    inputs: inputs.clone(),
                }),
                _ => None,
            })
            .collect()
    }

    /// The state of the sweep behind `panel` (idle for a panel without one).
    pub fn sweep_state(&self, panel: Panel) -> &SweepState {
        const IDLE: &SweepState = &SweepState::Idle;
        sweep_of(panel).map_or(IDLE, |i| &self.sweeps[i].state)
    }

    /// What `panel` draws of its sweep: its data as `T`, or a notice.
    pub fn sweep_view<T: 'static>(&self, panel: Panel) -> SweepView<'_, T> {
        let computing = sweep_of(panel).map_or("", |i| SWEEPS[i].computing());
        let wrong_type =
            || SweepView::Notice("internal error: the sweep's data has another type".into());
        match self.sweep_state(panel) {
            SweepState::Ready(data) => data
                .downcast_ref::<T>()
                .map_or_else(wrong_type, SweepView::Ready),
            SweepState::Pending(Some(data)) => data
                .downcast_ref::<T>()
                .map_or_else(wrong_type, SweepView::Outdated),
            SweepState::Pending(None) => SweepView::Notice(computing.into()),
            SweepState::Failed(e) => SweepView::Notice(e.clone()),
            SweepState::Idle => SweepView::Notice("not computed".into()),
        }
    }
}
