//! Headless rendering (issues 3 and 4): the frame of every preset at 120×40 and 80×24, in
//! Unicode and in ASCII, as insta snapshots; ASCII frames contain only ASCII; frames are
//! byte-identical from run to run and between the library and `beamfric render`.
//!
//! The `render` command's own behaviour (arguments, saves, palettes) is in `command`.

use std::process::Command;

use beamfric::plot::buffer_to_text;
use beamfric::scene::PRESETS;
use beamfric::tui::{draw_to_buffer, prepare};

use crate::harness::process::beamfric;
use crate::harness::scenes::{loaded_preset, plain_render};
use crate::harness::screen::typed;

mod command;

const SIZES: [(u16, u16); 2] = [(120, 40), (80, 24)];

/// The four frames of a preset (two sizes, two looks), from one prepared state.
fn frames(name: &str) -> Vec<(String, String)> {
    let loaded = loaded_preset(name);
    let mut app = prepare(loaded, &[], plain_render(120, 40, false)).unwrap();
    let mut out = Vec::new();
    for ascii in [false, true] {
        app.look.ascii = ascii;
        for (w, h) in SIZES {
            let text = buffer_to_text(&draw_to_buffer(&app, w, h), false);
            let label = format!("{name}-{w}x{h}{}", if ascii { "-ascii" } else { "" });
            out.push((label, text));
        }
    }
    out
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
    let source = include_str!("mod.rs");
    for p in PRESETS {
        assert!(source.contains(&format!("\"{}\",", p.name)), "{}", p.name);
    }
}

// Issue 13: charts that tell the truth, at the sizes a lecturer uses, in Unicode and ASCII.

const LESSON_SIZES: [(u16, u16); 3] = [(80, 24), (100, 30), (120, 40)];

/// The frame of `scene` after `keys` at every lesson size, Unicode and ASCII, each checked for
/// its size and (ASCII) for containing only ASCII; `adjust` may change the prepared state.
fn lesson_frames(
    scene: &str,
    keys_at: impl Fn(u16) -> String,
    adjust: impl Fn(&mut beamfric::tui::state::App),
) -> Vec<(String, u16, bool, String)> {
    let mut out = Vec::new();
    for (w, h) in LESSON_SIZES {
        let loaded = loaded_preset(scene);
        let keys = beamfric::tui::input::keys::parse_keys(&keys_at(w)).unwrap();
        let mut app = prepare(loaded, &keys, plain_render(w, h, false)).unwrap();
        adjust(&mut app);
        for ascii in [false, true] {
            app.look.ascii = ascii;
            let text = buffer_to_text(&draw_to_buffer(&app, w, h), false);
            assert_eq!(text.lines().count(), h as usize);
            assert!(text.lines().all(|l| l.chars().count() == w as usize));
            if ascii {
                assert!(text.is_ascii(), "{scene} {w}x{h}: non-ASCII output");
            }
            let label = format!("{w}x{h}{}", if ascii { "-ascii" } else { "" });
            out.push((label, w, ascii, text));
        }
    }
    out
}

/// The frame after `keys` on a preset, at each size and look.
fn frames_after(name: &str, keys: &str, sizes: &[(u16, u16)]) -> Vec<(String, String, bool)> {
    let loaded = loaded_preset(name);
    let keys = beamfric::tui::input::keys::parse_keys(keys).unwrap();
    let mut app = prepare(loaded, &keys, plain_render(120, 40, false)).unwrap();
    let mut out = Vec::new();
    for ascii in [false, true] {
        app.look.ascii = ascii;
        for &(w, h) in sizes {
            let text = buffer_to_text(&draw_to_buffer(&app, w, h), false);
            let label = format!("{w}x{h}{}", if ascii { "-ascii" } else { "" });
            out.push((label, text, ascii));
        }
    }
    out
}

