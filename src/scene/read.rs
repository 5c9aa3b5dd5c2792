//! Reading a scene file safely: only a regular file is read (a FIFO, a device, a directory or
//! a socket is refused before it is opened, and the file is opened without blocking and looked
//! at again, so a FIFO swapped in meanwhile cannot make the read wait for a writer), and at
//! most [`MAX_SCENE_BYTES`] + 1 bytes are ever read (through `Read::take`), so a huge file is
//! refused with a message instead of filling memory.

use std::fs::{File, FileType, Metadata};
use std::io::Read;
use std::path::Path;

use super::SceneError;

/// Largest scene file accepted: 1 MB (1 048 576 bytes). The presets are under 2 kB.
pub const MAX_SCENE_BYTES: u64 = 1 << 20;

/// The text of the scene file at `path`, or an error naming `source` (the file as the user
/// wrote it) and the rule: not a regular file, larger than [`MAX_SCENE_BYTES`], not UTF-8, or
/// unreadable.
pub fn read_scene_text(path: &Path, source: &str) -> Result<String, SceneError> {
    let limit = MAX_SCENE_BYTES;
    let error = |rule: String| SceneError {
        source: source.to_string(),
        field: String::new(),
        rule,
    };
    let bytes = read_regular_file(path, limit).map_err(|refusal| match refusal {
        Refusal::Unreadable(e) => error(format!("cannot read the file: {e}")),
        Refusal::NotRegular(kind) => {
            error(format!("{kind}; a scene is read only from a regular file"))
        }
        Refusal::TooLarge => error(format!(
            "larger than 1 MB ({limit} bytes), the limit for a scene file; not read"
        )),
    })?;
    String::from_utf8(bytes).map_err(|e| {
        error(format!(
            "not UTF-8 text (invalid byte at offset {}); a scene file is TOML text",
            e.utf8_error().valid_up_to()
        ))
    })
}

/// Why [`read_regular_file`] read nothing.
pub(crate) enum Refusal {
    /// The system refused.
    Unreadable(std::io::Error),
    /// Not a regular file: what it is, in words ("a FIFO (named pipe), not a regular file").
    NotRegular(String),
    /// Larger than the limit (only the limit and one byte more were read).
    TooLarge,
}

/// The bytes of the regular file at `path` if it holds at most `limit` of them: a FIFO,
/// device, directory or socket is refused before it is opened (and looked at again once
/// opened), and no more than `limit` + 1 bytes are read. Scenes, lessons and answers to
/// grade are read through it.
pub(crate) fn read_regular_file(path: &Path, limit: u64) -> Result<Vec<u8>, Refusal> {
    let unreadable = Refusal::Unreadable;
    // Looked at before it is opened: opening a FIFO for reading waits for a writer.
    let meta = std::fs::metadata(path).map_err(unreadable)?;
    check_regular(&meta).map_err(Refusal::NotRegular)?;
    let file = open_without_waiting(path).map_err(unreadable)?;
    // The file opened may not be the one looked at (it may have been replaced meanwhile).
    check_regular(&file.metadata().map_err(unreadable)?).map_err(Refusal::NotRegular)?;
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(unreadable)?;
    if bytes.len() as u64 > limit {
        return Err(Refusal::TooLarge);
    }
    Ok(bytes)
}

/// The rule a file's type must follow: a regular file (or a symbolic link to one); else what
/// it is instead.
fn check_regular(meta: &Metadata) -> Result<(), String> {
    if meta.is_file() {
        return Ok(());
    }
    Err(format!("{}, not a regular file", kind_of(meta.file_type())))
}

/// What a file that is not a regular file is, in words.
fn kind_of(file_type: FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if file_type.is_char_device() {
            return "a character device";
        }
        if file_type.is_block_device() {
            return "a block device";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    if file_type.is_dir() {
        "a directory"
    } else {
        "a special file"
    }
}

/// Opens `path` for reading without ever waiting (`O_NONBLOCK`: a FIFO without a writer
/// opens at once; a regular file reads as without it).
fn open_without_waiting(path: &Path) -> std::io::Result<File> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(nix::libc::O_NONBLOCK);
    }
    options.open(path)
}
