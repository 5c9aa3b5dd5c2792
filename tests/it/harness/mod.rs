//! What the integration tests share.
//!
//! - [`scenes`]: presets as scenes, loaded scenes and validated problems, solve options, the
//!   reference values of `tests/data/`, the crowded scene whose solve takes seconds.
//! - [`process`]: the program run to its end as a script runs it (no terminal), and the names
//!   of the files it leaves.
//! - [`screen`]: finding text on a screen and mouse reports to send to it.

pub mod process;
pub mod scenes;
pub mod screen;
