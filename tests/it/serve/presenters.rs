//! Who leads a class served with `--presenter-keys` (stop 59's lecture pass found both): a
//! student who logs in before any presenter is on their own and steps the lesson alone, then
//! follows the first presenter to log in; of two presenters the newest leads, starting where
//! the class is, and the one before leads again when it leaves; a silent presenter's class is
//! not idle.

use super::*;

#[test]
fn a_student_before_the_presenter_steps_alone_and_the_newest_of_two_presenters_leads() {
    let dir = tempfile::tempdir().unwrap();
    let (first_key, student_key, second_key) = (user_key(1), user_key(2), user_key(3));
    let presenters = keys_file(&dir, "presenters", &[&first_key, &second_key]);
    let students = keys_file(&dir, "students", &[&student_key]);
    let server = Server::start(&ServeOptions {
        authorized_keys: Some(students),
        presenter_keys: Some(presenters),
        lesson: Some("lessons/regularisation.toml".into()),
        open: false,
        ..options(&dir)
    })
    .unwrap();
    runtime().block_on(async {
        // Before any presenter: the student's own, and Space steps their own lesson (it used
        // to "follow" nobody and refuse Space).
        let (_student, mut alice) = session_of(server.address(), "alice", student_key).await;
        alice
            .wait_for("own exploration · no presenter connected")
            .await;
        alice.wait_for("no presenter yet: the keys are yours").await;
        alice.wait_for("step 1/7").await;
        alice.send(b" ").await;
        alice.wait_for("step 2/7").await;
        assert_eq!(server.followers(), 0);

        // The first presenter logs in: the student, with nothing unsaved, follows it.
        let (first, mut lecturer) = session_of(server.address(), "lecturer", first_key).await;
        lecturer.wait_for("presenting · 1 follow").await;
        alice
            .wait_for("a presenter logged in: following them")
            .await;
        alice.wait_for("step 1/7").await;
        alice.wait_for("following the presenter").await;

        // The first presenter steps on; a second presenter (the lecturer again, from another
        // laptop) starts where the class is and leads; the first is told, and its steps no
        // longer reach the class.
        lecturer.send(b" ").await;
        alice.wait_for("step 2/7").await;
        let (second, mut laptop) = session_of(server.address(), "lecturer", second_key).await;
        laptop.wait_for("presenting · 1 follow").await;
        laptop.wait_for("presenting from where the class is").await;
        laptop.wait_for("step 2/7").await;
        lecturer
            .wait_for("presenting (another presenter leads)")
            .await;
        lecturer
            .wait_for("another presenter logged in and leads")
            .await;
        laptop.send(b" ").await;
        laptop.wait_for("step 3/7").await;
        alice.wait_for("step 3/7").await;
        lecturer.send(b"   ").await;
        lecturer.wait_for("step 5/7").await;
        laptop.send(b" ").await;
        laptop.wait_for("step 4/7").await;
        alice.wait_for("step 4/7").await;
        let seen = String::from_utf8_lossy(&alice.raw).into_owned();
        assert!(
            !seen.contains("step 5/7"),
            "the first presenter's step reached a student"
        );

        // The laptop leaves: the first presenter leads again, and the class follows it on.
        disconnect(&second).await;
        lecturer.wait_for("you lead the class again").await;
        lecturer.wait_for("presenting · 1 follow").await;
        alice.wait_for("step 5/7").await;
        assert!(
            !alice.text().contains("the presenter left"),
            "{}",
            alice.text()
        );
        assert_eq!(server.followers(), 1);

        // The last presenter leaves: the student is told and has the keys again.
        disconnect(&first).await;
        alice.wait_for("the presenter left").await;
        alice
            .wait_for("own exploration · no presenter connected")
            .await;
        alice.send(b" ").await;
        alice.wait_for("step 6/7").await;
    });
}

/// Stop 59's pass: a presenter who talked for the whole idle timeout without a key had every
/// follower closed. A student following, and a presenter whom students follow, are not idle;
/// a student on their own is, with its warning first.
#[test]
fn a_silent_presenters_class_is_not_idle() {
    let dir = tempfile::tempdir().unwrap();
    let (presenter_key, alice_key, bob_key) = (user_key(1), user_key(2), user_key(4));
    let presenters = keys_file(&dir, "presenters", &[&presenter_key]);
    let students = keys_file(&dir, "students", &[&alice_key, &bob_key]);
    let server = Server::start(&ServeOptions {
        authorized_keys: Some(students),
        presenter_keys: Some(presenters),
        idle_timeout: Some(Duration::from_secs(2)),
        open: false,
        ..options(&dir)
    })
    .unwrap();
    runtime().block_on(async {
        let (lecturer, mut presenter) =
            session_of(server.address(), "lecturer", presenter_key).await;
        presenter.wait_for("presenting").await;
        let (_alice, mut alice) = session_of(server.address(), "alice", alice_key).await;
        alice.wait_for("following the presenter").await;
        // Bob forks after Alice and the presenter last had input: idle from later than both.
        let (_bob, mut bob) = session_of(server.address(), "bob", bob_key).await;
        bob.wait_for("following the presenter").await;
        bob.send(b"f").await;
        bob.wait_for("own exploration").await;
        bob.wait_for("idle: this session ends in").await;
        bob.wait_for_close().await;
        assert!(String::from_utf8_lossy(&bob.raw).contains("closed after 2 s without input"));
        // Had they been counted idle, both would have been closed before Bob: each still
        // answers, and what came before that answer holds no warning.
        presenter.send(b"]").await;
        presenter.wait_for("load f0 (x=0)  5.0e5").await;
        alice.wait_for("load f0 (x=0)  5.0e5").await;
        for (who, explorer) in [("alice", &alice), ("the presenter", &presenter)] {
            let raw = String::from_utf8_lossy(&explorer.raw);
            assert!(
                !raw.contains("idle: this session"),
                "{who} was warned: {raw:?}"
            );
        }
        assert_eq!(server.sessions(), 2);
        // A silence longer than the timeout with nothing happening in the class (a session
        // of another server is closed idle meanwhile), then the presenter leaves: Alice is
        // idle from then on, warned first (she was closed at once, idle since long before).
        let elsewhere_dir = tempfile::tempdir().unwrap();
        let elsewhere = Server::start(&ServeOptions {
            idle_timeout: Some(Duration::from_secs(3)),
            ..options(&elsewhere_dir)
        })
        .unwrap();
        let other = logged_in(elsewhere.address()).await;
        Explorer::open(&other, (80, 24), &[])
            .await
            .wait_for_close()
            .await;
        disconnect(&lecturer).await;
        alice.wait_for("the presenter left").await;
        alice.wait_for("idle: this session ends in 1 s").await;
        alice.wait_for_close().await;
    });
}
