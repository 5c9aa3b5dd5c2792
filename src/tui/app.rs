//! The explorer's state. Everything a frame shows is here; [`super::update::update`] is the
//! only code that changes it, and drawing only reads it.

use crate::fem::Mesh;
use crate::model::Problem;
use crate::scene::{LoadedScene, Panel, Scene, SceneSource, Settings};
use crate::solve::{ConditionLevel, Solution, SolveError, SolveOptions, solve};

use super::params::{Row, rows};
use super::studies::{
    STUDIES, StudyContext, StudyRequest, StudyResult, StudySlot, StudyState, StudyView, study_of,
};

pub use crate::plot::Look;

/// What the keyboard is doing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Mode {
    /// Selecting and stepping parameters.
    Normal,
    /// Typing an exact value for a row.
    Editing { row: Row, buffer: String },
    /// The help overlay.
    Help,
    /// The preset picker, with the highlighted entry.
    Presets { index: usize },
    /// Typing the file name to save to.
    Save { buffer: String },
    /// The file exists: overwrite it?
    ConfirmOverwrite { path: String },
    /// The scene has unsaved changes: lose them to do `then`?
    ConfirmDiscard { then: Discard },
}

/// What would throw away unsaved changes, waiting for a yes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Discard {
    Quit,
    /// Load the preset with this index.
    Preset(usize),
    /// Back to the scene as loaded.
    Reset,
}

/// What a save does with the file system: write (the explorer), or only say what it would do
/// (`render`, unless `--allow-save DIR` lets it write under DIR).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SavePolicy {
    Write,
    Simulate,
    Within(std::path::PathBuf),
}

/// Most undo steps kept.
pub const UNDO_LIMIT: usize = 1000;

/// Which diagram the deflection panel shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Diagram {
    Deflection,
    Moment,
    Shear,
}

/// The explorer's state.
#[derive(Debug, Clone)]
pub struct App {
    /// The scene being explored (always valid).
    pub scene: Scene,
    /// The scene as loaded, for reset.
    pub loaded: Scene,
    /// The scene as last loaded or saved: the state differs from it when it is modified.
    pub saved: Scene,
    /// Earlier scenes, the newest last (undo), and undone ones (redo).
    pub undo: Vec<Scene>,
    pub redo: Vec<Scene>,
    pub save_policy: SavePolicy,
    /// The problem and settings the loaded scene validated to.
    pub loaded_problem: (Problem, Settings),
    /// Where the scene came from.
    pub source: SceneSource,
    /// The directory new files are saved to by default.
    pub save_directory: std::path::PathBuf,
    /// The file to save to by default.
    pub save_path: String,
    pub problem: Problem,
    pub mesh: Mesh,
    /// The current solution, or why the method gave none.
    pub solution: Result<Solution, SolveError>,
    /// Index into [`App::rows`].
    pub selected: usize,
    pub mode: Mode,
    /// The last message for the user (a rejected value, a saved file, …).
    pub message: Option<String>,
    pub diagram: Diagram,
    /// The panel shown when only one fits (index into the scene's panels).
    pub focus: usize,
    /// Show run times (they make frames depend on the clock).
    pub show_timings: bool,
    pub look: Look,
    /// Terminal size in cells, as last reported.
    pub size: (u16, u16),
    pub quit: bool,
    /// One slot per study of [`super::studies::STUDIES`], by the same index.
    pub studies: Vec<StudySlot>,
}

/// Solve options of the explorer: no condition numbers on the per-keystroke path, the
/// reference error for the status line.
pub fn solve_options(scene: &Scene) -> SolveOptions {
    SolveOptions {
        epsilon: scene.solver.epsilon,
        condition: ConditionLevel::Off,
        ..SolveOptions::default()
    }
}

impl App {
    /// The explorer on a loaded scene. Obstacles are kept ordered by position.
    pub fn new(loaded: LoadedScene, look: Look, show_timings: bool) -> Result<App, String> {
        let loaded = sorted(loaded).map_err(|e| e.to_string())?;
        let save_path = loaded.source.default_file_name().display().to_string();
        let mesh = Mesh::new(&loaded.problem, loaded.settings.elements);
        let solution = solve(
            &loaded.problem,
            &mesh,
            loaded.settings.method,
            &solve_options(&loaded.scene),
        );
        let mut app = App {
            loaded: loaded.scene.clone(),
            saved: loaded.scene.clone(),
            undo: Vec::new(),
            redo: Vec::new(),
            save_policy: SavePolicy::Write,
            loaded_problem: (loaded.problem.clone(), loaded.settings),
            scene: loaded.scene,
            source: loaded.source,
            save_directory: std::path::PathBuf::from("."),
            save_path,
            problem: loaded.problem,
            mesh,
            solution,
            selected: 0,
            mode: Mode::Normal,
            message: None,
            diagram: Diagram::Deflection,
            focus: 0,
            show_timings,
            look,
            size: (120, 40),
            quit: false,
            studies: vec![StudySlot::default(); STUDIES.len()],
        };
        app.refresh_studies();
        Ok(app)
    }

