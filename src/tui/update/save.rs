//! Saving the scene: the file-name prompt (pre-filled, the first key replacing it), the
//! question before a file is overwritten, and the save itself — written atomically, only
//! where this explorer may write (a headless render only says what it would do, a served
//! session saves under `--save-dir` or shows the TOML to copy), and followed by what was
//! waiting for it (a quit, a reset, a preset after "save, then …").

use crate::scene::{SaveError, Scene, save_scene};
use crate::tui::input::keymap::Action;
use crate::tui::state::prompt::{Prompt, Typed};
use crate::tui::state::{App, Discard, Mode, SavePolicy};

use super::typing::{edit_prompt, too_long};

/// Longest file name the save prompt accepts (PATH_MAX on Linux).
const PATH_LIMIT: usize = 4096;

/// Where saving to a file is off (a served session): says why, or shows the scene as text.
/// Returns whether it was.
fn saving_is_off(app: &mut App) -> bool {
    match &app.save_policy {
        SavePolicy::Refuse(reason) => app.message = Some(format!("not saved: {reason}")),
        SavePolicy::ShowText => app.mode = Mode::SceneText,
        _ => return false,
    }
    true
}

/// Asks for the file name to save to, unless saving is off here.
pub(super) fn start_save(app: &mut App) {
    if !saving_is_off(app) {
        app.mode = Mode::Save {
            prompt: Prompt::new(app.save_path.clone(), true),
        };
    }
}

/// A key in the file-name prompt. Returns what was waiting for the save (a quit, a reset, a
/// preset) once the scene is saved.
pub(super) fn save_prompt(app: &mut App, action: Action, mut prompt: Prompt) -> Option<Discard> {
    match edit_prompt(&mut prompt, action, PATH_LIMIT) {
        Some(Typed::Full) => {
            app.message = Some(too_long("a file name", PATH_LIMIT, prompt.refused));
            app.mode = Mode::Save { prompt };
            return None;
        }
        Some(Typed::Inserted) => {
            app.mode = Mode::Save { prompt };
            return None;
        }
        None => {}
    }
    match action {
        Action::Confirm => {
            let path = with_extension(prompt.text.trim());
            if prompt.refused > 0 {
                // Saved under a name cut short, the file would be hard to find.
                app.mode = Mode::Normal;
                app.message = Some(format!(
                    "not saved: {}",
                    too_long("a file name", PATH_LIMIT, prompt.refused)
                ));
            } else if path.is_empty() {
                app.mode = Mode::Normal;
                app.message = Some("not saved: no file name".into());
            } else if only_an_extension(&path) {
                // `.toml` alone would be a hidden file of no name (stop 60's pass).
                app.mode = Mode::Normal;
                app.message = Some(format!("not saved: {path} has no name before .toml"));
            } else if save_target(&app.save_policy, &path).is_some_and(|t| t.exists()) {
                // The file the save would write (under --allow-save DIR, inside DIR).
                app.mode = Mode::ConfirmOverwrite { path };
            } else {
                app.mode = Mode::Normal;
                return save(app, &path, false);
            }
        }
        Action::Cancel => {
            app.mode = Mode::Normal;
            app.after_save = None;
            app.message = Some("not saved".into());
        }
        _ => app.mode = Mode::Save { prompt },
    }
    None
}

/// A typed name that does not end in `.toml` gets it: a scene file is TOML, a name without it
/// in the working directory shadows a preset of that name (`beamfric benchmark-1` opens the
/// file first), and a dot of its own (`eps-1e-4.5`, `run-1.5`) is no extension. The status
/// line says the name written.
fn with_extension(typed: &str) -> String {
    let names_a_file = !typed.is_empty() && !typed.ends_with(std::path::MAIN_SEPARATOR);
    if names_a_file && !typed.to_ascii_lowercase().ends_with(".toml") {
        format!("{typed}.toml")
    } else {
        typed.to_string()
    }
}

/// Is the file name of `path` `.toml` and nothing else?
fn only_an_extension(path: &str) -> bool {
    std::path::Path::new(path)
        .file_name()
        .is_some_and(|name| name.eq_ignore_ascii_case(".toml"))
}

