//! Markers for every room (issue 25): every chart drawn in every marker set at 80×24 (one
//! chart at a time, Tab's panels) and 120×40 (all four at once), as snapshots; in every frame
//! each chart marks its current point in the plot itself, in plain text (a rule `┆`, `:` in
//! ASCII: the selected obstacle's position in the deflection, the scene's ε in the ε charts,
//! the current run in the error chart). The projector look and the ASCII look likewise.

use beamfric::plot::{MarkerSet, Palette, buffer_to_text};
use beamfric::tui::input::keys::Key;
use beamfric::tui::state::App;
use beamfric::tui::{draw_to_buffer, prepare};

use crate::harness::scenes::{loaded_preset, plain_render};

/// Benchmark 1 solved with every chart's data, the first obstacle's position selected (the
/// deflection's current point).
fn benchmark_1(ascii: bool) -> App {
    // f0, f1, E, width, height, then obstacle 1's x.
    let keys = [Key::Down; 5];
    prepare(
        loaded_preset("benchmark-1"),
        &keys,
        plain_render(120, 40, ascii),
    )
    .expect("the preset opens")
}

/// The charts' rows of a frame (the panels right of the parameters and results).
fn chart_text(text: &str, from_column: usize) -> Vec<String> {
    text.lines()
        .map(|l| l.chars().skip(from_column).collect())
        .collect()
}

/// Does the chart region show the current point's rule on at least three rows (a rule, not a
/// stray character)?
fn has_rule(lines: &[String], rule: char) -> bool {
    lines.iter().filter(|l| l.contains(rule)).count() >= 3
}

/// The charts drawn in `markers` at 80×24 (each panel focused in turn) and 120×40.
fn frames(app: &mut App, markers: MarkerSet, suffix: &str) -> Vec<(String, String)> {
    app.markers = markers;
    let mut out = Vec::new();
    let panels = app.exploration.panels();
    for (i, panel) in panels.iter().enumerate() {
        app.exploration.focus = i;
        let text = buffer_to_text(&draw_to_buffer(app, 80, 24), false);
        out.push((format!("{}-{panel:?}-80x24{suffix}", markers.name()), text));
    }
    app.exploration.focus = 0;
    let text = buffer_to_text(&draw_to_buffer(app, 120, 40), false);
    out.push((format!("{}-all-120x40{suffix}", markers.name()), text));
    out
}

fn check_and_snapshot(label: &str, text: &str, rule: char) {
    let (w, h) = if label.contains("120x40") {
        (120, 40)
    } else {
        (80, 24)
    };
    assert_eq!(text.lines().count(), h, "{label}");
    // At 80×24 the chart is right of the 30-column left side; at 120×40 four charts, the
    // deflection on top and three below, each checked in its own columns.
    let regions: Vec<Vec<String>> = if w == 80 {
        vec![chart_text(text, 30)]
    } else {
        let lines: Vec<&str> = text.lines().collect();
        let top: Vec<String> = lines[..18]
            .iter()
            .map(|l| l.chars().skip(38).collect())
            .collect();
        let bottom = |from: usize, to: usize| -> Vec<String> {
            lines[18..]
                .iter()
                .map(|l| l.chars().skip(from).take(to - from).collect())
                .collect()
        };
        vec![top, bottom(38, 65), bottom(65, 93), bottom(93, 120)]
    };
    for (i, region) in regions.iter().enumerate() {
        assert!(
            has_rule(region, rule),
            "{label}: chart {i} has no current point's rule {rule:?}:\n{text}"
        );
    }
    insta::assert_snapshot!(label.to_string(), text);
}

#[test]
fn every_chart_in_every_marker_set() {
    let mut app = benchmark_1(false);
    for markers in MarkerSet::ALL {
        for (label, text) in frames(&mut app, markers, "") {
            check_and_snapshot(&label, &text, '┆');
            // The curves are drawn in the set's own characters.
            let curve = match markers {
                MarkerSet::Braille => '⠤'..='⣿',
                MarkerSet::HalfBlock => '▀'..='▀',
                MarkerSet::Quadrant => '▖'..='▟',
                MarkerSet::Sextant => '🬀'..='🬻',
                MarkerSet::Block => '█'..='█',
                MarkerSet::Ascii => '*'..='*',
            };
            assert!(
                text.chars().filter(|c| curve.contains(c)).count() >= 5,
                "{label}: no curve drawn in {curve:?}:\n{text}"
            );
        }
    }
}

#[test]
fn the_ascii_look_draws_every_chart_in_ascii_whatever_the_set() {
    let mut app = benchmark_1(true);
    for markers in [MarkerSet::Braille, MarkerSet::Block] {
        for (label, text) in frames(&mut app, markers, "-ascii") {
            assert!(text.is_ascii(), "{label}: not ASCII:\n{text}");
            assert!(text.matches('*').count() >= 5, "{label}: no curve:\n{text}");
            check_and_snapshot(&label, &text, ':');
        }
    }
}

#[test]
fn the_projector_look() {
    let mut app = benchmark_1(false);
    app.palette = Palette::HighContrast;
    for (label, text) in frames(&mut app, MarkerSet::HalfBlock, "-projector") {
        check_and_snapshot(&label, &text, '┆');
    }
    // Bold labels with or without colours: the axis labels' cells are bold.
    app.exploration.focus = 1;
    let buffer = draw_to_buffer(&app, 80, 24);
    let label = (0..24)
        .flat_map(|y| (30..80).map(move |x| (x, y)))
        .find(|&(x, y)| buffer[(x, y)].symbol() == "1" && buffer[(x + 1, y)].symbol() == "e")
        .expect("a decade label");
    assert!(
        buffer[label]
            .modifier
            .contains(ratatui::style::Modifier::BOLD),
        "the projector's labels are bold"
    );
}

/// The deflection numbers its obstacles beside their markers, in the plot itself (where the
/// cells are blank): Benchmark 3's four at 80×24.
#[test]
fn the_deflection_numbers_its_obstacles() {
    let app = prepare(
        loaded_preset("benchmark-3"),
        &[],
        plain_render(80, 24, false),
    )
    .unwrap();
    let text = buffer_to_text(&draw_to_buffer(&app, 80, 24), false);
    let mut numbers = Vec::new();
    for line in text.lines() {
        let chart: Vec<char> = line.chars().skip(30).collect();
        // The graph: right of the y axis (its ┤ or │), left of the panel's border.
        let Some(axis) = chart.iter().position(|c| *c == '┤' || *c == '│') else {
            continue;
        };
        let graph = &chart[axis + 1..chart.len().saturating_sub(1)];
        for (i, c) in graph.iter().enumerate() {
            let digit = |j: Option<usize>| {
                j.and_then(|j| graph.get(j))
                    .is_some_and(|c| c.is_ascii_digit())
            };
            if c.is_ascii_digit() && !digit(i.checked_sub(1)) && !digit(Some(i + 1)) {
                numbers.push(*c);
            }
        }
    }
    numbers.sort();
    assert_eq!(numbers, ['1', '2', '3', '4'], "{text}");
}
