//! `beamfric solve --history`: which formats print the convergence history, and its CSV.

use super::CliError;
use super::args::Format;
use crate::solve::Solution;

/// `--format csv` prints the history only, so it needs `--history`; the table has no place
/// for it, so `--history` needs JSON or CSV.
pub(super) fn check_format(format: Format, history: bool) -> Result<(), CliError> {
    match (format, history) {
        (Format::Csv, false) => Err(CliError::Argument(
            "--format csv prints the convergence history: add --history (or use --format json \
             or table for the solution)"
                .into(),
        )),
        (Format::Table, true) => Err(CliError::Argument(
            "--history prints with --format json (under \"history\") or --format csv (one row \
             per iterate)"
                .into(),
        )),
        _ => Ok(()),
    }
}

/// The CSV of `solve --history --format csv`.
pub(super) fn csv_text(solution: &Solution) -> String {
    crate::output::history_csv(solution)
}
