//! The explorer's state: what the presenter shares ([`Exploration`]) and what is one screen's
//! own — its mode and prompts, undo history, saving, scroll, zoom, look and size. Everything a
//! frame shows is here; `tui::update` is the only code that changes it after [`App::new`], and
//! drawing only reads it.

use std::path::PathBuf;
use std::time::Instant;

use crate::scene::{LoadedScene, Scene, SceneSource};

use super::exploration::{Exploration, LessonPlace};
use super::follow::Follow;
use super::history::History;
use super::params::Row;
use super::picker::PresetPicker;
use super::prompt::Prompt;

pub use crate::plot::{Look, MarkerSet, Palette};

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
    Presets(PresetPicker),
    /// Typing the file name to save to.
    Save { prompt: Prompt },
    /// The file exists: overwrite it?
    ConfirmOverwrite { path: String },
    /// The scene has unsaved changes: lose them to do `then`?
    ConfirmDiscard { then: Discard },
    /// The lecturer's quit with students connected: end the class?
    ConfirmEndClass,
    /// How students join the class (the lecturer's explorer: `J`, and at start).
    Join,
    /// The presenter's list of students (`S`), scrolled down by `offset` rows.
    Students { offset: u16 },
    /// Typing a line for every student (from the list of students).
    Broadcast { prompt: Prompt },
    /// A student's closing screen: the class was ended by `by`; the scene was saved as
    /// `saved` (under `--save-dir`), and is shown as TOML to copy. Any key leaves.
    ClassEnded { by: String, saved: Option<String> },
}

/// What would throw away unsaved changes, waiting for a yes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Discard {
    Quit,
    /// Load the preset with this index.
    Preset(usize),
    /// Back to the scene as loaded.
    Reset,
    /// Follow the presenter again (a student's `F`).
    Rejoin,
}

/// What a save does with the file system: write (the explorer), or only say what it would do
/// (`render`, unless `--allow-save DIR` lets it write under DIR).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SavePolicy {
    Write,
    Simulate,
    Within(PathBuf),
    /// No file is written or read (a served session): `s` says why, in these words.
    Refuse(String),
    /// No file is written: `s` shows the scene as TOML to copy (a served session).
    ShowText,
}

/// What a mouse drag that started on something is moving.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Drag {
    /// An obstacle's marker on the deflection chart (the obstacle's index); `moved` once the
    /// first move was applied (the undo step is kept then, once per drag).
    Obstacle { index: usize, moved: bool },
}

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

/// How an explorer starts, beyond its scene: its look and what it may do here.
#[derive(Debug, Clone)]
pub struct Options {
    pub look: Look,
    /// The colours (`T` cycles them).
    pub palette: Palette,
    /// What the charts' curves are drawn with (`M` cycles them).
    pub markers: MarkerSet,
    /// Show run times (they make frames depend on the clock).
    pub show_timings: bool,
    /// Ask the terminal for mouse reports (off with `--no-mouse`).
    pub mouse: bool,
    pub save_policy: SavePolicy,
    /// The directory new files are saved to by default (`None`: the current one).
    pub save_directory: Option<PathBuf>,
    /// Most elements a change may ask for (served sessions); `None`: the scene rules only.
    pub max_elements: Option<usize>,
    /// Follow mode (served sessions with a presenter).
    pub follow: Option<Follow>,
    /// The first message for the user.
    pub greeting: Option<String>,
    /// Whose explorer this is (a served session's user name): the files it offers to save
    /// are named after them, so that students sharing a save directory do not collide.
    pub owner: Option<String>,
    /// How students join this lecturer's class (`beamfric present`): shown at start and on `J`.
    pub join: Option<JoinInfo>,
    /// The lesson and the step to start on (`--lesson`); the scene given to [`App::new`] is
    /// that step's.
    pub lesson: Option<LessonPlace>,
}

/// How students reach a class: what the join screen shows.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JoinInfo {
    /// The address the server listens on.
    pub address: std::net::SocketAddr,
    /// The host key's fingerprint (`SHA256:…`), for students to check when ssh asks.
    pub fingerprint: String,
    /// How students log in, in words (no password, the class password, their key).
    pub login: String,
}

