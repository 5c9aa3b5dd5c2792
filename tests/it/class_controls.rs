//! The lecturer's class controls over real SSH (issue 23): the list of students (user,
//! following or exploring, idle time, unsaved work), bringing everyone back to follow — a
//! student whose own exploration holds unsaved work is asked, not pulled away from it — and
//! a one-line message to every student.

#![cfg(unix)]

use crate::harness::lecture::{past_the_join_screen, present};
use crate::harness::ssh::{Explorer, logged_in_as, runtime};

#[test]
fn the_lecturer_lists_the_students_brings_them_back_and_writes_to_all() {
    let dir = tempfile::tempdir().unwrap();
    let mut lecturer = present(dir.path(), &[], (100, 30));
    let (_, address) = past_the_join_screen(&mut lecturer);
    // Stop 59's lecture pass: the lecturer's Ctrl-Z stopped the process, and the whole class
    // with it. It is refused, and the class goes on below.
    lecturer.type_bytes(b"\x1a");
    lecturer.wait_for_screen("Ctrl-Z would stop the server and every student with it: not done");
    runtime().block_on(async {
        let (alice, bob, carol) = (
            logged_in_as(address, "alice").await,
            logged_in_as(address, "bob").await,
            logged_in_as(address, "carol").await,
        );
        let mut follower = Explorer::open(&alice, (80, 24), &[]).await;
        let mut changer = Explorer::open(&bob, (80, 24), &[]).await;
        let mut wanderer = Explorer::open(&carol, (80, 24), &[]).await;
        for student in [&mut follower, &mut changer, &mut wanderer] {
            student.wait_for("following the presenter").await;
        }
        // Bob forks and changes the load; Carol forks and changes nothing.
        changer.send(b"f").await;
        changer.wait_for("own exploration").await;
        changer.send(b"]").await;
        changer.wait_for("5.0e5").await;
        wanderer.send(b"f").await;
        wanderer.wait_for("own exploration").await;

        // The list: who follows, who explores, who holds unsaved work.
        lecturer.wait_for_screen("3 students");
        lecturer.type_bytes(b"S");
        lecturer.wait_for_screen("Students: 3 connected · 1 following · 1 with unsaved work");
        let screen = lecturer.screen();
        let line = |user: &str| {
            screen
                .lines()
                .find(|l| l.contains(user))
                .unwrap_or_else(|| panic!("{user} not listed:\n{screen}"))
                .to_string()
        };
        assert!(line("alice").contains("following"), "{screen}");
        assert!(line("bob").contains("own exploration"), "{screen}");
        assert!(line("bob").contains("unsaved"), "{screen}");
        assert!(line("carol").contains("own exploration"), "{screen}");
        assert!(!line("carol").contains("unsaved"), "{screen}");
        assert!(line("alice").contains("idle "), "{screen}");

        // b: everyone back. Carol follows again; Bob keeps his work and is asked.
        lecturer.type_bytes(b"b");
        lecturer.wait_for_screen("asked the 2 students exploring on their own to follow again");
        wanderer
            .wait_for("the presenter brought everyone back")
            .await;
        wanderer.wait_for("following the presenter").await;
        changer
            .wait_for("the presenter asks everyone to follow: F follows (unsaved: s saves first)")
            .await;
        assert!(
            changer.text().contains("own exploration"),
            "{}",
            changer.text()
        );
        assert!(changer.text().contains("5.0e5"), "{}", changer.text());
        lecturer.type_bytes(b"S");
        lecturer.wait_for_screen("Students: 3 connected · 2 following · 1 with unsaved work");
        lecturer.type_bytes(b"x");

        // A message to all: S, m, the line, Enter.
        lecturer.type_bytes(b"S");
        lecturer.wait_for_screen("Students: 3 connected");
        lecturer.type_bytes(b"m");
        lecturer.wait_for_screen("to every student:");
        lecturer.type_bytes(b"look at the error curve\r");
        lecturer.wait_for_screen("sent to 3 students: look at the error curve");
        for student in [&mut follower, &mut changer, &mut wanderer] {
            student
                .wait_for("from the presenter: look at the error curve")
                .await;
        }
        // The class ends while they are connected: the question counts Bob's unsaved work.
        lecturer.type_bytes(b"q");
        lecturer.wait_for_screen("3 students (1 with unsaved work): end the class?");
        lecturer.type_bytes(b"y");
        changer
            .wait_for("The class was ended by the lecturer")
            .await;
        // Stop 59's lecture pass: without --save-dir Bob's scene was shown only on the
        // closing screen, cut to its height and wrapped into invalid TOML, and gone with the
        // first key. Now it is printed on his own screen after the explorer has left it, whole
        // however he leaves (here with keys still coming).
        changer
            .wait_for("Your changes are not saved on the server: when this closes")
            .await;
        changer.send(b"x\x1b[C\x1b[C").await;
        changer.wait_for_close().await;
        let raw = String::from_utf8_lossy(&changer.raw).into_owned();
        let marker = "the scene as TOML, to copy into a file:\r\n\r\n";
        let at = raw.rfind(marker).unwrap_or_else(|| panic!("{raw:?}")) + marker.len();
        assert!(raw[..at].contains("beamfric: the class was ended by the lecturer\r\n"));
        let printed = raw[at..].replace("\r\n", "\n");
        let scene = beamfric::scene::Scene::from_toml(&printed, "printed").unwrap();
        assert_eq!(scene.load.f0, 5e5, "{printed}");
    });
    assert_eq!(lecturer.exit().code(), Some(0));
}

