//! The mouse (issue 13), through the explorer's own update function: a click lands on what the
//! frame draws at that cell. Every test finds its target in the drawn frame (a row's label, an
//! obstacle's marker, a panel's title), clicks there, and checks the state — and, for a drag,
//! that the marker is drawn again where the pointer let go.

use beamfric::scene::Panel;
use beamfric::tui::input::keys::parse_keys;
use beamfric::tui::input::pointer::Pointer;
use beamfric::tui::layout::hit::{Target, target};
use beamfric::tui::state::params::Row;
use beamfric::tui::state::{App, Mode, Options};
use beamfric::tui::update::{Msg, update};
use beamfric::tui::{draw_to_buffer, press, settle};

use crate::harness::scenes::{PLAIN, loaded_preset};
use crate::harness::screen::find;

fn app(name: &str, width: u16, height: u16) -> App {
    let mut app = App::new(loaded_preset(name), Options::new(PLAIN)).unwrap();
    update(&mut app, Msg::Resize(width, height));
    settle(&mut app);
    app
}

/// The frame's rows as text.
fn screen(app: &App) -> Vec<String> {
    let buffer = draw_to_buffer(app, app.size.0, app.size.1);
    (0..buffer.area.height)
        .map(|y| {
            (0..buffer.area.width)
                .map(|x| buffer[(x, y)].symbol().to_string())
                .collect()
        })
        .collect()
}

/// Every cell showing `glyph`, left to right within rows.
fn cells_of(screen: &[String], glyph: char) -> Vec<(u16, u16)> {
    let mut cells = Vec::new();
    for (y, line) in screen.iter().enumerate() {
        for (x, c) in line.chars().enumerate() {
            if c == glyph {
                cells.push((x as u16, y as u16));
            }
        }
    }
    cells
}

fn click(app: &mut App, (x, y): (u16, u16)) {
    let pointer = Pointer::Click {
        x,
        y,
        double: false,
    };
    update(app, Msg::Pointer(pointer));
    settle(app);
}

#[test]
fn a_click_selects_the_row_drawn_under_it() {
    for (width, height) in [(120, 40), (80, 24), (60, 16)] {
        let mut app = app("benchmark-3", width, height);
        let rows = app.exploration.rows();
        for (i, row) in rows.iter().enumerate() {
            let frame = screen(&app);
            // Rows of one label ("  sliding g1") repeat: find the one of this obstacle by
            // selecting from the top of the visible rows.
            let Some(cell) = find(&frame, &format!("│{}", row.label())) else {
                continue; // scrolled out of view
            };
            if rows.iter().filter(|r| r.label() == row.label()).count() > 1 {
                continue;
            }
            click(&mut app, (cell.0 + 3, cell.1));
            assert_eq!(
                app.exploration.rows()[app.exploration.selected],
                *row,
                "{width}x{height} row {i}"
            );
        }
        // A click on the parameters' border selects nothing new.
        let before = app.exploration.selected;
        let frame = screen(&app);
        let (x, y) = find(&frame, "Parameters").unwrap();
        click(&mut app, (x, y));
        assert_eq!(app.exploration.selected, before);
    }
}

#[test]
fn a_clicked_row_stays_under_the_pointer_when_the_list_scrolls() {
    // eight-obstacles has more rows than fit at 80x24.
    let mut app = app("eight-obstacles", 80, 24);
    press(&mut app, parse_keys("G").unwrap()[0]);
    let frame = screen(&app);
    // An obstacle's row shown after G, not the selected (last) row.
    let (index, (x, y)) = (0..8)
        .rev()
        .find_map(|i| Some((i, find(&frame, &format!("│obstacle {} x", i + 1))?)))
        .expect("an obstacle's row shown after G");
    assert_ne!(app.exploration.selected_row(), Row::ObstacleX(index));
    click(&mut app, (x + 3, y));
    assert_eq!(app.exploration.selected_row(), Row::ObstacleX(index));
    let frame = screen(&app);
    assert_eq!(
        find(&frame, &format!("│obstacle {} x", index + 1)),
        Some((x, y)),
        "the row did not move"
    );
}

