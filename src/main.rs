//! The `beamfric` binary: parse the command line, hand it to the library.

use std::process::ExitCode;

use beamfric::cli::{Cli, Command};
use clap::Parser;

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return beamfric::cli::report_usage_error(e),
    };
    // One user's solves keep the memory they free for the next; a classroom server, whose
    // sessions come and go, hands it back to the system (`beamfric::memory`).
    if !matches!(cli.command, Some(Command::Serve(_) | Command::Present(_))) {
        // SAFETY: only this thread runs yet (parsing starts none).
        unsafe { beamfric::memory::keep_freed_memory() };
    }
    beamfric::cli::dispatch(cli)
}
