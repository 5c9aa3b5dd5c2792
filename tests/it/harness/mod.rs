//! What the integration tests share.
//!
//! - [`scenes`]: presets as scenes, loaded scenes and validated problems, solve options, a
//!   converged `condensed` solve, the reference values of `tests/data/`, the crowded scene
//!   whose solve takes seconds.
//! - [`process`]: the program run to its end as a script runs it (no terminal), and the names
//!   of the files it leaves.
//! - [`pty`]: the program on a pseudo-terminal of its own, as a person at a terminal runs it.
//! - [`ssh`]: a russh client of `beamfric serve`, logins, and a served explorer as the client
//!   sees it.
//! - [`screen`]: finding text on a screen and mouse reports to send to it.
//! - [`wait`]: waiting for a condition (`eventually`) instead of sleeping or timing.
//! - [`serve_process`]: `beamfric serve` as a process of its own, its log line by line.
//! - [`lecture`]: `beamfric present` on a pty, past its join screen.
//! - [`cpu`]: a thread's CPU time, to wait until work is provably under way.
//! - [`seed`]: the one seed of every random draw, `BEAMFRIC_SEED`, printed to repeat a run.

pub mod cpu;
#[cfg(unix)]
pub mod lecture;
pub mod process;
#[cfg(unix)]
pub mod pty;
pub mod scenes;
pub mod screen;
pub mod seed;
pub mod serve_process;
#[cfg(unix)]
pub mod ssh;
pub mod wait;