#[test]
fn the_wheel_over_the_parameters_steps_the_selected_value() {
    let mut app = app("benchmark-1", 120, 40);
    let frame = screen(&app);
    let (x, y) = find(&frame, "│modulus E").unwrap();
    click(&mut app, (x + 3, y));
    assert_eq!(app.exploration.selected_row(), Row::Young);
    let young = app.scene().beam.young;
    update(
        &mut app,
        Msg::Pointer(Pointer::Scroll {
            x: x + 3,
            y: y + 2,
            up: true,
        }),
    );
    // One fine step up: ×10^0.1, the same as → (checked against the key).
    let mut by_key = self::app("benchmark-1", 120, 40);
    for _ in 0..app.exploration.selected {
        press(&mut by_key, parse_keys("Down").unwrap()[0]);
    }
    press(&mut by_key, parse_keys("Right").unwrap()[0]);
    assert_eq!(app.scene().beam.young, by_key.scene().beam.young);
    assert!((app.scene().beam.young / young - 10f64.powf(0.1)).abs() < 1e-12);
    update(
        &mut app,
        Msg::Pointer(Pointer::Scroll {
            x: x + 3,
            y,
            up: false,
        }),
    );
    assert!((app.scene().beam.young / young - 1.0).abs() < 1e-12);
    // Over a chart the wheel changes nothing.
    let (cx, cy) = find(&frame, "Deflection").unwrap();
    let scene = app.scene().clone();
    update(
        &mut app,
        Msg::Pointer(Pointer::Scroll {
            x: cx,
            y: cy + 5,
            up: true,
        }),
    );
    assert_eq!(*app.scene(), scene);
}

#[test]
fn dragging_an_obstacle_marker_moves_the_obstacle_to_where_it_is_let_go() {
    for (width, height) in [(120, 40), (80, 24)] {
        let mut app = app("benchmark-1", width, height);
        let frame = screen(&app);
        // Benchmark 1's obstacle slides: its marker is ↕.
        let markers = cells_of(&frame, '↕');
        let &(mx, my) = markers
            .iter()
            .find(|(_, y)| *y > 1 && (*y as usize) < frame.len() - 5)
            .expect("the marker is drawn");
        assert_eq!(target(&app, mx, my), Target::Obstacle(0));
        let undo_before = app.history.undo_len();
        update(
            &mut app,
            Msg::Pointer(Pointer::Click {
                x: mx,
                y: my,
                double: false,
            }),
        );
        assert_eq!(app.exploration.selected_row(), Row::ObstacleX(0));
        // Drag in steps to 12 columns left, re-solving on the way.
        for dx in 1..=12 {
            update(&mut app, Msg::Pointer(Pointer::Drag { x: mx - dx, y: my }));
            settle(&mut app);
        }
        update(
            &mut app,
            Msg::Pointer(Pointer::Release { x: mx - 12, y: my }),
        );
        let x = app.scene().obstacles[0].x;
        assert!(x < 0.8 - 0.05, "{width}x{height}: x = {x}");
        assert_eq!(
            app.history.undo_len(),
            undo_before + 1,
            "one undo step per drag"
        );
        // The marker is drawn where the pointer let go (the chart's own drawing).
        let frame = screen(&app);
        let now: Vec<u16> = frame
            .iter()
            .enumerate()
            .filter(|(y, _)| *y > 1 && *y < frame.len() - 5)
            .flat_map(|(y, line)| {
                line.chars()
                    .enumerate()
                    .filter(|(_, c)| "●↕↻✱".contains(*c))
                    .map(move |(x, _)| (x as u16, y))
            })
            .map(|(x, _)| x)
            .collect();
        assert!(
            now.contains(&(mx - 12)),
            "{width}x{height}: marker at {now:?}, let go at {}",
            mx - 12
        );
        // u undoes the whole drag.
        press(&mut app, parse_keys("u").unwrap()[0]);
        assert_eq!(app.scene().obstacles[0].x, 0.8);
    }
}