/// Every method's marker appears in the chart rows (not only in the key): the key line is the
/// only place a method's name is written, so a marker seen twice is drawn at least once.
fn assert_every_series_drawn(text: &str, ascii: bool, label: &str) {
    let markers: [(&str, char, char); 6] = [
        ("dual", '●', 'o'),
        ("condensed", '■', '#'),
        ("flexibility", '▲', '^'),
        ("regularized", '◆', '%'),
        ("regularized-newton", '✚', '+'),
        ("dual-inverse", '✖', 'x'),
    ];
    for (name, unicode, plain) in markers {
        let marker = if ascii { plain } else { unicode };
        let in_key = text.contains(&format!("{marker} {name}"))
            || text
                .lines()
                .any(|l| l.contains(&format!("{marker} ")) && l.contains("dual"));
        assert!(in_key, "{label}: {name} missing from the key\n{text}");
        if !ascii || marker != 'x' {
            assert!(
                text.matches(marker).count() >= 2,
                "{label}: no {name} marker drawn\n{text}"
            );
        }
    }
}

/// Error against n on lesson-mesh: all series drawn, none hidden, the current n marked with
/// the selected method's error printed.
#[test]
fn lesson_mesh_error_against_n() {
    // One panel at a time below 100x30: Tab brings the error chart.
    let keys = |w: u16| {
        if w < 100 {
            "Tab".to_string()
        } else {
            String::new()
        }
    };
    for (label, _, ascii, text) in lesson_frames("lesson-mesh", keys, |_| {}) {
        let current = if ascii {
            ": n = 2000:"
        } else {
            "┆ n = 2000:"
        };
        assert!(
            text.contains(current),
            "{label}: current n not marked\n{text}"
        );
        let error = if ascii { "o 8.1e-6" } else { "● 8.1e-6" };
        assert!(
            text.contains(error),
            "{label}: dual's error at n = 2000\n{text}"
        );
        assert_every_series_drawn(&text, ascii, &label);
        insta::assert_snapshot!(format!("lesson-mesh-error-vs-n-{label}"), text);
    }
}

/// Synthetic run times (a fixed cost per element, per method; n³ for the dense inverse), so
/// that the error-vs-run-time frame is the same on every machine and every run.
fn synthetic_time(point: &beamfric::study::MeshPoint) -> std::time::Duration {
    use beamfric::solve::Method;
    let n = point.elements as f64;
    let seconds = match point.method {
        Method::Dual => 8e-8 * n,
        Method::Condensed => 2e-7 * n,
        Method::Flexibility => 3e-8 * n,
        Method::Regularized => 1e-7 * n + 2e-6,
        Method::RegularizedNewton => 1.2e-7 * n + 1e-6,
        Method::DualInverse => 4e-10 * n * n * n,
        Method::ClosedForm => 1e-8 * n,
    };
    std::time::Duration::from_secs_f64(seconds + 1e-6)
}

/// Error against run time on lesson-mesh (run times replaced by [`synthetic_time`]): all
/// series drawn, the current n's points marked, its error and time printed.
#[test]
fn lesson_mesh_error_against_run_time() {
    use beamfric::tui::jobs::sweeps::sweep_of;
    use beamfric::tui::state::sweeps::SweepState;
    let keys = |w: u16| {
        if w < 100 {
            "t Tab".to_string()
        } else {
            "t".to_string()
        }
    };
    let deterministic = |app: &mut beamfric::tui::state::App| {
        let slot = sweep_of(beamfric::scene::Panel::ErrorTime).unwrap();
        let SweepState::Ready(data) = &app.exploration.sweeps[slot].state else {
            panic!("the mesh sweep ran");
        };
        let mut points = data
            .downcast_ref::<Vec<beamfric::study::MeshPoint>>()
            .unwrap()
            .clone();
        for p in &mut points {
            p.run_time = synthetic_time(p);
        }
        app.exploration.sweeps[slot].state = SweepState::Ready(std::sync::Arc::new(points));
        if let Some(Ok(solution)) = app.exploration.shown.as_mut().map(|s| &mut s.solution) {
            solution.timing = Default::default();
        }
    };
    for (label, _, ascii, text) in lesson_frames("lesson-mesh", keys, deterministic) {
        assert!(text.contains("Error vs run time"), "{label}\n{text}");
        // dual at n = 2000: 8e-8·2000 + 1e-6 s = 161 µs.
        assert!(
            text.contains("in 161.0"),
            "{label}: time at n not printed\n{text}"
        );
        assert_every_series_drawn(&text, ascii, &label);
        // The current run's rule is drawn in the plot, not only named in the key (issue 25):
        // a plain-text frame shows it on rows of the plot area too.
        let (rule, tick) = if ascii { (':', '+') } else { ('┆', '┤') };
        // Rows of the plot with a y tick: the rule crosses at least two of them.
        let plot_rows = text
            .lines()
            .filter(|l| l.contains(tick) && l.contains(rule) && !l.contains("n = 2000:"))
            .count();
        assert!(
            plot_rows >= 2,
            "{label}: no rule at the current run\n{text}"
        );
        insta::assert_snapshot!(format!("lesson-mesh-error-vs-time-{label}"), text);
    }
}

