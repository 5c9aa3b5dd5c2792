//! Saving the scene: the file-name prompt (pre-filled, the first key replacing it), the
//! question before a file is overwritten, and the save itself — written atomically, only
//! where this explorer may write (a headless render only says what it would do, a served
//! session saves under `--save-dir` or shows the TOML to copy), and followed by what was
//! waiting for it (a quit, a reset, a preset after "save, then …").

use crate::scene::{SaveError, save_scene};
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

/// A typed name without an extension gets `.toml`: a scene is found by that (`beamfric my`
/// would look for a preset called `my`), and the name the save says shows it. A name with an
/// extension of its own is kept as typed.
fn with_extension(typed: &str) -> String {
    let path = std::path::Path::new(typed);
    let names_a_file = !typed.is_empty() && !typed.ends_with(std::path::MAIN_SEPARATOR);
    if names_a_file && path.file_name().is_some() && path.extension().is_none() {
        format!("{typed}.toml")
    } else {
        typed.to_string()
    }
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
                app.message = Some(format!(
                    "not saved: {path} is outside {}, the only directory saves may go to (or a \
                     link leads out of it)",
                    directory_shown(app, dir)
                ));
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
            app.message = Some(format!("not saved: {e}"));
            None
        }
    }
}

/// At the end of a class: saves a student's unsaved work under a name of its own where saves
/// may go (`--save-dir`), never over a file (`alice-benchmark-1.toml`, else `…-2.toml` and
/// on). Returns the name, or `None` when there is nothing to save or nowhere to save it (the
/// closing screen shows the TOML either way).
pub(super) fn save_at_closing(app: &mut App) -> Option<String> {
    if !app.modified() || !matches!(app.save_policy, SavePolicy::Within(_)) {
        return None;
    }
    let offered = app.save_path.clone();
    let stem = offered
        .strip_suffix(".toml")
        .unwrap_or(&offered)
        .to_string();
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
        match save_scene(app.scene(), &target, false) {
            Ok(_) => {
                app.save_path = name.clone();
                app.saved = app.scene().clone();
                return Some(name);
            }
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
