//! The explorer (issue 3): frames after key sequences as insta snapshots, and what keys do to
//! the state and the solution. The frames of every preset are in `render/`.
//!
//! Saving and quitting are in `saving`, typed values and panels in `editing`, a student's
//! explorer in a lecture in `students`.

use beamfric::plot::buffer_to_text;
use beamfric::scene::{PRESETS, Panel, SceneSource};
use beamfric::solve::{Method, Solution, SolveErrorKind};
use beamfric::tui::input::keys::{Key, parse_keys};
use beamfric::tui::jobs::sweeps::compute_now;
use beamfric::tui::layout::visible_panels;
use beamfric::tui::state::sweeps::SweepState;
use beamfric::tui::state::{App, Mode, Options};
use beamfric::tui::update::{Msg, update};
use beamfric::tui::{RenderOptions, draw_to_buffer, render, settled};

use crate::harness::scenes::{PLAIN, loaded_preset};
use crate::harness::screen::typed;

mod class_work;
mod editing;
mod saving;
mod students;

fn frame(name: &str, width: u16, height: u16, keys: &str) -> String {
    let options = RenderOptions {
        width,
        height,
        look: PLAIN,
        timings: false,
        palette: Default::default(),
        markers: Default::default(),
        allow_save: None,
        lesson: None,
    };
    let buffer = render(loaded_preset(name), &parse_keys(keys).unwrap(), options).unwrap();
    buffer_to_text(&buffer, false)
}

/// The explorer on a preset at 120 × 40, solved.
fn app(name: &str) -> App {
    app_with(name, Options::new(PLAIN))
}

fn app_with(name: &str, options: Options) -> App {
    let mut app = settled(App::new(loaded_preset(name), options).unwrap());
    update(&mut app, Msg::Resize(120, 40));
    app
}

/// The explorer on a preset, saving presets to `dir`.
fn app_saving_to(name: &str, dir: &std::path::Path) -> App {
    let options = Options {
        save_directory: Some(dir.to_path_buf()),
        ..Options::new(PLAIN)
    };
    app_with(name, options)
}

/// Takes finished sweeps; returns whether each was taken (it answered the current state).
fn take_sweeps(app: &mut App, results: Vec<beamfric::tui::jobs::sweeps::SweepResult>) -> Vec<bool> {
    results
        .into_iter()
        .map(|result| {
            let sweep = result.sweep;
            let was_pending = matches!(app.exploration.sweeps[sweep].state, SweepState::Pending(_));
            update(app, Msg::Swept(result));
            was_pending && !matches!(app.exploration.sweeps[sweep].state, SweepState::Pending(_))
        })
        .collect()
}

/// Computes every pending sweep and takes it.
fn finish_pending(app: &mut App) {
    let results = app
        .exploration
        .pending_sweeps()
        .iter()
        .map(compute_now)
        .collect();
    assert!(take_sweeps(app, results).into_iter().all(|taken| taken));
}

fn press(app: &mut App, keys: &str) {
    for key in parse_keys(keys).unwrap() {
        beamfric::tui::press(app, key);
    }
}

