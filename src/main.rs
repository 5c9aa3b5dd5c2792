//! The `beamfric` binary: parse the command line, hand it to the library.

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    match beamfric::cli::Cli::try_parse() {
        Ok(cli) => beamfric::cli::dispatch(cli),
        Err(e) => beamfric::cli::report_usage_error(e),
    }
}
