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
    std::os::unix::fs::symlink(outside.join("target.toml"), allowed.join("flink.toml")).unwrap();
    for (name, confirm) in [("lnk/x.toml", ""), ("flink.toml", ""), ("flink", "")] {
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

/// The numbers written inside the deflection chart of `frame` (the focused panel): every run
/// of digits between the chart's title row and its x axis, right of the y axis.
fn obstacle_numbers(frame: &str) -> Vec<u32> {
    // The focused chart's frame is heavy (┃); the y axis is ┤ or │, the x axis starts at └.
    let rows = frame
        .lines()
        .skip_while(|line| !line.contains("Deflection u(x)"))
        .skip(1)
        .filter_map(|line| line.split('┃').nth(1))
        .take_while(|chart| !chart.contains('└'));
    let mut numbers = Vec::new();
    for chart in rows {
        let Some((_, plot)) = chart.split_once(['┤', '│']) else {
            continue;
        };
        numbers.extend(
            plot.split(|c: char| !c.is_ascii_digit())
                .filter(|run| !run.is_empty())
                .map(|run| run.parse::<u32>().unwrap_or(u32::MAX)),
        );
    }
    numbers
}

#[test]
fn obstacle_numbers_stand_apart_and_only_where_they_name_their_column() {
    // Stop 58's hostile pass: with thousands of obstacles the chart's numbers ran together
    // ("32" beside the curve, among the first 60 obstacles' column).
    let dir = tempfile::tempdir().unwrap();
    let frame_of = |obstacles: usize| {
        let text = crate::harness::scenes::crowded_scene_text_of(obstacles, 1000)
            .replace("method = \"dual\"", "method = \"condensed\"");
        let path = dir.path().join(format!("k{obstacles}.toml"));
        std::fs::write(&path, text).unwrap();
        let path = path.to_str().unwrap();
        let out = beamfric(&["render", "--scene", path, "--size", "120x40"]);
        assert!(out.status.success(), "{out:?}");
        String::from_utf8(out.stdout).unwrap()
    };
    // Twelve obstacles, columns apart: numbered, each once, none merged with another.
    let frame = frame_of(12);
    let mut numbers = obstacle_numbers(&frame);
    numbers.sort_unstable();
    assert!(numbers.len() >= 8, "{numbers:?}\n{frame}");
    assert!(
        numbers.windows(2).all(|w| w[0] < w[1]),
        "{numbers:?}\n{frame}"
    );
    assert!(
        numbers.iter().all(|n| (1..=12).contains(n)),
        "{numbers:?}\n{frame}"
    );
    // 300 obstacles in a chart about 68 columns wide: four or five to a column, none numbered.
    let frame = frame_of(300);
    assert_eq!(obstacle_numbers(&frame), Vec::<u32>::new(), "{frame}");
}

/// Stop 59's lecture pass: a message longer than the width was cut at 80 columns (a figure's
/// refusal lost its reason). Where the warnings' row holds only "no warnings", a long message
/// takes it too and is read whole; real warnings keep their row, and the message is cut at a
/// word.
#[test]
fn a_long_message_takes_the_quiet_warnings_row_at_80_columns() {
    let frame = |scene: &str| {
        let run = beamfric(&["render", "--scene", scene, "--size", "80x24", "--keys", "e"]);
        assert!(run.status.success());
        String::from_utf8_lossy(&run.stdout).into_owned()
    };
    let quiet = frame("benchmark-1");
    let rows: Vec<&str> = quiet.lines().map(str::trim_end).collect();
    let at = rows
        .iter()
        .position(|row| row.starts_with("figure not written:"))
        .unwrap_or_else(|| panic!("{quiet}"));
    assert_eq!(
        format!("{} {}", rows[at], rows[at + 1]),
        "figure not written: benchmark-1-deflection.svg (a render writes no files without \
         --allow-save DIR)"
    );
    assert!(!quiet.contains("no warnings"), "{quiet}");
    let warned = frame("lesson-mesh");
    assert!(warned.contains("⚠ 4 warnings (w: all)"), "{warned}");
    assert!(
        warned
            .contains("figure not written: lesson-mesh-deflection.svg (a render writes no files…"),
        "{warned}"
    );
}