impl Options {
    /// The local explorer's defaults in this look: the dark palette, mouse on, saves write.
    pub fn new(look: Look) -> Options {
        Options {
            look,
            palette: Palette::default(),
            markers: MarkerSet::default(),
            show_timings: false,
            mouse: true,
            save_policy: SavePolicy::Write,
            save_directory: None,
            max_elements: None,
            follow: None,
            greeting: None,
            owner: None,
            join: None,
            lesson: None,
        }
    }
}

/// The explorer's state.
#[derive(Debug, Clone)]
pub struct App {
    /// What a presenter shares with the students who follow: the scene, its solve, the
    /// sweeps and the view of it.
    pub exploration: Exploration,
    /// The scene as last loaded or saved: the state differs from it when it is modified.
    pub saved: Scene,
    /// Earlier scenes (undo) and undone ones (redo), bounded in steps and bytes.
    pub history: History,
    pub save_policy: SavePolicy,
    /// What to do once the save in progress succeeds (`s` in a "lose the changes?" question).
    pub after_save: Option<Discard>,
    /// The directory new files are saved to by default.
    pub save_directory: PathBuf,
    /// The file to save to by default (see [`App::default_save_path`]).
    pub save_path: String,
    /// Whose explorer this is ([`Options::owner`]).
    pub owner: Option<String>,
    /// How students join ([`Options::join`]).
    pub join: Option<JoinInfo>,
    /// Since when the wanted solve runs (interactive only: frames of a headless render never
    /// depend on the clock).
    pub busy_since: Option<Instant>,
    pub mode: Mode,
    /// The last message for the user (a rejected value, a saved file, …).
    pub message: Option<String>,
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
    /// What the charts' curves are drawn with (`M` cycles them).
    pub markers: MarkerSet,
    /// The deflection panel shows u − u_ref instead of u and u_ref (`c`).
    pub show_difference: bool,
    /// Terminal size in cells, as last reported.
    pub size: (u16, u16),
    /// How the explorer ended, once it has: the event loop stops then.
    pub ending: Option<Ending>,
    /// The idle warning shown as the message (cleared, with it, by the next input).
    pub idle_warning: Option<String>,
    /// Where the scene's unsaved changes went when the session was closed for it (idle or
    /// hung up) under a save directory: the file's name.
    pub saved_at_closing: Option<String>,
    /// Ctrl-Z: the event loop gives the terminal back and stops the process.
    pub suspend_requested: bool,
    /// Most elements a change may ask for (served sessions); `None`: the scene rules only.
    pub max_elements: Option<usize>,
    /// Follow mode (served sessions with a presenter); `None`: an explorer of its own.
    pub follow: Option<Follow>,
    /// A lesson's steps left with changes, by step: the scene as changed and as last saved,
    /// given back on return to the step (stepping on loses nothing).
    pub step_edits: std::collections::BTreeMap<usize, StepEdits>,
}

/// What a lesson's step was left with.
#[derive(Debug, Clone, PartialEq)]
pub struct StepEdits {
    pub scene: Scene,
    pub saved: Scene,
}

impl App {
    /// The explorer on a loaded scene, before any message. Obstacles are kept ordered by
    /// position. Nothing is solved yet: the scene's solve and its sweeps are pending (see
    /// `tui::update` and the runtimes).
    pub fn new(loaded: LoadedScene, options: Options) -> Result<App, crate::scene::SceneError> {
        let loaded = sorted(loaded)?;
        let save_path = default_save_path(
            &options.save_policy,
            options.save_directory.as_deref(),
            options.owner.as_deref(),
            &loaded.source,
        );
        let mut exploration = Exploration::new(loaded);
        if let Some(place) = options.lesson {
            exploration.focus = place.current().focus;
            exploration.lesson = Some(place);
        }
        Ok(App {
            saved: exploration.scene.clone(),
            exploration,
            history: History::default(),
            save_policy: options.save_policy,
            after_save: None,
            save_directory: options.save_directory.unwrap_or_else(|| PathBuf::from(".")),
            save_path,
            owner: options.owner,
            // The lecturer sees how students join first.
            mode: if options.join.is_some() {
                Mode::Join
            } else {
                Mode::Normal
            },
            join: options.join,
            busy_since: None,
            message: options.greeting,
            zoom: false,
            mouse: options.mouse,
            drag: None,
            parameters_offset: 0,
            show_timings: options.show_timings,
            look: options.look,
            palette: options.palette,
            markers: options.markers,
            show_difference: false,
            size: (120, 40),
            ending: None,
            idle_warning: None,
            saved_at_closing: None,
            suspend_requested: false,
            max_elements: options.max_elements,
            follow: options.follow,
            step_edits: Default::default(),
        })
    }

