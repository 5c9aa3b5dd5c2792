//! Typing values and choosing methods and panels in the explorer: values out of range, the
//! value prompt, typed positions, methods expected to be slow, charts waiting for new data,
//! only the visible panel computed, and what the diagram key changes.

use super::*;

#[test]
fn typed_values_out_of_range_are_refused_quoting_what_was_typed() {
    // Issue 22: a typed 1e300 in the elements row said "18446744073709551615 asked for".
    let mut app = app("benchmark-1");
    let before = app.scene().clone();
    let elements = "Down Down Down Down Down Down Down Down Down";
    for value in ["1e300", "-1", "2.5", "0", "20000000"] {
        press(
            &mut app,
            &format!("{elements} Enter {} Enter g", typed(value)),
        );
        let message = app.message.clone().unwrap_or_default();
        assert_eq!(
            message,
            format!("rejected: mesh.elements = {value}: must be a whole number from 1 to 10000000")
        );
    }
    // A number beyond f64 in any row: quoted, not shown as "inf".
    press(&mut app, "Enter 1 e 4 0 0 Enter");
    assert_eq!(
        app.message.as_deref(),
        Some("rejected: load.f0 = 1e400: must be a finite number (at most 1.8e308 in size)")
    );
    assert_eq!(*app.scene(), before);
}

#[test]
fn cycling_the_method_skips_one_expected_to_be_slow_and_says_so() {
    let mut app = app("benchmark-1");
    press(
        &mut app,
        "Down Down Down Down Down Down Down Down Down Enter 2 0 0 0 Enter",
    );
    assert_eq!(app.scene().mesh.elements, 2000);
    for _ in 0..4 {
        press(&mut app, "m");
    }
    assert_eq!(app.scene().solver.method, Method::RegularizedNewton);
    press(&mut app, "m");
    // dual-inverse (about 0.4 s here… and growing like N³) is not entered silently.
    assert_eq!(app.scene().solver.method, Method::ClosedForm);
    let message = app.message.clone().unwrap();
    assert!(
        message.starts_with("skipped dual-inverse: about"),
        "{message}"
    );
    // At n = 20 it is quick and is entered.
    let mut app = self::app("benchmark-1");
    for _ in 0..5 {
        press(&mut app, "m");
    }
    assert_eq!(app.scene().solver.method, Method::DualInverse);
}

#[test]
fn a_chart_keeps_its_data_marked_as_updating_until_the_new_data_arrives() {
    let mut app = app("lesson-epsilon");
    finish_pending(&mut app);
    assert!(matches!(
        app.exploration.sweep_state(Panel::EpsError),
        SweepState::Ready(_)
    ));
    // A change of the load: the sweep is outdated, its old points stay (marked).
    press(&mut app, "Right");
    assert!(matches!(
        app.exploration.sweep_state(Panel::EpsError),
        SweepState::Pending(Some(_))
    ));
    let frame = buffer_to_text(&draw_to_buffer(&app, 200, 50), false);
    assert!(frame.contains("updating…"), "{frame}");
    assert!(!frame.contains("computing the ε sweep"), "{frame}");
    // The new data replaces it.
    finish_pending(&mut app);
    let frame = buffer_to_text(&draw_to_buffer(&app, 200, 50), false);
    assert!(!frame.contains("updating…"), "{frame}");
}

#[test]
fn only_the_visible_panel_is_computed_at_80x24() {
    let mut app = app("benchmark-1");
    update(&mut app, Msg::Resize(80, 24));
    // One panel at a time: the deflection, which needs no study.
    assert!(app.exploration.pending_sweeps().is_empty());
    press(&mut app, "Tab");
    let pending = app.exploration.pending_sweeps();
    assert_eq!(
        pending.len(),
        1,
        "only the ε sweep behind the focused panel"
    );
    // Hiding it again cancels the need.
    press(&mut app, "Tab Tab Tab");
    assert!(app.exploration.pending_sweeps().is_empty());
}

