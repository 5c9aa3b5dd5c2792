//! One seed for every random draw of the suite (the property tests, the fuzzers), printed by
//! every test that draws from it, so that a failing test's output says how to repeat it:
//! `BEAMFRIC_SEED=N cargo test` draws exactly what the run that printed N drew.
//!
//! The seed is `BEAMFRIC_SEED` if set, else `PROPTEST_RNG_SEED` (which repeated a property
//! test's draw before this existed, and still does), else a fresh random one per run.

use std::hash::{BuildHasher, Hasher};
use std::sync::OnceLock;

use proptest::test_runner::{Config, RngAlgorithm, RngSeed, TestRng};

/// This run's seed, printed (a test's output is shown when it fails).
pub fn seed() -> u64 {
    static SEED: OnceLock<u64> = OnceLock::new();
    let seed = *SEED.get_or_init(|| {
        from_env("BEAMFRIC_SEED")
            .or_else(|| from_env("PROPTEST_RNG_SEED"))
            .unwrap_or_else(fresh)
    });
    println!("random seed: {seed} (BEAMFRIC_SEED={seed} repeats this run)");
    seed
}

/// `config` drawing from this run's seed (proptest's `rng_seed`).
pub fn config(config: Config) -> Config {
    Config {
        rng_seed: RngSeed::Fixed(seed()),
        ..config
    }
}

/// A random stream of its own for each `stream` (say, one per thread), from this run's seed.
pub fn rng(stream: u64) -> TestRng {
    let mut bytes = [0u8; 32];
    bytes[..8].copy_from_slice(&seed().to_le_bytes());
    bytes[8..16].copy_from_slice(&stream.to_le_bytes());
    TestRng::from_seed(RngAlgorithm::ChaCha, &bytes)
}

/// The seed in the environment variable `name`, if set (a value that is not one fails).
fn from_env(name: &str) -> Option<u64> {
    let value = std::env::var(name).ok().filter(|v| !v.trim().is_empty())?;
    let seed = value
        .trim()
        .parse()
        .unwrap_or_else(|_| panic!("{name}={value:?} is not a seed (a number below 2^64)"));
    Some(seed)
}

/// A fresh random seed: the standard library's per-process random hash keys.
fn fresh() -> u64 {
    std::collections::hash_map::RandomState::new()
        .build_hasher()
        .finish()
}