/// The ε charts on Benchmark 1: the current ε marked with the error, cond₂(Â) and the scaled
/// condition number printed (the values of the sweep at exactly that ε, checked against an
/// independent run of the sweep), and cond₂'s plateau drawn on top of the scaled markers.
#[test]
fn benchmark_1_epsilon_charts() {
    let problem = loaded_preset("benchmark-1");
    let sweep = beamfric::study::epsilon_sweep(
        &problem.problem,
        20,
        beamfric::solve::Method::Regularized,
        &[1e-6, 1.0],
        &beamfric::solve::Cancellation::NEVER,
        &beamfric::study::silent,
    )
    .unwrap()
    .unwrap();
    let at_1e6 = &sweep[0];
    let error = beamfric::format::sci(at_1e6.error.unwrap().max_rel.unwrap(), 2);
    let cond = beamfric::format::sci(at_1e6.cond_max.unwrap().value, 2);
    let scaled = beamfric::format::sci(at_1e6.cond_scaled_max.unwrap().value, 2);
    let plateau = sweep[1].cond_max.unwrap().value;
    assert!((plateau / 2.0956e5 - 1.0).abs() < 1e-3, "{plateau}");
    // 80x24 shows one panel: Tab to each ε chart.
    for (panel, tabs) in [("error", "Tab"), ("cond", "Tab Tab")] {
        let keys = |w: u16| {
            if w < 100 {
                tabs.to_string()
            } else {
                String::new()
            }
        };
        for (label, w, ascii, text) in lesson_frames("benchmark-1", keys, |_| {}) {
            if w >= 100 && panel == "cond" {
                continue; // the same frame as for "error"
            }
            let eps = if ascii {
                "eps = 1.0e-6:"
            } else {
                "ε = 1.0e-6:"
            };
            assert!(text.contains(eps), "{label}\n{text}");
            if panel == "error" || w >= 100 {
                assert!(text.contains(&format!("error {error}")), "{label}\n{text}");
            }
            if panel == "cond" || w >= 100 {
                let name = if ascii { "cond2(A^)" } else { "cond₂(Â)" };
                assert!(text.contains(&format!("{name} {cond}")), "{label}\n{text}");
                assert!(
                    text.contains(&format!("scaled {scaled}")),
                    "{label}\n{text}"
                );
            }
            let name = if w >= 100 { "all" } else { panel };
            insta::assert_snapshot!(format!("benchmark-1-eps-{name}-{label}"), text);
        }
    }
}

/// The deflection of `regularized` at ε = 1e-2 on Benchmark 1 with the reference (condensed)
/// under it, and with `c` the difference u − u_ref on its own scale.
#[test]
fn regularized_deflection_with_its_reference() {
    let keys = format!(
        "m m m {} Enter {} 1 e - 2 Enter",
        "Down ".repeat(8),
        "Backspace ".repeat(12)
    );
    for difference in [false, true] {
        let keys_at = |_: u16| {
            if difference {
                format!("{keys} c")
            } else {
                keys.clone()
            }
        };
        for (label, _, ascii, text) in lesson_frames("benchmark-1", keys_at, |app| {
            assert_eq!(app.scene().solver.epsilon, 1e-2);
            let shown = app.exploration.shown.as_ref().unwrap();
            let reference = shown.reference.as_ref().expect("the reference is solved");
            assert_eq!(reference.method, beamfric::solve::Method::Condensed);
        }) {
            if difference {
                let title = if ascii {
                    "u - u_ref [m]"
                } else {
                    "u − u_ref [m]"
                };
                assert!(text.contains(title), "{label}\n{text}");
                assert!(
                    text.contains("regularized - condensed")
                        || text.contains("regularized − condensed"),
                    "{label}\n{text}"
                );
            } else {
                assert!(text.contains("condensed = reference"), "{label}\n{text}");
                // The reference curve's dots on several rows of the panel (the title line and
                // the status lines, which use · as a separator, left out).
                // In ASCII the dots are `.`, told from decimal points by having no digit beside.
                let reference = if ascii { '.' } else { '·' };
                let rows = text.lines().count();
                let is_dot = |line: &[char], i: usize| {
                    let digit = |j: Option<usize>| {
                        j.and_then(|j| line.get(j))
                            .is_some_and(|c| c.is_ascii_digit())
                    };
                    line[i] == reference && !digit(i.checked_sub(1)) && !digit(Some(i + 1))
                };
                let with_dots = text
                    .lines()
                    .skip(1)
                    .take(rows - 5)
                    .map(|l| l.chars().collect::<Vec<char>>())
                    .filter(|l| (0..l.len()).any(|i| is_dot(l, i)))
                    .count();
                assert!(with_dots >= 4, "{label}: no reference curve\n{text}");
            }
            let name = if difference {
                "difference"
            } else {
                "reference"
            };
            insta::assert_snapshot!(format!("regularized-1e-2-{name}-{label}"), text);
        }
    }
}