/// Issue 13: typing a position that moves an obstacle past another keeps the selection on
/// the obstacle that was edited (now with another number), and a rejected value is named by
/// the number the user sees.
#[test]
fn a_typed_position_keeps_the_cursor_on_its_obstacle() {
    let mut app = app("eight-obstacles");
    // Row 4 is obstacle 1's position (0.1 m): move it to 0.95 m, past all the others.
    press(&mut app, "Down Down Down Down Enter 0 . 9 5 Enter");
    assert_eq!(app.message, None, "accepted");
    let xs: Vec<f64> = app.scene().obstacles.iter().map(|o| o.x).collect();
    assert_eq!(xs.last(), Some(&0.95), "sorted: {xs:?}");
    assert_eq!(
        format!("{:?}", app.exploration.selected_row()),
        "ObstacleX(7)",
        "the cursor followed the obstacle to its new number"
    );
    // Its sliding threshold is the next row: the same obstacle.
    press(&mut app, "Down Enter 7 7 7 Enter");
    assert_eq!(app.scene().obstacles[7].sliding, 777.0);
    assert_eq!(app.scene().obstacles[7].x, 0.95);
    // A position that would make it the first again but is too close to obstacle 1 (0.2 m
    // after the move) is rejected naming obstacle 8, the number on screen, not the number
    // it would have had after sorting.
    press(&mut app, "Up Enter 0 . 2 Enter");
    let message = app.message.clone().unwrap_or_default();
    assert!(message.contains("rejected"), "{message}");
    assert!(message.contains("obstacle[8]"), "{message}");
    assert!(!message.contains("obstacle[2]"), "{message}");
}

/// Issue 13: the value prompt starts with the current value (typing replaces it), the cursor
/// moves, Ctrl-U erases before it.
#[test]
fn the_value_prompt_is_pre_filled_and_editable() {
    let mut app = app("benchmark-1");
    press(&mut app, "Enter");
    let Mode::Editing { prompt, .. } = &app.mode else {
        panic!("not editing")
    };
    assert_eq!(prompt.text, "50000");
    // ← then typing edits the value in place: 50000 → 500090 … then Enter.
    press(&mut app, "Left 9 Enter");
    assert_eq!(app.scene().load.f0, 500090.0);
    // Typing at once replaces the value, as the keys of earlier lessons expect.
    press(&mut app, "Enter 7 Enter");
    assert_eq!(app.scene().load.f0, 7.0);
    // Ctrl-U erases everything before the cursor.
    press(&mut app, "Enter Left C-u");
    let Mode::Editing { prompt, .. } = &app.mode else {
        panic!("not editing")
    };
    assert_eq!(prompt.text, "7");
    assert_eq!(prompt.cursor, 0);
    press(&mut app, "Esc");
    assert_eq!(app.mode, Mode::Normal);
}

#[test]
fn a_value_longer_than_the_prompt_takes_is_refused_never_cut() {
    // Stop 58's hostile pass: the prompt dropped what came past 200 characters in silence,
    // so "0." with 250 zeros and a 5 set f0 to 0, and 200 digits with e-190 set 1.2e199.
    let mut app = app("benchmark-1");
    let before = app.scene().clone();
    let digits = format!("1{}", "2".repeat(199));
    press(&mut app, &format!("Enter {} e - 1 9 0", typed(&digits)));
    let message = app.message.clone().unwrap_or_default();
    assert_eq!(
        message,
        "a value has at most 200 characters (5 more typed, not taken)"
    );
    press(&mut app, "Enter");
    assert_eq!(
        app.message.as_deref(),
        Some(
            "rejected: a value has at most 200 characters (5 more typed, not taken); nothing \
             changed"
        )
    );
    assert_eq!(*app.scene(), before);
    // A paste past the limit alike.
    press(&mut app, "Enter");
    update(&mut app, Msg::Paste(format!("0.{}5", "0".repeat(250))));
    press(&mut app, "Enter");
    assert!(
        app.message
            .as_deref()
            .unwrap_or_default()
            .starts_with("rejected: a value has at most"),
        "{:?}",
        app.message
    );
    assert_eq!(*app.scene(), before);
    // Emptied, the prompt takes a value again.
    press(&mut app, &format!("Enter {} C-u 7 Enter", typed(&digits)));
    assert_eq!(app.scene().load.f0, 7.0);
}

/// Issue 13: `b` where no deflection panel is on screen brings it forward; the diagram does
/// not leak into the next preset.
#[test]
fn the_diagram_key_shows_what_it_changes() {
    let mut app = app("benchmark-1");
    update(&mut app, Msg::Resize(80, 24));
    press(&mut app, "Tab");
    assert!(!visible_panels(&app).contains(&Panel::Deflection));
    press(&mut app, "b");
    assert!(visible_panels(&app).contains(&Panel::Deflection));
    assert_eq!(format!("{:?}", app.exploration.diagram), "Moment");
    press(&mut app, "p Down Enter");
    assert_eq!(
        format!("{:?}", app.exploration.diagram),
        "Deflection",
        "a new scene starts afresh"
    );
}
