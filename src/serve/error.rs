//! Why `beamfric serve` or `beamfric present` could not start, or a session could not.

use crate::lesson::LessonError;
use crate::scene::SceneError;
use crate::tui::TerminalError;

/// What went wrong, in categories a caller can tell apart; each says in words what and where.
#[derive(Debug)]
pub enum ServeError {
    /// An option breaks its rule (the text names the option and the rule).
    Option(String),
    /// The scene every session starts with could not be loaded.
    Scene(SceneError),
    /// The lesson (`--lesson`) could not be read or is not valid.
    Lesson(LessonError),
    /// A host key, authorized-keys or password file is missing, unreadable, malformed or
    /// readable by others (the text names the file).
    Secret(String),
    /// The address cannot be listened on.
    Listen {
        address: String,
        source: std::io::Error,
    },
    /// The server's runtime or one of its threads could not start.
    Start(String),
    /// The lecturer's own explorer (`present`) failed.
    Terminal(TerminalError),
    /// The recording (`present --record`) could not be finished (the text says why and what
    /// the file holds).
    Recording(String),
}

impl std::fmt::Display for ServeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ServeError::Option(text)
            | ServeError::Secret(text)
            | ServeError::Start(text)
            | ServeError::Recording(text) => f.write_str(text),
            ServeError::Scene(e) => e.fmt(f),
            ServeError::Lesson(e) => e.fmt(f),
            ServeError::Listen { address, source } => {
                write!(f, "cannot listen on {address}: {source}")
            }
            ServeError::Terminal(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for ServeError {}

impl From<LessonError> for ServeError {
    fn from(e: LessonError) -> Self {
        ServeError::Lesson(e)
    }
}

impl From<SceneError> for ServeError {
    fn from(e: SceneError) -> Self {
        ServeError::Scene(e)
    }
}
