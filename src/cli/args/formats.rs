//! The output formats the commands print in (`--format`), one type per command family, so
//! that each command's help lists only what it takes.

use clap::ValueEnum;

/// Output format of `grade` (`solve`'s csv, a convergence history, has no grade to show).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum GradeFormat {
    Table,
    Json,
}

/// Output format of the sweeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TableFormat {
    Csv,
    Json,
}

/// Output format of `check`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CheckFormat {
    Markdown,
    Json,
}

/// Output format of `solve`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    Json,
    Table,
    /// The convergence history, one row per iterate (with --history).
    Csv,
}
