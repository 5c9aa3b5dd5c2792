//! beamfric: a clamped Euler–Bernoulli beam through point obstacles with given sliding and
//! swivel friction (Bobková & Pospíšil, *Mathematics* 2021, 9(8), 898), solved by the paper's
//! regularised and dual methods, closed forms, and a force formulation that stays accurate at
//! any mesh size.
//!
//! - [`scene`]: TOML scenes, validation, presets, atomic saving.
//! - [`lesson`]: lesson files, a lecture's steps with their scenes and captions.
//! - [`model`]: the validated physical problem.
//! - [`fem`]: Hermite cubic mesh, assembly, evaluation.
//! - [`linalg`]: the block-tridiagonal factorization, the box QP, condition numbers.
//! - [`solve`]: one module per method and the common [`solve::Solution`].
//! - [`study`]: ε sweeps and mesh sweeps (the explorer's charts, `sweep`, `report`).
//! - [`figure`]: slide-quality SVG figures of the panels (`e`, `figure`, `report`).
//! - [`plot`]: look, theme, ASCII mapping and log-axis charts shared by the explorer and reports.
//! - [`tui`]: the explorer (terminal UI and headless rendering).
//! - [`check`]: the stability suite on the presets (`beamfric check`).
//! - [`report`]: the error-against-run-time report (`beamfric report`).
//! - [`exchange`]: bring your own method: the discrete problem exported as plain files
//!   (`beamfric export`), an answer computed elsewhere graded (`beamfric grade`).
//! - [`cli`], [`output`], [`format`]: the command line and what it prints.
//! - [`memory`]: the allocator set to keep a solve's freed memory for the next.

// Numerical kernels index several arrays in lockstep (matrix rows, vectors, bounds); an index
// reads closer to the formulas than zipped iterators there.
#![allow(clippy::needless_range_loop)]

pub mod check;
pub mod cli;
pub mod exchange;
pub mod fem;
pub mod figure;
pub mod format;
pub mod lesson;
pub mod linalg;
pub mod memory;
pub mod model;
pub mod output;
pub mod plot;
pub mod report;
pub mod scene;
#[cfg(unix)]
pub mod serve;
pub mod solve;
pub mod study;
pub mod tui;
