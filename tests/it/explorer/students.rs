//! The explorer of a student in a lecture (issue 23): the follow keys, forks and rejoins, the save
//! prompt's offered name, the lecturer's quit and the end of the class, and the closing save.

use super::*;

/// A served student's explorer, following a presenter from the start.
fn student() -> App {
    use beamfric::tui::state::follow::{Follow, Followers};
    let options = Options {
        follow: Some(Follow::student(&Followers::new(|| {}), "student")),
        ..Options::new(PLAIN)
    };
    app_with("benchmark-1", options)
}

fn screen(app: &App) -> String {
    buffer_to_text(&draw_to_buffer(app, 120, 40), false)
}

#[test]
fn a_students_help_and_hints_list_the_follow_keys_and_fork_and_rejoin_work() {
    let mut app = student();
    // Stop 59's lecture pass: a follower's hint line offered ↑↓:select ←→:change Enter:type
    // m:method, keys that only answer "following the presenter", and F while following. It
    // names the keys that work now.
    let following = "?:help q:quit f:fork w:warnings t:time z:zoom c:compare e:export T:theme";
    assert!(screen(&app).contains(following), "{}", screen(&app));
    for gone in ["F:rejoin", ":select", ":change", ":method"] {
        assert!(!screen(&app).contains(gone), "{gone}: {}", screen(&app));
    }
    keys(&mut app, "?");
    assert_eq!(app.mode, Mode::Help { offset: 0 });
    let help = screen(&app);
    assert!(help.contains("fork: explore on your own"), "{help}");
    assert!(help.contains("follow the presenter again"), "{help}");
    keys(&mut app, "Esc");
    // Following: a change is refused; forked: it is made; rejoined: following again.
    keys(&mut app, "]");
    assert!(!app.modified());
    keys(&mut app, "f");
    assert!(screen(&app).contains("own exploration"));
    let hints = screen(&app);
    assert!(
        hints.contains("?:help q:quit F:rejoin ↑↓:select"),
        "{hints}"
    );
    assert!(!hints.contains("f:fork"), "{hints}");
    keys(&mut app, "]");
    assert!(app.modified());
    // Stop 59's lecture pass: F threw the fork's changes away without a word. It asks, n
    // keeps them, y follows.
    keys(&mut app, "F");
    assert_eq!(
        app.mode,
        Mode::ConfirmDiscard {
            then: beamfric::tui::state::Discard::Rejoin
        }
    );
    assert!(
        screen(&app).contains("follow the presenter"),
        "{}",
        screen(&app)
    );
    keys(&mut app, "n");
    assert!(app.modified() && screen(&app).contains("own exploration"));
    keys(&mut app, "F y");
    assert!(screen(&app).contains("following the presenter"));
}

#[test]
fn a_follower_may_change_what_only_its_own_screen_shows() {
    let mut app = student();
    let palette = app.palette;
    keys(&mut app, "T");
    assert_ne!(app.palette, palette, "the theme is the student's own");
    keys(&mut app, "c");
    assert!(app.show_difference);
    keys(&mut app, "z");
    assert!(app.zoom);
    keys(&mut app, "w");
    assert_eq!(app.mode, Mode::Warnings { offset: 0 });
    keys(&mut app, "Esc");
    // The scene is still the presenter's.
    assert!(!app.modified());
}

/// Issue 23 item 4: `s` then `x` gave `benchmark-1.tomlx`; the first key typed replaces the
/// offered name, as the README says, and a key that moves the cursor keeps it for editing.
#[test]
fn the_save_prompts_first_key_replaces_the_offered_name() {
    let mut app = app("benchmark-1");
    press(&mut app, "s x");
    let Mode::Save { prompt } = &app.mode else {
        panic!("left the prompt")
    };
    assert_eq!(prompt.text, "x");
    press(&mut app, "Esc s Left x");
    let Mode::Save { prompt } = &app.mode else {
        panic!("left the prompt")
    };
    assert_eq!(prompt.text, "benchmark-1.tomxl");
}

