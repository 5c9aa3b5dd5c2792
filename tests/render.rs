//! Headless rendering (issues 3 and 4): the frame of every preset at 120×40 and 80×24, in
//! Unicode and in ASCII, as insta snapshots; ASCII frames contain only ASCII; frames are
//! byte-identical from run to run and between the library and `beamfric render`.

use std::process::Command;

use beamfric::plot::{Look, buffer_to_text};
use beamfric::scene::{LoadedScene, PRESETS, preset};
use beamfric::tui::{RenderOptions, draw_to_buffer, prepare};

const SIZES: [(u16, u16); 2] = [(120, 40), (80, 24)];

fn options(width: u16, height: u16, ascii: bool) -> RenderOptions {
    RenderOptions {
        width,
        height,
        look: Look {
            ascii,
            color: false,
        },
        palette: Default::default(),
        timings: false,
        allow_save: None,
    }
}

/// The four frames of a preset (two sizes, two looks), from one prepared state.
fn frames(name: &str) -> Vec<(String, String)> {
    let loaded = LoadedScene::preset(preset(name).unwrap()).unwrap();
    let mut app = prepare(loaded, &[], options(120, 40, false)).unwrap();
    let mut out = Vec::new();
    for ascii in [false, true] {
        app.look.ascii = ascii;
        for (w, h) in SIZES {
            let text = buffer_to_text(&draw_to_buffer(&app, w, h).unwrap(), false);
            let label = format!("{name}-{w}x{h}{}", if ascii { "-ascii" } else { "" });
            out.push((label, text));
        }
    }
    out
}

fn beamfric(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_beamfric"))
        .args(args)
        .output()
        .expect("the binary runs")
}

macro_rules! preset_snapshots {
    ($($test:ident: $name:literal,)*) => {$(
        #[test]
        fn $test() {
            for (label, text) in frames($name) {
                let (w, h) = if label.contains("120x40") { (120, 40) } else { (80, 24) };
                assert_eq!(text.lines().count(), h, "{label}");
                assert!(text.lines().all(|l| l.chars().count() == w), "{label}");
                if label.ends_with("-ascii") {
                    assert!(text.is_ascii(), "{label}: non-ASCII output");
                }
                insta::assert_snapshot!(label, text);
            }
        }
    )*};
}

preset_snapshots! {
    snapshot_benchmark_1: "benchmark-1",
    snapshot_benchmark_2: "benchmark-2",
    snapshot_benchmark_3: "benchmark-3",
    snapshot_lesson_epsilon: "lesson-epsilon",
    snapshot_lesson_mesh: "lesson-mesh",
    snapshot_fine_mesh: "fine-mesh",
    snapshot_epsilon_1e_16: "epsilon-1e-16",
    snapshot_zero_thresholds: "zero-thresholds",
    snapshot_huge_thresholds: "huge-thresholds",
    snapshot_modulus_contrast: "modulus-contrast",
    snapshot_obstacle_near_support: "obstacle-near-support",
    snapshot_close_obstacles: "close-obstacles",
    snapshot_eight_obstacles: "eight-obstacles",
    snapshot_tiny_beam: "tiny-beam",
    snapshot_huge_beam: "huge-beam",
    snapshot_zero_load: "zero-load",
}

#[test]
fn every_preset_has_a_snapshot_test() {
    let source = include_str!("render.rs");
    for p in PRESETS {
        assert!(source.contains(&format!("\"{}\",", p.name)), "{}", p.name);
    }
}

#[test]
fn the_command_prints_the_library_frame_byte_for_byte_and_the_same_every_time() {
    let keys = "Down Right a m Tab";
    let first = beamfric(&[
        "render",
        "--scene",
        "benchmark-3",
        "--size",
        "100x30",
        "--keys",
        keys,
    ]);
    assert!(first.status.success());
    let second = beamfric(&[
        "render",
        "--scene",
        "benchmark-3",
        "--size",
        "100x30",
        "--keys",
        keys,
    ]);
    assert_eq!(first.stdout, second.stdout, "two renders differ");
    let loaded = LoadedScene::preset(preset("benchmark-3").unwrap()).unwrap();
    let keys = beamfric::tui::keymap::parse_keys(keys);
    let buffer = beamfric::tui::render(loaded, &keys, options(100, 30, false)).unwrap();
    assert_eq!(
        String::from_utf8(first.stdout).unwrap(),
        buffer_to_text(&buffer, false)
    );
}