/// The warnings of a preset's solution after `keys`, from the solver (not from the screen).
fn warning_messages(name: &str, keys: &str) -> Vec<String> {
    let loaded = loaded_preset(name);
    let keys = beamfric::tui::input::keys::parse_keys(keys).unwrap();
    let app = prepare(loaded, &keys, plain_render(120, 40, false)).unwrap();
    match app.exploration.solution() {
        Some(Ok(solution)) => solution
            .warnings
            .iter()
            .map(|w| w.message.clone())
            .collect(),
        other => panic!("{name}: no solution: {other:?}"),
    }
}

const ALL_SIZES: [(u16, u16); 3] = [(80, 24), (100, 30), (120, 40)];
/// From the first row to the elements row (the second to last), then the warnings view.
const LESSON_MESH_200K: &str = "Down Down Down Down Down Down Down Down Down Down Down Down \
                                Down Down Down Down Down Down Down Up Enter 2 0 0 0 0 0 Enter";

/// Issue 13: the warnings view shows every word of every warning at every size, wrapped,
/// never cut, the real cause first.
#[test]
fn the_warnings_view_shows_every_word() {
    for (name, keys, snapshot) in [
        ("fine-mesh", "", "fine-mesh"),
        ("lesson-mesh", LESSON_MESH_200K, "lesson-mesh-200000"),
    ] {
        let messages = warning_messages(name, keys);
        assert!(!messages.is_empty(), "{name}: the scene has warnings");
        let opened = format!("{keys} w");
        // The view scrolled line by line: every message must be readable whole on some line
        // offset (at 80x24 five warnings do not fit on one screen).
        let scrolled: Vec<Vec<(String, String, bool)>> = (1..=16)
            .map(|lines| {
                frames_after(
                    name,
                    &format!("{opened}{}", " Down".repeat(lines)),
                    &ALL_SIZES,
                )
            })
            .collect();
        for (index, (label, text, ascii)) in frames_after(name, &opened, &ALL_SIZES)
            .into_iter()
            .enumerate()
        {
            if !ascii {
                // Every word of every message, in order, inside the frame's box.
                let words_of = |text: &str| -> Vec<String> {
                    text.lines()
                        .flat_map(|l| {
                            l.trim_matches(|c| c == '┃' || c == ' ')
                                .split_whitespace()
                                .map(str::to_string)
                                .collect::<Vec<_>>()
                        })
                        .collect()
                };
                let pages: Vec<Vec<String>> = std::iter::once(words_of(&text))
                    .chain(scrolled.iter().map(|frames| words_of(&frames[index].1)))
                    .collect();
                for message in &messages {
                    let wanted: Vec<&str> = message.split_whitespace().collect();
                    let found = pages.iter().any(|words| {
                        words
                            .windows(wanted.len())
                            .any(|w| w.iter().map(String::as_str).eq(wanted.iter().copied()))
                    });
                    assert!(
                        found,
                        "{name} {label}: not all of {message:?} visible:\n{text}"
                    );
                }
            } else {
                assert!(text.is_ascii(), "{name} {label}");
            }
            insta::assert_snapshot!(format!("warnings-{snapshot}-{label}"), text);
        }
    }
}
