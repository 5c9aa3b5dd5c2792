//! Reading a scene file with a size bound: at most [`MAX_SCENE_BYTES`] + 1 bytes are ever
//! read (through `Read::take`), so `/dev/zero`, a FIFO or stdin that never ends, or a huge
//! file, is refused with a message instead of filling memory.

use std::io::Read;
use std::path::Path;

use super::SceneError;

/// Largest scene file accepted: 1 MB (1 048 576 bytes). The presets are under 2 kB.
pub const MAX_SCENE_BYTES: u64 = 1 << 20;

/// The text of the scene file at `path`, or an error naming `source` (the file as the user
/// wrote it) and the rule: larger than [`MAX_SCENE_BYTES`], not UTF-8, or unreadable.
pub fn read_scene_text(path: &Path, source: &str) -> Result<String, SceneError> {
    let limit = MAX_SCENE_BYTES;
    let error = |rule: String| SceneError {
        source: source.to_string(),
        field: String::new(),
        rule,
    };
    let file =
        std::fs::File::open(path).map_err(|e| error(format!("cannot read the file: {e}")))?;
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| error(format!("cannot read the file: {e}")))?;
    if bytes.len() as u64 > limit {
        return Err(error(format!(
            "larger than 1 MB ({limit} bytes), the limit for a scene file; not read"
        )));
    }
    String::from_utf8(bytes).map_err(|e| {
        error(format!(
            "not UTF-8 text (invalid byte at offset {}); a scene file is TOML text",
            e.utf8_error().valid_up_to()
        ))
    })
}