    /// The scene being explored.
    pub fn scene(&self) -> &Scene {
        &self.exploration.scene
    }

    /// The first parameter row to show in a box of `height` rows: the kept scroll, moved only
    /// as far as needed to show the selected row.
    pub fn parameters_offset(&self, height: usize) -> usize {
        let selected = self
            .exploration
            .selected
            .min(self.exploration.rows().len() - 1);
        self.parameters_offset
            .min(selected)
            .max((selected + 1).saturating_sub(height.max(1)))
    }

    /// Should the terminal report the mouse now? Not with `--no-mouse`, and not while the
    /// scene is shown as text to copy (plain dragging selects it then).
    pub fn wants_mouse(&self) -> bool {
        self.mouse && self.mode != Mode::SceneText
    }

    /// Does the scene differ from the one last loaded or saved?
    pub fn modified(&self) -> bool {
        self.exploration.scene != self.saved
    }

    /// The lesson's steps (counted from 0) left with unsaved changes.
    pub fn changed_steps(&self) -> Vec<usize> {
        self.step_edits
            .iter()
            .filter(|(_, e)| e.scene != e.saved)
            .map(|(step, _)| *step)
            .collect()
    }

    /// Is any work unsaved: this scene's, or a lesson step's left with changes?
    pub fn has_unsaved_work(&self) -> bool {
        // Asked after every message (the class's count of unsaved work): no list built.
        self.modified() || self.step_edits.values().any(|e| e.scene != e.saved)
    }

    /// Is this a served student following the presenter (who may not change the scene)?
    pub fn is_following(&self) -> bool {
        self.follow.as_ref().is_some_and(Follow::is_following)
    }
}

/// The loaded scene with its obstacles ordered by position (validated again only when the
/// order changed, since error messages name obstacles by index).
pub fn sorted(mut loaded: LoadedScene) -> Result<LoadedScene, crate::scene::SceneError> {
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

/// The file the save prompt offers for a scene from `source`. Where saves land in one
/// directory (`--save-dir`, `--allow-save`: [`SavePolicy::Within`]) it is a plain name inside
/// it, shown relative to it — never the server's own path — and led by the owner's user name
/// (`alice-benchmark-1.toml`); otherwise a preset's `name.toml` (in `save_directory` when one
/// is set) or the scene file's own path.
pub fn default_save_path(
    policy: &SavePolicy,
    save_directory: Option<&std::path::Path>,
    owner: Option<&str>,
    source: &SceneSource,
) -> String {
    let file = source.default_file_name();
    match (policy, source) {
        (SavePolicy::Within(_), _) => {
            let name = file
                .file_name()
                .map_or_else(|| source.stem(), |n| n.to_string_lossy().into_owned());
            match owner.map(file_safe).filter(|o| !o.is_empty()) {
                Some(owner) => format!("{owner}-{name}"),
                None => name,
            }
        }
        (_, SceneSource::Preset(_)) => match save_directory {
            Some(directory) => directory.join(file).display().to_string(),
            None => file.display().to_string(),
        },
        _ => file.display().to_string(),
    }
}

/// `name` as part of a file name: letters, digits, `.`, `_` and `-` kept (a leading dot
/// dropped), anything else `_`, at most 32 characters.
fn file_safe(name: &str) -> String {
    name.trim_start_matches('.')
        .chars()
        .take(32)
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-') {
                c
            } else {
                '_'
            }
        })
        .collect()
}
