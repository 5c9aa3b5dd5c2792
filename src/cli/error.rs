//! Why a command failed before it could give its answer (exit status 2, one line on stderr):
//! an argument, a scene, the terminal, the server or a report's destination.

use crate::lesson::LessonError;
use crate::report::ReportError;
use crate::scene::SceneError;
#[cfg(unix)]
use crate::serve::ServeError;
use crate::tui::ExploreError;

/// A command's failure, in categories a caller can tell apart; each says in words what.
#[derive(Debug)]
pub enum CliError {
    /// An argument breaks its rule (the text names the argument and the rule).
    Argument(String),
    /// A scene could not be loaded or is not valid.
    Scene(SceneError),
    /// A lesson could not be read or is not valid.
    Lesson(LessonError),
    /// The command draws on a terminal, and standard output is not one (the text says what
    /// to use instead).
    NotATerminal(&'static str),
    /// The command needs a system this is not (the text says which).
    Unsupported(&'static str),
    /// `beamfric serve` or `beamfric present` failed.
    #[cfg(unix)]
    Serve(ServeError),
    /// The explorer failed.
    Explore(ExploreError),
    /// A report's destination cannot be used or written.
    Report(ReportError),
    /// A figure's file cannot be written (the text names it and says why).
    Figure(String),
    /// An export cannot be written, or an answer cannot be read or graded (the text names
    /// the file, the field and the rule).
    Exchange(crate::exchange::ExchangeError),
    /// Standard output cannot be written (a full disk behind a redirection): the answer
    /// printed is incomplete.
    Output(std::io::Error),
}

impl std::fmt::Display for CliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CliError::Argument(text) => f.write_str(text),
            CliError::Scene(e) => e.fmt(f),
            CliError::Lesson(e) => e.fmt(f),
            CliError::NotATerminal(text) | CliError::Unsupported(text) => f.write_str(text),
            #[cfg(unix)]
            CliError::Serve(e) => e.fmt(f),
            CliError::Explore(e) => e.fmt(f),
            CliError::Report(e) => e.fmt(f),
            CliError::Figure(text) => f.write_str(text),
            CliError::Exchange(e) => e.fmt(f),
            CliError::Output(e) => write!(
                f,
                "cannot write to standard output ({e}): what was printed is incomplete"
            ),
        }
    }
}

impl std::error::Error for CliError {}

impl From<LessonError> for CliError {
    fn from(e: LessonError) -> Self {
        CliError::Lesson(e)
    }
}

impl From<SceneError> for CliError {
    fn from(e: SceneError) -> Self {
        CliError::Scene(e)
    }
}

#[cfg(unix)]
impl From<ServeError> for CliError {
    fn from(e: ServeError) -> Self {
        CliError::Serve(e)
    }
}

impl From<ExploreError> for CliError {
    fn from(e: ExploreError) -> Self {
        CliError::Explore(e)
    }
}

impl From<ReportError> for CliError {
    fn from(e: ReportError) -> Self {
        CliError::Report(e)
    }
}

/// Writes `text` to standard output. A reader that stopped reading (a broken pipe: `beamfric
/// solve | head`) is no failure; any other error (a full disk behind `> file`) is
/// [`CliError::Output`], so that a script is not handed a cut answer with exit status 0.
pub(super) fn write_stdout(text: &str) -> Result<(), CliError> {
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    // Flushed here, not at exit (where an error would go unseen): a text not ending in a
    // newline stays in the line buffer until then.
    match stdout
        .write_all(text.as_bytes())
        .and_then(|()| stdout.flush())
    {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(CliError::Output(e)),
        _ => Ok(()),
    }
}
