//! Bring your own method (issue 24): the discrete problem goes out as plain files, a
//! student's answer comes back and is graded like the built-in methods' answers.
//!
//! - `discrete`: A and b of (36)–(39), B of (46) and g of (45) from the assembly every method
//!   uses, as Matrix Market (`%.17g`) and JSON.
//! - `export`: `beamfric export`, those files, the mesh and a README of the conventions,
//!   written atomically and never over existing files without `--force`.
//! - `answer`: reading an answer — forces λ of (48), nodal u and u', or both — as JSON (the
//!   document `beamfric solve --format json` prints is one form) or CSV.
//! - `grade`: `beamfric grade`, the answer certified by [`crate::solve::grade`] (KKT residual
//!   of (38), friction states, error against the reference, warnings) and printed.

mod answer;
mod discrete;
mod export;
mod grade;
#[cfg(test)]
mod tests;

use std::fmt;
use std::path::{Path, PathBuf};

pub use answer::{AnswerError, AnswerFormat, AnswerShape, parse_answer};
pub use discrete::{DiscreteProblem, Entry, g17};
pub use export::{EXPORT_FILES, ExportedScene, export};
pub use grade::{Grade, GradeContext, Verdict, grade_file};

use crate::solve::GradeError;

/// Why an export or a grading failed, naming the file.
#[derive(Debug)]
pub enum ExchangeError {
    /// The file system refused (the path, what was being done, why).
    Io {
        path: PathBuf,
        action: &'static str,
        reason: String,
    },
    /// Files of an export exist and `--force` was not given; nothing was written.
    Exists(Vec<PathBuf>),
    /// The answer file breaks a rule of its format.
    Answer { file: PathBuf, error: AnswerError },
    /// The answer could not be graded (it does not fit the scene, or rebuilding failed).
    Grade { file: PathBuf, error: GradeError },
}

impl ExchangeError {
    /// A failure to write `path`.
    pub(crate) fn io(path: &Path, error: std::io::Error) -> ExchangeError {
        ExchangeError::Io {
            path: path.to_path_buf(),
            action: "write",
            reason: error.to_string(),
        }
    }
}

impl fmt::Display for ExchangeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let show = |p: &Path| crate::format::printable(&p.display().to_string()).into_owned();
        match self {
            ExchangeError::Io {
                path,
                action,
                reason,
            } => write!(f, "cannot {action} {}: {reason}", show(path)),
            ExchangeError::Exists(paths) => {
                let names: Vec<String> = paths.iter().map(|p| show(p)).collect();
                let verb = if paths.len() == 1 { "exists" } else { "exist" };
                write!(
                    f,
                    "{} {verb} and nothing was written: pass --force to replace, or choose \
                     another --out",
                    names.join(", ")
                )
            }
            ExchangeError::Answer { file, error } => write!(f, "{}: {error}", show(file)),
            ExchangeError::Grade { file, error } => write!(f, "{}: {error}", show(file)),
        }
    }
}

impl std::error::Error for ExchangeError {}