/// The answer to "overwrite the file?". Returns what was waiting for the save once the scene
/// is saved.
pub(super) fn confirm_overwrite(app: &mut App, action: Action, path: String) -> Option<Discard> {
    app.mode = Mode::Normal;
    match action {
        Action::Confirm => save(app, &path, true),
        _ => {
            app.after_save = None;
            app.message = Some(format!("not saved: {path} left as it was"));
            None
        }
    }
}

/// Saves the scene to `path`. Returns what was waiting for the save when it succeeded (a
/// failed or refused save drops it).
fn save(app: &mut App, path: &str, overwrite: bool) -> Option<Discard> {
    let then = app.after_save.take();
    if saving_is_off(app) {
        return None;
    }
    let target = match &app.save_policy {
        SavePolicy::Write => std::path::PathBuf::from(path),
        // Handled by `saving_is_off`.
        SavePolicy::Refuse(_) | SavePolicy::ShowText => return None,
        SavePolicy::Simulate => {
            app.message = Some(format!(
                "not saved: a headless render writes no files (it would save to {path}; \
                 --allow-save DIR lets it)"
            ));
            return None;
        }
        SavePolicy::Within(dir) => match save_target(&app.save_policy, path) {
            Some(target) => target,
            None => {
                app.message = Some(format!("not saved: {}", not_a_target(app, dir, path)));
                return None;
            }
        },
    };
    match save_scene(app.scene(), &target, overwrite) {
        Ok(outcome) => {
            app.save_path = path.to_string();
            app.saved = app.scene().clone();
            let notes = outcome.summary();
            app.message = Some(if notes.is_empty() {
                format!("saved to {path}")
            } else {
                format!("saved to {path} ({notes})")
            });
            then
        }
        Err(e) => {
            app.message = Some(format!("not saved: {}", error_shown(app, &e)));
            None
        }
    }
}

/// At the end of a class (or of a session closed for its user): saves a student's unsaved
/// work under names of its own where saves may go (`--save-dir`), never over a file
/// (`alice-benchmark-1.toml`, else `…-2.toml` and on): the scene shown, and every lesson step
/// left with changes under its step's scene's name (stop 60's pass: those were lost). Returns
/// the names written, or `None` when there is nothing to save or nowhere to save it; what is
/// not saved is printed as TOML (`runtime::remote`).
pub(super) fn save_at_closing(app: &mut App) -> Option<String> {
    if !app.has_unsaved_work() || !matches!(app.save_policy, SavePolicy::Within(_)) {
        return None;
    }
    let mut names = Vec::new();
    // Each file says which step it holds where there are steps to tell apart.
    let labelled = !app.changed_steps().is_empty();
    let label = |step: usize| {
        if labelled {
            format!(" (step {})", step + 1)
        } else {
            String::new()
        }
    };
    if app.modified() {
        let scene = app.scene().clone();
        let shown = app.exploration.lesson.as_ref().map(|place| place.step);
        if let Some(name) = save_under_a_free_name(app, &scene, &app.save_path) {
            app.save_path = name.clone();
            app.saved = scene;
            names.push(format!("{name}{}", shown.map(label).unwrap_or_default()));
        }
    }
    for step in app.changed_steps() {
        let Some(place) = &app.exploration.lesson else {
            break;
        };
        let offered = crate::tui::state::app::default_save_path(
            &app.save_policy,
            Some(&app.save_directory),
            app.owner.as_deref(),
            &place.lesson.step(step).scene.source,
        );
        let Some(scene) = app.step_edits.get(&step).map(|edits| edits.scene.clone()) else {
            continue;
        };
        if let Some(name) = save_under_a_free_name(app, &scene, &offered) {
            if let Some(edits) = app.step_edits.get_mut(&step) {
                edits.saved = scene;
            }
            names.push(format!("{name}{}", label(step)));
        }
    }
    (!names.is_empty()).then(|| names.join(", "))
}