#[test]
fn a_drag_never_passes_a_neighbour_or_a_support() {
    let mut app = app("benchmark-3", 120, 40);
    let frame = screen(&app);
    // The second obstacle (x = 0.4): its marker column is the second marker's.
    // The markers in the plot (not those of the key under it), left to right.
    let mut markers: Vec<(u16, u16)> = "↕●↻✱"
        .chars()
        .flat_map(|glyph| cells_of(&frame, glyph))
        .filter(|&(x, y)| matches!(target(&app, x, y), Target::Obstacle(_)))
        .collect();
    markers.sort();
    assert_eq!(markers.len(), 4, "{markers:?}");
    let (mx, my) = markers[1];
    assert_eq!(target(&app, mx, my), Target::Obstacle(1));
    click(&mut app, (mx, my));
    update(&mut app, Msg::Pointer(Pointer::Drag { x: 0, y: my }));
    update(&mut app, Msg::Pointer(Pointer::Release { x: 0, y: my }));
    let xs: Vec<f64> = app.scene().obstacles.iter().map(|o| o.x).collect();
    assert!(xs[1] > xs[0], "{xs:?}");
    assert!((xs[1] - xs[0] - 1e-3).abs() < 1e-12, "{xs:?}");
}

#[test]
fn clicking_a_panel_focuses_it_and_its_title_or_a_double_click_zooms() {
    let mut app = app("benchmark-1", 120, 40);
    let frame = screen(&app);
    let (x, y) = find(&frame, "cond2 of the cases").expect("the panel's title");
    // Inside the panel: focus.
    click(&mut app, (x, y + 4));
    assert_eq!(
        app.exploration.panels()[app.exploration.focus],
        Panel::EpsCond
    );
    assert!(!app.zoom);
    // On its title: zoom, and the zoomed frame is that panel alone.
    click(&mut app, (x, y));
    assert!(app.zoom);
    let frame = screen(&app);
    assert!(find(&frame, "cond2 of the cases").is_some());
    assert!(find(&frame, "Parameters").is_none());
    assert!(find(&frame, "Deflection").is_none());
    // Its title again: back.
    let (x, y) = find(&frame, "cond2 of the cases").unwrap();
    click(&mut app, (x, y));
    assert!(!app.zoom);
    // A double click inside a panel zooms too; z unzooms.
    let frame = screen(&app);
    let (x, y) = find(&frame, "Error vs n").unwrap();
    update(
        &mut app,
        Msg::Pointer(Pointer::Click {
            x,
            y: y + 3,
            double: true,
        }),
    );
    assert!(app.zoom);
    assert_eq!(
        app.exploration.panels()[app.exploration.focus],
        Panel::ErrorTime
    );
    press(&mut app, parse_keys("z").unwrap()[0]);
    assert!(!app.zoom);
}

#[test]
fn the_preset_picker_takes_clicks_and_the_wheel() {
    let mut app = app("benchmark-1", 80, 24);
    press(&mut app, parse_keys("p").unwrap()[0]);
    let frame = screen(&app);
    let (x, y) = find(&frame, "lesson-mesh").expect("listed");
    click(&mut app, (x, y));
    let Mode::Presets(picker) = &app.mode else {
        panic!("still picking")
    };
    assert_eq!(
        picker
            .highlighted()
            .map(|i| beamfric::scene::PRESETS[i].name),
        Some("lesson-mesh")
    );
    update(&mut app, Msg::Pointer(Pointer::Scroll { x, y, up: false }));
    let Mode::Presets(picker) = &app.mode else {
        panic!("still picking")
    };
    assert_eq!(
        picker
            .highlighted()
            .map(|i| beamfric::scene::PRESETS[i].name),
        Some("fine-mesh")
    );
    // A double click loads the entry under it.
    let frame = screen(&app);
    let (x, y) = find(&frame, "tiny-beam").expect("listed");
    update(
        &mut app,
        Msg::Pointer(Pointer::Click { x, y, double: true }),
    );
    settle(&mut app);
    assert_eq!(app.mode, Mode::Normal);
    assert_eq!(app.scene().title, "Tiny beam (l = 1 mm)");
    // A click outside the picker closes it.
    press(&mut app, parse_keys("p").unwrap()[0]);
    click(&mut app, (0, 0));
    assert_eq!(app.mode, Mode::Normal);
}