#[test]
fn frames_after_key_sequences() {
    let cases = [
        // Load: f0 up by two fine steps and a coarse one.
        ("load", "benchmark-1", "Right Right S-Right"),
        // Sliding threshold above the shear the point carries: it sticks.
        (
            "threshold",
            "benchmark-1",
            "Down Down Down Down Down Down S-Right S-Right S-Right",
        ),
        // Obstacle position: ten fine steps to the left.
        (
            "position",
            "benchmark-1",
            "Down Down Down Down Down Left Left Left Left Left Left Left Left Left Left",
        ),
        // ε: regularised method, ε two decades down (the preset opens on the ε row).
        ("epsilon", "lesson-epsilon", "S-Left S-Left"),
        ("typed-value", "benchmark-1", "Enter 3 e 4 Enter"),
        ("rejected-value", "benchmark-1", "Enter a b c Enter"),
        ("add-obstacle", "benchmark-1", "a"),
        ("delete-obstacle", "benchmark-3", "Down Down Down Down d"),
        ("method-refused", "eight-obstacles", "m m m"),
        ("moment-diagram", "benchmark-1", "b"),
        ("help", "benchmark-1", "?"),
        ("presets", "benchmark-1", "p Down"),
        // The picker's search: "mesh" keeps the presets about the mesh; PgDn to the last.
        ("preset-search", "benchmark-1", "p m e s h PgDn"),
        ("preset-search-nothing", "benchmark-1", "p z z z"),
        // z zooms the focused panel; Tab first focuses the next one.
        ("zoom", "benchmark-1", "z"),
        ("zoom-tab", "lesson-mesh", "Tab z"),
        ("tab", "benchmark-3", "Tab Tab"),
    ];
    for (label, name, keys) in cases {
        for (w, h) in [(120, 40), (80, 24)] {
            insta::assert_snapshot!(format!("keys-{label}-{w}x{h}"), frame(name, w, h, keys));
        }
    }
}

#[test]
fn a_too_small_terminal_says_so() {
    let text = frame("benchmark-1", 40, 10, "");
    assert!(text.contains("terminal too small: 40x10"), "{text}");
    assert!(text.contains("60x16"), "{text}");
    for (w, h) in [(1, 1), (2, 50), (200, 3), (59, 16), (60, 15)] {
        let text = frame("benchmark-1", w, h, "");
        assert_eq!(text.lines().count(), h as usize);
    }
}

#[test]
fn frames_are_deterministic() {
    let keys = "Down Right a Tab m";
    assert_eq!(
        frame("benchmark-3", 120, 40, keys),
        frame("benchmark-3", 120, 40, keys)
    );
}

/// The solution the explorer shows, which must be there and be one.
fn shown(app: &App) -> &Solution {
    app.exploration.solution().unwrap().as_ref().unwrap()
}

#[test]
fn raising_the_sliding_threshold_makes_the_obstacle_stick() {
    let mut app = app("benchmark-1");
    let before = shown(&app).obstacles[0];
    assert!(before.sliding && (before.force - 100.0).abs() < 1e-9);
    // Row 6 is the sliding threshold; three coarse steps: 100 N → 1e5 N, above the shear.
    press(
        &mut app,
        "Down Down Down Down Down Down S-Right S-Right S-Right",
    );
    assert_eq!(app.scene().obstacles[0].sliding, 1e5);
    let after = shown(&app).obstacles[0];
    assert!(!after.sliding && !after.swivel);
    assert!(after.force.abs() < 1e5 && after.force > 100.0);
    assert_eq!(after.u, 0.0);
}

#[test]
fn keys_change_the_state_and_the_solution() {
    let mut app = app("benchmark-1");
    let u0 = shown(&app).max_deflection();
    // Load: one fine step multiplies f (and, with the point still sliding, changes u).
    press(&mut app, "Right");
    assert!((app.scene().load.f0 / 5e4 - 10f64.powf(0.1)).abs() < 1e-12);
    assert!(shown(&app).max_deflection() > u0);
    // A typed exact value; a bad one changes nothing and says why.
    press(&mut app, "Enter 3 e 4 Enter");
    assert_eq!(app.scene().load.f0, 3e4);
    press(&mut app, "Enter a b c Enter");
    assert_eq!(app.scene().load.f0, 3e4);
    assert!(app.message.as_deref().unwrap().contains("not a number"));
    // A value the scene rules reject: a negative threshold.
    press(&mut app, "Down Down Down Down Down Down Enter - 5 Enter");
    assert_eq!(app.scene().obstacles[0].sliding, 1e2);
    assert!(app.message.as_deref().unwrap().contains("zero or positive"));
    // Reset (it asks first: the scene has unsaved changes).
    press(&mut app, "r y");
    assert_eq!(*app.scene(), loaded_preset("benchmark-1").scene);
    // Method and ε (row 8, counted from the top).
    press(&mut app, "m");
    assert_eq!(shown(&app).method, Method::Condensed);
    press(&mut app, "Up Up Up Up Up Up Up Up Up Up Up Up");
    press(&mut app, "Down Down Down Down Down Down Down Down S-Left");
    assert_eq!(
        app.exploration.selected_row(),
        beamfric::tui::state::params::Row::Epsilon
    );
    assert!((app.scene().solver.epsilon - 1e-7).abs() < 1e-20);
}

