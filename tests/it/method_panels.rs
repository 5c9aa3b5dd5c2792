//! The panels that show how a method works (issue 24): their frames at 80×24 and 120×40 in
//! Unicode and ASCII on Benchmark 1, Benchmark 3 and a stiff preset (insta snapshots); the
//! iterations recorded only while their panel is on screen; Figure 5 in one panel with both
//! values; ε steps landing on exact decades; the dual picture's words against the Results
//! state.

use beamfric::plot::buffer_to_text;
use beamfric::scene::Panel;
use beamfric::tui::input::keys::parse_keys;
use beamfric::tui::jobs::sweeps::compute_now;
use beamfric::tui::layout::visible_panels;
use beamfric::tui::state::{App, Options, PanelSet};
use beamfric::tui::update::{Msg, update};
use beamfric::tui::{draw_to_buffer, render, settled};

use crate::harness::scenes::{PLAIN, loaded_preset, plain_render};

/// The frame of a preset after `keys`.
fn frame(name: &str, keys: &str, (width, height): (u16, u16), ascii: bool) -> String {
    let keys = parse_keys(keys).unwrap();
    let buffer = render(
        loaded_preset(name),
        &keys,
        plain_render(width, height, ascii),
    )
    .unwrap();
    buffer_to_text(&buffer, false)
}

/// The explorer on a preset at `size`, its solve and sweeps done.
fn app_at(name: &str, (width, height): (u16, u16)) -> App {
    let mut app = settled(App::new(loaded_preset(name), Options::new(PLAIN)).unwrap());
    update(&mut app, Msg::Resize(width, height));
    finish(&mut app);
    app
}

/// Runs the pending solve and sweeps to completion, as the workers would.
fn finish(app: &mut App) {
    for _ in 0..4 {
        if let Some(request) = app.exploration.pending_solve().cloned() {
            let solved = beamfric::tui::jobs::solve::solve(&request);
            update(app, Msg::Solved(Box::new(solved)));
        }
        for request in app.exploration.pending_sweeps() {
            update(app, Msg::Swept(compute_now(&request)));
        }
    }
}

fn press(app: &mut App, keys: &str) {
    for key in parse_keys(keys).unwrap() {
        update(app, Msg::Key(key));
    }
    finish(app);
}

fn text(app: &App) -> String {
    buffer_to_text(&draw_to_buffer(app, app.size.0, app.size.1), false)
}

/// The keys that bring each view (and so each new panel) on screen: at 80×24 its first panel
/// alone, at 120×40 all of it.
const VIEWS: [(&str, &str); 5] = [
    ("iterations", "v"),
    ("dual-box", "v v"),
    ("cases", "v v v"),
    ("figure-5", "v v v v"),
    ("matrices", "v v v v v"),
];

fn snapshots_of(preset: &str) {
    for ascii in [false, true] {
        let look = if ascii { "-ascii" } else { "" };
        for size in [(80, 24), (120, 40)] {
            for (panel, keys) in VIEWS {
                let text = frame(preset, keys, size, ascii);
                let label = format!("{preset}-{panel}-{}x{}{look}", size.0, size.1);
                assert_eq!(text.lines().count(), usize::from(size.1), "{label}");
                if ascii {
                    assert!(text.is_ascii(), "{label}: non-ASCII output\n{text}");
                }
                insta::assert_snapshot!(label, text);
            }
        }
    }
}

#[test]
fn method_panel_snapshots_on_benchmark_1() {
    snapshots_of("benchmark-1");
}

#[test]
fn method_panel_snapshots_on_benchmark_3() {
    snapshots_of("benchmark-3");
}

#[test]
fn method_panel_snapshots_on_a_stiff_preset() {
    snapshots_of("modulus-contrast");
}

#[test]
fn the_keystroke_solve_records_no_history_while_the_iterations_panel_is_hidden() {
    let mut app = app_at("benchmark-1", (80, 24));
    assert!(!visible_panels(&app).contains(&Panel::Iterations));
    assert!(!app.exploration.wanted.options.history);
    let shown = app.exploration.solution().unwrap().as_ref().unwrap();
    assert!(
        shown.history.is_none(),
        "history recorded with the panel hidden"
    );
    // Editing a value while hidden: still none.
    press(&mut app, "Right");
    let shown = app.exploration.solution().unwrap().as_ref().unwrap();
    assert!(shown.history.is_none());
    // Shown: the solve asks for it, and it arrives.
    press(&mut app, "v");
    assert_eq!(app.exploration.panel_set, Some(PanelSet::Iterations));
    assert_eq!(visible_panels(&app), vec![Panel::Iterations]);
    assert!(app.exploration.wanted.options.history);
    let history = app.exploration.solution().unwrap().as_ref().unwrap();
    let history = history
        .history
        .as_ref()
        .expect("history with the panel shown");
    assert!(history.iterations.len() >= 2, "{history:?}");
    // Hidden again (Tab to the deflection): the next solve records none.
    press(&mut app, "Tab");
    assert_eq!(visible_panels(&app), vec![Panel::Deflection]);
    press(&mut app, "Left");
    assert!(!app.exploration.wanted.options.history);
    let shown = app.exploration.solution().unwrap().as_ref().unwrap();
    assert!(shown.history.is_none());
}

