//! `beamfric render` as a command: the library's frame byte for byte and the same every time,
//! ASCII and colour output, one-line errors for bad arguments, saves simulated unless a
//! directory is allowed, and palettes that carry no information in hard-to-see colours.

use super::*;

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
    let loaded = loaded_preset("benchmark-3");
    let keys = beamfric::tui::input::keys::parse_keys(keys).unwrap();
    let buffer = beamfric::tui::render(loaded, &keys, plain_render(100, 30, false)).unwrap();
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
    render(
        &format!("Right s {erase} {} Enter y", typed("victim.txt")),
        &[],
    );
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
        &format!(
            "Right s {} {} Enter",
            "Backspace ".repeat(300),
            typed("../escape.toml")
        ),
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
        let keys = format!(
            "Right s {} {} Enter{confirm}",
            "Backspace ".repeat(300),
            typed(name)
        );
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
            "Right s {} {} Enter",
            "Backspace ".repeat(300),
            typed("benchmark-1.toml")
        ),
        &["--allow-save", dir],
    );
    assert!(frame.contains("exists: overwrite it?"), "{frame}");
}

/// Issue 13: in every palette, dark grey draws only decoration (axis lines, the zero line, the
/// clamped ends), never a letter or a digit; the light palette writes no text in yellow; the
/// high-contrast palette sets the background of every cell.
#[test]
fn palettes_carry_no_information_in_dark_grey_or_light_yellow() {
    use beamfric::plot::Palette;
    use ratatui::style::Color;
    let keys =
        beamfric::tui::input::keys::parse_keys("m m m Down Down Down Down Down Down Down Down")
            .unwrap();
    for scene in ["benchmark-1", "lesson-mesh"] {
        for palette in Palette::ALL {
            for (w, h) in LESSON_SIZES {
                let loaded = loaded_preset(scene);
                let mut options = plain_render(w, h, false);
                options.look.color = true;
                options.palette = palette;
                let app = prepare(loaded, &keys, options).unwrap();
                let buffer = draw_to_buffer(&app, w, h);
                for cell in buffer.content.iter() {
                    let text = cell.symbol().chars().any(|c| c.is_alphanumeric());
                    let case = format!("{scene} {w}x{h} {}: {:?}", palette.name(), cell);
                    if cell.fg == Color::DarkGray {
                        assert!(!text, "dark grey text: {case}");
                    }
                    if palette == Palette::Light {
                        assert!(
                            !(text && matches!(cell.fg, Color::Yellow | Color::LightYellow)),
                            "yellow text on the light theme: {case}"
                        );
                    }
                    if palette == Palette::HighContrast {
                        // Black, or white under the selected row: never the terminal's own.
                        assert!(matches!(cell.bg, Color::Black | Color::White), "{case}");
                    }
                }
            }
        }
    }
}