/// Issue 23 item 4: under a save directory (a served session's `--save-dir`) the offered name
/// is relative to it, never the server's own path, and carries the owner's user name (made
/// safe for a file name), so students sharing the directory do not overwrite each other; the
/// save lands there; a preset loaded later is offered under the same rule.
#[test]
fn under_a_save_directory_the_offered_name_is_relative_and_the_owners() {
    let dir = std::env::temp_dir().join(format!("beamfric-owner-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let options = Options {
        save_policy: beamfric::tui::state::SavePolicy::Within(dir.clone()),
        save_directory: Some(dir.clone()),
        owner: Some("../al ice".into()),
        ..Options::new(PLAIN)
    };
    let mut app = app_with("benchmark-1", options);
    assert_eq!(app.save_path, "_al_ice-benchmark-1.toml");
    press(&mut app, "Right s");
    let Mode::Save { prompt } = &app.mode else {
        panic!("no prompt")
    };
    assert_eq!(prompt.text, "_al_ice-benchmark-1.toml");
    assert!(!prompt.text.contains(dir.to_str().unwrap()));
    press(&mut app, "Enter");
    let message = app.message.clone().unwrap();
    assert!(message.starts_with("saved to"), "{message}");
    assert!(dir.join("_al_ice-benchmark-1.toml").is_file(), "{message}");
    let index = PRESETS
        .iter()
        .position(|p| p.name == "benchmark-3")
        .unwrap();
    press(&mut app, "p");
    for _ in 0..index {
        press(&mut app, "Down");
    }
    press(&mut app, "Enter");
    assert_eq!(app.exploration.source, SceneSource::Preset("benchmark-3"));
    assert_eq!(app.save_path, "_al_ice-benchmark-3.toml");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Stop 59's lecture pass: a student who followed the presenter to another scene (a lesson's
/// later step) and forked it was offered `alice-benchmark-1.toml`, the scene the session
/// started on, and the closing save took that name too.
#[test]
fn a_followers_save_is_offered_under_the_scene_it_shows() {
    use beamfric::tui::state::follow::{Follow, Followers};
    let dir = tempfile::tempdir().unwrap();
    let options = Options {
        follow: Some(Follow::student(&Followers::new(|| {}), "alice")),
        save_policy: beamfric::tui::state::SavePolicy::Within(dir.path().into()),
        save_directory: Some(dir.path().into()),
        owner: Some("alice".into()),
        ..Options::new(PLAIN)
    };
    let mut app = app_with("benchmark-1", options);
    assert_eq!(app.save_path, "alice-benchmark-1.toml");
    let presenter = App::new(loaded_preset("benchmark-3"), Options::new(PLAIN)).unwrap();
    update(
        &mut app,
        Msg::Follow(std::sync::Arc::new(presenter.exploration.clone())),
    );
    press(&mut app, "f Right s");
    let Mode::Save { prompt } = &app.mode else {
        panic!("no prompt")
    };
    assert_eq!(prompt.text, "alice-benchmark-3.toml");
}

/// Issue 23 item 1: the class counts each student's unsaved work as `update` sees it, and the
/// lecturer's quit asks with the counts while students are connected; n keeps teaching, a
/// second Ctrl-C forces the end, as for unsaved changes.
#[test]
fn the_lecturers_quit_asks_with_the_students_unsaved_work() {
    use beamfric::tui::state::follow::{Follow, Followers};
    let followers = Followers::new(|| {});
    let lecturer = |followers: &std::sync::Arc<Followers>| {
        let options = Options {
            follow: Some(Follow::presenter(followers, true)),
            ..Options::new(PLAIN)
        };
        app_with("benchmark-1", options)
    };
    let mut presenter = lecturer(&followers);
    // Alone, the lecturer quits at once.
    keys(&mut presenter, "q");
    assert_eq!(presenter.ending, Some(beamfric::tui::state::Ending::Quit));
    let mut presenter = lecturer(&followers);
    let student_options = || Options {
        follow: Some(Follow::student(&followers, "student")),
        ..Options::new(PLAIN)
    };
    let mut alice = app_with("benchmark-1", student_options());
    let bob = app_with("benchmark-1", student_options());
    assert_eq!((followers.students(), followers.unsaved()), (2, 0));
    keys(&mut alice, "f ]");
    assert_eq!(followers.unsaved(), 1);
    keys(&mut alice, "u");
    assert_eq!(followers.unsaved(), 0, "undone to the scene as loaded");
    keys(&mut alice, "]");
    keys(&mut presenter, "q");
    assert_eq!(presenter.mode, Mode::ConfirmEndClass);
    let asked = screen(&presenter);
    assert!(
        asked.contains("2 students (1 with unsaved work): end the class? y / n"),
        "{asked}"
    );
    keys(&mut presenter, "n");
    assert_eq!(
        (presenter.mode.clone(), presenter.ending),
        (Mode::Normal, None)
    );
    assert!(screen(&presenter).contains("the class goes on"));
    keys(&mut presenter, "C-c");
    assert_eq!(presenter.mode, Mode::ConfirmEndClass);
    keys(&mut presenter, "C-c");
    assert_eq!(presenter.ending, Some(beamfric::tui::state::Ending::Quit));
    // A student who leaves is no longer counted.
    drop(alice);
    assert_eq!((followers.students(), followers.unsaved()), (1, 0));
    drop(bob);
    assert_eq!(followers.students(), 0);
}

/// Issue 23 items 1 and 6 as the student's explorer sees them: the presenter leaving gives a
/// follower its keys back with the view kept; the class ending shows the closing screen with
/// the scene as TOML (nothing saved without a save directory), and any key leaves.
#[test]
fn a_student_hears_the_presenter_leave_and_the_class_end() {
    use beamfric::tui::state::follow::ClassNews;
    let mut app = student();
    let shown = app.scene().clone();
    update(&mut app, Msg::Class(ClassNews::PresenterLeft));
    let told = buffer_to_text(&draw_to_buffer(&app, 80, 24), false);
    assert!(
        told.contains("the presenter left: the keys are yours (you follow again once one is back)"),
        "{told}"
    );
    assert_eq!(*app.scene(), shown);
    keys(&mut app, "]");
    assert!(app.modified(), "the keys are the student's again");
    update(
        &mut app,
        Msg::Class(ClassNews::Ended {
            by: "the lecturer".into(),
        }),
    );
    assert_eq!(
        app.mode,
        Mode::ClassEnded {
            by: "the lecturer".into(),
            saved: None
        }
    );
    // The changes are printed on the client's own screen once the explorer has left it
    // (`serve::lecture`); the closing screen says so, and shows no cut copy of its own.
    let closing = buffer_to_text(&draw_to_buffer(&app, 80, 24), false);
    assert!(
        closing.contains("The class was ended by the lecturer."),
        "{closing}"
    );
    assert!(
        closing.contains("Your changes are not saved on the server: when this closes, your"),
        "{closing}"
    );
    assert!(!closing.contains("[load]"), "{closing}");
    assert!(app.ending.is_none());
    keys(&mut app, "x");
    assert_eq!(app.ending, Some(beamfric::tui::state::Ending::Quit));
}

/// Issue 23 item 5: a student who forks the presenter's fine mesh (10⁶ elements) on a server
/// that allows 10⁵ gets a usable explorer at 10⁵ with a note, and the picker marks the presets
/// beyond the limit with the reason.
#[test]
fn a_fork_beyond_the_servers_mesh_limit_starts_at_the_limit_with_a_note() {
    use beamfric::tui::state::follow::{Follow, Followers};
    let followers = Followers::new(|| {});
    let options = Options {
        follow: Some(Follow::student(&followers, "student")),
        max_elements: Some(100_000),
        ..Options::new(PLAIN)
    };
    let mut app = app_with("benchmark-1", options);
    let presenter = App::new(loaded_preset("fine-mesh"), Options::new(PLAIN)).unwrap();
    assert_eq!(presenter.scene().mesh.elements, 1_000_000);
    update(
        &mut app,
        Msg::Follow(std::sync::Arc::new(presenter.exploration.clone())),
    );
    assert_eq!(
        app.scene().mesh.elements,
        1_000_000,
        "following shows the presenter's"
    );
    keys(&mut app, "f");
    assert_eq!(app.scene().mesh.elements, 100_000);
    let note = app.message.clone().unwrap();
    assert!(
        note.contains("at n = 100000") && note.contains("1000000"),
        "{note}"
    );
    // Stop 59's lecture pass: at 80 columns the note lost its end.
    assert!(note.chars().count() <= 80, "{note}");
    // Usable: a change is taken, not "rejected: mesh.elements".
    keys(&mut app, "]");
    assert!(
        !app.message
            .clone()
            .unwrap_or_default()
            .starts_with("rejected"),
        "{:?}",
        app.message
    );
    keys(&mut app, "p");
    let picker = screen(&app);
    let line = picker.lines().find(|l| l.contains("> fine-mesh")).unwrap();
    assert!(
        line.contains("[n = 1000000 is over this server's 100000: not here]"),
        "{picker}"
    );
    assert!(
        !picker
            .lines()
            .any(|l| l.contains("benchmark-1 ") && l.contains("not here"))
    );
    // Neither undo nor a reset goes past the limit (a hostile pass found both did).
    keys(&mut app, "Esc u");
    assert!(app.scene().mesh.elements <= 100_000);
    keys(&mut app, "u");
    assert_eq!(app.scene().mesh.elements, 100_000);
    let note = app.message.clone().unwrap_or_default();
    assert!(
        note == "nothing to undo" || note.contains("at most 100000"),
        "{note}"
    );
    keys(&mut app, "] r y");
    assert_eq!(app.scene().mesh.elements, 100_000, "{:?}", app.message);
}

/// Issue 23 item 1, with files in the way: the closing save of a student's unsaved work never
/// overwrites a file nor follows a link (even one to nothing); it takes the next free name.
#[test]
fn the_closing_save_takes_the_next_free_name() {
    use beamfric::tui::state::follow::{ClassNews, Follow, Followers};
    let dir = tempfile::tempdir().unwrap();
    let taken = dir.path().join("bob-benchmark-1.toml");
    std::fs::write(&taken, "someone else's").unwrap();
    std::os::unix::fs::symlink(
        dir.path().join("nowhere"),
        dir.path().join("bob-benchmark-1-2.toml"),
    )
    .unwrap();
    let options = Options {
        save_policy: beamfric::tui::state::SavePolicy::Within(dir.path().to_path_buf()),
        save_directory: Some(dir.path().to_path_buf()),
        owner: Some("bob".into()),
        follow: Some(Follow::student(&Followers::new(|| {}), "student")),
        ..Options::new(PLAIN)
    };
    let mut app = app_with("benchmark-1", options);
    keys(&mut app, "f ]");
    update(
        &mut app,
        Msg::Class(ClassNews::Ended {
            by: "the lecturer".into(),
        }),
    );
    assert_eq!(
        app.mode,
        Mode::ClassEnded {
            by: "the lecturer".into(),
            saved: Some("bob-benchmark-1-3.toml".into())
        }
    );
    assert_eq!(std::fs::read_to_string(&taken).unwrap(), "someone else's");
    assert!(!dir.path().join("nowhere").exists());
    let saved = std::fs::read_to_string(dir.path().join("bob-benchmark-1-3.toml")).unwrap();
    assert_eq!(
        beamfric::scene::Scene::from_toml(&saved, "bob").unwrap(),
        *app.scene()
    );
}

/// Stop 59's lecture pass: past the limit, the lecturer's message was refused on Enter even
/// after Backspace had shortened it, and only Esc got out of the prompt.
#[test]
fn a_message_refused_for_its_length_is_sent_once_shortened() {
    use beamfric::tui::state::follow::{Follow, Followers};
    let followers = Followers::new(|| {});
    let options = Options {
        follow: Some(Follow::presenter(&followers, true)),
        ..Options::new(PLAIN)
    };
    let mut app = app_with("benchmark-1", options);
    let x59 = vec!["x"; 59].join(" ");
    press(&mut app, &format!("S m {x59}"));
    assert_eq!(
        app.message.as_deref(),
        Some("a message has at most 58 characters (1 more typed, not taken)")
    );
    press(&mut app, "Enter");
    assert!(matches!(app.mode, Mode::Broadcast { .. }), "{:?}", app.mode);
    assert_eq!(
        app.message.as_deref(),
        Some("nothing sent (1 typed past 58 characters): Backspace, then Enter")
    );
    press(&mut app, "Backspace Enter");
    assert_eq!(app.mode, Mode::Normal);
    let sent = app.message.clone().unwrap_or_default();
    // (No server here to hand it to students: sent to none.)
    assert!(sent.starts_with("sent to 0 students: "), "{sent}");
    assert!(
        sent.contains(&"x".repeat(57)) && !sent.contains(&"x".repeat(58)),
        "{sent}"
    );
}

/// Stop 59's lecture pass: with `--presenter-keys` and no presenter connected, students
/// "followed" nobody and Space did not step. A student who joins without one is on their own
/// and steps their own lesson; the first presenter to log in is followed by every student
/// waiting for one (joined before it, or left by the last) who holds nothing unsaved, and only
/// told to the others.
#[test]
fn students_without_a_presenter_step_alone_and_follow_the_first_to_log_in() {
    use beamfric::lesson::read_lesson;
    use beamfric::tui::state::LessonPlace;
    use beamfric::tui::state::follow::{ClassNews, Follow, Followers};
    let lesson = read_lesson(std::path::Path::new("lessons/regularisation.toml")).unwrap();
    let place = LessonPlace {
        lesson: std::sync::Arc::new(lesson),
        step: 0,
    };
    let followers = Followers::new(|| {});
    let joined = |follow: Follow| {
        let options = Options {
            follow: Some(follow),
            lesson: Some(place.clone()),
            ..Options::new(PLAIN)
        };
        let mut app = settled(App::new(place.current().scene.clone(), options).unwrap());
        update(&mut app, Msg::Resize(120, 40));
        app
    };
    let step = |app: &App| app.exploration.lesson.as_ref().map(|place| place.step);
    let mut alice = joined(Follow::student_without_presenter(&followers, "alice"));
    assert!(screen(&alice).contains("own exploration · no presenter connected"));
    // The hint line offers stepping, and no rejoin while there is nobody to follow.
    assert!(screen(&alice).contains("Space:next"), "{}", screen(&alice));
    assert!(!screen(&alice).contains("F:rejoin"), "{}", screen(&alice));
    keys(&mut alice, "Space");
    assert_eq!(step(&alice), Some(1), "{}", screen(&alice));
    assert!(!alice.is_following());
    // Bob changes his scene; Carol forks on purpose from a presenter who then leaves; Dan
    // follows that presenter and is left by it.
    let mut bob = joined(Follow::student_without_presenter(&followers, "bob"));
    keys(&mut bob, "]");
    assert!(bob.modified());
    let (mut carol, mut dan) = (
        joined(Follow::student(&followers, "carol")),
        joined(Follow::student(&followers, "dan")),
    );
    keys(&mut carol, "f");
    for student in [&mut carol, &mut dan] {
        update(student, Msg::Class(ClassNews::PresenterLeft));
    }
    assert!(screen(&dan).contains("the keys are yours (you follow again once one is back)"));
    assert_eq!(followers.count(), 0);
    for student in [&mut alice, &mut bob, &mut carol, &mut dan] {
        update(student, Msg::Class(ClassNews::PresenterArrived));
    }
    assert!(alice.is_following() && dan.is_following());
    assert!(screen(&alice).contains("a presenter logged in: following them"));
    assert_eq!(followers.count(), 2);
    assert!(
        !bob.is_following() && bob.modified(),
        "Bob's changes stay his"
    );
    assert!(screen(&bob).contains("F follows them (unsaved: s saves first)"));
    assert!(!carol.is_following());
    assert!(screen(&carol).contains("a presenter logged in: F follows them"));
    // Following, the presenter steps the class: Space is refused again.
    keys(&mut alice, "Space");
    assert_eq!(step(&alice), Some(1));
    // F with no presenter connected says so, and waits for the next one.
    let mut erin = joined(Follow::student_without_presenter(&followers, "erin"));
    keys(&mut erin, "f F");
    assert!(screen(&erin).contains("no presenter is connected: you follow the next to log in"));
    update(&mut erin, Msg::Class(ClassNews::PresenterArrived));
    assert!(erin.is_following());
}

/// Of two presenters the newest leads (the hub publishes only its frames); the one before is
/// told, and told again when it leads once more.
#[test]
fn a_presenter_hears_whether_it_leads() {
    use beamfric::tui::state::follow::{ClassNews, Follow, Followers};
    let followers = Followers::new(|| {});
    let options = Options {
        follow: Some(Follow::presenter(&followers, false)),
        ..Options::new(PLAIN)
    };
    let mut presenter = app_with("benchmark-1", options);
    assert!(screen(&presenter).contains("presenting · 0 follow"));
    update(&mut presenter, Msg::Class(ClassNews::Lead(false)));
    let told = buffer_to_text(&draw_to_buffer(&presenter, 80, 24), false);
    assert!(
        told.contains("presenting (another presenter leads)"),
        "{told}"
    );
    assert!(told.contains("another presenter logged in and leads: the students see theirs"));
    update(&mut presenter, Msg::Class(ClassNews::Lead(true)));
    let told = buffer_to_text(&draw_to_buffer(&presenter, 80, 24), false);
    assert!(told.contains("presenting · 0 follow"), "{told}");
    assert!(told.contains("you lead the class again: the students see your explorer"));
}