#[test]
fn iterates_step_with_angle_brackets_and_draw_over_the_deflection() {
    let mut app = app_at("benchmark-3", (120, 40));
    press(&mut app, "v");
    let history = app.exploration.solution().unwrap().as_ref().unwrap();
    let count = history.history.as_ref().unwrap().iterations.len();
    assert!(count >= 2);
    assert_eq!(app.exploration.iterate, None);
    press(&mut app, "<");
    assert_eq!(app.exploration.iterate, Some(count - 2));
    let frame = text(&app);
    assert!(
        frame.contains(&format!("iterate {} (< >)", count - 2)),
        "{frame}"
    );
    // Back to the last one: no extra curve.
    press(&mut app, ">");
    assert_eq!(app.exploration.iterate, None);
    assert!(!text(&app).contains("(< >)"));
    // Never before the first.
    for _ in 0..count + 3 {
        press(&mut app, ",");
    }
    assert_eq!(app.exploration.iterate, Some(0));
}

#[test]
fn figure_5_shows_both_curves_and_both_current_values_at_80x24() {
    let app = app_at("lesson-epsilon", (80, 24));
    assert_eq!(visible_panels(&app), vec![Panel::Figure5]);
    // The preset opens on ε.
    assert_eq!(
        app.exploration.selected_row(),
        beamfric::tui::state::params::Row::Epsilon
    );
    let frame = text(&app);
    let points = match app
        .exploration
        .sweep_view::<Vec<beamfric::study::EpsPoint>>(Panel::Figure5)
    {
        beamfric::tui::state::sweeps::SweepView::Ready(points) => points.clone(),
        _ => panic!("the ε sweep is not ready"),
    };
    let epsilon = app.scene().solver.epsilon;
    let current = points.iter().find(|p| p.epsilon == epsilon).unwrap();
    let error = current.error.unwrap().max_rel.unwrap();
    let condition = current.cond_max.unwrap().value;
    let sci = |v: f64| beamfric::format::sci(v, 2);
    assert!(frame.contains(&format!("error {}", sci(error))), "{frame}");
    assert!(
        frame.contains(&format!("cond₂(Â) {}", sci(condition))),
        "{frame}"
    );
    // Two plots, one above the other: two x axes, each with the ε decades labelled.
    // (The panel is right of the 30 columns of parameters; its own corners are heavy.)
    let lines: Vec<String> = frame
        .lines()
        .map(|l| l.chars().skip(30).collect())
        .collect();
    let corners: Vec<usize> = (0..lines.len())
        .filter(|&i| lines[i].contains('└'))
        .collect();
    assert_eq!(corners.len(), 2, "{frame}");
    // Both curves drawn: braille dots in the rows of each plot.
    let has_curve = |rows: std::ops::Range<usize>| {
        rows.into_iter().any(|i| {
            lines[i]
                .chars()
                .any(|c| ('\u{2801}'..='\u{28ff}').contains(&c))
        })
    };
    assert!(has_curve(0..corners[0]), "no error curve\n{frame}");
    assert!(has_curve(corners[0]..corners[1]), "no cond curve\n{frame}");
}

#[test]
fn sixteen_coarse_epsilon_steps_from_1e_16_land_on_exactly_1() {
    let mut app = app_at("lesson-epsilon", (80, 24));
    press(&mut app, "Enter 1 e - 1 6 Enter");
    assert_eq!(app.scene().solver.epsilon, 1e-16);
    for step in 1..=16 {
        press(&mut app, "]");
        let expected: f64 = format!("1e{}", step - 16).parse().unwrap();
        assert_eq!(app.scene().solver.epsilon, expected, "after {step} steps");
    }
    assert_eq!(app.scene().solver.epsilon, 1.0);
    // The prompt reads the value as typed, with no drift digits.
    press(&mut app, "Enter");
    assert!(text(&app).contains("1"), "{}", text(&app));
    assert!(!text(&app).contains("1.0000000000000007"));
    press(&mut app, "Esc");
    // Ten fine steps are one decade exactly, both ways.
    for _ in 0..10 {
        press(&mut app, "Left");
    }
    assert_eq!(app.scene().solver.epsilon, 0.1);
    for _ in 0..30 {
        press(&mut app, "Left");
    }
    assert_eq!(app.scene().solver.epsilon, 1e-4);
    // A value off the grid keeps its digits through coarse steps.
    press(&mut app, "Enter 3 e - 7 Enter [ [ ] ] ]");
    assert_eq!(app.scene().solver.epsilon, 3e-6);
}

#[test]
fn the_dual_picture_names_the_state_the_results_panel_names() {
    // Benchmark 1 slides: on the edge |λ1| = g1.
    let mut app = app_at("benchmark-1", (120, 40));
    press(&mut app, "v v");
    let frame = text(&app);
    assert!(frame.contains("on the edge |λ1| = g1: slides"), "{frame}");
    let results_state = app
        .exploration
        .solution()
        .unwrap()
        .as_ref()
        .unwrap()
        .obstacles[0]
        .state();
    assert_eq!(results_state, "slides");
}

#[test]
fn the_views_cycle_back_to_the_scenes_own_panels() {
    let mut app = app_at("benchmark-1", (80, 24));
    let own = app.exploration.panels();
    for set in PanelSet::ALL.map(Some).into_iter().chain([None]) {
        press(&mut app, "v");
        assert_eq!(app.exploration.panel_set, set);
    }
    assert_eq!(app.exploration.panels(), own);
    // Nothing is computed for a panel not shown: at 80×24 the iterations view computes the
    // iterations (the solve's own history), not the dual box, cases or matrices.
    press(&mut app, "v");
    for panel in [Panel::DualBox, Panel::Cases, Panel::Matrices] {
        assert!(matches!(
            app.exploration.sweep_state(panel),
            beamfric::tui::state::sweeps::SweepState::Idle
        ));
    }
}
