//! Atomic saving. The bytes go to a fresh temporary file made by the `tempfile` crate in the
//! target's directory (random name, `O_CREAT | O_EXCL`, so a symlink or file planted at any
//! name is never followed or reused), which is synced, renamed over the target and the
//! directory synced: a crash, a full disk or a failed write never leaves a half-written file,
//! and the old content stays until the new one is complete.
//!
//! Decisions, documented in README "Reliability":
//! - **A symlink** at the target is followed: its final target is replaced atomically (the
//!   temporary file sits next to it) and the link itself stays as it was. A link whose target
//!   is missing is refused rather than followed to create a file somewhere else.
//! - **Permissions** of a replaced file are kept (0600 stays 0600; set-id bits are dropped);
//!   a new file gets 0666 less the umask, as `File::create` would. The owner is kept when the
//!   system allows it, otherwise a note says the file changed hands.
//! - **Hard links** cannot survive a rename: when the file had other names, the
//!   [`SaveOutcome`] says so (those names keep the old content).
//! - Only regular files are replaced: a directory, a device or a FIFO at the target is an
//!   error, and nothing is written.

use std::fmt;
use std::io::Write;
use std::path::{Path, PathBuf};

use super::Scene;
use super::serialize::{SAVED_HEADER, scene_to_toml};

/// Why a save failed; nothing was changed on disk.
#[derive(Debug)]
pub enum SaveError {
    /// The target exists and overwriting was not confirmed.
    Exists(PathBuf),
    /// The target is a symbolic link to nothing (the link, where it points): a save never
    /// follows it to create a file elsewhere.
    DanglingLink(PathBuf, PathBuf),
    /// The file system refused.
    Io(PathBuf, std::io::Error),
}

impl fmt::Display for SaveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SaveError::Exists(path) => write!(
                f,
                "{} exists and was not overwritten: save again and confirm, or choose another \
                 name",
                path.display()
            ),
            SaveError::DanglingLink(link, points_to) => write!(
                f,
                "{} is a symbolic link to {}, which does not exist; not followed: remove the \
                 link or choose another name",
                link.display(),
                points_to.display()
            ),
            // The reason first: a long path would push it off a status line.
            SaveError::Io(path, e) => write!(f, "cannot save ({e}): {}", path.display()),
        }
    }
}

impl std::error::Error for SaveError {}

/// What a successful save did, for the user to see.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SaveOutcome {
    /// The file whose content was replaced: the path given, or a symlink's final target.
    pub written: PathBuf,
    /// Things the user should know, in words (empty for a plain save), e.g. "the file had 2
    /// links; the other names keep the old content".
    pub notes: Vec<String>,
}

impl SaveOutcome {
    /// The notes joined for a status line ("" when there are none).
    pub fn summary(&self) -> String {
        self.notes.join("; ")
    }
}

/// Writes `text` to `path` atomically (see the module documentation). With
/// `overwrite == false` anything already at `path` — a file or a symlink — is an error.
/// Kept for callers that need no [`SaveOutcome`]; [`write_atomic`] returns it.
pub fn save_atomic(path: &Path, text: &str, overwrite: bool) -> Result<(), SaveError> {
    write_atomic(path, text.as_bytes(), overwrite).map(|_| ())
}

/// Serializes `scene` (a fixed comment line, then [`Scene::to_toml`]) and saves it with
/// [`write_atomic`]. The text is parsed back first: a scene that would not load back to the
/// same model is refused and nothing is written.
pub fn save_scene(scene: &Scene, path: &Path, overwrite: bool) -> Result<SaveOutcome, SaveError> {
    let text = format!("{SAVED_HEADER}{}", scene_to_toml(scene));
    match Scene::from_toml(&text, &path.display().to_string()) {
        Ok(again) if again == *scene => {}
        Ok(_) => {
            return Err(SaveError::Io(
                path.to_path_buf(),
                std::io::Error::other("the scene would not read back the same (NaN value?)"),
            ));
        }
        Err(e) => {
            return Err(SaveError::Io(
                path.to_path_buf(),
                std::io::Error::other(format!("the scene would not read back: {e}")),
            ));
        }
    }
    write_atomic(path, text.as_bytes(), overwrite)
}

