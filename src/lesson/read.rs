//! Reading a lesson file: TOML into [`Lesson`], every step's scene loaded (a preset by name, a
//! scene file relative to the lesson's folder, or the step before's) with the step's method,
//! ε, elements and panels set, and validated by the scene rules. Unknown fields are errors;
//! every error names the file, the step and the field.

use std::path::Path;

use serde::Deserialize;

use super::caption::{CAPTION_LINES, CAPTION_WIDTH, columns, paragraphs, wrap};
use super::{Lesson, LessonError, Step};
use crate::format::printable;
use crate::model::Method;
use crate::scene::{
    LoadedScene, PRESETS, Panel, Scene, SceneError, SceneSource, check_elements, check_epsilon,
    preset, read_scene_text, text_position,
};

/// Most steps in a lesson.
pub const MAX_STEPS: usize = 200;
/// Most columns of a lesson's title.
pub const MAX_TITLE: usize = 60;
/// Most columns of a step's title (it shares the strip's first line with the lesson's).
pub const MAX_STEP_TITLE: usize = 50;
/// Most characters in a lesson's description (shown in the help).
pub const MAX_DESCRIPTION: usize = 1000;

/// A lesson file as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct LessonFile {
    title: String,
    #[serde(default)]
    description: String,
    #[serde(default, rename = "step")]
    steps: Vec<StepFile>,
}

/// `[[step]]` as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct StepFile {
    title: String,
    preset: Option<String>,
    scene: Option<String>,
    method: Option<Method>,
    epsilon: Option<f64>,
    elements: Option<usize>,
    panels: Option<Vec<Panel>>,
    focus: Option<Panel>,
    caption: String,
}

/// Reads and validates the lesson at `path` (named in errors as written).
pub fn read_lesson(path: &Path) -> Result<Lesson, LessonError> {
    let file = path.display().to_string();
    let text = read_scene_text(path, &file).map_err(|e| LessonError {
        file: file.clone(),
        step: None,
        field: String::new(),
        rule: e
            .rule
            .replace("a scene file", "a lesson file")
            .replace("a scene is read", "a lesson is read"),
    })?;
    let parsed: LessonFile = toml::from_str(&text).map_err(|e| syntax_error(&text, &file, &e))?;
    let error = |step: Option<usize>, field: &str, rule: String| LessonError {
        file: file.clone(),
        step,
        field: field.to_string(),
        rule,
    };
    check_title(&parsed.title, MAX_TITLE).map_err(|rule| error(None, "title", rule))?;
    if parsed.description.chars().count() > MAX_DESCRIPTION
        || parsed
            .description
            .chars()
            .any(|c| c.is_control() && c != '\n')
    {
        return Err(error(
            None,
            "description",
            format!("must be plain text of at most {MAX_DESCRIPTION} characters"),
        ));
    }
    if parsed.steps.is_empty() {
        return Err(error(
            None,
            "step",
            "a lesson needs at least one [[step]] (with a title, a preset or scene, and a caption)"
                .into(),
        ));
    }
    if parsed.steps.len() > MAX_STEPS {
        return Err(error(
            None,
            "step",
            format!(
                "{} steps: a lesson may have at most {MAX_STEPS}",
                parsed.steps.len()
            ),
        ));
    }
    let folder = path.parent().unwrap_or(Path::new("."));
    let mut steps: Vec<Step> = Vec::with_capacity(parsed.steps.len());
    for (index, written) in parsed.steps.into_iter().enumerate() {
        let previous = steps.last().map(|s| &s.scene);
        let step = read_step(written, previous, folder)
            .map_err(|(field, rule)| error(Some(index + 1), &field, rule))?;
        steps.push(step);
    }
    Ok(Lesson {
        title: parsed.title.trim().to_string(),
        description: parsed
            .description
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" "),
        path: path.to_path_buf(),
        steps,
    })
}

