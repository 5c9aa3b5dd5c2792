//! The hard scenes of issue 10 as check cases: soft and stiff segments, obstacles 1e-9·l from
//! each other, the supports and segment ends, huge and zero thresholds on tiny meshes, loads of
//! 1e-300 and 1e300, forty stuck obstacles. The scene files live in `tests/scenes/hard` (the
//! same files the reference tests use), compiled in so that `beamfric check` runs them.

/// (name, TOML text) of every hard case.
pub const HARD_CASES: &[(&str, &str)] = &[
    (
        "benchmark-1-two-elements",
        include_str!("../../tests/scenes/hard/benchmark-1-two-elements.toml"),
    ),
    (
        "both-supports-2e-9",
        include_str!("../../tests/scenes/hard/both-supports-2e-9.toml"),
    ),
    (
        "contrast-3e10-six-obstacles",
        include_str!("../../tests/scenes/hard/contrast-3e10-six-obstacles.toml"),
    ),
    (
        "forty-stuck",
        include_str!("../../tests/scenes/hard/forty-stuck.toml"),
    ),
    (
        "huge-thresholds-two-elements",
        include_str!("../../tests/scenes/hard/huge-thresholds-two-elements.toml"),
    ),
    (
        "load-1e-300",
        include_str!("../../tests/scenes/hard/load-1e-300.toml"),
    ),
    (
        "load-1e300",
        include_str!("../../tests/scenes/hard/load-1e300.toml"),
    ),
    (
        "near-left-support",
        include_str!("../../tests/scenes/hard/near-left-support.toml"),
    ),
    (
        "near-right-support",
        include_str!("../../tests/scenes/hard/near-right-support.toml"),
    ),
    (
        "pair-1.001e-9-apart",
        include_str!("../../tests/scenes/hard/pair-1.001e-9-apart.toml"),
    ),
    (
        "pair-1e-6-apart",
        include_str!("../../tests/scenes/hard/pair-1e-6-apart.toml"),
    ),
    (
        "pair-1e-8-apart",
        include_str!("../../tests/scenes/hard/pair-1e-8-apart.toml"),
    ),
    (
        "past-segment-end",
        include_str!("../../tests/scenes/hard/past-segment-end.toml"),
    ),
    (
        "sign-change-symmetric",
        include_str!("../../tests/scenes/hard/sign-change-symmetric.toml"),
    ),
    (
        "soft-segment",
        include_str!("../../tests/scenes/hard/soft-segment.toml"),
    ),
    (
        "threshold-1e20-one",
        include_str!("../../tests/scenes/hard/threshold-1e20-one.toml"),
    ),
];