/// Writes `bytes` to `path` atomically and says what it did (see the module documentation
/// for symlinks, permissions and hard links). With `overwrite == false` anything already at
/// `path` is an error ([`SaveError::Exists`]), also when it appears during the save.
pub fn write_atomic(path: &Path, bytes: &[u8], overwrite: bool) -> Result<SaveOutcome, SaveError> {
    let io = |e| SaveError::Io(path.to_path_buf(), e);
    let existing = match std::fs::symlink_metadata(path) {
        Ok(meta) => Some(meta),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => return Err(io(e)),
    };
    if let Some(meta) = &existing
        && meta.file_type().is_symlink()
        && let Err(e) = std::fs::metadata(path)
        && e.kind() == std::io::ErrorKind::NotFound
    {
        let points_to = std::fs::read_link(path).map_err(io)?;
        return Err(SaveError::DanglingLink(path.to_path_buf(), points_to));
    }
    if existing.is_some() && !overwrite {
        return Err(SaveError::Exists(path.to_path_buf()));
    }
    let mut notes = Vec::new();

    // The file to replace: the path itself, or the final target of a symlink.
    let (target, target_meta) = match existing {
        Some(meta) if meta.file_type().is_symlink() => {
            let resolved = std::fs::canonicalize(path).map_err(|e| {
                io(std::io::Error::new(
                    e.kind(),
                    format!(
                        "it is a symbolic link whose target cannot be resolved ({e}); not followed"
                    ),
                ))
            })?;
            let meta = std::fs::metadata(&resolved).map_err(io)?;
            notes.push(format!(
                "{} is a symbolic link: wrote its target {}",
                path.display(),
                resolved.display()
            ));
            (resolved, Some(meta))
        }
        other => (path.to_path_buf(), other),
    };
    if let Some(meta) = &target_meta
        && !meta.is_file()
    {
        return Err(io(std::io::Error::other(format!(
            "{} is not a regular file",
            target.display()
        ))));
    }

    let directory = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let file_name = target
        .file_name()
        .ok_or_else(|| io(std::io::Error::other("not a file name")))?;

    let mut prefix = std::ffi::OsString::from(".");
    prefix.push(file_name);
    prefix.push(".");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    if target_meta.is_none() {
        // Created with 0666 less the umask, as `File::create` would.
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut temporary = builder.tempfile_in(&directory).map_err(io)?;

    #[cfg(unix)]
    if let Some(meta) = &target_meta {
        keep_metadata(temporary.as_file(), meta, &target, &mut notes).map_err(io)?;
    }

    temporary.write_all(bytes).map_err(io)?;
    temporary.as_file().sync_all().map_err(io)?;

    // Dropping a failed `persist`'s temporary file deletes it.
    let persisted = if overwrite {
        temporary.persist(&target)
    } else {
        temporary.persist_noclobber(&target)
    };
    if let Err(e) = persisted {
        if e.error.kind() == std::io::ErrorKind::AlreadyExists {
            return Err(SaveError::Exists(path.to_path_buf()));
        }
        return Err(io(e.error));
    }
    // The rename is durable once the directory is synced.
    std::fs::File::open(&directory)
        .and_then(|d| d.sync_all())
        .map_err(io)?;
    Ok(SaveOutcome {
        written: target,
        notes,
    })
}

/// Gives the temporary file the replaced file's permissions and owner, and notes what
/// cannot be kept (other hard links, an owner the system does not let us keep).
#[cfg(unix)]
fn keep_metadata(
    file: &std::fs::File,
    meta: &std::fs::Metadata,
    target: &Path,
    notes: &mut Vec<String>,
) -> std::io::Result<()> {
    use std::os::unix::fs::{MetadataExt, PermissionsExt, fchown};
    let wanted = (meta.uid(), meta.gid());
    let ours = file.metadata()?;
    if (ours.uid(), ours.gid()) != wanted && fchown(file, Some(wanted.0), Some(wanted.1)).is_err() {
        // Not allowed to give the file away: keep at least the group if we may.
        let _ = fchown(file, None, Some(wanted.1));
    }
    // After the chown, which may clear mode bits.
    file.set_permissions(std::fs::Permissions::from_mode(meta.mode() & 0o777))?;
    let now = file.metadata()?;
    if (now.uid(), now.gid()) != wanted {
        notes.push(format!(
            "{} belonged to uid {} gid {}; it now belongs to uid {} gid {}",
            target.display(),
            wanted.0,
            wanted.1,
            now.uid(),
            now.gid()
        ));
    }
    if meta.nlink() > 1 {
        notes.push(format!(
            "{} had {} links; the other names keep the old content",
            target.display(),
            meta.nlink()
        ));
    }
    Ok(())
}