#[test]
fn ascii_output_is_ascii_and_color_output_has_escapes() {
    let out = beamfric(&[
        "render",
        "--scene",
        "benchmark-1",
        "--size",
        "90x28",
        "--ascii",
        "--keys",
        "?",
    ]);
    assert!(out.status.success());
    assert!(out.stdout.is_ascii());
    assert_eq!(String::from_utf8_lossy(&out.stdout).lines().count(), 28);
    let colored = beamfric(&[
        "render",
        "--scene",
        "benchmark-1",
        "--size",
        "90x28",
        "--color",
    ]);
    let text = String::from_utf8(colored.stdout).unwrap();
    assert!(text.contains("\x1b["), "no ANSI escapes with --color");
    let plain = beamfric(&["render", "--scene", "benchmark-1", "--size", "90x28"]);
    assert!(!String::from_utf8(plain.stdout).unwrap().contains('\x1b'));
}

#[test]
fn bad_render_arguments_are_one_line() {
    for (args, expected) in [
        (vec!["render", "--size", "wide"], "WIDTHxHEIGHT"),
        (vec!["render", "--size", "0x10"], "from 1 to 1000"),
        (vec!["render", "--scene", "nope"], "not a preset name"),
    ] {
        let out = beamfric(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(expected), "{err}");
    }
}

/// Issue 12, item 7: a headless render never touches the file system unless `--allow-save DIR`
/// says where it may write, and then only inside DIR.
#[test]
fn render_simulates_saves_unless_a_directory_is_allowed() {
    let cwd = tempfile::tempdir().unwrap();
    let victim = cwd.path().join("victim.txt");
    std::fs::write(&victim, "precious").unwrap();
    let render = |keys: &str, extra: &[&str]| {
        let output = Command::new(env!("CARGO_BIN_EXE_beamfric"))
            .current_dir(cwd.path())
            .args(["render", "--size", "100x30", "--keys", keys])
            .args(extra)
            .output()
            .unwrap();
        assert!(output.status.success(), "{output:?}");
        String::from_utf8(output.stdout).unwrap()
    };
    // The default name, and an existing file confirmed with y: nothing written.
    let frame = render("Right s Enter", &[]);
    assert!(
        frame.contains("not saved: a headless render writes no files"),
        "{frame}"
    );
    let erase = "Backspace ".repeat(20);
    render(&format!("Right s {erase} victim.txt Enter y"), &[]);
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    let names: Vec<_> = std::fs::read_dir(cwd.path()).unwrap().collect();
    assert_eq!(names.len(), 1, "render wrote into the directory");

    // With --allow-save DIR: the save lands in DIR, and nowhere else.
    let allowed = cwd.path().join("allowed");
    std::fs::create_dir(&allowed).unwrap();
    let dir = allowed.to_str().unwrap();
    let frame = render("Right s Enter", &["--allow-save", dir]);
    assert!(frame.contains("saved to"), "{frame}");
    assert!(allowed.join("benchmark-1.toml").exists());
    let frame = render(
        &format!("Right s {} ../escape.toml Enter", "Backspace ".repeat(300)),
        &["--allow-save", dir],
    );
    assert!(frame.contains("is outside"), "{frame}");
    assert!(!cwd.path().join("escape.toml").exists());
    // Nor through a symbolic link inside DIR (found by a hostile test pass).
    let outside = cwd.path().join("outside");
    std::fs::create_dir(&outside).unwrap();
    std::os::unix::fs::symlink(&outside, allowed.join("lnk")).unwrap();
    std::fs::write(outside.join("target.toml"), "keep").unwrap();
    std::os::unix::fs::symlink(outside.join("target.toml"), allowed.join("flink")).unwrap();
    for (name, confirm) in [("lnk/x.toml", ""), ("flink", "")] {
        let keys = format!("Right s {} {name} Enter{confirm}", "Backspace ".repeat(300));
        let frame = render(&keys, &["--allow-save", dir]);
        assert!(frame.contains("is outside"), "{name}: {frame}");
    }
    assert!(!outside.join("x.toml").exists());
    assert_eq!(
        std::fs::read_to_string(outside.join("target.toml")).unwrap(),
        "keep"
    );
    // The overwrite question is about the file inside DIR.
    let frame = render(
        &format!(
            "Right s {} benchmark-1.toml Enter",
            "Backspace ".repeat(300)
        ),
        &["--allow-save", dir],
    );
    assert!(frame.contains("exists: overwrite it?"), "{frame}");
}
