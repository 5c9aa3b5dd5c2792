//! The explorer's state. Everything a frame shows is here; [`super::update::update`] is the
//! only code that changes it, and drawing only reads it.

use crate::fem::Mesh;
use crate::model::Problem;
use crate::scene::{LoadedScene, Panel, Scene, SceneSource, Settings};
use crate::solve::{ConditionLevel, Method, Solution, SolveError, SolveOptions};

use super::params::{Row, rows};
use super::prompt::Prompt;
use super::studies::{
    STUDIES, StudyContext, StudyRequest, StudyResult, StudySlot, StudyState, StudyView, study_of,
};

pub use crate::plot::{Look, Palette};

/// What the keyboard is doing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Mode {
    /// Selecting and stepping parameters.
    Normal,
    /// Typing an exact value for a row (pre-filled with the current one).
    Editing { row: Row, prompt: Prompt },
    /// The help, scrolled down by `offset` lines.
    Help { offset: u16 },
    /// Every warning in full, scrolled down by `offset` lines.
    Warnings { offset: u16 },
    /// The scene as TOML, to copy from the screen (saving in a served session).
    SceneText,
    /// The preset picker: its search, highlighted entry and scroll.
    Presets(super::picker::PresetPicker),
    /// Typing the file name to save to.
    Save { prompt: Prompt },
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
    /// No file is written or read (a served session): `s` says why, in these words.
    Refuse(String),
    /// No file is written: `s` shows the scene as TOML to copy (a served session).
    ShowText,
}

/// What a solve depends on: the keystroke's re-solve is asked for by this, computed off the
/// UI thread, and its result kept only while it is still the one wanted.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveRequest {
    pub problem: Problem,
    pub elements: usize,
    pub method: Method,
    pub options: SolveOptions,
}

/// A finished solve: what it was computed for, its mesh and its solution.
#[derive(Debug, Clone)]
pub struct Shown {
    pub request: SolveRequest,
    pub mesh: Mesh,
    pub solution: Result<Solution, SolveError>,
    /// max |u| over the nodes, found once on the worker (an O(n) scan has no place in a
    /// frame: 10⁷ nodes take milliseconds).
    pub max_deflection: f64,
    /// The reference (the `condensed` method on the same mesh), solved on the worker too, when
    /// the method is another one and the reference gave a solution.
    pub reference: Option<Solution>,
}

