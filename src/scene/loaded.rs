//! A scene together with where it came from and the problem it validated to: loading validates
//! once, and whoever loads passes the validated problem on instead of validating again.

use std::fmt;
use std::path::{Path, PathBuf};

use super::{PRESETS, Preset, Scene, SceneError, Settings, preset, read_scene_text};
use crate::model::Problem;

/// Where a scene came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SceneSource {
    /// A file, by the path it was opened with.
    File(PathBuf),
    /// A compiled-in preset, by name.
    Preset(&'static str),
}

impl SceneSource {
    /// The name a saved copy gets by default: the file itself, or `NAME.toml` for a preset.
    pub fn default_file_name(&self) -> PathBuf {
        match self {
            SceneSource::File(path) => path.clone(),
            SceneSource::Preset(name) => PathBuf::from(format!("{name}.toml")),
        }
    }

    /// A short name: the preset's name, or the file's stem.
    pub fn stem(&self) -> String {
        match self {
            SceneSource::Preset(name) => name.to_string(),
            SceneSource::File(path) => path.file_stem().map_or_else(
                || path.display().to_string(),
                |s| s.to_string_lossy().into(),
            ),
        }
    }
}

/// How messages and the title bar name the source: the path, or `preset NAME`.
impl fmt::Display for SceneSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneSource::File(path) => write!(f, "{}", path.display()),
            SceneSource::Preset(name) => write!(f, "preset {name}"),
        }
    }
}

/// A valid scene, where it came from, and the problem and settings it validated to.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedScene {
    pub scene: Scene,
    pub source: SceneSource,
    pub problem: Problem,
    pub settings: Settings,
}

impl LoadedScene {
    /// Validates `scene` (once) and keeps what validation built.
    pub fn new(scene: Scene, source: SceneSource) -> Result<LoadedScene, SceneError> {
        let (problem, settings) = scene.validate(&source.to_string())?;
        Ok(LoadedScene {
            scene,
            source,
            problem,
            settings,
        })
    }

    /// A compiled-in preset.
    pub fn preset(preset: &Preset) -> Result<LoadedScene, SceneError> {
        let source = SceneSource::Preset(preset.name);
        let scene = Scene::from_toml(preset.text, &source.to_string())?;
        LoadedScene::new(scene, source)
    }
}

/// Loads a scene by preset name or file path. A path that exists wins over a preset name.
pub fn load(name_or_path: &str) -> Result<LoadedScene, SceneError> {
    let path = Path::new(name_or_path);
    if path.exists() {
        let source = name_or_path.to_string();
        let text = read_scene_text(path, &source)?;
        let scene = Scene::from_toml(&text, &source)?;
        return LoadedScene::new(scene, SceneSource::File(path.to_path_buf()));
    }
    if let Some(preset) = preset(name_or_path) {
        return LoadedScene::preset(preset);
    }
    let names: Vec<&str> = PRESETS.iter().map(|p| p.name).collect();
    Err(SceneError {
        source: name_or_path.to_string(),
        field: String::new(),
        rule: format!(
            "no such file, and not a preset name (presets: {})",
            names.join(", ")
        ),
    })
}
