//! The program run to its end as a script runs it (no terminal, output collected), and the
//! names of the files it leaves.

use std::path::Path;
use std::process::{Command, Output};

/// The environment of a run without colours.
pub const NO_COLOR: &[(&str, &str)] = &[("NO_COLOR", "1")];

/// `beamfric ARGS`, its output collected.
pub fn beamfric(args: &[&str]) -> Output {
    beamfric_with(args, &[])
}

/// `beamfric ARGS` with `env` added to the environment, its output collected.
pub fn beamfric_with(args: &[&str], env: &[(&str, &str)]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_beamfric"))
        .args(args)
        .envs(env.iter().copied())
        .output()
        .expect("the binary runs")
}

/// Every name in `dir` (hidden ones included), sorted.
pub fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}
