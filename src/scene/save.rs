//! Atomic saving: the text goes to a temporary file in the target's directory, is flushed to
//! disk, then renamed over the target, so a crash or a full disk never leaves a half-written
//! scene. An existing file is only replaced when the caller says so.

use std::fmt;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Why a save failed; nothing was changed on disk.
#[derive(Debug)]
pub enum SaveError {
    /// The target exists and overwriting was not confirmed.
    Exists(PathBuf),
    /// The file system refused.
    Io(PathBuf, std::io::Error),
}

impl fmt::Display for SaveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SaveError::Exists(path) => write!(
                f,
                "{} exists; confirm to overwrite it (or use --force)",
                path.display()
            ),
            SaveError::Io(path, e) => write!(f, "cannot save {}: {e}", path.display()),
        }
    }
}

impl std::error::Error for SaveError {}

/// Writes `text` to `path` atomically. With `overwrite == false` an existing file is an error.
pub fn save_atomic(path: &Path, text: &str, overwrite: bool) -> Result<(), SaveError> {
    if !overwrite && path.exists() {
        return Err(SaveError::Exists(path.to_path_buf()));
    }
    let io = |e| SaveError::Io(path.to_path_buf(), e);
    let directory = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let file_name = path
        .file_name()
        .ok_or_else(|| io(std::io::Error::other("not a file name")))?;
    let temporary = directory.join(format!(
        ".{}.{}.tmp",
        file_name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| {
        let mut file = std::fs::File::create(&temporary)?;
        file.write_all(text.as_bytes())?;
        file.sync_all()?;
        drop(file);
        if !overwrite && path.exists() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::AlreadyExists,
                "appeared while saving",
            ));
        }
        std::fs::rename(&temporary, path)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&temporary);
        if e.kind() == std::io::ErrorKind::AlreadyExists {
            return Err(SaveError::Exists(path.to_path_buf()));
        }
        return Err(io(e));
    }
    Ok(())
}
