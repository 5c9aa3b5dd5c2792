//! The integration tests, one binary (one link of the library instead of one per file).
//!
//! One module per area, each named after the file it was before (`cargo test --test it
//! serve::` runs the served explorer's tests, `cargo test --test it explorer::` the
//! explorer's); [`harness`] is what they share, [`reference`] the independent multi-precision
//! reference solver the numerical checks compare with (also used by `benches/reference.rs`).
//! Fixtures stay in `tests/scenes/` and `tests/data/`, insta snapshots in `tests/it/snapshots/`.

mod harness;
mod reference;

mod architecture;
mod cancel;
mod certificate;
#[cfg(unix)]
mod class_controls;
mod cli_solve;
mod condensed;
mod escaping;
mod exchange;
mod explorer;
mod families;
mod figure;
mod fitting;
mod fuzz;
mod half_ties;
mod headless;
mod history;
mod lessons;
mod markers;
mod method_panels;
mod mouse;
mod numerics;
mod paper_figures;
mod presets;
mod properties;
#[cfg(unix)]
mod record;
mod reference_check;
mod render;
mod report_atomic;
mod save_roundtrip;
mod save_safety;
mod scene;
#[cfg(unix)]
mod serve;
mod serve_attacks;
mod study;
#[cfg(unix)]
mod terminal;
mod ties;
