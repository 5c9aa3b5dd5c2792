//! What the integration tests share.
//!
//! - [`scenes`]: presets as scenes and validated problems, solve options, the reference values
//!   of `tests/data/`, the crowded scene whose solve takes seconds.

pub mod scenes;