#[test]
fn obstacles_stay_ordered_inside_and_apart() {
    let mut app = app("benchmark-3");
    // Push obstacle 1 to the right far past obstacle 2, and obstacle 4 past the support.
    press(&mut app, "Down Down Down Down");
    for _ in 0..100 {
        beamfric::tui::press(&mut app, Key::ShiftRight);
    }
    let xs: Vec<f64> = app.scene().obstacles.iter().map(|o| o.x).collect();
    assert!(xs.windows(2).all(|w| w[0] < w[1]), "{xs:?}");
    assert!(xs[0] < xs[1] - 1e-4);
    // Add obstacles until the gaps are small; every one lands inside, ordered.
    for _ in 0..6 {
        press(&mut app, "a");
    }
    let xs: Vec<f64> = app.scene().obstacles.iter().map(|o| o.x).collect();
    assert_eq!(xs.len(), 10);
    assert!(xs.windows(2).all(|w| w[0] < w[1]) && xs[0] > 0.0 && xs[9] < 1.0);
    // Delete the selected one.
    press(&mut app, "d");
    assert_eq!(app.scene().obstacles.len(), 9);
    // d on a row that is not an obstacle explains itself.
    press(&mut app, "r y Up Up Up Up Up Up Up Up d");
    assert_eq!(app.scene().obstacles.len(), 4);
    assert!(
        app.message
            .as_deref()
            .unwrap()
            .contains("select a row of an obstacle")
    );
}

#[test]
fn a_refusal_cut_at_80x24_still_names_what_works_and_the_key_for_all_of_it() {
    // Stop 58's hostile pass: dual-inverse at n = 10⁵ ended at 80 columns with "…the limit is
    // N = 4000 unknowns; the…": neither the method that works nor `w` was on screen.
    let keys = "G Up Enter 1 0 0 0 0 0 Enter G Enter C-u d u a l - i n v e r s e Enter";
    let text = frame("benchmark-1", 80, 24, keys);
    assert!(
        text.contains("dual-inverse refused: the dense inverse"),
        "{text}"
    );
    assert!(
        text.contains("… the condensed method works here (w: in full)"),
        "{text}"
    );
    // Where it fits, it is whole.
    let text = frame("benchmark-1", 120, 30, keys);
    assert!(
        text.contains("unknowns; the condensed method works here (w: in full)"),
        "{text}"
    );
}

#[test]
fn a_method_that_does_not_apply_says_why() {
    let mut app = app("benchmark-3");
    while app.scene().solver.method != Method::ClosedForm {
        press(&mut app, "m");
    }
    let error = app.exploration.solution().unwrap().as_ref().unwrap_err();
    assert_eq!(error.kind, SolveErrorKind::NotApplicable);
    let text = buffer_to_text(&draw_to_buffer(&app, 120, 40), false);
    assert!(text.contains("closed-form not applicable"), "{text}");
}