#[test]
fn forty_students_scroll_in_the_lecturers_list_at_80x24_and_wide_names_keep_their_columns() {
    use beamfric::plot::{Look, buffer_to_text};
    use beamfric::tui::draw_to_buffer;
    use beamfric::tui::input::keys::parse_keys;
    use beamfric::tui::state::follow::{Follow, Followers};
    use beamfric::tui::state::{App, Options};
    use beamfric::tui::update::{Msg, update};

    let followers = Followers::new(|| {});
    let mut names: Vec<String> = (1..=39).map(|i| format!("student{i:02}")).collect();
    names.insert(0, "梁梁梁梁梁梁梁梁梁梁".into());
    let seats: Vec<Follow> = names
        .iter()
        .map(|name| Follow::student(&followers, name))
        .collect();
    let options = Options {
        follow: Some(Follow::presenter(&followers, true)),
        ..Options::new(Look {
            ascii: false,
            color: false,
        })
    };
    let loaded = crate::harness::scenes::loaded_preset("benchmark-1");
    let mut app = App::new(loaded, options).unwrap();
    update(&mut app, Msg::Resize(80, 24));
    let press = |app: &mut App, keys: &str| {
        for key in parse_keys(keys).unwrap() {
            update(app, Msg::Key(key));
        }
        buffer_to_text(&draw_to_buffer(app, 80, 24), false)
    };
    let first = press(&mut app, "S");
    assert!(
        first.contains("Students: 40 connected · 40 following"),
        "{first}"
    );
    // The wide name: 16 columns with its cut, the next column where ASCII names have it.
    let wide = first.lines().find(|l| l.contains('梁')).unwrap();
    let ascii = first.lines().find(|l| l.contains("student01")).unwrap();
    // (A wide character is one cell of text and its second column a blank cell.)
    let column = |line: &str| line.find("following").map(|b| line[..b].chars().count());
    assert_eq!(column(wide), column(ascii), "{wide}\n{ascii}");
    assert!(first.contains("more (↓ scrolls)"), "{first}");
    assert!(!first.contains("student39"), "{first}");
    // Down to the end: the last student shows, and the list stays open.
    let last = press(&mut app, "PgDn PgDn PgDn PgDn j j");
    assert!(last.contains("student39"), "{last}");
    assert!(!last.contains("more (↓ scrolls)"), "{last}");
    assert!(last.contains("Students: 40 connected"));
    // Any other key closes it.
    let closed = press(&mut app, "x");
    assert!(!closed.contains("Students: 40 connected"), "{closed}");
    drop(seats);
    let none = press(&mut app, "S");
    assert!(none.contains("no student is connected"), "{none}");
}
