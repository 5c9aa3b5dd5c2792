//! The explorer's state. Everything a frame shows is here; [`super::update::update`] is the
//! only code that changes it, and drawing only reads it.

use crate::fem::Mesh;
use crate::model::Problem;
use crate::scene::{Panel, Scene};
use crate::solve::{ConditionLevel, Solution, SolveError, SolveOptions, solve};
use crate::study::{EpsPoint, MeshPoint};

use super::params::{Row, rows};

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
}

/// Which diagram the deflection panel shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Diagram {
    Deflection,
    Moment,
    Shear,
}

/// How the frame is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Look {
    /// No Unicode: ASCII borders, markers and text.
    pub ascii: bool,
    /// Colours (off with NO_COLOR).
    pub color: bool,
}

/// A study's data for the state it was computed for.
#[derive(Debug, Clone, PartialEq)]
pub enum StudyState<T> {
    /// Not needed: no visible panel shows it.
    Idle,
    /// Being computed for the current state.
    Pending,
    /// Done, for the current state.
    Ready(T),
    /// The study cannot run for this state (e.g. the enumeration refuses).
    Failed(String),
}

/// What an ε sweep depends on.
#[derive(Debug, Clone, PartialEq)]
pub struct EpsInputs {
    pub problem: Problem,
    pub elements: usize,
}

/// What a mesh sweep depends on.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshInputs {
    pub problem: Problem,
    pub epsilon: f64,
    pub elements: usize,
    /// Median over this many runs (1 when run times are not shown).
    pub repeat: usize,
}

/// A study slot: the inputs its data belongs to and the data.
#[derive(Debug, Clone, PartialEq)]
pub struct Study<I, T> {
    pub inputs: Option<I>,
    pub state: StudyState<T>,
}

impl<I, T> Default for Study<I, T> {
    fn default() -> Self {
        Study {
            inputs: None,
            state: StudyState::Idle,
        }
    }
}

/// A request for the study runner.
#[derive(Debug, Clone, PartialEq)]
pub enum StudyRequest {
    Epsilon(EpsInputs),
    Mesh(MeshInputs),
}

/// A finished study, tagged with the inputs it was computed for.
#[derive(Debug, Clone, PartialEq)]
pub enum StudyResult {
    Epsilon(EpsInputs, Result<Vec<EpsPoint>, String>),
    Mesh(MeshInputs, Result<Vec<MeshPoint>, String>),
}

/// The explorer's state.
#[derive(Debug, Clone)]
pub struct App {
    /// The scene being explored (always valid).
    pub scene: Scene,
    /// The scene as loaded, for reset.
    pub loaded: Scene,
    /// Where the scene came from: a file path or `preset <name>`.
    pub source: String,
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
    pub eps_study: Study<EpsInputs, Vec<EpsPoint>>,
    pub mesh_study: Study<MeshInputs, Vec<MeshPoint>>,
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
    /// The explorer on a valid scene. Obstacles are kept ordered by position.
    pub fn new(
        mut scene: Scene,
        source: String,
        look: Look,
        show_timings: bool,
    ) -> Result<App, String> {
        scene.obstacles.sort_by(|a, b| a.x.total_cmp(&b.x));
        let (problem, settings) = scene.validate(&source).map_err(|e| e.to_string())?;
        let mesh = Mesh::new(&problem, settings.elements);
        let solution = solve(&problem, &mesh, settings.method, &solve_options(&scene));
        let save_path = if source.starts_with("preset ") {
            format!("{}.toml", source.trim_start_matches("preset "))
        } else {
            source.clone()
        };
        let save_directory = std::path::PathBuf::from(".");
        let mut app = App {
            loaded: scene.clone(),
            scene,
            source,
            save_directory,
            save_path,
            problem,
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
            eps_study: Study::default(),
            mesh_study: Study::default(),
        };
        app.refresh_studies();
        Ok(app)
    }

    /// Saves of presets go to `directory` from now on.
    pub fn set_save_directory(&mut self, directory: std::path::PathBuf) {
        if let Some(name) = self.source.strip_prefix("preset ") {
            self.save_path = directory.join(format!("{name}.toml")).display().to_string();
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

    /// Re-solves after a change of the scene (which is valid).
    pub(super) fn resolve(&mut self) {
        let (problem, settings) = self
            .scene
            .validate(&self.source)
            .expect("the explorer only keeps valid scenes");
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
        let eps_needed = panels.contains(&Panel::EpsError) || panels.contains(&Panel::EpsCond);
        let eps_inputs = EpsInputs {
            problem: self.problem.clone(),
            elements: self.scene.mesh.elements,
        };
        refresh(&mut self.eps_study, eps_needed, eps_inputs);
        let mesh_inputs = MeshInputs {
            problem: self.problem.clone(),
            epsilon: self.scene.solver.epsilon,
            elements: self.scene.mesh.elements,
            repeat: if self.show_timings { 3 } else { 1 },
        };
        refresh(
            &mut self.mesh_study,
            panels.contains(&Panel::ErrorTime),
            mesh_inputs,
        );
    }

    /// The studies that must be computed for the current state.
    pub fn pending_studies(&self) -> Vec<StudyRequest> {
        let mut requests = Vec::new();
        if let (StudyState::Pending, Some(inputs)) = (&self.eps_study.state, &self.eps_study.inputs)
        {
            requests.push(StudyRequest::Epsilon(inputs.clone()));
        }
        if let (StudyState::Pending, Some(inputs)) =
            (&self.mesh_study.state, &self.mesh_study.inputs)
        {
            requests.push(StudyRequest::Mesh(inputs.clone()));
        }
        requests
    }

    /// Takes a finished study if it belongs to the current state; an outdated result is
    /// dropped. Returns whether it was taken.
    pub fn accept(&mut self, result: StudyResult) -> bool {
        fn take<I: PartialEq, T>(
            slot: &mut Study<I, T>,
            inputs: I,
            data: Result<T, String>,
        ) -> bool {
            if slot.inputs.as_ref() != Some(&inputs) || !matches!(slot.state, StudyState::Pending) {
                return false;
            }
            slot.state = match data {
                Ok(d) => StudyState::Ready(d),
                Err(e) => StudyState::Failed(e),
            };
            true
        }
        match result {
            StudyResult::Epsilon(inputs, data) => take(&mut self.eps_study, inputs, data),
            StudyResult::Mesh(inputs, data) => take(&mut self.mesh_study, inputs, data),
        }
    }
}

fn refresh<I: PartialEq, T>(slot: &mut Study<I, T>, needed: bool, inputs: I) {
    if !needed {
        *slot = Study {
            inputs: None,
            state: StudyState::Idle,
        };
        return;
    }
    if slot.inputs.as_ref() != Some(&inputs) {
        *slot = Study {
            inputs: Some(inputs),
            state: StudyState::Pending,
        };
    }
}