/// What a mouse drag that started on something is moving.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Drag {
    /// An obstacle's marker on the deflection chart (the obstacle's index); `moved` once the
    /// first move was applied (the undo step is kept then, once per drag).
    Obstacle { index: usize, moved: bool },
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
    /// What to do once the save in progress succeeds (`s` in a "lose the changes?" question).
    pub after_save: Option<Discard>,
    /// The problem and settings the loaded scene validated to.
    pub loaded_problem: (Problem, Settings),
    /// Where the scene came from.
    pub source: SceneSource,
    /// The directory new files are saved to by default.
    pub save_directory: std::path::PathBuf,
    /// The file to save to by default.
    pub save_path: String,
    pub problem: Problem,
    /// The solve the current state needs.
    pub wanted: SolveRequest,
    /// The last solve received: for the current state, or an earlier one while the new one
    /// runs (then drawn as out of date). `None` before the first one arrives.
    pub shown: Option<Shown>,
    /// Since when the wanted solve runs (interactive only: frames of a headless render never
    /// depend on the clock).
    pub busy_since: Option<std::time::Instant>,
    /// Index into [`App::rows`].
    pub selected: usize,
    pub mode: Mode,
    /// The last message for the user (a rejected value, a saved file, …).
    pub message: Option<String>,
    pub diagram: Diagram,
    /// The panel shown when only one fits (index into the scene's panels).
    pub focus: usize,
    /// The focused panel fills the screen below the title.
    pub zoom: bool,
    /// Mouse capture is wanted (off with `--no-mouse`); input from the mouse is ignored
    /// without it.
    pub mouse: bool,
    /// A mouse drag in progress.
    pub drag: Option<Drag>,
    /// The first parameter row shown (kept by `update` so that the selected row is visible
    /// and a clicked row stays under the pointer).
    pub parameters_offset: usize,
    /// Show run times (they make frames depend on the clock).
    pub show_timings: bool,
    pub look: Look,
    /// The colours (`T` cycles them).
    pub palette: Palette,
    /// The deflection panel shows u − u_ref instead of u and u_ref (`c`).
    pub show_difference: bool,
    /// Terminal size in cells, as last reported.
    pub size: (u16, u16),
    pub quit: bool,
    /// Ctrl-Z: the event loop gives the terminal back and stops the process.
    pub suspend_requested: bool,
    /// One slot per study of [`super::studies::STUDIES`], by the same index.
    pub studies: Vec<StudySlot>,
    /// Most elements a change may ask for (served sessions); `None`: the scene rules only.
    pub max_elements: Option<usize>,
    /// Follow mode (served sessions with a presenter); `None`: an explorer of its own.
    pub follow: Option<super::follow::Follow>,
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
        let wanted = solve_request(&loaded.scene, &loaded.problem, loaded.settings);
        let mut app = App {
            loaded: loaded.scene.clone(),
            saved: loaded.scene.clone(),
            undo: Vec::new(),
            redo: Vec::new(),
            save_policy: SavePolicy::Write,
            after_save: None,
            loaded_problem: (loaded.problem.clone(), loaded.settings),
            scene: loaded.scene,
            source: loaded.source,
            save_directory: std::path::PathBuf::from("."),
            save_path,
            problem: loaded.problem,
            wanted,
            shown: None,
            busy_since: None,
            selected: 0,
            mode: Mode::Normal,
            message: None,
            diagram: Diagram::Deflection,
            focus: 0,
            zoom: false,
            mouse: true,
            drag: None,
            parameters_offset: 0,
            show_timings,
            look,
            palette: Palette::default(),
            show_difference: false,
            size: (120, 40),
            quit: false,
            suspend_requested: false,
            studies: vec![StudySlot::default(); STUDIES.len()],
            max_elements: None,
            follow: None,
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

    /// The first parameter row to show in a box of `height` rows: the kept scroll, moved only
    /// as far as needed to show the selected row.
    pub fn parameters_offset(&self, height: usize) -> usize {
        let selected = self.selected.min(self.rows().len() - 1);
        self.parameters_offset
            .min(selected)
            .max((selected + 1).saturating_sub(height.max(1)))
    }

    /// Should the terminal report the mouse now? Not with `--no-mouse`, and not while the
    /// scene is shown as text to copy (plain dragging selects it then).
    pub fn wants_mouse(&self) -> bool {
        self.mouse && self.mode != Mode::SceneText
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

    /// Asks for a re-solve after a change of the scene, with the problem and settings its
    /// validation built. Nothing is solved here: see [`App::settle`] and the event loop.
    pub(super) fn resolve(&mut self, problem: Problem, settings: Settings) {
        self.wanted = solve_request(&self.scene, &problem, settings);
        self.problem = problem;
        self.refresh_studies();
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

    /// Takes a finished solve if it is the one wanted now; returns whether it was taken.
    pub fn accept_solution(&mut self, shown: Shown) -> bool {
        if shown.request != self.wanted {
            return false;
        }
        self.shown = Some(shown);
        self.busy_since = None;
        true
    }

    /// Solves the current state on the spot if needed (headless rendering and tests; the
    /// interactive explorer solves on a worker instead).
    pub fn settle(&mut self) {
        if let Some(request) = self.pending_solve().cloned() {
            self.accept_solution(super::solver::run_solve(&request));
        }
    }

    /// The solution shown, if one has arrived.
    pub fn solution(&self) -> Option<&Result<Solution, SolveError>> {
        self.shown.as_ref().map(|s| &s.solution)
    }

    /// The panels on screen, as [`super::view::screen_layout`] places them: none when the
    /// terminal is too small.
    pub fn visible_panels(&self) -> Vec<Panel> {
        let area = ratatui::layout::Rect::new(0, 0, self.size.0, self.size.1);
        super::view::screen_layout(self, area)
            .map(|layout| layout.panels.into_iter().map(|(panel, _)| panel).collect())
            .unwrap_or_default()
    }

    /// Marks the studies whose inputs changed as pending (or idle when no visible panel needs
    /// them). Their data for older inputs is never drawn as current: it is kept only to be
    /// drawn marked as out of date until the new data arrives.
    pub(super) fn refresh_studies(&mut self) {
        let panels = self.visible_panels();
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
                (StudyState::Pending(_), Some(inputs)) => Some(StudyRequest {
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
        let wrong_type =
            || StudyView::Notice("internal error: the study's data has another type".into());
        match self.study_state(panel) {
            StudyState::Ready(data) => data
                .downcast_ref::<T>()
                .map_or_else(wrong_type, StudyView::Ready),
            StudyState::Pending(Some(data)) => data
                .downcast_ref::<T>()
                .map_or_else(wrong_type, StudyView::Outdated),
            StudyState::Pending(None) => StudyView::Notice(computing.into()),
            StudyState::Failed(e) => StudyView::Notice(e.clone()),
            StudyState::Idle => StudyView::Notice("not computed".into()),
        }
    }
}

/// The solve a scene needs.
fn solve_request(scene: &Scene, problem: &Problem, settings: Settings) -> SolveRequest {
    SolveRequest {
        problem: problem.clone(),
        elements: settings.elements,
        method: settings.method,
        options: solve_options(scene),
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