/// One step, from the scene before it (if any): `Err((field, rule))`.
fn read_step(
    written: StepFile,
    previous: Option<&LoadedScene>,
    folder: &Path,
) -> Result<Step, (String, String)> {
    check_title(&written.title, MAX_STEP_TITLE).map_err(|rule| ("title".to_string(), rule))?;
    let caption = check_caption(&written.caption).map_err(|rule| ("caption".to_string(), rule))?;
    let (mut scene, source) = match (&written.preset, &written.scene, previous) {
        (Some(_), Some(_), _) => {
            return Err((
                "preset, scene".into(),
                "name a preset or a scene file, not both".into(),
            ));
        }
        (Some(name), None, _) => {
            let preset = preset(name).ok_or_else(|| {
                let names: Vec<&str> = PRESETS.iter().map(|p| p.name).collect();
                (
                    "preset".to_string(),
                    format!("= {name:?}: no such preset (presets: {})", names.join(", ")),
                )
            })?;
            let loaded = LoadedScene::preset(preset).map_err(scene_rule)?;
            (loaded.scene, loaded.source)
        }
        (None, Some(file), _) => {
            let path = folder.join(file);
            let shown = path.display().to_string();
            let text = read_scene_text(&path, &shown).map_err(|e| {
                (
                    "scene".to_string(),
                    format!(
                        "= {file:?}: {} (read relative to the lesson's folder)",
                        e.rule
                    ),
                )
            })?;
            let scene = Scene::from_toml(&text, &shown).map_err(scene_rule)?;
            (scene, SceneSource::File(path))
        }
        (None, None, Some(previous)) => (previous.scene.clone(), previous.source.clone()),
        (None, None, None) => {
            return Err((
                "preset".into(),
                "the first step must name its scene: preset = \"NAME\" or scene = \"FILE.toml\""
                    .into(),
            ));
        }
    };
    if let Some(method) = written.method {
        scene.solver.method = method;
    }
    if let Some(epsilon) = written.epsilon {
        check_epsilon(epsilon).map_err(|rule| ("epsilon".to_string(), rule))?;
        scene.solver.epsilon = epsilon;
    }
    if let Some(elements) = written.elements {
        check_elements(elements).map_err(|rule| ("elements".to_string(), rule))?;
        scene.mesh.elements = elements;
    }
    if let Some(panels) = written.panels {
        scene.view.panels = panels;
    }
    let shown: Vec<Panel> = Panel::ALL
        .into_iter()
        .filter(|p| scene.view.panels.contains(p))
        .collect();
    let focus = match written.focus {
        None => 0,
        Some(panel) => shown.iter().position(|p| *p == panel).ok_or_else(|| {
            let names: Vec<&str> = shown.iter().map(|p| p.name()).collect();
            (
                "focus".to_string(),
                format!(
                    "= \"{}\": must be one of the step's panels ({})",
                    panel.name(),
                    if names.is_empty() {
                        "none".to_string()
                    } else {
                        names.join(", ")
                    }
                ),
            )
        })?,
    };
    let loaded = LoadedScene::new(scene, source).map_err(scene_rule)?;
    Ok(Step {
        title: written.title.trim().to_string(),
        caption,
        scene: loaded,
        focus,
    })
}

/// A scene's rejection as a step's: the scene's field, with the scene named in the rule.
fn scene_rule(e: SceneError) -> (String, String) {
    let field = if e.field.is_empty() {
        "scene".to_string()
    } else {
        e.field
    };
    (field, format!("{} (in {})", e.rule, e.source))
}

/// A title: not empty, one line, at most `max` columns (a CJK character takes two).
fn check_title(title: &str, max: usize) -> Result<(), String> {
    let title = title.trim();
    let width = columns(title);
    if title.is_empty() {
        Err("must not be empty".into())
    } else if title.chars().any(char::is_control) {
        Err("must be one line of plain text (no control characters)".into())
    } else if width > max {
        Err(format!(
            "takes {width} columns: at most {max} fit the caption strip"
        ))
    } else {
        Ok(())
    }
}

/// A caption: plain text that wraps to at most [`CAPTION_LINES`] lines at 80 columns.
fn check_caption(text: &str) -> Result<Vec<String>, String> {
    if text
        .chars()
        .any(|c| c.is_control() && c != '\n' && c != '\t' && c != '\r')
    {
        return Err("must be plain text (no control characters)".into());
    }
    let caption = paragraphs(text);
    if caption.is_empty() {
        return Err("must not be empty: a few lines on what the step shows".into());
    }
    let lines = wrap(&caption, CAPTION_WIDTH).len();
    if lines > CAPTION_LINES {
        return Err(format!(
            "takes {lines} lines at 80 columns: at most {CAPTION_LINES} fit the caption strip at \
             80x24 (shorten it, or split the step in two)"
        ));
    }
    Ok(caption)
}

/// A TOML error located: the step it is in (by the `[[step]]` headers before it), the line
/// and column, and the key on that line.
fn syntax_error(text: &str, file: &str, error: &toml::de::Error) -> LessonError {
    // Quoted names from the file may hold control characters: escaped, one line.
    let rule = printable(error.message().trim()).into_owned();
    let Some(span) = error.span() else {
        return LessonError {
            file: file.into(),
            step: None,
            field: String::new(),
            rule,
        };
    };
    let start = span.start.min(text.len());
    let before = &text[..start];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    // The headers up to the end of this line: an error on a `[[step]]` line is that step's.
    let line_end = text[start..].find('\n').map_or(text.len(), |i| start + i);
    let steps_before = text[..line_end]
        .lines()
        .filter(|l| l.trim_start().starts_with("[[step]]"))
        .count();
    let (line, column) = text_position(text, start);
    let this_line = text[line_start..].lines().next().unwrap_or("");
    let key = this_line
        .split_once('=')
        .map(|(key, _)| key.trim())
        .filter(|k| !k.is_empty() && k.len() <= 40 && !k.starts_with('['));
    let place = format!("line {line}, column {column}");
    LessonError {
        file: file.into(),
        step: (steps_before > 0).then_some(steps_before),
        field: match key {
            Some(key) => format!("{key} ({place})"),
            None => place,
        },
        rule,
    }
}