    /// Saves of presets go to `directory` from now on.
    pub fn set_save_directory(&mut self, directory: std::path::PathBuf) {
        if let SceneSource::Preset(_) = self.source {
            self.save_path = directory
                .join(self.source.default_file_name())
                .display()
                .to_string();
        }
        self.save_directory = directory;
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

    /// The panels the scene asks for, in display order, without repeats.
    pub fn panels(&self) -> Vec<Panel> {
        let mut panels: Vec<Panel> = Panel::ALL
            .into_iter()
            .filter(|p| self.scene.view.panels.contains(p))
            .collect();
        panels.dedup();
        panels
    }

    /// Does the scene differ from the one last loaded or saved?
    pub fn modified(&self) -> bool {
        self.scene != self.saved
    }

    /// Replaces the scene by a newly loaded one (a preset), and re-solves. Undo starts afresh.
    pub(super) fn load(&mut self, loaded: LoadedScene) {
        let Ok(loaded) = sorted(loaded) else { return };
        self.loaded = loaded.scene.clone();
        self.saved = loaded.scene.clone();
        self.undo.clear();
        self.redo.clear();
        self.loaded_problem = (loaded.problem.clone(), loaded.settings);
        self.scene = loaded.scene;
        self.source = loaded.source;
        self.resolve(loaded.problem, loaded.settings);
    }

    /// Re-solves after a change of the scene, with the problem and settings its validation
    /// built.
    pub(super) fn resolve(&mut self, problem: Problem, settings: Settings) {
        self.mesh = Mesh::new(&problem, settings.elements);
        self.problem = problem;
        self.solution = solve(
            &self.problem,
            &self.mesh,
            settings.method,
            &solve_options(&self.scene),
        );
        self.refresh_studies();
    }

    /// Marks the studies whose inputs changed as pending (or idle when no visible panel needs
    /// them). Their data for older inputs is dropped: it is never drawn as current.
    pub(super) fn refresh_studies(&mut self) {
        let panels = self.panels();
        let context = StudyContext {
            problem: &self.problem,
            elements: self.scene.mesh.elements,
            epsilon: self.scene.solver.epsilon,
            show_timings: self.show_timings,
        };
        for (slot, study) in self.studies.iter_mut().zip(STUDIES) {
            let needed = study.panels().iter().any(|p| panels.contains(p));
            slot.refresh(needed, study.inputs(context));
        }
    }

    /// The studies that must be computed for the current state.
    pub fn pending_studies(&self) -> Vec<StudyRequest> {
        self.studies
            .iter()
            .enumerate()
            .filter_map(|(study, slot)| match (&slot.state, &slot.inputs) {
                (StudyState::Pending, Some(inputs)) => Some(StudyRequest {
                    study,
                    inputs: inputs.clone(),
                }),
                _ => None,
            })
            .collect()
    }

    /// Takes a finished study if it belongs to the current state; an outdated result is
    /// dropped. Returns whether it was taken.
    pub fn accept(&mut self, result: StudyResult) -> bool {
        match self.studies.get_mut(result.study) {
            Some(slot) => slot.accept(&result.inputs, result.data),
            None => false,
        }
    }

    /// The state of the study behind `panel` (idle for a panel without one).
    pub fn study_state(&self, panel: Panel) -> &StudyState {
        const IDLE: &StudyState = &StudyState::Idle;
        study_of(panel).map_or(IDLE, |i| &self.studies[i].state)
    }

    /// What `panel` draws of its study: its data as `T`, or a notice.
    pub fn study_view<T: 'static>(&self, panel: Panel) -> StudyView<'_, T> {
        let computing = study_of(panel).map_or("", |i| STUDIES[i].computing());
        match self.study_state(panel) {
            StudyState::Ready(data) => match data.downcast_ref::<T>() {
                Some(data) => StudyView::Ready(data),
                None => {
                    StudyView::Notice("internal error: the study's data has another type".into())
                }
            },
            StudyState::Pending => StudyView::Notice(computing.into()),
            StudyState::Failed(e) => StudyView::Notice(e.clone()),
            StudyState::Idle => StudyView::Notice("not computed".into()),
        }
    }
}

/// The loaded scene with its obstacles ordered by position (validated again only when the
/// order changed, since error messages name obstacles by index).
fn sorted(mut loaded: LoadedScene) -> Result<LoadedScene, crate::scene::SceneError> {
    let in_order = loaded
        .scene
        .obstacles
        .windows(2)
        .all(|w| w[0].x.total_cmp(&w[1].x).is_le());
    if in_order {
        return Ok(loaded);
    }
    loaded.scene.obstacles.sort_by(|a, b| a.x.total_cmp(&b.x));
    LoadedScene::new(loaded.scene, loaded.source)
}