/// Saves `scene` as `offered`, or `…-2.toml` and on where that is taken; the name written.
fn save_under_a_free_name(app: &App, scene: &Scene, offered: &str) -> Option<String> {
    let stem = offered.strip_suffix(".toml").unwrap_or(offered);
    for attempt in 1..=100 {
        let name = match attempt {
            1 => format!("{stem}.toml"),
            n => format!("{stem}-{n}.toml"),
        };
        // Never over anything: a file, or a link (even to nothing, which has no target inside
        // the directory), takes the next name.
        let Some(target) = save_target(&app.save_policy, &name) else {
            continue;
        };
        match save_scene(scene, &target, false) {
            Ok(_) => return Some(name),
            Err(SaveError::Exists(_) | SaveError::DanglingLink(..)) => continue,
            Err(_) => return None,
        }
    }
    None
}

/// The file a save of `path` writes: the path itself, or under `--allow-save DIR` the path
/// inside DIR (`None` when it leads out of DIR, by `..`, an absolute path elsewhere, or a
/// symbolic link inside DIR that points out — the save would follow it).
pub fn save_target(policy: &SavePolicy, path: &str) -> Option<std::path::PathBuf> {
    use std::path::Component;
    let dir = match policy {
        SavePolicy::Within(dir) => dir,
        _ => return Some(std::path::PathBuf::from(path)),
    };
    let real_dir = dir.canonicalize().ok()?;
    let path = std::path::Path::new(path);
    let relative = path
        .strip_prefix(dir)
        .or_else(|_| path.strip_prefix(&real_dir))
        .unwrap_or(path);
    let plain = relative
        .components()
        .all(|c| matches!(c, Component::Normal(_) | Component::CurDir));
    if !plain || relative.as_os_str().is_empty() {
        return None;
    }
    let target = real_dir.join(relative);
    // Where the write really lands: the parent resolved, and the file's own link followed.
    let parent = target.parent()?.canonicalize().ok()?;
    let landing = match std::fs::symlink_metadata(&target) {
        Ok(meta) if meta.file_type().is_symlink() => target.canonicalize().ok()?,
        _ => parent.join(target.file_name()?),
    };
    landing.starts_with(&real_dir).then_some(target)
}

/// The one directory saves may go to, as the user is shown it: a served session's (it has an
/// owner) is the class's save directory, never the server's own path; a render's
/// `--allow-save DIR` is the user's own DIR.
pub(super) fn directory_shown(app: &App, dir: &std::path::Path) -> String {
    if app.owner.is_some() {
        "the class's save directory".into()
    } else {
        dir.display().to_string()
    }
}

/// `error` (a save's or a figure's, which names the file written) as the user is shown it:
/// the save directory's path put as [`directory_shown`] puts it (a served session never reads
/// the server's own path: stop 60's pass found `not saved: … /srv/class/sub/`).
pub(super) fn error_shown(app: &App, error: &dyn std::fmt::Display) -> String {
    let text = error.to_string();
    match &app.save_policy {
        SavePolicy::Within(dir) if app.owner.is_some() => {
            text.replace(&dir.display().to_string(), &directory_shown(app, dir))
        }
        _ => text,
    }
}

/// Why `path` is no file a save may write under the save directory `dir` ([`save_target`]
/// said none): a folder of it that does not exist there (stop 60's pass: `nodir/x` was called
/// outside the directory), or a path out of it.
pub(super) fn not_a_target(app: &App, dir: &std::path::Path, path: &str) -> String {
    let shown = directory_shown(app, dir);
    let inside = std::path::Path::new(path)
        .components()
        .all(|c| matches!(c, std::path::Component::Normal(_)));
    if let (true, Some(folder), Ok(real_dir)) = (
        inside,
        std::path::Path::new(path).parent(),
        dir.canonicalize(),
    ) && !folder.as_os_str().is_empty()
        && std::fs::symlink_metadata(real_dir.join(folder)).is_err()
    {
        return format!(
            "there is no folder {} in {shown} (only files may be made there, not folders)",
            folder.display()
        );
    }
    format!(
        "{path} is outside {shown}, the only directory files may go to (or a link leads out of it)"
    )
}
