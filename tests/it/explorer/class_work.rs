//! A student's own work in a class as presenters come and go (stop 60's OpenSSH pass): a
//! question left open when the presenter leaves, changes on lesson steps other than the one
//! shown, the closing save of every changed step, a presenter who does not lead, and saves
//! that fail inside the class's save directory.

use std::path::Path;
use std::sync::Arc;

use beamfric::lesson::read_lesson;
use beamfric::tui::state::follow::{ClassNews, Follow, Followers};
use beamfric::tui::state::{LessonPlace, SavePolicy};

use super::*;

/// A served student of the regularisation lesson, saving (if at all) to `save_dir`.
fn student_of_the_lesson(follow: Follow, save_dir: Option<&Path>) -> App {
    let lesson = read_lesson(Path::new("lessons/regularisation.toml")).unwrap();
    let place = LessonPlace {
        lesson: Arc::new(lesson),
        step: 0,
    };
    let options = Options {
        follow: Some(follow),
        lesson: Some(place.clone()),
        owner: Some("alice".into()),
        save_policy: match save_dir {
            Some(dir) => SavePolicy::Within(dir.to_path_buf()),
            None => SavePolicy::ShowText,
        },
        save_directory: save_dir.map(Path::to_path_buf),
        ..Options::new(PLAIN)
    };
    let mut app = settled(App::new(place.current().scene.clone(), options).unwrap());
    update(&mut app, Msg::Resize(120, 40));
    app
}

fn status(app: &App) -> String {
    app.message.clone().unwrap_or_default()
}

#[test]
fn a_yes_to_follow_after_the_presenter_left_keeps_the_students_changes() {
    let followers = Followers::new(|| {});
    let mut alice = student_of_the_lesson(Follow::student(&followers, "alice"), None);
    keys(&mut alice, "f ] F");
    assert!(
        matches!(alice.mode, Mode::ConfirmDiscard { .. }),
        "{:?}",
        alice.mode
    );
    // The presenter leaves while the question is open; the student answers y.
    update(&mut alice, Msg::Class(ClassNews::PresenterLeft));
    keys(&mut alice, "y");
    assert!(!alice.is_following(), "following nobody");
    assert!(alice.modified(), "the changes were kept");
    assert_eq!(
        status(&alice),
        "no presenter is connected: you follow the next to log in"
    );
    assert_eq!(followers.count(), 0);
}

#[test]
fn changes_on_another_lesson_step_keep_a_student_from_being_pulled_in() {
    let followers = Followers::new(|| {});
    let mut alice =
        student_of_the_lesson(Follow::student_without_presenter(&followers, "alice"), None);
    keys(&mut alice, "Space ] Space");
    assert!(
        !alice.modified() && alice.has_unsaved_work(),
        "step 2's changes wait"
    );
    update(&mut alice, Msg::Class(ClassNews::PresenterArrived));
    assert!(!alice.is_following());
    assert_eq!(
        status(&alice),
        "a presenter logged in: F follows them (unsaved: s saves first)"
    );
    // `f` with nobody to follow says what it does.
    let mut bob = student_of_the_lesson(Follow::student_without_presenter(&followers, "bob"), None);
    keys(&mut bob, "f");
    assert!(status(&bob).starts_with("on your own: the next presenter to log in will not pull"));
    update(&mut bob, Msg::Class(ClassNews::PresenterArrived));
    assert!(!bob.is_following());
}

/// Stop 60's pass: the closing save wrote only the scene shown; changes left on another step
/// were lost, after the idle warning had said "your unsaved changes are kept".
#[test]
fn the_closing_save_writes_every_changed_lesson_step() {
    let dir = tempfile::tempdir().unwrap();
    let followers = Followers::new(|| {});
    let mut alice = student_of_the_lesson(
        Follow::student_without_presenter(&followers, "alice"),
        Some(dir.path()),
    );
    keys(&mut alice, "Space ] Space Space ]");
    let (step_two, step_four) = (
        alice.step_edits[&1].scene.clone(),
        alice.exploration.scene.clone(),
    );
    update(
        &mut alice,
        Msg::Class(ClassNews::Ended {
            by: "the lecturer".into(),
        }),
    );
    let Mode::ClassEnded {
        saved: Some(names), ..
    } = &alice.mode
    else {
        panic!("{:?}", alice.mode)
    };
    // Each name says which step it holds.
    assert!(
        names.ends_with("(step 2)") && names.contains(" (step 4), "),
        "{names}"
    );
    let names: Vec<&str> = names
        .split(", ")
        .map(|name| name.split(" (").next().unwrap())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
    let read = |name: &str| {
        beamfric::scene::load(dir.path().join(name).to_str().unwrap())
            .unwrap()
            .scene
    };
    assert_eq!(read(names[1]).load, step_two.load);
    assert_eq!(read(names[0]).load, step_four.load);
    assert!(!alice.has_unsaved_work());
    let closing = buffer_to_text(&draw_to_buffer(&alice, 80, 24), false);
    assert!(closing.contains("Your changes are saved as"), "{closing}");
}