#[test]
fn without_a_layout_or_outside_everything_the_mouse_does_nothing() {
    let mut app = app("benchmark-1", 40, 10);
    let scene = app.scene().clone();
    for (x, y) in [(0, 0), (39, 9), (500, 500)] {
        click(&mut app, (x, y));
        update(&mut app, Msg::Pointer(Pointer::Drag { x, y }));
        update(&mut app, Msg::Pointer(Pointer::Scroll { x, y, up: true }));
        update(&mut app, Msg::Pointer(Pointer::Release { x, y }));
    }
    assert_eq!(*app.scene(), scene);
    assert_eq!(app.mode, Mode::Normal);
}

#[test]
fn list_keys_move_to_the_ends_and_by_pages() {
    let mut app = app("eight-obstacles", 80, 24);
    let last = app.exploration.rows().len() - 1;
    for (keys, expected) in [
        ("G", last),
        ("g", 0),
        ("End", last),
        ("Home", 0),
        ("PgDn", 0),
        ("PgDn PgDn PgDn PgDn PgDn PgDn", last),
        ("PgUp PgUp PgUp PgUp PgUp PgUp", 0),
    ] {
        for key in parse_keys(keys).unwrap() {
            press(&mut app, key);
        }
        if keys == "PgDn" {
            // One page: as many rows as the box shows.
            let frame = screen(&app);
            let top = find(&frame, "Parameters").unwrap().1;
            let bottom = frame
                .iter()
                .enumerate()
                .skip(top as usize + 1)
                .find(|(_, l)| l.starts_with('└') || l.starts_with('├'))
                .unwrap()
                .0;
            let page = bottom - top as usize - 1;
            assert_eq!(app.exploration.selected, page, "{keys}");
        } else {
            assert_eq!(app.exploration.selected, expected, "{keys}");
        }
    }
    // The selected row is on screen after each.
    press(&mut app, parse_keys("G").unwrap()[0]);
    let frame = screen(&app);
    assert!(find(&frame, "│method").is_some());
}

#[test]
fn a_drag_of_an_obstacle_deleted_meanwhile_does_nothing() {
    // Found in review: the drag kept the index of an obstacle that `d` had deleted.
    let mut app = app("benchmark-3", 120, 40);
    let frame = screen(&app);
    let mut markers: Vec<(u16, u16)> = "↕●↻✱"
        .chars()
        .flat_map(|glyph| cells_of(&frame, glyph))
        .filter(|&(x, y)| matches!(target(&app, x, y), Target::Obstacle(_)))
        .collect();
    markers.sort();
    let (mx, my) = *markers.last().unwrap();
    assert_eq!(target(&app, mx, my), Target::Obstacle(3));
    click(&mut app, (mx, my));
    // Delete it and the one before it: the drag's index is now two past the last.
    for key in parse_keys("d Up Up Up d").unwrap() {
        press(&mut app, key);
    }
    assert_eq!(app.scene().obstacles.len(), 2);
    let scene = app.scene().clone();
    update(&mut app, Msg::Pointer(Pointer::Drag { x: mx - 5, y: my }));
    update(
        &mut app,
        Msg::Pointer(Pointer::Release { x: mx - 5, y: my }),
    );
    assert_eq!(*app.scene(), scene);
}

#[test]
fn a_click_on_the_warnings_in_the_status_opens_the_warnings_view() {
    let mut app = app("lesson-mesh", 120, 40);
    let frame = screen(&app);
    let (x, y) = find(&frame, "warnings (w: all)").expect("the status counts the warnings");
    click(&mut app, (x, y));
    assert!(
        matches!(app.mode, Mode::Warnings { offset: 0 }),
        "{:?}",
        app.mode
    );
    // The wheel scrolls it; a click closes it.
    update(&mut app, Msg::Pointer(Pointer::Scroll { x, y, up: false }));
    assert!(
        matches!(app.mode, Mode::Warnings { offset: 1 }),
        "{:?}",
        app.mode
    );
    update(&mut app, Msg::Pointer(Pointer::Scroll { x, y, up: true }));
    assert!(
        matches!(app.mode, Mode::Warnings { offset: 0 }),
        "{:?}",
        app.mode
    );
    click(&mut app, (x, y));
    assert_eq!(app.mode, Mode::Normal);
    // Without warnings the status line opens nothing.
    let mut app = self::app("benchmark-1", 120, 40);
    let frame = screen(&app);
    let (x, y) = find(&frame, "no warnings").unwrap();
    click(&mut app, (x, y));
    assert_eq!(app.mode, Mode::Normal);
}
