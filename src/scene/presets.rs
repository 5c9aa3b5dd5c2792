//! The scenes shipped in `presets/`, compiled into the program so a preset name works from
//! any directory.

/// A scene shipped with the program.
#[derive(Debug, Clone, Copy)]
pub struct Preset {
    /// The name used on the command line, e.g. `benchmark-1`.
    pub name: &'static str,
    /// The TOML text of `presets/<name>.toml`.
    pub text: &'static str,
}

macro_rules! presets {
    ($($name:literal),* $(,)?) => {
        /// Every preset, in the order the explorer's picker lists them.
        pub const PRESETS: &[Preset] = &[
            $(Preset { name: $name, text: include_str!(concat!("../../presets/", $name, ".toml")) },)*
        ];
    };
}

presets![
    "benchmark-1",
    "benchmark-2",
    "benchmark-3",
    "lesson-epsilon",
    "lesson-mesh",
    "fine-mesh",
    "epsilon-1e-16",
    "zero-thresholds",
    "huge-thresholds",
    "modulus-contrast",
    "obstacle-near-support",
    "close-obstacles",
    "eight-obstacles",
    "tiny-beam",
    "huge-beam",
    "zero-load",
];

/// The preset called `name` (with or without the `.toml` extension).
pub fn preset(name: &str) -> Option<&'static Preset> {
    let name = name.strip_suffix(".toml").unwrap_or(name);
    PRESETS.iter().find(|p| p.name == name)
}