/// Stop 60's second pass: with changes left on another step only, F followed at once; the
/// changes stayed hidden (a fork showed the presenter's step) and were still counted. F asks,
/// naming the steps, and a yes lets them go; a forked student's idle warning stays while the
/// presenter's states arrive.
#[test]
fn following_asks_for_changes_left_on_other_steps_and_lets_them_go() {
    let followers = Followers::new(|| {});
    let mut alice =
        student_of_the_lesson(Follow::student_without_presenter(&followers, "alice"), None);
    keys(&mut alice, "Space ] Space");
    update(&mut alice, Msg::Class(ClassNews::PresenterArrived));
    keys(&mut alice, "F");
    assert!(
        matches!(alice.mode, Mode::ConfirmDiscard { .. }),
        "{:?}",
        alice.mode
    );
    let asked = buffer_to_text(&draw_to_buffer(&alice, 120, 40), false);
    assert!(
        asked.contains("follow the presenter (step 2 changed too)"),
        "{asked}"
    );
    keys(&mut alice, "y");
    assert!(alice.is_following());
    assert!(
        !alice.has_unsaved_work(),
        "the steps are the presenter's now"
    );
    // A forked student's idle warning is not cleared by the presenter's next state.
    keys(&mut alice, "f");
    update(
        &mut alice,
        Msg::IdleWarning(std::time::Duration::from_secs(5)),
    );
    let warning = status(&alice);
    assert!(
        warning.starts_with("idle: this session ends in 5 s"),
        "{warning}"
    );
    let presenters = alice.exploration.clone();
    update(&mut alice, Msg::Follow(Arc::new(presenters)));
    assert_eq!(status(&alice), warning);
}

#[test]
fn a_presenter_who_does_not_lead_cannot_bring_the_class_back() {
    let followers = Followers::new(|| {});
    let options = Options {
        follow: Some(Follow::presenter(&followers, false)),
        ..Options::new(PLAIN)
    };
    let mut presenter = app_with("benchmark-1", options);
    update(&mut presenter, Msg::Class(ClassNews::Lead(false)));
    keys(&mut presenter, "S b");
    assert_eq!(
        status(&presenter),
        "another presenter leads the class: only they bring everyone back"
    );
}

/// Stop 60's pass: a save that failed inside the class's save directory named the server's
/// own path (`not saved: … /srv/class/sub/x.toml`).
#[test]
fn a_failed_save_in_the_class_directory_does_not_show_the_servers_path() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("sub"), "a file, not a directory").unwrap();
    let followers = Followers::new(|| {});
    let mut alice = student_of_the_lesson(
        Follow::student_without_presenter(&followers, "alice"),
        Some(dir.path()),
    );
    keys(&mut alice, "] s");
    press(&mut alice, &typed("sub/x"));
    press(&mut alice, "Enter");
    let message = status(&alice);
    assert!(message.starts_with("not saved:"), "{message}");
    assert!(message.contains("the class's save directory"), "{message}");
    assert!(!message.contains(dir.path().to_str().unwrap()), "{message}");
}

/// Stop 60's second pass: a save into a folder missing from the class's save directory was
/// called "outside" it, and a name of `.toml` alone saved a hidden file of no name.
#[test]
fn a_missing_folder_and_a_name_of_only_toml_are_said_so() {
    let dir = tempfile::tempdir().unwrap();
    let followers = Followers::new(|| {});
    let mut alice = student_of_the_lesson(
        Follow::student_without_presenter(&followers, "alice"),
        Some(dir.path()),
    );
    for (typed_name, said) in [
        (
            "nodir/x",
            "not saved: there is no folder nodir in the class's save directory (only files may \
             be made there, not folders)",
        ),
        (
            "../x",
            "not saved: ../x.toml is outside the class's save directory",
        ),
        (".toml", "not saved: .toml has no name before .toml"),
    ] {
        keys(&mut alice, "] s");
        press(&mut alice, &typed(typed_name));
        press(&mut alice, "Enter");
        assert!(
            status(&alice).starts_with(said),
            "{typed_name}: {}",
            status(&alice)
        );
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}