#[test]
fn presets_load_from_the_picker_and_panels_follow_the_scene() {
    let mut app = app("benchmark-1");
    let index = PRESETS
        .iter()
        .position(|p| p.name == "lesson-epsilon")
        .unwrap();
    press(&mut app, "p");
    for _ in 0..index {
        press(&mut app, "Down");
    }
    press(&mut app, "Enter");
    assert_eq!(
        app.exploration.source,
        SceneSource::Preset("lesson-epsilon")
    );
    assert_eq!(app.exploration.panels(), vec![Panel::Figure5]);
    // It opens on the row it is about.
    assert_eq!(
        app.exploration.selected_row(),
        beamfric::tui::state::params::Row::Epsilon
    );
    // Panels the scene does not list are neither drawn nor computed.
    assert!(matches!(
        app.exploration.sweep_state(Panel::ErrorTime),
        SweepState::Idle
    ));
    assert!(matches!(
        app.exploration.sweep_state(Panel::EpsError),
        SweepState::Pending(_)
    ));
    let text = buffer_to_text(&draw_to_buffer(&app, 120, 40), false);
    assert!(!text.contains("Deflection") && !text.contains("Error vs n"));
    assert!(
        text.contains("computing the ε sweep"),
        "a pending panel says so"
    );
}

#[test]
fn outdated_study_results_are_never_taken() {
    let mut app = app("benchmark-1");
    let old = app.exploration.pending_sweeps();
    assert_eq!(old.len(), 2);
    let results: Vec<_> = old.iter().map(compute_now).collect();
    // A keystroke that changes the mesh makes both studies outdated.
    press(
        &mut app,
        "Down Down Down Down Down Down Down Down Down Right",
    );
    assert_eq!(app.scene().mesh.elements, 22);
    assert_eq!(take_sweeps(&mut app, results), vec![false, false]);
    assert!(matches!(
        app.exploration.sweep_state(Panel::EpsError),
        SweepState::Pending(_)
    ));
    // The current ones are taken.
    finish_pending(&mut app);
    assert!(matches!(
        app.exploration.sweep_state(Panel::EpsError),
        SweepState::Ready(_)
    ));
}

/// Issue 25: PgDn pages the help (and the warnings) instead of closing it; PgUp pages back.
#[test]
fn page_down_pages_the_help_and_page_up_comes_back() {
    let first = frame("benchmark-1", 80, 24, "?");
    assert!(first.contains("PgUp PgDn: lines 1–"), "{first}");
    let paged = frame("benchmark-1", 80, 24, "? PgDn");
    assert!(paged.contains("PgUp PgDn: lines 22–"), "{paged}");
    let back = frame("benchmark-1", 80, 24, "? PgDn PgUp");
    assert!(back.contains("PgUp PgDn: lines 1–"), "{back}");
    // Any other key still closes it.
    let closed = frame("benchmark-1", 80, 24, "? PgDn x");
    assert!(!closed.contains("PgUp PgDn: lines"), "{closed}");
}

/// Below the smallest size only a notice is drawn: keys that would change what nobody can see
/// do nothing there, and those that leave still work (a hostile pass stepped a lesson and
/// changed the scene unseen at 40×10).
#[test]
fn keys_change_nothing_unseen_below_the_smallest_size() {
    let mut app = app("benchmark-1");
    update(&mut app, Msg::Resize(40, 10));
    let before = app.scene().clone();
    keys(&mut app, "] a d m Enter 5 Enter");
    assert_eq!(app.scene(), &before);
    assert_eq!(app.mode, Mode::Normal);
    // Back at a usable size, the same keys act.
    update(&mut app, Msg::Resize(80, 24));
    keys(&mut app, "]");
    assert_ne!(app.scene(), &before);
    // Quitting works at any size (the changes are asked about, as always).
    update(&mut app, Msg::Resize(40, 10));
    keys(&mut app, "q y");
    assert_eq!(app.ending, Some(beamfric::tui::state::Ending::Quit));
}

/// Keys as the event loop applies them: follow mode's keys first.
fn keys(app: &mut App, keys: &str) {
    for key in parse_keys(keys).unwrap() {
        update(app, Msg::Key(key));
    }
}
